"""The implicit methods of integrators/geometric.py on the engine's arrays: implicit_gyro, implicit_midpoint.

Both step the slides' state S (N, 18) = [x, R (row by row), P, L] (layout MATRIX), L about the rotation
centre (the centre of mass, or the pivot of a pivoted body), and end with the pivot constraint
(motion.constrain_state: x = p − R b, P = M ω × (x − p)), as the numpy steps end with scene.constrain.
Same formulas, same order of operations as the numpy steps, so the two agree to rounding.

    implicit_gyro_step      (Catto, GDC 2015; Bullet): forces at t            -> nodes (0.0,)
    implicit_midpoint_step  (midpoint on the world momenta, R′ = R exp(h ω̄*)): forces at t + h/2,
                            re-evaluated at every Newton iteration             -> nodes (0.5,)

Both take values (1, slots, 3): the forces given as functions f(t), at the one node, so values[0].

implicit_gyro uses the inertia I about the rotation centre (sys.I, body axes) and its inverse (sys.I_inv),
both from the scene, as the numpy step does.
"""
from __future__ import annotations

import numpy as np

from .algebra import (add, axpy, cross, dot, exp_so3, identity, mat_axpy, matmul, matvec, retract, scale,
                      solve3, star, sub, transpose)
from .jit import inline, njit
from .motion import constrain_state, copy_into, drift, fill, forced, forces, kinematics_matrix, mat, put_state, state_of, vec

# implicit_midpoint's Newton loop (the numpy step's defaults); opts = (tol, max_iter) overrides them
TOL = 1e-15
MAX_ITER = 60
FAIL = 1e-8      # a last Newton change above FAIL (1 + size) after max_iter: no solution, the run stops


@inline
def cayley(a):
    """The Cayley map, a rotation for every a (3,):

        cay(a) = (I − a*/2)⁻¹ (I + a*/2) = I + 4/(4 + |a|²) (a* + a*²/2)

    (integrators/geometric.cayley, written in the tuple algebra)."""
    A = star(a)
    k = 4.0 / (4.0 + dot(a, a))
    return mat_axpy(identity(), k, mat_axpy(A, 0.5, matmul(A, A)))


@njit
def implicit_gyro_step(sys, values, opts, Y, out, h, K, U, w):
    """Implicit gyroscopic step (Catto, GDC 2015; Bullet's computeGyroscopicImpulseImplicit_Body), per body:

        torque kick in the body frame, ω₁ = I⁻¹ Rᵀ (L + h τ);
        one Newton step on I (ω₂ − ω₁) + h ω₂ × I ω₂ = 0 from ω₁:
        J = I + h (ω₁* I − (I ω₁)*),   ω₂ = ω₁ − J⁻¹ (h ω₁ × I ω₁);
        R' = retract(R exp(h ω₂*)),  L' = R' I ω₂;  P' = P + h F,  x' = x + h P'/M

    F, τ at the start of the step (time t: values[0], node 0); I = sys.I, I⁻¹ = sys.I_inv.
    Unconditionally stable; dissipates rotational energy; first order.  K, U unused."""
    kinematics_matrix(sys, Y, w)          # x, v, ω (pivots applied) at t, then F, τ
    forces(sys, values[0], w)
    F, tau = w[5], w[6]
    for i in range(len(sys.mass)):
        x, R, P, L = state_of(Y, i)       # a pivoted body's x and P: set by constrain_state below
        I, I_inv = mat(sys.I, i), mat(sys.I_inv, i)
        Lb = matvec(transpose(R), axpy(L, h, vec(tau, i)))
        w1 = matvec(I_inv, Lb)
        Iw1 = matvec(I, w1)
        J = mat_axpy(I, h, mat_axpy(matmul(star(w1), I), -1.0, star(Iw1)))
        w2 = sub(w1, solve3(J, scale(h, cross(w1, Iw1))))
        R1 = retract(matmul(R, exp_so3(scale(h, w2))))
        P1 = axpy(P, h, vec(F, i))
        put_state(out, i, drift(x, h, P1, sys.mass[i]), R1, P1, matvec(R1, matvec(I, w2)))
    constrain_state(sys, out)


@inline
def dexp(phi):
    """The left Jacobian of exp on so(3): d exp(φ*) = ((dexp_φ δφ)*) exp(φ*),

        dexp_φ = I + (1 − cos θ)/θ² φ* + (θ − sin θ)/θ³ φ*²,   θ = |φ|   (Taylor series for small θ)."""
    theta2 = dot(phi, phi)
    if theta2 < 1e-8:
        b = 0.5 - theta2 / 24.0
        c = 1.0 / 6.0 - theta2 / 120.0
    else:
        theta = np.sqrt(theta2)
        b = (1.0 - np.cos(theta)) / theta2
        c = (theta - np.sin(theta)) / (theta2 * theta)
    K = star(phi)
    return mat_axpy(mat_axpy(identity(), b, K), c, matmul(K, K))


@njit
def implicit_midpoint_step(sys, values, opts, Y, out, h, K, U, w):
    """Implicit midpoint rule on the world momenta, R turned by the exponential of the midpoint rate:

        L' = L + h τ̄,   P' = P + h F̄,   x' = x + h P̄/M,   R' = R exp(h ω̄*),
        ω̄ = I⁻¹ L̄_b,  L̄_b = (Rᵀ L + R'ᵀ L')/2   (body axes, I about the rotation centre)

    F̄, τ̄ at the midpoint (t + h/2: values[0], node 0.5): x̄ = x + h P̄/(2M), R̄ = R exp(h ω̄*/2) (the same
    seen from either end: R' exp(−h ω̄*/2)), L̄ = (L + L')/2, the pivots applied.  The torque enters the
    world L unturned: a torque with no vertical part (gravity on a top, about its pivot) leaves L_z exactly
    as it was, and the step commutes with rotations about the vertical (Noether: L_z kept to rounding).
    In R's axes (L_b = Rᵀ L, T = Rᵀ τ̄) the unknown is L_b' = R'ᵀ L':

        G(L_b') = L_b' − exp(−h ω̄*) (L_b + h T) = 0

    solved by Newton's method with ∂G/∂L_b' = I − h/2 (exp(−h ω̄*) (L_b + h T))* dexp(−h ω̄) I⁻¹ (the midpoint
    forces, evaluated again at each iteration, held in the derivative), P' by the fixed point P' = P + h F̄,
    for every body at once; it stops when max|ΔL_b| + max|ΔP| <= tol (1 + max|L_b'| + max|P'|), after at
    most max_iter iterations (opts = (tol, max_iter), or TOL, MAX_ITER when opts is empty).  If it has not
    settled then (its last change above FAIL (1 + max|L_b'| + max|P'|), or not finite), the step has no
    usable solution: its result is NaN and the run stops there with SimulationDiverged, the steps before kept.
    A free body (τ̄ = 0): L' = L, and L_b' = exp(−h ω̄*) L_b turns about ω̄ = I⁻¹ L̄_b, so the world L, |L| and
    the energy ½ L_b·I⁻¹L_b (ΔT = ω̄·ΔL_b = 0) are kept to rounding, R on SO(3); the rotation angle per step
    is h|ω̄| (a Cayley update, 2 atan(h|ω̄|/2), would slow a fast spin: at h|ω| = 2 by 21 %).
    Order 2, symmetric (a step of −h undoes a step of h).
    Scratch: K[0] holds per body L_b (cols 0–2), L_b' (3–5), P' (6–8); U the midpoint state; out the
    (constrained) start state until the body's result is written."""
    tol, max_iter = TOL, MAX_ITER
    if opts.shape[0] >= 2:
        tol, max_iter = opts[0], int(opts[1])
    n = len(sys.mass)
    W = K[0]
    copy_into(out, Y)                     # X: the start state, pivots applied (as scene.constrain leaves it)
    constrain_state(sys, out)
    for i in range(n):
        x, R, P, L = state_of(out, i)
        Lb = matvec(transpose(R), L)
        for c in range(3):
            W[i, c], W[i, 3 + c], W[i, 6 + c] = Lb[c], Lb[c], P[c]
    with_forces = forced(sys)
    change, size = np.inf, 0.0
    for _ in range(max_iter):
        if with_forces:                   # the midpoint state of every body, then its forces
            for i in range(n):
                x, R, P, L = state_of(out, i)
                Lb0, Lb1 = (W[i, 0], W[i, 1], W[i, 2]), (W[i, 3], W[i, 4], W[i, 5])
                a = scale(h, matvec(mat(sys.I_inv, i), scale(0.5, add(Lb0, Lb1))))
                Pbar = scale(0.5, add(P, (W[i, 6], W[i, 7], W[i, 8])))
                Rbar = matmul(R, exp_so3(scale(0.5, a)))
                Lbar = scale(0.5, add(L, matvec(matmul(R, exp_so3(a)), Lb1)))
                put_state(U, i, drift(x, 0.5 * h, Pbar, sys.mass[i]), Rbar, Pbar, Lbar)
            kinematics_matrix(sys, U, w)
            forces(sys, values[0], w)
        dL_max, dP_max, L_max, P_max = 0.0, 0.0, 0.0, 0.0
        for i in range(n):
            x, R, P, L = state_of(out, i)
            I_inv = mat(sys.I_inv, i)
            Lb0, Lb1, P1 = (W[i, 0], W[i, 1], W[i, 2]), (W[i, 3], W[i, 4], W[i, 5]), (W[i, 6], W[i, 7], W[i, 8])
            phi = scale(-h, matvec(I_inv, scale(0.5, add(Lb0, Lb1))))
            v = Lb0
            P_new = P
            if with_forces:
                v = axpy(Lb0, h, matvec(transpose(R), vec(w[6], i)))
                P_new = axpy(P, h, vec(w[5], i))
            turned = matvec(exp_so3(phi), v)
            G = sub(Lb1, turned)
            J = mat_axpy(identity(), -0.5 * h, matmul(matmul(star(turned), dexp(phi)), I_inv))
            dL = solve3(J, scale(-1.0, G))
            Lb1 = add(Lb1, dL)
            for c in range(3):
                dL_max = max(dL_max, abs(dL[c]))
                dP_max = max(dP_max, abs(P_new[c] - P1[c]))
                L_max = max(L_max, abs(Lb1[c]))
                P_max = max(P_max, abs(P_new[c]))
                W[i, 3 + c], W[i, 6 + c] = Lb1[c], P_new[c]
        change, size = dL_max + dP_max, 1.0 + L_max + P_max
        if change <= tol * size:
            break
    if not change <= FAIL * size:         # no solution found (or NaN): the run stops here, clearly
        fill(out, np.nan)
        return
    for i in range(n):
        x, R, P, L = state_of(out, i)
        Lb1, P1 = (W[i, 3], W[i, 4], W[i, 5]), (W[i, 6], W[i, 7], W[i, 8])
        a = scale(h, matvec(mat(sys.I_inv, i), scale(0.5, add((W[i, 0], W[i, 1], W[i, 2]), Lb1))))
        R1 = retract(matmul(R, exp_so3(a)))
        L1 = axpy(L, h, vec(w[6], i)) if with_forces else L
        put_state(out, i, drift(x, h * 0.5, add(P, P1), sys.mass[i]), R1, P1, L1)
    constrain_state(sys, out)
