"""Geometric methods: R stays a rotation by construction, and (for a free body) L is kept exactly.

Kicks change the momenta by the forces at fixed positions; flows move positions at
fixed momenta.  Body-frame quantities: L_b = Rᵀ L, ω_b = I⁻¹_body L_b.
"""
from __future__ import annotations

import numpy as np

from ..dynamics import motion
from ..rotation import cross, exp_so3, matvec, retract, star, transpose
from ..state import State
from .base import Prepared, prepare
from .tableaus import EULER, MIDPOINT, RK4, rk_stages

KICK_TABLES = {1: EULER, 2: MIDPOINT, 4: RK4}


def kick(scene, t: float, X: State, h: float, order: int = 1) -> State:
    """Momenta change by the forces at fixed positions:  P += h F,  L += h τ.

    Exact in one evaluation when forces depend on positions (and time) only.  With drag or
    damping the forces change as the momenta do: the kick then integrates dP/dt = F,
    dL/dt = τ at fixed positions to the given order (KICK_TABLES: explicit midpoint for 2,
    RK4 for 4, through tableaus.rk_stages)."""
    if not (scene.has_forces or scene.has_pivots):
        return X

    def moved(dP, dL):
        return scene.constrain(State.unchecked(X.x, X.R, X.P + dP, X.L + dL))

    def rate(c, U):
        _, _, F, tau = motion(scene, t, moved(*U))
        return np.stack([F, tau])

    table = EULER if not scene.velocity_dependent else KICK_TABLES[order]
    (dP, dL), _ = rk_stages(table, rate, h, (2,) + X.P.shape)
    return moved(dP, dL)


def drift_x(scene, X: State, h: float) -> State:
    """Free translation at fixed momentum:  x += h P/M."""
    return State.unchecked(X.x + h * X.P / scene.mass[:, None], X.R, X.P, X.L)


def axis_flow(prep: Prepared, R: np.ndarray, L: np.ndarray, i: int, h: float) -> np.ndarray:
    """Exact flow of T_i = L_i² / 2I_i, one term of the free rotor's energy in principal axes:
    the body turns about its principal axis a_i by θ = h L_i / I_i, with L_i = a_i · (Rᵀ L);
    R ← R exp(θ a_i*), and the world L does not change."""
    a = prep.I_rot_axes[:, :, i]
    L_i = np.sum(a * matvec(transpose(R), L), axis=-1)
    theta = h * L_i / prep.I_rot_moments[:, i]
    return R @ exp_so3(theta[:, None] * a)


def free_rotor_strang(prep: Prepared, R: np.ndarray, L: np.ndarray, h: float) -> np.ndarray:
    """Strang splitting of the free rotor, T = T₁ + T₂ + T₃:  Φ₁(h/2) Φ₂(h/2) Φ₃(h) Φ₂(h/2) Φ₁(h/2)
    (McLachlan 1993; Reich 1994; Touma & Wisdom 1994).  Symmetric, order 2, symplectic."""
    for i, frac in ((0, 0.5), (1, 0.5), (2, 1.0), (1, 0.5), (0, 0.5)):
        R = axis_flow(prep, R, L, i, frac * h)
    return retract(R)


def splitting_step(scene, t: float, X: State, h: float, prep: Prepared | None = None) -> State:
    """Kick(h/2) — drift x and free-rotor splitting (h) — kick(h/2).  Order 2, symplectic.

    R stays a rotation; for a free body L is exactly constant and the energy error stays bounded."""
    prep = prepare(scene) if prep is None else prep
    X = kick(scene, t, X, h / 2, order=2)
    X = drift_x(scene, X, h)
    X = scene.constrain(State.unchecked(X.x, free_rotor_strang(prep, X.R, X.L, h), X.P, X.L))
    return kick(scene, t + h, X, h / 2, order=2)


def symplectic_euler_step(scene, t: float, X: State, h: float, prep=None) -> State:
    """Momenta first, then an exact rotation (semi-implicit Euler):

        P ← P + h F,   L ← L + h τ            (forces at the old positions)
        x ← x + h P/M, R ← exp(h ω*) R,  ω = R I⁻¹_body Rᵀ L  (the new momenta)

    R stays a rotation; a free body keeps L exactly; first order."""
    X = kick(scene, t, X, h)
    v = X.P / scene.mass[:, None]
    omega = matvec(X.R @ scene.I_rot_inv @ transpose(X.R), X.L)
    return scene.constrain(State.unchecked(X.x + h * v, retract(exp_so3(h * omega) @ X.R), X.P, X.L))


def cayley(a: np.ndarray) -> np.ndarray:
    """cay(a) = (I − a*/2)⁻¹ (I + a*/2) = I + 4/(4 + |a|²) (a* + a*²/2): a rotation for any a."""
    A = star(a)
    k = 4.0 / (4.0 + np.sum(a * a, axis=-1))
    return np.eye(3) + k[..., None, None] * (A + 0.5 * A @ A)


def implicit_midpoint_step(scene, t: float, X: State, h: float, prep=None, tol: float = 1e-15,
                           max_iter: int = 60) -> State:
    """Implicit midpoint rule in the body frame, with a Cayley update of R (Lie–Poisson midpoint):

        L_b' = L_b − h ω̄ × L̄ + h R̄ᵀ τ̄,   L̄ = (L_b + L_b')/2,  ω̄ = I⁻¹ L̄
        R' = R cay(h ω̄),   P' = P + h F̄,   x' = x + h P̄/M

    forces at the midpoint (x̄, R̄ = R cay(h ω̄/2)).  Solved by Newton's method on the
    gyroscopic term (robust for stiff spins).  For a free body it keeps the energy, L and
    |L| exactly (quadratic invariants) and R on SO(3).  Order 2, symmetric."""
    Iinv = scene.I_rot_inv
    Lb0 = matvec(transpose(X.R), X.L)
    Lb1, P1 = Lb0.copy(), X.P.copy()
    forced = scene.has_forces or scene.has_pivots
    for _ in range(max_iter):
        Lbar = 0.5 * (Lb0 + Lb1)
        wbar = matvec(Iinv, Lbar)
        G = Lb1 - Lb0 + h * cross(wbar, Lbar)
        Pbar = 0.5 * (X.P + P1)
        if forced:
            Rbar = X.R @ cayley(0.5 * h * wbar)
            xbar = X.x + 0.5 * h * Pbar / scene.mass[:, None]
            Xbar = scene.constrain(State.unchecked(xbar, Rbar, Pbar, matvec(Rbar, Lbar)))
            _, _, F, tau = motion(scene, t + h / 2, Xbar)
            G = G - h * matvec(transpose(Rbar), tau)
            P_new = X.P + h * F
        else:
            P_new = X.P
        # Newton on the gyroscopic part: ∂G/∂L_b' = I + h/2 (ω̄* − L̄* I⁻¹)
        J = np.eye(3) + 0.5 * h * (star(wbar) - star(Lbar) @ Iinv)
        dL = np.linalg.solve(J, -G[..., None])[..., 0]
        Lb1 = Lb1 + dL
        change = np.abs(dL).max() + np.abs(P_new - P1).max()
        P1 = P_new
        if change <= tol * (1.0 + np.abs(Lb1).max() + np.abs(P1).max()):
            break
    Lbar = 0.5 * (Lb0 + Lb1)
    wbar = matvec(Iinv, Lbar)
    R1 = retract(X.R @ cayley(h * wbar))
    x1 = X.x + h * 0.5 * (X.P + P1) / scene.mass[:, None]
    return scene.constrain(State.unchecked(x1, R1, P1, matvec(R1, Lb1)))


def implicit_gyro_step(scene, t: float, X: State, h: float, prep=None) -> State:
    """Implicit gyroscopic step (Catto, GDC 2015; Bullet's btRigidBody::computeGyroscopicImpulseImplicit_Body):

        torque kick in the body frame, ω₁ = I⁻¹ (L_b + h τ_b);
        solve I (ω₂ − ω₁) + h ω₂ × I ω₂ = 0 with one Newton step from ω₁:
        J = I + h (ω₁* I − (I ω₁)*),   ω₂ = ω₁ − J⁻¹ (h ω₁ × I ω₁);
        R ← R exp(h ω₂*),  L = R I ω₂;  P ← P + h F,  x ← x + h P/M.

    Unconditionally stable; it dissipates rotational energy (first order)."""
    I = scene.I_rot
    _, _, F, tau = motion(scene, t, X) if (scene.has_forces or scene.has_pivots) else (None, None, 0.0, 0.0)
    Lb = matvec(transpose(X.R), X.L + h * tau)
    w1 = matvec(scene.I_rot_inv, Lb)
    Iw1 = matvec(I, w1)
    J = I + h * (star(w1) @ I - star(Iw1))
    w2 = w1 - np.linalg.solve(J, (h * cross(w1, Iw1))[..., None])[..., 0]
    R1 = retract(X.R @ exp_so3(h * w2))
    P1 = X.P + h * F
    return scene.constrain(State.unchecked(X.x + h * P1 / scene.mass[:, None], R1, P1, matvec(R1, matvec(I, w2))))


