"""The two states of the quaternion methods, Y (N, 13) per body, and their rates.  q is the unit
quaternion of R (R = R(q), Baraff 2001 eq. 4-3).

Baraff's state (notes G, "Quaternions", eq. 4-2; layout QUAT_WORLD), L the world angular momentum
about the rotation centre, as on the slides:

    d/dt [x, q, P, L] = [v, ½ (0, ω) q, F, τ],   I⁻¹(t) = R I⁻¹_body Rᵀ,   ω = I⁻¹(t) L

With no torque L is never changed: a step keeps world L exactly.

The body-frame state (layout QUAT; rk4, adaptive and quaternion_euler_body), L_b = Rᵀ L, which
follows Euler's equations:

    d/dt [x, q, P, L_b] = [v, ½ q (0, ω_b), F, L_b × ω_b + Rᵀ τ],   ω_b = I⁻¹_body L_b

ω_b needs no R, but L_b turns (the gyroscopic term L_b × ω_b): a step that is not exact on it lets
world L = R L_b drift.  (½ (0, ω) q = ½ q (0, ω_b): the same q̇, written in either frame.)
"""
from __future__ import annotations

from .algebra import add, cross, matrix_from_quat, matvec, quat_multiply, quat_normalize, transpose
from .jit import hot, inline, njit
from .motion import (angular_velocity, body_resultants, forces, inverse_inertia, mat, pivot_constraint,
                     put_kinematics, rotation_centre, vec, velocity)


WIDTH = 13      # a body's row: x (3), q (4), P (3), L_b or L (3) — a constant: loops over it unroll


@inline
def quat_state_of(Y, i):
    """Body i's x, q, P, L_b (or L: layout QUAT_WORLD) from a row of Y."""
    return ((Y[i, 0], Y[i, 1], Y[i, 2]), (Y[i, 3], Y[i, 4], Y[i, 5], Y[i, 6]),
            (Y[i, 7], Y[i, 8], Y[i, 9]), (Y[i, 10], Y[i, 11], Y[i, 12]))


@inline
def put_quat_state(Y, i, x, q, P, Lb):
    """Row i of Y := (x, q, P, L_b) (or L: layout QUAT_WORLD)."""
    Y[i, 0], Y[i, 1], Y[i, 2] = x[0], x[1], x[2]
    Y[i, 3], Y[i, 4], Y[i, 5], Y[i, 6] = q[0], q[1], q[2], q[3]
    Y[i, 7], Y[i, 8], Y[i, 9] = P[0], P[1], P[2]
    Y[i, 10], Y[i, 11], Y[i, 12] = Lb[0], Lb[1], Lb[2]


@inline
def quat_motion(sys, i, x, q, P, Lb):
    """Body i: R = R(q), ω_b = I⁻¹_body L_b, ω = R ω_b, and its (x, P) after the pivot constraint, v."""
    R = matrix_from_quat(q)
    omega_b = matvec(mat(sys.I_inv, i), Lb)
    omega = matvec(R, omega_b)
    if sys.pivoted[i]:
        x, P = pivot_constraint(vec(sys.pivot_p, i), vec(sys.pivot_b, i), R, omega, sys.mass[i])
    return x, R, P, velocity(P, sys.mass[i]), omega_b, omega


@njit
def rates_quat(sys, values, Y, dY, w):
    """dY/dt = [v, ½ q ⊗ (0, ω_b), F, L_b × ω_b + Rᵀ τ] for every body, into dY (N, 13).
    A scene with no effect and no pivot evaluates no force at all (F = 0, τ = 0)."""
    n = len(sys.mass)
    torqued = values is not None
    if values is not None:    # every body's kinematics first (a spring may join two bodies), then the forces
        for i in range(n):
            x, q, P, Lb = quat_state_of(Y, i)
            x, R, P, v, omega_b, omega = quat_motion(sys, i, x, q, P, Lb)
            put_kinematics(sys, w, i, x, R, v, omega)
        forces(sys, values, w)
    for i in range(n):
        x, q, P, Lb = quat_state_of(Y, i)
        v, dq, F, dLb = quat_rate(sys, i, q, P, Lb, w, torqued)
        put_quat_state(dY, i, v, dq, F, dLb)


@inline
def spin_rates(q, Lb, omega_b, v, F, tau_b):
    """[v, ½ q ⊗ (0, ω_b), F, L_b × ω_b + τ_b]: the body-frame state's rates (Euler's equations for L_b)."""
    dq = quat_multiply(q, (0.0, omega_b[0], omega_b[1], omega_b[2]))
    return v, (0.5 * dq[0], 0.5 * dq[1], 0.5 * dq[2], 0.5 * dq[3]), F, add(cross(Lb, omega_b), tau_b)


@inline
def quat_rate(sys, i, q, P, Lb, w, torqued):
    """Body i's [v, ½ q ⊗ (0, ω_b), F, L_b × ω_b + Rᵀ τ], its forces and torques read from w (torqued), or none."""
    if torqued:
        return spin_rates(q, Lb, matvec(mat(sys.I_inv, i), Lb), vec(w[2], i), vec(w[5], i),
                          matvec(transpose(mat(w[1], i)), vec(w[6], i)))          # τ_b = Rᵀ τ
    return free_rate(mat(sys.I_inv, i), sys.mass[i], q, P, Lb, (0.0, 0.0, 0.0))


@inline
def free_rate(I_inv, M, q, P, Lb, F):
    """The rates [v, ½ q ⊗ (0, ω_b), F, L_b × ω_b] of a body free but for a force F at its centre of mass
    (gravity, or none: F = 0): v = P/M, ω_b = I⁻¹_body L_b, τ = 0 (as −0: x + (−0) = x, an add compiled away)."""
    return spin_rates(q, Lb, matvec(I_inv, Lb), velocity(P, M), F, (-0.0, -0.0, -0.0))


@hot
def quat_body_rate(sys, values, base, i, x, q, P, Lb):
    """Body i's rate alone, its forces in registers from the effect rows that act on every body
    (motion.body_resultants; values (rows, 3) the forces over time, this stage's from row base): for a scene
    whose effects act alike on each body and join none (stages.py)."""
    x, R, P, v, omega_b, omega = quat_motion(sys, i, x, q, P, Lb)
    F, tau = body_resultants(sys, values, base, i, x, R, v, omega, rotation_centre(sys, i, x))
    return spin_rates(q, Lb, omega_b, v, F, matvec(transpose(R), tau))


@inline
def quat_world_motion(sys, i, x, q, P, L):
    """Body i in Baraff's state: R = R(q), I⁻¹(t) = R I⁻¹_body Rᵀ, ω = I⁻¹(t) L, and its (x, P) after the
    pivot constraint, v."""
    R = matrix_from_quat(q)
    omega = angular_velocity(inverse_inertia(R, mat(sys.I_inv, i)), L)
    if sys.pivoted[i]:
        x, P = pivot_constraint(vec(sys.pivot_p, i), vec(sys.pivot_b, i), R, omega, sys.mass[i])
    return x, R, P, velocity(P, sys.mass[i]), omega


@njit
def rates_quat_world(sys, values, Y, dY, w):
    """Baraff's dY/dt = [v, ½ (0, ω) q, F, τ] for every body (ω world, on the left of q), into dY (N, 13).
    A scene with no effect and no pivot evaluates no force at all (F = 0, τ = 0: L̇ = 0)."""
    n = len(sys.mass)
    if values is not None:    # every body's kinematics first (a spring may join two bodies), then the forces
        for i in range(n):
            x, q, P, L = quat_state_of(Y, i)
            x, R, P, v, omega = quat_world_motion(sys, i, x, q, P, L)
            put_kinematics(sys, w, i, x, R, v, omega)
        forces(sys, values, w)
    for i in range(n):
        x, q, P, L = quat_state_of(Y, i)
        if values is not None:
            v, omega, F, tau = vec(w[2], i), vec(w[3], i), vec(w[5], i), vec(w[6], i)
        else:                                                        # a free body: v = P/M, F = 0, τ = 0
            x, R, P, v, omega = quat_world_motion(sys, i, x, q, P, L)
            F, tau = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        dq = quat_multiply((0.0, omega[0], omega[1], omega[2]), q)
        put_quat_state(dY, i, v, (0.5 * dq[0], 0.5 * dq[1], 0.5 * dq[2], 0.5 * dq[3]), F, tau)


@njit
def normalize_quats(Y):
    """Each body's q normalised (algebra.quat_normalize), so R(q) is a rotation."""
    for i in range(Y.shape[0]):
        q = quat_normalize((Y[i, 3], Y[i, 4], Y[i, 5], Y[i, 6]))
        Y[i, 3], Y[i, 4], Y[i, 5], Y[i, 6] = q[0], q[1], q[2], q[3]
