"""Explicit methods: the slides' Euler and its fixes, classic RK4, RK–Munthe-Kaas 4."""
from __future__ import annotations

import numpy as np

from ..dynamics import motion, rates
from ..rotation import cross, exp_so3, retract
from ..state import State
from . import quaternion as quat
from .base import Method, register


def euler_step(scene, t: float, X: State, h: float) -> State:
    """X(t + Δt) = X(t) + Δt · dX/dt(t),  dX/dt = (v, ω* R, F, τ)   (slide "Evolution temporelle (Euler)").

    Exactly the slides' recipe, with no correction: R + Δt ω* R is not a rotation,
    so R drifts off SO(3) (‖RᵀR − I‖ grows) and the energy grows.
    """
    d = rates(scene, t, X)
    return State.unchecked(X.x + h * d.v, X.R + h * d.R_dot, X.P + h * d.F, X.L + h * d.tau)


def orthonormalize(R: np.ndarray, tol: float = 1e-15, max_iter: int = 20) -> np.ndarray:
    """The nearest rotation to an almost-orthogonal R (polar factor), by Björck's iteration
    R ← R (3 I − RᵀR) / 2, which converges quadratically; SVD if R is far from SO(3)."""
    for _ in range(max_iter):
        E = np.swapaxes(R, -1, -2) @ R - np.eye(3)
        err = np.abs(E).max()
        if err < tol:
            return R
        if not np.isfinite(err):          # a blown-up R: left as it is, for the divergence check to see
            return R
        if err > 0.5:
            from ..rotation import project_so3
            return project_so3(R)
        R = R - 0.5 * R @ E
    return R


def euler_project_step(scene, t: float, X: State, h: float) -> State:
    """The slides' Euler step, then R projected back onto SO(3) (its polar factor):
    R stays a rotation, but the energy still drifts (first order)."""
    Y = euler_step(scene, t, X, h)
    return State.unchecked(Y.x, orthonormalize(Y.R), Y.P, Y.L)


def quaternion_euler_step(scene, t: float, Y: np.ndarray, h: float) -> np.ndarray:
    """Euler on (x, q, P, L) with q̇ = ½ q ⊗ (0, ω_body), then q normalised (Baraff 2001, notes G §4)."""
    return quat.normalized(Y + h * quat.rates(scene, t, Y))


def rk4_step(scene, t: float, Y: np.ndarray, h: float) -> np.ndarray:
    """Classic Runge–Kutta 4 on Y = (x, q, P, L_b); q normalised at the end, so R(q) ∈ SO(3).

        k1 = f(t, y),  k2 = f(t + h/2, y + h/2 k1),  k3 = f(t + h/2, y + h/2 k2),  k4 = f(t + h, y + h k3)
        y(t + h) = y + h/6 (k1 + 2 k2 + 2 k3 + k4)
    """
    f = quat.rates
    k1 = f(scene, t, Y)
    k2 = f(scene, t + h / 2, Y + (h / 2) * k1)
    k3 = f(scene, t + h / 2, Y + (h / 2) * k2)
    k4 = f(scene, t + h, Y + h * k3)
    k2 += k3                         # in place: k1 + 2 (k2 + k3) + k4 without temporaries
    k2 *= 2.0
    k2 += k1
    k2 += k4
    k2 *= h / 6
    k2 += Y
    return quat.normalized(k2)


_RK4_A = ((), (0.5,), (0.0, 0.5), (0.0, 0.0, 1.0))
_RK4_B = (1 / 6, 1 / 3, 1 / 3, 1 / 6)
_RK4_C = (0.0, 0.5, 0.5, 1.0)


def rkmk4_step(scene, t: float, X: State, h: float) -> State:
    """Runge–Kutta–Munthe-Kaas 4 on SO(3): R(t+h) = exp(u) R(t), with u built in the Lie algebra.

    For each stage i:  u_i = Σ a_ij k̃_j,   R_i = exp(u_i) R,   k_i = h ω(R_i, …),
    k̃_i = dexp⁻¹_{u_i}(k_i) ≈ k_i − ½ u_i × k_i + 1/12 u_i × (u_i × k_i);
    then u = Σ b_i k̃_i.  x, P, L take the ordinary RK4 stages.  (Munthe-Kaas 1998.)
    """
    kt, kx, kP, kL = [], [], [], []
    for a, c in zip(_RK4_A, _RK4_C):
        u = sum((aj * k for aj, k in zip(a, kt)), np.zeros_like(X.L))
        Xi = State.unchecked(X.x + sum((aj * k for aj, k in zip(a, kx)), 0.0), exp_so3(u) @ X.R,
                        X.P + sum((aj * k for aj, k in zip(a, kP)), 0.0), X.L + sum((aj * k for aj, k in zip(a, kL)), 0.0))
        v, omega, F, tau = motion(scene, t + c * h, Xi)
        k = h * omega
        uk = cross(u, k)
        kt.append(k - 0.5 * uk + cross(u, uk) / 12.0)
        kx.append(h * v)
        kP.append(h * F)
        kL.append(h * tau)
    step = lambda ks: sum(b * k for b, k in zip(_RK4_B, ks))  # noqa: E731
    return State.unchecked(X.x + step(kx), retract(exp_so3(step(kt)) @ X.R), X.P + step(kP), X.L + step(kL))


register(Method(
    "euler", euler_step, order=1, keeps=frozenset({"L"}),
    cost="1 force evaluation",
    reference="the course slides; Baraff 2001, notes D §2 (explicit Euler on X = (x, R, P, L))",
    summary="the slides' explicit Euler, uncorrected: R leaves SO(3), energy grows",
    stable="none: energy grows; it overflows on fast spins and the heavy top (B, C, thin disk, rod), "
           "and stops there with the divergence error",
    claims=dict(finite=False, free_L=1e-15, diverges_on=("fast_spin_large_step", "fast_thin_disk", "slender_rod", "heavy_top_coarse", "heavy_top_fine", "symmetric_body"))))

register(Method(
    "euler_project", euler_project_step, order=1, keeps=frozenset({"SO(3)", "L"}),
    cost="1 force evaluation + 2–3 Björck iterations",
    reference="Baraff 2001 notes D §2 remark: re-orthogonalise R",
    summary="the slides' Euler, then R projected onto SO(3): a rotation again, but energy still grows",
    stable="finite on every hard case, R on SO(3); but the energy error is large (first order)",
    claims=dict(finite=True, so3=1e-12, free_L=1e-15)))

register(Method(
    "quaternion_euler", quaternion_euler_step, order=1, keeps=frozenset({"SO(3)"}),
    cost="1 force evaluation",
    reference="Baraff 2001, notes G §4 (quaternions instead of R)",
    summary="Euler on (x, q, P, L_b), q normalised: R stays a rotation; energy still grows",
    stable="R on SO(3) while it runs; energy grows and it overflows on B at dt = 1e-2, the rod and the "
           "coarse heavy top", encode=quat.encode, decode=quat.decode,
    claims=dict(finite=False, so3=1e-12, diverges_on=("fast_spin_large_step", "slender_rod", "heavy_top_coarse"))))

register(Method(
    "rk4", rk4_step, order=4, keeps=frozenset({"SO(3)"}),
    cost="4 force evaluations",
    reference="Kutta 1901; on (x, q, P, L_b) with a normalised quaternion (as MuJoCo's RK4 on (q, ω_b))",
    summary="classic Runge–Kutta 4 on (x, q, P, L_b): accurate, R on SO(3), slow energy drift",
    stable="finite on every hard case at small steps; energy drifts slowly", encode=quat.encode, decode=quat.decode,
    claims=dict(finite=True, so3=1e-12)))

register(Method(
    "rkmk4", rkmk4_step, order=4, keeps=frozenset({"SO(3)", "L"}),
    cost="4 force evaluations + 5 exponentials",
    reference="Munthe-Kaas, BIT 38 (1998); Iserles et al., Acta Numerica 9 (2000)",
    summary="Runge–Kutta–Munthe-Kaas 4: RK4 in the Lie algebra, R = exp(u) R stays exactly on SO(3)",
    stable="R on SO(3) to rounding; energy drifts slowly",
    claims=dict(finite=True, so3=1e-12, free_L=1e-12)))
