"""Re-orthonormalisation of the kernel: each body's R back onto SO(3) after a step that left it (euler_project's
finish), by its polar factor, the rotation nearest to R.  (rbcourse.rotation.project_so3, by the SVD, is the
numpy one for any 3×3 matrix, det < 0 included: the public nearest rotation, for drawing and for the exercise.
algebra.retract, one Björck step, only removes the rounding drift of a product of rotations.)
"""
from __future__ import annotations

import numpy as np

from .algebra import axpy, bjorck_step, cross, dot, gram_defect, scale
from .jit import njit
from .motion import put_state, state_of


@njit
def orthonormalize_rows(S, tol=1e-15, max_iter=20):
    """Each body's R (in S) replaced by its polar factor, by Björck's iteration R ← R − ½ R (RᵀR − I);
    by Newton's iteration (polar_newton) if R is far from SO(3) (max |RᵀR − I| > 0.5); a blown-up R is left as it is."""
    for i in range(S.shape[0]):
        x, R, P, L = state_of(S, i)
        for _ in range(max_iter):
            E = gram_defect(R)
            err = 0.0
            for r in range(3):
                for c in range(3):
                    err = max(err, abs(E[r][c]))
            if err < tol or not np.isfinite(err):
                break
            if err > 0.5:
                R = polar_newton(R)
                break
            R = bjorck_step(R, E)
        put_state(S, i, x, R, P, L)


@njit
def polar_newton(R, max_iter=60):
    """The rotation nearest to R (its polar factor), by Newton's iteration R ← ½ (R + R⁻ᵀ), with
    R⁻ᵀ = cof(R) / det R; it converges (quadratically) for every R with det R > 0 — as every R of the
    Euler step has: det(R + Δt ω* R) = (1 + Δt² |ω|²) det R."""
    for _ in range(max_iter):
        c0, c1, c2 = cross(R[1], R[2]), cross(R[2], R[0]), cross(R[0], R[1])   # the cofactor rows
        det = dot(R[0], c0)
        if not det > 0.0:
            return R
        s = 0.5 / det
        Q = (axpy(scale(0.5, R[0]), s, c0), axpy(scale(0.5, R[1]), s, c1), axpy(scale(0.5, R[2]), s, c2))
        change = 0.0
        for r in range(3):
            for c in range(3):
                change = max(change, abs(Q[r][c] - R[r][c]))
        R = Q
        if change < 1e-15:
            break
    return R
