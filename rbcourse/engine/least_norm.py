"""The least-squares, least-norm solve y = A⁺ b of a small dense system A = B C, compiled: the contact
solver's mode systems (engine/contact.py), B (p×6) the kept velocities from a body's 6 velocities, C (6×p)
the body's response to the p unknowns, p <= 24 (the solver's P_MAX: 3 per contact point).

    Where the r <= 6 columns of B that are used (P) give well-conditioned Gram matrices (their smallest
    eigenvalue above GRAM_RCOND times the largest): y = (P C)ᵀ (P C Cᵀ Pᵀ)⁻¹ (P Bᵀ B Pᵀ)⁻¹ P Bᵀ b,
    two 6×6 Cholesky solves (the unused rows and columns padded by the trace);
    otherwise (1 or 2 points, an edge): A⁺ b by a one-sided Jacobi SVD of A, singular values below
    PINV_RCOND times the largest dropped.

The pieces: cholesky and cholesky_solve (6×6), well_conditioned (the Gram matrices' test), pinv_solve (p×p,
Jacobi SVD), min_norm_solve (the two together).  Scratch is the solver's Work (engine/contact.py work(N)):
min_norm_solve reads w.B, w.C, w.b and writes w.y, using w.Q, w.F, w.z, w.A, w.V; nothing is allocated here.
"""
from __future__ import annotations

import math

from .jit import njit

GRAM_RCOND = 1e-6      # the 6×6 normal equations are solved directly if this well conditioned
PINV_RCOND = 1e-9      # the least-norm solve drops singular values below this fraction of the largest
JACOBI_SWEEPS = 60     # the SVD's sweeps, at most (it converges quadratically: ~6-10)

NOT_FINITE, DIRECT, SVD = 0, 1, 2      # how a mode system was solved


@njit
def cholesky(Q, shift, Lf):
    """Lf := the lower Cholesky factor of Q − shift Id (6×6); False if that is not positive definite."""
    for j in range(6):
        d = Q[j, j] - shift
        for k in range(j):
            d -= Lf[j, k] * Lf[j, k]
        if not d > 0.0:
            return False
        Lf[j, j] = math.sqrt(d)
        for i in range(j + 1, 6):
            t = Q[i, j]
            for k in range(j):
                t -= Lf[i, k] * Lf[j, k]
            Lf[i, j] = t / Lf[j, j]
    return True


@njit
def cholesky_solve(Lf, z):
    """z := (Lf Lfᵀ)⁻¹ z (forward, then back substitution)."""
    for i in range(6):
        t = z[i]
        for k in range(i):
            t -= Lf[i, k] * z[k]
        z[i] = t / Lf[i, i]
    for i in range(5, -1, -1):
        t = z[i]
        for k in range(i + 1, 6):
            t -= Lf[k, i] * z[k]
        z[i] = t / Lf[i, i]


@njit
def well_conditioned(Q, F):
    """λ_min(Q) > GRAM_RCOND λ_max(Q) for a symmetric positive semi-definite 6×6 Q, tested at most √6 too
    strictly: Q − GRAM_RCOND λ̂ Id has a Cholesky factor (F[2]), with λ̂ = |Q|_F, λ_max <= λ̂ <= √6 λ_max
    (a stricter test only sends a system to the SVD, which solves every one)."""
    f2 = 0.0
    for i in range(6):
        f2 += Q[i, i] * Q[i, i]
        for j in range(i + 1, 6):
            f2 += 2.0 * (Q[i, j] * Q[i, j])
    if not f2 > 0.0:
        return False
    return cholesky(Q, GRAM_RCOND * math.sqrt(f2), F[2])


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
    (see the module docstring).  Returns DIRECT (two 6×6 Cholesky solves) or SVD (the rank-deficient
    cases), or NOT_FINITE if the system is not finite (a state that is no longer physical)."""
    B, C, Q, F, z = w.B, w.C, w.Q, w.F, w.z
    for r in range(p):
        if not math.isfinite(w.b[r]):
            return NOT_FINITE
        for c in range(6):
            if not (math.isfinite(B[r, c]) and math.isfinite(C[c, r])):
                return NOT_FINITE
    unused = 0                                                  # a bit per column of B that is all 0 (P's complement)
    for c in range(6):
        used = False
        for r in range(p):
            if B[r, c] != 0.0:
                used = True
        if not used:
            unused |= 1 << c
            for r in range(p):
                C[c, r] = 0.0
    for a in range(6):                                          # Bᵀ B and C Cᵀ: symmetric, their upper halves
        for c in range(a, 6):
            t, u = 0.0, 0.0
            for r in range(p):
                t += B[r, a] * B[r, c]
                u += C[a, r] * C[c, r]
            Q[0, a, c], Q[1, a, c] = t, u
            Q[0, c, a], Q[1, c, a] = t, u
    for m in range(2):                                          # the unused rows and columns: padded by the trace
        tr = Q[m, 0, 0] + Q[m, 1, 1] + Q[m, 2, 2] + Q[m, 3, 3] + Q[m, 4, 4] + Q[m, 5, 5]
        for a in range(6):
            if unused & (1 << a):
                Q[m, a, a] = tr
    if well_conditioned(Q[0], F) and well_conditioned(Q[1], F):
        for a in range(6):
            t = 0.0
            for r in range(p):
                t += B[r, a] * w.b[r]
            z[0, a] = t
        cholesky(Q[0], 0.0, F[2])
        cholesky_solve(F[2], z[0])
        cholesky(Q[1], 0.0, F[2])
        cholesky_solve(F[2], z[0])
        for r in range(p):
            t = 0.0
            for a in range(6):
                t += C[a, r] * z[0, a]
            w.y[r] = t
        return DIRECT
    for r in range(p):
        for q in range(p):
            t = 0.0
            for a in range(6):
                t += B[r, a] * C[a, q]
            w.A[r, q] = t
    pinv_solve(w.A, w.V, w.b, w.y, p)
    return SVD
