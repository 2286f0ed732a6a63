"""Named scenes for the demo, the notebooks and the benchmarks: a table, as box2d-lite's demos.

Each function returns an Example: the scene, its initial state, and a suggested
t_end, dt and method.  ``SCENES[name]()`` builds one; ``python -m rbcourse demo NAME`` runs it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..body import RigidBody
from ..effects import Gravity, LinearDrag, AngularDrag, PointForce, Spring
from ..pivot import Pivot
from ..scene import Scene
from ..state import State


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
                   description="a free box spinning about its intermediate axis: it flips about every 5 s")


def box_on_spring() -> Example:
    """A box hanging from a damped spring attached at one of its corners, under gravity: it bobs and swings."""
    body = racket_box()
    spring = Spring(body_point=(0.15, 0.1, 0.025), world_point=(0.0, 0.0, 1.0), stiffness=50.0, damping=0.1,
                    rest_length=0.3)
    scene = Scene(body, [Gravity(), spring], name="box on a spring")
    X0 = State.from_velocities(body, [0.1, 0.0, 0.5], np.eye(3), np.zeros(3), [0.0, 0.0, 2.0])
    return Example("box_on_spring", scene, X0, t_end=10.0, dt=1e-3, method="rk4",
                   description="a box hanging from a spring at one corner, bobbing and swinging under gravity")


def top_disc() -> RigidBody:
    """Benchmark C's disc: cylinder r = 0.04 m, h = 0.01 m, m = 1 kg (symmetry axis: body z)."""
    return RigidBody.cylinder(mass=1.0, radius=0.04, height=0.01)


def heavy_top(tilt_deg: float = 30.0, spin: float = 200.0) -> Example:
    """Benchmark C: a disc on a massless stem, pivot at the world origin, centre of mass 5 cm up the
    symmetry axis; tilted 30° about world x, spinning at 200 rad/s about its axis, under gravity."""
    body = top_disc()
    pivot = Pivot(body_point=(0.0, 0.0, -0.05), world_point=(0.0, 0.0, 0.0))
    R0 = rotation_about_x(np.radians(tilt_deg))
    X0 = pivot.state(body, R0, R0 @ np.array([0.0, 0.0, spin]))
    scene = Scene(body, [Gravity(), pivot], name="heavy top")
    return Example("heavy_top", scene, X0, t_end=5.0, dt=2.5e-4, method="rk4",
                   description="a fast heavy top: it spins, precesses slowly and nutates a little")


def many_bodies(n: int = 200, seed: int = 0) -> Example:
    """A field of n boxes of random sizes and spins on a grid, slowed by a little drag: stepped as arrays."""
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(n)))
    bodies, states = [], []
    for i in range(n):
        size = rng.uniform(0.05, 0.3, 3)
        body = RigidBody.box(mass=float(rng.uniform(0.5, 2.0)), size=size)
        x = np.array([i % side, i // side, 1.0]) * 0.5
        states.append(State.from_velocities(body, x, np.eye(3), np.zeros(3), rng.normal(0.0, 3.0, 3)))
        bodies.append(body)
    scene = Scene(bodies, [AngularDrag(1e-4), LinearDrag(1e-3)], name="field of boxes")
    return Example("many_bodies", scene, State.stack(states), t_end=5.0, dt=2e-3, method="rk4",
                   description=f"{n} tumbling boxes, stepped together as arrays")


def dropped_box(restitution: float = 0.4, friction: float = 0.5) -> Example:
    """A box dropped from 1 m, tilted and spinning, moving sideways: it bounces, slides, tips over
    and comes to rest on the floor (gravity + ground contact, nothing else)."""
    from ..contact import Ground
    from ..rotation import rotation_about
    body = racket_box()
    R0 = rotation_about([1.0, 0.5, 0.0], 0.6)
    X0 = State.from_velocities(body, [0.0, 0.0, 1.0], R0, [1.0, 0.0, 0.0], [2.0, -3.0, 5.0])
    scene = Scene(body, [Gravity(), Ground(height=0.0, restitution=restitution, friction=friction)], name="dropped box")
    return Example("dropped_box", scene, X0, t_end=3.0, dt=2e-3, method="rk4",
                   description="a box dropped on the floor: it bounces, slides, tips over and comes to rest")


def rotation_about_x(angle: float) -> np.ndarray:
    """The rotation by `angle` (rad) about world x."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


SCENES = {
    "pushed_box": pushed_box,
    "tennis_racket": tennis_racket,
    "box_on_spring": box_on_spring,
    "heavy_top": heavy_top,
    "many_bodies": many_bodies,
    "dropped_box": dropped_box,
}


def get_scene(name: str) -> Example:
    """SCENES[name]() with a clear error for an unknown name."""
    if name not in SCENES:
        raise ValueError(f"scene must be one of {sorted(SCENES)}, got {name!r}")
    return SCENES[name]()
