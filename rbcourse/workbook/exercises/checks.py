"""The checks of the exercise's functions, one a formula: each runs the student's function on seeded
random inputs against the reference and, on a difference, names the mistake by computing the known
wrong formulas on the same input (τ = F ∧ r, Ṙ = R ω*, I⁻¹_body as the world inertia, …).

    check_box_inertia       I_body = M/12 · diag(b² + c², a² + c², a² + b²)
    check_velocity          v = P / M
    check_inverse_inertia   I⁻¹(t) = R · I⁻¹_body · Rᵀ
    check_angular_velocity  ω = I⁻¹(t) · L
    check_resultants        F = Σ Fᵢ,  τ = Σ (rᵢ − x) ∧ Fᵢ
    check_dxdt              dX/dt = (v, ω* R, F, τ)
    check_euler_step        X(t+Δt) = X(t) + Δt · dX/dt
    check_project_so3       R = U Σ Vᵀ → U Vᵀ
    check_euler_step_projected   the Euler step, then R ← U Vᵀ
(check_simulate, the loop, is in loop.py.)
"""
from __future__ import annotations

import numpy as np

from ...rotation import project_so3 as engine_project_so3, star
from ...state import inverse_inertia as engine_inverse_inertia
from . import reference as ref
from .harness import N, random_forces, random_rotation, random_spd, random_state
from .mistakes import BIBLIO, BOX, EULER, FORMULES, CheckResult
from .reference import as_floats
from .verdict import Case, Spec, run


def check_box_inertia(box_inertia, *, verbose: bool = True, seed: int = 2001) -> CheckResult:
    """box_inertia(mass, size) -> I_body, the 3×3 inertia of a solid box of full sides size = (a, b, c)
    along the body axes x, y, z:

        I_body = M/12 · diag(b² + c², a² + c², a² + b²)
    """
    spec = Spec("box_inertia", "I_body = M/12 · diag(b² + c², a² + c², a² + b²)", BOX)

    def cases(rng):
        out = []
        for _ in range(N):
            M = float(rng.uniform(0.5, 5.0))
            a, b, c = (float(s) for s in rng.uniform(0.1, 2.0, 3))
            moments = M / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])

            def candidates(M=M, a=a, b=b, c=c, moments=moments):
                yield "box_not_squared", M / 12 * np.diag([b + c, a + c, a + b]), ""
                for perm in ((0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
                    yield "box_wrong_pairing", np.diag(moments[list(perm)]), ""
                yield "box_wrong_pairing", M / 12 * np.diag([a * a, b * b, c * c]), ""
                yield "box_missing_twelfth", 12 * np.diag(moments), ""
                yield "box_half_sizes", np.diag(moments) / 4, ""
                yield "box_missing_mass", np.diag(moments) / M, ""
                yield "box_moments_not_matrix", moments, ""
            out.append(Case((M, (a, b, c)), ("mass", "size"), ref.box_inertia(M, (a, b, c)), candidates))
        return out
    return run(spec, box_inertia, cases, verbose, seed)


def check_velocity(velocity, *, verbose: bool = True, seed: int = 2002) -> CheckResult:
    """velocity(P, M) -> v(t) = P(t) / M."""
    spec = Spec("velocity", "v = P/M", EULER)

    def cases(rng):
        out = []
        for _ in range(N):
            P, M = rng.normal(0.0, 2.0, 3), float(rng.uniform(0.5, 5.0))
            out.append(Case((P, M), ("P", "M"), P / M,
                            lambda P=P, M=M: [("velocity_times_mass", P * M, ""), ("velocity_mass_over_P", M / P, "")]))
        return out
    return run(spec, velocity, cases, verbose, seed)


def check_inverse_inertia(inverse_inertia, *, verbose: bool = True, seed: int = 2003) -> CheckResult:
    """inverse_inertia(R, I_body_inv) -> I⁻¹(t) = R(t) · I⁻¹_body · R(t)ᵀ   (world axes)."""
    spec = Spec("inverse_inertia", "I⁻¹(t) = R · I⁻¹_body · Rᵀ", EULER)

    def cases(rng):
        out = []
        for _ in range(N):
            R, Ib = random_rotation(rng), random_spd(rng)

            def candidates(R=R, Ib=Ib):
                yield "I_body_as_world", Ib, ""
                yield "R_inverse_I_R", R.T @ Ib @ R, ""
                yield "missing_RT", R @ Ib, ""
                yield "inverse_inertia_not_inverted", R @ np.linalg.inv(Ib) @ R.T, ""
                yield "elementwise", R * Ib * R.T, ""
                yield "elementwise", R * Ib @ R.T, ""
                yield "elementwise", R @ Ib * R.T, ""
            out.append(Case((R, Ib), ("R", "I_body_inv"), engine_inverse_inertia(R, Ib), candidates))
        return out
    return run(spec, inverse_inertia, cases, verbose, seed)


def check_angular_velocity(angular_velocity, *, verbose: bool = True, seed: int = 2004) -> CheckResult:
    """angular_velocity(I_inv, L) -> ω(t) = I⁻¹(t) · L(t)."""
    spec = Spec("angular_velocity", "ω = I⁻¹(t) · L", EULER)

    def cases(rng):
        out = []
        for _ in range(N):
            I_inv, L = random_spd(rng), rng.normal(0.0, 2.0, 3)

            def candidates(I_inv=I_inv, L=L):
                yield "elementwise", I_inv * L, ""
                yield "elementwise", L * np.diag(I_inv), ""
                yield "omega_uses_inertia", np.linalg.solve(I_inv, L), ""
            out.append(Case((I_inv, L), ("I_inv", "L"), I_inv @ L, candidates))
        return out
    return run(spec, angular_velocity, cases, verbose, seed)


def resultant_variants(x, forces):
    """The wrong resultants: (id, (F, τ))."""
    r = np.array([p for p, _ in forces]).reshape(-1, 3)
    f = np.array([q for _, q in forces]).reshape(-1, 3)
    F = f.sum(0)
    yield "tau_sign", (F, np.cross(f, r - x).sum(0))
    yield "lever_arm", (F, np.cross(r, f).sum(0))
    yield "tau_sign_and_lever_arm", (F, np.cross(f, r).sum(0))
    if len(forces) > 1:
        yield "last_force_only", (f[-1], np.cross(r[-1] - x, f[-1]))
    yield "F_tau_swapped", (np.cross(r - x, f).sum(0), F)


def check_resultants(resultants, *, verbose: bool = True, seed: int = 2005) -> CheckResult:
    """resultants(x, forces) -> (F, τ) for forces = [(r₁, F₁), (r₂, F₂), …] (world points, world forces):

        F = Σ Fᵢ          τ = Σ (rᵢ − x(t)) ∧ Fᵢ        (slide "Les Formules": les résultantes)
    """
    spec = Spec("resultants", "F = Σ Fᵢ, τ = Σ (rᵢ − x) ∧ Fᵢ", FORMULES, labels=("F", "τ"))

    def cases(rng):
        out = []
        for i in range(N):
            x = rng.normal(0.0, 1.0, 3)
            k = 0 if i == N - 1 else int(rng.integers(2, 5)) if i < 10 else int(rng.integers(1, 5))
            forces = random_forces(rng, x, k)
            expected = tuple(np.asarray(a, float) for a in ref.resultants(x, forces))
            out.append(Case((x, forces), ("x", "forces"), expected,
                            lambda x=x, forces=forces: ((m, v, "") for m, v in resultant_variants(x, forces)),
                            special="empty_forces" if k == 0 else None))
        return out
    return run(spec, resultants, cases, verbose, seed)


def dxdt_variants(M, Ib, X, forces):
    """The wrong dX/dt: (id, (dx, dR, dP, dL), prefix) — the slides' formula with one piece wrong."""
    x, R, P, L = as_floats(X)
    F, tau = (np.asarray(a, float) for a in ref.resultants(x, forces))
    I_inv = R @ Ib @ R.T
    v, omega = P / M, I_inv @ L
    S = star(omega)
    SR = S @ R
    yield "R_dot_order", (v, R @ S, F, tau), ""
    yield "R_dot_missing_R", (v, S, F, tau), ""
    yield "omega_star_sign", (v, -SR, F, tau), ""
    yield "omega_from_P", (v, star(I_inv @ P) @ R, F, tau), ""
    yield "v_from_L", (L / M, SR, F, tau), ""
    yield "P_L_swapped", (L / M, star(I_inv @ P) @ R, F, tau), ""
    yield "dx_is_P", (P, SR, F, tau), ""
    yield "dP_is_acceleration", (v, SR, F / M, tau), ""
    yield "dL_is_angular_acceleration", (v, SR, F, I_inv @ tau), ""
    # a derived quantity computed wrongly (the student's velocity / inverse_inertia / angular_velocity)
    yield "velocity_times_mass", (P * M, SR, F, tau), "v: "
    for mistake, J in (("I_body_as_world", Ib), ("R_inverse_I_R", R.T @ Ib @ R), ("missing_RT", R @ Ib),
                       ("inverse_inertia_not_inverted", R @ np.linalg.inv(Ib) @ R.T)):
        yield mistake, (v, star(J @ L) @ R, F, tau), "I⁻¹(t): "
    yield "omega_uses_inertia", (v, star(np.linalg.solve(I_inv, L)) @ R, F, tau), "ω: "
    # the resultants computed wrongly (the student's resultants)
    for mistake, (F_bad, tau_bad) in resultant_variants(x, forces):
        yield mistake, (v, SR, F_bad, tau_bad), "F, τ: "


def _dxdt_cases(rng, n=N, off_so3=0.0, with_dt=False):
    out = []
    for _ in range(n):
        M, Ib = float(rng.uniform(0.5, 5.0)), random_spd(rng)
        X = random_state(rng, off_so3)
        forces = random_forces(rng, X.x, int(rng.integers(2, 4)))
        args = (M, Ib, X, forces) + ((float(rng.uniform(0.02, 0.1)),) if with_dt else ())
        out.append(args)
    return out


def check_dxdt(dxdt, *, verbose: bool = True, seed: int = 2006) -> CheckResult:
    """dxdt(M, I_body_inv, X, forces) -> (v, ω* R, F, τ), the rates of X = (x, R, P, L):

        d/dt (x, R, P, L) = (v(t), ω(t)* R(t), F(t), τ(t))          (slide "Les Formules")
        v = P/M,  I⁻¹(t) = R I⁻¹_body Rᵀ,  ω = I⁻¹(t) L,  F = Σ Fᵢ,  τ = Σ (rᵢ − x) ∧ Fᵢ
    """
    spec = Spec("dxdt", "dX/dt = (v, ω* R, F, τ)", FORMULES, labels=("dx/dt", "dR/dt", "dP/dt", "dL/dt"))

    def cases(rng):
        return [Case(args, ("M", "I_body_inv", "X", "forces"), ref.dxdt(*args),
                     lambda args=args: dxdt_variants(*args))
                for args in _dxdt_cases(rng)]
    return run(spec, dxdt, cases, verbose, seed)


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
    x_new_P = x + dt * P1 / M                                       # semi-implicit: the new momenta move x, R
    R_new_L = R + dt * star(R @ Ib @ R.T @ L1) @ R
    yield "semi_implicit", (x_new_P, R1, P1, L1), ""
    yield "semi_implicit", (x1, R_new_L, P1, L1), ""
    yield "semi_implicit", (x_new_P, R_new_L, P1, L1), ""
    for mistake, d, prefix in dxdt_variants(M, Ib, X, forces):     # a wrong dX/dt, stepped correctly
        yield mistake, tuple(a + dt * b for a, b in zip((x, R, P, L), d)), "dX/dt: " + prefix


_STATE_LABELS = ("x(t+Δt)", "R(t+Δt)", "P(t+Δt)", "L(t+Δt)")


def check_euler_step(euler_step, *, verbose: bool = True, seed: int = 2007) -> CheckResult:
    """euler_step(M, I_body_inv, X, forces, dt) -> X(t+Δt), the slides' explicit Euler:

        X(t + Δt) = X(t) + Δt · dX/dt(t) = (x + Δt v,  R + Δt ω* R,  P + Δt F,  L + Δt τ)

    every rate taken at t (slide "Evolution temporelle (Euler)"; "Itération i").
    """
    spec = Spec("euler_step", "X(t+Δt) = X(t) + Δt · dX/dt", EULER, labels=_STATE_LABELS)

    def cases(rng):
        return [Case(args, ("M", "I_body_inv", "X", "forces", "dt"), tuple(ref.euler_step(*args)),
                     lambda args=args: euler_variants(*args))
                for args in _dxdt_cases(rng, with_dt=True)]
    return run(spec, euler_step, cases, verbose, seed)


def _is_rotation(Q) -> bool:
    return bool(np.all(np.isfinite(Q)) and np.abs(Q.T @ Q - np.eye(3)).max() < 1e-9
                and abs(np.linalg.det(Q) - 1.0) < 1e-9)


def check_project_so3(project_so3, *, verbose: bool = True, seed: int = 2008) -> CheckResult:
    """project_so3(R) -> the rotation nearest to R (R a little off SO(3), as after Euler steps):

        R = U Σ Vᵀ  (np.linalg.svd)   →   U Vᵀ
    """
    spec = Spec("project_so3", "R ← U Vᵀ, the nearest rotation", BIBLIO)

    def cases(rng):
        out = []
        for _ in range(N):
            R = random_rotation(rng) + 0.08 * rng.normal(size=(3, 3))
            Q = engine_project_so3(R)

            def candidates(R=R, Q=Q):
                U, _, Vt = np.linalg.svd(R)
                yield "svd_V_transposed", U @ Vt.T, ""
                yield "svd_not_projected", R, ""
                yield "columns_normalized", R / np.linalg.norm(R, axis=0), ""
                yield "columns_normalized", R / np.linalg.norm(R, axis=1)[:, None], ""
                yield "projection_transposed", Q.T, ""
            out.append(Case((R,), ("R",), Q, candidates))
        return out

    def accept(got, case):
        R, Q = case.args[0], case.expected
        if got.shape == (3, 3) and _is_rotation(got) and np.linalg.norm(got - R) <= 1.5 * np.linalg.norm(Q - R):
            return "a rotation close to R, though not the nearest one — Gram–Schmidt? Fine for this fix"
        return None

    def last_resort(got, case):
        if got.shape != (3, 3):
            return None
        return "not_nearest" if _is_rotation(got) else "not_a_rotation"

    return run(spec, project_so3, cases, verbose, seed, accept, last_resort)



def check_euler_step_projected(euler_step_projected, *, verbose: bool = True, seed: int = 2009) -> CheckResult:
    """euler_step_projected(M, I_body_inv, X, forces, dt): the Euler step, then R(t+Δt) ← its nearest
    rotation U Vᵀ (the fix for R drifting off SO(3))."""
    spec = Spec("euler_step_projected", "Euler step, then R ← U Vᵀ", BIBLIO, labels=_STATE_LABELS)

    def variants(M, Ib, X, forces, dt):
        x, R, P, L = ref.euler_step(M, Ib, X, forces, dt)
        yield "step_not_projected", (x, R, P, L), ""
        x0, R0, P0, L0 = as_floats(X)
        yield "projected_before", tuple(ref.euler_step(M, Ib, (x0, engine_project_so3(R0), P0, L0), forces, dt)), ""
        for mistake, (xb, Rb, Pb, Lb), prefix in euler_variants(M, Ib, X, forces, dt):
            yield mistake, (xb, engine_project_so3(Rb), Pb, Lb), "the Euler step: " + prefix

    def cases(rng):
        return [Case(args, ("M", "I_body_inv", "X", "forces", "dt"), tuple(ref.euler_step_projected(*args)),
                     lambda args=args: variants(*args))
                for args in _dxdt_cases(rng, off_so3=0.05, with_dt=True)]
    return run(spec, euler_step_projected, cases, verbose, seed)
