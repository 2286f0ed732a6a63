"""The methods' steps on the engine's arrays, each a few lines over the same per-body physics.

A method is data (driver.ENGINE_METHODS): the state it steps (layout), its Butcher table (A, b, den),
and how it finishes a step.  The explicit Runge–Kutta methods are one stage loop, rk_stages:

    K_i = f(Y + h Σ_{j<i} a_ij K_j),   out = Y + h/den Σ b_i K_i

    euler             the EULER table on the slides' state (x, R, P, L)       (slide "Evolution temporelle")
    euler_project     the same, then R projected back onto SO(3)
    quaternion_euler  the EULER table on (x, q, P, L_b), then q normalised     (Baraff 2001, notes G §4)
    rk4               the RK4 table on (x, q, P, L_b), then q normalised       (Kutta 1901)

Arguments: Y (N, m) the state of the N bodies, out (N, m) the result; values (stages, slots, 3) the forces
given as functions f(t) at the stage times t + c_i h (evaluated by the driver); K (stages, N, m), U (N, m),
w: work arrays.
"""
from __future__ import annotations

import numpy as np

from .algebra import axpy, cross, dot, mat_axpy, matmul, scale, transpose
from .jit import hot, njit
from .motion import put_state, rates_kick, rates_matrix, state_of
from .quaternion import normalize_quats, rates_quat



# the state a method steps: S = [x, R, P, L] (N, 18), or Y = [x, q, P, L_b] (N, 13); KICK: S, with the
# momenta's rates only, (0, 0, F, τ) at fixed positions (the kicks of the splitting methods)
MATRIX, QUAT, KICK = 0, 1, 2


@hot
def rate(layout, sys, values, Y, dY, w):
    """dX/dt of the slides' state (layout MATRIX), of the quaternion state (QUAT), or the momenta's
    rates at fixed positions (KICK), into dY."""
    if layout == MATRIX:
        rates_matrix(sys, values, Y, dY, w)
    elif layout == QUAT:
        rates_quat(sys, values, Y, dY, w)
    else:
        rates_kick(sys, values, Y, dY, w)


@njit
def rk_stages(layout, sys, values, A, b, den, Y, out, h, K, U, w):
    """The stage loop of an explicit Runge–Kutta table: K_i = f(Y + h Σ a_ij K_j), out = Y + h/den Σ b_i K_i."""
    n, m = Y.shape
    for i in range(len(b)):
        for p in range(n):
            for q in range(m):
                acc = 0.0
                for j in range(i):
                    acc += A[i, j] * K[j, p, q]
                U[p, q] = Y[p, q] + h * acc
        rate(layout, sys, values[i], U, K[i], w)
    for p in range(n):
        for q in range(m):
            acc = 0.0
            for i in range(len(b)):
                acc += b[i] * K[i, p, q]
            out[p, q] = Y[p, q] + (h / den) * acc


@njit
def orthonormalize_rows(S, tol=1e-15, max_iter=20):
    """Each body's R (in S) replaced by its polar factor, by Björck's iteration R ← R − ½ R (RᵀR − I);
    the SVD's U Vᵀ (det +1) if R is far from SO(3) (‖RᵀR − I‖ > 0.5); a blown-up R is left as it is."""
    for i in range(S.shape[0]):
        x, R, P, L = state_of(S, i)
        for _ in range(max_iter):
            E = matmul(transpose(R), R)
            E = ((E[0][0] - 1.0, E[0][1], E[0][2]), (E[1][0], E[1][1] - 1.0, E[1][2]), (E[2][0], E[2][1], E[2][2] - 1.0))
            err = 0.0
            for r in range(3):
                for c in range(3):
                    err = max(err, abs(E[r][c]))
            if err < tol or not np.isfinite(err):
                break
            if err > 0.5:
                R = project_so3(R)
                break
            R = mat_axpy(R, -0.5, matmul(R, E))
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
# the kinds of step (run.run_steps calls step(kind, …))
EXPLICIT_RK = 0


@hot
def explicit_rk_step(layout, finish, sys, values, A, b, den, Y, out, h, K, U, w):
    """One step of an explicit Runge–Kutta table on the state `layout`, then its finish: none (the
    slides' Euler: R + Δt ω* R leaves SO(3)), R projected onto SO(3), or q normalised (R(q) ∈ SO(3))."""
    rk_stages(layout, sys, values, A, b, den, Y, out, h, K, U, w)
    if finish == PROJECT_R:
        orthonormalize_rows(out)
    elif finish == NORMALIZE_Q:
        normalize_quats(out)


@njit
def step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """The step of a method of this kind (EXPLICIT_RK: its table, layout and finish); opts (k,): the
    method's numerical options (e.g. adaptive's rtol, atol), empty for most."""
    if kind == EXPLICIT_RK:
        explicit_rk_step(layout, finish, sys, values, A, b, den, Y, out, h, K, U, w)
