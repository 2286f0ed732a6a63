import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import rbcourse as rb

from helpers import vec3

forces_lists = st.lists(st.tuples(vec3, vec3), min_size=1, max_size=5)


def test_hand_computed_corner_push():
    F, tau = rb.resultants([0, 0, 0], [((0.15, 0.1, 0.025), (0, 0, 10.0))])
    np.testing.assert_allclose(F, [0, 0, 10])
    np.testing.assert_allclose(tau, [1.0, -1.5, 0.0])       # (r − x) ∧ F, not F ∧ (r − x)


def test_no_force():
    F, tau = rb.resultants([1, 2, 3], [])
    assert F.tolist() == [0, 0, 0] and tau.tolist() == [0, 0, 0]


@given(vec3, vec3)
def test_force_through_the_centre_has_no_torque(x, f):
    F, tau = rb.resultants(x, [(x, f)])
    np.testing.assert_array_equal(tau, 0)
    np.testing.assert_array_equal(F, f)


@given(vec3, vec3, vec3, vec3)
def test_couple_has_no_force_and_the_same_torque_about_any_point(x1, x2, r, f):
    d = np.array([0.3, -0.2, 0.5])
    F1, tau1 = rb.resultants(x1, [(r, f), (r + d, -f)])
    F2, tau2 = rb.resultants(x2, [(r, f), (r + d, -f)])
    np.testing.assert_allclose(F1, 0, atol=1e-12)
    np.testing.assert_allclose(tau1, tau2, atol=1e-9)
    np.testing.assert_allclose(tau1, np.cross(-d, f), atol=1e-9)


@given(vec3, forces_lists, st.floats(-5, 5))
def test_linearity(x, forces, a):
    F, tau = rb.resultants(x, forces)
    Fa, taua = rb.resultants(x, [(r, a * f) for r, f in forces])
    np.testing.assert_allclose(Fa, a * F, atol=1e-9)
    np.testing.assert_allclose(taua, a * tau, atol=1e-8)
    F2, tau2 = rb.resultants(x, forces + forces)
    np.testing.assert_allclose(F2, 2 * F, atol=1e-9)
    np.testing.assert_allclose(tau2, 2 * tau, atol=1e-8)


@given(vec3, vec3, forces_lists)
def test_moving_the_reference_point(x, shift, forces):
    # τ about x + s  =  τ about x  −  s × F
    F, tau = rb.resultants(x, forces)
    _, tau_s = rb.resultants(x + shift, forces)
    np.testing.assert_allclose(tau_s, tau - np.cross(shift, F), atol=1e-8)


@pytest.mark.parametrize("forces, match", [
    ([((0, 0), (0, 0, 1))], r"forces\[0\] point r_i must have shape"),
    ([((0, 0, 0), (0, np.nan, 1))], r"forces\[0\] force F_i must contain only finite"),
    ([(0, 0, 0)], r"forces\[0\] must be a pair"),
    (5, "forces must be a list"),
])
def test_bad_forces(forces, match):
    with pytest.raises(ValueError, match=match):
        rb.resultants([0, 0, 0], forces)


def test_a_scene_of_several_bodies_sums_each_bodys_forces_with_the_same_formula():
    """dxdt of 3 bodies (a spring between bodies 0 and 1, a point force on 2, angular drag on 1): each body's F
    and τ are rb.resultants of the forces on it (about x), plus its pure torques — the engine's sum, per body."""
    bodies = [rb.RigidBody.box(1.0, (0.3, 0.2, 0.05)), rb.RigidBody(2.0, [1.0, 2.0, 2.5]), rb.RigidBody.box(0.5, (0.1, 0.1, 0.1))]
    ba, bb, bf, f = np.array([0.1, 0, 0]), np.array([0, 0.2, 0]), np.array([0, 0, 0.05]), np.array([0, -1.0, 0])
    scene = rb.Scene(bodies, [rb.Spring(ba, stiffness=3.0, body=0, other_body=1, other_point=bb),
                              rb.PointForce(bf, f, body=2), rb.AngularDrag(0.5, body=1)])
    R = np.stack([rb.rotation.rotation_about(a, 0.4) for a in ([1, 0, 0], [0, 1, 1], [1, 1, 1])])
    x = np.array([[0.0, 0, 0], [1.0, 2, 3], [0, 0, 1.0]])
    omega = np.array([[0.0, 0, 0], [0.0, 0, 2.0], [0, 0, 0]])
    X = rb.State(x, R, np.zeros((3, 3)), np.stack([R[i] @ np.linalg.inv(bodies[i].I_body_inv) @ R[i].T @ omega[i]
                                                   for i in range(3)]))
    d = rb.dxdt(scene, 0.0, X)
    ra, rb_ = x[0] + R[0] @ ba, x[1] + R[1] @ bb
    spring = -3.0 * (ra - rb_)                      # on body 0; −spring on body 1
    for i, pairs, extra in [(0, [(ra, spring)], 0.0), (1, [(rb_, -spring)], -0.5 * omega[1]),
                            (2, [(x[2] + R[2] @ bf, f)], 0.0)]:
        Fi, taui = rb.resultants(x[i], pairs)
        np.testing.assert_allclose(d.F[i], Fi, atol=1e-14)
        np.testing.assert_allclose(d.tau[i], taui + extra, atol=1e-14)


def test_the_scene_asks_its_effects_and_sums_with_the_slides_formula():
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    b, f = np.array([0.15, 0.1, 0.025]), np.array([0, 0, 10.0])
    scene = rb.Scene(body, [rb.Gravity(), rb.PointForce(b, f), rb.AngularDrag(0.5)])
    R = rb.rotation.rotation_about([1, 1, 0], 0.3)
    x, omega = np.array([0.5, 0, 1]), np.array([0, 0, 2.0])
    L = R @ body.I_body @ R.T @ omega
    d = rb.dxdt(scene, 0.0, rb.State(x, R, np.zeros(3), L))
    F_ref, tau_ref = rb.resultants(x, [(x, (0, 0, -9.81)), (x + R @ b, f)])
    np.testing.assert_allclose(d.F, F_ref, atol=1e-15)
    np.testing.assert_allclose(d.tau, tau_ref - 0.5 * omega, atol=1e-14)
