"""A scene as data for the engine: the bodies' constants, and one row per effect.

The compiled functions take no Python objects: a Scene becomes a System of arrays, so that one
compiled function serves every composition of effects (compiled once per method, not per scene),
and an effect the scene does not call for has no row — it costs nothing.

    mass (N,), I (N, 3, 3) and I_inv (N, 3, 3): the inertia about the rotation centre and its inverse, body
        axes (I_body, or I_p for a pivoted body); I_moments (N, 3), I_axes (N, 3, 3): I = A diag(I₁, I₂, I₃) Aᵀ,
        the principal axes as the columns of A, det A = +1 (integrators.base.prepare); pivoted (N,) bool, pivot_b (N, 3) the pivot's body point, pivot_p (N, 3) its
        world point (zeros for free bodies);
    code (E,) one effect per row (GRAVITY, POINT_FORCE, SPRING, LINEAR_DRAG, ANGULAR_DRAG);
    body (E,) the body it acts on (EVERY: all of them), other (E,) the second body of a spring (-1: none);
    params (E, 9) its parameters (see the codes); slot (E,) for a force given as a function f(t),
        its column in the values the driver evaluates in Python (-1: a constant force).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..contact import Ground
from ..effects import AngularDrag, Gravity, LinearDrag, PointForce, Spring
from ..impulse import Impulse
from ..integrators.base import prepare
from ..pivot import Pivot

EVERY = -1   # body = EVERY: the effect acts on every body of the scene

# effect codes and their params:
GRAVITY = 1        # params[0] = g                           F = −M g ẑ at x
POINT_FORCE = 2    # [0:3] b, [3:6] f, [6] 1 if body frame   F = f (or R f) at r = x + R b
SPRING = 3         # [0:3] b, [3:6] world point (or the other body's point), [6] k, [7] c, [8] ℓ₀
LINEAR_DRAG = 4    # [0] c                                   F = −c v at x
ANGULAR_DRAG = 5   # [0] c                                   τ = −c ω

N_PARAMS = 9


class System(NamedTuple):
    """The scene's constants as arrays (see the module docstring)."""
    mass: np.ndarray
    I: np.ndarray
    I_inv: np.ndarray
    I_moments: np.ndarray
    I_axes: np.ndarray
    pivoted: np.ndarray
    pivot_b: np.ndarray
    pivot_p: np.ndarray
    code: np.ndarray
    body: np.ndarray
    other: np.ndarray
    params: np.ndarray
    slot: np.ndarray


class Compiled(NamedTuple):
    """A scene's System and the functions f(t) it needs evaluated (one per slot, in slot order)."""
    system: System
    functions: tuple          # (PointForce, ...) whose force is a function of t
    has_forces: bool


def _rows(scene, effect) -> list[int]:
    """The bodies an effect acts on: [EVERY] for all of them, else their indices."""
    if effect.body is None:
        return [EVERY]
    return [int(i) for i in scene.bodies_of(effect)]


def _effect_rows(scene, effect, functions: list):
    """(code, body, other, params, slot) rows for one effect of the scene."""
    p = np.zeros(N_PARAMS)
    other, slot = -1, -1
    if isinstance(effect, Gravity):
        code, p[0] = GRAVITY, effect.g
    elif isinstance(effect, PointForce):
        code = POINT_FORCE
        p[0:3] = effect.body_point
        if callable(effect.force):
            slot = len(functions)
            functions.append(effect)
        else:
            p[3:6] = effect.force
        p[6] = 1.0 if effect.frame == "body" else 0.0
    elif isinstance(effect, Spring):
        code = SPRING
        p[0:3] = effect.body_point
        p[6], p[7], p[8] = effect.stiffness, effect.damping, effect.rest_length
        if effect.other_body is None:
            p[3:6] = effect.world_point
        else:
            p[3:6] = effect.other_point
            other = scene.other_body_of(effect)
    elif isinstance(effect, LinearDrag):
        code, p[0] = LINEAR_DRAG, effect.coefficient
    elif isinstance(effect, AngularDrag):
        code, p[0] = ANGULAR_DRAG, effect.coefficient
    else:
        raise ValueError(f"the engine has no data layout for effect {effect!r}")
    return [(code, b, other, p, slot) for b in _rows(scene, effect)]


def compile_scene(scene) -> Compiled:
    """The Scene's constants and smooth effects as a System (pivots included; impulses and contacts
    are applied between steps by the driver, and are not rows here)."""
    functions: list = []
    rows = []
    for e in scene.effects:
        if isinstance(e, (Pivot, Impulse, Ground)):
            continue
        rows += _effect_rows(scene, e, functions)
    E = len(rows)
    params = np.zeros((E, N_PARAMS))
    code, body, other, slot = (np.zeros(E, dtype=np.int64) for _ in range(4))
    for k, (c, b, o, p, s) in enumerate(rows):
        code[k], body[k], other[k], params[k], slot[k] = c, b, o, p, s
    prep = prepare(scene)
    system = System(np.ascontiguousarray(scene.mass, dtype=float), np.ascontiguousarray(scene.I_rot),
                    np.ascontiguousarray(scene.I_rot_inv), np.ascontiguousarray(prep.I_rot_moments),
                    np.ascontiguousarray(prep.I_rot_axes),
                    np.ascontiguousarray(scene.pivoted), np.ascontiguousarray(scene.pivot_body_point),
                    np.ascontiguousarray(scene.pivot_world_point), code, body, other, params, slot)
    return Compiled(system, tuple(functions), bool(rows))
