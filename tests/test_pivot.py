"""The pivot (pivot.py): I_p = I_body + M (|b|² Id − b bᵀ), x = p − R b, P = M ω × (x − p), L_p = L + (x − p) × P."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rbcourse as rb
from rbcourse.rotation import rotation_about
from rbcourse.examples import heavy_top

BOX = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))


def test_inertia_about_the_pivot_by_the_parallel_axis_theorem():
    pivot = rb.Pivot((0, 0, -0.05), (0, 0, 1.0), body=0)
    scene = rb.Scene([BOX, BOX], [pivot])
    # |b|² Id − b bᵀ = diag(0.0025, 0.0025, 0), M = 1: only the moments about axes across b grow
    np.testing.assert_allclose(scene.I_rot[0], BOX.I_body + np.diag([0.0025, 0.0025, 0.0]), rtol=1e-15)
    np.testing.assert_array_equal(scene.I_rot[1], BOX.I_body)                # the free body keeps I_body
    np.testing.assert_allclose(scene.I_rot_inv[0] @ scene.I_rot[0], np.eye(3), atol=1e-12)
    assert scene.pivoted.tolist() == [True, False] and scene.has_pivots and not rb.Scene(BOX).has_pivots


def test_the_centre_of_mass_follows_the_rotation_and_L_is_taken_about_the_pivot():
    b, p = np.array([0.02, -0.01, -0.05]), np.array([0.3, 0.0, 1.0])
    pivot = rb.Pivot(b, p)
    scene = rb.Scene(BOX, [pivot])
    R = rotation_about([1, 2, 0], 0.7)
    X = rb.State.stack([pivot.state(BOX, R, [0.5, -1.0, 4.0])])
    np.testing.assert_allclose(X.x[0], p - R @ b, atol=1e-15)                      # x = p − R b
    E = scene.to_engine(X)
    np.testing.assert_allclose(E.L, X.L + np.cross(X.x - p, X.P), atol=1e-15)      # L_p = L + (x − p) × P
    np.testing.assert_allclose(scene.to_state_arrays(E.x, E.R, E.P, E.L), X.L, atol=1e-15)   # and back
    np.testing.assert_array_equal(scene.centre(E.x), p[None])                    # torques about p
    # constrain: x and P from R and L_p alone, P = M ω × (x − p), ω = R I_p⁻¹ Rᵀ L_p
    R2 = rotation_about([0, 1, 1], 0.3) @ R
    C = scene.constrain(rb.State.unchecked(np.zeros((1, 3)), R2[None], np.zeros((1, 3)), E.L))
    omega = R2 @ np.linalg.inv(BOX.inertia_about(b)) @ R2.T @ E.L[0]
    np.testing.assert_allclose(C.x[0], p - R2 @ b, atol=1e-15)
    np.testing.assert_allclose(C.P[0], BOX.mass * np.cross(omega, C.x[0] - p), atol=1e-14)
    free = rb.Scene(BOX)
    assert free.constrain(X) is X and free.to_state_arrays(X.x, X.R, X.P, X.L) is X.L


def _top_reference(ex, T):
    """Benchmark C's reference: Euler's equations about the pivot, body frame, scipy DOP853 at 1e-13."""
    body, pivot = ex.scene.bodies[0], ex.scene.effects[1]
    Ip = body.inertia_about(pivot.body_point)
    Ipi = np.linalg.inv(Ip)
    c = -pivot.body_point                                   # centre of mass seen from the pivot, body axes
    R0 = ex.X0.R
    w0 = R0.T @ (R0 @ body.I_body_inv @ R0.T @ ex.X0.L)

    def f(t, y):
        R, w = y[:9].reshape(3, 3), y[9:]
        tau = np.cross(c, R.T @ [0, 0, -9.81 * body.mass])
        return np.concatenate([(R @ rb.star(w)).ravel(), Ipi @ (tau - np.cross(w, Ip @ w))])
    sol = solve_ivp(f, (0, T), np.concatenate([R0.ravel(), w0]), method="DOP853", rtol=1e-13, atol=1e-13)
    return sol.y[:9, -1].reshape(3, 3)


def test_heavy_top_matches_benchmark_C_reference():
    ex = heavy_top()
    T = ex.t_end
    R_ref = _top_reference(ex, T)
    traj = rb.simulate(ex.scene, ex.X0, T, T / 10, "adaptive", rtol=1e-11, atol=1e-13)
    assert rb.rotation_angle(R_ref, traj.R[-1]) < 1e-6
    fine = rb.simulate(ex.scene, ex.X0, T, 1.25e-4, "rk4", record_every=1000)  # a fine step of a 4th-order method
    assert rb.rotation_angle(R_ref, fine.R[-1]) < 1e-6
    # the pivot point stays at the origin, and L_z about the pivot is conserved (gravity is vertical)
    np.testing.assert_allclose(traj.body_point([0, 0, -0.05]), 0, atol=1e-15)
    Lz = traj.angular_momentum(about=[0, 0, 0])[:, 2]
    assert np.ptp(Lz) < 1e-9 * abs(Lz[0])
    E = traj.total_energy()
    assert np.ptp(E) < 1e-8 * abs(E[0])


def test_pivoted_initial_state_must_be_consistent():
    ex = heavy_top()
    with pytest.raises(ValueError, match="pivot point"):
        rb.simulate(ex.scene, rb.State.at_rest(), 0.1, 0.01)
    moving = ex.X0.replace(P=[1.0, 0, 0])
    with pytest.raises(ValueError, match="must move with its pivot"):
        rb.simulate(ex.scene, moving, 0.1, 0.01)


