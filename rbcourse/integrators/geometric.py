"""Geometric methods: R stays a rotation by construction, and (for a free body) L is kept exactly.

Kicks change the momenta by the forces at fixed positions; flows move positions at
fixed momenta.  Body-frame quantities: L_b = Rᵀ L, ω_b = I⁻¹_body L_b.
"""
from __future__ import annotations

import numpy as np

from ..dynamics import motion
from ..rotation import cross, exp_so3, matvec, retract, star, transpose
from ..state import State
from .base import Method, register


def kick(scene, t: float, X: State, h: float, order: int = 1) -> State:
    """Momenta change by the forces at fixed positions:  P += h F,  L += h τ.

    Exact in one evaluation when forces depend on positions (and time) only.  With drag or
    damping the forces change as the momenta do: the kick then integrates dP/dt = F,
    dL/dt = τ at fixed positions to the given order (midpoint for 2, RK4 for 4)."""
    if not (scene.has_forces or scene.has_pivots):
        return X

    def rate(Y):
        _, _, F, tau = motion(scene, t, Y)
        return F, tau

    def moved(Y, dP, dL):
        return scene.constrain(State.unchecked(Y.x, Y.R, Y.P + dP, Y.L + dL))

    F, tau = rate(X)
    if order == 1 or not scene.velocity_dependent:
        return moved(X, h * F, h * tau)
    if order == 2:                                              # explicit midpoint
        F, tau = rate(moved(X, h / 2 * F, h / 2 * tau))
        return moved(X, h * F, h * tau)
    F2, tau2 = rate(moved(X, h / 2 * F, h / 2 * tau))           # RK4
    F3, tau3 = rate(moved(X, h / 2 * F2, h / 2 * tau2))
    F4, tau4 = rate(moved(X, h * F3, h * tau3))
    return moved(X, h / 6 * (F + 2 * F2 + 2 * F3 + F4), h / 6 * (tau + 2 * tau2 + 2 * tau3 + tau4))


def drift_x(scene, X: State, h: float) -> State:
    """Free translation at fixed momentum:  x += h P/M."""
    return State.unchecked(X.x + h * X.P / scene.mass[:, None], X.R, X.P, X.L)


def axis_flow(scene, R: np.ndarray, L: np.ndarray, i: int, h: float) -> np.ndarray:
    """Exact flow of T_i = L_i² / 2I_i, one term of the free rotor's energy in principal axes:
    the body turns about its principal axis a_i by θ = h L_i / I_i, with L_i = a_i · (Rᵀ L);
    R ← R exp(θ a_i*), and the world L does not change."""
    a = scene.I_rot_axes[:, :, i]
    L_i = np.sum(a * matvec(transpose(R), L), axis=-1)
    theta = h * L_i / scene.I_rot_moments[:, i]
    return R @ exp_so3(theta[:, None] * a)


def free_rotor_strang(scene, R: np.ndarray, L: np.ndarray, h: float) -> np.ndarray:
    """Strang splitting of the free rotor, T = T₁ + T₂ + T₃:  Φ₁(h/2) Φ₂(h/2) Φ₃(h) Φ₂(h/2) Φ₁(h/2)
    (McLachlan 1993; Reich 1994; Touma & Wisdom 1994).  Symmetric, order 2, symplectic."""
    for i, frac in ((0, 0.5), (1, 0.5), (2, 1.0), (1, 0.5), (0, 0.5)):
        R = axis_flow(scene, R, L, i, frac * h)
    return retract(R)


def splitting_step(scene, t: float, X: State, h: float) -> State:
    """Kick(h/2) — drift x and free-rotor splitting (h) — kick(h/2).  Order 2, symplectic.

    R stays a rotation; for a free body L is exactly constant and the energy error stays bounded."""
    X = kick(scene, t, X, h / 2, order=2)
    X = drift_x(scene, X, h)
    X = scene.constrain(State.unchecked(X.x, free_rotor_strang(scene, X.R, X.L, h), X.P, X.L))
    return kick(scene, t + h, X, h / 2, order=2)


def symplectic_euler_step(scene, t: float, X: State, h: float) -> State:
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


def implicit_midpoint_step(scene, t: float, X: State, h: float, tol: float = 1e-15, max_iter: int = 60) -> State:
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


def implicit_gyro_step(scene, t: float, X: State, h: float) -> State:
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


register(Method(
    "symplectic_euler", symplectic_euler_step, order=1, keeps=frozenset({"SO(3)", "L", "|L|"}),
    cost="1 force evaluation + 1 exponential",
    reference="semi-implicit Euler (momenta first) with an exponential-map rotation (Lie–Euler); "
              "Hairer, Lubich, Wanner, GNI ch. IV, VI",
    summary="momenta first, then an exact rotation: R on SO(3) and L exact, but for a free body it is "
            "Lie–Euler in the rotation, so the energy error is first order (not symplectic there)",
    stable="finite and on SO(3) on every hard case, L and |L| exact for a free body; the energy is not kept "
           "(it drifts to the largest value |L|²/2I_min allows)",
    claims=dict(finite=True, so3=1e-12, free_L=1e-12, free_norm_L=1e-12)))

register(Method(
    "implicit_gyro", implicit_gyro_step, order=1, keeps=frozenset({"SO(3)"}),
    cost="1 force evaluation + one 3×3 solve",
    reference="E. Catto, 'Numerical Methods', GDC 2015; Bullet Physics (implicit gyroscopic term)",
    summary="implicit gyroscopic step as in game engines: never blows up, but dissipates (a top slows and falls)",
    stable="finite and on SO(3) at any step; energy never grows (dissipative)",
    claims=dict(finite=True, so3=1e-12, dissipative=True)))

register(Method(
    "implicit_midpoint", implicit_midpoint_step, order=2, keeps=frozenset({"SO(3)", "L", "|L|", "energy"}),
    cost="Newton iterations, each 1 force evaluation + one 3×3 solve",
    reference="Lie–Poisson implicit midpoint with a Cayley update; Austin, Krishnaprasad & Wang, J. Comput. Phys. 107 (1993)",
    summary="implicit midpoint: a free body keeps energy, L and |L| exactly; R on SO(3); second order",
    stable="finite, on SO(3), energy and |L| exact for a free body at any step",
    claims=dict(finite=True, so3=1e-12, free_L=1e-12, free_norm_L=1e-12, free_energy=1e-12)))

register(Method(
    "splitting", splitting_step, order=2, keeps=frozenset({"SO(3)", "L", "|L|"}),
    cost="2 force evaluations (1 with FSAL) + 5 axis rotations",
    reference="free-rotor splitting: McLachlan, SIAM J. Sci. Comput. 16 (1995); Touma & Wisdom, AJ 107 (1994); Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107 (1997)",
    summary="kick / drift + free-rotor splitting / kick: symplectic, L exact, energy bounded, second order",
    stable="finite and on SO(3) on every hard case; |L| exact; energy bounded without drift",
    claims=dict(finite=True, so3=1e-12, free_L=1e-12, free_norm_L=1e-12, energy_bounded=True)))
