"""rk4 on a scene whose bodies do not act on one another is stepped LANES bodies at a time (engine/stages.py:
rk_stages_lanes, a lane block whose loop runs several bodies at once in vector instructions): the same sums in
the same order as the stage loop over all bodies, so each body's run is the one it has alone, to the bit."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.driver import kernel
from rbcourse.simulate import Run  # noqa: E402 (the module: rb.simulate is the function)
from rbcourse.engine import motion, quaternion, stages, steps
from rbcourse.engine.tableaus import RK4
from rbcourse.examples import Pulse


def _bodies(n):
    """n bodies, every other one a box and the others with inertia tensors that are not diagonal (principal axes
    turned: all nine entries of I⁻¹_body read), each with its own random motion."""
    rng = np.random.default_rng(4)
    bodies = list(rb.RigidBody.boxes(rng.uniform(0.5, 2.0, n), rng.uniform(0.05, 0.3, (n, 3))))
    for i in range(1, n, 2):
        Q, moments = rb.exp_so3(rng.normal(size=3)), np.sort(rng.uniform(0.5, 1.5, 3))
        moments[2] = min(moments[2], moments[0] + moments[1] - 0.01)
        bodies[i] = rb.RigidBody(bodies[i].mass, Q @ np.diag(moments) @ Q.T)
    X = [rb.State.from_velocities(b, rng.normal(size=3), rb.exp_so3(rng.normal(size=3)), rng.normal(size=3),
                                  rng.normal(0, 3, size=3)) for b in bodies]
    return bodies, X


ALIKE = {"free": [], "gravity": [rb.Gravity()],
         "every effect": [rb.Gravity(), rb.LinearDrag(0.1), rb.AngularDrag(0.01),
                          rb.PointForce((0.01, 0.02, 0.0), Pulse((0, 0, 3.0), 0.0, 0.05), frame="body"),
                          rb.Spring((0.01, 0, 0), (0, 0, 1.0), stiffness=5.0, damping=0.1, rest_length=0.2)]}
N = stages.LANES + 6            # a full block and a part of one


@pytest.mark.parametrize("name", list(ALIKE))
def test_many_alike_bodies_step_as_each_one_alone(name):
    bodies, X = _bodies(N)
    scene = rb.Scene(bodies, ALIKE[name])
    assert motion.alike(scene.compile().system)
    together = rb.simulate(scene, rb.State.stack(X), 0.2, 1e-2, "rk4")
    for i in (0, stages.LANES - 1, stages.LANES, N - 1):
        alone = rb.simulate(rb.Scene(bodies[i], ALIKE[name]), X[i], 0.2, 1e-2, "rk4")
        for a, b in ((together.x[:, i], alone.x), (together.R[:, i], alone.R), (together.P[:, i], alone.P),
                     (together.L[:, i], alone.L)):
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("name", list(ALIKE))
def test_the_lane_block_gives_the_stage_loops_numbers_to_the_bit(name):
    """One rk4 step of the N bodies (the run's own arrays and forces over time: simulate.Run) by the lane block
    (K holds one: lane_scratch) and by the stage loop over all bodies (K without it): the same bits, q
    normalised or not, -0 and +0 told apart."""
    bodies, X = _bodies(N)
    scene = rb.Scene(bodies, ALIKE[name])
    run = Run(kernel(True), scene, scene.compile(), rb.METHODS["rk4"], scene.to_engine(rb.State.stack(X)), 1, 1e-2, 1)
    assert run.K.shape[0] == RK4.stages + stages.lane_scratch(N)
    values = run.values(np.zeros(1), 1e-2)
    values = None if values is None else values[0]           # None: a free scene evaluates no force
    for normalize in (False, True):
        outs = []
        K = np.full_like(run.K, np.nan)
        assert stages.lanes_fit(run.sys, RK4.A, RK4.b, run.Y, K) and not stages.lanes_fit(
            run.sys, RK4.A, RK4.b, run.Y, K[:RK4.stages])
        out = np.full_like(run.Y, np.nan)
        stages.rk_stages_lanes(run.sys, values, RK4.A, RK4.b, float(RK4.den), run.Y, out, 1e-2, K, normalize)
        outs.append(out)
        out = np.full_like(run.Y, np.nan)
        stages.rk_stages(quaternion.rates_quat, run.sys, values, RK4.A, RK4.b, float(RK4.den), run.Y, out, 1e-2,
                         K[:RK4.stages], np.empty_like(run.Y), run.w, 0, normalize)
        outs.append(out)
        assert np.isfinite(outs[0]).all()
        assert np.array_equal(outs[0].view(np.int64), outs[1].view(np.int64))


def test_a_lane_block_fits_in_the_stages_work_for_any_number_of_bodies():
    for n in (1, 2, 13, stages.LANES, 10**4):
        assert (RK4.stages + stages.lane_scratch(n)) * n * 13 >= stages.LANE_BLOCK + RK4.stages * n * 13


def test_bodies_that_act_on_one_another_are_not_alike():
    bodies, X = _bodies(3)
    joined = rb.Scene(bodies, [rb.Spring((0, 0, 0), stiffness=1.0, body=0, other_body=1)])
    one = rb.Scene(bodies, [rb.Gravity(body=[1])])
    assert not motion.alike(joined.compile().system) and not motion.alike(one.compile().system)
    traj = rb.simulate(joined, rb.State.stack(X), 0.1, 1e-2, "rk4")        # the stage loop over all bodies
    assert np.isfinite(traj.x).all()


def test_only_a_chained_table_is_stepped_in_lanes():
    """step_block takes each stage from the one before alone (rk4's table); a table with other terms (Kutta's
    3/8 rule) keeps the stage loop over all bodies, and gives each body's run alone there too, to the bit."""
    assert stages.chained(RK4.A)
    three_eighths = np.array([[0, 0, 0, 0], [1 / 3, 0, 0, 0], [-1 / 3, 1.0, 0, 0], [1.0, -1.0, 1.0, 0]])
    assert not stages.chained(three_eighths)
    bodies, X = _bodies(N)
    scene = rb.Scene(bodies, ALIKE["gravity"])
    run = Run(kernel(True), scene, scene.compile(), rb.METHODS["rk4"], scene.to_engine(rb.State.stack(X)), 1, 1e-2, 1)
    values = run.values(np.zeros(1), 1e-2)[0]
    b = np.array([1.0, 3.0, 3.0, 1.0])
    outs = []
    for K in (run.K, run.K[:RK4.stages]):      # room for a lane block, or none: the same loop all the same
        out = np.full_like(run.Y, np.nan)
        steps.explicit_quat_step(0, 0, 0, three_eighths, b, 8.0, np.zeros(0), run.sys, values, run.Y, out, 1e-2,
                                 np.full_like(K, np.nan), np.empty_like(run.Y), run.w)
        outs.append(out)
    assert np.isfinite(outs[0]).all()
    assert np.array_equal(outs[0].view(np.int64), outs[1].view(np.int64))
