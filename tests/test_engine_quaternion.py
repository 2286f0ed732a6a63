"""The two quaternion Euler methods: Baraff's (quaternion_euler, on (x, q, P, L) with world L) and the
body-frame one (quaternion_euler_body, on (x, q, P, L_b)).

Compiled == interpreted over 1000 steps on every engine test scene, pivots, f(t) forces, impulses and
the ground included, is tests/test_engine.py's (parametrised over rb.METHODS, so over both); its
measured first order too.  Here: Baraff's step is his formula, keeps world L exactly with no torque,
what its energy does, and the body-frame method still gives the numbers it gave before the rename.
"""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse import rotation as rot
from rbcourse import driver

BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
R_TILT = rot.rotation_about([1.0, 2.0, 3.0], 0.4)
PIVOT = rb.Pivot(body_point=(0.0, 0.0, -0.05))


def spinning(R=R_TILT, omega=(0.3, 2.0, 0.5)):
    return rb.State.from_velocities(BOX, x=(0.0, 0.0, 1.0), R=R, v=(0.1, -0.2, 0.3), omega=omega)


def baraff_step(body, X, h, F, tau):
    """Baraff 2001, notes G eq. 4-2, one Euler step in numpy, written here (not the engine's):
    x += h P/M, q += h ½ (0, ω) q (then normalised), P += h F, L += h τ, ω = R I⁻¹_body Rᵀ L."""
    q = rot.quat_from_matrix(X.R)
    omega = X.R @ body.I_body_inv @ X.R.T @ X.L
    dq = 0.5 * rot.quat_multiply(np.concatenate([[0.0], omega]), q)
    q1 = q + h * dq
    q1 = q1 / np.linalg.norm(q1)
    return X.x + h * X.P / body.mass, rot.matrix_from_quat(q1), X.P + h * np.asarray(F), X.L + h * np.asarray(tau)


@pytest.mark.parametrize("fast", [True, False], ids=["compiled", "as-python"])
def test_one_step_is_baraffs_formula(fast):
    r, f = np.array([0.15, 0.1, 0.025]), np.array([1.0, -2.0, 10.0])     # a world force at a body point
    scene = rb.Scene(BOX, [rb.PointForce(tuple(r), tuple(f)), rb.Gravity()])
    X0 = spinning()
    h = 1e-2
    traj = rb.simulate(scene, X0, h, h, "quaternion_euler", fast=fast)
    F = f + np.array([0.0, 0.0, -9.81 * BOX.mass])
    tau = np.cross(X0.R @ r, f)                     # about the centre of mass: (r_world − x) × f
    x1, R1, P1, L1 = baraff_step(BOX, X0, h, F, tau)
    np.testing.assert_allclose(traj.x[-1], x1, rtol=0, atol=1e-15)
    np.testing.assert_allclose(traj.R[-1], R1, rtol=0, atol=1e-14)
    np.testing.assert_allclose(traj.P[-1], P1, rtol=0, atol=1e-14)
    np.testing.assert_allclose(traj.L[-1], L1, rtol=0, atol=1e-15)
    # and it is not the body-frame method (whose L moves by the gyroscopic term too): they differ at one step
    other = rb.simulate(scene, X0, h, h, "quaternion_euler_body", fast=fast)
    assert np.abs(other.L[-1] - L1).max() > 1e-6


def test_a_free_body_keeps_world_L_exactly_and_the_body_frame_method_does_not():
    X0 = spinning(omega=(0.3, 5.0, 0.5))
    baraff = rb.simulate(BOX, X0, 20.0, 1e-3, "quaternion_euler")           # 20 000 steps
    assert baraff.implementation.startswith("compiled")
    L0 = np.linalg.norm(X0.L)
    assert np.abs(baraff.L - X0.L).max() <= 1e-13 * L0
    assert baraff.orthogonality_error().max() < 1e-13
    body = rb.simulate(BOX, X0, 20.0, 1e-3, "quaternion_euler_body")
    assert np.abs(body.L - X0.L).max() > 1e-2 * L0                            # L_b's Euler lets world L drift


def test_baraffs_free_body_energy_grows_first_order_and_stays_below_the_bound():
    """With L fixed and R a rotation, T = ½ Lᵀ R I⁻¹_body Rᵀ L ≤ |L|²/(2 I_min): the energy cannot blow up.
    Euler's error is still first order: it grows, step after step, half as fast when dt halves."""
    X0 = spinning(omega=(0.3, 5.0, 0.5))
    bound = float(X0.L @ X0.L) / (2.0 * np.linalg.eigvalsh(BOX.I_body).min())
    growth = []
    for dt in (2e-3, 1e-3):
        traj = rb.simulate(BOX, X0, 2.0, dt, "quaternion_euler")
        E = traj.kinetic_energy()
        assert E.max() <= bound * (1.0 + 1e-12)
        assert np.all(np.diff(E) >= -1e-14 * E[0])                  # never decreases (to rounding)
        growth.append(E[-1] - E[0])
    assert growth[1] > 0.0
    assert 1.7 < growth[0] / growth[1] < 2.3, growth


def test_the_heavy_top_keeps_its_vertical_L_about_the_pivot_and_its_pivot():
    """Gravity's torque about the pivot, (x − p) × M g, is horizontal: L̇_z = 0, so Euler on world L keeps L_z
    exactly (the body-frame method does not); the pivot point stays where it is."""
    scene = rb.Scene(BOX, [rb.Gravity(), PIVOT])
    X0 = PIVOT.state(BOX, R_TILT, [0.5, 0.0, 10.0])
    for fast in (True, False):
        traj = rb.simulate(scene, X0, 1.0 if fast else 0.1, 1e-3, "quaternion_euler", fast=fast)
        Lz = traj.angular_momentum()[:, 2]                     # about the origin, where the pivot is
        assert np.abs(Lz - Lz[0]).max() <= 1e-13 * np.abs(X0.L).max(), (fast, np.abs(Lz - Lz[0]).max())
        tip = traj.x + np.einsum("nij,j->ni", traj.R, PIVOT.body_point)
        np.testing.assert_allclose(tip, 0.0, atol=1e-12)
    body = rb.simulate(scene, X0, 1.0, 1e-3, "quaternion_euler_body")
    assert np.ptp(body.angular_momentum()[:, 2]) > 1e-6


def test_baraffs_box_lands_on_the_ground():
    scene = rb.Scene(BOX, [rb.Gravity(), rb.Ground(restitution=0.5, friction=0.5)])
    X0 = rb.State.from_velocities(BOX, x=(0.0, 0.0, 0.3), R=R_TILT, v=(0.3, 0.0, -1.0), omega=(1.0, 2.0, 0.5))
    traj = rb.simulate(scene, X0, 2.0, 1e-3, "quaternion_euler")
    assert traj.P[:, 2].min() < -1.5 and traj.P[:, 2].max() > 0.1          # falls, then bounces up
    assert abs(traj.x[-1, 2] - 0.025) < 1e-3                                  # at rest on a face
    assert traj.orthogonality_error().max() < 1e-13


# The body-frame method's final states at t = 1 s (1000 steps of 1e-3), as quaternion_euler gave them at
# commit a32c368, before it was renamed quaternion_euler_body (same layout, table and finish): its numbers
# must not change.
BODY_FRAME_BEFORE = {
    "free": dict(
        x=[0.10000000000000184, -0.20000000000000367, 1.299999999999967],
        R=[[-0.65587667390932, 0.07392153452969741, 0.7512399053261369],
           [0.37565254349987337, 0.8951769780726057, 0.2398819386508153],
           [-0.6547602272463746, 0.4395381492675835, -0.6148945114039515]],
        P=[0.1, -0.2, 0.3],
        L=[-0.00060047003598566, 0.0142070788012244, 0.00577384736405947]),
    "forced": dict(
        x=[0.02424306553643903, 0.09784444432280079, 0.12343632370477392],
        R=[[0.3436787498477867, -0.8069024311621668, -0.4804095997038853],
           [-0.7423221004273041, 0.07990757063546983, -0.6652613617010483],
           [0.5751893741371255, 0.5852548562290809, -0.5715189735608259]],
        P=[0.28760550354221315, 0.7005774931081766, 1.9682822901206227],
        L=[-0.08638609477876062, -0.03944614066848207, 0.01077962762980357]),
}


@pytest.mark.parametrize("name", sorted(BODY_FRAME_BEFORE))
def test_the_body_frame_method_gives_its_old_numbers(name):
    scene = rb.Scene(BOX) if name == "free" else rb.Scene(
        BOX, [rb.Gravity(), rb.Spring((0.1, 0.05, 0.0), (0.0, 0.0, 1.0), stiffness=20.0)])
    traj = rb.simulate(scene, spinning(), 1.0, 1e-3, "quaternion_euler_body")
    assert len(traj.t) == 1001
    for k, value in BODY_FRAME_BEFORE[name].items():
        np.testing.assert_allclose(getattr(traj, k)[-1], value, rtol=0, atol=1e-13, err_msg=f"{name}: {k}")


def test_layouts_encode_and_decode_the_same_state():
    X = rb.Scene(BOX).to_engine(rb.Scene(BOX).batch(spinning()))
    world, body = driver.encode("quat_world", X), driver.encode("quat", X)
    np.testing.assert_array_equal(world[:, :10], body[:, :10])              # x, q, P: the same
    np.testing.assert_allclose(world[:, 10:], X.L, rtol=0, atol=0)          # L world, as it is
    np.testing.assert_allclose(body[:, 10:], X.L @ X.R[0], rtol=0, atol=1e-15)   # L_b = Rᵀ L
    with pytest.raises(ValueError, match="layout"):
        driver.encode("quaternion", X)
