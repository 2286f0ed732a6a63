"""The physics of the slides, written once, for one body at a time (compiled by numba, or run as Python).

For body i (slide "Evolution temporelle (Euler)", and "Les Formules"):

    v = P / M,   I⁻¹(t) = R I⁻¹_body Rᵀ,   ω = I⁻¹(t) L
    F = Σ Fⱼ,    τ = Σ (rⱼ − x) × Fⱼ (+ pure torques)       over the scene's effects only
    dX/dt = (v, ω* R, F, τ)

A pivoted body turns about its pivot p: L and I_body are about p, x = p − R b and P = M ω × (x − p)
follow from R and L, and torques are taken about p.  N bodies are a loop over the same functions.
Arrays hold the N bodies (x (N, 3), R (N, 3, 3), ...); a body's vectors are read out as tuples
(algebra.py).  `values` (slots, 3) holds the forces given as functions f(t), evaluated by the driver.
"""
from __future__ import annotations

import numpy as np

from .algebra import add, axpy, cross, dot, matmul, matvec, norm, scale, star, sub, transpose
from .jit import hot, inline, njit
from .system import ANGULAR_DRAG, EVERY, GRAVITY, LINEAR_DRAG, POINT_FORCE, SPRING


# --- a body's vectors in and out of the arrays -----------------------------------------------

@inline
def vec(a, i):
    """Row i of an (N, 3) array, as a vector."""
    return (a[i, 0], a[i, 1], a[i, 2])


@inline
def mat(A, i):
    """Matrix i of an (N, 3, 3) array."""
    return ((A[i, 0, 0], A[i, 0, 1], A[i, 0, 2]), (A[i, 1, 0], A[i, 1, 1], A[i, 1, 2]),
            (A[i, 2, 0], A[i, 2, 1], A[i, 2, 2]))


@inline
def put(a, i, v):
    """Row i of an (N, 3) array := v."""
    a[i, 0], a[i, 1], a[i, 2] = v[0], v[1], v[2]


@inline
def put_mat(A, i, M):
    """Matrix i of an (N, 3, 3) array := M."""
    for r in range(3):
        A[i, r, 0], A[i, r, 1], A[i, r, 2] = M[r][0], M[r][1], M[r][2]


@inline
def accumulate(a, i, v):
    """Row i of an (N, 3) array += v."""
    a[i, 0] += v[0]
    a[i, 1] += v[1]
    a[i, 2] += v[2]


@hot
def fill(a, value):
    """Every entry of the (N, 3) array a := value."""
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            a[i, j] = value


@hot
def copy_into(dst, src):
    """dst (N, m) := src (N, m), both contiguous: one loop over their N m numbers."""
    d, s = dst.reshape(-1), src.reshape(-1)
    for k in range(d.size):
        d[k] = s[k]


# --- the derived quantities (slide "Evolution temporelle (Euler)") ------------------------------

@inline
def velocity(P, M):
    """v = P / M"""
    return (P[0] / M, P[1] / M, P[2] / M)


@inline
def drift(x, h, P, M):
    """x + h P/M: free translation over h at fixed momentum (rounded as written: (h P)/M)."""
    return (x[0] + h * P[0] / M, x[1] + h * P[1] / M, x[2] + h * P[2] / M)


@inline
def inverse_inertia(R, I_body_inv):
    """I⁻¹(t) = R I⁻¹_body Rᵀ"""
    return matmul(matmul(R, I_body_inv), transpose(R))


@inline
def angular_velocity(I_inv, L):
    """ω = I⁻¹(t) L"""
    return matvec(I_inv, L)


@inline
def rotation_rate(omega, R):
    """Ṙ = ω* R"""
    return matmul(star(omega), R)


@inline
def body_point(x, R, b):
    """r = x + R b: where the body point b (body axes, from the centre of mass) is."""
    return add(x, matvec(R, b))


@inline
def point_velocity(x, v, omega, r):
    """ṙ = v + ω × (r − x): how fast the body point at r moves."""
    return add(v, cross(omega, sub(r, x)))


@inline
def pivot_constraint(p, b, R, omega, M):
    """A pivoted body: x = p − R b and P = M ω × (x − p), from its rotation."""
    x = sub(p, matvec(R, b))
    return x, scale(M, cross(omega, sub(x, p)))


# --- the effects' forces (effects.py holds their parameters and formulas in words) ---------------

@inline
def spring_force(d, d_dot, k, c, rest):
    """F_a = −k (ℓ − ℓ₀) u − c (ḋ·u) u,  ℓ = |d|, u = d/ℓ;  with ℓ₀ = 0: F_a = −k d − c ḋ."""
    if rest == 0.0:
        return sub(scale(-k, d), scale(c, d_dot))
    length = norm(d)
    u = scale(1.0 / length, d) if length > 0.0 else d
    return scale(-(k * (length - rest) + c * dot(d_dot, u)), u)


@inline
def torque(c, r, f):
    """τ = (r − c) ∧ f: the torque about the point c of the force f applied at the world point r."""
    return cross(sub(r, c), f)


@inline
def add_force(F, tau, centre, i, r, f):
    """A force f at the world point r on body i:  F += f,  τ += (r − c) ∧ f (c its rotation centre)."""
    accumulate(F, i, f)
    accumulate(tau, i, torque(vec(centre, i), r, f))


@hot
def effect_on_body(sys, e, values, base, M, pivoted, x, R, v, omega, centre):
    """Effect row e's force F and torque τ about the rotation centre c on one body, from that body's
    kinematics alone (x, R, v, ω: a row that joins no other body).  values (…, 3): the forces over time,
    row base + slot."""
    code, p = sys.code[e], sys.params[e]
    zero = (0.0, 0.0, 0.0)
    if code == GRAVITY:                       # M g at x: about the centre of mass, no torque at all
        f = (0.0, 0.0, -M * p[0])
        return f, torque(centre, x, f) if pivoted else zero
    if code == POINT_FORCE:
        r = body_point(x, R, (p[0], p[1], p[2]))
        f = vec(values, base + sys.slot[e]) if sys.slot[e] >= 0 else (p[3], p[4], p[5])
        if p[6] != 0.0:
            f = matvec(R, f)                   # a body-frame force turns with the body
        return f, torque(centre, r, f)
    if code == SPRING:                        # its other end fixed in the world
        ra = body_point(x, R, (p[0], p[1], p[2]))
        f = spring_force(sub(ra, (p[3], p[4], p[5])), point_velocity(x, v, omega, ra), p[6], p[7], p[8])
        return f, torque(centre, ra, f)
    if code == LINEAR_DRAG:
        f = scale(-p[0], v)
        return f, torque(centre, x, f) if pivoted else zero
    if code == ANGULAR_DRAG:
        return zero, scale(-p[0], omega)
    return zero, zero


@hot
def effect_on(sys, e, i, values, M, x, R, v, omega, centre, F, tau, base=0):
    """Effect row e acting on body i: adds its forces and torques to F and τ (N, 3) — effect_on_body, or a
    spring joining body i to body j (−F on j at its end).  values (…, 3): the forces over time, row
    base + slot (base: a stage's first row, when a step's stages are given as one array)."""
    j = sys.other[e]
    if sys.code[e] == SPRING and j >= 0:
        p = sys.params[e]
        ra = body_point(vec(x, i), mat(R, i), (p[0], p[1], p[2]))
        va = point_velocity(vec(x, i), vec(v, i), vec(omega, i), ra)
        rb = body_point(vec(x, j), mat(R, j), (p[3], p[4], p[5]))
        vb = point_velocity(vec(x, j), vec(v, j), vec(omega, j), rb)
        f = spring_force(sub(ra, rb), sub(va, vb), p[6], p[7], p[8])
        add_force(F, tau, centre, i, ra, f)
        add_force(F, tau, centre, j, rb, scale(-1.0, f))
    else:
        f, t = effect_on_body(sys, e, values, base, M[i], sys.pivoted[i], vec(x, i), mat(R, i), vec(v, i),
                              vec(omega, i), vec(centre, i))
        accumulate(F, i, f)
        accumulate(tau, i, t)


@njit
def resultants(sys, values, x, R, v, omega, centre, F, tau):
    """F = Σ Fⱼ and τ = Σ (rⱼ − c) × Fⱼ + Σ τⱼ on every body, effect row after effect row
    (slide "Les Formules — les résultantes").  F, τ (N, 3) are overwritten."""
    fill(F, 0.0)
    fill(tau, 0.0)
    M = sys.mass
    for e in range(len(sys.code)):
        if sys.body[e] == EVERY:
            for i in range(len(M)):
                effect_on(sys, e, i, values, M, x, R, v, omega, centre, F, tau)
        else:
            effect_on(sys, e, sys.body[e], values, M, x, R, v, omega, centre, F, tau)


@hot
def body_resultants(sys, values, base, i, x, R, v, omega, centre):
    """F = Σ Fⱼ and τ = Σ (rⱼ − c) × Fⱼ + Σ τⱼ on body i alone, from its kinematics (effect_on_body, row after
    row), for a scene whose rows all act on every body and join none (alike): stages.py steps such a scene body
    by body, its forces in registers.  values (rows, 3): the forces over time, a stage's from row base."""
    F, tau = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    for e in range(len(sys.code)):
        f, t = effect_on_body(sys, e, values, base, sys.mass[i], sys.pivoted[i], x, R, v, omega, centre)
        F, tau = add(F, f), add(tau, t)
    return F, tau


@njit
def alike(sys):
    """Does every effect row act on every body, and join no two (a body's rate needs no other body)?"""
    for e in range(len(sys.code)):
        if sys.body[e] != EVERY or sys.other[e] >= 0:
            return False
    return True


# --- the energy: T and U (the trajectory's diagnostics, the ground's no-energy-gain rule) -------------

@inline
def kinetic_energy(R, P, L, M, I_body_inv):
    """T = ½ P·v + ½ L·ω,  v = P/M,  ω = R I⁻¹_body Rᵀ L  (translation + rotation; L about the centre of mass)."""
    v = velocity(P, M)
    omega = angular_velocity(inverse_inertia(R, I_body_inv), L)
    return 0.5 * dot(P, v) + 0.5 * dot(L, omega)


@njit
def potential(sys, S, i):
    """U of body i in state S (N, 18): its gravity, M g z, and its springs, ½ k (|r_a − r_b| − ℓ₀)²
    (a spring between two bodies counts once, on the body it is attached to first).  Drags, point forces,
    pivots and the ground have none."""
    x, R, _, _ = state_of(S, i)
    U = 0.0
    for e in range(len(sys.code)):
        if sys.body[e] != EVERY and sys.body[e] != i:
            continue
        p = sys.params[e]
        if sys.code[e] == GRAVITY:
            U += sys.mass[i] * p[0] * x[2]
        elif sys.code[e] == SPRING:
            ra = body_point(x, R, (p[0], p[1], p[2]))
            o = sys.other[e]
            if o < 0:
                rb = (p[3], p[4], p[5])
            else:
                xo, Ro, _, _ = state_of(S, o)
                rb = body_point(xo, Ro, (p[3], p[4], p[5]))
            stretch = norm(sub(ra, rb)) - p[8]
            U += 0.5 * p[6] * (stretch * stretch)
    return U


def work(n):
    """Work arrays for N bodies: x, R, v, ω, the rotation centre c, F, τ (the kinematics and forces)."""
    return (np.empty((n, 3)), np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3)),
            np.empty((n, 3)), np.empty((n, 3)))


@inline
def motion(sys, i, x, R, P, L):
    """Body i's (x, P) after its pivot constraint, v and ω (engine coordinates: L about the rotation centre)."""
    omega = angular_velocity(inverse_inertia(R, mat(sys.I_inv, i)), L)
    if sys.pivoted[i]:
        x, P = pivot_constraint(vec(sys.pivot_p, i), vec(sys.pivot_b, i), R, omega, sys.mass[i])
    return x, P, velocity(P, sys.mass[i]), omega


@inline
def stage(values, i):
    """values[i]: the forces over time at a step's stage i — or None for a scene that evaluates no force (a free
    body: system.evaluates_forces): then no force code is compiled (`values is None` is decided by its type)."""
    return None if values is None else values[i]


@inline
def stages_between(values, start, stop):
    """values[start:stop] (the forces over time of some of a step's stages), or None as stage gives it."""
    return None if values is None else values[start:stop]


@hot
def forces(sys, values, w):
    """The resultants on every body from the kinematics in w (zeros, computed from nothing, for a scene that
    evaluates no force: values None).  w: the work arrays (x, R, v, ω, c, F, τ)."""
    x, R, v, omega, centre, F, tau = w
    if values is None:
        fill(F, 0.0)
        fill(tau, 0.0)
    else:
        resultants(sys, values, x, R, v, omega, centre, F, tau)


# --- dX/dt on the slides' state (x, R, P, L): S (N, 18) = [x, R (row by row), P, L] ---------------

@inline
def state_of(S, i):
    """Body i's x, R, P, L from a row of S."""
    return ((S[i, 0], S[i, 1], S[i, 2]),
            ((S[i, 3], S[i, 4], S[i, 5]), (S[i, 6], S[i, 7], S[i, 8]), (S[i, 9], S[i, 10], S[i, 11])),
            (S[i, 12], S[i, 13], S[i, 14]), (S[i, 15], S[i, 16], S[i, 17]))


@inline
def put_state(S, i, x, R, P, L):
    """Row i of S := (x, R, P, L)."""
    S[i, 0], S[i, 1], S[i, 2] = x[0], x[1], x[2]
    for r in range(3):
        S[i, 3 + 3 * r], S[i, 4 + 3 * r], S[i, 5 + 3 * r] = R[r][0], R[r][1], R[r][2]
    S[i, 12], S[i, 13], S[i, 14] = P[0], P[1], P[2]
    S[i, 15], S[i, 16], S[i, 17] = L[0], L[1], L[2]


@inline
def rotation_centre(sys, i, x):
    """The point body i turns about, that its L is taken about: its pivot p, or its centre of mass x."""
    return vec(sys.pivot_p, i) if sys.pivoted[i] else x


@inline
def put_kinematics(sys, w, i, x, R, v, omega):
    """Body i's x, R, v, ω and its rotation centre c (x, or its pivot p) into the work arrays w, for the forces."""
    put(w[0], i, x)
    put_mat(w[1], i, R)
    put(w[2], i, v)
    put(w[3], i, omega)
    put(w[4], i, rotation_centre(sys, i, x))


@njit
def kinematics_matrix(sys, S, w):
    """Fill w's x, R, v, ω and rotation centre c from the slides' state S (pivots applied)."""
    for i in range(len(sys.mass)):
        x, R, P, L = state_of(S, i)
        x, P, v, omega = motion(sys, i, x, R, P, L)
        put_kinematics(sys, w, i, x, R, v, omega)


@njit
def dxdt(sys, values, S, dS, w):
    """dX/dt = (v, Ṙ = ω* R, F, τ) for every body (slide "Les Formules"), into dS (N, 18): v, I⁻¹(t), ω of
    each body (kinematics_matrix), then the forces and torques of the scene's effects (forces)."""
    kinematics_matrix(sys, S, w)
    forces(sys, values, w)
    for i in range(len(sys.mass)):
        put_state(dS, i, vec(w[2], i), rotation_rate(vec(w[3], i), mat(w[1], i)), vec(w[5], i), vec(w[6], i))


@njit
def constrain_state(sys, S):
    """Pivoted bodies in S (N, 18): x = p − R b and P = M ω × (x − p), from R and L (a no-op otherwise)."""
    for i in range(S.shape[0]):
        if sys.pivoted[i]:
            x, R, P, L = state_of(S, i)
            x, P, v, omega = motion(sys, i, x, R, P, L)
            put_state(S, i, x, R, P, L)


@njit
def kick(sys, S, i, b, J):
    """An impulse J at the body point b of body i, on S (N, 18) in place (between two steps):

        ΔP = J,    ΔL = (r − c) × J,    r = x + R b

    c the point L is taken about (the centre of mass x, or the pivot p: then x and P follow from R and L_p)."""
    x, R, P, L = state_of(S, i)
    c = rotation_centre(sys, i, x)
    P, L = add(P, J), add(L, torque(c, body_point(x, R, b), J))
    if sys.pivoted[i]:
        x, P, _, _ = motion(sys, i, x, R, P, L)
    put_state(S, i, x, R, P, L)


@njit
def rates_kick(sys, values, S, dS, w):
    """The momenta's rates at fixed positions, dS = (0, 0, F, τ) (a kick: P += h F, L += h τ), into dS."""
    kinematics_matrix(sys, S, w)
    forces(sys, values, w)
    zero = (0.0, 0.0, 0.0)
    for i in range(len(sys.mass)):
        put_state(dS, i, zero, (zero, zero, zero), vec(w[5], i), vec(w[6], i))
