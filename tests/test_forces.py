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


def test_a_scene_sums_its_effects_with_the_same_formula_per_body():
    """forces.scene_resultants: each body's F and τ are rb.resultants of the forces on it (about x,
    or about the pivot p for a pivoted body), plus its pure torques."""
    from rbcourse.forces import scene_resultants
    c = np.array([[0.0, 0, 0], [1.0, 2, 3], [0, 0, 1.0]])
    r1, F1 = np.array([[0.1, 0, 0], [1, 2.5, 3]]), np.array([[0, 0, 2.0], [1.0, 0, 0]])   # on bodies 0, 1
    r2, F2 = np.array([[0.0, 0.2, 1], [0, 0, 0]]), np.array([[0, -1.0, 0], [0, 0, -9.81]])  # on bodies 2, 0
    tau_pure = np.array([[0.0, 0, 0.5]])
    F, tau = scene_resultants(c, [(np.array([0, 1]), r1, F1), (np.array([2, 0]), r2, F2)],
                              [(np.array([1]), tau_pure)])
    for i, pairs, extra in [(0, [(r1[0], F1[0]), (r2[1], F2[1])], 0.0), (1, [(r1[1], F1[1])], tau_pure[0]),
                            (2, [(r2[0], F2[0])], 0.0)]:
        Fi, taui = rb.resultants(c[i], pairs)
        np.testing.assert_allclose(F[i], Fi, atol=1e-15)
        np.testing.assert_allclose(tau[i], taui + extra, atol=1e-15)
    np.testing.assert_allclose(tau[0], np.cross([0.1, 0, 0], [0, 0, 2.0]), atol=1e-15)   # (0, −0.2, 0), by hand


def test_the_scene_asks_its_effects_and_sums_with_the_slides_formula():
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    b, f = np.array([0.15, 0.1, 0.025]), np.array([0, 0, 10.0])
    scene = rb.Scene(body, [rb.Gravity(), rb.PointForce(b, f), rb.AngularDrag(0.5)])
    R = rb.rotation.rotation_about([1, 1, 0], 0.3)
    x, omega = np.array([0.5, 0, 1]), np.array([0, 0, 2.0])
    F, tau = scene.resultants(0.0, x[None], R[None], np.zeros((1, 3)), omega[None])
    F_ref, tau_ref = rb.resultants(x, [(x, (0, 0, -9.81)), (x + R @ b, f)])
    np.testing.assert_allclose(F[0], F_ref, atol=1e-15)
    np.testing.assert_allclose(tau[0], tau_ref - 0.5 * omega, atol=1e-15)
