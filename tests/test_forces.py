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
