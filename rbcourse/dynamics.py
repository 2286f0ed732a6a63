"""The equations of motion, dX/dt (slide "Les Formules"):

    d/dt (x, R, P, L) = (v, ω* R, F, τ)

with v = P/M, I⁻¹(t) = R I⁻¹_body Rᵀ, ω = I⁻¹(t) L, and F, τ the resultants of
the scene's effects (only those: a free body evaluates no force at all).  The formulas are the
engine's (rbcourse/engine/motion.py), written once; dxdt evaluates them for a State.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .support import checks
from .scene import Scene, as_scene
from .driver import derivative, kernel
from .state import State


class StateDerivative(NamedTuple):
    """dX/dt = (dx/dt, dR/dt, dP/dt, dL/dt) = (v, ω* R, F, τ)."""
    v: np.ndarray
    R_dot: np.ndarray
    F: np.ndarray
    tau: np.ndarray


def dxdt(scene, t: float, X: State) -> StateDerivative:
    """dX/dt = (v, ω* R, F, τ) for a scene (or a bare RigidBody) at time t.

    Shapes follow X: one body (3,), (3, 3), ... or N bodies (N, 3), (N, 3, 3), ...
    For a pivoted body, L and τ are taken about the pivot (the engine's coordinates).
    Computed by the engine's own functions (engine/motion.py: dxdt), run as Python.
    """
    scene = as_scene(scene)
    t = checks.real("t", t)
    if not isinstance(X, State):
        raise ValueError(f"X must be a State, got {X!r}")
    single = X.x.ndim == 1
    d = derivative(kernel(fast=False), scene, t, scene.to_engine(X))
    return StateDerivative(*(a[0] for a in d)) if single else StateDerivative(*d)
