"""Measured orders against a reference the project did not write: scipy's solve_ivp (DOP853) on the
slides' equations d/dt (x, R, P, L) = (v, ω* R, F, τ), written here from the slides, not from rbcourse.

A sign error shared by the engine's rk4 and its adaptive method (which the order test of
methods/test_methods.py uses as its reference) would pass that test; it cannot pass this one.
"""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rbcourse as rb

M, G = 1.3, 9.81
I_PRINCIPAL = np.diag([0.02, 0.03, 0.04])
K, C, ANCHOR, B_SPRING = 20.0, 0.3, np.array([0.0, 0.0, 1.0]), np.array([0.1, 0.05, 0.0])
B_PUSH, F_PUSH_BODY, C_ANG = np.array([0.0, 0.1, 0.0]), np.array([0.1, 0.2, 0.3]), 0.001
T = 0.4


def rotation(axis, angle):
    """Rodrigues, written out: R = I + sin θ a* + (1 − cos θ) a*²."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    A = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * A + (1 - np.cos(angle)) * A @ A


Q = rotation([1, 2, 3], 0.6)
I_BODY = Q @ I_PRINCIPAL @ Q.T


def slides_rhs(t, y):
    """The slides' "Les Formules", for this one scene:
        v = P/M,  I⁻¹(t) = R I⁻¹_body Rᵀ,  ω = I⁻¹(t) L,  Ṙ = ω* R,
        F = Σ Fᵢ,  τ = Σ (rᵢ − x) ∧ Fᵢ (+ the drag's pure torque −c ω)."""
    x, R, P, L = y[0:3], y[3:12].reshape(3, 3), y[12:15], y[15:18]
    v = P / M
    I_inv = R @ np.linalg.inv(I_BODY) @ R.T
    omega = I_inv @ L
    star = np.array([[0, -omega[2], omega[1]], [omega[2], 0, -omega[0]], [-omega[1], omega[0], 0]])
    forces = [(x, np.array([0.0, 0.0, -M * G]))]                           # gravity at the centre of mass
    r_s = x + R @ B_SPRING                                                  # the damped spring, rest length 0
    v_s = v + np.cross(omega, r_s - x)
    forces.append((r_s, -K * (r_s - ANCHOR) - C * v_s))
    forces.append((x + R @ B_PUSH, R @ F_PUSH_BODY))                        # a push given in body axes
    F = sum(f for _, f in forces)
    tau = sum(np.cross(r - x, f) for r, f in forces) - C_ANG * omega
    return np.concatenate([v, (star @ R).ravel(), F, tau])


def initial_state():
    x0, R0 = np.array([0.1, 0.0, 0.8]), rotation([1, 2, 3], 0.4)
    v0, w0 = np.array([0.2, 0.0, 0.1]), np.array([1.0, -2.0, 3.0])
    L0 = R0 @ I_BODY @ R0.T @ w0
    return x0, R0, M * v0, L0


@pytest.fixture(scope="module")
def reference():
    x0, R0, P0, L0 = initial_state()
    sol = solve_ivp(slides_rhs, (0.0, T), np.concatenate([x0, R0.ravel(), P0, L0]), method="DOP853",
                    rtol=1e-13, atol=1e-13)
    assert sol.success
    y = sol.y[:, -1]
    return y[0:3], y[3:12].reshape(3, 3), y[15:18]


def engine_scene():
    body = rb.RigidBody(M, I_BODY)
    scene = rb.Scene(body, [rb.Gravity(G), rb.Spring(B_SPRING, ANCHOR, stiffness=K, damping=C),
                            rb.PointForce(B_PUSH, F_PUSH_BODY, frame="body"), rb.AngularDrag(C_ANG)])
    x0, R0, P0, L0 = initial_state()
    return scene, rb.State(x=x0, R=R0, P=P0, L=L0)


def error(traj, ref):
    x, R, L = ref
    return rb.rotation_angle(R, traj.R[-1]) + np.abs(traj.x[-1] - x).max() + np.abs(traj.L[-1] - L).max()


def test_the_engine_agrees_with_the_slides_equations_under_scipy(reference):
    scene, X0 = engine_scene()
    adaptive = rb.simulate(scene, X0, T, T, "adaptive", rtol=1e-12, atol=1e-14)
    assert error(adaptive, reference) < 1e-9
    rk4 = rb.simulate(scene, X0, T, 1e-3, "rk4")
    assert error(rk4, reference) < 1e-8


DTS = {1: [0.004, 0.002, 0.001], 2: [0.02, 0.01, 0.005], 4: [0.04, 0.02, 0.01]}
FIXED = [m for m in rb.METHODS if "rtol" not in rb.METHODS[m].options]


@pytest.mark.parametrize("method", FIXED)
def test_measured_order_against_the_independent_reference(method, reference):
    scene, X0 = engine_scene()
    claim = rb.METHODS[method].order
    dts = DTS[claim]
    errors = [error(rb.simulate(scene, X0, T, dt, method), reference) for dt in dts]
    slope = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert abs(slope - claim) < 0.3, f"{method}: measured order {slope:.2f}, claimed {claim} (errors {errors})"


def test_a_sign_error_would_be_caught(reference):
    """The test can fail: the same scene with the push's sign flipped is far from the reference."""
    body = rb.RigidBody(M, I_BODY)
    wrong = rb.Scene(body, [rb.Gravity(G), rb.Spring(B_SPRING, ANCHOR, stiffness=K, damping=C),
                            rb.PointForce(B_PUSH, -F_PUSH_BODY, frame="body"), rb.AngularDrag(C_ANG)])
    _, X0 = engine_scene()
    assert error(rb.simulate(wrong, X0, T, 1e-3, "rk4"), reference) > 1e-4
