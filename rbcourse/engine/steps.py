"""The methods' steps on the engine's arrays, each a few lines over the same per-body physics.

Every step has one signature, step(sys, values, Y, out, h, K, U, w): it advances the state Y (N, m) of
the N bodies by h into out; values (stages, slots, 3): the forces given as functions f(t) at the
method's stage times t + c_i h (evaluated by the driver); K (stages, N, m), U (N, m), w: work arrays.

The Runge–Kutta methods are their tables (integrators/tableaus.py) run by one stage loop, rk_stages:

    K_i = f(Y + h Σ_{j<i} a_ij K_j),   out = Y + h/den Σ b_i K_i
"""
from __future__ import annotations

import numpy as np

from ..integrators.tableaus import EULER, RK4
from .algebra import axpy, cross, dot, mat_axpy, matmul, scale, transpose
from .jit import njit
from .motion import put_state, rates_matrix, state_of
from .quaternion import normalize_quats, rates_quat



def constants(table):
    """A table as the compiled functions read it: tuples of floats (constants of the machine code)."""
    return tuple(tuple(float(a) for a in row) for row in table.A), tuple(float(b) for b in table.b), table.den


EULER_A, EULER_B, EULER_DEN = constants(EULER)
RK4_A, RK4_B, RK4_DEN = constants(RK4)


MATRIX, QUAT = 0, 1      # the state a method steps: S = [x, R, P, L] (N, 18), or Y = [x, q, P, L_b] (N, 13)


@njit
def rate(layout, sys, values, Y, dY, w):
    """dX/dt of the slides' state (layout MATRIX) or of the quaternion state (QUAT), into dY."""
    if layout == MATRIX:
        rates_matrix(sys, values, Y, dY, w)
    else:
        rates_quat(sys, values, Y, dY, w)


@njit
def rk_stages(layout, sys, values, A, b, den, Y, out, h, K, U, w):
    """The stage loop of an explicit Runge–Kutta table: K_i = f(Y + h Σ a_ij K_j), out = Y + h/den Σ b_i K_i."""
    n, m = Y.shape
    for i in range(len(b)):
        for p in range(n):
            for q in range(m):
                acc = 0.0
                for j in range(i):
                    acc += A[i][j] * K[j, p, q]
                U[p, q] = Y[p, q] + h * acc
        rate(layout, sys, values[i], U, K[i], w)
    for p in range(n):
        for q in range(m):
            acc = 0.0
            for i in range(len(b)):
                acc += b[i] * K[i, p, q]
            out[p, q] = Y[p, q] + (h / den) * acc


@njit
def euler_step(sys, values, Y, out, h, K, U, w):
    """X(t + Δt) = X(t) + Δt · dX/dt(t),  dX/dt = (v, ω* R, F, τ)   (slide "Evolution temporelle (Euler)").
    Exactly the slides' recipe, uncorrected: R + Δt ω* R leaves SO(3)."""
    rk_stages(MATRIX, sys, values, EULER_A, EULER_B, EULER_DEN, Y, out, h, K, U, w)


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


@njit
def euler_project_step(sys, values, Y, out, h, K, U, w):
    """The slides' Euler step, then R projected back onto SO(3) (its polar factor): a rotation again,
    but the energy still drifts (first order)."""
    euler_step(sys, values, Y, out, h, K, U, w)
    orthonormalize_rows(out)


@njit
def quaternion_euler_step(sys, values, Y, out, h, K, U, w):
    """Euler on (x, q, P, L_b) with q̇ = ½ q ⊗ (0, ω_body), then q normalised (Baraff 2001, notes G §4)."""
    rk_stages(QUAT, sys, values, EULER_A, EULER_B, EULER_DEN, Y, out, h, K, U, w)
    normalize_quats(out)


@njit
def rk4_step(sys, values, Y, out, h, K, U, w):
    """Classic Runge–Kutta 4 on Y = (x, q, P, L_b); q normalised at the end, so R(q) ∈ SO(3).

        k1 = f(y),  k2 = f(y + h/2 k1),  k3 = f(y + h/2 k2),  k4 = f(y + h k3)
        y(t + h) = y + h/6 (k1 + 2 k2 + 2 k3 + k4)
    """
    rk_stages(QUAT, sys, values, RK4_A, RK4_B, RK4_DEN, Y, out, h, K, U, w)
    normalize_quats(out)


# the compiled engine's methods, by number (run.run_steps compiles the one a run uses)
EULER_CODE, EULER_PROJECT_CODE, QUATERNION_EULER_CODE, RK4_CODE = 0, 1, 2, 3


@njit
def step(method, sys, values, Y, out, h, K, U, w):
    """The step of method number `method` (a compile-time constant: only its branch is compiled)."""
    if method == EULER_CODE:
        euler_step(sys, values, Y, out, h, K, U, w)
    elif method == EULER_PROJECT_CODE:
        euler_project_step(sys, values, Y, out, h, K, U, w)
    elif method == QUATERNION_EULER_CODE:
        quaternion_euler_step(sys, values, Y, out, h, K, U, w)
    elif method == RK4_CODE:
        rk4_step(sys, values, Y, out, h, K, U, w)
