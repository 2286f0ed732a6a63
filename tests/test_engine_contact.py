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


def resolved(engine, bodies, X, ground, dt):
    """S (N, 18) after engine.resolve (engine: the compiled module, or the same file run as Python), and its return."""
    scene = rb.Scene(bodies, [rb.Gravity(), ground])
    S = np.concatenate([X.x, X.R.reshape(-1, 9), X.P, X.L], axis=1)
    w = engine.work(len(bodies))
    touched = engine.resolve(S, w.S0, scene.compile().system, 0, float(dt), w)
    return S, touched


def test_compiled_equals_interpreted_on_random_states():
    python = module("contact")                  # engine/contact.py loaded a second time, as plain Python
    assert python.njit(len) is len and python is not solver
    touched = 0
    for seed in range(60):
        rng = np.random.default_rng(1000 + seed)
        bodies, X, ground, dt = random_case(rng, 1 + seed % 4)
        S, n = resolved(solver, bodies, X, ground, dt)
        T, m = resolved(python, bodies, X, ground, dt)
        assert n == m
        touched += n
        np.testing.assert_allclose(S, T, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(T).max()))
    assert touched > 60                        # most of them touched the ground


def lowest(traj, body):
    """z of the body's lowest corner, over time."""
    return np.min([traj.body_point(s * body.half_extents())[:, 2] for s in SIGNS], axis=0)


def test_a_dropped_box_comes_to_rest_on_its_face_without_sinking_or_gaining_energy():
    box = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    X0 = rb.State.from_velocities(box, [0, 0, 0.5], rotation_about([1, 2, 0.5], 0.3), [0.2, 0, 0], [0, 0, 2.0])
    traj = rb.simulate(rb.Scene(box, [rb.Gravity(), rb.Ground()]), X0, 2.0, 1e-3, "rk4")
    assert lowest(traj, box).min() >= -solver.CONTACT_TOL         # never below the plane beyond the tolerance
    E = traj.total_energy()
    assert np.diff(E).max() <= 1e-9 * E[0]                        # contact never adds energy
    assert E[-1] < 0.1 * E[0]
    assert abs(traj.x[-1, 2] - 0.025) < 1e-9                      # at rest, on its largest face
    assert np.abs(traj.velocity()[-200:]).max() < 1e-9 and np.abs(traj.angular_velocity()[-200:]).max() < 1e-9


@pytest.mark.parametrize("dt", [2e-3, 5e-4])
def test_an_elastic_sphere_bounces_back_to_its_height(dt):
    ball, h0 = rb.RigidBody.sphere(1.0, 0.1), 0.5
    X0 = rb.State.at_rest((0, 0, 0.1 + h0))
    traj = rb.simulate(rb.Scene(ball, [rb.Gravity(), rb.Ground(restitution=1.0, friction=0.5)]), X0, 0.7, dt)
    z, vz = traj.x[:, 2] - 0.1, traj.velocity()[:, 2]
    hit = np.argmax(vz > 0)
    assert 0 < hit and z.min() >= -1e-12
    assert abs(z[hit:].max() - h0) <= np.sqrt(2 * G * h0) * dt       # the bounce is resolved up to v dt above the plane
    assert np.ptp(traj.total_energy()) <= 1e-9 * traj.total_energy()[0]


@pytest.mark.parametrize("v0, mu", [(2.0, 0.4), (1.0, 0.8)])
def test_friction_stops_a_sliding_box_after_v0_squared_over_2_mu_g(v0, mu):
    box, dt = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05)), 1e-3
    X0 = rb.State.from_velocities(box, [0, 0, 0.025], np.eye(3), [v0, 0, 0], [0, 0, 0])
    traj = rb.simulate(rb.Scene(box, [rb.Gravity(), rb.Ground(friction=mu)]), X0, 1.5 * v0 / (mu * G), dt)
    assert 0 <= traj.x[-1, 0] - v0**2 / (2 * mu * G) <= v0 * dt
    assert np.abs(traj.velocity()[-10:]).max() < 1e-9 and abs(traj.x[-1, 2] - 0.025) < 1e-12


def test_bodies_that_do_not_touch_are_left_as_they_are():
    rng = np.random.default_rng(5)
    bodies, X, ground, dt = random_case(rng, 3)
    X = X.replace(x=X.x + [0, 0, 5.0])                             # all of them high above the plane
    S, touched = resolved(solver, bodies, X, ground, dt)
    assert touched == 0
    np.testing.assert_array_equal(S, np.concatenate([X.x, X.R.reshape(-1, 9), X.P, X.L], axis=1))
    scene = rb.Scene(bodies, [rb.Gravity(), ground])
    assert ground.resolve(scene, X, slice(None), dt) is X
