"""The methods' steps on the engine's arrays, each a few lines over the same per-body physics.

A method is data (driver.ENGINE_METHODS): the state it steps (layout), its Butcher table (A, b, den),
and how it finishes a step.  The explicit Runge–Kutta methods are one stage loop, rk_stages:

    K_i = f(Y + h Σ_{j<i} a_ij K_j),   out = Y + h/den Σ b_i K_i

    euler                  the EULER table on the slides' state (x, R, P, L)  (slide "Evolution temporelle")
    euler_project          the same, then R projected back onto SO(3)
    quaternion_euler       the EULER table on Baraff's (x, q, P, L), L world, then q normalised
                           (Baraff 2001, notes G "Quaternions", eq. 4-2: q̇ = ½ (0, ω) q, L̇ = τ)
    quaternion_euler_body  the EULER table on (x, q, P, L_b), L_b = Rᵀ L, then q normalised
    rk4                    the RK4 table on (x, q, P, L_b), then q normalised  (Kutta 1901)

Arguments: Y (N, m) the state of the N bodies, out (N, m) the result; values (stages, slots, 3) the forces
given as functions f(t) at the stage times t + c_i h (evaluated by the driver); K (stages, N, m), U (N, m),
w: work arrays.
"""
from __future__ import annotations

import numpy as np

from .algebra import axpy, bjorck_step, cross, dot, gram_defect, scale
from .jit import hot, njit
from .motion import put_state, state_of
from .quaternion import normalize_quats
from .stages import KICK, MATRIX, QUAT, QUAT_WORLD, rk_stages   # noqa: F401  (the layouts, and the one stage loop)
from .adaptive import adaptive_step
from .implicit import implicit_gyro_step, implicit_midpoint_step
from . import geometric, variational
from .exact_flow import exact_step   # noqa: F401  (exact_splitting: kick / exact free flow / kick)



@njit
def orthonormalize_rows(S, tol=1e-15, max_iter=20):
    """Each body's R (in S) replaced by its polar factor, by Björck's iteration R ← R − ½ R (RᵀR − I);
    by Newton's iteration (project_so3) if R is far from SO(3) (max |RᵀR − I| > 0.5); a blown-up R is left as it is."""
    for i in range(S.shape[0]):
        x, R, P, L = state_of(S, i)
        for _ in range(max_iter):
            E = gram_defect(R)
            err = 0.0
            for r in range(3):
                for c in range(3):
                    err = max(err, abs(E[r][c]))
            if err < tol or not np.isfinite(err):
                break
            if err > 0.5:
                R = project_so3(R)
                break
            R = bjorck_step(R, E)
        put_state(S, i, x, R, P, L)


@njit
def project_so3(R, max_iter=60):
    """The rotation nearest to R (its polar factor), by Newton's iteration R ← ½ (R + R⁻ᵀ), with
    R⁻ᵀ = cof(R) / det R; it converges (quadratically) for every R with det R > 0 — as every R of the
    Euler step has: det(R + Δt ω* R) = (1 + Δt² |ω|²) det R."""
    for _ in range(max_iter):
        c0, c1, c2 = cross(R[1], R[2]), cross(R[2], R[0]), cross(R[0], R[1])   # the cofactor rows
        det = dot(R[0], c0)
        if not det > 0.0:
            return R
        s = 0.5 / det
        Q = (axpy(scale(0.5, R[0]), s, c0), axpy(scale(0.5, R[1]), s, c1), axpy(scale(0.5, R[2]), s, c2))
        change = 0.0
        for r in range(3):
            for c in range(3):
                change = max(change, abs(Q[r][c] - R[r][c]))
        R = Q
        if change < 1e-15:
            break
    return R


# how a method finishes its step
NO_FINISH, PROJECT_R, NORMALIZE_Q = 0, 1, 2
# the kinds of step
EXPLICIT_RK, ADAPTIVE, IMPLICIT_GYRO, IMPLICIT_MIDPOINT, SYMPLECTIC_EULER, SPLITTING, RKMK4, EXACT_SPLITTING, VARIATIONAL = range(9)


@hot
def explicit_rk_step(layout, finish, sys, values, A, b, den, Y, out, h, K, U, w):
    """One step of an explicit Runge–Kutta table on the state `layout`, then its finish: none (the
    slides' Euler: R + Δt ω* R leaves SO(3)), R projected onto SO(3), or q normalised (R(q) ∈ SO(3))."""
    rk_stages(layout, sys, values, A, b, den, Y, out, h, K, U, w)
    if finish == PROJECT_R:
        orthonormalize_rows(out)
    elif finish == NORMALIZE_Q:
        normalize_quats(out)


# Each family of methods has its own step (one signature): a run compiles only its family's code.
# step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w)

@njit
def explicit_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """euler, euler_project, quaternion_euler, quaternion_euler_body, rk4: an explicit Runge–Kutta table on its layout, then its finish."""
    explicit_rk_step(layout, finish, sys, values, A, b, den, Y, out, h, K, U, w)


@njit
def geometric_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """symplectic_euler, splitting, rkmk4 (engine/geometric.py), variational (engine/variational.py)."""
    if kind == SYMPLECTIC_EULER:
        geometric.symplectic_euler_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)
    elif kind == SPLITTING:
        geometric.splitting_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)
    elif kind == VARIATIONAL:
        variational.variational_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)
    else:
        geometric.rkmk4_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)


@njit
def implicit_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """implicit_gyro, implicit_midpoint (engine/implicit.py)."""
    if kind == IMPLICIT_GYRO:
        implicit_gyro_step(sys, values, opts, Y, out, h, K, U, w)
    else:
        implicit_midpoint_step(sys, values, opts, Y, out, h, K, U, w)


@njit
def error_controlled_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """adaptive: DOP853 substeps under error control over the output step h (engine/adaptive.py)."""
    adaptive_step(A, b, den, opts, sys, values, Y, out, h, K, U, w)
