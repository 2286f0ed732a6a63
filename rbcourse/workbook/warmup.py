"""Every method's compiled code made ahead of time: `python -m rbcourse compile` (for an instructor preparing a
lab image or a JupyterHub, so that no student waits for numba's first compile).

Each method runs a few steps on small scenes that between them reach what a run can compile — a free body; a
body under gravity, a spring, a point force (a constant one and one given as a function of t) and drag; a
pivoted top; a box resting on rb.Ground; two bodies joined by a spring — then the numpy face's helpers (the
derived quantities, the rotation helpers, a trajectory's energy).  numba keeps what it compiles on disk
(cache_folder()), where every later process finds it.
"""
from __future__ import annotations

import time

import numpy as np

from ..support.checks import method_names

STEPS = 20          # steps per run: enough to reach every compiled call of a run (contacts, forces, records)
DT = 1e-3


def check_methods(text: str | None, allowed=None) -> list[str]:
    """The methods of --methods a,b (every name of `allowed` when None; allowed: every name in METHODS, sorted, by
    default), checked: ValueError naming the allowed ones for an unknown or empty name."""
    from ..methods import METHODS
    return method_names(text, sorted(METHODS) if allowed is None else allowed)


def scenes() -> list[tuple[str, object, object]]:
    """(name, scene, initial State) of the small scenes every method is run on."""
    from ..body import RigidBody
    from ..contact import Ground
    from ..effects import AngularDrag, Gravity, LinearDrag, PointForce, Spring
    from ..pivot import Pivot
    from ..profiles import Pulse
    from ..scene import Scene
    from ..state import State
    box = RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))
    spin = State.from_velocities(box, np.zeros(3), np.eye(3), np.zeros(3), [0.01, 5.0, 0.01])
    forced = Scene(box, [Gravity(), Spring(body_point=(0.15, 0.1, 0.025), world_point=(0.0, 0.0, 1.0),
                                           stiffness=50.0, damping=0.1),
                         PointForce(body_point=(0.15, 0.0, 0.0), force=(0.0, 1.0, 0.0)),
                         PointForce(body_point=(0.0, 0.1, 0.0), force=lambda t: np.array([np.sin(t), 0.0, 0.0])),
                         PointForce(body_point=(0.1, 0.0, 0.0), force=Pulse((0.0, 0.0, 1.0), 0.0, 0.1)),
                         LinearDrag(1e-3), AngularDrag(1e-4)])
    disc = RigidBody.cylinder(mass=1.0, radius=0.1, height=0.02)
    pivot = Pivot(body_point=(0.0, 0.0, -0.05))
    top = Scene(disc, [Gravity(), pivot])
    resting = Scene(box, [Gravity(), Ground(height=0.0, restitution=0.2, friction=0.5)])
    lying = State.from_velocities(box, [0.0, 0.0, 0.025], np.eye(3), [0.1, 0.0, -0.1], [0.0, 0.0, 1.0])   # on it
    pair = Scene([box, box], [Spring(body_point=(0.15, 0.1, 0.025), stiffness=100.0, rest_length=0.5, body=0,
                                     other_body=1, other_point=(-0.15, -0.1, -0.025))])
    two = State.stack([spin, State.from_velocities(box, [0.8, 0.3, 0.0], np.eye(3), [0.0, 1.0, 0.5],
                                                   [1.0, 2.0, 3.0])])
    return [("free body", box, spin), ("forces", forced, spin),
            ("pivoted top", top, pivot.state(disc, np.eye(3), [0.5, 0.0, 50.0])),
            ("box on the ground", resting, lying), ("two bodies", pair, two)]


def rows(body, scene, X) -> None:
    """The numpy face's helpers (engine/rows.py), each once: derived quantities, rotation helpers, the energy and
    velocities of a trajectory (of the scene, run interpreted: the helpers compile, not a method)."""
    from ..rotation import (cross, exp_so3, matrix_from_quat, project_so3, quat_from_matrix, quat_multiply,
                           quat_normalize, retract, rotation_angle, star)
    from ..simulate import simulate
    from ..state import derived
    derived(body, X)
    star(np.ones(3))
    cross(np.ones(3), np.ones(3))
    exp_so3(np.full(3, 0.1))
    project_so3(np.eye(3))
    rotation_angle(np.eye(3), 1.001 * np.eye(3))       # nearest_rotation: orthonormalize's rows
    retract(np.eye(3))
    q = quat_normalize(quat_from_matrix(np.eye(3)))
    matrix_from_quat(quat_multiply(q, q))
    traj = simulate(scene, X, STEPS * DT, DT, "euler", fast=False)
    traj.total_energy(), traj.velocity(), traj.angular_velocity()
    from ..profiles import Pulse
    Pulse((0.0, 0.0, 1.0), 0.0, 1.0)(0.5)           # a profile called from Python, once a run loaded the kernel


def warm(methods, progress: bool = True) -> list[str]:
    """Run every method on every scene (scenes()), then the helpers (rows): what they compile is cached.
    -> the runs that could not be made, one line each (a method that refuses a scene, say why)."""
    from tqdm.auto import tqdm
    from .. import compiling
    from ..simulate import simulate
    plan = [(m, *s) for m in methods for s in scenes()]
    refused = []
    with compiling.quiet(), tqdm(total=len(plan) + 1, disable=not progress, unit="run", leave=True) as bar:
        for method, name, scene, X in plan:
            bar.set_description(method)
            try:
                simulate(scene, X, STEPS * DT, DT, method, on_divergence="stop")
            except ValueError as err:
                refused.append(f"{method} on {name}: {err}")
            bar.update()
        bar.set_description("helpers")
        (_, body, free), (_, forced, _) = scenes()[:2]
        rows(body, forced, free)
        bar.update()
    return refused


def cache_folder() -> str:
    """Where numba keeps the engine's compiled code (NUMBA_CACHE_DIR's folder, engine/__pycache__, or the user's
    own for a read-only install): engine.jit.cache_folder(); '' when nothing is cached (interpreted)."""
    from ..engine import jit
    folder = jit.cache_folder()
    return "" if folder is None else str(folder)


def timed(methods, progress: bool = True) -> tuple[float, list[str]]:
    """warm(methods): (seconds taken, the runs refused)."""
    start = time.perf_counter()
    refused = warm(methods, progress)
    return time.perf_counter() - start, refused
