"""A Lie group variational integrator on SO(3), with the Cayley map, on the slides' state S (N, 18).

The Hamilton–Pontryagin variational integrator on a Lie group with the Cayley map as its retraction:
N. Bou-Rabee & J. E. Marsden, "Hamilton–Pontryagin integrators on Lie groups", Found. Comput. Math. 9 (2009)
197–219; M. Kobilarov, K. Crane & M. Desbrun, "Lie group integrators for animation and control of vehicles",
ACM Trans. Graph. 28 (2009).  The discrete rotation of a step is F = Rₖᵀ Rₖ₊₁ = cay(a), a = h ξ (ξ the body
angular velocity of the step), the discrete Lagrangian L_d = (h/2) ξ·J ξ − h/2 (U(Rₖ) + U(Rₖ₊₁)), and the
discrete Euler–Poincaré equations, with Π the body angular momentum at a time step and M the body torque, read

    h Πₖ + h²/2 Mₖ = (dcay⁻¹_a)ᵀ J a = J a + ½ a × J a + ¼ (a·J a) a,      Rₖ₊₁ = Rₖ cay(a),
    h Πₖ₊₁ − h²/2 Mₖ₊₁ = (dcay⁻¹_−a)ᵀ J a = J a − ½ a × J a + ¼ (a·J a) a

(dcay⁻¹_a = I − a*/2 + a aᵀ/4, the inverse of the Cayley map's trivialised derivative; J the inertia
about the rotation centre, body axes).  Since cay(a) (dcay⁻¹_−a)ᵀ = (dcay⁻¹_a)ᵀ, the world L = R Π is the same
after the rotor as before it: in the world frame (L = R Π, τ = R M) the step is
kick(h/2) at t — the discrete free rotor (world L unchanged) and the drift of x — kick(h/2) at t + h: the
splitting's kicks (engine/geometric.kick) around the Cayley rotor, and for the translation the matching
discrete Euler–Lagrange equations (velocity Verlet): P += h/2 F, x += h P/M, P += h/2 F.
So world L is changed only by the kicks (a torque with no vertical part keeps L_z to rounding: Noether), R
stays on SO(3), the map is symplectic (variational) and symmetric, order 2, with a bounded modified energy.
The free rotor keeps |L| exactly, and the energy ½ Π·J⁻¹Π exactly for a symmetric body (J₁ = J₂), where
a·J⁻¹(a × J a) = 0; for three different moments it changes by ¼ (a·J a) a·J⁻¹(a × J a) per step and stays
bounded (no drift).  About a principal axis the rotor turns by θ = 2 atan(u/2) where u + u³/4 = h|ω|:
behind the true turn by (h|ω|)²/3 of the angle turned (to leading order), at any step — the rotor equation
has a solution for every h Π (its left side grows like |a|³).

Why the Cayley map and not the exponential's Moser–Veselov rotor (Lee, Leok & McClamroch, IEEE CCA 2005):
that one solves (F J_d − J_d Fᵀ)^∨ = h Π (J_d = tr(J)/2 I − J), whose left side is bounded — about the symmetry
axis J₃ sin θ = h Π₃ — so no step exists once h|ω| > 1 (a top at ω·Δt = 2 could not be stepped at all).

The rotor's equation φ(a) = J a + ½ a × J a + ¼ (a·J a) a − h Π⁺ = 0, Π⁺ = Πₖ + h/2 Mₖ (the kicked momentum),
is solved by Newton's method from the root along a = s h J⁻¹Π⁺ (a scalar cubic); if it has not settled after MAX_ITER iterations (or is not
finite) the step is NaN and the run stops with SimulationDiverged, the steps before kept.
"""
from __future__ import annotations

import numpy as np

from .algebra import add, cross, dot, identity, mat_axpy, matmul, matvec, retract, scale, solve3, star, sub, transpose
from .geometric import EULER_B, kick, velocity_dependent
from .implicit import cayley
from .jit import inline, njit
from .motion import constrain_state, copy_into, drift, fill, mat, put_state, state_of

TOL = 1e-15        # the rotor's Newton loop: |Δa| <= TOL (1 + |a|)
MAX_ITER = 50
FAIL = 1e-8        # not settled to FAIL (1 + |a|) after MAX_ITER: the run stops (NaN) rather than step wrongly


@inline
def rotor_residual(J, a, hPi):
    """φ(a) = J a + ½ a × J a + ¼ (a·J a) a − h Π  and
    ∂φ/∂a = J + ½ (a* J − (J a)*) + ½ a (J a)ᵀ + ¼ (a·J a) I."""
    Ja = matvec(J, a)
    aJa = dot(a, Ja)
    phi = sub(add(add(Ja, scale(0.5, cross(a, Ja))), scale(0.25 * aJa, a)), hPi)
    D = mat_axpy(J, 0.5, mat_axpy(matmul(star(a), J), -1.0, star(Ja)))
    D = mat_axpy(D, 0.25 * aJa, identity())
    outer = ((a[0] * Ja[0], a[0] * Ja[1], a[0] * Ja[2]), (a[1] * Ja[0], a[1] * Ja[1], a[1] * Ja[2]),
             (a[2] * Ja[0], a[2] * Ja[1], a[2] * Ja[2]))
    return phi, mat_axpy(D, 0.5, outer)


@inline
def axial_scale(c):
    """The root s of c s³ + s = 1 (c >= 0), by Newton's method from min(1, c^(−1/3)), above it (convex):
    φ(s a₀) = 0 along a₀ = h J⁻¹Π, exact for a spin about a principal axis (a·J a ∝ |a|²)."""
    s = 1.0 if c <= 1.0 else c ** (-1.0 / 3.0)
    for _ in range(60):
        ds = (c * s * s * s + s - 1.0) / (3.0 * c * s * s + 1.0)
        s -= ds
        if ds <= 1e-16 * s:
            break
    return s


@inline
def discrete_rotor(J, J_inv, Pi, h):
    """F = cay(a) with h Π = (dcay⁻¹_a)ᵀ J a = J a + ½ a × J a + ¼ (a·J a) a  (module docstring), by Newton's
    method on φ(a) = 0 (rotor_residual) from a = s h J⁻¹ Π, s the root along that line (axial_scale);
    returns (F, settled)."""
    hPi = scale(h, Pi)
    a = scale(axial_scale(0.25 * dot(matvec(J_inv, hPi), matvec(J_inv, hPi))), matvec(J_inv, hPi))
    change = np.inf
    for _ in range(MAX_ITER):
        phi, D = rotor_residual(J, a, hPi)
        da = solve3(D, scale(-1.0, phi))
        a = add(a, da)
        change = abs(da[0]) + abs(da[1]) + abs(da[2])
        if change <= TOL * (1.0 + abs(a[0]) + abs(a[1]) + abs(a[2])):
            break
    return cayley(a), change <= FAIL * (1.0 + abs(a[0]) + abs(a[1]) + abs(a[2]))


@njit
def half_kick(sys, values, A, b, den, vd, Y, out, h, K, U, w):
    """kick(h/2) (geometric.kick): with the table (A, b, den) if a force depends on the velocities (vd), else
    with one evaluation (EULER)."""
    if vd:
        kick(sys, values, A, b, den, Y, out, 0.5 * h, K, U, w)
    else:
        kick(sys, values, A, EULER_B, 1.0, Y, out, 0.5 * h, K, U, w)


@njit
def variational_step(sys, values, opts, A, b, den, Y, out, h, K, U, w):
    """One step of the Lie group variational integrator (module docstring), for every body:

        kick(h/2) at t:  P += h/2 F,  L += h/2 τ
        x += h P/M,   Π = Rᵀ L,   a from h Π = J a + ½ a × J a + ¼ (a·J a) a,   R ← retract(R cay(a))   (L unchanged)
        kick(h/2) at t + h

    A, b, den: the kicks' table when a force depends on the velocities (MIDPOINT); otherwise each kick is one
    evaluation (EULER).  values: its first half at t (nodes 0, 0), its second half at t + h (nodes 1, 1).
    J = sys.I, J⁻¹ = sys.I_inv (about the rotation centre).  A rotor whose Newton solve does not settle
    makes the result NaN.  opts: unused.  K: len(b) + 1 slots."""
    second = None if values is None else values[values.shape[0] // 2:]
    mid = K[len(b)]
    vd = velocity_dependent(sys)
    half_kick(sys, values, A, b, den, vd, Y, out, h, K, U, w)
    for i in range(out.shape[0]):
        x, R, P, L = state_of(out, i)
        F, settled = discrete_rotor(mat(sys.I, i), mat(sys.I_inv, i), matvec(transpose(R), L), h)
        if not settled:
            fill(out, np.nan)
            return
        put_state(out, i, drift(x, h, P, sys.mass[i]), retract(matmul(R, F)), P, L)
    constrain_state(sys, out)
    copy_into(mid, out)
    half_kick(sys, second, A, b, den, vd, mid, out, h, K, U, w)
