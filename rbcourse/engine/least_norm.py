"""The least-squares, least-norm solve y = A⁺ b of a small dense system A = B C, compiled: the contact
solver's mode systems (engine/contact.py), B (p×6) the kept velocities from a body's 6 velocities, C (6×p)
the body's response to the p unknowns, p <= 24 (the solver's P_MAX: 3 per contact point).

    Where the r <= 6 columns of B that are used (P) give well-conditioned Gram matrices (their smallest
    eigenvalue above GRAM_RCOND times the largest): y = (P C)ᵀ (P C Cᵀ Pᵀ)⁻¹ (P Bᵀ B Pᵀ)⁻¹ P Bᵀ b,
    two r×r Cholesky solves (r the used columns; tested as 6×6 Gram matrices padded by the trace);
    otherwise (1 or 2 points, an edge): A⁺ b by a one-sided Jacobi SVD of A, singular values below
    PINV_RCOND times the largest dropped.

    Where each unknown pushes along its own kept velocity (every point sticking, or frictionless: the lift),
    C = 𝓜⁻¹ Bᵀ and the same formula needs one Gram matrix only: engine/symmetric.py (symmetric_solve).

The pieces: cholesky and cholesky_solve (r×r), well_conditioned and rcond_shift (the Gram matrices' test),
pinv_solve (p×p, Jacobi SVD), min_norm_solve (the two together); gram, kept_velocity and spread the products
with the used columns P.  Scratch is the solver's Work (engine/contact.py work(N)): min_norm_solve reads w.B,
w.C, w.b and writes w.y, using w.at, w.Q, w.F, w.z, w.A, w.V; nothing is allocated here.
"""
from __future__ import annotations

import math

from .jit import inline, njit

GRAM_RCOND = 1e-6      # the 6×6 normal equations are solved directly if this well conditioned
PINV_RCOND = 1e-9      # the least-norm solve drops singular values below this fraction of the largest
JACOBI_SWEEPS = 60     # the SVD's sweeps, at most (it converges quadratically: ~6-10)

NOT_FINITE, DIRECT, SVD = 0, 1, 2      # how a mode system was solved


@njit
def cholesky(Q, m, r, shift, Lf):
    """Lf := the lower Cholesky factor of Q[m] − shift Id (its first r rows and columns); False if that is not
    positive definite."""
    for j in range(r):
        d = Q[m, j, j] - shift
        for k in range(j):
            d -= Lf[j, k] * Lf[j, k]
        if not d > 0.0:
            return False
        Lf[j, j] = math.sqrt(d)
        for i in range(j + 1, r):
            t = Q[m, i, j]
            for k in range(j):
                t -= Lf[i, k] * Lf[j, k]
            Lf[i, j] = t / Lf[j, j]
    return True


@njit
def cholesky_solve(Lf, r, z):
    """z := (Lf Lfᵀ)⁻¹ z, r×r (forward, then back substitution)."""
    for i in range(r):
        t = z[i]
        for k in range(i):
            t -= Lf[i, k] * z[k]
        z[i] = t / Lf[i, i]
    for i in range(r - 1, -1, -1):
        t = z[i]
        for k in range(i + 1, r):
            t -= Lf[k, i] * z[k]
        z[i] = t / Lf[i, i]


@inline
def rcond_shift(Q, m, at, tr):
    """GRAM_RCOND λ̂, λ̂ = |Q̄|_F, for the symmetric positive semi-definite 6×6 Q̄: Q[m]'s used places (at[c] the
    place of column c, −1 if unused) padded by tr on the unused diagonal; 0 if Q̄ is 0.  Q̄ is well conditioned
    where Q̄ − this Id is positive definite: λ_min > GRAM_RCOND λ_max, tested at most √6 too strictly
    (λ_max <= λ̂ <= √6 λ_max; a stricter test only sends a system to the SVD, which solves every one)."""
    f2 = 0.0
    for i in range(6):
        a = at[i]
        if a < 0:
            f2 += tr * tr
            continue
        f2 += Q[m, a, a] * Q[m, a, a]
        for j in range(i + 1, 6):
            c = at[j]
            if c >= 0:
                f2 += 2.0 * (Q[m, a, c] * Q[m, a, c])
    return GRAM_RCOND * math.sqrt(f2) if f2 > 0.0 else 0.0


@njit
def well_conditioned(Q, m, r, at, tr, F):
    """λ_min(Q̄) > GRAM_RCOND λ_max(Q̄) (rcond_shift) for Q[m]'s r×r of the used columns padded by tr: Q̄ − shift Id
    has a Cholesky factor (F)."""
    shift = rcond_shift(Q, m, at, tr)
    return shift > 0.0 and (r == 6 or tr - shift > 0.0) and cholesky(Q, m, r, shift, F)


@njit
def pinv_solve(A, V, b, y, p):
    """y := A⁺ b for the p×p matrix A (overwritten): one-sided Jacobi SVD A V = U Σ (columns of A rotated
    until orthogonal; their norms are the singular values σ_j), y = Σ_{σ_j > PINV_RCOND σ_max} V_j (A_j·b)/σ_j²."""
    for i in range(p):
        for j in range(p):
            V[i, j] = 1.0 if i == j else 0.0
    for sweep in range(JACOBI_SWEEPS):
        rotated = False
        for i in range(p - 1):
            for j in range(i + 1, p):
                alpha, beta, gamma = 0.0, 0.0, 0.0
                for r in range(p):
                    alpha += A[r, i] * A[r, i]
                    beta += A[r, j] * A[r, j]
                    gamma += A[r, i] * A[r, j]
                if gamma == 0.0 or abs(gamma) <= 1e-15 * math.sqrt(alpha * beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                t = (1.0 if zeta >= 0.0 else -1.0) / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
                c = 1.0 / math.sqrt(1.0 + t * t)
                s = c * t
                for r in range(p):
                    ai, aj = A[r, i], A[r, j]
                    A[r, i], A[r, j] = c * ai - s * aj, s * ai + c * aj
                    vi, vj = V[r, i], V[r, j]
                    V[r, i], V[r, j] = c * vi - s * vj, s * vi + c * vj
        if not rotated:
            break
    smax = 0.0
    for j in range(p):
        t = 0.0
        for r in range(p):
            t += A[r, j] * A[r, j]
        y[j] = t                       # σ_j², kept here for a moment
        smax = max(smax, math.sqrt(t))
    cut = PINV_RCOND * smax
    for j in range(p):
        sig2 = y[j]
        if math.sqrt(sig2) > cut:
            t = 0.0
            for r in range(p):
                t += A[r, j] * b[r]
            y[j] = t / sig2
        else:
            y[j] = 0.0
    for r in range(p):                 # y := V y (in place through A's first column, no longer needed)
        t = 0.0
        for j in range(p):
            t += V[r, j] * y[j]
        A[r, 0] = t
    for r in range(p):
        y[r] = A[r, 0]


@njit
def min_norm_solve(w, p):
    """w.y[:p] := A⁺ b, A = B C (w.B (p×6), w.C (6×p), w.b): the least-squares solution of least norm
    (see the module docstring).  Returns DIRECT (two Cholesky solves) or SVD (the rank-deficient
    cases), or NOT_FINITE if the system is not finite (a state that is no longer physical)."""
    B, C, Q, F, z, at = w.B, w.C, w.Q, w.F, w.z, w.at
    for k in range(p):
        if not math.isfinite(w.b[k]):
            return NOT_FINITE
        for c in range(6):
            if not (math.isfinite(B[k, c]) and math.isfinite(C[c, k])):
                return NOT_FINITE
    r = used_columns(B, p, at)                                  # the used columns of B (P): at[c] their places
    gram(B, p, at, r, Q[0])                                     # P Bᵀ B Pᵀ and P C Cᵀ Pᵀ: symmetric, r×r
    gram(C.T, p, at, r, Q[1])
    tr0, tr1 = 0.0, 0.0                                         # the traces, that pad the unused places
    for a in range(r):
        tr0 += Q[0, a, a]
        tr1 += Q[1, a, a]
    if well_conditioned(Q, 0, r, at, tr0, F[0]) and well_conditioned(Q, 1, r, at, tr1, F[0]):
        kept_velocity(B, w.b, p, at, r, z[0])
        cholesky(Q, 0, r, 0.0, F[0])
        cholesky_solve(F[0], r, z[0])
        cholesky(Q, 1, r, 0.0, F[0])
        cholesky_solve(F[0], r, z[0])
        spread(C.T, p, at, z[0], w.y)                           # y = (P C)ᵀ z
        return DIRECT
    for k in range(p):
        for q in range(p):
            t = 0.0
            for c in range(6):
                t += B[k, c] * C[c, q]
            w.A[k, q] = t
    pinv_solve(w.A, w.V, w.b, w.y, p)
    return SVD


@njit
def used_columns(B, p, at):
    """at[c] := the place of column c of B (p×6) among the used ones (those with a non-zero), −1 if unused;
    returns how many are used (r)."""
    r = 0
    for c in range(6):
        at[c] = -1
        for k in range(p):
            if B[k, c] != 0.0:
                at[c] = r
                r += 1
                break
    return r


@njit
def gram(X, p, at, r, G):
    """G[:r, :r] := P Xᵀ X Pᵀ for X (p×6) — G[at[c], at[d]] = Σ_k X[k, c] X[k, d] over the used columns, each
    sum in the order k = 0 … p−1.  The loop over k is the outer one, so that the 21 sums run side by side
    rather than one after the other (a sum's additions wait for each other; different sums do not)."""
    for a in range(r):
        for e in range(r):
            G[a, e] = 0.0
    for k in range(p):
        for c in range(6):
            a = at[c]
            if a < 0:
                continue
            xc = X[k, c]
            for d in range(c, 6):
                e = at[d]
                if e >= 0:
                    G[a, e] += xc * X[k, d]
    for a in range(r):
        for e in range(a):
            G[a, e] = G[e, a]


@njit
def kept_velocity(B, b, p, at, r, z):
    """z[:r] := P Bᵀ b (z[at[c]] = Σ_k B[k, c] b[k], in the order k = 0 … p−1; the loop over k outer, as gram)."""
    for a in range(r):
        z[a] = 0.0
    for k in range(p):
        for c in range(6):
            a = at[c]
            if a >= 0:
                z[a] += B[k, c] * b[k]


@inline
def spread(X, p, at, z, y):
    """y[:p] := X Pᵀ z for X (p×6): y[k] = Σ_c X[k, c] z[at[c]] over the used columns (the unknowns from the
    r numbers solved for)."""
    for k in range(p):
        t = 0.0
        for c in range(6):
            a = at[c]
            if a >= 0:
                t += X[k, c] * z[a]
        y[k] = t
