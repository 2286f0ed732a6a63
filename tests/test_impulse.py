"""Impulses (impulse.py): ΔP = J, ΔL = (r − c) × J at the start of the step that holds the kick's time."""
import numpy as np

import rbcourse as rb

BOX = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))


def test_impulse_kicks_at_its_time():
    scene = rb.Scene(BOX, [rb.Impulse((0.15, 0.1, 0.025), (0, 0, 0.2), time=0.5)])
    traj = rb.simulate(scene, rb.State.at_rest(), 1.0, 0.01, "rk4")
    before, after = traj.t < 0.5 - 1e-12, traj.t > 0.5 + 1e-12
    assert np.all(traj.P[before] == 0) and np.all(traj.L[before] == 0)
    np.testing.assert_allclose(traj.P[after], [[0, 0, 0.2]] * after.sum())
    np.testing.assert_allclose(traj.L[after][0], np.cross([0.15, 0.1, 0.025], [0, 0, 0.2]), atol=1e-9)


def test_no_kick_due_leaves_the_state_as_it_is_and_two_kicks_add_up():
    kicks = [rb.Impulse((0.1, 0, 0), (0, 1.0, 0), time=0.5), rb.Impulse((0, 0.1, 0), (0, 0, 2.0), time=0.5)]
    scene = rb.Scene(BOX, kicks)
    X = scene.batch(rb.State.at_rest())
    assert scene.apply_impulses(0.0, 0.5, X) is X                         # [t0, t1) does not hold 0.5
    Y = scene.apply_impulses(0.5, 0.51, X)
    np.testing.assert_array_equal(Y.P[0], [0, 1.0, 2.0])
    np.testing.assert_allclose(Y.L[0], np.cross([0.1, 0, 0], [0, 1.0, 0]) + np.cross([0, 0.1, 0], [0, 0, 2.0]))


def test_a_kick_on_a_pivoted_body_turns_it_about_the_pivot():
    p, b, r = np.array([0, 0, 1.0]), np.array([0, 0, -0.05]), np.array([0.15, 0, 0])
    pivot = rb.Pivot(b, p)
    J = np.array([0, 0.3, 0])
    scene = rb.Scene(BOX, [pivot, rb.Impulse(r, J, time=0.0)])
    traj = rb.simulate(scene, pivot.state(BOX, np.eye(3), [0, 0, 0]), 0.01, 1e-3, "rk4")
    # ΔL_p = (r_world − p) × J with r_world = x + R b_r = p − b + r: about the pivot, not the centre of mass
    np.testing.assert_allclose(traj.angular_momentum(about=p)[1], np.cross(r - b, J), atol=1e-15)
    np.testing.assert_allclose(traj.body_point(b), np.broadcast_to(p, (len(traj), 3)), atol=1e-15)   # b stays at p


def test_the_kick_is_the_engines_and_runs_as_the_run_does(monkeypatch):
    """The kick is engine/motion.py's (one formula): a run as Python (fast=False) kicks with the interpreted
    engine, never the compiled one, and both give the same numbers; a pivoted body's x and P follow."""
    from rbcourse.engine import interpreted, motion
    p, b = np.array([0.2, 0, 1.0]), np.array([0.01, 0.02, -0.05])
    pivot = rb.Pivot(b, p)
    scene = rb.Scene(BOX, [pivot, rb.Gravity(), rb.Impulse((0.15, 0.1, 0), (0.1, 0.3, -0.2), time=0.02)])
    X0 = pivot.state(BOX, rb.rotation.rotation_about([1, 1, 0], 0.4), [1.0, -2.0, 3.0])
    fast = rb.simulate(scene, X0, 0.05, 1e-3, "rk4")
    kicks = []
    python = interpreted.module("motion")
    real = python.kick
    for module in (python, interpreted.module("kicks")):         # the loop's kicks (engine/kicks.py), run as Python
        monkeypatch.setattr(module, "kick", lambda *a: kicks.append(a[2]) or real(*a))
    monkeypatch.setattr(motion, "kick", lambda *a: (_ for _ in ()).throw(AssertionError("compiled kick in a Python run")))
    slow = rb.simulate(scene, X0, 0.05, 1e-3, "rk4", fast=False)
    assert kicks == [0]
    for a, c in ((fast.x, slow.x), (fast.R, slow.R), (fast.P, slow.P), (fast.L, slow.L)):
        np.testing.assert_allclose(a, c, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(slow.body_point(b), np.broadcast_to(p, (len(slow), 3)), atol=1e-14)
    k = np.searchsorted(slow.t, 0.02)
    assert np.abs(slow.P[k + 1] - slow.P[k]).max() > 0.05          # the kick is there
