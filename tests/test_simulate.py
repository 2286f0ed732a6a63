import numpy as np
import pytest

import rbcourse as rb
from rbcourse.rotation import star

BOX = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))


def test_euler_step_is_the_slides_recipe_bit_for_bit():
    rng = np.random.default_rng(1)
    X = rb.State.from_velocities(BOX, rng.normal(size=3), rb.rotation.rotation_about(rng.normal(size=3), 1.0),
                                 rng.normal(size=3), rng.normal(size=3))
    scene = rb.Scene(BOX, [rb.PointForce((0.1, 0, 0), (0, 1.0, 2.0)), rb.Gravity()])
    dt = 0.01
    traj = rb.simulate(scene, X, dt, dt, "euler")
    # by hand, in the slides' order
    v = X.P / BOX.mass
    I_inv = X.R @ BOX.I_body_inv @ X.R.T
    omega = I_inv @ X.L
    r = X.x + X.R @ np.array([0.1, 0, 0])
    F = np.array([0, 1.0, 2.0]) + np.array([0, 0, -9.81 * BOX.mass])
    tau = np.cross(r - X.x, [0, 1.0, 2.0])
    np.testing.assert_allclose(traj.x[1], X.x + dt * v, rtol=0, atol=1e-15)
    np.testing.assert_allclose(traj.R[1], X.R + dt * star(omega) @ X.R, rtol=0, atol=1e-15)
    np.testing.assert_allclose(traj.P[1], X.P + dt * F, rtol=0, atol=1e-15)
    np.testing.assert_allclose(traj.L[1], X.L + dt * tau, rtol=0, atol=1e-15)


def test_free_body_euler_keeps_L_but_leaves_SO3():
    # spin about the principal z axis: Euler gives R_n = (I + dt ω*)^n, so RᵀR = diag(s, s, 1)
    # with s = (1 + dt² ω²)^n: ‖RᵀR − I‖ = √2 (s − 1) and det R = s, exactly
    w, dt, n = 5.0, 1e-3, 2000
    X0 = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), np.zeros(3), [0, 0, w])
    traj = rb.simulate(BOX, X0, n * dt, dt, "euler")
    assert np.all(traj.L == traj.L[0])                                   # L constant, by construction
    s = (1 + dt**2 * w**2) ** np.arange(n + 1)
    np.testing.assert_allclose(traj.orthogonality_error(), np.sqrt(2) * (s - 1), rtol=1e-6, atol=1e-15)
    np.testing.assert_allclose(traj.det_R(), s, rtol=1e-12)
    assert traj.orthogonality_error()[-1] > 0.07                         # measured drift off SO(3)


def test_tumbling_box_euler_drifts_while_rk4_does_not():
    X0 = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), np.zeros(3), [0.01, 5.0, 0.01])
    eu = rb.simulate(BOX, X0, 5.0, 1e-3, "euler")
    k4 = rb.simulate(BOX, X0, 5.0, 1e-3, "rk4")
    assert eu.orthogonality_error()[-1] > 0.1 and k4.orthogonality_error().max() < 1e-13
    assert np.all(eu.L == eu.L[0])
    assert eu.kinetic_energy()[-1] > 1.005 * eu.kinetic_energy()[0]      # the slides' Euler gains energy
    E = k4.kinetic_energy()
    assert abs(E[-1] / E[0] - 1) < 1e-8


def test_constant_force_at_the_centre_is_first_order():
    # x(t) = x0 + v0 t + ½ (F/M) t²; Euler's error is ½ (F/M) t dt: linear in dt
    F = np.array([1.0, -2.0, 3.0])
    scene = rb.Scene(BOX, [rb.PointForce((0, 0, 0), F)])
    X0 = rb.State.from_velocities(BOX, [1, 2, 3], np.eye(3), [0.5, 0, -1], np.zeros(3))
    T, errors, dts = 1.0, [], [0.1, 0.05, 0.025, 0.0125, 0.00625]
    exact = np.array([1, 2, 3]) + np.array([0.5, 0, -1]) * T + 0.5 * F / BOX.mass * T**2
    for dt in dts:
        traj = rb.simulate(scene, X0, T, dt, "euler")
        assert traj.t[-1] == pytest.approx(T)
        errors.append(np.linalg.norm(traj.x[-1] - exact))
        np.testing.assert_allclose(traj.x[-1] - exact, -0.5 * F / BOX.mass * T * dt, atol=1e-12)
    order = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert abs(order - 1.0) < 0.05
    assert np.all(traj.R == np.eye(3))      # no torque: R never moves


def test_trajectory_shapes_and_diagnostics():
    scene = rb.Scene(BOX, [rb.Gravity()])
    X0 = rb.State.from_velocities(BOX, [0, 0, 10], np.eye(3), [1, 0, 0], [0, 0, 1.0])
    traj = rb.simulate(scene, X0, t_end=0.5, dt=0.01, method="rk4")
    n = 50
    assert traj.t.shape == (n + 1,) and traj.x.shape == (n + 1, 3) and traj.R.shape == (n + 1, 3, 3)
    assert traj.P.shape == (n + 1, 3) and traj.L.shape == (n + 1, 3)
    assert traj.kinetic_energy().shape == (n + 1,) and traj.angular_momentum().shape == (n + 1, 3)
    E = traj.total_energy()
    assert abs(E[-1] - E[0]) < 1e-9 * abs(E[0])                       # rk4 is exact on a parabola
    np.testing.assert_allclose(traj.potential_energy(), 9.81 * traj.x[:, 2])
    np.testing.assert_allclose(traj.linear_momentum()[:, 2], -9.81 * traj.t, atol=1e-12)
    np.testing.assert_allclose(traj.angular_momentum("com"), traj.L)
    np.testing.assert_allclose(traj.angular_momentum(), traj.L + np.cross(traj.x, traj.P))
    np.testing.assert_allclose(traj.angular_momentum([1, 0, 0]), traj.L + np.cross(traj.x - [1, 0, 0], traj.P))
    np.testing.assert_allclose(traj.det_R(), 1, atol=1e-13)


def test_zero_duration_and_record_every():
    X0 = rb.State.at_rest()
    assert len(rb.simulate(BOX, X0, 0.0, 0.1)) == 1
    traj = rb.simulate(BOX, X0, 1.0, 0.01, "euler", record_every=30)
    assert traj.t.tolist() == pytest.approx([0.0, 0.3, 0.6, 0.9, 1.0])


def test_divergence_keeps_the_trajectory():
    # benchmark B (fast spin about the major axis): the slides' Euler overflows
    X0 = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), np.zeros(3), [0.1, 0.1, 50.0])
    with pytest.raises(rb.SimulationDiverged) as info:
        rb.simulate(BOX, X0, 10.0, 1e-3, "euler")
    err = info.value
    assert "diverged at t =" in str(err) and "euler" in str(err)
    traj = err.trajectory
    assert 0 < err.t < 10 and len(traj) == err.step
    assert np.all(np.isfinite(traj.R)) and traj.t[-1] == pytest.approx(err.t - 1e-3)
    with np.errstate(over="ignore"):
        assert traj.orthogonality_error()[-1] > 1e10                    # it was blowing up


def test_nan_force_is_caught():
    scene = rb.Scene(BOX, [rb.PointForce((0, 0, 0), lambda t: [0, 0, 1.0 / (0.5 - t) if t < 0.5 else np.inf])])
    with pytest.raises((rb.SimulationDiverged, ValueError)) as info:
        rb.simulate(scene, rb.State.at_rest(), 1.0, 0.1, "euler")
    assert "finite" in str(info.value) or "diverged" in str(info.value)


@pytest.mark.parametrize("kwargs, match", [
    (dict(dt=0.0), "dt must be > 0"),
    (dict(dt=-0.1), "dt must be > 0"),
    (dict(dt=np.nan), "dt must be finite"),
    (dict(t_end=-1.0), "t_end must be >= 0"),
    (dict(t_end=np.inf), "t_end must be finite"),
    (dict(method="verlet"), "method must be one of"),
    (dict(X0="rest"), "X0 must be a State"),
    (dict(scene="box"), "scene must be a Scene or a RigidBody"),
    (dict(record_every=0), "record_every must be an integer"),
    (dict(t_end=1e6, dt=1e-6), "at most 1e9 steps"),
])
def test_bad_simulate_inputs(kwargs, match):
    args = dict(scene=BOX, X0=rb.State.at_rest(), t_end=1.0, dt=0.1, method="euler")
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        rb.simulate(**args)


def test_methods_registry():
    assert {"euler", "rk4"} <= set(rb.METHODS)
    assert rb.METHODS["euler"].order == 1 and rb.METHODS["rk4"].order == 4


@pytest.mark.parametrize("method", sorted(rb.METHODS))
def test_a_run_leaves_the_scene_as_it_was(method):
    """What a method precomputes lives with the run (the scene's System, built per run), never in the scene."""
    scene = rb.Scene(BOX, [rb.Gravity(), rb.Pivot((0.0, 0.0, -0.05))])
    before = dict(vars(scene))
    X0 = rb.Pivot((0.0, 0.0, -0.05)).state(BOX, np.eye(3), [0.5, 0.0, 10.0])
    for fast in (True, False):
        rb.simulate(scene, X0, 0.05, 0.01, method, fast=fast)
    assert vars(scene).keys() == before.keys() and all(vars(scene)[k] is v for k, v in before.items())


def test_the_system_holds_the_principal_axes_of_the_inertia():
    Q = rb.rotation.rotation_about([1, 2, 3], 0.7)
    full = rb.Scene([BOX, rb.RigidBody(1.0, Q @ np.diag([1.0, 2.0, 3.0]) @ Q.T)])
    sys = full.system()
    A, m = sys.I_axes, sys.I_moments
    np.testing.assert_allclose(A @ (m[:, :, None] * np.swapaxes(A, 1, 2)), full.I_rot, atol=1e-12)
    assert np.all(np.linalg.det(A) > 0)
    np.testing.assert_allclose(np.sort(m[0]), np.sort(np.diag(BOX.I_body)), rtol=1e-15)
    assert np.all(np.diff(m, axis=1) >= 0)           # ascending, as the exact flow's body_kind reads them


def test_import_does_not_import_scipy_integrate():
    """DOP853's table is read at the first adaptive step (tableaus.dop853), not at import."""
    import subprocess
    import sys
    code = ("import sys, numpy as np, rbcourse as rb; assert 'scipy.integrate' not in sys.modules; "
            "rb.simulate(rb.RigidBody.box(1.0, (1, 2, 3)), rb.State.at_rest(), 0.1, 0.1, 'adaptive'); "
            "assert 'scipy.integrate' in sys.modules")
    from pathlib import Path
    subprocess.run([sys.executable, "-c", code], check=True, cwd=Path(__file__).resolve().parents[1])


def test_the_recorded_run_is_returned_without_a_copy():
    """The trajectory's arrays are views of the run's record, preallocated once (driver.py: new_record, which
    simulate.py's run calls)."""
    import importlib
    sim = importlib.import_module("rbcourse.simulate")     # the module (rb.simulate is the function)
    X0 = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), [1.0, 0.0, 0.0], [0.3, 0.2, 1.0])
    blocks = []
    original = sim.new_record

    def kept(*args):
        blocks.append(original(*args))
        return blocks[-1]
    for fast in (True, False):
        traj = rb.simulate(BOX, X0, 1.0, 0.01, "rk4", fast=fast)
        assert len(traj) == 101 and traj.x.base is not None and traj.L.base is not None
    import unittest.mock
    with unittest.mock.patch.object(sim, "new_record", kept):
        traj = rb.simulate(BOX, X0, 1.0, 0.01, "rk4")
    (record,) = blocks
    for got, block in zip((traj.t, traj.x, traj.R, traj.P, traj.L), record):
        assert np.shares_memory(got, block)


def test_pivoted_L_is_converted_in_place_chunk_by_chunk(monkeypatch):
    """L = L_p − (x − p) × P row by row: converting in chunks of 7 rows gives the same bits as all at once."""
    import importlib
    sim = importlib.import_module("rbcourse.simulate")     # the module (rb.simulate is the function)
    pivot = rb.Pivot((0.0, 0.0, -0.05), (0.1, 0.2, 0.3))
    scene = rb.Scene(BOX, [rb.Gravity(), pivot])
    X0 = pivot.state(BOX, rb.rotation.rotation_about([1, 2, 3], 0.4), [0.5, 0.0, 10.0])
    whole = rb.simulate(scene, X0, 0.5, 0.01, "rk4", fast=False)
    monkeypatch.setattr(sim, "_CHUNK", 7)
    chunked = rb.simulate(scene, X0, 0.5, 0.01, "rk4", fast=False)
    np.testing.assert_array_equal(chunked.L, whole.L)
    np.testing.assert_allclose(whole.L[0], X0.L, rtol=1e-12, atol=1e-15)   # L about the centre of mass, as given
    kernel = rb.simulate(scene, X0, 0.5, 0.01, "rk4")              # the float kernel's record, same conversion
    np.testing.assert_allclose(kernel.L, whole.L, rtol=1e-9, atol=1e-12)
