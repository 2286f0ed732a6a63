import numpy as np
import pytest
from hypothesis import given

import rbcourse as rb
from rbcourse.rotation import star

from helpers import bodies, rotations, vec3


@given(bodies(), rotations(), vec3, vec3)
def test_from_velocities_round_trip(body, R, v, omega):
    X = rb.State.from_velocities(body, np.zeros(3), R, v, omega)
    np.testing.assert_allclose(X.P, body.mass * v, rtol=1e-12, atol=1e-12)
    d = rb.derived(body, X)
    np.testing.assert_allclose(d.v, v, atol=1e-9)
    np.testing.assert_allclose(d.omega, omega, atol=1e-8 * (1 + np.abs(omega).max()))


def test_derived_are_the_slides_formulas():
    body = rb.RigidBody(2.0, [1.0, 2.0, 2.5])
    R = rb.rotation.rotation_about([0, 0, 1], np.pi / 2)   # body x -> world y
    X = rb.State(x=[1, 2, 3], R=R, P=[2.0, 4.0, 6.0], L=[0.0, 1.0, 0.0])
    v, I_inv, omega = rb.derived(body, X)
    np.testing.assert_allclose(v, [1.0, 2.0, 3.0])                      # v = P/M
    np.testing.assert_allclose(I_inv, np.diag([0.5, 1.0, 0.4]), atol=1e-15)  # world y is body x: 1/1
    np.testing.assert_allclose(omega, [0.0, 1.0, 0.0], atol=1e-15)      # ω = I⁻¹ L


def test_state_is_immutable_and_copies():
    x = np.zeros(3)
    X = rb.State(x, np.eye(3), np.zeros(3), np.zeros(3))
    x[0] = 5
    assert X.x[0] == 0
    with pytest.raises(AttributeError):
        X.x = np.ones(3)
    with pytest.raises(ValueError):
        X.P[0] = 1.0
    Y = X.replace(P=[1, 2, 3])
    assert Y.P.tolist() == [1, 2, 3] and X.P.tolist() == [0, 0, 0]
    assert Y == rb.State(np.zeros(3), np.eye(3), [1, 2, 3], np.zeros(3))


def test_stack():
    a = rb.State.at_rest()
    b = rb.State.at_rest(x=[1, 0, 0])
    s = rb.State.stack([a, b])
    assert s.x.shape == (2, 3) and s.R.shape == (2, 3, 3) and s.n_bodies == 2
    assert s.body(1).x.tolist() == [1, 0, 0]


@pytest.mark.parametrize("kwargs, match", [
    (dict(R=2 * np.eye(3)), "R must be a rotation"),
    (dict(R=np.diag([1.0, 1.0, -1.0])), "R must be a rotation"),
    (dict(R=np.eye(3) + 1e-3), "R must be a rotation"),
    (dict(R=np.eye(2)), "R must have shape"),
    (dict(x=[0, 0]), "x must have shape"),
    (dict(P=[0, 0, np.nan]), "P must contain only finite"),
    (dict(L=[np.inf, 0, 0]), "L must contain only finite"),
    (dict(x="here"), "x must be an array of numbers"),
    (dict(P=np.zeros((2, 3))), "P must have shape"),
])
def test_bad_state_inputs(kwargs, match):
    args = dict(x=np.zeros(3), R=np.eye(3), P=np.zeros(3), L=np.zeros(3))
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        rb.State(**args)


def test_bad_from_velocities():
    body = rb.RigidBody.box(1.0, (1, 1, 1))
    with pytest.raises(ValueError, match="omega must contain only finite"):
        rb.State.from_velocities(body, np.zeros(3), np.eye(3), np.zeros(3), [np.nan, 0, 0])
    with pytest.raises(ValueError, match="body must be a RigidBody"):
        rb.State.from_velocities("box", np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3))


def test_dxdt_is_v_omega_star_R_F_tau():
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    R = rb.rotation.rotation_about([1, 1, 0], 0.4)
    X = rb.State.from_velocities(body, [0, 0, 1], R, [1, 0, 0], [0.3, -2.0, 1.0])
    scene = rb.Scene(body, [rb.PointForce((0.15, 0.1, 0.025), (0, 0, 10.0))])
    d = rb.dxdt(scene, 0.0, X)
    omega = rb.derived(body, X).omega
    np.testing.assert_allclose(d.v, [1, 0, 0])
    for j in range(3):                                   # each body axis turns as dX'/dt = ω × X'
        np.testing.assert_allclose(d.R_dot[:, j], np.cross(omega, R[:, j]), atol=1e-14)
    r = X.x + R @ [0.15, 0.1, 0.025]
    np.testing.assert_allclose(d.F, [0, 0, 10.0])
    np.testing.assert_allclose(d.tau, np.cross(r - X.x, [0, 0, 10.0]), atol=1e-14)
    assert np.allclose(star(omega) @ R, d.R_dot)


def test_stacked_from_velocities_is_the_stack_of_single_ones_to_the_bit():
    """x, v, ω (N, 3), R (N, 3, 3), one body or N: P = M v, L = R I_body Rᵀ ω, checked once as arrays."""
    from rbcourse.rotation import rotation_about
    rng = np.random.default_rng(5)
    n = 200
    bodies = rb.RigidBody.boxes(rng.uniform(0.1, 10, n), rng.uniform(0.01, 3, (n, 3)))
    x, v, w = rng.normal(size=(n, 3)), rng.normal(size=(n, 3)), 5 * rng.normal(size=(n, 3))
    R = np.stack([rotation_about(rng.normal(size=3), a) for a in rng.uniform(0, 6, n)])
    for body in (list(bodies), bodies[0]):
        each = [body[i] if isinstance(body, list) else body for i in range(n)]
        want = rb.State.stack([rb.State.from_velocities(b, x[i], R[i], v[i], w[i]) for i, b in enumerate(each)])
        got = rb.State.from_velocities(body, x, R, v, w)
        for k in rb.State.__slots__:
            np.testing.assert_array_equal(getattr(got, k), getattr(want, k))
    with pytest.raises(ValueError, match="2 of them"):
        rb.State.from_velocities(bodies[:3], x[:2], R[:2], v[:2], w[:2])
    with pytest.raises(ValueError, match="v must have shape"):
        rb.State.from_velocities(bodies[0], x[:2], R[:2], v[:3], w[:2])
    with pytest.raises(ValueError, match="R must be a rotation"):
        rb.State.from_velocities(bodies[0], x[:2], 2 * R[:2], v[:2], w[:2])
    with pytest.raises(ValueError, match="body must be"):
        rb.State.from_velocities("box", x[:2], R[:2], v[:2], w[:2])


def test_the_derived_quantities_over_many_rows_are_the_engines_and_broadcast():
    """rb.velocity, rb.inverse_inertia, rb.angular_velocity over any leading axes (a trajectory's (m, N) rows)
    are the engine's per-body formulas (engine/rows.py over engine/motion.py), checked against numpy's
    v = P/M, R I⁻¹_body Rᵀ, I⁻¹ L to rounding, with the masses and inertias broadcast per body."""
    rng = np.random.default_rng(11)
    m, n = 4, 3
    R = np.stack([[rb.rotation.rotation_about(rng.normal(size=3), rng.uniform(0, 3)) for _ in range(n)] for _ in range(m)])
    J = np.stack([np.linalg.inv(rb.RigidBody(1.0, rng.uniform(1.0, 2.0, 3)).I_body) for _ in range(n)])
    P, L, M = rng.normal(size=(m, n, 3)), rng.normal(size=(m, n, 3)), rng.uniform(0.5, 2.0, n)
    I_inv = rb.inverse_inertia(R, J)
    np.testing.assert_allclose(I_inv, R @ J @ np.swapaxes(R, -1, -2), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(rb.angular_velocity(I_inv, L), np.einsum("...ij,...j->...i", I_inv, L), rtol=1e-14, atol=1e-14)
    np.testing.assert_array_equal(rb.velocity(P, M), P / M[:, None])
    assert rb.velocity(P[0, 0], 2.0).shape == (3,) and rb.inverse_inertia(R[0, 0], J[0]).shape == (3, 3)
