"""Contacts inside the compiled loop (engine/run.py: loop, engine/contact.py: contacts) against the way they
were solved before, from Python between steps: one step of the method on the scene without its ground, then
Ground.resolve (the same solver run as Python) — step after step, for each family of methods and each of
their layouts, one body and several."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.rotation import exp_so3

BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
DT, STEPS = 2e-3, 150


def _case(n):
    rng = np.random.default_rng(11)
    bodies = [BOX, rb.RigidBody.cylinder(2.0, 0.1, 0.3), rb.RigidBody.sphere(0.5, 0.1)][:n]
    states = [rb.State.from_velocities(b, [0.4 * i, 0, 0.2], exp_so3(rng.normal(size=3) * 0.5),
                                       [0.3, 0, -2.0], rng.normal(size=3) * 3) for i, b in enumerate(bodies)]
    return bodies, rb.State.stack(states)


def _by_steps(bodies, X, ground, method):
    """The contacts solved between steps, from Python (Ground.resolve after each one-step run)."""
    smooth, full = rb.Scene(bodies, [rb.Gravity()]), rb.Scene(bodies, [rb.Gravity(), ground])
    out = [X]
    for _ in range(STEPS):
        X = rb.simulate(smooth, X, DT, DT, method).final
        X = ground.resolve(full, X, dt=DT)
        out.append(X)
    return out


@pytest.mark.parametrize("method", ["euler", "euler_project", "quaternion_euler", "rk4", "symplectic_euler",
                                    "implicit_midpoint", "exact_splitting", "rkmk4"])
@pytest.mark.parametrize("n", [1, 3])
def test_the_compiled_loop_solves_contacts_as_between_steps(method, n):
    bodies, X0 = _case(n)
    ground = rb.Ground(0.0, restitution=0.4, friction=0.6)
    traj = rb.simulate(rb.Scene(bodies, [rb.Gravity(), ground]), X0, STEPS * DT, DT, method)
    ref = _by_steps(bodies, X0, ground, method)
    Pz = np.array([np.reshape(X.P, (-1, 3))[:, 2] for X in ref])
    mg = 9.81 * DT * np.array([b.mass for b in bodies])
    hit = [k for k in range(1, STEPS + 1) if not np.allclose(Pz[k], Pz[k - 1] - mg, rtol=0, atol=1e-12)]
    assert hit, "the bodies never touched the ground: the test tests nothing"
    exact = rb.METHODS[method].kernel.layout == "matrix"
    for k in range(STEPS + 1):
        for a, b in ((traj.x[k], ref[k].x), (traj.R[k], ref[k].R), (traj.P[k], ref[k].P), (traj.L[k], ref[k].L)):
            if exact:
                np.testing.assert_array_equal(a, b.reshape(a.shape))      # the slides' state: the same operations
            else:
                np.testing.assert_allclose(a, b.reshape(a.shape), rtol=0, atol=1e-9)   # q re-encoded: rounding


def test_adaptive_with_a_ground_stays_above_it_and_gains_no_energy():
    bodies, X0 = _case(3)
    traj = rb.simulate(rb.Scene(bodies, [rb.Gravity(), rb.Ground(0.0, 0.4, 0.6)]), X0, 0.6, DT, "adaptive")
    E = traj.total_energy()
    assert np.all(np.diff(E, axis=0) <= 1e-9 * np.abs(E[0]) + 1e-12)
    assert traj.x[:, :, 2].min() > 0.0
