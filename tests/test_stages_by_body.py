"""rk4 on a scene whose bodies do not act on one another is stepped body by body (engine/stages.py:
rk_stages_by_body, each body's stages in cache): the same sums in the same order as the stage loop over all
bodies, so each body's run is the one it has alone, to the bit."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.engine import motion
from rbcourse.workbook.examples import Pulse


def _bodies(n):
    rng = np.random.default_rng(4)
    bodies = list(rb.RigidBody.boxes(rng.uniform(0.5, 2.0, n), rng.uniform(0.05, 0.3, (n, 3))))
    X = [rb.State.from_velocities(b, rng.normal(size=3), rb.exp_so3(rng.normal(size=3)), rng.normal(size=3),
                                  rng.normal(0, 3, size=3)) for b in bodies]
    return bodies, X


ALIKE = {"free": [], "gravity": [rb.Gravity()],
         "every effect": [rb.Gravity(), rb.LinearDrag(0.1), rb.AngularDrag(0.01),
                          rb.PointForce((0.01, 0.02, 0.0), Pulse((0, 0, 3.0), 0.0, 0.05), frame="body"),
                          rb.Spring((0.01, 0, 0), (0, 0, 1.0), stiffness=5.0, damping=0.1, rest_length=0.2)]}


@pytest.mark.parametrize("name", list(ALIKE))
def test_many_alike_bodies_step_as_each_one_alone(name):
    bodies, X = _bodies(7)
    scene = rb.Scene(bodies, ALIKE[name])
    assert motion.alike(scene.compile().system)
    together = rb.simulate(scene, rb.State.stack(X), 0.2, 1e-2, "rk4")
    for i in (0, 3, 6):
        alone = rb.simulate(rb.Scene(bodies[i], ALIKE[name]), X[i], 0.2, 1e-2, "rk4")
        for a, b in ((together.x[:, i], alone.x), (together.R[:, i], alone.R), (together.P[:, i], alone.P),
                     (together.L[:, i], alone.L)):
            np.testing.assert_array_equal(a, b)


def test_bodies_that_act_on_one_another_are_not_alike():
    bodies, X = _bodies(3)
    joined = rb.Scene(bodies, [rb.Spring((0, 0, 0), stiffness=1.0, body=0, other_body=1)])
    one = rb.Scene(bodies, [rb.Gravity(body=[1])])
    assert not motion.alike(joined.compile().system) and not motion.alike(one.compile().system)
    traj = rb.simulate(joined, rb.State.stack(X), 0.1, 1e-2, "rk4")        # the stage loop over all bodies
    assert np.isfinite(traj.x).all()
