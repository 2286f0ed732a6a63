"""exact_splitting on the slides' state S (N, 18) = [x, R, P, L]: kick / exact torque-free flow / kick.

    K(b₀h) F(a₁h) K(b₁h) F(a₂h) … F(a_s h) K(b_s h)       (integrators/splitting_exact.py: composed_step)

K: a kick, P += bh F, L += bh τ at fixed positions (geometric.kick: one evaluation, or the method's kick
table when a force depends on the velocities: MIDPOINT for the order-2 strang, RK4 for the order-4
compositions), forces at the time reached so far, t + (a₁ + … + a_j) h.
F: the exact free flow over ah: x ← x + ah P/M, and R from the exact torque-free motion with L constant
(world), in body axes m = Rᵀ L (rbcourse/exact/flow.py, _OneBody):

    spherical:   R(h) = R exp(h m*/I_eq)                                 (I₁ = I₂ = I₃, I_eq their mean)
    symmetric:   R(h) = R exp(h m*/I_eq) exp(h (1/I_s − 1/I_eq)(a·m) a*)  (a the symmetry axis, moment I_s;
                                                                          I_eq the mean of the equal pair)

then retract (one Björck step) and the pivot constraint.  Equal moments: closer than body.SYMMETRY_TOL
times the largest, tested on the System's ascending I_moments, the symmetry axis a column of I_axes (as the
numpy flow does).  An asymmetric body needs Jacobi's elliptic functions (rbcourse/exact): it stays on the
numpy engine (exact_flow_supported says so).

The composition arrives as data: opts = [s, b₀ … b_s, a₁ … a_s] (options(scene, settings)); the kick table as
the step's A, b, den (kick_table(settings)); the force values at the kick times (nodes(settings): kick j's
stages all at c_j = a₁ + … + a_j, values[j len(b) + i] for its stage i).
"""
from __future__ import annotations

import numpy as np

from ..body import SYMMETRY_TOL
from ..integrators.base import prepare
from ..integrators.splitting_exact import COMPOSITIONS, DEFAULT
from ..integrators.tableaus import MIDPOINT, RK4
from .algebra import dot, exp_so3, matmul, matvec, retract, scale, transpose
from .geometric import EULER_B, kick, velocity_dependent
from .jit import inline, njit
from .motion import constrain_state, copy_into, drift, put_state, state_of

SPHERICAL, SYMMETRIC, ASYMMETRIC = 0, 1, 2


# --- the method as data (Python side) ------------------------------------------------------------------

def composition(settings: dict) -> dict:
    """The composition table of the settings (splitting_exact.COMPOSITIONS; default blanes_moan4)."""
    return COMPOSITIONS[settings.get("composition", DEFAULT)]


def kick_table(settings: dict):
    """The kicks' table when a force depends on the velocities: MIDPOINT (order 2), RK4 (order 4)
    (integrators/geometric.KICK_TABLES[order])."""
    return MIDPOINT if composition(settings)["order"] == 2 else RK4


def nodes(settings: dict) -> tuple:
    """The times t + c h of the force evaluations: kick j at c_j = a₁ + … + a_j, repeated for each
    stage of the kick table (all of a kick's stages at its time, as the numpy kick)."""
    table = composition(settings)
    stages = kick_table(settings).stages
    c, out = 0.0, []
    for j in range(len(table["kicks"])):
        if j > 0:
            c += table["flows"][j - 1]
        out += [c] * stages
    return tuple(out)


def table_and_nodes(settings: dict) -> tuple:
    """(kick_table(settings), nodes(settings)): what of the EngineMethod follows the composition."""
    return kick_table(settings), nodes(settings)


def options(scene, settings: dict) -> np.ndarray:
    """opts = [s, b₀ … b_s, a₁ … a_s]: the number of flows s, the kick fractions, the flow fractions."""
    table = composition(settings)
    kicks, flows = table["kicks"], table["flows"]
    return np.array([float(len(flows)), *kicks, *flows], dtype=float)


@inline
def body_kind(moments):
    """SPHERICAL, SYMMETRIC or ASYMMETRIC for ascending principal moments (exact/flow.py's test: two
    moments closer than SYMMETRY_TOL, relative to the largest, are equal)."""
    I1, I2, I3 = moments[0], moments[1], moments[2]
    sym12 = I2 - I1 <= SYMMETRY_TOL * I3
    sym23 = I3 - I2 <= SYMMETRY_TOL * I3
    if sym12 and sym23:
        return SPHERICAL
    if sym12 or sym23:
        return SYMMETRIC
    return ASYMMETRIC


def exact_flow_supported(scene) -> str:
    """'' if every body of the scene has a closed-form free flow (spherical or symmetric inertia about
    its rotation centre), else why exact_splitting stays on the numpy engine (one line)."""
    moments = prepare(scene).I_rot_moments
    bad = [i for i, m in enumerate(moments) if body_kind(m) == ASYMMETRIC]
    if bad:
        return (f"exact_splitting on an asymmetric body (body {bad[0]}: principal moments "
                f"{np.round(moments[bad[0]], 12).tolist()}) needs Jacobi's elliptic functions (scipy.special), which the compiled engine does not have")
    return ""


# --- the exact free flow (compiled) ----------------------------------------------------------------------

@inline
def free_rotation(moments, axes, R, L, h):
    """R(h) of the torque-free motion with the world L constant, for a spherical or symmetric body
    (module docstring), moments the ascending principal moments (I₁, I₂, I₃), axes the principal axes
    as columns (det +1); an asymmetric body is returned unchanged (never called with one:
    exact_flow_supported)."""
    I1, I2, I3 = moments[0], moments[1], moments[2]
    kind = body_kind(moments)
    sym12 = I2 - I1 <= SYMMETRY_TOL * I3                 # the pair of equal moments, for a symmetric body
    m = matvec(transpose(R), L)                          # body axes
    if kind == SPHERICAL:
        D = exp_so3(scale(h / ((I1 + I2 + I3) / 3.0), m))
    elif kind == SYMMETRIC:
        s = 2 if sym12 else 0
        I_eq = 0.5 * (I1 + I2) if sym12 else 0.5 * (I2 + I3)
        a = (axes[0, s], axes[1, s], axes[2, s])
        c = h * (1.0 / moments[s] - 1.0 / I_eq) * dot(a, m)
        D = matmul(exp_so3(scale(h / I_eq, m)), exp_so3(scale(c, a)))
    else:
        return R
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
    K: len(b) + 1 slots (the kick's stages, then the state between kicks); U: the kick's."""
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
        vj = values[j * st:(j + 1) * st]
        bh = opts[1 + j] * h
        if vd:
            kick(sys, vj, A, b, den, src, out, bh, K, U, w)
        else:
            kick(sys, vj, A, EULER_B, 1.0, src, out, bh, K, U, w)


@njit
def exact_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """exact_splitting (this file): the family step, in steps.py's one signature (kind, layout, finish unused)."""
    exact_splitting_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)
