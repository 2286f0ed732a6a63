"""The slides' Euler step, as the kernel writes it (engine/euler.py: euler_step), against the slide's formula
written out here in numpy, bit for bit, and against the explicit Runge–Kutta stage loop with the EULER table.

    v = P/M,  I⁻¹(t) = R I⁻¹_body Rᵀ,  ω = I⁻¹(t) L,  Ṙ = ω* R,  F = Σ Fᵢ,  τ = Σ (rᵢ − x) × Fᵢ
    X(t + Δt) = X(t) + Δt · (v, Ṙ, F, τ)
"""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.driver import Kernel, encode
from rbcourse.engine import plan, tableaus


def kernel_module(kernel, name: str):
    """A module of the kernel that runs (compiled rbcourse.engine, or the interpreted copy)."""
    import importlib
    return importlib.import_module(f"{kernel.package.__name__}.{name}")


BOX = rb.RigidBody.box(mass=1.3, size=(0.3, 0.2, 0.05))
FORCES = [((0.15, 0.1, 0.025), (0.0, 0.0, 10.0)), ((-0.1, 0.05, 0.0), (1.0, -2.0, 0.5))]


def tilted_state():
    R = rb.rotation.rotation_about([1.0, 2.0, 0.5], 0.7)
    return rb.State(x=np.array([0.1, -0.2, 0.3]), R=R, P=np.array([0.2, 0.1, -0.4]), L=np.array([0.03, 0.5, -0.02]))


def mul(A, B):
    """A B for 3×3 (or 3×3 by 3): each entry summed as written, a₀b₀ + a₁b₁ + a₂b₂ (numpy's matmul may sum
    in another order, and round otherwise)."""
    B2 = B.reshape(3, -1)
    out = np.array([[A[i, 0] * B2[0, j] + A[i, 1] * B2[1, j] + A[i, 2] * B2[2, j] for j in range(B2.shape[1])]
                    for i in range(3)])
    return out.reshape((3,) + B.shape[1:])


def slide_step(body, X, forces, dt):
    """The slide, in numpy, line by line ("Evolution temporelle (Euler)"): the forces at body points b_i."""
    M, I_body_inv = body.mass, body.I_body_inv
    v = X.P / M                                          # v = P / M
    I_inv = mul(mul(X.R, I_body_inv), X.R.T)             # I⁻¹(t) = R I⁻¹_body Rᵀ
    omega = mul(I_inv, X.L)                              # ω = I⁻¹(t) L
    wx, wy, wz = omega
    star = np.array([[0.0, -wz, wy], [wz, 0.0, -wx], [-wy, wx, 0.0]])
    R_dot = mul(star, X.R)                               # Ṙ = ω* R
    F, tau = np.zeros(3), np.zeros(3)
    for b, f in forces:
        r = X.x + mul(X.R, np.array(b))                  # rᵢ = x + R bᵢ
        F = F + np.array(f)                              # F = Σ Fᵢ
        tau = tau + np.cross(r - X.x, np.array(f))       # τ = Σ (rᵢ − x) × Fᵢ
    return X.x + dt * v, X.R + dt * R_dot, X.P + dt * F, X.L + dt * tau


@pytest.mark.parametrize("fast", [True, False])
def test_euler_step_is_the_slide_bit_for_bit(fast):
    scene = rb.Scene(BOX, [rb.PointForce(b, f) for b, f in FORCES])
    X, dt = tilted_state(), 0.01
    kernel = Kernel(fast)
    euler = kernel_module(kernel, "euler")
    S = encode("matrix", scene.to_engine(scene.batch(X)))
    out, dS = np.empty_like(S), np.empty_like(S)
    euler.euler_step(scene.system(), np.zeros((0, 3)), S, out, dt, dS, kernel.motion.work(1))
    x, R, P, L = slide_step(BOX, X, FORCES, dt)
    assert np.array_equal(out[0, 0:3], x) and np.array_equal(out[0, 3:12].reshape(3, 3), R)
    assert np.array_equal(out[0, 12:15], P) and np.array_equal(out[0, 15:18], L)


@pytest.mark.parametrize("fast", [True, False])
def test_euler_step_equals_the_stage_loop_with_the_euler_table(fast):
    """The explicit Runge–Kutta stage loop (stages.rk_stages) with EULER's table on the slides' state: the same bits."""
    scene = rb.Scene(BOX, [rb.Gravity(), rb.Spring((0.1, 0.0, 0.0), (0.0, 0.0, 1.0), stiffness=40.0, damping=0.3),
                           rb.LinearDrag(0.2), rb.AngularDrag(0.01)])
    kernel = Kernel(fast)
    S = encode("matrix", scene.to_engine(scene.batch(tilted_state())))
    sys, w, h = scene.system(), kernel.motion.work(1), 0.003
    out_euler, out_table = np.empty_like(S), np.empty_like(S)
    kernel_module(kernel, "euler").euler_step(sys, np.zeros((0, 3)), S, out_euler, h, np.empty_like(S), w)
    t = tableaus.EULER
    kernel_module(kernel, "stages").rk_stages(kernel.motion.dxdt, sys, np.zeros((1, 0, 3)), np.ascontiguousarray(t.A),
                                      np.ascontiguousarray(t.b), t.den, S, out_table, h, np.empty((1,) + S.shape),
                                      np.empty_like(S), w)
    assert np.array_equal(out_euler, out_table)


def test_simulate_euler_runs_euler_step():
    """rb.simulate(..., "euler") is euler_step, step after step: its first step is the slide's."""
    scene = rb.Scene(BOX, [rb.PointForce(b, f) for b, f in FORCES])
    X = tilted_state()
    traj = rb.simulate(scene, X, 0.01, 0.01, "euler")
    x, R, P, L = slide_step(BOX, X, FORCES, 0.01)
    assert rb.METHODS["euler"].kernel.family == "euler"
    assert np.array_equal(traj.x[1], x) and np.array_equal(traj.R[1], R) and np.array_equal(traj.P[1], P)
    np.testing.assert_allclose(traj.L[1], L, rtol=0, atol=1e-15)   # L about the centre of mass: as stepped
