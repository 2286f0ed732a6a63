"""Contact with the ground z = height, per body, compiled (Baraff 2001, notes part II, "Nonpenetration").

For body i, with n = (0, 0, 1), its contact points ρ_k = r_k − x (world axes), v = P/M, I⁻¹ = R I⁻¹_body Rᵀ,
ω = I⁻¹ L, the velocity of point k u_k = v + ω × ρ_k, its normal part u_n = n·u_k, its gap z_k − height:

* a point is in contact if gap + min(u_n, 0) Δt <= CONTACT_TOL;
* its target normal velocity: colliding (u_n < −ε, ε = REST_SPEED + 2 g Δt): −e u_n; else (resting) what
  just reaches the plane in Δt, −max(gap, 0)/Δt;
* an impulse j_l at point l changes u_k by W_kl j_l, W_kl = Id/M − ρ_k* I⁻¹ ρ_l*;  the impulses
  j_k (u_n >= target, j_n >= 0, |j_t| <= μ j_n, Coulomb) are solved in modes: sticking (u_k = target n,
  j_k free), sliding along s_k (u_n = target, j_k = j_n (n − μ s_k)), off (j_k = 0), corrected and solved
  again (MODE_PASSES at most: the most negative j_n goes off; |j_t| > μ j_n slides against j_t; a slide that
  stopped, u·s <= 0, sticks; an off point still approaching comes on); a body whose modes do not settle
  finishes by projected Gauss–Seidel sweeps;
* P ← P + Σ j_k,  L ← L + Σ ρ_k × j_k;
* position: the penetrating points' depths are removed by a pseudo-impulse j_p with the same response
  (frictionless, target depth/Δt from rest): x ← x + Δt Σ j_p/M, R ← exp(Δt I⁻¹ Σ ρ × j_p) R, then x_z lifted
  by what is left (O(Δt²));
* no energy gain: if T + U is above its value before, P and L are scaled by √(1 − excess/T).

Each mode solve is one small linear system A y = b (the kept equations D_k u_k = D_k goal_k in the unknowns
y of the modes' impulses), A = B C with B = D G (p×6: the kept velocities from the body's 6 velocities)
and C = H E (6×p: the body's response to the unknowns), solved in the least-squares, least-norm sense,
y = A⁺ b, by least_norm.min_norm_solve (two 6×6 Cholesky solves, or a Jacobi SVD where A is rank-deficient) —
or, where every unknown pushes along its own kept velocity (every point sticking, or μ = 0: frictionless, the
lift), C = 𝓜⁻¹ Bᵀ is not even built: symmetric.symmetric_solve gives the same A⁺ b from one Gram matrix.

The contact points ρ_k of each shape (BOX, CYLINDER, ELLIPSOID) are contact_points.py's.

Scratch arrays come in a Work (work(N)), allocated once per run: nothing is allocated here.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .algebra import add, cross, dot, exp_so3, matmul, matvec, quat_multiply, quat_of_rotation, scale, star
from .contact_points import BOX, CYLINDER, ELLIPSOID, K_MAX, contact_point, n_points   # noqa: F401  (the shapes)
from .jit import hot, inline, njit, unrolled
from .least_norm import DIRECT, NOT_FINITE, SVD, min_norm_solve   # noqa: F401  (how a mode system was solved)
from .symmetric import symmetric_solve
from .motion import inverse_inertia, kinetic_energy, potential, put, put_state, state_of, vec

CONTACT_TOL = 1e-6     # m: a point this close above the plane counts as touching
REST_SPEED = 0.01      # m/s: ε = REST_SPEED + 2 g Δt, below which contact is resting (no restitution)
MODE_PASSES = 8        # exact solves with corrected contact modes, at most
MAX_SWEEPS = 20        # then Gauss–Seidel sweeps, at most ...
SWEEP_TOL = 1e-6       # ... until no impulse changes by more than this fraction of the largest one

P_MAX = 3 * K_MAX                      # unknowns of a mode system, at most

OFF, STICK, SLIDE = 0, 1, 2            # the modes


class Work(NamedTuple):
    """Scratch for the solver (work(N)): one body's points and its mode system, and the N bodies' flags."""
    rho: np.ndarray       # (K_MAX, 3) the active points' ρ (world axes)
    u0: np.ndarray        # (K_MAX, 3) their velocities before
    target: np.ndarray    # (K_MAX,) their target normal velocities
    slot: np.ndarray      # (K_MAX,) int: the body's slot of each active point
    mode: np.ndarray      # (K_MAX,) int: OFF, STICK, SLIDE
    s: np.ndarray         # (K_MAX, 3) the sliding directions
    J: np.ndarray         # (K_MAX, 3) the impulses
    depth: np.ndarray     # (K_MAX,) how deep each active point is below the plane
    point: np.ndarray     # (P_MAX,) int: the point of each unknown / kept equation
    comp: np.ndarray      # (P_MAX,) int: its component (0, 1, 2)
    B: np.ndarray         # (P_MAX, 6)
    C: np.ndarray         # (6, P_MAX)
    A: np.ndarray         # (P_MAX, P_MAX)
    V: np.ndarray         # (P_MAX, P_MAX)
    b: np.ndarray         # (P_MAX,)
    y: np.ndarray         # (P_MAX,)
    Q: np.ndarray         # (2, 6, 6) the Gram matrices
    F: np.ndarray         # (3, 6, 6) products and factors
    z: np.ndarray         # (2, 6)
    at: np.ndarray        # (6,) int: the place of each used column of B in the Gram matrices, −1 if unused
    touched: np.ndarray   # (N,) int: 1 for a body whose state this ground's contact changed
    changed: np.ndarray   # (N,) int: 1 for a body whose state any ground's contact changed
    turn: np.ndarray      # (N, 4) the quaternion the lifts turned each body by (1, 0, 0, 0): none)
    S: np.ndarray         # (N, 18) a quaternion state read as the slides' S
    S0: np.ndarray        # (N, 18) the state before


def work(n: int) -> Work:
    """The solver's scratch for n bodies (Python side, once per run)."""
    f = np.zeros
    return Work(f((K_MAX, 3)), f((K_MAX, 3)), f(K_MAX), np.zeros(K_MAX, np.int64), np.zeros(K_MAX, np.int64),
                f((K_MAX, 3)), f((K_MAX, 3)), f(K_MAX), np.zeros(P_MAX, np.int64), np.zeros(P_MAX, np.int64),
                f((P_MAX, 6)), f((6, P_MAX)), f((P_MAX, P_MAX)), f((P_MAX, P_MAX)), f(P_MAX), f(P_MAX),
                f((2, 6, 6)), f((3, 6, 6)), f((2, 6)), np.zeros(6, np.int64), np.zeros(n, np.int64), np.zeros(n, np.int64), f((n, 4)),
                f((n, 18)), f((n, 18)))


# --- the impulses --------------------------------------------------------------------------------------

@inline
def response(j, rho, M, I_inv):
    """(Δv, Δω) = (j/M, I⁻¹ (ρ × j)): the body's response to an impulse j at ρ."""
    return scale(1.0 / M, j), matvec(I_inv, cross(rho, j))


@inline
def beyond(jx, jy, limit):
    """|j_t| = hypot(jx, jy) > limit: hypot (a call to libm) only where its bound |jx| + |jy| is beyond too
    (a point well inside its friction cone, the usual case, costs two additions)."""
    return abs(jx) + abs(jy) > limit and math.hypot(jx, jy) > limit


@inline
def slide_direction(s, mu):
    """The impulse of a sliding point per unit j_n: n − μ s."""
    return (-mu * s[0], -mu * s[1], 1.0 - mu * s[2])


@hot
def solve_modes(w, n, M, I_inv, mu):
    """One mode pass on the n active points (w.mode, w.s): w.J := the impulses of the modes' system, the
    modes corrected.  Returns 1 if a mode changed, 0 if not, −1 if the system is not finite."""
    p = 0
    for k in range(n):
        if w.mode[k] == STICK:
            for c in range(3):
                w.point[p], w.comp[p] = k, c
                p += 1
        elif w.mode[k] == SLIDE:
            w.point[p], w.comp[p] = k, 2
            p += 1
    symmetric = True                    # each unknown pushes along its own kept velocity: C = 𝓜⁻¹ Bᵀ
    for r in range(p):
        k, c = w.point[r], w.comp[r]
        rho = vec(w.rho, k)
        # kept equation: component c of u_k = v + ω × ρ_k = G_k (v, ω), G_k = [Id, −ρ_k*]
        g = (-star(rho)[c][0], -star(rho)[c][1], -star(rho)[c][2])
        w.B[r, 0], w.B[r, 1], w.B[r, 2] = 1.0 if c == 0 else 0.0, 1.0 if c == 1 else 0.0, 1.0 if c == 2 else 0.0
        w.B[r, 3], w.B[r, 4], w.B[r, 5] = g[0], g[1], g[2]
        goal = w.target[k] if c == 2 else 0.0
        w.b[r] = goal - w.u0[k, c]
        symmetric = symmetric and (w.mode[k] == STICK or mu == 0.0)
    for k in range(n):
        put(w.J, k, (0.0, 0.0, 0.0))
    how = symmetric_solve(w, p, M, I_inv) if symmetric and p > 0 else SVD
    if how == SVD and p > 0:
        for r in range(p):
            # unknown r: the impulse direction of its mode, and the body's response to it
            k, c = w.point[r], w.comp[r]
            if w.mode[k] == STICK:
                j = (1.0 if c == 0 else 0.0, 1.0 if c == 1 else 0.0, 1.0 if c == 2 else 0.0)
            else:
                j = slide_direction(vec(w.s, k), mu)
            dv, dw = response(j, vec(w.rho, k), M, I_inv)
            w.C[0, r], w.C[1, r], w.C[2, r] = dv[0], dv[1], dv[2]
            w.C[3, r], w.C[4, r], w.C[5, r] = dw[0], dw[1], dw[2]
        how = min_norm_solve(w, p)
    if how == NOT_FINITE:
        return -1
    for r in range(p):
        k, c = w.point[r], w.comp[r]
        if w.mode[k] == STICK:
            w.J[k, c] = w.y[r]
        else:
            put(w.J, k, scale(w.y[r], slide_direction(vec(w.s, k), mu)))
    # the velocities after, and the corrections
    P_, Lr = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    big_j, big_u, jn_min = 0.0, 0.0, math.inf
    for k in range(n):
        j = vec(w.J, k)
        P_ = add(P_, j)
        Lr = add(Lr, cross(vec(w.rho, k), j))
        big_j = max(big_j, abs(j[0]), abs(j[1]), abs(j[2]))
        big_u = max(big_u, abs(w.u0[k, 0]), abs(w.u0[k, 1]), abs(w.target[k] - w.u0[k, 2]))
        if w.mode[k] != OFF:
            jn_min = min(jn_min, j[2])
    dv, dw = scale(1.0 / M, P_), matvec(I_inv, Lr)
    tol_j, tol_u = 1e-9 * big_j + 1e-300, 1e-9 * big_u + 1e-300
    changed = 0
    for k in range(n):
        j = vec(w.J, k)
        u = add(add(vec(w.u0, k), dv), cross(dw, vec(w.rho, k)))
        m = w.mode[k]
        off = m != OFF and j[2] == jn_min and j[2] < -tol_j
        if off:
            w.mode[k] = OFF
        elif m == STICK and beyond(j[0], j[1], mu * j[2] + tol_j):          # slides against j_t
            w.mode[k] = SLIDE
            d = max(math.sqrt(j[0] * j[0] + j[1] * j[1]), 1e-300)
            put(w.s, k, (-j[0] / d, -j[1] / d, -0.0 / d))
        elif m == SLIDE and mu > 0.0 and dot(u, vec(w.s, k)) <= tol_u:   # stopped: sticks
            w.mode[k] = STICK
        elif m == OFF and u[2] < w.target[k] - tol_u:              # approaching: on
            w.mode[k] = STICK if mu > 0.0 else SLIDE
        else:
            continue
        changed = 1
    return changed


@njit
def sweeps(w, n, v, omega, M, I_inv, mu):
    """Projected Gauss–Seidel from w.J: sweeps over the points (forward, backward: no bias to one corner),
    each impulse projected on j_n >= 0 and |j_t| <= μ j_n, until none changes by more than SWEEP_TOL of the
    largest:  j_n ← max(j_n + (target − u_n)/W_kk,nn, 0);  j_t ← j_t − |u_t| d/(d·W_kk,tt d), d = u_t/|u_t|."""
    for k in range(n):
        j = vec(w.J, k)
        v, omega = (v[0] + j[0] / M, v[1] + j[1] / M, v[2] + j[2] / M), add(omega, matvec(I_inv, cross(vec(w.rho, k), j)))
    for sweep in range(MAX_SWEEPS):
        change = 0.0
        for kk in range(n):
            k = kk if sweep % 2 == 0 else n - 1 - kk
            rho = vec(w.rho, k)
            Sr = star(rho)
            W = matmul(Sr, matmul(I_inv, Sr))                  # W_kk = Id/M − ρ* I⁻¹ ρ*
            W = ((1.0 / M - W[0][0], -W[0][1], -W[0][2]), (-W[1][0], 1.0 / M - W[1][1], -W[1][2]),
                 (-W[2][0], -W[2][1], 1.0 / M - W[2][2]))
            u = add(v, cross(omega, rho))
            J0 = vec(w.J, k)
            jn = max(J0[2] + (w.target[k] - u[2]) / W[2][2], 0.0)
            djn = jn - J0[2]
            jx, jy = J0[0], J0[1]
            if mu > 0.0:
                ux, uy = u[0] + W[0][2] * djn, u[1] + W[1][2] * djn
                speed = math.hypot(ux, uy)
                if speed > 0.0:
                    dx, dy = ux / speed, uy / speed
                    stop = speed / (dx * (W[0][0] * dx + W[0][1] * dy) + dy * (W[1][0] * dx + W[1][1] * dy))
                    jx, jy = jx - stop * dx, jy - stop * dy
                size = math.hypot(jx, jy)
                f = min(1.0, mu * jn / max(size, 1e-300))
                jx, jy = jx * f, jy * f
            else:
                jx, jy = 0.0, 0.0
            dj = (jx - J0[0], jy - J0[1], djn)
            put(w.J, k, add(J0, dj))
            v = (v[0] + dj[0] / M, v[1] + dj[1] / M, v[2] + dj[2] / M)
            omega = add(omega, matvec(I_inv, cross(rho, dj)))
            change = max(change, abs(dj[0]), abs(dj[1]), abs(dj[2]))
        big = 0.0
        for k in range(n):
            big = max(big, abs(w.J[k, 0]), abs(w.J[k, 1]), abs(w.J[k, 2]))
        if not change > SWEEP_TOL * big:
            break


@hot
def impulses(w, n, v, omega, M, I_inv, mu):
    """w.J := the impulses at the n active points (w.rho, w.u0, w.target): u_n >= target, j_n >= 0,
    |j_t| <= μ j_n — mode passes, projected on the cones, then sweeps if the modes did not settle.
    False if the system is not finite."""
    for k in range(n):
        w.mode[k] = STICK if mu > 0.0 else SLIDE
        put(w.s, k, (0.0, 0.0, 0.0))
    changed = 1
    for _ in range(MODE_PASSES):
        changed = solve_modes(w, n, M, I_inv, mu)
        if changed < 0:
            return False
        if changed == 0:
            break
    for k in range(n):                                           # projected on the cones
        jn = max(w.J[k, 2], 0.0)
        f = 0.0 if mu == 0.0 else 1.0 if not beyond(w.J[k, 0], w.J[k, 1], mu * jn) else \
            min(1.0, mu * jn / max(math.hypot(w.J[k, 0], w.J[k, 1]), 1e-300))
        w.J[k, 0], w.J[k, 1], w.J[k, 2] = w.J[k, 0] * f, w.J[k, 1] * f, jn
    if changed:
        sweeps(w, n, v, omega, M, I_inv, mu)
    return True


# --- a body, and the N bodies ------------------------------------------------------------------------------

@hot
def resolve_body(S, S0, i, sys, shape, half, axes, height, e, mu, g, dt, w):
    """Body i's contact (S0 before, S := after): 0 if it does not touch, 1 if it does, −1 if its system
    is not finite."""
    x, R, P, L = state_of(S0, i)
    M = sys.mass[i]
    Ib = ((sys.I_inv[i, 0, 0], sys.I_inv[i, 0, 1], sys.I_inv[i, 0, 2]),
          (sys.I_inv[i, 1, 0], sys.I_inv[i, 1, 1], sys.I_inv[i, 1, 2]),
          (sys.I_inv[i, 2, 0], sys.I_inv[i, 2, 1], sys.I_inv[i, 2, 2]))
    I_inv = inverse_inertia(R, Ib)
    v, omega = (P[0] / M, P[1] / M, P[2] / M), matvec(I_inv, L)
    eps = REST_SPEED + 2.0 * g * dt
    n, deep = 0, False
    K = n_points(shape)
    for k in range(K):
        rho = contact_point(shape, R, half, axes, k)
        u = add(v, cross(omega, rho))
        gap = x[2] + rho[2] - height
        if gap + min(u[2], 0.0) * dt <= CONTACT_TOL:
            put(w.rho, n, rho)
            put(w.u0, n, u)
            w.target[n] = -e * u[2] if u[2] < -eps else -max(gap, 0.0) / dt
            w.depth[n] = max(-gap, 0.0)
            deep = deep or gap < 0.0
            w.slot[n] = k
            n += 1
    if n == 0:
        return 0
    P1, L1, x1, R1 = P, L, x, R
    zero = (0.0, 0.0, 0.0)
    for lift in range(2 if deep else 1):
        # 0: the impulses;  1 (a point below the plane): the lift, frictionless pseudo-impulses from rest
        # that move each point up by its depth in Δt  (one call of impulses for both: compiled once)
        if lift:
            for k in range(n):
                put(w.u0, k, zero)
                w.target[k] = w.depth[k] / dt
        if not impulses(w, n, zero if lift else v, zero if lift else omega, M, I_inv, 0.0 if lift else mu):
            return -1
        sj, st = zero, zero                  # Σ j_k, Σ ρ_k × j_k
        for k in range(n):
            j = vec(w.J, k)
            sj, st = add(sj, j), add(st, cross(vec(w.rho, k), j))
        if not lift:
            P1, L1 = add(P, sj), add(L, st)
            continue
        phi = scale(dt, matvec(I_inv, st))
        turn = exp_so3(phi)
        t = (w.turn[i, 0], w.turn[i, 1], w.turn[i, 2], w.turn[i, 3])
        t = quat_multiply(quat_of_rotation(phi), t)
        w.turn[i, 0], w.turn[i, 1], w.turn[i, 2], w.turn[i, 3] = t[0], t[1], t[2], t[3]
        x1 = (x[0] + dt * sj[0] / M, x[1] + dt * sj[1] / M, x[2] + dt * sj[2] / M)
        R1 = matmul(turn, R)
        low = 0.0                       # what is left below the plane, O(Δt²): every point, turned
        for k in range(K):
            z = x1[2] + matvec(turn, contact_point(shape, R, half, axes, k))[2] - height
            low = min(low, z)
        x1 = (x1[0], x1[1], x1[2] - low)
    put_state(S, i, x1, R1, P1, L1)
    return 1


@hot
def no_energy_gain(S, S0, i, sys):
    """Body i's P and L scaled by √(1 − excess/T) if its T + U went up from S0 to S (the lift, round-off)."""
    x0, R0, P0, L0 = state_of(S0, i)
    x1, R1, P1, L1 = state_of(S, i)
    Ib = ((sys.I_inv[i, 0, 0], sys.I_inv[i, 0, 1], sys.I_inv[i, 0, 2]),
          (sys.I_inv[i, 1, 0], sys.I_inv[i, 1, 1], sys.I_inv[i, 1, 2]),
          (sys.I_inv[i, 2, 0], sys.I_inv[i, 2, 1], sys.I_inv[i, 2, 2]))
    M = sys.mass[i]
    T0, T1 = kinetic_energy(R0, P0, L0, M, Ib), kinetic_energy(R1, P1, L1, M, Ib)
    excess = T1 + potential(sys, S, i) - T0 - potential(sys, S0, i)
    if not excess > 0.0:
        return
    lose = excess / T1 if T1 > 0.0 else 1.0
    f = math.sqrt(min(max(1.0 - lose, 0.0), 1.0))
    put_state(S, i, x1, R1, scale(f, P1), scale(f, L1))


@unrolled
def resolve(S, S0, sys, g, dt, w):
    """The contacts of ground g of the System (sys.grounds[g] = height, e, μ, gravity; its bodies' rows
    sys.first[g] … sys.first[g + 1] − 1 of contact_body, contact_shape (BOX, CYLINDER, ELLIPSOID),
    contact_half (a cylinder: radius, radius, half height), contact_axes (ellipsoids)), in place on
    S (N, 18) = [x, R row by row, P, L] (S0: scratch, the state before); sys also gives mass, I_inv and the
    effects whose potential counts.  Returns how many bodies touched (w.touched), or −1 if a contact system
    is not finite (a state that is no longer physical)."""
    for r in range(S.shape[0]):
        w.touched[r] = 0
        for c in range(18):
            S0[r, c] = S[r, c]
    height, e, mu, grav = sys.grounds[g, 0], sys.grounds[g, 1], sys.grounds[g, 2], sys.grounds[g, 3]
    touched = 0
    for a in range(sys.first[g], sys.first[g + 1]):
        i = sys.contact_body[a]
        half, axes = sys.contact_half[a], sys.contact_axes[a]
        h = (half[0], half[1], half[2])
        Ax = ((axes[0, 0], axes[0, 1], axes[0, 2]), (axes[1, 0], axes[1, 1], axes[1, 2]),
              (axes[2, 0], axes[2, 1], axes[2, 2]))
        status = resolve_body(S, S0, i, sys, sys.contact_shape[a], h, Ax, height, e, mu, grav, dt, w)
        if status < 0:
            return -1
        w.touched[i] = status
        touched += status
    if touched:
        for i in range(S.shape[0]):
            if w.touched[i]:
                no_energy_gain(S, S0, i, sys)
                w.changed[i] = 1
    return touched
