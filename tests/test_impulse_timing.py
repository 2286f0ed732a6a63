"""Impulses on time (simulate.py: kick_plan, _python_step): a kick between two steps is applied at its time
(the step split there), one at t_end before the last state is recorded, one on a step boundary at it."""
import numpy as np
import pytest

import rbcourse as rb

BALL = rb.RigidBody.sphere(1.0, 0.1)
METHODS = list(rb.METHODS)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("t_kick, x_end", [(0.3, 0.7), (0.35, 0.65), (0.0, 1.0), (0.97, 0.03), (1e-3, 0.999)])
def test_a_kick_is_applied_at_its_time_by_every_method(method, t_kick, x_end):
    scene = rb.Scene(BALL, [rb.Impulse((0, 0, 0), (1, 0, 0), t_kick)])
    traj = rb.simulate(scene, rb.State.at_rest(), 1.0, 0.1, method)
    assert traj.t[-1] == 1.0 and len(traj.t) == 11
    np.testing.assert_allclose(traj.x[-1], [x_end, 0, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(traj.P[-1], [1.0, 0, 0], rtol=0, atol=1e-15)
    k = int(np.floor(t_kick / 0.1 + 1e-9))
    assert np.all(traj.P[:k + (t_kick == 0), 0] == (1.0 if t_kick == 0 else 0.0)) or t_kick == 0


@pytest.mark.parametrize("method", ["euler", "rk4", "adaptive", "exact_splitting"])
def test_a_kick_at_t_end_is_in_the_last_state(method):
    scene = rb.Scene(BALL, [rb.Impulse((0, 0.1, 0), (0, 0, 2.0), 1.0)])
    traj = rb.simulate(scene, rb.State.at_rest(), 1.0, 0.1, method)
    np.testing.assert_allclose(traj.P[-1], [0, 0, 2.0])
    np.testing.assert_allclose(traj.L[-1], np.cross([0, 0.1, 0], [0, 0, 2.0]))
    np.testing.assert_array_equal(traj.x[-1], [0, 0, 0])          # it moved nothing yet
    assert np.all(traj.P[:-1] == 0)


def test_a_kick_at_t_end_is_recorded_with_record_every():
    scene = rb.Scene(BALL, [rb.Impulse((0, 0, 0), (0, 0, 2.0), 1.0)])
    traj = rb.simulate(scene, rb.State.at_rest(), 1.0, 0.01, "rk4", record_every=30)
    assert traj.t[-1] == 1.0
    np.testing.assert_allclose(traj.P[-1], [0, 0, 2.0])


def test_kicks_in_one_step_are_applied_in_time_order_with_forces_between():
    """Two kicks inside one step, under gravity: each at its own time (the exact answer, rk4 exact on it)."""
    g, J1, J2 = 9.81, 1.0, 0.5
    scene = rb.Scene(BALL, [rb.Gravity(g), rb.Impulse((0, 0, 0), (0, 0, J2), 0.27),
                            rb.Impulse((0, 0, 0), (0, 0, J1), 0.23)])
    traj = rb.simulate(scene, rb.State.at_rest((0, 0, 10.0)), 0.5, 0.1, "rk4")
    z = 10.0 - 0.5 * g * 0.5**2 + J1 * (0.5 - 0.23) + J2 * (0.5 - 0.27)
    np.testing.assert_allclose(traj.x[-1, 2], z, rtol=0, atol=1e-12)


def test_a_kick_in_a_scene_with_a_ground_and_a_force_over_time():
    box = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    scene = rb.Scene(box, [rb.Gravity(), rb.Ground(0.0, 0.0, 0.5), rb.PointForce((0, 0, 0), rb.Pulse((0, 0, 5.0), 0, 0.2)),
                           rb.Impulse((0.1, 0, 0), (0, 0, 3.0), 0.305)])
    traj = rb.simulate(scene, rb.State.at_rest((0, 0, 0.025)), 1.0, 1e-2, "rk4")
    vz = traj.velocity()[:, 2]
    assert np.all(vz[:30] <= 1e-12) and vz[31] > 1.0                  # resting until the kick in step 30, then up
    assert traj.x[:, 2].min() >= 0.025 - 1e-9


def test_a_kick_in_a_run_of_no_step_is_in_its_one_state():
    traj = rb.simulate(rb.Scene(BALL, [rb.Impulse((0, 0, 0), (1, 0, 0), 0.0)]), rb.State.at_rest(), 0.0, 0.1)
    assert len(traj.t) == 1
    np.testing.assert_array_equal(traj.P[0], [1.0, 0, 0])
