"""Every method: its measured order of convergence, and every invariant METHODS claims for it."""
import numpy as np
import pytest

import rbcourse as rb

FIXED = [m for m in rb.METHODS if "rtol" not in rb.METHODS[m].options]


def _forced_problem():
    """A smooth problem with forces and torques: a full-inertia body on a damped spring, under gravity,
    pushed at a body point, with angular drag."""
    Q = rb.rotation.rotation_about([1, 2, 3], 0.6)
    body = rb.RigidBody(1.3, Q @ np.diag([0.02, 0.03, 0.04]) @ Q.T)
    scene = rb.Scene(body, [rb.Gravity(), rb.Spring((0.1, 0.05, 0.0), (0, 0, 1.0), stiffness=20, damping=0.3),
                            rb.PointForce((0, 0.1, 0), (0.1, 0.2, 0.3), frame="body"), rb.AngularDrag(0.001)])
    X0 = rb.State.from_velocities(body, [0.1, 0, 0.8], rb.rotation.rotation_about([1, 2, 3], 0.4), [0.2, 0, 0.1], [1, -2, 3])
    return scene, X0


def _pivot_problem():
    body = rb.RigidBody.box(1.0, (0.2, 0.1, 0.05))
    pivot = rb.Pivot((0.02, 0.01, -0.1))
    scene = rb.Scene(body, [rb.Gravity(), pivot])
    return scene, pivot.state(body, rb.rotation.rotation_about([1, 0.3, 0], 0.5), [0.5, -1, 3])


def _error(traj, ref):
    return (rb.rotation_angle(ref.R[-1], traj.R[-1]) + np.abs(traj.x[-1] - ref.x[-1]).max()
            + np.abs(traj.L[-1] - ref.L[-1]).max())


DTS = {1: [0.004, 0.002, 0.001], 2: [0.02, 0.01, 0.005], 4: [0.04, 0.02, 0.01]}


@pytest.mark.parametrize("problem", [_forced_problem, _pivot_problem], ids=["forced", "pivot"])
@pytest.mark.parametrize("method", FIXED)
def test_measured_order_matches_the_claim(problem, method):
    scene, X0 = problem()
    T = 0.4
    ref = rb.simulate(scene, X0, T, T, "adaptive", rtol=1e-13, atol=1e-15, fast=False)
    claim = rb.METHODS[method].order
    dts = DTS[claim]
    errors = [_error(rb.simulate(scene, X0, T, dt, method, fast=False), ref) for dt in dts]
    slope = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert abs(slope - claim) < 0.3, f"{method}: measured order {slope:.2f}, claimed {claim} (errors {errors})"


def test_adaptive_error_follows_its_tolerance():
    scene, X0 = _forced_problem()
    ref = rb.simulate(scene, X0, 0.4, 1e-4, "rk4", fast=False)
    errors = [_error(rb.simulate(scene, X0, 0.4, 0.4, "adaptive", rtol=r, atol=r * 1e-2), ref) for r in (1e-5, 1e-7, 1e-9)]
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 1e-7 and errors[0] < 1e-3


def _free_body():
    Q = rb.rotation.rotation_about([0.3, -1, 2], 1.1)
    body = rb.RigidBody(2.0, Q @ np.diag([0.01, 0.025, 0.03]) @ Q.T)
    X0 = rb.State.from_velocities(body, [1, 2, 3], rb.rotation.rotation_about([1, 1, 0], 0.3), [0.5, 0, 0], [3, -4, 5])
    return body, X0


@pytest.mark.parametrize("method", sorted(rb.METHODS))
@pytest.mark.parametrize("fast", [True, False], ids=["compiled", "as-python"])
def test_claimed_invariants_hold_for_a_free_body(method, fast):
    body, X0 = _free_body()
    traj = rb.simulate(body, X0, 2.0, 0.01, method, fast=fast)
    keeps = rb.METHODS[method].keeps
    L0 = traj.angular_momentum()[0]
    if "SO(3)" in keeps:
        assert traj.orthogonality_error().max() < 1e-12
    else:
        assert traj.orthogonality_error().max() > 1e-6          # the slides' Euler leaves SO(3)
    if "L" in keeps:
        assert np.abs(traj.angular_momentum() - L0).max() < 1e-12 * np.linalg.norm(L0)
    if "|L|" in keeps:
        norms = np.linalg.norm(traj.L, axis=1)
        assert np.ptp(norms) < 1e-12 * norms[0]
    E = traj.kinetic_energy()
    if "energy" in keeps:
        assert np.ptp(E) < 1e-12 * E[0]
    elif method != "adaptive":
        assert np.ptp(E) > 1e-12 * E[0]                          # a claim not made is not kept either
    np.testing.assert_allclose(traj.P, np.broadcast_to(X0.P, traj.P.shape), rtol=0, atol=1e-15)


def test_metadata_is_complete():
    required = {"euler", "euler_project", "quaternion_euler", "symplectic_euler", "implicit_gyro", "implicit_midpoint",
                "splitting", "rk4", "rkmk4", "adaptive", "exact_splitting"}
    assert required <= set(rb.METHODS)
    for name, m in rb.METHODS.items():
        assert m.name == name and m.order >= 1 and m.cost and m.reference and m.summary
        assert m.keeps <= {"SO(3)", "L", "|L|", "energy"}
    from rbcourse.bench.claims import CLAIMS
    assert list(CLAIMS) == list(rb.METHODS) and all(c.stable for c in CLAIMS.values())


def test_unknown_option_is_refused():
    with pytest.raises(ValueError, match="method 'rk4' takes no options; got rtol"):
        rb.simulate(rb.RigidBody.sphere(1, 1), rb.State.at_rest(), 1.0, 0.1, "rk4", rtol=1e-6)
    with pytest.raises(ValueError, match="rtol must be > 0"):
        rb.simulate(rb.RigidBody.sphere(1, 1), rb.State.at_rest(), 1.0, 0.1, "adaptive", rtol=-1.0)


def test_exact_splitting_is_exact_for_a_free_body():
    body, X0 = _free_body()
    coarse = rb.simulate(body, X0, 3.0, 0.75, "exact_splitting")
    from rbcourse.exact import exact_free_body
    exact = exact_free_body(body, X0, coarse.t)
    assert rb.rotation_angle(exact.R, coarse.R).max() < 1e-10
    np.testing.assert_allclose(coarse.x, exact.x, atol=1e-12)
