import numpy as np
import pytest

import rbcourse as rb


def test_box_inertia_formula():
    body = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))
    # benchmarks.md: I = (3.5417e-3, 7.7083e-3, 1.0833e-2)
    np.testing.assert_allclose(np.diag(body.I_body), [0.0425 / 12, 0.0925 / 12, 0.13 / 12], rtol=1e-15)
    np.testing.assert_allclose(body.I_body @ body.I_body_inv, np.eye(3), atol=1e-12)
    assert body.mass == 1.0


def test_cylinder_and_sphere():
    cyl = rb.RigidBody.cylinder(mass=1.0, radius=0.04, height=0.01)
    np.testing.assert_allclose(np.diag(cyl.I_body), [(3 * 0.04**2 + 0.01**2) / 12] * 2 + [0.04**2 / 2])
    # benchmark C: about the pivot at l = 0.05 add m l² to the first two moments
    np.testing.assert_allclose(np.diag(cyl.inertia_about([0, 0, 0.05])), [2.90833e-3, 2.90833e-3, 8.0e-4], rtol=1e-5)
    sph = rb.RigidBody.sphere(mass=2.0, radius=0.5)
    np.testing.assert_allclose(sph.I_body, 0.4 * 2.0 * 0.25 * np.eye(3))


def test_full_matrix_and_principal_axes():
    Q = rb.rotation.rotation_about([1, 2, 3], 0.7)
    I = Q @ np.diag([1.0, 2.0, 2.5]) @ Q.T
    body = rb.RigidBody(mass=2.0, inertia=I)
    np.testing.assert_allclose(body.principal_moments, [1.0, 2.0, 2.5])
    A = body.principal_axes
    np.testing.assert_allclose(A.T @ I @ A, np.diag([1.0, 2.0, 2.5]), atol=1e-12)
    assert np.linalg.det(A) == pytest.approx(1.0)


def test_flat_plate_is_allowed():
    rb.RigidBody(1.0, [1.0, 2.0, 3.0])        # equality: a thin plate
    rb.RigidBody.box(1.0, (1.0, 1.0, 1e-9))


def test_body_is_constant():
    body = rb.RigidBody.box(1.0, (1, 2, 3))
    with pytest.raises(AttributeError):
        body.mass = 2.0
    with pytest.raises(ValueError):
        body.I_body[0, 0] = 5.0


@pytest.mark.parametrize("mass, inertia, match", [
    (0.0, [1, 1, 1], "mass must be > 0"),
    (-1.0, [1, 1, 1], "mass must be > 0"),
    (np.nan, [1, 1, 1], "mass must be finite"),
    (np.inf, [1, 1, 1], "mass must be finite"),
    ("heavy", [1, 1, 1], "mass must be a real number"),
    (1.0, [1, 1, 3], "triangle inequality"),
    (1.0, [1, -1, 1], "positive definite"),
    (1.0, [0, 1, 1], "positive definite"),
    (1.0, [1, 1], "shape"),
    (1.0, [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]], "symmetric"),
    (1.0, [1, np.nan, 1], "finite"),
    (1.0, "abc", "inertia must be"),
])
def test_bad_body_inputs(mass, inertia, match):
    with pytest.raises(ValueError, match=match):
        rb.RigidBody(mass, inertia)


@pytest.mark.parametrize("call, match", [
    (lambda: rb.RigidBody.box(1.0, (1, 2)), "size must be 3 positive lengths"),
    (lambda: rb.RigidBody.box(1.0, (1, -2, 3)), r"size\[1\] must be > 0"),
    (lambda: rb.RigidBody.box(0, (1, 2, 3)), "mass must be > 0"),
    (lambda: rb.RigidBody.cylinder(1.0, 0.0, 1.0), "radius must be > 0"),
    (lambda: rb.RigidBody.sphere(1.0, np.inf), "radius must be finite"),
])
def test_bad_factory_inputs(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_boxes_are_the_boxes_to_the_bit():
    """RigidBody.boxes(masses, sizes) checks once as arrays and gives RigidBody.box(masses[i], sizes[i])."""
    rng = np.random.default_rng(3)
    m, s = rng.uniform(1e-3, 1e3, 500), rng.uniform(1e-3, 10.0, (500, 3))
    for i, b in enumerate(rb.RigidBody.boxes(m, s)):
        o = rb.RigidBody.box(m[i], s[i])
        for k in rb.RigidBody.__slots__:
            got, want = getattr(b, k), getattr(o, k)
            assert np.array_equal(got, want) if isinstance(want, np.ndarray) else got == want, (i, k)
            if isinstance(got, np.ndarray):
                assert not got.flags.writeable


@pytest.mark.parametrize("masses, sizes, match", [
    ([1.0, -1.0], [[1, 1, 1], [1, 1, 1]], "masses"),
    ([1.0, 1.0], [[1, 1, 1], [1, 0, 1]], "sizes"),
    ([1.0, 1.0], [[1, 1, 1]], "shape"),
    ([1.0], [[1, 1, np.nan]], "sizes"),
    (["a"], [[1, 1, 1]], "masses"),
    ([1e-300], [[1e-10, 1e-10, 1e-10]], "principal moments"),
])
def test_boxes_refuse_bad_arrays(masses, sizes, match):
    with pytest.raises(ValueError, match=match):
        rb.RigidBody.boxes(masses, sizes)
