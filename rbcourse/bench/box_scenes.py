"""The boxes the throughput report times: n random free boxes (boxes), the ground they meet
(bench_ground), the boxes resting flat on it (resting_state) and the slides' box dropped on it
(dropped_box).  Used by bench/throughput.py and bench/contact_rows.py.
"""
from __future__ import annotations

import numpy as np

from ..body import RigidBody
from ..effects import Gravity
from ..scene import Scene
from ..state import State

MAX_BODIES = 10**6      # the largest N of the throughput report (the command line's --bodies is checked against it)
DROP_FROM = 0.2             # m: the dropped box's lowest point … its centre at DROP_FROM + half its height


def boxes(n: int, seed: int = 0):
    """n random boxes (0.5–2 kg, sides 0.05–0.3 m) with random spins, on a grid 1 m up, built as
    arrays (RigidBody.boxes, a stacked State.from_velocities): (bodies, their State)."""
    rng = np.random.default_rng(seed)
    bodies = RigidBody.boxes(rng.uniform(0.5, 2.0, n), rng.uniform(0.05, 0.3, (n, 3)))
    i = np.arange(n)
    x = np.stack([i % 100, i // 100, np.ones(n)], axis=1).astype(float)
    R = np.broadcast_to(np.eye(3), (n, 3, 3))
    X0 = State.from_velocities(bodies, x, R, rng.normal(0.0, 0.1, (n, 3)), rng.normal(0.0, 3.0, (n, 3)))
    return bodies, X0


def bench_ground():
    """The scenes' ground: Ground(0, e = 0.5, μ = 0.5), or None without rbcourse.contact."""
    try:
        from ..contact import Ground
    except ImportError:
        return None
    return Ground(height=0.0, restitution=0.5, friction=0.5)


def dropped_box():
    """The slides' box (1 kg, 0.3 × 0.2 × 0.05 m) over Ground(0, e = 0.5, μ = 0.5) under gravity, its lowest
    point DROP_FROM up before the tilt (centre at DROP_FROM + 0.025), tilted by exp_so3((0.3, 0.2, 0)), spinning
    at ω = (1, −0.5, 2) rad/s: (body, scene, X0)."""
    from ..rotation import exp_so3
    body = RigidBody.box(1.0, (0.3, 0.2, 0.05))
    scene = Scene(body, [Gravity(), bench_ground()])
    X0 = State.from_velocities(body, [0.0, 0.0, DROP_FROM + 0.025], exp_so3(np.array([0.3, 0.2, 0.0])),
                               np.zeros(3), [1.0, -0.5, 2.0])
    return body, scene, X0


def resting_state(bodies):
    """The bodies (boxes) at rest flat on the ground z = 0: centres half their height up, R = I, on boxes()'s
    1 m grid."""
    n = len(bodies)
    i = np.arange(n)
    half = np.array([b.size[2] for b in bodies], dtype=float) / 2
    x = np.stack([i % 100, i // 100, half], axis=1).astype(float)
    return State.from_velocities(bodies, x, np.broadcast_to(np.eye(3), (n, 3, 3)), np.zeros((n, 3)), np.zeros((n, 3)))
