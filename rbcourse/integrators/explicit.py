"""Explicit methods: the slides' Euler and its fixes, classic RK4, RK–Munthe-Kaas 4.

Every step is step(scene, t, Y, h, prep) (integrators/base.py); RK4 and RK–MK4 run the one
stage loop of tableaus.py over the same table, RK4.
"""
from __future__ import annotations

import numpy as np

from ..dynamics import motion, rates
from ..rotation import cross, exp_so3, orthonormalize, retract
from ..state import State
from . import quaternion as quat
from .tableaus import RK4, rk_stages


def euler_step(scene, t: float, X: State, h: float, prep=None) -> State:
    """X(t + Δt) = X(t) + Δt · dX/dt(t),  dX/dt = (v, ω* R, F, τ)   (slide "Evolution temporelle (Euler)").

    Exactly the slides' recipe, with no correction: R + Δt ω* R is not a rotation,
    so R drifts off SO(3) (‖RᵀR − I‖ grows) and the energy grows.
    """
    d = rates(scene, t, X)
    return State.unchecked(X.x + h * d.v, X.R + h * d.R_dot, X.P + h * d.F, X.L + h * d.tau)


def euler_project_step(scene, t: float, X: State, h: float, prep=None) -> State:
    """The slides' Euler step, then R projected back onto SO(3) (rotation.orthonormalize, its polar
    factor): R stays a rotation, but the energy still drifts (first order)."""
    Y = euler_step(scene, t, X, h)
    return State.unchecked(Y.x, orthonormalize(Y.R), Y.P, Y.L)


def quaternion_euler_step(scene, t: float, Y: np.ndarray, h: float, prep=None) -> np.ndarray:
    """Euler on (x, q, P, L) with q̇ = ½ q ⊗ (0, ω_body), then q normalised (Baraff 2001, notes G §4)."""
    return quat.normalized(Y + h * quat.rates(scene, t, Y, prep))


def rk4_step(scene, t: float, Y: np.ndarray, h: float, prep=None) -> np.ndarray:
    """Classic Runge–Kutta 4 (tableaus.RK4) on Y = (x, q, P, L_b); q normalised at the end, so R(q) ∈ SO(3).

        k1 = f(t, y),  k2 = f(t + h/2, y + h/2 k1),  k3 = f(t + h/2, y + h/2 k2),  k4 = f(t + h, y + h k3)
        y(t + h) = y + h/6 (k1 + 2 k2 + 2 k3 + k4)
    """
    dY, _ = rk_stages(RK4, lambda c, U: quat.rates(scene, t + c * h, Y + U, prep), h, Y.shape)
    return quat.normalized(Y + dY)


def dexp_inv(u: np.ndarray, k: np.ndarray) -> np.ndarray:
    """dexp⁻¹_u(k) ≈ k − ½ u × k + 1/12 u × (u × k): the algebra's rate from the body's ω (to order 4)."""
    uk = cross(u, k)
    return k - 0.5 * uk + cross(u, uk) / 12.0


def rkmk4_step(scene, t: float, X: State, h: float, prep=None) -> State:
    """Runge–Kutta–Munthe-Kaas 4 on SO(3): R(t+h) = exp(u) R(t), with u built in the Lie algebra.

    The RK4 table's stages (tableaus.rk_stages), on the increments U_i = (u_i, Δx_i, ΔP_i, ΔL_i):
    R_i = exp(u_i) R,  k_i = (dexp⁻¹_{u_i}(ω(R_i, …)), v, F, τ);  then u = h Σ b_i k̃_i, and
    x, P, L take the ordinary RK4 increments.  (Munthe-Kaas 1998.)
    """
    def rate(c, U):
        u, dx, dP, dL = U
        v, omega, F, tau = motion(scene, t + c * h, State.unchecked(X.x + dx, exp_so3(u) @ X.R, X.P + dP, X.L + dL))
        return np.stack([dexp_inv(u, omega), v, F, tau])

    (u, dx, dP, dL), _ = rk_stages(RK4, rate, h, (4,) + X.L.shape)
    return State.unchecked(X.x + dx, retract(exp_so3(u) @ X.R), X.P + dP, X.L + dL)
