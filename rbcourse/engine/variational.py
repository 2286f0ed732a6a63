"""The Lie group variational integrator on SO(3) of Lee, Leok & McClamroch, on the slides' state S (N, 18).

T. Lee, M. Leok, N. H. McClamroch, "A Lie group variational integrator for the attitude dynamics of a rigid
body with applications to the 3D pendulum", Proc. IEEE Conf. on Control Applications (2005) 962–967; and
"Lie group variational integrators for the full body problem", Comput. Methods Appl. Mech. Eng. 196 (2007).
The discrete Lagrangian L_d = (1/h) tr((I − F) J_d) − h/2 (U(R_k) + U(R_k F)) gives, with J_d = tr(J)/2 I − J
(J the inertia about the rotation centre, body axes; Π the body angular momentum; M the body torque):

    h Π_k + h²/2 M_k = (F_k J_d − J_d F_kᵀ)^∨,     R_{k+1} = R_k F_k,
    Π_{k+1} = F_kᵀ Π_k + h/2 F_kᵀ M_k + h/2 M_{k+1}

and, for the translation, the matching discrete Euler–Lagrange equations (velocity Verlet):
P += h/2 F_k, x_{k+1} = x_k + h P/M, P += h/2 F_{k+1}.  In the world frame (L = R Π, τ = R M) this is
kick(h/2) at t — the discrete free rotor F_k (world L unchanged: R_{k+1} Π_{k+1} = R_k Π) and the drift of
x — kick(h/2) at t + h: the splitting's kicks (engine/geometric.kick) around the discrete Moser–Veselov rotor.
So world L is changed only by the kicks (a torque with no vertical part keeps L_z to rounding: Noether), R
stays on SO(3), the map is symplectic (variational) and symmetric, order 2, with a bounded modified energy.

The rotor's implicit equation, with the Cayley parameter f (F = (I + f*)(I − f*)⁻¹ = cay(2f)), reads

    φ(f) = 2 (J f + f × J f) − (1 + f·f) h Π⁺ = 0,     Π⁺ = Π_k + h/2 M_k  (the kicked momentum)

(as (F J_d − J_d Fᵀ)^∨ = 2 (J f + f × J f)/(1 + |f|²)), solved by Newton's method from f = h J⁻¹Π⁺/2 with
∂φ/∂f = 2 (J + f* J − (J f)*) − 2 h Π⁺ fᵀ.  It has a solution only if the step turns the body by less than a
quarter turn: about a principal axis J₃ sin θ = h Π₃, so h |ω| <= 1 (a faster spin has no discrete rotor):
then the step is NaN and the run stops with SimulationDiverged, the steps before kept.
"""
from __future__ import annotations

import numpy as np

from .algebra import add, cross, dot, matmul, matvec, retract, scale, solve3, star, sub, transpose, mat_axpy
from .geometric import EULER_B, kick, velocity_dependent
from .implicit import cayley
from .jit import inline, njit
from .motion import constrain_state, copy_into, drift, fill, mat, put_state, state_of

TOL = 1e-15        # the rotor's Newton loop: |Δf| <= TOL (1 + |f|)
MAX_ITER = 50
FAIL = 1e-8        # not settled to FAIL (1 + |f|) after MAX_ITER: no discrete rotor for this step


@inline
def rotor_residual(J, f, hPi):
    """φ(f) = 2 (J f + f × J f) − (1 + f·f) h Π  and  ∂φ/∂f = 2 (J + f* J − (J f)*) − 2 h Π fᵀ."""
    Jf = matvec(J, f)
    phi = sub(scale(2.0, add(Jf, cross(f, Jf))), scale(1.0 + dot(f, f), hPi))
    D = mat_axpy(J, 1.0, mat_axpy(matmul(star(f), J), -1.0, star(Jf)))
    outer = ((hPi[0] * f[0], hPi[0] * f[1], hPi[0] * f[2]), (hPi[1] * f[0], hPi[1] * f[1], hPi[1] * f[2]),
             (hPi[2] * f[0], hPi[2] * f[1], hPi[2] * f[2]))
    return phi, mat_axpy(scale_mat(2.0, D), -2.0, outer)


@inline
def scale_mat(s, A):
    """s A for a 3×3 A."""
    return (scale(s, A[0]), scale(s, A[1]), scale(s, A[2]))


@inline
def discrete_rotor(J, J_inv, Pi, h):
    """F with (F J_d − J_d Fᵀ)^∨ = h Π (Lee, Leok & McClamroch 2005), F = cay(2f), Newton on φ(f) = 0
    (rotor_residual); returns (F, settled)."""
    hPi = scale(h, Pi)
    f = scale(0.5, matvec(J_inv, hPi))
    change = np.inf
    for _ in range(MAX_ITER):
        phi, D = rotor_residual(J, f, hPi)
        df = solve3(D, scale(-1.0, phi))
        f = add(f, df)
        change = abs(df[0]) + abs(df[1]) + abs(df[2])
        if change <= TOL * (1.0 + abs(f[0]) + abs(f[1]) + abs(f[2])):
            break
    return cayley(scale(2.0, f)), change <= FAIL * (1.0 + abs(f[0]) + abs(f[1]) + abs(f[2]))


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
        x += h P/M,   Π = Rᵀ L,   F_k from h Π = (F_k J_d − J_d F_kᵀ)^∨,   R ← retract(R F_k)   (L unchanged)
        kick(h/2) at t + h

    A, b, den: the kicks' table when a force depends on the velocities (MIDPOINT); otherwise each kick is one
    evaluation (EULER).  values: its first half at t (nodes 0, 0), its second half at t + h (nodes 1, 1).
    J = sys.I, J⁻¹ = sys.I_inv (about the rotation centre).  A rotor with no solution (h |ω| > 1 about a
    principal axis) makes the result NaN.  opts: unused.  K: len(b) + 1 slots."""
    second = values[values.shape[0] // 2:]
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
