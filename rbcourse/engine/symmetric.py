"""The symmetric mode solve, compiled: y = A⁺ b for A = B 𝓜⁻¹ Bᵀ (engine/least_norm.py's A = B C with
C = 𝓜⁻¹ Bᵀ, 𝓜⁻¹ = diag(Id/M, I⁻¹)), where each unknown's impulse is along its own kept velocity: every
point sticking, or frictionless (μ = 0: the lift).

    Then P C = K P Bᵀ, K = P 𝓜⁻¹ Pᵀ, and P C Cᵀ Pᵀ = K G K with G = P Bᵀ B Pᵀ: least_norm's formula
    y = (P C)ᵀ (P C Cᵀ Pᵀ)⁻¹ (P Bᵀ B Pᵀ)⁻¹ P Bᵀ b is y = B Pᵀ G⁻¹ K⁻¹ G⁻¹ P Bᵀ b — one Gram matrix to test
    and solve with, and K⁻¹ = diag(M, (P I⁻¹ Pᵀ)⁻¹) on the used columns.  Each kept equation is one component
    of one point's velocity, so G = [[D, E], [Eᵀ, W]] has a diagonal velocity block D = diag(n_c) (blocks),
    and its test and its solves go through the 3×3 Schur complement S = W − Eᵀ D⁻¹ E (schur, block_solve):
    S positive definite by its leading minors, S⁻¹ by its cofactors (algebra.positive_definite3, solve3) —
    short chains of products where Cholesky factors chain square roots and divisions.

The pieces: blocks (G and P Bᵀ b), pivots (D's inverse), schur, block_solve (G⁻¹ by S), spin_block (P I⁻¹ Pᵀ),
symmetric_solve (the whole).  Scratch is the solver's Work (engine/contact.py work(N)): symmetric_solve reads
w.B, w.b and writes w.y, using w.at, w.Q, w.z; nothing is allocated here.
"""
from __future__ import annotations

import math

from .algebra import positive_definite3, solve3
from .jit import hot, inline
from .least_norm import DIRECT, NOT_FINITE, SVD, rcond_shift, spread


@inline
def blocks(B, b, p, Q, z, at):
    """The Gram matrix G = Bᵀ B of a symmetric system by its blocks, into Q (6×6), and q = Bᵀ b into z:
    each row r of B has a single 1 among its velocity columns (component c of a kept point velocity) and
    g_r = B[r, 3:6] among its spin ones, so G = [[D, E], [Eᵀ, W]] with D = diag(n_c) (n_c: the rows of
    component c), E[c] = Σ_{rows of c} g_r, W = Σ_r g_r g_rᵀ; q = (Σ_{rows of c} b_r, Σ_r b_r g_r), each sum
    in the order of the rows (W and q's spin part in registers).  at[c] := c for a used column (n_c > 0; a
    spin column with a non-zero g: each keeps its own place), −1 if not."""
    for c in range(3):
        z[c] = 0.0
        at[c] = -1
        for e in range(6):
            Q[c, e] = 0.0
    w00, w01, w02, w11, w12, w22 = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    q0, q1, q2 = 0.0, 0.0, 0.0
    u0, u1, u2 = False, False, False
    for r in range(p):
        c = 0 if B[r, 0] != 0.0 else (1 if B[r, 1] != 0.0 else 2)
        one, g0, g1, g2, br = B[r, c], B[r, 3], B[r, 4], B[r, 5], b[r]
        Q[c, c] += one * one
        Q[c, 3] += one * g0
        Q[c, 4] += one * g1
        Q[c, 5] += one * g2
        z[c] += one * br
        at[c] = c
        w00, w01, w02 = w00 + g0 * g0, w01 + g0 * g1, w02 + g0 * g2
        w11, w12, w22 = w11 + g1 * g1, w12 + g1 * g2, w22 + g2 * g2
        q0, q1, q2 = q0 + g0 * br, q1 + g1 * br, q2 + g2 * br
        u0, u1, u2 = u0 or g0 != 0.0, u1 or g1 != 0.0, u2 or g2 != 0.0
    Q[3, 3], Q[3, 4], Q[3, 5], Q[4, 4], Q[4, 5], Q[5, 5] = w00, w01, w02, w11, w12, w22
    z[3], z[4], z[5] = q0, q1, q2
    at[3], at[4], at[5] = 3 if u0 else -1, 4 if u1 else -1, 5 if u2 else -1
    for c in range(6):
        for e in range(c):
            Q[c, e] = Q[e, c]


@inline
def pivots(G, at, shift):
    """1/(n_c − shift) for the used velocity columns c of G = [[D, E], [Eᵀ, W]] (blocks: D = diag(n_c)), 0 for
    the unused ones: the three divisions the Schur complement and the block solve then multiply by."""
    return (1.0 / (G[0, 0] - shift) if at[0] >= 0 else 0.0, 1.0 / (G[1, 1] - shift) if at[1] >= 0 else 0.0,
            1.0 / (G[2, 2] - shift) if at[2] >= 0 else 0.0)


@inline
def schur_entry(G, at, shift, inv, d, e):
    """(W − shift Id − Eᵀ (D − shift Id)⁻¹ E)[d, e] on the used columns of G = [[D, E], [Eᵀ, W]] (blocks;
    inv = pivots(G, at, shift)); the identity's where spin column d or e is unused."""
    if at[3 + d] < 0 or at[3 + e] < 0:
        return 1.0 if d == e else 0.0
    t = G[3 + d, 3 + e] - (shift if d == e else 0.0)
    for c in range(3):
        t -= G[c, 3 + d] * inv[c] * G[c, 3 + e]
    return t


@inline
def schur(G, at, shift):
    """S = W − shift Id − Eᵀ (D − shift Id)⁻¹ E (3×3, a tuple) on the used spin columns of G (blocks), the
    identity on the unused ones.  With every used n_c − shift > 0, G − shift Id is positive definite if and
    only if S is."""
    inv = pivots(G, at, shift)
    s00, s11, s22 = schur_entry(G, at, shift, inv, 0, 0), schur_entry(G, at, shift, inv, 1, 1), \
        schur_entry(G, at, shift, inv, 2, 2)
    s01, s02, s12 = schur_entry(G, at, shift, inv, 0, 1), schur_entry(G, at, shift, inv, 0, 2), \
        schur_entry(G, at, shift, inv, 1, 2)
    return (s00, s01, s02), (s01, s11, s12), (s02, s12, s22)


@inline
def spin_part(G, at, inv, z_v, z_w, d):
    """(z_w − Eᵀ D⁻¹ z_v)[d] for a used spin column d of G (blocks; inv = pivots(G, at, 0)), 0 for an unused one."""
    if at[3 + d] < 0:
        return 0.0
    t = z_w[d]
    for c in range(3):
        t -= G[c, 3 + d] * inv[c] * z_v[c]
    return t


@inline
def velocity_part(G, at, inv, z_v, w, c):
    """D⁻¹ (z_v − E w)[c] for a used velocity column c of G (blocks; inv = pivots(G, at, 0)), 0 for an unused one."""
    if at[c] < 0:
        return 0.0
    t = z_v[c]
    for d in range(3):
        if at[3 + d] >= 0:
            t -= G[c, 3 + d] * w[d]
    return t * inv[c]


@inline
def block_solve(G, at, S, z_v, z_w):
    """G⁻¹ (z_v, z_w) for G = [[D, E], [Eᵀ, W]] (blocks), S = W − Eᵀ D⁻¹ E (schur): first
    w = S⁻¹ (z_w − Eᵀ D⁻¹ z_v) (algebra.solve3), then v = D⁻¹ (z_v − E w); the unused places are 0."""
    inv = pivots(G, at, 0.0)
    w = solve3(S, (spin_part(G, at, inv, z_v, z_w, 0), spin_part(G, at, inv, z_v, z_w, 1),
                   spin_part(G, at, inv, z_v, z_w, 2)))
    return (velocity_part(G, at, inv, z_v, w, 0), velocity_part(G, at, inv, z_v, w, 1),
            velocity_part(G, at, inv, z_v, w, 2)), w


@inline
def spin_entry(I_inv, at, c, d):
    """(P I⁻¹ Pᵀ)[c, d], padded by the identity where spin column c or d is unused."""
    if at[3 + c] >= 0 and at[3 + d] >= 0:
        return I_inv[c][d]
    return 1.0 if c == d else 0.0


@inline
def spin_block(I_inv, at):
    """P I⁻¹ Pᵀ on the used spin columns, the identity on the unused ones (3×3, a tuple)."""
    return ((spin_entry(I_inv, at, 0, 0), spin_entry(I_inv, at, 0, 1), spin_entry(I_inv, at, 0, 2)),
            (spin_entry(I_inv, at, 1, 0), spin_entry(I_inv, at, 1, 1), spin_entry(I_inv, at, 1, 2)),
            (spin_entry(I_inv, at, 2, 0), spin_entry(I_inv, at, 2, 1), spin_entry(I_inv, at, 2, 2)))


@hot
def symmetric_solve(w, p, M, I_inv):
    """w.y[:p] := A⁺ b for A = B 𝓜⁻¹ Bᵀ (C = 𝓜⁻¹ Bᵀ, 𝓜⁻¹ = diag(Id/M, I⁻¹): each unknown's impulse is along
    its own kept velocity): y = B Pᵀ G⁻¹ K⁻¹ G⁻¹ P Bᵀ b, G = P Bᵀ B Pᵀ, K⁻¹ = diag(M on the used velocity
    columns, (P I⁻¹ Pᵀ)⁻¹ on the used spin columns) — least_norm's formula with one Gram matrix, whose
    velocity block is diagonal (blocks): its test (G − λ Id positive definite, λ = least_norm.rcond_shift, as
    well_conditioned's) and its solves go through its 3×3 Schur complement (schur, block_solve), K⁻¹'s spin
    block by its cofactors (algebra.solve3).  Reads w.B, w.b (w.C is not used); returns
    DIRECT, NOT_FINITE, or SVD when G is not well conditioned (nothing solved: the caller builds C and calls
    min_norm_solve)."""
    Q, z, at = w.Q, w.z, w.at
    for k in range(p):
        if not math.isfinite(w.b[k]):
            return NOT_FINITE
    blocks(w.B, w.b, p, Q[0], z[0], at)
    G = Q[0]
    for c in range(6):                  # an inf or NaN in B shows on G's diagonal (the sums of its squares)
        if not math.isfinite(G[c, c]):
            return NOT_FINITE
    tr = 0.0                                                    # the trace, that pads the unused places
    for c in range(6):
        if at[c] >= 0:
            tr += G[c, c]
    shift = rcond_shift(Q, 0, at, tr)
    if not shift > 0.0:
        return SVD
    for c in range(3):                                          # G − shift Id positive definite: D − shift Id,
        if not (G[c, c] if at[c] >= 0 else tr) - shift > 0.0:   # the padding …
            return SVD
    if not (at[3] >= 0 and at[4] >= 0 and at[5] >= 0 or tr - shift > 0.0):
        return SVD
    if not positive_definite3(schur(G, at, shift)):             # … and the Schur complement
        return SVD
    S = schur(G, at, 0.0)
    if not positive_definite3(S):
        return SVD
    v, om = block_solve(G, at, S, (z[0, 0], z[0, 1], z[0, 2]), (z[0, 3], z[0, 4], z[0, 5]))   # G⁻¹ P Bᵀ b
    v = (M * v[0], M * v[1], M * v[2])                          # K⁻¹: M on the velocities (0 where unused) …
    if at[3] >= 0 or at[4] >= 0 or at[5] >= 0:                  # … (P I⁻¹ Pᵀ)⁻¹ on the spins
        K = spin_block(I_inv, at)
        if not (math.isfinite(M) and positive_definite3(K)):
            return NOT_FINITE
        om = solve3(K, om)
    v, om = block_solve(G, at, S, v, om)                        # G⁻¹ K⁻¹ G⁻¹ P Bᵀ b
    z[0, 0], z[0, 1], z[0, 2], z[0, 3], z[0, 4], z[0, 5] = v[0], v[1], v[2], om[0], om[1], om[2]
    spread(w.B, p, at, z[0], w.y)                               # y = B Pᵀ z
    return DIRECT
