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
against a tight DOP853 integration in tests/test_exact.py):

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

3.  Elliptic functions.  For m' >= 1e-2 scipy.special.ellipj (after the reduction to
    |τ| <= K, K = R_F(0, m', 1)).  Closer to the separatrix scipy's ellipj loses
    digits (it takes m, not m', and uses a first-order expansion for m' < 1e-9), so
    sn, cn, dn come from ascending Landen transformations (DLMF 22.7.ii) driven by
    m' itself, down to m' < 1e-15 where the hyperbolic limit with its first-order
    correction (A&S 16.15) is exact to rounding.  Exactly on the separatrix (m' = 0):
    sn = tanh τ, cn = dn = sech τ and Π(am τ, n | 1) = (τ + √ν atan(√ν tanh τ))/(1 + ν), ν = −n.

Two moments within SYMMETRY_TOL (relative, a few ulps: eigen-decomposition noise) are
taken as equal (the symmetric closed form); a momentum component below 1e-150 |L| is
taken as zero (a spin along that principal axis).
"""
from __future__ import annotations

import math

import numpy as np
from scipy import special

from .. import checks
from ..body import RigidBody, inertia_matrix
from ..rotation import exp_so3, orthogonality_error, transpose
from ..scene import Scene
from ..state import R_TOLERANCE, State
from ..trajectory import Trajectory

__all__ = ["exact_free_body", "free_rotation_flow", "FreeRotationFlow", "SYMMETRY_TOL"]

SYMMETRY_TOL = 2e-15      # principal moments closer than this (relative to the largest) are equal
_TINY = 1e-150            # |μᵢ| below this is taken as 0 (a spin along a principal axis)
_LANDEN_MC = 1e-2         # m' below this: our own Landen evaluation instead of scipy's ellipj
_LANDEN_STOP = 1e-15      # Landen steps until m' is below this
_SEPARATRIX_MC = 1e-280   # m' below this is the separatrix itself (K would overflow cosh)


# =====================================================================================
# public API
# =====================================================================================

def exact_free_body(body: RigidBody, X0: State, t) -> Trajectory:
    """The exact motion of a free rigid body (no force, no torque) from X0, at the times t.

        x(t) = x0 + (P/M) t,   P(t) = P,   L(t) = L   (world, about the centre of mass),
        R(t) exact (closed forms; Jacobi elliptic functions for an asymmetric body).

    body: the RigidBody (any inertia: asymmetric, symmetric, spherical, non-diagonal).
    X0: a single-body State.  t: a time or a 1-D array of times (any real values, in any
    order, negative ones run backwards); all times are computed at once (vectorised).
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
    t = _times(t)

    A = np.asarray(body.principal_axes)
    moments = np.asarray(body.principal_moments)
    mb = R0.T @ L                                      # body angular momentum
    motion = _Motion(moments[None], (A.T @ mb)[None])
    D = motion.increment(t)[:, 0]                      # (T, 3, 3), principal frame
    if not _is_identity(A):
        D = A @ D @ A.T
    R = R0 @ D
    R[t == 0] = R0                                     # exactly X0 at t = 0
    T = len(t)
    x = x0 + np.outer(t, P / body.mass)
    return Trajectory(t, x, R, np.broadcast_to(P, (T, 3)).copy(), np.broadcast_to(L, (T, 3)).copy(),
                      scene=Scene(body), method="exact")


class FreeRotationFlow:
    """The exact torque-free flow of the orientation, for splitting integrators.

    ``flow = FreeRotationFlow(inertia)`` does the set-up that depends only on the
    inertia (the principal axes) once; ``flow(R, L, h)`` then returns R(h), the
    orientation after a time h of torque-free motion with the constant world angular
    momentum L:  Ṙ = ω* R,  ω = R I⁻¹ Rᵀ L.  Use it as the "free rigid body" step of a
    kick–flow–kick method (L is unchanged by this step; the kicks change it).

    inertia: body-frame inertia about the rotation centre — 3 principal moments (3,),
    one 3×3 matrix, one matrix per body (N, 3, 3), or a RigidBody (its I_body).
    R: (3, 3) or (N, 3, 3); L: (3,) or (N, 3) (world); h: a real step (any sign).

    A single body (R (3, 3), or (1, 3, 3)) takes a plain-Python fast path; N bodies
    are computed as arrays.  R, L are not checked for finiteness here (it is a hot
    path); shapes and h are.
    """

    def __init__(self, inertia):
        if isinstance(inertia, RigidBody):
            inertia = inertia.I_body
        arr = checks.numbers("inertia", inertia, "3 principal moments, a 3x3 matrix or (N, 3, 3) matrices")
        if arr.shape in ((3,), (3, 3)):
            mats = inertia_matrix(arr)[None]
            self.n = None
        elif arr.ndim == 3 and arr.shape[1:] == (3, 3) and arr.shape[0] > 0:
            mats = np.stack([inertia_matrix(a) for a in arr])
            self.n = arr.shape[0]
        else:
            raise ValueError(f"inertia must have shape (3,), (3, 3) or (N, 3, 3), got shape {arr.shape}")
        moments, axes = np.linalg.eigh(mats)
        axes[np.linalg.det(axes) < 0, :, 2] *= -1.0
        self.inertia = mats if self.n is not None else mats[0]
        self.moments = moments                         # (N or 1, 3) ascending
        self.axes = axes                               # (N or 1, 3, 3), det +1
        self.identity_axes = bool(all(_is_identity(a) for a in axes))
        # a single body (also given as (1, 3, 3)): plain-float constants for the fast path
        self._one = _OneBody(moments[0], axes[0]) if self.n in (None, 1) else None

    def __call__(self, R, L, h):
        """R(h) for the constant world angular momentum L (see the class docstring)."""
        h = checks.real("h", h)
        R = np.asarray(R, dtype=float)
        L = np.asarray(L, dtype=float)
        if R.ndim == 2:
            if R.shape != (3, 3) or L.shape != (3,):
                raise ValueError(f"R must have shape (3, 3) and L (3,) (or (N, 3, 3) and (N, 3)), "
                                 f"got R {R.shape} and L {L.shape}")
            if self.n is not None and self.n != 1:
                raise ValueError(f"the flow holds {self.n} bodies but R has shape (3, 3): pass R (N, 3, 3)")
            return self._one.flow(R, L, h)
        if R.ndim != 3 or R.shape[1:] != (3, 3) or L.shape != (R.shape[0], 3):
            raise ValueError(f"R must have shape (N, 3, 3) and L (N, 3) (or (3, 3) and (3,)), "
                             f"got R {R.shape} and L {L.shape}")
        if self.n is not None and self.n != R.shape[0]:
            raise ValueError(f"the flow holds {self.n} bodies but R holds {R.shape[0]}")
        if R.shape[0] == 1 and self._one is not None:
            return self._one.flow(R[0], L[0], h)[None]
        return self._many(R, L, h)

    def _many(self, R, L, h):
        if h == 0.0:
            return R.copy()
        N = R.shape[0]
        A = np.broadcast_to(self.axes, (N, 3, 3))
        moments = np.broadcast_to(self.moments, (N, 3))
        mb = np.einsum("nji,nj->ni", R, L)             # Rᵀ L
        mp = mb if self.identity_axes else np.einsum("nji,nj->ni", A, mb)
        D = _Motion(moments, mp).increment(np.array([h]))[0]
        if not self.identity_axes:
            D = A @ D @ transpose(A)
        return R @ D


def free_rotation_flow(inertia, R, L, h):
    """R(h): the exact torque-free flow of the orientation (one call of FreeRotationFlow).

    inertia: body-frame inertia — 3 principal moments, a 3×3 matrix, or (N, 3, 3).
    R (3, 3) or (N, 3, 3) at the start, L (3,) or (N, 3) the constant world angular
    momentum, h the time step (any sign).  Returns R(h) with Ṙ = ω* R, ω = R I⁻¹ Rᵀ L.
    For repeated steps build ``FreeRotationFlow(inertia)`` once and call it (the
    eigen-decomposition of the inertia is then done once).
    """
    R_arr = checks.numbers("R", R, "an array of numbers of shape (3, 3) or (N, 3, 3)")
    L_arr = checks.numbers("L", L, "an array of numbers of shape (3,) or (N, 3)")
    for name, arr in (("R", R_arr), ("L", L_arr)):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must contain only finite numbers, got {arr.tolist()}")
    return FreeRotationFlow(inertia)(R_arr, L_arr, h)


# =====================================================================================
# the motion in principal axes, vectorised over N bodies and T times
# =====================================================================================

class _Motion:
    """Constants of the torque-free motion of N bodies; increment(t) -> D(t) (T, N, 3, 3).

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
        mu = np.where(np.abs(mu) < _TINY, 0.0, mu)
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
            self.ell = _Elliptic(moments[self.ie], mu[self.ie], Ln[self.ie])

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


_S_PERM = [2, 1, 0]
_S_SIGN = np.array([1.0, -1.0, 1.0])


class _Elliptic:
    """The asymmetric, off-axis case (see the module docstring for the formulas)."""

    def __init__(self, I, mu, Ln):
        I1, I2, I3 = I[:, 0], I[:, 1], I[:, 2]
        m1, m3 = mu[:, 0], mu[:, 2]
        delta = m1 * m1 * ((I1 - I2) / I1) + m3 * m3 * ((I3 - I2) / I3)
        self.flip = delta < 0                       # polhode about axis 1: relabel (3, 2, 1)
        f = self.flip[:, None]
        J = np.where(f, I[:, ::-1], I)
        w = np.where(f, mu[:, _S_PERM] * _S_SIGN, mu)
        J1, J2, J3 = J[:, 0], J[:, 1], J[:, 2]
        w1, w2, w3 = w[:, 0], w[:, 1], w[:, 2]
        d31, d32, d21 = J3 - J1, J3 - J2, J2 - J1
        beta = w2 * w2 * (d21 / J2) + w3 * w3 * (d31 / J3)
        mc = np.clip((d31 * delta) / (d32 * beta), 0.0, 1.0)
        mc = np.where(mc < _SEPARATRIX_MC, 0.0, mc)
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
        """Λ(τ) = Π(am τ, n | m) − τ (|n| <= 1) or Π(am τ, n | m) itself (|n| > 1), (T, n) arrays.

        τ = u + 2jK with |u| <= K and sn, cn, dn at u.  For |n| > 1 Π comes from the
        transformation n → m/n (DLMF 19.7.9), free of the cancellation F + (n/3)(...):
            Π(φ, n|m) = sn R_C(cn² dn², (1 − n sn²)(1 − (m/n) sn²)) − (m/3n) sn³ R_J(cn², dn², 1, 1 − (m/n) sn²).
        On the separatrix (m = 1): Π(am τ, n|1) = (τ + √ν atan(√ν tanh τ))/(1 + ν), ν = −n.
        """
        out = np.empty_like(u)
        sep, big = self.sep, self.big_n
        for cols, kind in ((~sep & ~big, 0), (~sep & big, 1), (sep, 2)):
            if not cols.any():
                continue
            cols = np.flatnonzero(cols)
            n = self.n[cols]
            uu, s = u[:, cols], sn[:, cols]
            if kind == 2:
                nu = -n
                r = np.sqrt(nu)
                at = r * np.arctan(r * np.tanh(uu))
                out[:, cols] = np.where(big[cols], uu + at, at - nu * uu) / (1.0 + nu)
                continue
            c2, d2, s2 = cn[:, cols] ** 2, dn[:, cols] ** 2, s * s
            if kind == 0:
                val = n / 3.0 * s * s2 * special.elliprj(c2, d2, 1.0, 1.0 - n * s2)
            else:
                w = self.w[cols]
                val = (s * special.elliprc(c2 * d2, (1.0 - n * s2) * (1.0 - w * s2))
                       - w / 3.0 * s * s2 * special.elliprj(c2, d2, 1.0, 1.0 - w * s2))
            out[:, cols] = val + j[:, cols] * self.half[cols]
        return out

    def increment(self, t):
        """D(t) in principal axes, t (T, 1) -> (T, n, 3, 3)."""
        u = self.tau0 + self.lam * t
        K2 = 2.0 * np.where(self.sep, 1.0, self.K)
        j = np.where(self.sep, 0.0, np.rint(u / K2))
        ur = u - j * K2
        sn, cn, dn = _jacobi(ur, self.mc, self.sep)
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
            Df = D[..., _S_PERM, :][..., :, _S_PERM] * (_S_SIGN[:, None] * _S_SIGN[None, :])
            D = np.where(self.flip[:, None, None], Df, D)
        return D


def _jacobi(u, mc, sep):
    """sn, cn, dn (u | m = 1 − mc) for u (T, n) reduced to |u| <= K, mc (n,) given directly."""
    sn, cn, dn = np.empty_like(u), np.empty_like(u), np.empty_like(u)
    big = mc >= _LANDEN_MC
    near = ~big & ~sep
    if big.all():
        sn, cn, dn, _ = special.ellipj(u, 1.0 - mc)
        return sn, cn, dn
    if big.any():
        c = np.flatnonzero(big)
        sn[:, c], cn[:, c], dn[:, c], _ = special.ellipj(u[:, c], 1.0 - mc[c])
    if sep.any():
        c = np.flatnonzero(sep)
        sn[:, c], cn[:, c] = np.tanh(u[:, c]), _sech(u[:, c])
        dn[:, c] = cn[:, c]
    if near.any():
        c = np.flatnonzero(near)
        sn[:, c], cn[:, c], dn[:, c] = _jacobi_landen(u[:, c], mc[c])
    return sn, cn, dn


def _sech(u):
    e = np.exp(-np.abs(u))
    return 2.0 * e / (1.0 + e * e)


def _jacobi_landen(u, mc):
    """sn, cn, dn for m' = mc small (< 1e-2) by ascending Landen transformations (DLMF 22.7.ii).

    k₂' = (1 − k)/(1 + k) = m'/(1 + k)²,  m₂' = k₂'²,  v = u/(1 + k₂'),
    sn(u|m) = (1 + k₂') sn cn/dn,  cn(u|m) = (1 + k₂')/k₂² (dn² − k₂')/dn,
    dn(u|m) = (1 − k₂')/k₂² (dn² + k₂')/dn   (right sides at (v | m₂)),
    until m' < 1e-15, then the hyperbolic limit with its first-order term (A&S 16.15).
    """
    c = np.broadcast_to(mc, u.shape).copy()
    v = u.copy()
    kps = []
    while np.any(c > _LANDEN_STOP):
        kp = c / (1.0 + np.sqrt(1.0 - c)) ** 2
        kps.append(kp)
        v = v / (1.0 + kp)
        c = kp * kp
    th, se = np.tanh(v), _sech(v)
    sh = th / se                                  # |v| <= K < 330 here: no overflow
    a = 0.25 * c * (sh - v * se)                  # ¼ m' (sinh cosh − v) sech
    b = 0.25 * c * (sh + v * se)
    sn, cn, dn = th + a * se, se - a * th, se + b * th
    for kp in reversed(kps):
        k22 = (1.0 - kp) * (1.0 + kp)
        d2 = dn * dn
        sn, cn, dn = (1.0 + kp) * sn * cn / dn, (1.0 + kp) / k22 * (d2 - kp) / dn, (1.0 - kp) / k22 * (d2 + kp) / dn
    return sn, cn, dn


# =====================================================================================
# one body, plain Python floats (the splitting methods' hot path)
# =====================================================================================

class _OneBody:
    """Precomputed constants of one body; flow(R, L, h) with Python floats throughout.

    The closed forms are applied in body axes (no change of frame): with m = RᵀL,
    R(h) = R exp(h m*/I_eq) exp(h (1/I_s − 1/I_eq)(a·m) a*)  (a the body symmetry axis).
    """

    def __init__(self, moments, axes):
        I1, I2, I3 = (float(v) for v in moments)
        axes = np.asarray(axes, dtype=float)
        self.I = (I1, I2, I3)
        self.A = None if _is_identity(axes) else axes.tolist()
        self.At = None if self.A is None else axes.T.tolist()
        sym12 = I2 - I1 <= SYMMETRY_TOL * I3
        sym23 = I3 - I2 <= SYMMETRY_TOL * I3
        self.a = None
        if sym12 and sym23:
            self.kind, self.I_eq = "spherical", (I1 + I2 + I3) / 3.0
        elif sym12 or sym23:
            s = 2 if sym12 else 0
            self.kind = "symmetric"
            self.I_eq = 0.5 * (I1 + I2) if sym12 else 0.5 * (I2 + I3)
            self.a = axes[:, s].tolist()                    # symmetry axis in body axes
            self.c_s = 1.0 / self.I[s] - 1.0 / self.I_eq
        else:
            self.kind, self.I_eq = "asymmetric", None

    def flow(self, R, L, h):
        if h == 0.0:
            return R.copy()
        Rl = R.tolist()
        L0, L1, L2 = L.tolist()
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = Rl
        m0, m1, m2 = r00 * L0 + r10 * L1 + r20 * L2, r01 * L0 + r11 * L1 + r21 * L2, r02 * L0 + r12 * L1 + r22 * L2
        kind = self.kind
        if kind == "spherical":
            k = h / self.I_eq
            D = _quat_matrix(_quat_rotvec((k * m0, k * m1, k * m2)))
        elif kind == "symmetric":
            k = h / self.I_eq
            a0, a1, a2 = self.a
            c = h * self.c_s * (a0 * m0 + a1 * m1 + a2 * m2)
            D = _quat_matrix(_quat_mul(_quat_rotvec((k * m0, k * m1, k * m2)), _quat_rotvec((c * a0, c * a1, c * a2))))
        else:
            A = self.A
            mp = [m0, m1, m2] if A is None else [A[0][i] * m0 + A[1][i] * m1 + A[2][i] * m2 for i in range(3)]
            Ln = math.hypot(mp[0], mp[1], mp[2])
            if Ln == 0.0:
                return R.copy()
            mu = [v / Ln if abs(v / Ln) >= _TINY else 0.0 for v in mp]
            if (mu[0] != 0.0) + (mu[1] != 0.0) + (mu[2] != 0.0) <= 1:    # spin along a principal axis
                k = h / self.I[max(range(3), key=lambda i: abs(mu[i]))]
                D = _quat_matrix(_quat_rotvec((k * m0, k * m1, k * m2)))
            else:
                D = _elliptic_one(self.I, mu, Ln, h)
                if A is not None:
                    D = _mm(_mm(A, D), self.At)
        return np.array(_mm(Rl, D))


def _elliptic_one(I, mu, Ln, h):
    """D(h) in principal axes for one asymmetric body off its axes (same formulas as _Elliptic)."""
    I1, I2, I3 = I
    m1, m2, m3 = mu
    delta = m1 * m1 * ((I1 - I2) / I1) + m3 * m3 * ((I3 - I2) / I3)
    flip = delta < 0
    if flip:
        J1, J2, J3 = I3, I2, I1
        w1, w2, w3 = m3, -m2, m1
    else:
        J1, J2, J3 = I1, I2, I3
        w1, w2, w3 = m1, m2, m3
    d31, d32, d21 = J3 - J1, J3 - J2, J2 - J1
    beta = w2 * w2 * (d21 / J2) + w3 * w3 * (d31 / J3)
    mc = min(max((d31 * delta) / (d32 * beta), 0.0), 1.0)
    if mc < _SEPARATRIX_MC:
        mc = 0.0
    a1 = math.sqrt(w1 * w1 + w2 * w2 * ((J1 * d32) / (J2 * d31)))
    a2 = math.sqrt(w2 * w2 + w1 * w1 * ((J2 * d31) / (J1 * d32)))
    a3 = math.sqrt(w3 * w3 + w2 * w2 * ((J3 * d21) / (J2 * d31)))
    s1 = -1.0 if w1 < 0 else 1.0
    s3 = -1.0 if w3 < 0 else 1.0
    lam = s1 * s3 * math.copysign(1.0, d31) * Ln * math.sqrt((d32 * beta) / (J1 * J2 * J3))
    n = -(J3 * d21) / (J1 * d32)
    C = Ln * d31 / (J1 * J3 * lam)
    sn0 = w2 / a2
    cn0 = abs(w1) / a1
    hyp = math.hypot(sn0, cn0)
    sn0, cn0 = sn0 / hyp, cn0 / hyp
    dn0 = abs(w3) / a3
    tau0 = sn0 * float(special.elliprf(cn0 * cn0, dn0 * dn0, 1.0))
    u = tau0 + lam * h
    big = abs(n) > 1.0
    if mc == 0.0:
        nu = -n
        r = math.sqrt(nu)
        sn, cn = math.tanh(u), _sech1(u)
        dn = cn
        if big:
            P = (u + r * math.atan(r * sn)) / (1.0 + nu)
            P0 = (tau0 + r * math.atan(r * math.tanh(tau0))) / (1.0 + nu)
        else:
            P = (r * math.atan(r * sn) - nu * u) / (1.0 + nu)
            P0 = (r * math.atan(r * math.tanh(tau0)) - nu * tau0) / (1.0 + nu)
    else:
        if abs(u) <= max(abs(tau0), 1.5707963267948966):     # |u| <= K for sure (|τ0| <= K, π/2 <= K)
            j, ur = 0, u
        else:
            K = float(special.elliprf(0.0, mc, 1.0))
            j = round(u / (2.0 * K))
            ur = u - j * 2.0 * K
        if mc >= _LANDEN_MC:
            sn, cn, dn, _ = special.ellipj(ur, 1.0 - mc)
            sn, cn, dn = float(sn), float(cn), float(dn)
        else:
            sn, cn, dn = _landen1(ur, mc)
        if big:
            w = (1.0 - mc) / n
            P = _pi_big(sn, cn, dn, n, w)
            P0 = _pi_big(sn0, cn0, dn0, n, w)
            if j:
                P += 2.0 * j * float(special.elliprc(0.0, (1.0 - n) * (1.0 - w))
                                     - w / 3.0 * special.elliprj(0.0, mc, 1.0, 1.0 - w))
        else:
            n3 = n / 3.0
            P = n3 * sn ** 3 * float(special.elliprj(cn * cn, dn * dn, 1.0, 1.0 - n * sn * sn))
            P0 = n3 * sn0 ** 3 * float(special.elliprj(cn0 * cn0, dn0 * dn0, 1.0, 1.0 - n * sn0 * sn0))
            if j:
                P += n3 * 2.0 * j * float(special.elliprj(0.0, mc, 1.0, 1.0 - n))
        if j % 2:
            sn, cn = -sn, -cn
    psi = Ln / (J3 if big else J1) * h + C * (P - P0)
    B0 = _B1(w1, w2, w3)
    B = _B1(s1 * a1 * cn, a2 * sn, s3 * a3 * dn)
    c, s = math.cos(psi), math.sin(psi)
    r1, r2 = B[0], B[1]
    RzB = [[c * r1[i] - s * r2[i] for i in range(3)], [s * r1[i] + c * r2[i] for i in range(3)], B[2]]
    D = _mtm(B0, RzB)
    if flip:
        p = _S_PERM
        sg = (1.0, -1.0, 1.0)
        D = [[sg[i] * sg[k] * D[p[i]][p[k]] for k in range(3)] for i in range(3)]
    return D


def _pi_big(sn, cn, dn, n, w):
    """Π(am τ, n | m) for |n| > 1 by the n → m/n transformation (w = m/n); see _Elliptic._phase."""
    s2, c2, d2 = sn * sn, cn * cn, dn * dn
    return float(sn * special.elliprc(c2 * d2, (1.0 - n * s2) * (1.0 - w * s2))
                 - w / 3.0 * sn * s2 * special.elliprj(c2, d2, 1.0, 1.0 - w * s2))


def _B1(w1, w2, w3):
    nrm = math.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
    w1, w2, w3 = w1 / nrm, w2 / nrm, w3 / nrm
    rho = math.hypot(w1, w2)
    c1, c2 = w1 / rho, w2 / rho
    return [[c2, -c1, 0.0], [w3 * c1, w3 * c2, -rho], [w1, w2, w3]]


def _sech1(u):
    e = math.exp(-abs(u))
    return 2.0 * e / (1.0 + e * e)


def _landen1(u, mc):
    """Scalar version of _jacobi_landen."""
    c, v, kps = mc, u, []
    while c > _LANDEN_STOP:
        kp = c / (1.0 + math.sqrt(1.0 - c)) ** 2
        kps.append(kp)
        v = v / (1.0 + kp)
        c = kp * kp
    th, se = math.tanh(v), _sech1(v)
    sh = th / se
    a = 0.25 * c * (sh - v * se)
    b = 0.25 * c * (sh + v * se)
    sn, cn, dn = th + a * se, se - a * th, se + b * th
    for kp in reversed(kps):
        k22 = (1.0 - kp) * (1.0 + kp)
        d2 = dn * dn
        sn, cn, dn = (1.0 + kp) * sn * cn / dn, (1.0 + kp) / k22 * (d2 - kp) / dn, (1.0 - kp) / k22 * (d2 + kp) / dn
    return sn, cn, dn


def _quat_rotvec(phi):
    """Unit quaternion (w, x, y, z) of the rotation vector φ (plain floats)."""
    th = math.sqrt(phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2])
    if th < 1e-8:
        s = 0.5 - th * th / 48.0
        return (1.0 - th * th / 8.0, s * phi[0], s * phi[1], s * phi[2])
    s = math.sin(0.5 * th) / th
    return (math.cos(0.5 * th), s * phi[0], s * phi[1], s * phi[2])


def _quat_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def _quat_matrix(q):
    w, x, y, z = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def _mm(A, B):
    """A B for 3×3 nested lists (unrolled: this is the hot path)."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = A
    (b00, b01, b02), (b10, b11, b12), (b20, b21, b22) = B
    return [[a00 * b00 + a01 * b10 + a02 * b20, a00 * b01 + a01 * b11 + a02 * b21, a00 * b02 + a01 * b12 + a02 * b22],
            [a10 * b00 + a11 * b10 + a12 * b20, a10 * b01 + a11 * b11 + a12 * b21, a10 * b02 + a11 * b12 + a12 * b22],
            [a20 * b00 + a21 * b10 + a22 * b20, a20 * b01 + a21 * b11 + a22 * b21, a20 * b02 + a21 * b12 + a22 * b22]]


def _mtm(A, B):
    """Aᵀ B for 3×3 nested lists."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = A
    (b00, b01, b02), (b10, b11, b12), (b20, b21, b22) = B
    return [[a00 * b00 + a10 * b10 + a20 * b20, a00 * b01 + a10 * b11 + a20 * b21, a00 * b02 + a10 * b12 + a20 * b22],
            [a01 * b00 + a11 * b10 + a21 * b20, a01 * b01 + a11 * b11 + a21 * b21, a01 * b02 + a11 * b12 + a21 * b22],
            [a02 * b00 + a12 * b10 + a22 * b20, a02 * b01 + a12 * b11 + a22 * b21, a02 * b02 + a12 * b12 + a22 * b22]]


# =====================================================================================
# helpers
# =====================================================================================

def _is_identity(A) -> bool:
    return bool(np.array_equal(np.asarray(A), np.eye(3)))


def _times(t) -> np.ndarray:
    """t: a real number or a 1-D array of finite real numbers (ints or floats: not strings, bools, complex)."""
    if isinstance(t, (str, bytes)) or (np.isscalar(t) and not checks._is_real_scalar(t)):
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
