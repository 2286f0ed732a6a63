"""The trajectory's energy, T and U, is the engine's formula (engine/motion.py: kinetic_energy, potential)
applied state by state: checked here against the textbook formulas written out in numpy, on states
far from rest, one body and N bodies, gravity, springs to the world and between bodies, rest lengths."""
import numpy as np
import rbcourse as rb
from rbcourse.trajectory import Trajectory



def _states(rng, n, N):
    x = rng.normal(size=(n, N, 3))
    R = rb.rotation.matrix_from_quat(rng.normal(size=(n, N, 4)))
    P, L = rng.normal(size=(n, N, 3)), rng.normal(size=(n, N, 3))
    return x, R, P, L


def _bodies():
    return [rb.RigidBody.box(mass=1.5, size=(0.3, 0.2, 0.1)), rb.RigidBody.box(mass=0.7, size=(0.1, 0.4, 0.2)),
            rb.RigidBody.box(mass=2.0, size=(0.5, 0.5, 0.1))]


def test_kinetic_energy_is_half_p_v_plus_half_l_omega():
    rng = np.random.default_rng(1)
    bodies = _bodies()
    scene = rb.Scene(bodies)
    x, R, P, L = _states(rng, 7, 3)
    traj = Trajectory(np.arange(7.0), x, R, P, L, scene)
    M = np.array([b.mass for b in bodies])
    Ib_inv = np.stack([b.I_body_inv for b in bodies])
    omega = np.einsum("knij,njl,knml,knm->kni", R, Ib_inv, R, L)      # R I_body⁻¹ Rᵀ L
    T = 0.5 * np.sum(P * P, -1) / M + 0.5 * np.sum(L * omega, -1)
    np.testing.assert_allclose(traj.kinetic_energy(), T, rtol=1e-13)
    one = Trajectory(np.arange(7.0), x[:, 1], R[:, 1], P[:, 1], L[:, 1], rb.Scene(bodies[1]))
    np.testing.assert_allclose(one.kinetic_energy(), T[:, 1], rtol=1e-13)


def test_potential_energy_gravity_and_springs():
    rng = np.random.default_rng(2)
    bodies = _bodies()
    b0, w0 = np.array([0.1, -0.05, 0.02]), np.array([0.3, 0.0, 1.0])
    b1, b2 = np.array([0.0, 0.2, 0.0]), np.array([-0.2, 0.1, 0.05])
    effects = [rb.Gravity(g=9.81, body=[0, 2]),
               rb.Spring(b0, w0, stiffness=40.0, rest_length=0.25, body=0),
               rb.Spring(b1, stiffness=15.0, rest_length=0.1, body=1, other_body=2, other_point=b2),
               rb.LinearDrag(0.3)]                       # no potential
    scene = rb.Scene(bodies, effects)
    x, R, P, L = _states(rng, 5, 3)
    traj = Trajectory(np.arange(5.0), x, R, P, L, scene)
    M = np.array([b.mass for b in bodies])
    U = np.zeros((5, 3))
    U[:, [0, 2]] += M[[0, 2]] * 9.81 * x[:, [0, 2], 2]
    ra = x[:, 0] + np.einsum("kij,j->ki", R[:, 0], b0)
    U[:, 0] += 0.5 * 40.0 * (np.linalg.norm(ra - w0, axis=-1) - 0.25) ** 2
    r1 = x[:, 1] + np.einsum("kij,j->ki", R[:, 1], b1)
    r2 = x[:, 2] + np.einsum("kij,j->ki", R[:, 2], b2)
    U[:, 1] += 0.5 * 15.0 * (np.linalg.norm(r1 - r2, axis=-1) - 0.1) ** 2      # on the body it is attached to
    np.testing.assert_allclose(traj.potential_energy(), U, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(traj.total_energy(), traj.kinetic_energy() + U, rtol=1e-13, atol=1e-14)


def test_no_potential_is_zeros_of_the_right_shape():
    rng = np.random.default_rng(3)
    x, R, P, L = _states(rng, 4, 2)
    traj = Trajectory(np.arange(4.0), x, R, P, L, rb.Scene(_bodies()[:2], [rb.AngularDrag(0.1)]))
    assert traj.potential_energy().shape == (4, 2) and not traj.potential_energy().any()
    one = Trajectory(np.arange(4.0), x[:, 0], R[:, 0], P[:, 0], L[:, 0], rb.Scene(_bodies()[0]))
    assert one.potential_energy().shape == (4,) and not one.potential_energy().any()


def test_potential_energy_in_chunks(monkeypatch):
    """A long trajectory is handed to the engine in chunks: the same numbers as in one piece."""
    import rbcourse.trajectory as tr
    rng = np.random.default_rng(4)
    body = _bodies()[0]
    scene = rb.Scene(body, [rb.Gravity(), rb.Spring((0.1, 0, 0), (0, 0, 1.0), stiffness=5.0, rest_length=0.2)])
    x, R, P, L = (a[:, 0] for a in _states(rng, 23, 1))
    traj = Trajectory(np.arange(23.0), x, R, P, L, scene)
    whole = traj.potential_energy()
    monkeypatch.setattr(tr, "_ENERGY_CHUNK", 5)
    np.testing.assert_array_equal(traj.potential_energy(), whole)
