"""exact_splitting on the slides' state S (N, 18) = [x, R, P, L]: kick / exact torque-free flow / kick.

    K(b₀h) F(a₁h) K(b₁h) F(a₂h) … F(a_s h) K(b_s h)       (the fractions: compositions.py)

K: a kick, P += bh F, L += bh τ at fixed positions (geometric.kick: one evaluation, or a Runge–Kutta
table of the composition's order when a force depends on the velocities: MIDPOINT for the order-2
strang, RK4 for the order-4 compositions, tableaus.py), forces at the time reached so far, t + (a₁ + … + a_j) h.
F: the exact free flow over ah: x ← x + ah P/M, and R from the exact torque-free motion with L constant
(world), in body axes m = Rᵀ L (free_rotation):

    spherical:   R(h) = R exp(h m*/I_eq)                                 (I₁ = I₂ = I₃, I_eq their mean)
    symmetric:   R(h) = R exp(h m*/I_eq) exp(h (1/I_s − 1/I_eq)(a·m) a*)  (a the symmetry axis, moment I_s;
                                                                          I_eq the mean of the equal pair)
    asymmetric:  R(h) = R exp(h m*/I_k) along a principal axis k, else R A D(h) Aᵀ with D from Jacobi's
                 solution at t = h (elliptic_rotation: Jacobi's sn, cn, dn and Carlson's R_F, R_C, R_J,
                 elliptic.py)

then retract (one Björck step) and the pivot constraint.  Equal moments: closer than EQUAL_MOMENTS times
the largest, tested on the System's ascending I_moments, the symmetry axis a column of I_axes.

Two exact torque-free motions, on purpose.  This one is a METHOD's step: it runs inside the compiled loop,
so it is written on plain floats and tuples (no scipy: scipy cannot be called from compiled code; no
array: the step allocates nothing), with its own elliptic functions (elliptic.py) and its own constants.
rbcourse/exact/ (free_body.py, with scipy.special) is the other: the independent REFERENCE that tests,
benchmarks and notebooks compare the methods with.  They share no code — a reference that shared code
with what it checks would prove nothing —; tests/test_two_exact_flows.py checks one against the other
(rotation and L, asymmetric, near-symmetric and symmetric bodies, both sides of the separatrix,
principal-axis spins, L = 0).  This file imports nothing of rbcourse outside rbcourse/engine/.

The composition arrives as data: opts = [s, b₀ … b_s, a₁ … a_s] (options(scene, settings)); the kick table as
the step's A, b, den (kick_table(settings)); the force values at the kick times (nodes(settings): kick j's
stages all at c_j = a₁ + … + a_j, values[j len(b) + i] for its stage i).
"""
from __future__ import annotations

import math

import numpy as np

from .algebra import dot, exp_so3, matmul, matvec, norm, retract, scale, transpose
from .compositions import composition
from .elliptic import SEPARATRIX_MC, elliprc, elliprf, elliprj, ellipk, jacobi_reduced
from .geometric import EULER_B, kick, velocity_dependent
from .jit import inline, njit
from .motion import constrain_state, copy_into, drift, put_state, stages_between, state_of
from .tableaus import MIDPOINT, RK4

SPHERICAL, SYMMETRIC, ASYMMETRIC = 0, 1, 2
# Two principal moments closer than this, relative to the largest, are equal (the symmetric closed form).
# The moments come from an eigen-decomposition of I_rot, good to a few ulps (2.2e-16 each): closer than
# ~10 ulps they are equal to that rounding, and the elliptic formulas, which divide by their difference
# (d32 or d21), have no digit left there, while the closed form is exact.  Above it, up to the nearly
# symmetric 1e-9 and beyond, the |n| > 1 form of ψ keeps the elliptic formulas accurate.
EQUAL_MOMENTS = 2e-15
# A component of the unit body momentum μ below this is 0: a spin along a principal axis (exp(h m*/I_k)).
# The elliptic formulas divide by ρ = √(μ₁² + μ₂²) and square the components: below 1e-150 the squares
# (1e-300) near the subnormal range; and a departure ε from an axis grows at most as ε e^(λh) over a step,
# which stays below rounding unless λh > 300.
ZERO_COMPONENT = 1e-150


# --- the method as data (Python side) ------------------------------------------------------------------

def kick_table(settings: dict):
    """The kicks' table when a force depends on the velocities: a Runge–Kutta table of the composition's
    order, MIDPOINT (order 2: strang) or RK4 (order 4) of tableaus.py."""
    return MIDPOINT if composition(settings)["order"] == 2 else RK4


def nodes(settings: dict) -> tuple:
    """The times t + c h of the force evaluations: kick j at c_j = a₁ + … + a_j, repeated for each
    stage of the kick table (all of a kick's stages at its time)."""
    table = composition(settings)
    stages = kick_table(settings).stages
    c, out = 0.0, []
    for j in range(len(table["kicks"])):
        if j > 0:
            c += table["flows"][j - 1]
        out += [c] * stages
    return tuple(out)


def configure(sys, settings: dict) -> tuple:
    """The family's run (run.py: LOOPS["exact"]): (table, nodes, opts), all following the composition of the
    method's settings — kick_table, nodes, options."""
    return kick_table(settings), nodes(settings), options(sys, settings)


def options(scene, settings: dict) -> np.ndarray:
    """opts = [s, b₀ … b_s, a₁ … a_s]: the number of flows s, the kick fractions, the flow fractions."""
    table = composition(settings)
    kicks, flows = table["kicks"], table["flows"]
    return np.array([float(len(flows)), *kicks, *flows], dtype=float)


@inline
def body_kind(moments):
    """SPHERICAL, SYMMETRIC or ASYMMETRIC for ascending principal moments (two moments closer than
    EQUAL_MOMENTS, relative to the largest, are equal)."""
    I1, I2, I3 = moments[0], moments[1], moments[2]
    sym12 = I2 - I1 <= EQUAL_MOMENTS * I3
    sym23 = I3 - I2 <= EQUAL_MOMENTS * I3
    if sym12 and sym23:
        return SPHERICAL
    if sym12 or sym23:
        return SYMMETRIC
    return ASYMMETRIC


def exact_flow_supported(sys) -> str:
    """'' if every body of the scene (its System, system.py) has an exact free flow here (every physical inertia:
    spherical, symmetric and asymmetric bodies, free_rotation), else why not (one line): principal moments about
    the rotation centre (sys.I_moments) that are not finite and positive."""
    bad = [i for i, m in enumerate(sys.I_moments) if not np.all(m > 0)]
    if bad:
        return (f"exact_splitting needs finite positive principal moments (body {bad[0]}: "
                f"{sys.I_moments[bad[0]].tolist()})")
    return ""


# --- the exact free flow (compiled) ----------------------------------------------------------------------

@inline
def _B(w):
    """B(μ) of Jacobi's solution for μ = w/|w| (off axis 3): rows r1 = (μ2, −μ1, 0)/ρ,
    r2 = (μ3μ1/ρ, μ3μ2/ρ, −ρ), r3 = μ, ρ = √(μ1² + μ2²); B μ = e3."""
    nrm = norm(w)
    w1, w2, w3 = w[0] / nrm, w[1] / nrm, w[2] / nrm
    rho = math.hypot(w1, w2)
    c1, c2 = w1 / rho, w2 / rho
    return ((c2, -c1, 0.0), (w3 * c1, w3 * c2, -rho), (w1, w2, w3))


@inline
def _pi_big_n(sn, cn, dn, n, w):
    """Π(am τ, n | m) for |n| > 1 by the n → w = m/n transformation (DLMF 19.7.9), free of cancellation:
    sn R_C(cn² dn², (1 − n sn²)(1 − w sn²)) − (w/3) sn³ R_J(cn², dn², 1, 1 − w sn²)."""
    s2, c2, d2 = sn * sn, cn * cn, dn * dn
    return (sn * elliprc(c2 * d2, (1.0 - n * s2) * (1.0 - w * s2))
            - w / 3.0 * sn * s2 * elliprj(c2, d2, 1.0, 1.0 - w * s2))


@inline
def elliptic_rotation(I, mu, Ln, h):
    """D(h) in principal axes of an asymmetric body (I₁ < I₂ < I₃) off its principal axes: μ the unit body
    angular momentum, |L| = Ln — Jacobi's solution at t = h (the derivation: rbcourse/exact/free_body.py,
    steps 1 and 2, whose notation this follows; the code is this one):

        polhode about axis 3 (δ >= 0), else relabelled (J1, J2, J3) = (I3, I2, I1), μ → (μ3, −μ2, μ1);
        m' = d31 δ/(d32 β), τ = τ0 + λh, τ0 = sn φ0 R_F(cn² φ0, dn² φ0, 1);
        D = B(μ(0))ᵀ Rz(ψ(h) − ψ(0)) B(μ(h)),  μ(h) = (s1 a1 cn τ, a2 sn τ, s3 a3 dn τ),
        ψ(h) − ψ(0) = |L| h/J1 + C [Λ(τ) − Λ(τ0)]   (|n| <= 1;  |L| h/J3 and Π when |n| > 1),

    Λ and Π in Carlson's forms (elliptic.py), τ reduced by the half period 2K when it leaves [−K, K]."""
    delta = mu[0] * mu[0] * ((I[0] - I[1]) / I[0]) + mu[2] * mu[2] * ((I[2] - I[1]) / I[2])
    flip = delta < 0
    if flip:
        J1, J2, J3 = I[2], I[1], I[0]
        w1, w2, w3 = mu[2], -mu[1], mu[0]
    else:
        J1, J2, J3 = I[0], I[1], I[2]
        w1, w2, w3 = mu[0], mu[1], mu[2]
    d31, d32, d21 = J3 - J1, J3 - J2, J2 - J1
    beta = w2 * w2 * (d21 / J2) + w3 * w3 * (d31 / J3)
    mc = min(max((d31 * delta) / (d32 * beta), 0.0), 1.0)
    if mc < SEPARATRIX_MC:
        mc = 0.0
    a1 = math.sqrt(w1 * w1 + w2 * w2 * ((J1 * d32) / (J2 * d31)))
    a2 = math.sqrt(w2 * w2 + w1 * w1 * ((J2 * d31) / (J1 * d32)))
    a3 = math.sqrt(w3 * w3 + w2 * w2 * ((J3 * d21) / (J2 * d31)))
    s1 = -1.0 if w1 < 0 else 1.0
    s3 = -1.0 if w3 < 0 else 1.0
    lam = s1 * s3 * math.copysign(1.0, d31) * Ln * math.sqrt((d32 * beta) / (J1 * J2 * J3))
    n = -(J3 * d21) / (J1 * d32)
    C = Ln * d31 / (J1 * J3 * lam)
    sn0, cn0 = w2 / a2, abs(w1) / a1
    hyp = math.hypot(sn0, cn0)
    sn0, cn0 = sn0 / hyp, cn0 / hyp
    dn0 = abs(w3) / a3
    tau0 = sn0 * elliprf(cn0 * cn0, dn0 * dn0, 1.0)
    u = tau0 + lam * h
    big = abs(n) > 1.0
    if mc == 0.0:                                        # on the separatrix: Π in closed form
        nu = -n
        r = math.sqrt(nu)
        sn, cn, dn = jacobi_reduced(u, 0.0)
        if big:
            P = (u + r * math.atan(r * sn)) / (1.0 + nu)
            P0 = (tau0 + r * math.atan(r * math.tanh(tau0))) / (1.0 + nu)
        else:
            P = (r * math.atan(r * sn) - nu * u) / (1.0 + nu)
            P0 = (r * math.atan(r * math.tanh(tau0)) - nu * tau0) / (1.0 + nu)
    else:
        j, ur = 0, u
        if abs(u) > max(abs(tau0), 1.5707963267948966):     # |u| <= K for sure below (|τ0| <= K, π/2 <= K)
            K = ellipk(mc)
            j = round(u / (2.0 * K))
            ur = u - j * 2.0 * K
        sn, cn, dn = jacobi_reduced(ur, mc)
        if big:
            w = (1.0 - mc) / n
            P = _pi_big_n(sn, cn, dn, n, w)
            P0 = _pi_big_n(sn0, cn0, dn0, n, w)
            if j:
                P += 2.0 * j * (elliprc(0.0, (1.0 - n) * (1.0 - w)) - w / 3.0 * elliprj(0.0, mc, 1.0, 1.0 - w))
        else:
            n3 = n / 3.0
            P = n3 * sn ** 3 * elliprj(cn * cn, dn * dn, 1.0, 1.0 - n * sn * sn)
            P0 = n3 * sn0 ** 3 * elliprj(cn0 * cn0, dn0 * dn0, 1.0, 1.0 - n * sn0 * sn0)
            if j:
                P += n3 * 2.0 * j * elliprj(0.0, mc, 1.0, 1.0 - n)
        if j % 2:
            sn, cn = -sn, -cn
    psi = Ln / (J3 if big else J1) * h + C * (P - P0)
    B0 = _B((w1, w2, w3))
    B = _B((s1 * a1 * cn, a2 * sn, s3 * a3 * dn))
    c, s = math.cos(psi), math.sin(psi)
    Rz = ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))
    D = matmul(transpose(B0), matmul(Rz, B))
    if flip:                                             # S D Sᵀ, S = [[0,0,1],[0,−1,0],[1,0,0]]
        D = ((D[2][2], -D[2][1], D[2][0]), (-D[1][2], D[1][1], -D[1][0]), (D[0][2], -D[0][1], D[0][0]))
    return D


@inline
def free_rotation(moments, axes, R, L, h):
    """R(h) = R D of the torque-free motion with the world L constant (module docstring), moments the
    ascending principal moments (I₁, I₂, I₃), axes the principal axes as columns (det +1), m = Rᵀ L:
    spherical and symmetric bodies in closed form; an asymmetric one spinning along a principal axis k
    (the other components of μ = Aᵀm/|m| below ZERO_COMPONENT) D = exp(h m*/I_k), else
    D = A elliptic_rotation(I, μ, |m|, h) Aᵀ."""
    I1, I2, I3 = moments[0], moments[1], moments[2]
    kind = body_kind(moments)
    sym12 = I2 - I1 <= EQUAL_MOMENTS * I3                # the pair of equal moments, for a symmetric body
    m = matvec(transpose(R), L)                          # body axes
    if h == 0.0:
        return R
    if kind == SPHERICAL:
        D = exp_so3(scale(h / ((I1 + I2 + I3) / 3.0), m))
    elif kind == SYMMETRIC:
        s = 2 if sym12 else 0
        I_eq = 0.5 * (I1 + I2) if sym12 else 0.5 * (I2 + I3)
        a = (axes[0, s], axes[1, s], axes[2, s])
        c = h * (1.0 / moments[s] - 1.0 / I_eq) * dot(a, m)
        D = matmul(exp_so3(scale(h / I_eq, m)), exp_so3(scale(c, a)))
    else:
        A = ((axes[0, 0], axes[0, 1], axes[0, 2]), (axes[1, 0], axes[1, 1], axes[1, 2]),
             (axes[2, 0], axes[2, 1], axes[2, 2]))
        mp = matvec(transpose(A), m)                     # principal axes
        Ln = norm(mp)
        if Ln == 0.0:
            return R
        mu = scale(1.0 / Ln, mp)
        mu = (mu[0] if abs(mu[0]) >= ZERO_COMPONENT else 0.0, mu[1] if abs(mu[1]) >= ZERO_COMPONENT else 0.0,
              mu[2] if abs(mu[2]) >= ZERO_COMPONENT else 0.0)
        nonzero = int(mu[0] != 0.0) + int(mu[1] != 0.0) + int(mu[2] != 0.0)    # (int: numpy's bools add as "or")
        if nonzero <= 1:                                 # spin along a principal axis k
            k = 0 if abs(mu[0]) >= max(abs(mu[1]), abs(mu[2])) else (1 if abs(mu[1]) >= abs(mu[2]) else 2)
            D = exp_so3(scale(h / moments[k], m))
        else:
            D = matmul(A, matmul(elliptic_rotation((I1, I2, I3), mu, Ln, h), transpose(A)))
    return matmul(R, D)


@njit
def free_flow(sys, S, h):
    """The exact free flow over h of every body of S (N, 18), in place: x ← x + h P/M,
    R ← retract(R(h)) (free_rotation), P, L unchanged; then the pivot constraint (x, P from R, L)."""
    for i in range(S.shape[0]):
        x, R, P, L = state_of(S, i)
        M = sys.mass[i]
        x = drift(x, h, P, M)
        R = retract(free_rotation(sys.I_moments[i], sys.I_axes[i], R, L, h))
        put_state(S, i, x, R, P, L)
    constrain_state(sys, S)


@njit
def exact_splitting_step(sys, values, opts, A, b, den, Y, out, h, K, U, w):
    """One step of the composition opts = [s, b₀ … b_s, a₁ … a_s] (options):

        out ← K(b₀h) Y;  for j = 1 … s:  out ← F(a_j h) out;  out ← K(b_j h) out

    A, b, den: the kick table when a force depends on the velocities (kick_table), else each kick is
    one evaluation (EULER); kick j reads values[j len(b) : (j + 1) len(b)] (nodes).
    K: len(b) + 1 slots (the kick's stages, then the state between kicks); U: the kick's.
    A scene with no force (and no pivot) has no kicks: the flows F(a₁h) … F(a_s h), a₁ + … + a_s = 1,
    compose exactly into one, F(h), which is what the step takes then (one flow, not s: the same motion,
    with s − 1 fewer roundings)."""
    if values is None:
        copy_into(out, Y)
        free_flow(sys, out, h)
        return
    s = int(opts[0])
    st = len(b)
    mid = K[st]
    vd = velocity_dependent(sys)
    for j in range(s + 1):
        src = Y
        if j > 0:
            free_flow(sys, out, opts[1 + s + j] * h)
            copy_into(mid, out)
            src = mid
        vj = stages_between(values, j * st, (j + 1) * st)
        bh = opts[1 + j] * h
        if vd:
            kick(sys, vj, A, b, den, src, out, bh, K, U, w)
        else:
            kick(sys, vj, A, EULER_B, 1.0, src, out, bh, K, U, w)
