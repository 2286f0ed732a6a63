"""The exact torque-free motion of a rigid body (no force, no torque), in closed form.

With no torque the world angular momentum L (about the centre of mass) and the
linear momentum P are constant, x(t) = x0 + (P/M) t, and the orientation R(t) is
known exactly (Euler 1758, Jacobi 1849):

* spherical body (I1 = I2 = I3): a steady rotation,  R(t) = exp(t L*/I) R0;
* symmetric body (two equal moments I_eq, symmetry axis a with moment I_s): the
  steady precession  R(t) = exp(t L*/I_eq) R0 exp(t (1/I_s − 1/I_eq) (a·m) a*),
  m = R0ᵀL the body angular momentum (a·m is constant);
* spin exactly along a principal axis k:  R(t) = exp(t L*/I_k) R0  (also about the
  unstable intermediate axis: the exact solution stays there for ever);
* asymmetric body (I1 < I2 < I3): the body angular momentum m(t) = R(t)ᵀL moves on
  its polhode, given by Jacobi's elliptic functions sn, cn, dn, and the remaining
  angle about L needs an incomplete elliptic integral of the third kind Π.

The asymmetric case, as computed here (the derivation follows the structure of
Celledoni, Fassò, Säfström & Zanna, SIAM J. Sci. Comput. 30(4) 2008, and of
van Zon & Schofield, J. Comput. Phys. 225 (2007); formulas re-derived and checked
against a tight DOP853 integration in tests/exact/test_exact.py):

1.  Principal frame: I_body = A diag(I1, I2, I3) Aᵀ, μ = Aᵀ R0ᵀ L/|L| (unit vector).
    G = |L|², 2E = Σ mᵢ²/Iᵢ.  The polhode encircles axis 3 if D = G/2E >= I2, axis 1
    otherwise; in the second case the axes are relabelled (J1, J2, J3) = (I3, I2, I1)
    by the rotation S = [[0,0,1],[0,−1,0],[1,0,0]], so that the polhode always
    encircles the working axis 3.  With dᵢⱼ = Jᵢ − Jⱼ (and μ now the working-frame
    components), everything below is a ratio of same-sign quantities:

        α = (2E J3 − G)/G = μ1² d31/J1 + μ2² d32/J2
        β = (G − 2E J1)/G = μ2² d21/J2 + μ3² d31/J3
        δ = (G − 2E J2)/G = μ1² (J1 − J2)/J1 + μ3² (J3 − J2)/J3      (0 on the separatrix)
        a1² = μ1² + μ2² J1 d32/(J2 d31),  a2² = μ2² + μ1² J2 d31/(J1 d32),
        a3² = μ3² + μ2² J3 d21/(J2 d31)
        m = d21 α/(d32 β)  (elliptic parameter),  m' = 1 − m = d31 δ/(d32 β)
        λ = s1 s3 sign(d31) |L| √(d32 β/(J1 J2 J3)),  s1 = sign μ1(0), s3 = sign μ3(0)

    and  m(t)/|L| = (s1 a1 cn(τ), a2 sn(τ), s3 a3 dn(τ)),  τ = τ0 + λ t,
    τ0 = F(φ0 | m) from sn φ0 = μ2/a2, cn φ0 = |μ1|/a1.  m' is computed directly
    from δ (not as 1 − m), which keeps its relative accuracy near the separatrix.

2.  Attitude.  Let B(μ) be the rotation with rows  r1 = (μ2, −μ1, 0)/ρ,
    r2 = (μ3μ1/ρ, μ3μ2/ρ, −ρ),  r3 = μ  (ρ = √(μ1² + μ2²) > 0 off the axis), so
    B μ = e3.  Then R(t) = R0 A Sᵀ B(μ(0))ᵀ Rz(ψ(t) − ψ(0)) B(μ(t)) S Aᵀ where ψ,
    the angle about L, obeys ψ' = |L|/J3 + |L| α/(J3 (μ1² + μ2²)); since
    μ1² + μ2² = a1² (1 − n sn²τ) with n = −J3 d21/(J1 d32) (< 0: no pole),

        ψ(t) − ψ(0) = |L| t/J1 + C [Λ(τ) − Λ(τ0)],   C = |L| d31/(J1 J3 λ),
        Λ(τ) = Π(am τ, n | m) − τ = (n/3) sn³τ R_J(cn²τ, dn²τ, 1, 1 − n sn²τ)    (|τ| <= K)

    (Carlson's form of Π; R_J from scipy.special.elliprj), extended to any τ by
    τ = τ' + 2jK, Λ(τ) = Λ(τ') + 2j (n/3) R_J(0, m', 1, 1 − n), sn, cn → (−1)ʲ sn, cn.
    When |n| > 1 (J2 close to J3: C is then large and Π small) the equivalent form
    ψ(t) − ψ(0) = |L| t/J3 + C [Π(τ) − Π(τ0)] is used, with Π from the transformation
    n → m/n (DLMF 19.7.9), which has no cancellation: this keeps nearly symmetric
    bodies (moments equal to a few ulps) accurate with the general formulas.
    The signs (λ, the orientation of B, the relabelling S) were derived from Euler's
    equations here rather than copied, so the known slips of the published formulas
    (a sign in λ, the n in ψ, the separatrix; Principia's documentation/Celledoni.tex)
    do not apply; the tests check every case against a tight numerical integration.

    (sn, cn, dn and Π: elliptic.py.)

Two moments within SYMMETRY_TOL (relative, a few ulps: eigen-decomposition noise) are
taken as equal (the symmetric closed form); a momentum component below 1e-150 |L| is
taken as zero (a spin along that principal axis).

The same motion over one step, for the splitting methods, is flow.py (FreeRotationFlow).

This is the independent REFERENCE: what the tests, the benchmarks and the notebooks compare the
methods with (rb.exact_free_body).  The method exact_splitting steps with another exact torque-free
motion, the compiled engine's (rbcourse/engine/exact_flow.py with engine/elliptic.py): a step must be
compiled and allocation-free, and scipy cannot be called from compiled code.  The two share no code and
no constant, on purpose: a reference that shared code with what it checks would prove nothing.
tests/test_two_exact_flows.py checks one against the other.
"""
from __future__ import annotations

import numpy as np
from scipy import special

from ..support import checks
from ..body import SYMMETRY_TOL, RigidBody
from ..rotation import exp_so3, orthogonality_error, transpose
from ..scene import Scene
from ..state import R_TOLERANCE, State
from ..trajectory import Trajectory
from .elliptic import SEPARATRIX_MC, ZERO_COMPONENT, jacobi, phase

__all__ = ["exact_free_body", "Motion", "SYMMETRY_TOL"]

RELABEL = [2, 1, 0]                         # S = [[0,0,1],[0,−1,0],[1,0,0]]: (J1, J2, J3) = (I3, I2, I1)
RELABEL_SIGN = np.array([1.0, -1.0, 1.0])   # … and μ → (μ3, −μ2, μ1)


def exact_free_body(body: RigidBody, X0: State, t) -> Trajectory:
    """The exact motion of a free rigid body (no force, no torque) from X0, at the times t.

        x(t) = x0 + (P/M) t,   P(t) = P,   L(t) = L   (world, about the centre of mass),
        R(t) exact (closed forms; Jacobi elliptic functions for an asymmetric body).

    body: the RigidBody (any inertia: asymmetric, symmetric, spherical, non-diagonal).
    X0: a single-body State.  t: a time or a 1-D array of times (any real values, in any
    order, negative ones run backwards) while the motion stays resolved in float64: the body turns by at most
    |L| |t| / I_min rad, which must stay within checks.ANGLE_MAX = 2³² rad (an angle float64 resolves to 1e-6 rad),
    and x(t) finite; all times are computed at once (vectorised).
    Returns Trajectory(t, x, R, P, L, scene=Scene(body), method="exact").
    """
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a RigidBody, got {body!r}")
    if not isinstance(X0, State):
        raise ValueError(f"X0 must be a State, got {X0!r}")
    if np.ndim(X0.x) != 1:
        raise ValueError(f"X0 must be a single-body State, got one holding {X0.n_bodies} bodies")
    x0, R0, P, L = (np.asarray(a, dtype=float) for a in (X0.x, X0.R, X0.P, X0.L))
    for name, arr, shape in (("x", x0, (3,)), ("R", R0, (3, 3)), ("P", P, (3,)), ("L", L, (3,))):
        if arr.shape != shape or not np.all(np.isfinite(arr)):
            raise ValueError(f"X0.{name} must be a finite array of shape {shape}, got {arr!r}")
    err = float(orthogonality_error(R0))
    if err > R_TOLERANCE or np.linalg.det(R0) <= 0:
        raise ValueError(f"X0.R must be a rotation matrix (‖RᵀR − I‖ <= {R_TOLERANCE:g}, det R > 0), "
                         f"got ‖RᵀR − I‖ = {err:.3g}")
    t = times(t)

    A = np.asarray(body.principal_axes)
    moments = np.asarray(body.principal_moments)
    spin = float(np.linalg.norm(L)) / float(moments.min())    # |ω| <= |L| / I_min: the fastest the body turns
    longest = checks.ANGLE_MAX / spin if spin > 0 else np.inf
    with np.errstate(over="ignore"):
        x = x0 + np.outer(t, P / body.mass)
    if not (np.abs(t).max() <= longest and np.all(np.isfinite(x))):
        bad = float(t[np.argmax(np.abs(t))])
        reach = f"the body turns by at most |L| |t| / I_min = {spin:.4g} |t| rad, within ±{checks.ANGLE_MAX:.4g} rad " \
                f"(2³²: an angle float64 resolves to 1e-6 rad), so |t| <= {longest:.4g} s" if spin > 0 else \
                "x(t) = x0 + (P/M) t must stay finite"
        if np.abs(t).max() <= longest:                  # turned little enough, but x overflowed
            reach = "x(t) = x0 + (P/M) t must stay finite"
        raise ValueError(f"t must be within the times the exact motion resolves in float64: {reach}; got t = {bad:g}")
    mb = R0.T @ L                                      # body angular momentum
    motion = Motion(moments[None], (A.T @ mb)[None])
    D = motion.increment(t)[:, 0]                      # (T, 3, 3), principal frame
    if not is_identity(A):
        D = A @ D @ A.T
    R = R0 @ D
    R[t == 0] = R0                                     # exactly X0 at t = 0
    T = len(t)
    return Trajectory(t, x, R, np.broadcast_to(P, (T, 3)).copy(), np.broadcast_to(L, (T, 3)).copy(),
                      scene=Scene(body), method="exact")


class Motion:
    """The torque-free motion of N bodies in principal axes: constants once, then
    increment(t) -> D(t) (T, N, 3, 3) at any times.  The closed forms (spherical, symmetric, a spin
    along a principal axis) are applied directly; the asymmetric off-axis bodies are in `ell`
    (an Elliptic: its `mc` is m', 0 on the separatrix).

    moments (N, 3) ascending principal moments, mp (N, 3) the angular momentum in the
    principal frame.  D(t) is the principal-frame increment: R(t) = R0 A D(t) Aᵀ.
    """

    def __init__(self, moments, mp):
        moments = np.asarray(moments, dtype=float)
        mp = np.asarray(mp, dtype=float)
        N = mp.shape[0]
        big = np.max(np.abs(mp), axis=-1, keepdims=True)           # |mp| without under/overflow
        big = np.where(big > 0, big, 1.0)
        Ln = big[:, 0] * np.sqrt(np.sum((mp / big) ** 2, axis=-1))
        mu = mp / np.where(Ln > 0, Ln, 1.0)[:, None]
        mu = np.where(np.abs(mu) < ZERO_COMPONENT, 0.0, mu)
        I1, I2, I3 = moments[:, 0], moments[:, 1], moments[:, 2]
        sym12 = (I2 - I1) <= SYMMETRY_TOL * I3
        sym23 = (I3 - I2) <= SYMMETRY_TOL * I3
        axis = np.count_nonzero(mu, axis=-1) <= 1
        closed = sym12 | sym23 | axis | (Ln == 0)
        self.N = N
        self.ic = np.flatnonzero(closed)
        self.ie = np.flatnonzero(~closed)
        if self.ic.size:
            self._closed_setup(moments[self.ic], mu[self.ic], Ln[self.ic],
                               sym12[self.ic], sym23[self.ic])
        if self.ie.size:
            self.ell = Elliptic(moments[self.ie], mu[self.ie], Ln[self.ie])

    def _closed_setup(self, I, mu, Ln, sym12, sym23):
        """R(t) = R0 A exp(t w1*) exp(t w2*) Aᵀ in principal axes (steady rotation or precession)."""
        n = len(Ln)
        I_eq = np.empty(n)
        w2 = np.zeros((n, 3))
        sph = sym12 & sym23
        I_eq[sph] = I[sph].mean(axis=-1)
        s = sym12 & ~sph                           # symmetry axis 3
        I_eq[s] = 0.5 * (I[s, 0] + I[s, 1])
        w2[s, 2] = (1.0 / I[s, 2] - 1.0 / I_eq[s]) * Ln[s] * mu[s, 2]
        s = sym23 & ~sph                           # symmetry axis 1
        I_eq[s] = 0.5 * (I[s, 1] + I[s, 2])
        w2[s, 0] = (1.0 / I[s, 0] - 1.0 / I_eq[s]) * Ln[s] * mu[s, 0]
        s = ~(sym12 | sym23)                       # asymmetric, spin along a principal axis
        k = np.argmax(np.abs(mu[s]), axis=-1)
        I_eq[s] = I[s][np.arange(k.size), k]
        self.w1 = (Ln / I_eq)[:, None] * mu
        self.w2 = w2
        self.has_w2 = bool(np.any(w2))

    def increment(self, t):
        t = np.asarray(t, dtype=float)
        D = np.empty((t.size, self.N, 3, 3))
        if self.ic.size:
            tt = t[:, None, None]
            Dc = exp_so3(tt * self.w1)
            if self.has_w2:
                Dc = Dc @ exp_so3(tt * self.w2)
            D[:, self.ic] = Dc
        if self.ie.size:
            D[:, self.ie] = self.ell.increment(t[:, None])
        return D



class Elliptic:
    """The asymmetric, off-axis case (the module docstring's steps 1 and 2, vectorised over n bodies):
    m(t)/|L| = (s1 a1 cn τ, a2 sn τ, s3 a3 dn τ), τ = τ0 + λ t, and the angle ψ about L."""

    def __init__(self, I, mu, Ln):
        I1, I2, I3 = I[:, 0], I[:, 1], I[:, 2]
        m1, m3 = mu[:, 0], mu[:, 2]
        delta = m1 * m1 * ((I1 - I2) / I1) + m3 * m3 * ((I3 - I2) / I3)
        self.flip = delta < 0                       # polhode about axis 1: relabel (3, 2, 1)
        f = self.flip[:, None]
        J = np.where(f, I[:, ::-1], I)
        w = np.where(f, mu[:, RELABEL] * RELABEL_SIGN, mu)
        J1, J2, J3 = J[:, 0], J[:, 1], J[:, 2]
        w1, w2, w3 = w[:, 0], w[:, 1], w[:, 2]
        d31, d32, d21 = J3 - J1, J3 - J2, J2 - J1
        beta = w2 * w2 * (d21 / J2) + w3 * w3 * (d31 / J3)
        mc = np.clip((d31 * delta) / (d32 * beta), 0.0, 1.0)
        mc = np.where(mc < SEPARATRIX_MC, 0.0, mc)
        self.mc = mc
        self.sep = mc == 0.0
        self.a1 = np.sqrt(w1 * w1 + w2 * w2 * ((J1 * d32) / (J2 * d31)))
        self.a2 = np.sqrt(w2 * w2 + w1 * w1 * ((J2 * d31) / (J1 * d32)))
        self.a3 = np.sqrt(w3 * w3 + w2 * w2 * ((J3 * d21) / (J2 * d31)))
        self.s1 = np.where(w1 < 0, -1.0, 1.0)
        self.s3 = np.where(w3 < 0, -1.0, 1.0)
        self.lam = self.s1 * self.s3 * np.sign(d31) * Ln * np.sqrt((d32 * beta) / (J1 * J2 * J3))
        self.n = -(J3 * d21) / (J1 * d32)
        self.C = Ln * d31 / (J1 * J3 * self.lam)
        # |n| > 1 (a nearly symmetric pair J2 ≈ J3): use Π itself, ψ = |L| t/J3 + C ΔΠ (C is large
        # and Π small there); otherwise Λ = Π − τ, ψ = |L| t/J1 + C ΔΛ.  See _phase.
        self.big_n = np.abs(self.n) > 1.0
        self.w = (1.0 - mc) / self.n
        self.rate = Ln / np.where(self.big_n, J3, J1)
        # initial phase τ0 = F(φ0 | m)
        sn0 = w2 / self.a2
        cn0 = np.abs(w1) / self.a1
        hyp = np.hypot(sn0, cn0)
        sn0, cn0 = sn0 / hyp, cn0 / hyp
        dn0 = np.abs(w3) / self.a3
        self.tau0 = sn0 * special.elliprf(cn0 * cn0, dn0 * dn0, 1.0)
        # complete integrals: K, and the phase over a half period (τ → τ + 2K)
        K = np.full_like(mc, np.inf)
        half = np.full_like(mc, np.inf)
        ns = ~self.sep
        K[ns] = special.elliprf(0.0, mc[ns], 1.0)
        c = ns & ~self.big_n
        half[c] = 2.0 * self.n[c] / 3.0 * special.elliprj(0.0, mc[c], 1.0, 1.0 - self.n[c])
        c = ns & self.big_n
        n_, w_ = self.n[c], self.w[c]
        half[c] = 2.0 * (special.elliprc(0.0, (1.0 - n_) * (1.0 - w_))
                         - w_ / 3.0 * special.elliprj(0.0, mc[c], 1.0, 1.0 - w_))
        self.K, self.half = K, half
        self.P0 = self._phase(self.tau0[None], sn0[None], cn0[None], dn0[None], np.zeros((1, mc.size)))[0]
        self.B0 = self._B(w1, w2, w3)                           # (n, 3, 3)

    @staticmethod
    def _B(w1, w2, w3):
        """Rows r1 = (μ2, −μ1, 0)/ρ, r2 = (μ3μ1/ρ, μ3μ2/ρ, −ρ), r3 = μ  (B μ = e3)."""
        nrm = np.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
        w1, w2, w3 = w1 / nrm, w2 / nrm, w3 / nrm
        rho = np.hypot(w1, w2)
        c1, c2 = w1 / rho, w2 / rho
        zero = np.zeros_like(w1)
        return np.stack([np.stack([c2, -c1, zero], -1),
                         np.stack([w3 * c1, w3 * c2, -rho], -1),
                         np.stack([w1, w2, w3], -1)], -2)

    def _phase(self, u, sn, cn, dn, j):
        """Λ(τ) or Π(τ) of these bodies (elliptic.phase), τ = u + 2jK."""
        return phase(u, sn, cn, dn, j, self.n, self.w, self.sep, self.big_n, self.half)

    def increment(self, t):
        """D(t) in principal axes, t (T, 1) -> (T, n, 3, 3)."""
        u = self.tau0 + self.lam * t
        K2 = 2.0 * np.where(self.sep, 1.0, self.K)
        j = np.where(self.sep, 0.0, np.rint(u / K2))
        ur = u - j * K2
        sn, cn, dn = jacobi(ur, self.mc, self.sep)
        P = self._phase(ur, sn, cn, dn, j)
        odd = np.where(np.mod(j, 2.0) == 1.0, -1.0, 1.0)
        sn, cn = sn * odd, cn * odd
        psi = self.rate * t + self.C * (P - self.P0)
        B = self._B(self.s1 * self.a1 * cn, self.a2 * sn, self.s3 * self.a3 * dn)   # (T, n, 3, 3)
        c, s = np.cos(psi)[..., None], np.sin(psi)[..., None]
        r1, r2, r3 = B[..., 0, :], B[..., 1, :], B[..., 2, :]
        RzB = np.stack([c * r1 - s * r2, s * r1 + c * r2, r3], -2)
        D = transpose(self.B0) @ RzB
        if self.flip.any():
            Df = D[..., RELABEL, :][..., :, RELABEL] * (RELABEL_SIGN[:, None] * RELABEL_SIGN[None, :])
            D = np.where(self.flip[:, None, None], Df, D)
        return D


def is_identity(A) -> bool:
    """Whether A is exactly the 3×3 identity (principal axes = body axes: no change of frame)."""
    return bool(np.array_equal(np.asarray(A), np.eye(3)))


def times(t) -> np.ndarray:
    """The times of exact_free_body, checked, as a 1-D float array.  t: a real number or a 1-D
    array of finite real numbers (ints or floats: not strings, bools, complex)."""
    if isinstance(t, (str, bytes)) or (np.isscalar(t) and not checks.is_real_scalar(t)):
        checks.real("t", t)                                     # one time must be a real number: raises
    arr = checks.numbers("t", t, "a real number or a 1-D array of real numbers (times in s)")
    if arr.ndim == 0:
        arr = arr.reshape(1)
    if arr.ndim != 1:
        raise ValueError(f"t must be a real number or a 1-D array of times, got shape {arr.shape}")
    if arr.size == 0:
        raise ValueError("t must hold at least one time, got an empty array")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"t must contain only finite times (no NaN or inf), got {arr.tolist()}")
    return arr
