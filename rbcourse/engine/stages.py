"""The one explicit Runge–Kutta stage loop, over the state layouts of the engine.

    K_i = f(Y + h Σ_{j<i} a_ij K_j),   out = Y + h/den Σ b_i K_i

f is dX/dt of the state: the slides' state S = [x, R, P, L] (MATRIX), the body-frame quaternion state
Y = [x, q, P, L_b] (QUAT), Baraff's quaternion state Y = [x, q, P, L], L world (QUAT_WORLD), or the
momenta's rates at fixed positions (KICK, the splittings' kicks).
"""
from __future__ import annotations

from .jit import hot, njit
from .motion import dxdt, rates_kick
from .plan import KICK, MATRIX, QUAT, QUAT_WORLD
from .quaternion import rates_quat, rates_quat_world


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


