"""The reference the checks compare with: the engine's formulas, on X = (x, R, P, L) as a tuple.

    box_inertia:          I_body = M/12 · diag(b² + c², a² + c², a² + b²)
    resultants:           F = Σ Fᵢ,  τ = Σ (rᵢ − x) ∧ Fᵢ
    dxdt:                 dX/dt = (v, ω* R, F, τ),  v = P/M,  I⁻¹(t) = R I⁻¹_body Rᵀ,  ω = I⁻¹(t) L
    euler_step:           X(t+Δt) = X(t) + Δt · dX/dt(t)
    euler_step_projected: the Euler step, then R ← its nearest rotation
    simulate:             X₀, X₁ = step(X₀), …, as arrays
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...body import RigidBody
from ...forces import resultants as engine_resultants
from ...engine import interpreted
from ...rotation import project_so3


class StateTuple(NamedTuple):
    """X = (x, R, P, L): position of the barycentre, orientation, quantité de mouvement, moment cinétique."""
    x: np.ndarray
    R: np.ndarray
    P: np.ndarray
    L: np.ndarray



def box_inertia(mass, size):
    """I_body = M/12 · diag(b² + c², a² + c², a² + b²)  (rbcourse.RigidBody.box)."""
    return np.array(RigidBody.box(mass, size).I_body)


def resultants(x, forces):
    """F = Σ Fᵢ,  τ = Σ (rᵢ − x) ∧ Fᵢ  (rbcourse.resultants)."""
    return engine_resultants(x, forces)


def unpack(X):
    """(x, R, P, L) from a tuple, a StateTuple, an rbcourse State or anything with .x .R .P .L."""
    if all(hasattr(X, k) for k in "xRPL"):
        return X.x, X.R, X.P, X.L
    x, R, P, L = X
    return x, R, P, L


def as_floats(X):
    """(x, R, P, L) as float arrays."""
    return tuple(np.asarray(a, dtype=float) for a in unpack(X))


def dxdt(M, I_body_inv, X, forces):
    """dX/dt = (v, ω* R, F, τ) with v = P/M, I⁻¹(t) = R I⁻¹_body Rᵀ, ω = I⁻¹(t) L  (slide "Les Formules")."""
    x, R, P, L = as_floats(X)
    motion, algebra = interpreted.module("motion"), interpreted.module("algebra")   # the engine's formulas
    v = motion.velocity(P, float(M))
    omega = motion.angular_velocity(motion.inverse_inertia(R, np.asarray(I_body_inv, float)), L)
    F, tau = resultants(x, forces)
    return (np.array(v, dtype=float), np.array(algebra.matmul(algebra.star(omega), R), dtype=float), F, tau)


def euler_step(M, I_body_inv, X, forces, dt):
    """X(t+Δt) = X(t) + Δt · dX/dt(t)  (slide "Evolution temporelle (Euler)")."""
    X = as_floats(X)
    return StateTuple(*(a + dt * d for a, d in zip(X, dxdt(M, I_body_inv, X, forces))))


def euler_step_projected(M, I_body_inv, X, forces, dt):
    """The Euler step, then R ← its nearest rotation."""
    x, R, P, L = euler_step(M, I_body_inv, X, forces, dt)
    return StateTuple(x, project_so3(R), P, L)


def simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=euler_step):
    """X₀, X₁ = step(X₀), …: arrays x (n+1, 3), R (n+1, 3, 3), P (n+1, 3), L (n+1, 3)."""
    X = StateTuple(*as_floats(X0))
    states = [X]
    for k in range(n_steps):
        X = StateTuple(*as_floats(step(M, I_body_inv, X, forces_at(k * dt, X), dt)))
        states.append(X)
    return tuple(np.array([s[i] for s in states]) for i in range(4))
