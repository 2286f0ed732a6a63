"""The ground contact solver of the engine (rbcourse/engine/contact.py): its physics, and compiled == interpreted."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.engine import contact as solver
from rbcourse.engine.interpreted import module
from rbcourse.rotation import rotation_about

G = 9.81
SIGNS = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], dtype=float)


def random_case(rng, n):
    """n bodies (boxes, spheres, cylinders) flat, on an edge, on a corner or lying on a side, sliding, spinning,
    falling, the lowest point a little below or above the plane (some far above: no contact)."""
    bodies, states = [], []
    for _ in range(n):
        kind = rng.integers(3)
        body = (rb.RigidBody.box(rng.uniform(0.5, 2), rng.uniform(0.05, 0.4, 3)) if kind == 0 else
                rb.RigidBody.sphere(rng.uniform(0.5, 2), rng.uniform(0.05, 0.2)) if kind == 1 else
                rb.RigidBody.cylinder(rng.uniform(0.5, 2), rng.uniform(0.05, 0.2), rng.uniform(0.1, 0.4)))
        how = rng.integers(4)
        yaw = rotation_about([0, 0, 1], rng.uniform(0, 6))
        R = (yaw if how == 0 else yaw @ rotation_about([1, 0, 0], rng.uniform(0.2, 1.2)) if how == 1 else
             rotation_about(rng.normal(size=3), rng.uniform(0, 3)) if how == 2 else yaw @ rotation_about([1, 0, 0], np.pi / 2))
        v = rng.normal(size=3) * rng.choice([0.0, 0.01, 0.5, 2.0])
        w = rng.normal(size=3) * rng.choice([0.0, 0.1, 3.0])
        X = rb.State.from_velocities(body, [rng.normal(), rng.normal(), 0.0], R, v, w)
        low = (X.R @ (SIGNS * body.half_extents()).T)[2].min() if body.shape != "sphere" else -body.half_extents()[0]
        gap = rng.choice([rng.uniform(-1e-3, 2e-3), 0.0, 1.0]) if rng.random() < 0.9 else rng.uniform(-1e-2, 0)
        bodies.append(body)
        states.append(X.replace(x=X.x + [0, 0, -low + gap]))
    ground = rb.Ground(rng.choice([0.0, 0.1]), rng.choice([0.0, 0.3, 1.0]), rng.choice([0.0, 0.5, 1.2]))
    return bodies, rb.State.stack(states), ground, rng.choice([1e-3, 4e-3])


def worst_difference(bodies, X, Y, Z):
    """max over bodies of |Y − Z|, relative to each body's scale: 1 m for x, 1 for R, M (|v| + |ω| r) for P,
    that times r for L (r: its largest half extent)."""
    worst = 0.0
    for i, b in enumerate(bodies):
        r = b.half_extents().max()
        I_inv = X.R[i] @ b.I_body_inv @ X.R[i].T
        p = b.mass * (np.linalg.norm(X.P[i]) / b.mass + np.linalg.norm(I_inv @ X.L[i]) * r + 1e-3) \
            + np.abs(Z.P[i]).max()
        for a, c, s in ((Y.x, Z.x, 1.0), (Y.R, Z.R, 1.0), (Y.P, Z.P, p), (Y.L, Z.L, p * r + np.abs(Z.L[i]).max())):
            worst = max(worst, np.abs(a[i] - c[i]).max() / s)
    return worst


def test_compiled_equals_the_numpy_solver_on_random_states():
    worst = []
    for seed in range(300):
        rng = np.random.default_rng(seed)
        bodies, X, ground, dt = random_case(rng, 1 + seed % 4)
        scene = rb.Scene(bodies, [rb.Gravity(), ground])
        geo = scene._contacts[0][2]
        Y = ground.resolve(scene, X, slice(None), dt, geo)
        with np.errstate(all="ignore"):
            Z = ground._resolve_numpy(scene, X, slice(None), dt, geo)
        worst.append(worst_difference(bodies, X, Y, Z))
    assert max(worst) <= 1e-12, (max(worst), int(np.argmax(worst)))
