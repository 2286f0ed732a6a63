"""Impulses inside the compiled loop (engine/kicks.py, run.split_step): the loop walks a sorted table of kicks and
makes a step that holds kicks as the driver makes it in Python (simulate._python_step, run with
Run.kicks_in_loop = False): the same pieces, the same kicks, in the same order — the same numbers, bit for bit."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.simulate import Run
from rbcourse.driver import encode

BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
BALL = rb.RigidBody.sphere(0.7, 0.1)
R0 = rb.rotation.rotation_about([1, 2, 0.5], 0.7)
X_BOX = rb.State.from_velocities(BOX, [0, 0, 1.0], R0, [0.1, -0.2, 0.3], [0.3, 4.0, 0.2])
H = 1e-2


def kick(b, J, t, **kw):
    return rb.Impulse(b, J, t, **kw)


def on_time():
    """Kicks in one step at two times (two at one of them), at t = 0, at t_end = 0.2, on the boundary 0.07 (and
    within rounding of it), and alone in a step."""
    return [kick((0.1, 0.05, 0), (0, 0.2, 0.3), 0.0537), kick((0, 0.1, 0.02), (0.1, 0, 0), 0.0537),
            kick((0.15, 0, 0), (0, 0, -0.4), 0.0571), kick((0.1, 0.05, 0), (0, 0.2, 0.3), 0.0),
            kick((0.1, 0, 0), (0, 0, 1.0), 0.2), kick((0, 0.1, 0), (1.0, 0, 0), 0.07),
            kick((0, 0.1, 0), (0, 1.0, 0), 0.07 + 1e-13), kick((0, 0, 0.025), (0.3, 0.1, 0), 0.1502)]


def two_bodies():
    box = rb.State.from_velocities(BOX, [0, 0, 0.05], R0 @ R0.T, [0.2, 0, 0], [0, 0, 1.0])
    ball = rb.State.from_velocities(BALL, [1.0, 0, 0.3], np.eye(3), [0, 0.1, 0], [1.0, 0.5, -2.0])
    effects = [rb.Gravity(), rb.Ground(0.0, 0.3, 0.5), kick((0.1, 0, 0), (0, 0, -1.0), 0.0333, body=0),
               kick((0, 0.1, 0), (0.2, 0, 0.5), 0.0333), kick((0, 0, 0.05), (0, 0.1, 0.2), 0.071, body=[1, 0]),
               kick((0, 0, 0.05), (0, -0.3, 0.1), 0.071, body=1), kick((0, 0, 0), (0, 0, 0.2), 0.1)]
    return rb.Scene([BOX, BALL], effects), rb.State.stack([box, ball])


def both(scene, X0, t_end, method, monkeypatch, **kw):
    """The run with its kicks in the loop, and the same run with each step that holds kicks made in Python."""
    looped = rb.simulate(scene, X0, t_end, H, method, on_divergence="stop", **kw)
    with monkeypatch.context() as m:
        m.setattr(Run, "kicks_in_loop", False)
        python = rb.simulate(scene, X0, t_end, H, method, on_divergence="stop", **kw)
    return looped, python


def assert_same(a, b):
    for name in ("t", "x", "R", "P", "L"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert str(a.divergence) == str(b.divergence)


@pytest.mark.parametrize("method", list(rb.METHODS))
def test_the_loop_kicks_as_the_python_step_does_bit_for_bit(method, monkeypatch):
    scene = rb.Scene(BOX, [rb.Gravity()] + on_time())
    looped, python = both(scene, X_BOX, 0.2, method, monkeypatch, record_every=3)
    assert_same(looped, python)
    assert looped.t[-1] == 0.2 and looped.P[-1, 2] - python.P[-1, 2] == 0


@pytest.mark.parametrize("method", ["euler", "rk4", "adaptive", "quaternion_euler", "implicit_midpoint"])
def test_two_bodies_on_a_ground_kicked_alike(method, monkeypatch):
    scene, X0 = two_bodies()
    assert_same(*both(scene, X0, 0.15, method, monkeypatch))


@pytest.mark.parametrize("method", ["euler", "rk4", "splitting"])
def test_forces_over_time_are_taken_at_the_pieces_stage_times(method, monkeypatch):
    """A force f(t) and a pulse: a piece of a split step reads its forces at its own stage times."""
    push = rb.PointForce((0.1, 0, 0), lambda t: np.array([0.0, 0.3 * np.sin(7 * t), 1.0 + t]))
    pulse = rb.PointForce((0, 0.1, 0), rb.Pulse((0, 0, 5.0), 0.02, 0.11))
    scene = rb.Scene(BOX, [push, pulse] + on_time())
    looped, python = both(scene, X_BOX, 0.2, method, monkeypatch)
    assert_same(looped, python)


def test_a_pivoted_body_and_the_engine_run_as_python(monkeypatch):
    pivot = rb.Pivot((0.01, 0.02, -0.05), (0.2, 0, 1.0))
    scene = rb.Scene(BOX, [pivot, rb.Gravity(), kick((0.15, 0.1, 0), (0.1, 0.3, -0.2), 0.0237),
                           kick((0.15, 0.1, 0), (0.1, 0.3, -0.2), 0.06)])
    X0 = pivot.state(BOX, R0, [1.0, -2.0, 3.0])
    assert_same(*both(scene, X0, 0.1, "rk4", monkeypatch))
    assert_same(*both(scene, X0, 0.1, "euler", monkeypatch, fast=False))


def test_many_kicks_each_at_its_time(monkeypatch):
    rng = np.random.default_rng(7)
    times = np.r_[rng.uniform(0, 2.0, 400), np.arange(0, 2.0, 0.05)]          # inside steps, and on boundaries
    J = rng.normal(scale=0.01, size=(len(times), 3))
    kicks = [kick(tuple(rng.uniform(-0.1, 0.1, 3)), tuple(j), float(t)) for j, t in zip(J, times)]
    scene = rb.Scene(BOX, kicks)
    looped, python = both(scene, X_BOX, 2.0, "rk4", monkeypatch)
    assert_same(looped, python)
    np.testing.assert_allclose(looped.P[-1], X_BOX.P + J.sum(axis=0), rtol=0, atol=1e-14)   # a free body: ΔP = ΣJ


def test_kicks_of_one_time_on_one_body_add_in_their_order():
    """(P + J₁) + J₂ + J₃ in the order the scene gives them (a float sum depends on it: 1 + 1 + 1e16 is not
    1e16 + 1 + 1); kicks of an earlier time first, wherever they are listed."""
    for order in ([1.0, 1.0, 1e16], [1e16, 1.0, 1.0]):
        scene = rb.Scene(BALL, [kick((0, 0, 0), (-5.0, 0, 0), 0.0512)] +
                         [kick((0, 0, 0), (j, 0, 0), 0.0537) for j in order])
        traj = rb.simulate(scene, rb.State.at_rest(), 0.1, H, "rk4")
        assert traj.P[-1, 0] == ((-5.0 + order[0]) + order[1]) + order[2]


def test_a_kicks_step_and_the_pieces_of_the_steps_it_splits():
    from rbcourse.engine import kicks as K
    step_of = getattr(K.kick_step, "py_func", K.kick_step)
    assert step_of(0.0537, 20, H) == (5, 0.0537) and step_of(0.0, 20, H) == (0, 0.0)
    assert step_of(0.07 + 1e-13, 20, H) == (7, 7 * H)                # on a boundary, to rounding: before step 7
    assert step_of(0.2, 20, H) == (19, 20 * H)                       # at t_end: at the end of the last step
    times = np.array([0.0, 0.0537, 0.0537, 0.0571, 0.07, 0.2])
    table = K.table(times, np.arange(6), np.zeros(6, int), np.zeros((6, 3)), np.zeros((6, 3)), np.zeros((1, 13)))
    # step 0: a kick at its start, then the whole step; step 5: three pieces around two times; 7 and 19: whole
    starts, sizes = K.pieces(table, 0, 20, 20, H)
    assert starts.tolist() == [0.05, 0.0537, 0.0571]
    assert sizes.tolist() == [0.0537 - 0.05, 0.0571 - 0.0537, 0.06 - 0.0571]
    assert K.pieces(table, 5, 6, 20, H)[0].tolist() == [0.05, 0.0537, 0.0571]
    assert len(K.pieces(table, 6, 20, 20, H)[0]) == len(K.pieces(table, 0, 5, 20, H)[0]) == 0


@pytest.mark.parametrize("fast", [True, False])
def test_a_kicks_state_is_laid_out_as_the_driver_lays_out_a_state(fast):
    """The loop's encode (engine/run.py: S -> the method's layout) gives driver.encode's numbers, bit for bit, in
    every branch of Shepperd's method and with q's sign turned."""
    from rbcourse.driver import kernel
    run = kernel(fast).run
    rng = np.random.default_rng(3)
    qs = np.r_[rng.normal(size=(60, 4)), np.eye(4), -np.eye(4), [[1e-9, 1, 1e-9, 0], [-0.5, 0.5, -0.5, 0.5]]]
    R = rb.rotation.matrix_from_quat(qs)
    X = rb.State.unchecked(rng.normal(size=(len(qs), 3)), R, rng.normal(size=(len(qs), 3)),
                           rng.normal(size=(len(qs), 3)))
    S = encode("matrix", X)
    for layout in ("matrix", "quat", "quat_world"):
        Y = np.empty_like(encode(layout, X))
        run.ENCODE[layout](S, Y)
        np.testing.assert_array_equal(Y, encode(layout, X), err_msg=layout)


def test_the_throughput_report_prices_an_impulse_beside_a_step(monkeypatch):
    """The report's rows (bench/impulse_rows.py): a step's cost (stubbed here: timing is not tested), an impulse's
    inside a step and on a boundary, each in µs and in steps."""
    from rbcourse.bench import impulse_rows
    monkeypatch.setattr(impulse_rows, "seconds_per_step", lambda *a, **k: (1e-7, "compiled: stub", 8))
    lines = impulse_rows.impulse_table(quick=True, impulses=40)
    rows = [[cell.strip() for cell in line.split("|")[1:-1]] for line in lines if line.startswith("| a")]
    assert [r[0] for r in rows] == ["a compiled step", "an impulse inside a step (the step split at it)",
                                    "an impulse on a step boundary"]
    assert rows[0][1:3] == ["0.1", "1"]
    for r in rows[1:]:
        assert float(r[2]) == pytest.approx(float(r[1]) / 0.1, rel=0.05, abs=0.01) and r[4] in ("yes", "no")
