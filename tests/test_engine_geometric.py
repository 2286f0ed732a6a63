"""The compiled geometric methods (rbcourse/engine/geometric.py) against the numpy engine (fast=False).

rb.simulate runs them through the driver (encode, force values at the nodes, record, decode) and is
compared with rb.simulate(..., fast=False) over 1000 steps, per array as max |a − b| / (1 + max |b|)
<= 1e-12 (tests/test_engine.py's measure).
"""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse import driver
from rbcourse.engine import geometric
from rbcourse.engine.motion import work
from rbcourse.engine.tableaus import MIDPOINT

DT = 1e-3
STEPS = 1000
TOL = 1e-12
BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
BOX2 = rb.RigidBody.box(2.0, (0.1, 0.4, 0.2))
R_TILT = rb.rotation.rotation_about([1.0, 2.0, 3.0], 0.4)
PIVOT = rb.Pivot(body_point=(0.0, 0.0, -0.05))

METHODS = ("symplectic_euler", "splitting", "rkmk4")


def spinning(body=BOX, x=(0.0, 0.0, 1.0), v=(0.1, -0.2, 0.3), omega=(0.3, 2.0, 0.5), R=None):
    return rb.State.from_velocities(body, x=x, R=np.eye(3) if R is None else R, v=v, omega=omega)


def push(t):
    return (np.sin(3.0 * t), 0.5 * np.cos(2.0 * t), 1.0 + t)


def three_bodies():
    box3 = rb.RigidBody(mass=0.5, inertia=[[0.02, 0.003, 0.0], [0.003, 0.03, 0.001], [0.0, 0.001, 0.04]])
    scene = rb.Scene([BOX, BOX2, box3],
                     [rb.Gravity(), rb.Spring((0.1, 0.0, 0.0), stiffness=20.0, damping=0.2, rest_length=0.3, body=0,
                                              other_body=1, other_point=(0.0, 0.1, 0.0))])
    X0 = rb.State.stack([spinning(), spinning(BOX2, x=(0.5, 0.2, 1.0), v=(0.0, 0.3, 0.0), omega=(-1.0, 0.4, 1.5),
                                              R=R_TILT),
                         spinning(box3, x=(-0.4, 0.1, 0.0), omega=(2.0, -1.0, 3.0), R=R_TILT.T)])
    return scene, X0


CASES = {
    "free": lambda: (rb.Scene(BOX), spinning()),
    "gravity": lambda: (rb.Scene(BOX, [rb.Gravity()]), spinning()),
    "point_world": lambda: (rb.Scene(BOX, [rb.PointForce((0.15, 0.1, 0.025), (0.0, 0.0, 10.0))]), spinning()),
    "point_body": lambda: (rb.Scene(BOX, [rb.PointForce((0.15, 0.1, 0.025), (0.0, 0.0, 1.0), frame="body")]),
                           spinning()),
    "point_world_f(t)": lambda: (rb.Scene(BOX, [rb.PointForce((0.15, 0.1, 0.025), push)]), spinning()),
    "point_body_f(t)": lambda: (rb.Scene(BOX, [rb.PointForce((0.15, -0.1, 0.0), push, frame="body")]), spinning()),
    "spring_undamped": lambda: (rb.Scene(BOX, [rb.Spring((0.1, 0.05, 0.0), (0.0, 0.0, 0.0), stiffness=5.0)]),
                                spinning(R=R_TILT)),
    "spring_damped": lambda: (rb.Scene(BOX, [rb.Spring((0.1, 0.05, 0.0), (0.0, 0.2, 1.5), stiffness=50.0,
                                                       damping=0.3, rest_length=0.4)]), spinning(R=R_TILT)),
    "linear_drag": lambda: (rb.Scene(BOX, [rb.LinearDrag(0.7), rb.Gravity()]), spinning()),
    "angular_drag": lambda: (rb.Scene(BOX, [rb.AngularDrag(0.02)]), spinning(omega=(0.3, 5.0, 0.5))),
    "heavy_top": lambda: (rb.Scene(BOX, [rb.Gravity(), PIVOT]), PIVOT.state(BOX, R_TILT, [0.5, 0.0, 10.0])),
    "heavy_top_drag": lambda: (rb.Scene(BOX, [rb.Gravity(), PIVOT, rb.LinearDrag(0.3)]),
                               PIVOT.state(BOX, R_TILT, [0.5, 0.0, 10.0])),
    "two_bodies_spring": lambda: (
        rb.Scene([BOX, BOX2], [rb.Spring((0.1, 0.0, 0.0), stiffness=20.0, damping=0.2, rest_length=0.3, body=0,
                                         other_body=1, other_point=(0.0, 0.1, 0.0))]),
        rb.State.stack([spinning(), spinning(BOX2, x=(0.5, 0.2, 1.0), v=(0.0, 0.3, 0.0), omega=(-1.0, 0.4, 1.5),
                                             R=R_TILT)])),
    "three_bodies_spring": three_bodies,
}


def spread(a, b) -> float:
    """max |a − b| / (1 + max |b|)."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    return float(np.max(np.abs(a - b)) / (1.0 + np.max(np.abs(b))))


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("method", METHODS)
def test_compiled_equals_numpy(method, case):
    scene, X0 = CASES[case]()
    slow = rb.simulate(scene, X0, STEPS * DT, DT, method, fast=False)
    fast = rb.simulate(scene, X0, STEPS * DT, DT, method)
    assert fast.implementation.startswith("compiled"), fast.implementation
    assert slow.implementation.startswith("interpreted (fast=False)"), slow.implementation
    np.testing.assert_allclose(fast.t, slow.t, rtol=0, atol=1e-12)
    for k in "xRPL":
        d = spread(getattr(fast, k), getattr(slow, k))
        assert d <= TOL, f"{method}, {case}: {k} differs by {d:.3g}"
    # and the runs moved: a wrong formula cannot hide behind a state that stays put
    assert spread(slow.R[-1], slow.R[0]) > 1e-3


@pytest.mark.parametrize("case", sorted(CASES))
def test_velocity_dependent_is_the_scenes(case):
    scene, _ = CASES[case]()
    assert geometric.velocity_dependent(scene.compile().system) == scene.velocity_dependent


def test_the_systems_principal_axes():
    scene, _ = three_bodies()
    sys = scene.compile().system
    assert sys.I_moments.shape == (3, 3) and sys.I_axes.shape == (3, 3, 3)
    for i in range(3):
        A = sys.I_axes[i]
        np.testing.assert_allclose(A @ np.diag(sys.I_moments[i]) @ A.T, scene.I_rot[i], rtol=0, atol=1e-15)
        assert np.linalg.det(A) == pytest.approx(1.0, abs=1e-14)


def test_splitting_keeps_a_free_bodys_L_and_the_state_it_was_given():
    """A free body: L is exactly constant, R stays on SO(3); the step leaves Y as it was."""
    scene, X0 = CASES["free"]()
    sys = scene.compile().system
    Y = driver.encode("matrix", scene.to_engine(scene.batch(X0)))
    Y0 = Y.copy()
    out, K, U, w = np.empty_like(Y), np.empty((4,) + Y.shape), np.empty_like(Y), work(1)
    values = np.zeros((4, 0, 3))
    geometric.splitting_step(sys, values, np.zeros(0), np.ascontiguousarray(MIDPOINT.A),
                             MIDPOINT.b, MIDPOINT.den, Y, out, 0.01, K, U, w)
    assert np.array_equal(Y, Y0)
    assert np.array_equal(out[0, 15:18], Y[0, 15:18])
    R = out[0, 3:12].reshape(3, 3)
    assert np.abs(R.T @ R - np.eye(3)).max() < 1e-15
    assert np.abs(R - Y[0, 3:12].reshape(3, 3)).max() > 1e-3
