"""Integrators: one small pure step function per method, and the METHODS registry.

Every step has the same form,  step(scene, t, X, dt) -> X(t + dt),  on a state of
N bodies (arrays with a leading body axis), and works with any effects a scene has.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .dynamics import forces, rates, velocities
from .rotation import matrix_from_quat, quat_from_matrix, quat_multiply, quat_normalize
from .state import State


@dataclass(frozen=True)
class Method:
    """An integrator: its step function and what it promises."""
    name: str
    step: Callable = field(repr=False)
    order: int
    keeps: frozenset          # invariants kept exactly (free body): "SO(3)", "|L|", "L", "energy"
    cost: str                 # per step: force evaluations, solves
    reference: str
    summary: str

    def __call__(self, scene, t, X, dt):
        return self.step(scene, t, X, dt)


# --- the slides' explicit Euler ----------------------------------------------------

def euler_step(scene, t: float, X: State, dt: float) -> State:
    """X(t + Δt) = X(t) + Δt · dX/dt(t),  dX/dt = (v, ω* R, F, τ)   (slide "Evolution temporelle (Euler)").

    Exactly the slides' recipe, with no correction: R + Δt ω* R is not a rotation,
    so R drifts off SO(3) (‖RᵀR − I‖ grows) and the energy grows.
    """
    d = rates(scene, t, X)
    return State._raw(X.x + dt * d.v, X.R + dt * d.R_dot, X.P + dt * d.F, X.L + dt * d.tau)


# --- classic RK4 on (x, q, P, L) ----------------------------------------------------

def _quat_rates(scene, t, x, q, P, L):
    """d/dt (x, q, P, L) = (v, ½ (0, ω) q, F, τ), with R = R(q)."""
    X = scene.constrain(State._raw(x, matrix_from_quat(q), P, L))
    v, omega = velocities(scene, X)
    F, tau = forces(scene, t, X, v, omega)
    omega_q = np.concatenate([np.zeros(omega.shape[:-1] + (1,)), omega], axis=-1)
    return v, 0.5 * quat_multiply(omega_q, q), F, tau


def rk4_step(scene, t: float, X: State, dt: float) -> State:
    """Classic Runge–Kutta 4 on (x, q, P, L); the quaternion is normalised at the end,
    so R = R(q) stays on SO(3) to rounding.

        k1 = f(t, y),  k2 = f(t + h/2, y + h/2 k1),  k3 = f(t + h/2, y + h/2 k2),  k4 = f(t + h, y + h k3)
        y(t + h) = y + h/6 (k1 + 2 k2 + 2 k3 + k4)
    """
    y = (X.x, quat_from_matrix(X.R), X.P, X.L)
    k1 = _quat_rates(scene, t, *y)
    k2 = _quat_rates(scene, t + dt / 2, *(a + dt / 2 * b for a, b in zip(y, k1)))
    k3 = _quat_rates(scene, t + dt / 2, *(a + dt / 2 * b for a, b in zip(y, k2)))
    k4 = _quat_rates(scene, t + dt, *(a + dt * b for a, b in zip(y, k3)))
    x, q, P, L = (a + dt / 6 * (b1 + 2 * b2 + 2 * b3 + b4) for a, b1, b2, b3, b4 in zip(y, k1, k2, k3, k4))
    return State._raw(x, matrix_from_quat(quat_normalize(q)), P, L)


METHODS: dict[str, Method] = {}


def register(method: Method) -> Method:
    """Add a method to METHODS (name -> Method)."""
    METHODS[method.name] = method
    return method


register(Method(
    "euler", euler_step, order=1, keeps=frozenset({"L"}),
    cost="1 force evaluation",
    reference="the course slides; Baraff 2001, notes D §2 (explicit Euler on X = (x, R, P, L))",
    summary="the slides' explicit Euler, uncorrected: R leaves SO(3), energy grows"))

register(Method(
    "rk4", rk4_step, order=4, keeps=frozenset({"SO(3)"}),
    cost="4 force evaluations",
    reference="Kutta 1901; Baraff 2001 (quaternion form, notes G §4)",
    summary="classic Runge–Kutta 4 on (x, q, P, L) with a normalised quaternion"))


def get_method(method) -> Method:
    """A Method from its name (or a Method itself)."""
    if isinstance(method, Method):
        return method
    if method not in METHODS:
        raise ValueError(f"method must be one of {sorted(METHODS)}, got {method!r}")
    return METHODS[method]
