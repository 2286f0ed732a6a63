"""A scene as data for the kernel: the bodies' constants, and one row per effect.

The compiled functions take no Python objects: a Scene lays itself out as a System of arrays (scene.py:
Scene.compile, each effect emitting its own rows: effects.py), so that one compiled function serves every
composition of effects (compiled once per method, not per scene), and an effect the scene does not call for
has no row — it costs nothing.

    mass (N,), I (N, 3, 3) and I_inv (N, 3, 3): the inertia about the rotation centre and its inverse, body
        axes (I_body, or I_p for a pivoted body); I_moments (N, 3), I_axes (N, 3, 3): I = A diag(I₁, I₂, I₃) Aᵀ,
        the principal axes as the columns of A, det A = +1 (principal_axes); pivoted (N,) bool, pivot_b (N, 3)
        the pivot's body point, pivot_p (N, 3) its world point (zeros for free bodies); I_inv_rows (9, N):
        I_inv's nine entries as rows, the bodies side by side (rk4's lanes read several bodies' at once: stages.py);
    code (E,) one effect per row (GRAVITY, POINT_FORCE, SPRING, LINEAR_DRAG, ANGULAR_DRAG);
    body (E,) the body it acts on (EVERY: all of them), other (E,) the second body of a spring (-1: none);
    params (E, 9) its parameters (see the codes); slot (E,) for a force given as a function f(t),
        its column in the values the driver evaluates in Python (-1: a constant force); velocity (E,) does its
        force depend on the velocities (the splittings' kicks then take a midpoint table: geometric.py).

This module is numpy only (no numba): the layers above build Systems without loading the compiler.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

EVERY = -1   # body = EVERY: the effect acts on every body of the scene

# effect codes and their params:
GRAVITY = 1        # params[0] = g                           F = −M g ẑ at x
POINT_FORCE = 2    # [0:3] b, [3:6] f, [6] 1 if body frame   F = f (or R f) at r = x + R b
SPRING = 3         # [0:3] b, [3:6] world point (or the other body's point), [6] k, [7] c, [8] ℓ₀
LINEAR_DRAG = 4    # [0] c                                   F = −c v at x
ANGULAR_DRAG = 5   # [0] c                                   τ = −c ω

N_PARAMS = 9

# forces over time given as data (profiles.py): the kinds of a profile row [slot, kind, p0 … p7]
CONSTANT, PULSE, RAMP, SINE, STEPS = range(5)
PROFILE_COLUMNS = 10


class System(NamedTuple):
    """The scene's constants as arrays (see the module docstring)."""
    mass: np.ndarray
    I: np.ndarray
    I_inv: np.ndarray
    I_inv_rows: np.ndarray
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
    velocity: np.ndarray
    profiles: np.ndarray
    table: np.ndarray
    grounds: np.ndarray
    first: np.ndarray
    contact_body: np.ndarray
    contact_shape: np.ndarray
    contact_half: np.ndarray
    contact_axes: np.ndarray


class Row(NamedTuple):
    """One effect on one body, as the kernel reads it: its code, the body (EVERY: all), the other body of a
    two-body effect (-1: none), its parameters (at most N_PARAMS floats), its slot among the forces f(t) (-1: none),
    whether its force depends on the velocities (a damped spring, a drag: the effect's velocity_dependent)."""
    code: int
    body: int
    params: tuple
    other: int = -1
    slot: int = -1
    velocity: bool = False


def evaluates_forces(sys: System) -> bool:
    """Does the scene evaluate forces at all: an effect row, or a pivot (its reaction torques the body)?  A free
    body evaluates none: its run is given no forces (values None: motion.stage), and compiles no force code."""
    return len(sys.code) > 0 or bool(np.any(sys.pivoted))


def principal_axes(I: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """I (N, 3, 3) = A diag(I₁, I₂, I₃) Aᵀ: the moments (N, 3), ascending, and the axes A (N, 3, 3) as columns,
    det A = +1 (the splitting's axis flows and the exact free flow turn about them).  NaN for an I that is not
    finite (a method that needs them says so: exact_flow.exact_flow_supported)."""
    finite = np.all(np.isfinite(I), axis=(-2, -1))
    moments, axes = np.full(I.shape[:-1], np.nan), np.full(I.shape, np.nan)
    if finite.any():
        moments[finite], axes[finite] = np.linalg.eigh(I[finite])
    axes[np.linalg.det(np.where(finite[:, None, None], axes, 1.0)) < 0, :, 2] *= -1.0
    return moments, axes


class TimeRow(NamedTuple):
    """A force over time as data (profiles.py): its slot among the forces f(t), its kind, its parameters
    (at most 8 floats), and its step table's rows [t_j, f_j] (STEPS; else empty)."""
    slot: int
    kind: int
    params: tuple
    table: tuple = ()


class GroundRows(NamedTuple):
    """A ground plane z = height with restitution e, friction μ (g: the scene's gravity, for the resting
    threshold), and the contact points of the bodies it acts on: body (n,), shape (n,), half (n, 3), axes (n, 3, 3)."""
    height: float
    restitution: float
    friction: float
    g: float
    body: np.ndarray
    shape: np.ndarray
    half: np.ndarray
    axes: np.ndarray


def system(mass, I, I_inv, pivoted, pivot_b, pivot_p, rows: list[Row], time_rows: list[TimeRow] = (),
           grounds: list[GroundRows] = ()) -> System:
    """The System of N bodies (their mass, inertia about the rotation centre and its inverse, pivots), the
    effects' rows, the forces over time given as data and the ground planes, as contiguous writable arrays
    (one array type per field: one compiled specialisation).  A step table's rows go in `table`; its profile
    row holds where."""
    E = len(rows)
    params = np.zeros((E, N_PARAMS))
    code, body, other, slot = (np.zeros(E, dtype=np.int64) for _ in range(4))
    velocity = np.zeros(E, dtype=np.bool_)
    for k, r in enumerate(rows):
        code[k], body[k], other[k], slot[k], velocity[k] = r.code, r.body, r.other, r.slot, r.velocity
        params[k, :len(r.params)] = r.params
    profiles, tables = np.zeros((len(time_rows), PROFILE_COLUMNS)), []
    for q, r in enumerate(time_rows):
        p = (sum(len(t) for t in tables), len(r.table)) if r.table else r.params
        profiles[q, :2], profiles[q, 2:2 + len(p)] = (r.slot, r.kind), p
        tables.append(r.table)
    table = np.array([row for t in tables for row in t], dtype=float).reshape(-1, 4)
    G = np.array([(g.height, g.restitution, g.friction, g.g) for g in grounds], dtype=float).reshape(-1, 4)
    first = np.cumsum([0] + [len(g.body) for g in grounds]).astype(np.int64)
    joined = [np.concatenate([np.asarray(getattr(g, f)).reshape((-1,) + tail) for g in grounds] or [np.zeros((0,) + tail)])
              for f, tail in (("body", ()), ("shape", ()), ("half", (3,)), ("axes", (3, 3)))]
    moments, axes = principal_axes(np.asarray(I, dtype=float))
    mass, I, I_inv, moments, axes = (np.array(a, dtype=float, order="C")
                                     for a in (mass, I, I_inv, moments, axes))
    rows_of_I_inv = np.array(I_inv.reshape(-1, 9).T, order="C")        # (9, N)
    return System(mass, I, I_inv, rows_of_I_inv, moments, axes, np.array(pivoted, dtype=np.bool_, order="C"),
                  np.array(pivot_b, dtype=float, order="C"), np.array(pivot_p, dtype=float, order="C"), code, body,
                  other, params, slot, velocity, profiles, table, G, first, np.array(joined[0], dtype=np.int64),
                  np.array(joined[1], dtype=np.int64), np.array(joined[2], dtype=float, order="C"),
                  np.array(joined[3], dtype=float, order="C"))
