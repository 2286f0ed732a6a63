"""The implicit methods on the kernel's arrays: implicit_gyro, implicit_midpoint.

Both step the slides' state S (N, 18) = [x, R (row by row), P, L] (layout MATRIX), L about the rotation
centre (the centre of mass, or the pivot of a pivoted body), and end with the pivot constraint
(motion.constrain_state: x = p − R b, P = M ω × (x − p)).

    implicit_gyro_step      (Catto, GDC 2015; Bullet): forces at t            -> nodes (0.0,)
    implicit_midpoint_step  (midpoint on the world momenta, R′ = R exp(h ω̄*)): forces at t + h/2,
                            re-evaluated at every Newton iteration, their derivative
                            with respect to the unknowns by differences        -> nodes (0.5,)

Both take values (1, slots, 3): the forces given as functions f(t), at the one node, so values[0].

implicit_gyro uses the inertia I about the rotation centre (sys.I, body axes) and its inverse (sys.I_inv),
both from the scene.
"""
from __future__ import annotations

import numpy as np

from .algebra import (add, axpy, cross, dot, exp_so3, identity, mat_axpy, matmul, matvec, retract, scale,
                      solve3, star, sub, transpose)
from .jit import hot, inline, njit
from .motion import (constrain_state, copy_into, drift, fill, forces, kinematics_matrix, mat, put_state, stage, state_of,
                     vec)

# implicit_midpoint's Newton loop (its defaults); opts = (tol, max_iter) overrides them
TOL = 1e-15
MAX_ITER = 60
FAIL = 1e-8      # a last Newton change above FAIL (1 + size) after max_iter: no solution, the run stops
DELTA = 1.4901161193847656e-08   # √ε: the difference step of the forces' derivative, DELTA (1 + |z_c|)


@inline
def cayley(a):
    """The Cayley map, a rotation for every a (3,):

        cay(a) = (I − a*/2)⁻¹ (I + a*/2) = I + 4/(4 + |a|²) (a* + a*²/2)

    (methods/geometric.cayley, written in the tuple algebra)."""
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
    forces(sys, stage(values, 0), w)
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


@inline
def midpoint_scratch(n):
    """The slots implicit_midpoint_step needs in K beyond its one stage, for n bodies: 2n + 1 (each slot
    (n, 18)), so that K[1:] holds the Newton matrix (6n × 6n), its right-hand side (6n) and the frames
    exp(φ_i*) R_iᵀ (n × 3 × 3): 36 n² + 15 n <= 18 n (2n + 1) floats."""
    return 2 * n + 1


@hot
def midpoint_state(sys, X, W, U, i, h):
    """Body i's midpoint state into row i of U, from its start state (row i of X) and the unknowns in W
    (L_b = W[i, 0:3], L_b' = W[i, 3:6], P' = W[i, 6:9]):

        a = h I⁻¹ (L_b + L_b')/2,  P̄ = (P + P')/2,  x̄ = x + h P̄/(2M),  R̄ = R exp(a*/2),  L̄ = (L + R exp(a*) L_b')/2

    (the pivots are applied by kinematics_matrix, when the forces are evaluated)."""
    x, R, P, L = state_of(X, i)
    Lb0, Lb1 = (W[i, 0], W[i, 1], W[i, 2]), (W[i, 3], W[i, 4], W[i, 5])
    a = scale(h, matvec(mat(sys.I_inv, i), scale(0.5, add(Lb0, Lb1))))
    Pbar = scale(0.5, add(P, (W[i, 6], W[i, 7], W[i, 8])))
    Rbar = matmul(R, exp_so3(scale(0.5, a)))
    Lbar = scale(0.5, add(L, matvec(matmul(R, exp_so3(a)), Lb1)))
    put_state(U, i, drift(x, 0.5 * h, Pbar, sys.mass[i]), Rbar, Pbar, Lbar)


@inline
def rotor_residual(h, I_inv, Lb0, Lb1, v):
    """The rotation's equation of one body and its derivative with v held fixed (v = L_b + h Rᵀ τ̄):

        G_L = L_b' − exp(φ*) v,   φ = −h I⁻¹ (L_b + L_b')/2,
        ∂G_L/∂L_b' = I − h/2 (exp(φ*) v)* dexp(φ) I⁻¹      (d exp(φ*) v = −(exp(φ*) v)* dexp(φ) dφ)

    -> (G_L, ∂G_L/∂L_b', exp(φ*))."""
    phi = scale(-h, matvec(I_inv, scale(0.5, add(Lb0, Lb1))))
    E = exp_so3(phi)
    turned = matvec(E, v)
    G = sub(Lb1, turned)
    J = mat_axpy(identity(), -0.5 * h, matmul(matmul(star(turned), dexp(phi)), I_inv))
    return G, J, E


@hot
def solve_in_place(A, b):
    """b := A⁻¹ b, by Gaussian elimination with partial pivoting (A (m, m) is overwritten by its LU factors).
    False when a pivot is zero or not a number (no solution: b is left as it is)."""
    m = b.shape[0]
    for k in range(m):
        p = k
        for r in range(k + 1, m):
            if abs(A[r, k]) > abs(A[p, k]):
                p = r
        if not abs(A[p, k]) > 0.0:
            return False
        if p != k:
            for c in range(k, m):
                A[k, c], A[p, c] = A[p, c], A[k, c]
            b[k], b[p] = b[p], b[k]
        for r in range(k + 1, m):
            f = A[r, k] / A[k, k]
            if f != 0.0:
                for c in range(k + 1, m):
                    A[r, c] -= f * A[k, c]
                b[r] -= f * b[k]
    for k in range(m - 1, -1, -1):
        s = b[k]
        for c in range(k + 1, m):
            s -= A[k, c] * b[c]
        b[k] = s / A[k, k]
    return True


@hot
def midpoint_forces(sys, values, X, W, U, w, h):
    """F̄, τ̄ at the midpoint state of every body (midpoint_state), into W[i, 9:12] and W[i, 12:15]."""
    for i in range(len(sys.mass)):
        midpoint_state(sys, X, W, U, i, h)
    kinematics_matrix(sys, U, w)
    forces(sys, values, w)
    for i in range(len(sys.mass)):
        for c in range(3):
            W[i, 9 + c], W[i, 12 + c] = w[5][i, c], w[6][i, c]


@njit
def newton_forced(sys, values, X, W, U, w, h, K, tol, max_iter):
    """Newton's method on all the unknowns together, z = (L_b'_i, P'_i)_i (6N), for a scene with forces:

        G(z) = [L_b'_i − exp(φ_i*) (L_b,i + h R_iᵀ τ̄_i) ;  P'_i − P_i − h F̄_i]_i = 0,   J Δz = −G,  z += Δz

    with the whole derivative J = ∂G/∂z, recomputed at every iteration:
        its rotor part, block per body (rotor_residual: ∂G_L,i/∂L_b'_i with τ̄ held; ∂G_P,i/∂P'_i = I), plus
        the forces' part, ∂G_L,i/∂z = −h exp(φ_i*) R_iᵀ ∂τ̄_i/∂z and ∂G_P,i/∂z = −h ∂F̄_i/∂z, by forward differences
        through the midpoint state: z_c moved by δ = DELTA (1 + |z_c|), its body's midpoint state rebuilt, the
        forces of every body evaluated once -> column c.
    Cost per iteration: 1 + 6N force evaluations and a dense (6N × 6N) solve (solve_in_place, (6N)³/3 flops).
    The midpoint forces of the last evaluation are left in W[i, 9:15] (F̄, τ̄); K[1:] holds J, G and the frames
    exp(φ_i*) R_iᵀ.  -> (the last change max|ΔL_b'| + max|ΔP'|, 1 + max|L_b'| + max|P'|, the iterations)."""
    n = len(sys.mass)
    m = 6 * n
    flat = K[1:].reshape(K[1:].size)
    J = flat[:m * m].reshape((m, m))
    G = flat[m * m:m * m + m]
    ER = flat[m * m + m:m * m + m + 9 * n].reshape((n, 3, 3))
    change, size, k = np.inf, 0.0, 0
    while k < max_iter:
        k += 1
        midpoint_forces(sys, values, X, W, U, w, h)
        J[:, :] = 0.0
        for i in range(n):                # G and the rotor part of J
            x, R, P, L = state_of(X, i)
            Lb0, Lb1 = (W[i, 0], W[i, 1], W[i, 2]), (W[i, 3], W[i, 4], W[i, 5])
            v = axpy(Lb0, h, matvec(transpose(R), (W[i, 12], W[i, 13], W[i, 14])))
            GL, JL, E = rotor_residual(h, mat(sys.I_inv, i), Lb0, Lb1, v)
            ERt = matmul(E, transpose(R))
            for r in range(3):
                G[6 * i + r] = GL[r]
                G[6 * i + 3 + r] = W[i, 6 + r] - (P[r] + h * W[i, 9 + r])
                J[6 * i + 3 + r, 6 * i + 3 + r] = 1.0
                for c in range(3):
                    J[6 * i + r, 6 * i + c] = JL[r][c]
                    ER[i, r, c] = ERt[r][c]
        for j in range(n):                # the forces' part of J, one column per unknown
            for c in range(6):
                z = W[j, 3 + c]           # L_b'_j (c < 3), P'_j (c >= 3)
                W[j, 3 + c] = z + DELTA * (1.0 + abs(z))
                d = W[j, 3 + c] - z
                midpoint_state(sys, X, W, U, j, h)
                W[j, 3 + c] = z
                kinematics_matrix(sys, U, w)
                forces(sys, values, w)
                col = 6 * j + c
                for i in range(n):
                    dtau = scale(1.0 / d, sub(vec(w[6], i), (W[i, 12], W[i, 13], W[i, 14])))
                    dL = matvec(mat(ER, i), dtau)
                    for r in range(3):
                        J[6 * i + r, col] -= h * dL[r]
                        J[6 * i + 3 + r, col] -= h * (w[5][i, r] - W[i, 9 + r]) / d
            midpoint_state(sys, X, W, U, j, h)
        for r in range(m):
            G[r] = -G[r]
        if not solve_in_place(J, G):      # G := Δz
            return np.nan, 1.0, k
        dL_max, dP_max, L_max, P_max = 0.0, 0.0, 0.0, 0.0
        for i in range(n):
            for c in range(3):
                W[i, 3 + c] += G[6 * i + c]
                W[i, 6 + c] += G[6 * i + 3 + c]
                dL_max = max(dL_max, abs(G[6 * i + c]))
                dP_max = max(dP_max, abs(G[6 * i + 3 + c]))
                L_max = max(L_max, abs(W[i, 3 + c]))
                P_max = max(P_max, abs(W[i, 6 + c]))
        change, size = dL_max + dP_max, 1.0 + L_max + P_max
        if change <= tol * size:
            break
    return change, size, k


@njit
def newton_free(sys, X, W, h, tol, max_iter):
    """Newton's method body by body for a scene without forces (τ̄ = 0, P' = P: the bodies are independent):
    G_L(L_b') = L_b' − exp(φ*) L_b = 0 with its exact 3 × 3 derivative (rotor_residual), one solve3 per body
    and iteration.  -> (the last change max|ΔL_b'|, 1 + max|L_b'| + max|P'|, the iterations)."""
    n = len(sys.mass)
    change, size, k = np.inf, 0.0, 0
    while k < max_iter:
        k += 1
        dL_max, L_max, P_max = 0.0, 0.0, 0.0
        for i in range(n):
            Lb0, Lb1 = (W[i, 0], W[i, 1], W[i, 2]), (W[i, 3], W[i, 4], W[i, 5])
            GL, JL, E = rotor_residual(h, mat(sys.I_inv, i), Lb0, Lb1, Lb0)
            dL = solve3(JL, scale(-1.0, GL))
            Lb1 = add(Lb1, dL)
            for c in range(3):
                dL_max = max(dL_max, abs(dL[c]))
                L_max = max(L_max, abs(Lb1[c]))
                P_max = max(P_max, abs(W[i, 6 + c]))
                W[i, 3 + c] = Lb1[c]
        change, size = dL_max, 1.0 + L_max + P_max
        if change <= tol * size:
            break
    return change, size, k


@njit
def implicit_midpoint_step(sys, values, opts, Y, out, h, K, U, w):
    """Implicit midpoint rule on the world momenta, R turned by the exponential of the midpoint rate:

        L' = L + h τ̄,   P' = P + h F̄,   x' = x + h P̄/M,   R' = R exp(h ω̄*),
        ω̄ = I⁻¹ L̄_b,  L̄_b = (Rᵀ L + R'ᵀ L')/2   (body axes, I about the rotation centre)

    F̄, τ̄ at the midpoint (t + h/2: values[0], node 0.5): x̄ = x + h P̄/(2M), R̄ = R exp(h ω̄*/2) (the same
    seen from either end: R' exp(−h ω̄*/2)), L̄ = (L + L')/2, the pivots applied (midpoint_state).  The torque
    enters the world L unturned: a torque with no vertical part (gravity on a top, about its pivot) leaves L_z
    exactly as it was, and the step commutes with rotations about the vertical (Noether: L_z kept to rounding).
    In R's axes (L_b = Rᵀ L, T = Rᵀ τ̄) the unknowns are, per body, L_b' = R'ᵀ L' and P':

        G(L_b', P') = [L_b' − exp(−h ω̄*) (L_b + h T) ;  P' − P − h F̄] = 0

    solved by Newton's method: with forces (values given), on the 6N unknowns of all bodies together, with the
    whole derivative, the forces' part by finite differences (newton_forced: 1 + 6N force evaluations and a
    6N × 6N solve per iteration; a stiff spring, k Δt²/m = 3.9, settles in a few iterations); without forces
    body by body, 3 × 3 (newton_free).  It stops when max|ΔL_b'| + max|ΔP'| <= tol (1 + max|L_b'| + max|P'|),
    after at most max_iter iterations (opts = (tol, max_iter), or TOL, MAX_ITER when opts is empty).  If it has
    not settled then (its last change above FAIL (1 + max|L_b'| + max|P'|), or not finite), the step has no
    usable solution: its result is NaN and the run stops there with SimulationDiverged, the steps before kept.
    The result is built from the last force evaluation: L' = L + h τ̄, P' = P + h F̄ (L_z and a scene's total P
    kept to rounding), R' = R exp(h ω̄*) from the last L_b'.
    A free body (τ̄ = 0): L' = L, and L_b' = exp(−h ω̄*) L_b turns about ω̄ = I⁻¹ L̄_b, so the world L, |L| and
    the energy ½ L_b·I⁻¹L_b (ΔT = ω̄·ΔL_b = 0) are kept to rounding, R on SO(3); the rotation angle per step
    is h|ω̄| (a Cayley update, 2 atan(h|ω̄|/2), would slow a fast spin: at h|ω| = 2 by 21 %).
    Order 2, symmetric (a step of −h undoes a step of h); a linear spring's quadratic energy kept exactly.
    Scratch: K (1 + midpoint_scratch(N), N, 18); K[0] holds per body L_b (cols 0–2), L_b' (3–5), P' (6–8),
    F̄ (9–11), τ̄ (12–14), and K[0][0, 15] the iterations of the step; K[1:] newton_forced's matrix; U the
    midpoint state; out the (constrained) start state until the body's result is written."""
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
    with_forces = values is not None
    if values is not None:
        if K.shape[0] < 1 + midpoint_scratch(n):
            raise ValueError("K: implicit_midpoint needs 1 + midpoint_scratch(N) = 2N + 2 slots with forces")
        change, size, k = newton_forced(sys, stage(values, 0), out, W, U, w, h, K, tol, max_iter)
    else:
        change, size, k = newton_free(sys, out, W, h, tol, max_iter)
    W[0, 15] = k
    if not change <= FAIL * size:         # no solution found (or NaN): the run stops here, clearly
        fill(out, np.nan)
        return
    for i in range(n):
        x, R, P, L = state_of(out, i)
        Lb1 = (W[i, 3], W[i, 4], W[i, 5])
        a = scale(h, matvec(mat(sys.I_inv, i), scale(0.5, add((W[i, 0], W[i, 1], W[i, 2]), Lb1))))
        R1 = retract(matmul(R, exp_so3(a)))
        P1, L1 = P, L
        if with_forces:
            P1 = axpy(P, h, (W[i, 9], W[i, 10], W[i, 11]))
            L1 = axpy(L, h, (W[i, 12], W[i, 13], W[i, 14]))
        put_state(out, i, drift(x, h * 0.5, add(P, P1), sys.mass[i]), R1, P1, L1)
    constrain_state(sys, out)
