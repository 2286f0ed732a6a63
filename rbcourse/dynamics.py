"""The equations of motion, dX/dt (slide "Les Formules"):

    d/dt (x, R, P, L) = (v, ω* R, F, τ)

with v = P/M, I⁻¹(t) = R I⁻¹_body Rᵀ, ω = I⁻¹(t) L, and F, τ the resultants of
the scene's effects (only those: a free body evaluates no force at all).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import checks
from .rotation import star
from .scene import Scene, as_scene
from .state import State, angular_velocity, inverse_inertia, velocity


class StateDerivative(NamedTuple):
    """dX/dt = (dx/dt, dR/dt, dP/dt, dL/dt) = (v, ω* R, F, τ)."""
    v: np.ndarray
    R_dot: np.ndarray
    F: np.ndarray
    tau: np.ndarray


def velocities(scene: Scene, X: State):
    """v = P/M and ω = I⁻¹(t) L with I⁻¹(t) = R I⁻¹_body Rᵀ, for the N bodies (arrays).

    (For a pivoted body, L and I_body are about the pivot: scene.I_rot_inv.)
    """
    v = velocity(X.P, scene.mass)
    I_inv = inverse_inertia(X.R, scene.I_rot_inv)
    omega = angular_velocity(I_inv, X.L)
    return v, omega


def forces(scene: Scene, t: float, X: State, v, omega):
    """F and τ of the scene's effects (zeros, computed from nothing, for a free body)."""
    F, tau = scene.resultants(t, X.x, X.R, v, omega)
    if F is None:
        return np.zeros_like(X.P), np.zeros_like(X.L)
    return F, tau


def motion(scene: Scene, t: float, X: State):
    """(v, ω, F, τ) for N bodies, in the engine's coordinates: velocities, then the scene's forces."""
    X = scene.constrain(X)              # pivoted bodies: x and P follow R and L (no-op otherwise)
    v, omega = velocities(scene, X)
    F, tau = forces(scene, t, X, v, omega)
    return v, omega, F, tau


def rates(scene: Scene, t: float, X: State) -> StateDerivative:
    """dX/dt = (v, ω* R, F, τ) for N bodies (arrays with a leading body axis)."""
    v, omega, F, tau = motion(scene, t, X)
    return StateDerivative(v, star(omega) @ X.R, F, tau)


def dxdt(scene, t: float, X: State) -> StateDerivative:
    """dX/dt = (v, ω* R, F, τ) for a scene (or a bare RigidBody) at time t.

    Shapes follow X: one body (3,), (3, 3), ... or N bodies (N, 3), (N, 3, 3), ...
    For a pivoted body, L and τ are taken about the pivot (the engine's coordinates).
    """
    scene = as_scene(scene)
    t = checks.real("t", t)
    if not isinstance(X, State):
        raise ValueError(f"X must be a State, got {X!r}")
    single = X.x.ndim == 1
    d = rates(scene, t, scene.to_engine(X))
    return StateDerivative(*(a[0] for a in d)) if single else d
