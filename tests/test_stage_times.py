"""Forces given as functions f(t) are evaluated at the stages' times t + c h; a stage at the step's end
(c = 1) sees the force as it acted during the step (its left limit), so a push that stops on a step
boundary keeps a Runge–Kutta method at its order (the slides' pushed box: the push stops at t = 0.1 s)."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.engine.profiles import fill_profiles
from rbcourse.forcing import force_values, stage_times
from rbcourse.examples import pushed_box


def test_the_end_stage_takes_the_left_limit():
    t = stage_times(np.array([[0.0], [0.08]]), np.array([[0.0, 0.5, 1.0]]), 0.02)
    assert t[1, 0] == 0.08 and t[1, 1] == 0.08 + 0.5 * 0.02
    assert t[1, 2] < 0.1 and t[1, 2] == np.nextafter(0.08 + 0.02, -np.inf)


def test_a_pulse_that_stops_on_a_step_boundary_acts_over_the_whole_last_step():
    ex = pushed_box()
    push = next(e for e in ex.scene.effects if isinstance(e, rb.PointForce) and callable(e.force))
    sys = ex.scene.compile().system                                   # the push is data: the kernel evaluates it
    fill = lambda times, values: fill_profiles(sys, times, values)    # noqa: E731
    v = force_values([push], [0.0, 0.5, 0.5, 1.0], 0.02, 0, 6, fill)  # steps [0, 0.02) … [0.1, 0.12)
    on = np.abs(v[:, :, 0]).max(axis=-1) > 0
    assert on[:5].all() and not on[5].any()                          # every stage of the first 5 steps, none after


@pytest.mark.parametrize("method, order", [("rk4", 4), ("exact_splitting", 4), ("splitting", 2)])
def test_the_pushed_box_converges_at_the_methods_order(method, order):
    ex = pushed_box()
    T = 2.0
    ref = rb.simulate(ex.scene, ex.X0, T, 0.02 / 64, "rk4")
    errors = [float(rb.rotation_angle(ref.R[-1], rb.simulate(ex.scene, ex.X0, T, dt, method).R[-1]))
              for dt in (0.01, 0.005)]
    measured = np.log2(errors[0] / errors[1])
    assert measured > order - 0.4, (method, errors, measured)
