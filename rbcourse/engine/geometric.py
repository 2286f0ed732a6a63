"""The geometric methods on the slides' state S (N, 18) = [x, R, P, L]: R stays a rotation by construction.

    symplectic_euler  kick(h) at t, then x ← x + h v,  R ← exp(h ω*) R
    splitting         kick(h/2) at t — drift x (h), free-rotor Strang splitting (h) — kick(h/2) at t + h
    rkmk4             Runge–Kutta–Munthe-Kaas 4: the RK4 table in the Lie algebra, R(t+h) = exp(u) R(t)
                      (Munthe-Kaas 1998)

A kick changes the momenta at fixed positions, P += h F, L += h τ: stages.rk_stages with motion.rates_kick,
with the method's table (A, b, den) as arguments.  symplectic_euler kicks with EULER (one evaluation);
splitting with MIDPOINT when a force depends on the velocities (velocity_dependent), else with EULER's
one evaluation.  The splitting's axis flows use the principal moments and axes of the inertia about the
rotation centre: the System's I_moments (N, 3) and I_axes (N, 3, 3) (the axes as columns, det +1:
system.principal_axes).

Arguments (every step): sys, values (stages, slots, 3) the forces given as functions of t at the
method's nodes, opts, the table A, b, den, Y (N, 18) the state (not modified), out (N, 18) the result,
h, K (slots, N, 18) and U (N, 18) scratch, w = motion.work(N).
"""
from __future__ import annotations

from .algebra import add, cross, dot, exp_so3, matmul, matvec, retract, scale, transpose
from .jit import inline, njit
from .motion import constrain_state, copy_into, drift, dxdt, motion, put_state, rates_kick, stage, state_of, vec
from .stages import rk_stages

EULER_B = (1.0,)   # EULER's weights (its A, 1×1 and zero, is never read by a one-stage loop)


# --- kicks ------------------------------------------------------------------------------------------

@njit
def velocity_dependent(sys):
    """Does a force of the scene depend on the velocities (a damped spring, a drag: each effect says so of itself,
    its velocity_dependent, in its rows: sys.velocity)?"""
    for e in range(len(sys.velocity)):
        if sys.velocity[e]:
            return True
    return False


@njit
def kick(sys, values, A, b, den, Y, out, h, K, U, w):
    """The momenta at fixed positions (x, R): dP/dt = F, dL/dt = τ integrated over h by the table
    (A, b, den) (EULER: P += h F, L += h τ), forces at values[i] for its stage i; then the pivot
    constraint (geometric.kick).  K[0 … len(b) − 1] and U are its scratch; out may not be Y."""
    if values is not None:
        rk_stages(rates_kick, sys, values, A, b, den, Y, out, h, K, U, w)
        constrain_state(sys, out)
    else:
        copy_into(out, Y)


# --- symplectic Euler ---------------------------------------------------------------------------------

@njit
def symplectic_euler_step(sys, values, opts, A, b, den, Y, out, h, K, U, w):
    """Momenta first, then an exact rotation (semi-implicit Euler), A, b, den the EULER table:

        P ← P + h F,   L ← L + h τ                 (forces at the old positions, values[0] at t)
        x ← x + h v,   R ← retract(exp(h ω*) R),   v = P/M, ω = R I⁻¹ Rᵀ L  (the new momenta)

    opts: unused.  K: 1 slot."""
    kick(sys, values, A, b, den, Y, out, h, K, U, w)
    for i in range(out.shape[0]):
        x, R, P, L = state_of(out, i)
        x, P, v, omega = motion(sys, i, x, R, P, L)
        put_state(out, i, add(x, scale(h, v)), retract(matmul(exp_so3(scale(h, omega)), R)), P, L)
    constrain_state(sys, out)


# --- splitting ------------------------------------------------------------------------------------------

@inline
def axis_flow(sys, i, R, L, k, h):
    """Exact flow of T_k = L_k² / 2 I_k for body i: R ← R exp(θ a*), θ = h L_k / I_k, L_k = a · (Rᵀ L),
    a = the k-th principal axis (column k of sys.I_axes[i]), I_k = sys.I_moments[i, k]; the world L does
    not change."""
    a = (sys.I_axes[i, 0, k], sys.I_axes[i, 1, k], sys.I_axes[i, 2, k])
    L_k = dot(a, matvec(transpose(R), L))
    theta = h * L_k / sys.I_moments[i, k]
    return matmul(R, exp_so3(scale(theta, a)))


@inline
def free_rotor_strang(sys, i, R, L, h):
    """Strang splitting of the free rotor T = T₁ + T₂ + T₃: Φ₁(h/2) Φ₂(h/2) Φ₃(h) Φ₂(h/2) Φ₁(h/2),
    then retract (McLachlan 1993; Reich 1994; Touma & Wisdom 1994)."""
    R = axis_flow(sys, i, R, L, 0, 0.5 * h)
    R = axis_flow(sys, i, R, L, 1, 0.5 * h)
    R = axis_flow(sys, i, R, L, 2, 1.0 * h)
    R = axis_flow(sys, i, R, L, 1, 0.5 * h)
    R = axis_flow(sys, i, R, L, 0, 0.5 * h)
    return retract(R)


@njit
def splitting_step(sys, values, opts, A, b, den, Y, out, h, K, U, w):
    """Kick(h/2) at t — drift x ← x + h P/M and the free-rotor splitting (h) — kick(h/2) at t + h.

    A, b, den: the kick's table when a force depends on the velocities (MIDPOINT); otherwise each kick
    is one evaluation (EULER).  values: its first half at t (nodes 0, 0), its second half at t + h
    (nodes 1, 1).  opts: unused (the principal moments and axes are the System's I_moments, I_axes).
    K: len(b) + 1 slots (the kicks' stages, then the state between the kicks)."""
    second = None if values is None else values[values.shape[0] // 2:]
    mid = K[len(b)]
    vd = velocity_dependent(sys)
    if vd:
        kick(sys, values, A, b, den, Y, out, 0.5 * h, K, U, w)
    else:
        kick(sys, values, A, EULER_B, 1.0, Y, out, 0.5 * h, K, U, w)
    for i in range(out.shape[0]):
        x, R, P, L = state_of(out, i)
        M = sys.mass[i]
        x = drift(x, h, P, M)
        put_state(out, i, x, free_rotor_strang(sys, i, R, L, h), P, L)
    constrain_state(sys, out)
    copy_into(mid, out)
    if vd:
        kick(sys, second, A, b, den, mid, out, 0.5 * h, K, U, w)
    else:
        kick(sys, second, A, EULER_B, 1.0, mid, out, 0.5 * h, K, U, w)


# --- RK–Munthe-Kaas 4 ------------------------------------------------------------------------------

@inline
def dexp_inv(u, k):
    """dexp⁻¹_u(k) ≈ k − ½ u × k + 1/12 u × (u × k): the algebra's rate from the body's ω (to order 4)."""
    uk = cross(u, k)
    c = cross(u, uk)
    return (k[0] - 0.5 * uk[0] + c[0] / 12.0, k[1] - 0.5 * uk[1] + c[1] / 12.0, k[2] - 0.5 * uk[2] + c[2] / 12.0)


@inline
def increment(A, K, i, p, q, h):
    """h Σ_{j<i} a_ij K[j, p, q:q+3]: stage i's increment of a 3-vector of body p."""
    a0, a1, a2 = 0.0, 0.0, 0.0
    for j in range(i):
        a0 += A[i, j] * K[j, p, q]
        a1 += A[i, j] * K[j, p, q + 1]
        a2 += A[i, j] * K[j, p, q + 2]
    return (h * a0, h * a1, h * a2)


@inline
def weighted(b, den, K, p, q, h):
    """h/den Σ_i b_i K[i, p, q:q+3]: the step's increment of a 3-vector of body p."""
    a0, a1, a2 = 0.0, 0.0, 0.0
    for i in range(len(b)):
        a0 += b[i] * K[i, p, q]
        a1 += b[i] * K[i, p, q + 1]
        a2 += b[i] * K[i, p, q + 2]
    s = h / den
    return (s * a0, s * a1, s * a2)


@njit
def rkmk4_step(sys, values, opts, A, b, den, Y, out, h, K, U, w):
    """Runge–Kutta–Munthe-Kaas on SO(3) with the table A, b, den (RK4), values[i] at t + c_i h:

        stage i: (u_i, Δx_i, ΔP_i, ΔL_i) = h Σ_j a_ij k_j,  R_i = exp(u_i) R,
                 k_i = (dexp⁻¹_{u_i}(ω_i), v_i, F_i, τ_i)  at (x + Δx_i, R_i, P + ΔP_i, L + ΔL_i)
        R(t + h) = retract(exp(u) R),  u = h/den Σ b_i k̃_i;  x, P, L: the ordinary RK increments.

    The stage state is not Y plus a combination of the K (R_i = exp(u_i) R), so stages.rk_stages cannot
    run it: this is its loop.  K[i] (N, 18) holds k_i in the MATRIX layout, the algebra's rate k̃_i in
    the slots of R's first row (3:6).  Stage i's state is built in U, its rates by motion.dxdt
    (then ω_i read from w).  opts: unused.  K: len(b) slots."""
    n = Y.shape[0]
    for i in range(len(b)):
        for p in range(n):
            x, R, P, L = state_of(Y, p)
            put_state(U, p, add(x, increment(A, K, i, p, 0, h)), matmul(exp_so3(increment(A, K, i, p, 3, h)), R),
                      add(P, increment(A, K, i, p, 12, h)), add(L, increment(A, K, i, p, 15, h)))
        dxdt(sys, stage(values, i), U, K[i], w)
        for p in range(n):
            k = dexp_inv(increment(A, K, i, p, 3, h), vec(w[3], p))
            K[i, p, 3], K[i, p, 4], K[i, p, 5] = k[0], k[1], k[2]
    for p in range(n):
        x, R, P, L = state_of(Y, p)
        put_state(out, p, add(x, weighted(b, den, K, p, 0, h)), retract(matmul(exp_so3(weighted(b, den, K, p, 3, h)), R)),
                  add(P, weighted(b, den, K, p, 12, h)), add(L, weighted(b, den, K, p, 15, h)))
    constrain_state(sys, out)
