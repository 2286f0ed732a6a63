"""The one explicit Runge–Kutta stage loop, over the state layouts of the engine.

    K_i = f(Y + h Σ_{j<i} a_ij K_j),   out = Y + h/den Σ b_i K_i

f is dX/dt of the state: the slides' state S = [x, R, P, L] (MATRIX), the body-frame quaternion state
Y = [x, q, P, L_b] (QUAT), Baraff's quaternion state Y = [x, q, P, L], L world (QUAT_WORLD), or the
momenta's rates at fixed positions (KICK, the splittings' kicks).
"""
from __future__ import annotations

from .jit import hot, njit
from .motion import alike, dxdt, forced, rates_kick
from .plan import KICK, MATRIX, QUAT, QUAT_WORLD
from .quaternion import WIDTH, quat_body_rate, quat_rate, quat_state_of, rates_quat, rates_quat_world


@hot
def rate(layout, sys, values, Y, dY, w):
    """dX/dt of the slides' state (layout MATRIX), of the body-frame quaternion state (QUAT), of Baraff's
    quaternion state (QUAT_WORLD), or the momenta's rates at fixed positions (KICK), into dY."""
    if layout == MATRIX:
        dxdt(sys, values, Y, dY, w)
    elif layout == QUAT:
        rates_quat(sys, values, Y, dY, w)
    elif layout == QUAT_WORLD:
        rates_quat_world(sys, values, Y, dY, w)
    else:
        rates_kick(sys, values, Y, dY, w)


@njit
def rk_stages(layout, sys, values, A, b, den, Y, out, h, K, U, w, first=0):
    """The stage loop of an explicit Runge–Kutta table: K_i = f(Y + h Σ a_ij K_j), out = Y + h/den Σ b_i K_i.
    first = 1: K[0] is given (f at the start known already: "first same as last", as DOP853 reuses f at
    the end of its last substep)."""
    if layout == QUAT and first == 0 and alike(sys):
        rk_stages_by_body(sys, values, A, b, den, Y, out, h, K, U, w)
        return
    n, m = Y.shape
    for i in range(first, len(b)):
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
def rk_stages_by_body(sys, values, A, b, den, Y, out, h, K, U, w):
    """The same stage loop on the body-frame quaternion state, body after body: each body's stages in a few
    rows that stay in cache (K[:, 0] its stages, U[0] its stage state), instead of each stage
    streaming the N bodies' arrays through memory — for a scene whose bodies do not act on one another
    (motion.alike): Y read once, out written once per step.  The same sums in the same order as rk_stages
    (its terms a_ij = 0 left out: adding 0 · K_j changes no finite sum), so the same numbers."""
    torqued = forced(sys)
    slots = values.shape[1]
    flat = values.reshape((-1, 3))              # the stages' forces over time as rows: no view per body
    for p in range(Y.shape[0]):
        for i in range(len(b)):
            for q in range(WIDTH):                                 # U[0] = Y_p + h Σ_j a_ij K_j
                U[0, q] = 0.0
            for j in range(i):
                a = A[i, j]
                if a != 0.0:
                    for q in range(WIDTH):
                        U[0, q] += a * K[j, 0, q]
            for q in range(WIDTH):
                U[0, q] = Y[p, q] + h * U[0, q]
            x, qq, P, Lb = quat_state_of(U, 0)
            if torqued:
                v, dq, F, dLb = quat_body_rate(sys, flat, i * slots, p, x, qq, P, Lb)
            else:                                              # a free body: no force, no view of values
                v, dq, F, dLb = quat_rate(sys, p, qq, P, Lb, w, False)
            put_stage(K, i, v, dq, F, dLb)
        for q in range(WIDTH):                                     # out_p = Y_p + h/den Σ_i b_i K_i
            U[0, q] = 0.0                                          # (U[0] is free again: the sum, in cache)
        for i in range(len(b)):
            c = b[i]
            for q in range(WIDTH):
                U[0, q] += c * K[i, 0, q]
        for q in range(WIDTH):
            out[p, q] = Y[p, q] + (h / den) * U[0, q]


@hot
def put_stage(K, i, v, dq, F, dLb):
    """K[i, 0] := [v, q̇, F, L̇_b] (the body's stage i, in its scratch row; no view of K is made)."""
    K[i, 0, 0], K[i, 0, 1], K[i, 0, 2] = v[0], v[1], v[2]
    K[i, 0, 3], K[i, 0, 4], K[i, 0, 5], K[i, 0, 6] = dq[0], dq[1], dq[2], dq[3]
    K[i, 0, 7], K[i, 0, 8], K[i, 0, 9] = F[0], F[1], F[2]
    K[i, 0, 10], K[i, 0, 11], K[i, 0, 12] = dLb[0], dLb[1], dLb[2]
