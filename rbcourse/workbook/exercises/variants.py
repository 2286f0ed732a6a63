"""The known wrong formulas, computed on a check's input: each variant is (mistake id, the wrong value[,
prefix naming the part of the result it is in]).  A wrong dX/dt holds the wrong I⁻¹(t) and resultants; a
wrong Euler step, every wrong dX/dt stepped correctly."""
from __future__ import annotations

import numpy as np

from ...rotation import exp_so3, project_so3 as engine_project_so3, star
from . import reference as ref
from .reference import as_floats
from .texts import tr


def part(name: str) -> str:
    """The prefix naming the part of a result a mistake is in ("v: ", in French "v : ")."""
    return tr("part").format(part=name)


def inverse_inertia_variants(R, Ib):
    """The wrong I⁻¹(t): (id, value, prefix)."""
    R_inv = np.linalg.inv(R)
    yield "I_body_as_world", Ib, ""
    yield "R_inverse_not_transpose", R @ Ib @ R_inv, ""
    yield "R_inverse_I_R", R.T @ Ib @ R, ""
    yield "R_inverse_I_R", R_inv @ Ib @ R, ""
    yield "missing_RT", R @ Ib, ""
    yield "missing_transpose", R @ Ib @ R, ""
    yield "missing_R_left", Ib @ R.T, ""
    yield "missing_R_left", R.T @ Ib, ""
    yield "transpose_both", R.T @ Ib @ R.T, ""
    yield "inverse_inertia_not_inverted", R @ np.linalg.inv(Ib) @ R.T, ""
    yield "inverse_inertia_not_inverted", np.linalg.inv(R @ Ib @ R.T), ""
    for wrong in (Ib @ R @ R.T, R @ R.T @ Ib, Ib @ R.T @ R, R.T @ R @ Ib):      # the three factors in another order
        yield "factor_order", wrong, ""


def resultant_variants(x, forces):
    """The wrong resultants: (id, (F, τ))."""
    r = np.array([p for p, _ in forces]).reshape(-1, 3)
    f = np.array([q for _, q in forces]).reshape(-1, 3)
    F = f.sum(0)
    k = len(forces)
    yield "tau_sign", (F, np.cross(f, r - x).sum(0))
    yield "lever_arm", (F, np.cross(r, f).sum(0))
    yield "tau_sign_and_lever_arm", (F, np.cross(f, r).sum(0))
    if k > 1:
        yield "last_force_only", (f[-1], np.cross(r[-1] - x, f[-1]))
        yield "first_force_only", (f[0], np.cross(r[0] - x, f[0]))
        yield "force_skipped", (f[:-1].sum(0), np.cross(r[:-1] - x, f[:-1]).sum(0))
        yield "force_skipped", (f[1:].sum(0), np.cross(r[1:] - x, f[1:]).sum(0))
        yield "forces_averaged", (F / k, np.cross(r - x, f).sum(0) / k)
    if k > 1:                   # one accumulator overwritten (τ = … for τ += …): the other sum is right
        tau = np.cross(r - x, f).sum(0)
        yield "last_force_only", (F, np.cross(r[-1] - x, f[-1]))
        yield "last_force_only", (f[-1], tau)
        yield "first_force_only", (F, np.cross(r[0] - x, f[0]))
        yield "first_force_only", (f[0], tau)
    yield "elementwise_cross", (F, ((r - x) * f).sum(0))        # (rᵢ − x) * Fᵢ for ∧
    yield "elementwise_cross", (F, ((x - r) * f).sum(0))
    yield "elementwise_cross", (F, (r * f).sum(0))
    yield "F_tau_swapped", (np.cross(r - x, f).sum(0), F)
    yield "tau_missing", (F, np.zeros(3))
    yield "lever_arm_plus", (F, np.cross(r + x, f).sum(0))
    dots = float(np.einsum("ij,ij->", r - x, f)) if k else 0.0
    yield "dot_for_cross", (F, np.array(dots))
    yield "dot_for_cross", (F, np.full(3, dots))
    if k > 1:
        yield "tau_of_sums", (F, np.cross(r.sum(0) - x, F))
        yield "tau_of_sums", (F, np.cross(r.mean(0) - x, F))
    yield "force_pair_order", (r.sum(0), np.cross(f - x, r).sum(0))


def dxdt_variants(M, Ib, X, forces):
    """The wrong dX/dt: (id, (dx, dR, dP, dL), prefix) — the slides' formula with one piece wrong."""
    x, R, P, L = as_floats(X)
    F, tau = (np.asarray(a, float) for a in ref.resultants(x, forces))
    I_inv = R @ Ib @ R.T
    v, omega = P / M, I_inv @ L
    S = star(omega)
    SR = S @ R
    yield "R_dot_order", (v, R @ S, F, tau), ""
    yield "R_dot_elementwise", (v, S * R, F, tau), ""
    yield "R_dot_is_omega", (v, omega, F, tau), ""
    yield "R_dot_body_frame", (v, R @ star(Ib @ R.T @ L), F, tau), ""
    yield "cross_rows", (v, np.cross(omega, R), F, tau), ""
    yield "R_dot_transposed", (v, SR.T, F, tau), ""
    yield "dP_times_mass", (v, SR, F * M, tau), ""
    yield "rates_order", (v, SR, tau, F), ""
    yield "R_dot_missing_R", (v, S, F, tau), ""
    yield "omega_star_sign", (v, -SR, F, tau), ""
    yield "omega_from_P", (v, star(I_inv @ P) @ R, F, tau), ""
    yield "v_from_L", (L / M, SR, F, tau), ""
    yield "P_L_swapped", (L / M, star(I_inv @ P) @ R, F, tau), ""
    yield "dx_is_P", (P, SR, F, tau), ""
    yield "dP_is_acceleration", (v, SR, F / M, tau), ""
    yield "dL_is_angular_acceleration", (v, SR, F, I_inv @ tau), ""
    yield "dP_is_P", (v, SR, P, tau), ""
    yield "dL_is_L", (v, SR, F, L), ""
    # a derived quantity computed wrongly (the student's velocity / inverse_inertia / angular_velocity)
    yield "velocity_times_mass", (P * M, SR, F, tau), part("v")
    for mistake, J, _ in inverse_inertia_variants(R, Ib):
        yield mistake, (v, star(J @ L) @ R, F, tau), part("I⁻¹(t)")
    yield "omega_uses_inertia", (v, star(np.linalg.solve(I_inv, L)) @ R, F, tau), part("ω")
    # the resultants computed wrongly (the student's resultants)
    for mistake, (F_bad, tau_bad) in resultant_variants(x, forces):
        yield mistake, (v, SR, F_bad, tau_bad), part("F, τ")


def euler_variants(M, Ib, X, forces, dt):
    """The wrong Euler steps: (id, X(t+Δt), prefix)."""
    x, R, P, L = as_floats(X)
    v, R_dot, F, tau = ref.dxdt(M, Ib, X, forces)
    x1, R1, P1, L1 = x + dt * v, R + dt * R_dot, P + dt * F, L + dt * tau
    yield "R_not_updated", (x1, R, P1, L1), ""
    yield "x_not_updated", (x, R1, P1, L1), ""
    yield "P_not_updated", (x1, R1, P, L1), ""
    yield "L_not_updated", (x1, R1, P1, L), ""
    yield "no_dt", (x + v, R + R_dot, P + F, L + tau), ""
    for i in range(4):          # Δt dropped on one part only
        parts = [x1, R1, P1, L1]
        parts[i] = (x, R, P, L)[i] + (v, R_dot, F, tau)[i]
        yield "no_dt", tuple(parts), ""
    yield "L_step_uses_F", (x1, R1, P1, L + dt * F), ""
    yield "P_step_uses_tau", (x1, R1, P + dt * tau, L1), ""
    yield "dt_twice", (x + dt * dt * v, R + dt * dt * R_dot, P + dt * dt * F, L + dt * dt * tau), ""
    for i in range(4):          # Δt twice in one line only
        parts = [x1, R1, P1, L1]
        parts[i] = (x, R, P, L)[i] + dt * dt * (v, R_dot, F, tau)[i]
        yield "dt_twice", tuple(parts), ""
    F_new, tau_new = (np.asarray(a, float) for a in ref.resultants(x1, forces))     # about the moved x
    yield "rates_after_update", (x1, R1, P + dt * F_new, L + dt * tau_new), ""
    yield "half_step", (x + dt / 2 * v, R + dt / 2 * R_dot, P + dt / 2 * F, L + dt / 2 * tau), ""
    yield "state_order", (x1, P1, R1, L1), ""
    yield "state_order", (x1, R1, L1, P1), ""
    omega = R @ Ib @ R.T @ L
    yield "R_exact_rotation", (x1, exp_so3(dt * omega) @ R, P1, L1), ""
    yield "projected_in_euler_step", (x1, engine_project_so3(R1), P1, L1), ""
    yield "R_dot_times_R", (x1, R + dt * R_dot @ R, P1, L1), ""
    yield "returned_rates", (v, R_dot, F, tau), ""
    yield "returned_increment", (dt * v, dt * R_dot, dt * F, dt * tau), ""
    yield "euler_minus", (x - dt * v, R - dt * R_dot, P - dt * F, L - dt * tau), ""
    x_new_P = x + dt * P1 / M                                       # semi-implicit: the new momenta move x, R
    R_new_L = R + dt * star(R @ Ib @ R.T @ L1) @ R
    yield "semi_implicit", (x_new_P, R1, P1, L1), ""
    yield "semi_implicit", (x1, R_new_L, P1, L1), ""
    yield "semi_implicit", (x_new_P, R_new_L, P1, L1), ""
    k1 = (v, R_dot, F, tau)     # another method than the slides' explicit Euler, with the same forces
    k2 = ref.dxdt(M, Ib, (x1, R1, P1, L1), forces)
    yield "other_method", tuple(a + dt / 2 * (b + c) for a, b, c in zip((x, R, P, L), k1, k2)), part(tr("heun"))
    half = tuple(a + dt / 2 * b for a, b in zip((x, R, P, L), k1))
    yield "other_method", tuple(a + dt * b for a, b in zip((x, R, P, L), ref.dxdt(M, Ib, half, forces))), \
        part(tr("midpoint"))
    for mistake, d, prefix in dxdt_variants(M, Ib, X, forces):     # a wrong dX/dt, stepped correctly
        yield mistake, tuple(a + dt * b for a, b in zip((x, R, P, L), d)), part("dX/dt") + prefix
