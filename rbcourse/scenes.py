"""Named scenes for the demo, the notebooks and the benchmarks: a table, as box2d-lite's demos.

Each function returns an Example: the scene, its initial state, and a suggested
t_end, dt and method.  ``SCENES[name]()`` builds one; ``python -m rbcourse demo NAME`` runs it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .body import RigidBody
from .effects import PointForce
from .scene import Scene
from .state import State


@dataclass(frozen=True)
class Example:
    """A ready-to-run scene."""
    name: str
    scene: Scene
    X0: State
    t_end: float
    dt: float
    method: str
    description: str
    drift_from: float = 0.0     # measure drift from here (after a push, say)


class Pulse:
    """A force that acts only for t_start <= t < t_stop:  F(t) = force on the interval, 0 outside."""

    def __init__(self, force, t_start: float, t_stop: float):
        self.force = np.asarray(force, dtype=float)
        self.t_start, self.t_stop = float(t_start), float(t_stop)
        self._zero = np.zeros(3)

    def __call__(self, t: float) -> np.ndarray:
        return self.force if self.t_start <= t < self.t_stop else self._zero

    def __repr__(self) -> str:
        return f"Pulse({self.force.tolist()} N for {self.t_start:g} <= t < {self.t_stop:g} s)"


def racket_box() -> RigidBody:
    """The benchmarks' box: 1 kg, 0.3 × 0.2 × 0.05 m (y is the intermediate axis)."""
    return RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))


def pushed_box() -> Example:
    """The slides' box, pushed at a corner: F = (0, 0, 10) N at the corner (0.15, 0.1, 0.025) for 0.1 s,
    then tumbling freely (no gravity)."""
    body = racket_box()
    corner = (0.15, 0.10, 0.025)
    push = PointForce(body_point=corner, force=Pulse((0.0, 0.0, 10.0), 0.0, 0.1), frame="world")
    scene = Scene(body, [push], name="pushed box")
    return Example("pushed_box", scene, State.at_rest(), t_end=5.0, dt=1e-3, method="rk4",
                   description="a box pushed at a corner for 0.1 s, then tumbling freely", drift_from=0.1)


def tennis_racket() -> Example:
    """Benchmark A: free box spun about its intermediate axis (Dzhanibekov flip), ω0 = (0.01, 5, 0.01) body."""
    body = racket_box()
    X0 = State.from_velocities(body, np.zeros(3), np.eye(3), np.zeros(3), [0.01, 5.0, 0.01])
    return Example("tennis_racket", Scene(body, name="tennis racket"), X0, t_end=20.0, dt=1e-3, method="rk4",
                   description="a free box spinning about its intermediate axis: it flips about every 10 s")


SCENES = {
    "pushed_box": pushed_box,
    "tennis_racket": tennis_racket,
}


def get_scene(name: str) -> Example:
    """SCENES[name]() with a clear error for an unknown name."""
    if name not in SCENES:
        raise ValueError(f"scene must be one of {sorted(SCENES)}, got {name!r}")
    return SCENES[name]()
