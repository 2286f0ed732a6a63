import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg
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
    np.testing.assert_array_equal(rot.orthonormalize(Q), Q)        # a rotation already: returned as it is
    blown = np.full((3, 3), np.inf)
    np.testing.assert_array_equal(rot.orthonormalize(blown), blown)  # left for the divergence check


def test_nearest_rotation_is_project_so3s_rotation_and_the_angle_uses_it():
    """nearest_rotation: the polar factor (orthonormalize) where det R > 0, the SVD where det R <= 0 — the same
    rotation as project_so3 to rounding, near SO(3), far from it, and with det < 0; rotation_angle on top of it."""
    rng = np.random.default_rng(26)
    Q = rot.exp_so3(rng.normal(size=(200, 3)))
    for R in (Q, Q + 1e-9 * rng.normal(size=Q.shape), Q + 1e-3 * rng.normal(size=Q.shape),
              1.7 * Q + 0.4 * rng.normal(size=Q.shape), -Q, np.diag([1.0, 1.0, -3.0])):
        P = rot.nearest_rotation(R)
        np.testing.assert_allclose(P, rot.project_so3(R), rtol=0, atol=1e-13)
        assert np.all(np.abs(np.linalg.det(P) - 1) < 1e-13) and np.all(rot.orthogonality_error(P) < 1e-13)
    np.testing.assert_array_equal(rot.nearest_rotation(Q), rot.orthonormalize(Q))    # on SO(3): R as it is
    noisy = Q + 1e-3 * rng.normal(size=Q.shape)
    D = rot.transpose(rot.project_so3(Q)) @ rot.project_so3(noisy)              # the angle with the SVD's projections
    svd_angle = 2 * np.arccos(np.clip((np.trace(D, axis1=-2, axis2=-1) - 1) / 2 * 0.5 + 0.5, -1, 1) ** 0.5)
    np.testing.assert_allclose(rot.rotation_angle(Q, noisy), svd_angle, rtol=0, atol=1e-7)
    for bad, name in ((np.full((3, 3), np.nan), "R"), (np.eye(2), "R")):
        with pytest.raises(ValueError, match=name):
            rot.nearest_rotation(bad)
    with pytest.raises(ValueError, match="R_ref"):
        rot.rotation_angle(np.full((3, 3), np.inf), np.eye(3))


def test_quat_times_vector_is_the_product_with_a_pure_quaternion():
    rng = np.random.default_rng(4)
    q, w = rng.normal(size=(5, 4)), rng.normal(size=(5, 3))
    np.testing.assert_array_equal(rot.quat_times_vector(q, w), rot.quat_multiply(q, np.c_[np.zeros(5), w]))
    # q ⊗ (0, w) by hand for one: (−v·w, s w + v × w)
    s, v = q[0, 0], q[0, 1:]
    np.testing.assert_allclose(rot.quat_times_vector(q[0], w[0]), np.r_[-v @ w[0], s * w[0] + np.cross(v, w[0])],
                               atol=1e-15)


# --- rotation.py applies the engine's formulas (engine/algebra.py) row by row: checked here against the
# textbook formulas written out in numpy, at every batch shape, with NaN in -> NaN out ---------------------

SHAPES = [(), (5,), (2, 3)]


def star_by_hand(w):
    """ω* written out, for one ω."""
    x, y, z = w
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def rodrigues_by_hand(phi):
    """I + (sin θ/θ) φ* + 2 (sin(θ/2)/θ)² φ*², θ = |φ| (the half-angle form of (1 − cos θ)/θ²: no
    cancellation, so accurate to rounding at every θ > 0 without a Taylor branch)."""
    theta = np.linalg.norm(phi)
    if theta == 0.0:
        return np.eye(3)
    K = star_by_hand(phi)
    return np.eye(3) + np.sin(theta) / theta * K + 2.0 * (np.sin(theta / 2) / theta) ** 2 * (K @ K)


def matrix_from_quat_by_hand(q):
    """Baraff 2001 eq. 4-3 for the unit quaternion q / |q| = (s, x, y, z)."""
    s, x, y, z = np.asarray(q) / np.linalg.norm(q)
    return np.array([[1 - 2 * y * y - 2 * z * z, 2 * x * y - 2 * s * z, 2 * x * z + 2 * s * y],
                     [2 * x * y + 2 * s * z, 1 - 2 * x * x - 2 * z * z, 2 * y * z - 2 * s * x],
                     [2 * x * z - 2 * s * y, 2 * y * z + 2 * s * x, 1 - 2 * x * x - 2 * y * y]])


def hamilton_by_hand(p, q):
    """(s1 s2 − v1·v2, s1 v2 + s2 v1 + v1 × v2)."""
    return np.r_[p[0] * q[0] - p[1:] @ q[1:], p[0] * q[1:] + q[0] * p[1:] + np.cross(p[1:], q[1:])]


def rows(a, tail):
    return np.reshape(a, (-1,) + tail)


@pytest.mark.parametrize("shape", SHAPES)
def test_star_and_cross_are_the_formulas_written_out(shape):
    rng = np.random.default_rng(10)
    w, a = rng.normal(size=shape + (3,)), rng.normal(size=shape + (3,))
    W, c = rot.star(w), rot.cross(w, a)
    assert W.shape == shape + (3, 3) and c.shape == shape + (3,)
    for Wi, ci, wi, ai in zip(rows(W, (3, 3)), rows(c, (3,)), rows(w, (3,)), rows(a, (3,))):
        np.testing.assert_array_equal(Wi, star_by_hand(wi))
        np.testing.assert_array_equal(ci, np.cross(wi, ai))            # the same products, the same order
        np.testing.assert_allclose(Wi @ ai, np.cross(wi, ai), rtol=0, atol=1e-15 * np.abs(wi).max() * np.abs(ai).max())


def test_cross_and_quat_multiply_broadcast():
    rng = np.random.default_rng(11)
    a, b = rng.normal(size=(2, 1, 3)), rng.normal(size=(4, 3))
    c = rot.cross(a, b)
    assert c.shape == (2, 4, 3)
    np.testing.assert_array_equal(c, np.cross(a, b))
    np.testing.assert_array_equal(rot.cross([0.0, 0.0, 1.0], b), np.cross([0.0, 0.0, 1.0], b))
    p, q = rng.normal(size=4), rng.normal(size=(2, 3, 4))
    pq = rot.quat_multiply(p, q)
    assert pq.shape == (2, 3, 4)
    for i, j in np.ndindex(2, 3):
        np.testing.assert_allclose(pq[i, j], hamilton_by_hand(p, q[i, j]), rtol=1e-15, atol=4e-16)
    with pytest.raises(ValueError, match="a and b must broadcast"):
        rot.cross(np.zeros((2, 3)), np.zeros((5, 3)))
    with pytest.raises(ValueError, match="q1 and q2 must broadcast"):
        rot.quat_multiply(np.zeros((2, 4)), np.zeros((3, 4)))


@pytest.mark.parametrize("shape", SHAPES)
def test_quaternion_formulas_written_out(shape):
    rng = np.random.default_rng(12)
    p, q = rng.normal(size=shape + (4,)), rng.normal(size=shape + (4,))
    pq, n, R = rot.quat_multiply(p, q), rot.quat_normalize(q), rot.matrix_from_quat(q)
    assert pq.shape == n.shape == shape + (4,) and R.shape == shape + (3, 3)
    for pi, qi, pqi, ni, Ri in zip(rows(p, (4,)), rows(q, (4,)), rows(pq, (4,)), rows(n, (4,)), rows(R, (3, 3))):
        np.testing.assert_allclose(pqi, hamilton_by_hand(pi, qi), rtol=1e-15, atol=1e-15)
        np.testing.assert_allclose(ni, qi / np.linalg.norm(qi), rtol=2e-16, atol=0)
        np.testing.assert_allclose(Ri, matrix_from_quat_by_hand(qi), rtol=0, atol=1e-15)
        np.testing.assert_allclose(rot.matrix_from_quat(7.25 * qi), Ri, rtol=0, atol=1e-15)   # normalised first
        # the rotation by θ about u is the quaternion (cos θ/2, sin θ/2 u): R(q) = exp(θ u*), by Rodrigues
        # (scipy's expm is off by up to 3e-14 here)
        theta, u = 2 * np.arctan2(np.linalg.norm(ni[1:]), ni[0]), ni[1:] / np.linalg.norm(ni[1:])
        np.testing.assert_allclose(Ri, rodrigues_by_hand(theta * u), rtol=0, atol=2e-15)


@pytest.mark.parametrize("angle", [0.0, 1e-9, 1e-6, 5e-5, 0.99e-4, 1e-4, 1.01e-4, 2e-4, 1e-3, 3e-2, 0.1, 1.0,
                                   3.0, np.pi, 10.0, 100.0])
def test_exp_so3_is_the_matrix_exponential(angle):
    """|φ|² from 0 through the Taylor threshold 1e-8 (|φ| = 1e-4) to 100² — against the half-angle Rodrigues
    formula and scipy's expm of φ*, to rounding: ~1e-16 |φ| (an ulp of the angle turns R by that much)."""
    rng = np.random.default_rng(13)
    u = rng.normal(size=(6, 3))
    phi = angle * u / np.linalg.norm(u, axis=-1, keepdims=True)
    R = rot.exp_so3(phi)
    for phi_i, R_i in zip(phi, R):
        ref = rodrigues_by_hand(phi_i)
        np.testing.assert_allclose(R_i, ref, rtol=0, atol=1.2e-15 * max(1.0, angle))
        np.testing.assert_allclose(R_i, scipy.linalg.expm(star_by_hand(phi_i)), rtol=0, atol=2e-15 * max(1.0, angle))
        # small angles: R − I to rounding relative to its own size, the antisymmetric part sin θ/θ φ*, and
        # (where the Taylor series is used) the symmetric part (1 − cos θ)/θ² φ*², which 1 − cos θ loses to
        # cancellation
        if angle < 0.1:
            np.testing.assert_allclose((R_i - R_i.T) / 2, (ref - ref.T) / 2, rtol=1e-14, atol=0)
        if angle ** 2 < 1e-8:
            off = ~np.eye(3, dtype=bool)
            np.testing.assert_allclose(((R_i + R_i.T) / 2)[off], ((ref + ref.T) / 2)[off], rtol=1e-13, atol=0)


@pytest.mark.parametrize("shape", SHAPES)
def test_exp_so3_batched(shape):
    rng = np.random.default_rng(14)
    phi = rng.normal(size=shape + (3,)) * np.logspace(-6, 0.5, int(np.prod(shape))).reshape(shape + (1,))
    R = rot.exp_so3(phi)
    assert R.shape == shape + (3, 3)
    for phi_i, R_i in zip(rows(phi, (3,)), rows(R, (3, 3))):
        np.testing.assert_allclose(R_i, rodrigues_by_hand(phi_i), rtol=0, atol=1.2e-15)
    np.testing.assert_allclose(rot.rotation_about([0, 0, 2], np.pi / 2), [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
                               rtol=0, atol=2.5e-16)


@pytest.mark.parametrize("shape", SHAPES)
def test_retract_is_one_bjorck_step(shape):
    rng = np.random.default_rng(15)
    R = rot.exp_so3(rng.normal(size=shape + (3,))) + 1e-4 * rng.normal(size=shape + (3, 3))
    out = rot.retract(R)
    assert out.shape == shape + (3, 3)
    for Ri, oi in zip(rows(R, (3, 3)), rows(out, (3, 3))):
        np.testing.assert_allclose(oi, Ri - 0.5 * Ri @ (Ri.T @ Ri - np.eye(3)), rtol=0, atol=4e-16)
        assert rot.orthogonality_error(oi) < rot.orthogonality_error(Ri) ** 2      # ε → ~ε² (here ε ~ 4e-4)


@pytest.mark.parametrize("shape", SHAPES)
def test_orthonormalize_each_rotation_is_its_polar_factor(shape):
    rng = np.random.default_rng(16)
    n = int(np.prod(shape))
    size = np.resize([1e-9, 1e-3, 0.1, 0.3, 0.8, 2.0], n).reshape(shape + (1, 1))   # Björck, and Newton beyond 0.5
    R = rot.exp_so3(rng.normal(size=shape + (3,))) + size * rng.normal(size=shape + (3, 3))
    R = np.where(np.linalg.det(R)[..., None, None] > 0, R, -R)
    out = rot.orthonormalize(R)
    assert out.shape == shape + (3, 3)
    for Ri, oi in zip(rows(R, (3, 3)), rows(out, (3, 3))):
        # both sides are backward stable: each is within a few u·κ(R) of the exact polar factor (u = 1.1e-16)
        np.testing.assert_allclose(oi, scipy.linalg.polar(Ri)[0], rtol=0, atol=1e-14 * np.linalg.cond(Ri))
        assert rot.orthogonality_error(oi) < 1e-15


def test_orthonormalize_rows_are_independent_and_blown_up_ones_stay():
    rng = np.random.default_rng(17)
    good = rot.exp_so3(rng.normal(size=3)) + 1e-6 * rng.normal(size=(3, 3))
    R = np.stack([good, np.full((3, 3), np.nan), np.full((3, 3), np.inf), good])
    out = rot.orthonormalize(R)
    np.testing.assert_array_equal(out[1:3], R[1:3])                 # left for the divergence check
    for i in (0, 3):                                                 # not held back by the others
        np.testing.assert_allclose(out[i], scipy.linalg.polar(good)[0], rtol=0, atol=2e-15)
    np.testing.assert_array_equal(rot.orthonormalize(R, max_iter=0), R)
    for bad in (dict(tol=-1.0), dict(tol=np.nan), dict(max_iter=2.5), dict(max_iter=-1)):
        with pytest.raises(ValueError, match=next(iter(bad))):
            rot.orthonormalize(good, **bad)


def test_nan_in_gives_nan_out():
    nan, inf = np.nan, np.inf
    for w in ([nan, 0, 0], [inf, 0, 0], [1e200, 0, 0]):
        assert np.isnan(rot.exp_so3(w)).all()
    phi = np.array([[0.1, 0.2, 0.3], [nan, 0, 0], [0, -inf, 0]])
    R = rot.exp_so3(phi)                                             # a bad row spoils only itself
    assert np.isnan(R[1:]).all() and np.isfinite(R[0]).all()
    np.testing.assert_allclose(R[0], rodrigues_by_hand(phi[0]), rtol=0, atol=1.2e-15)
    for q in ([0, 0, 0, 0], [nan, 1, 0, 0], [inf, 0, 0, 0], [1e200, 1e200, 0, 0]):
        assert np.isnan(rot.quat_normalize(q)).all() and np.isnan(rot.matrix_from_quat(q)).all()
    assert np.isnan(rot.quat_multiply([nan, 0, 0, 0], [1.0, 0, 0, 0])).all()
    assert np.isnan(rot.cross([nan, 0, 0], [0, 1.0, 0])).any()
    assert np.isnan(rot.retract(np.full((3, 3), nan))).all()


def test_bad_inputs_name_the_parameter():
    for call, name in [(lambda: rot.star([1, 2]), "omega"), (lambda: rot.cross([1, 2, 3], "abc"), "b"),
                       (lambda: rot.cross([1, 2], [1, 2, 3]), "a"), (lambda: rot.exp_so3([[1, 2]]), "phi"),
                       (lambda: rot.retract(np.eye(2)), "R"), (lambda: rot.orthonormalize([True] * 9), "R"),
                       (lambda: rot.quat_multiply([1, 0, 0, 0], [1, 0, 0]), "q2"),
                       (lambda: rot.quat_normalize([1, 0, 0]), "q"), (lambda: rot.matrix_from_quat("q"), "q"),
                       (lambda: rot.quat_times_vector([1, 0, 0, 0], [1, 0]), "w"),
                       (lambda: rot.rotation_about([0, 0, 0], 1.0), "axis"),
                       (lambda: rot.rotation_about([0, 0, 1], "x"), "angle")]:
        with pytest.raises(ValueError, match=name):
            call()


def test_rotation_runs_the_engines_functions_compiled_and_interpreted_alike():
    """The row functions, compiled (or run as Python, with NUMBA_DISABLE_JIT) and the engine's own files run as
    Python (engine/interpreted.py): the same numbers, to rounding."""
    from rbcourse.engine import interpreted
    py = interpreted.module("rows")
    rng = np.random.default_rng(18)
    w, a, q, p = rng.normal(size=(7, 3)), rng.normal(size=(7, 3)), rng.normal(size=(7, 4)), rng.normal(size=(7, 4))
    w[0] *= 1e-5                                                     # the Taylor branch
    R = rot.exp_so3(w) + 1e-3 * rng.normal(size=(7, 3, 3))

    def run(fn, *args, tail):
        out = np.empty((len(args[0]),) + tail)
        fn(*args, out)
        return out
    for mine, theirs in [(rot.star(w), run(py.star_rows, w, tail=(3, 3))),
                         (rot.cross(w, a), run(py.cross_rows, w, a, tail=(3,))),
                         (rot.exp_so3(w), run(py.exp_so3_rows, w, tail=(3, 3))),
                         (rot.retract(R), run(py.retract_rows, R, tail=(3, 3))),
                         (rot.quat_multiply(p, q), run(py.quat_multiply_rows, p, q, tail=(4,))),
                         (rot.quat_normalize(q), run(py.quat_normalize_rows, q, tail=(4,))),
                         (rot.matrix_from_quat(q), run(py.matrix_from_quat_rows, q, tail=(3, 3)))]:
        np.testing.assert_allclose(mine, theirs, rtol=0, atol=1e-15)
    S = np.zeros((7, 18))
    S[:, 3:12] = R.reshape(7, 9)
    interpreted.module("orthonormalize").orthonormalize_rows(S, 1e-15, 20)
    np.testing.assert_allclose(rot.orthonormalize(R), S[:, 3:12].reshape(7, 3, 3), rtol=0, atol=1e-15)


def test_importing_rotation_loads_no_numba():
    code = ("import sys, rbcourse, rbcourse.rotation, rbcourse.rowwise\n"
            "assert 'numba' not in sys.modules, 'numba imported by import rbcourse'\n"
            "rbcourse.rotation.star([1.0, 2.0, 3.0])\n"
            "assert 'rbcourse.engine.rows' in sys.modules\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr


def test_the_engines_exp_so3_gives_nan_for_a_blown_up_angle_compiled_and_as_python():
    """A geometric step of a run that blew up takes exp of an infinite angle: NaN (the divergence check
    sees it), not a math domain error, when the engine runs as Python too."""
    from rbcourse.engine import algebra, interpreted
    for mod in (algebra, interpreted.module("algebra")):
        for phi in ((np.inf, 0.0, 0.0), (1e200, 1e200, 0.0), (np.nan, 0.0, 1.0)):
            R = np.array(mod.exp_so3(phi) if mod is not algebra else rot.exp_so3(np.array(phi)))
            assert np.isnan(R).all(), (mod.__name__, phi)
