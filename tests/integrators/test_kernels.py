"""The fast paths are the same methods as the readable numpy ones, to rounding: the compiled engine
(rbcourse/engine: euler and rk4 here) and the float kernels left (adaptive, exact_splitting)."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.integrators import kernels
from rbcourse.workbook.examples import heavy_top, tennis_racket


def _asymmetric_body():
    Q = rb.rotation.rotation_about([1, 2, 0.5], 0.8)
    return rb.RigidBody(2.0, Q @ np.diag([0.02, 0.03, 0.045]) @ Q.T)


def _cases():
    A = tennis_racket()
    yield "tennis racket", A.scene, A.X0
    top = heavy_top()
    yield "heavy top", top.scene, top.X0
    body = _asymmetric_body()
    scene = rb.Scene(body, [rb.Gravity()])
    yield "falling full-inertia body", scene, rb.State.from_velocities(
        body, [0, 0, 3], rb.rotation.rotation_about([0, 1, 1], 0.3), [1, 0, 2], [2.0, -1.0, 3.0])
    pivot = rb.Pivot(body_point=(0.05, -0.02, -0.1), world_point=(0.1, 0.2, 0.3))
    scene = rb.Scene(body, [rb.Gravity(), pivot])
    yield "off-axis pivoted body", scene, pivot.state(body, rb.rotation.rotation_about([1, 0, 0], 0.4), [0.5, 1.0, 4.0])


CASES = list(_cases())


@pytest.mark.parametrize("name, scene, X0", CASES, ids=[c[0] for c in CASES])
@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_compiled_engine_is_the_numpy_method(name, scene, X0, method):
    dt = 1e-4 if method == "euler" else 2e-3
    fast = rb.simulate(scene, X0, 0.2, dt, method)
    slow = rb.simulate(scene, X0, 0.2, dt, method, fast=False)
    assert fast.implementation.startswith("compiled") and slow.implementation.startswith("numpy")
    assert fast.t.tolist() == slow.t.tolist()
    for k in "xRPL":
        a, b = getattr(fast, k), getattr(slow, k)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * (1 + np.abs(b).max()), err_msg=k)


@pytest.mark.parametrize("name, scene, X0", CASES, ids=[c[0] for c in CASES])
def test_compiled_adaptive_meets_its_tolerance_like_the_numpy_method(name, scene, X0):
    ref = rb.simulate(scene, X0, 0.5, 0.5, "adaptive", rtol=1e-13, atol=1e-15, fast=False)
    for fast in (True, False):
        traj = rb.simulate(scene, X0, 0.5, 0.05, "adaptive", rtol=1e-9, atol=1e-12, fast=fast)
        assert rb.rotation_angle(ref.R[-1], traj.R[-1]) < 1e-6
        np.testing.assert_allclose(traj.L[-1], ref.L[-1], atol=1e-6 * np.abs(ref.L[-1]).max())


def test_kernels_only_where_they_apply():
    """The last kernel: exact_splitting on one asymmetric body; everything else runs compiled."""
    body = rb.RigidBody.box(1.0, (1, 2, 3))
    exact = rb.METHODS["exact_splitting"]
    assert kernels.available(exact, rb.Scene(body))
    assert kernels.available(exact, rb.Scene(body, [rb.Gravity(), rb.Pivot((0, 0, 1))]))
    assert not kernels.available(exact, rb.Scene(body, [rb.Spring((0, 0, 0))]))
    assert not kernels.available(exact, rb.Scene([body, body]))
    for name in rb.METHODS:
        if name != "exact_splitting":
            assert not kernels.available(rb.METHODS[name], rb.Scene(body)), name
    X0 = rb.State.from_velocities(body, np.zeros(3), np.eye(3), np.zeros(3), [1.0, 2.0, 3.0])
    assert rb.simulate(body, X0, 0.1, 0.01, "exact_splitting").implementation.startswith("float kernel")
    assert rb.simulate(body, X0, 0.1, 0.01, "adaptive").implementation.startswith("compiled")
    cylinder = rb.RigidBody.cylinder(1.0, 0.1, 0.3)
    X1 = rb.State.from_velocities(cylinder, np.zeros(3), np.eye(3), np.zeros(3), [1.0, 2.0, 3.0])
    assert rb.simulate(cylinder, X1, 0.1, 0.01, "exact_splitting").implementation.startswith("compiled")
    assert not kernels.available(rb.METHODS["splitting"], rb.Scene(body))


def test_kernel_divergence_keeps_the_trajectory():
    ex = tennis_racket()
    X0 = rb.State.from_velocities(ex.scene.bodies[0], np.zeros(3), np.eye(3), np.zeros(3), [0.1, 0.1, 50.0])
    with pytest.raises(rb.SimulationDiverged) as info:
        rb.simulate(ex.scene, X0, 10.0, 1e-3, "euler", record_every=7)
    err = info.value
    traj = err.trajectory
    assert "diverged" in str(err) and np.all(np.isfinite(traj.R))
    assert traj.t[-1] == pytest.approx(err.t - 1e-3)          # the last good step is kept


def test_kernel_record_every():
    ex = tennis_racket()
    traj = rb.simulate(ex.scene, ex.X0, 1.0, 0.01, "rk4", record_every=30)
    assert traj.t.tolist() == pytest.approx([0.0, 0.3, 0.6, 0.9, 1.0])
    full = rb.simulate(ex.scene, ex.X0, 1.0, 0.01, "rk4")
    np.testing.assert_allclose(traj.R[-1], full.R[-1], atol=1e-15)


def test_rk4_is_its_table():
    """RK4 written once: the table's stage loop is the textbook k1 … k4 (numpy and compiled engine)."""
    from rbcourse.integrators import prepare, quaternion, rk4_step
    ex = tennis_racket()
    X = ex.scene.to_engine(ex.X0)
    prep = prepare(ex.scene)
    Y = quaternion.encode(ex.scene, X)
    h = 0.05

    def f(t, Y):
        return quaternion.rates(ex.scene, t, Y, prep)
    k1 = f(0, Y)
    k2 = f(h / 2, Y + h / 2 * k1)
    k3 = f(h / 2, Y + h / 2 * k2)
    k4 = f(h, Y + h * k3)
    by_hand = quaternion.normalized(Y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4))
    np.testing.assert_allclose(rk4_step(ex.scene, 0.0, Y.copy(), h, prep), by_hand, rtol=0, atol=1e-15)
    from rbcourse.engine import driver, motion, steps, system
    sys = system.compile_scene(ex.scene).system
    Y_engine = driver.encode("quat", X)
    out = np.empty_like(Y_engine)
    steps.explicit_step(*driver.ENGINE_METHODS["rk4"].arguments(ex.scene, {}), sys, np.zeros((4, 0, 3)), Y_engine, out, h,
               np.empty((4,) + Y_engine.shape), np.empty_like(Y_engine), motion.work(1))
    np.testing.assert_allclose(out, by_hand.T, rtol=0, atol=1e-15)


def _pushed_cases():
    from rbcourse.workbook.examples import pushed_box
    ex = pushed_box()
    yield "the slides' pushed box", ex.scene, ex.X0
    body = _asymmetric_body()
    spin = rb.PointForce((0.1, 0.0, 0.05), lambda t: (0.0, 3.0 * np.cos(5 * t), 1.0), frame="body")
    pull = rb.PointForce((-0.05, 0.02, 0.0), (0.5, -1.0, 2.0))
    scene = rb.Scene(body, [rb.Gravity(), spin, pull])
    yield "forces of t in body axes, with gravity", scene, rb.State.from_velocities(
        body, [0, 0, 1], rb.rotation.rotation_about([1, 1, 0], 0.7), [1, 0, 0], [0.5, -1.0, 2.0])
    pivot = rb.Pivot(body_point=(0.05, -0.02, -0.1), world_point=(0.1, 0.2, 0.3))
    scene = rb.Scene(body, [rb.Gravity(), pivot, spin, pull])
    yield "forces at points on a pivoted body", scene, pivot.state(body, rb.rotation.rotation_about([1, 0, 0], 0.4), [0.5, 1.0, 4.0])


PUSHED = list(_pushed_cases())


@pytest.mark.parametrize("name, scene, X0", PUSHED, ids=[c[0] for c in PUSHED])
def test_compiled_euler_with_forces_at_points_is_the_numpy_euler(name, scene, X0):
    fast = rb.simulate(scene, X0, 0.3, 1e-3, "euler", record_every=7)
    slow = rb.simulate(scene, X0, 0.3, 1e-3, "euler", record_every=7, fast=False)
    assert fast.t.tolist() == slow.t.tolist()
    for k in "xRPL":
        a, b = getattr(fast, k), getattr(slow, k)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * (1 + np.abs(b).max()), err_msg=k)


def test_compiled_euler_checks_a_force_function_as_the_numpy_path_does():
    body = rb.RigidBody.box(1.0, (1, 2, 3))
    X0 = rb.State.from_velocities(body, np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3))
    for force in (lambda t: (1.0, float("nan") if t > 0.05 else 0.0, 0.0), lambda t: (1.0, 2.0), lambda t: None):
        bad = rb.Scene(body, [rb.PointForce((0, 0, 0.5), force)])
        for fast in (True, False):
            with pytest.raises(ValueError, match=r"force\(t\) must return a finite 3-vector"):
                rb.simulate(bad, X0, 0.1, 0.01, "euler", fast=fast)
