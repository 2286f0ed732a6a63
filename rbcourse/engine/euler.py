"""The slides' explicit Euler, written as the slide writes it (slides "Evolution temporelle (Euler)",
"Itération 1 / Itération 2"):

    X(t + Δt) = X(t) + Δt · dX/dt,      dX/dt = (v, Ṙ = ω* R, F, τ),  every rate taken at X(t)

on the slides' state X = (x, R, P, L), one row per body: S (N, 18) = [x, R row by row, P, L] (plan.py).
The rates are motion.dxdt's: v = P/M, I⁻¹(t) = R I⁻¹_body Rᵀ, ω = I⁻¹(t) L, Ṙ = ω* R (motion.py),
F = Σ Fᵢ and τ = Σ (rᵢ − x) × Fᵢ over the scene's effects (motion.resultants).

R + Δt ω* R is not a rotation: R leaves SO(3) (det(R + Δt ω* R) = (1 + Δt²|ω|²) det R) — the lesson of the
slides.  euler_project is the same step, then R projected back onto SO(3) (orthonormalize.py).
"""
from __future__ import annotations

from .jit import njit
from .motion import dxdt, stage
from .orthonormalize import orthonormalize_rows
from .plan import PROJECT_R


@njit
def euler_step(sys, values, X, out, h, dXdt, w):
    """out = X(t + Δt) = X(t) + Δt · dX/dt, every rate from X(t); dXdt (N, 18) receives dX/dt.
    values: the forces given as functions f(t), at t (slots, 3); w: the work arrays (motion.work)."""
    dxdt(sys, values, X, dXdt, w)                    # v, ω* R, F, τ — all at X(t)
    for i in range(X.shape[0]):
        for j in range(X.shape[1]):
            out[i, j] = X[i, j] + h * dXdt[i, j]     # X(t + Δt) = X(t) + Δt · dX/dt


@njit
def euler_family_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """euler (the slides'), euler_project (then R projected onto SO(3)): the family's step, as run.py calls it."""
    euler_step(sys, stage(values, 0), Y, out, h, K[0], w)
    if finish == PROJECT_R:
        orthonormalize_rows(out)
