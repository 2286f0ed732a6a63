import numpy as np
from hypothesis import given

from rbcourse import rotation as rot

from helpers import rotations, vec3


@given(vec3, vec3)
def test_star_is_the_cross_product(a, b):
    np.testing.assert_allclose(rot.star(a) @ b, np.cross(a, b), atol=1e-12)


def test_star_batched():
    w = np.arange(12.0).reshape(4, 3)
    S = rot.star(w)
    assert S.shape == (4, 3, 3)
    np.testing.assert_array_equal(S[2], rot.star(w[2]))
    np.testing.assert_array_equal(S + np.swapaxes(S, -1, -2), 0)


@given(vec3)
def test_exp_is_a_rotation_about_phi(phi):
    R = rot.exp_so3(phi)
    assert rot.orthogonality_error(R) < 1e-13
    assert np.linalg.det(R) > 0
    np.testing.assert_allclose(R @ phi, phi, atol=1e-12)   # the axis is fixed


def test_exp_small_angles_and_log():
    for angle in [0.0, 1e-12, 1e-5, 0.3, 3.0]:
        phi = angle * np.array([0.6, 0.0, 0.8])
        R = rot.exp_so3(phi)
        q = rot.quat_from_matrix(R)
        np.testing.assert_allclose(q, [np.cos(angle / 2), *(np.sin(angle / 2) * np.array([0.6, 0, 0.8]))], atol=1e-15)
        np.testing.assert_allclose(rot.log_so3(R), phi, atol=1e-14)


@given(rotations())
def test_quaternion_round_trip(R):
    q = rot.quat_from_matrix(R)
    assert abs(np.linalg.norm(q) - 1) < 1e-14 and q[0] >= 0
    np.testing.assert_allclose(rot.matrix_from_quat(q), R, atol=1e-13)


@given(rotations(), rotations())
def test_quaternion_product_is_rotation_product(A, B):
    qa, qb = rot.quat_from_matrix(A), rot.quat_from_matrix(B)
    np.testing.assert_allclose(rot.matrix_from_quat(rot.quat_multiply(qa, qb)), A @ B, atol=1e-13)


def test_project_and_angle():
    R = rot.rotation_about([0, 0, 1], 0.5)
    noisy = R + 1e-3 * np.arange(9).reshape(3, 3)
    P = rot.project_so3(noisy)
    assert rot.orthogonality_error(P) < 1e-14 and np.linalg.det(P) > 0
    assert np.linalg.norm(P - R) < 1e-2
    assert abs(rot.rotation_angle(R, rot.rotation_about([0, 0, 1], 0.8)) - 0.3) < 1e-14
    assert abs(rot.rotation_angle(R, rot.rotation_about([1, 0, 0], np.pi) @ R) - np.pi) < 1e-7
    assert not rot.is_rotation(2 * R)
    assert rot.is_rotation(R)


def test_orthonormalize_is_the_polar_factor():
    rng = np.random.default_rng(3)
    Q = rot.rotation_about(rng.normal(size=3), 0.9)
    for size in (1e-9, 1e-3, 0.1, 0.8):                  # Björck near SO(3), the SVD beyond 0.5
        R = Q + size * rng.normal(size=(3, 3))
        np.testing.assert_allclose(rot.orthonormalize(R), rot.project_so3(R), atol=1e-12)
    assert rot.orthonormalize(Q) is Q                    # a rotation already: returned as it is
    blown = np.full((3, 3), np.inf)
    assert rot.orthonormalize(blown) is blown            # left for the divergence check


def test_quat_times_vector_is_the_product_with_a_pure_quaternion():
    rng = np.random.default_rng(4)
    q, w = rng.normal(size=(5, 4)), rng.normal(size=(5, 3))
    np.testing.assert_array_equal(rot.quat_times_vector(q, w), rot.quat_multiply(q, np.c_[np.zeros(5), w]))
    # q ⊗ (0, w) by hand for one: (−v·w, s w + v × w)
    s, v = q[0, 0], q[0, 1:]
    np.testing.assert_allclose(rot.quat_times_vector(q[0], w[0]), np.r_[-v @ w[0], s * w[0] + np.cross(v, w[0])],
                               atol=1e-15)
