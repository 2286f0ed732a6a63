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

from ...rotation import exp_so3, project_so3 as engine_project_so3, star
from ...state import inverse_inertia as engine_inverse_inertia
from . import reference as ref
from .harness import N, drifted_rotation, random_forces, random_rotation, random_spd, random_state
from .mistakes import BOX, EULER, FORMULES, PROJECTION, CheckResult, tr
from .reference import as_floats
from .verdict import Case, Spec, run


def part(name: str) -> str:
    """The prefix naming the part of a result a mistake is in ("v: ", in French "v : ")."""
    return tr("part").format(part=name)


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
                yield "box_third", 4 * np.diag(moments), ""
                yield "box_half_sizes", np.diag(moments) / 4, ""
                yield "box_missing_mass", np.diag(moments) / M, ""
                yield "box_moments_not_matrix", moments, ""
                yield "box_inverted", np.diag(1.0 / moments), ""
                yield "box_sum_all", M / 12 * (a * a + b * b + c * c) * np.eye(3), ""
            out.append(Case((M, (a, b, c)), ("mass", "size"), ref.box_inertia(M, (a, b, c)), candidates))
        return out

    def last_resort(got, case):
        want = case.expected
        if got.shape != (3, 3) or not np.allclose(got, np.diag(np.diag(got))):
            return None
        formulas = ("I_xx = M/12 (b² + c²)", "I_yy = M/12 (a² + c²)", "I_zz = M/12 (a² + b²)")
        bad = [i for i in range(3) if not np.isclose(got[i, i], want[i, i], rtol=1e-7)]
        if 0 < len(bad) < 3:
            return "box_one_moment", tr("moment_wrong").format(
                moments=", ".join(formulas[i].split(" =")[0] for i in bad), verb=tr("is" if len(bad) == 1 else "are"),
                formulas=", ".join(formulas[i] for i in bad))
        return None
    return run(spec, box_inertia, cases, verbose, seed, last_resort=last_resort)


def check_velocity(velocity, *, verbose: bool = True, seed: int = 2002) -> CheckResult:
    """velocity(P, M) -> v(t) = P(t) / M."""
    spec = Spec("velocity", "v = P/M", EULER)

    def cases(rng):
        out = []
        for _ in range(N):
            P, M = rng.normal(0.0, 2.0, 3), float(rng.uniform(0.5, 5.0))
            out.append(Case((P, M), ("P", "M"), P / M,
                            lambda P=P, M=M: [("velocity_times_mass", P * M, ""), ("velocity_mass_over_P", M / P, ""),
                                              ("velocity_no_mass", P, ""), ("floor_division", P // M, ""),
                                              ("velocity_mass_squared", P / M**2, "")]))
        return out
    return run(spec, velocity, cases, verbose, seed)


def check_inverse_inertia(inverse_inertia, *, verbose: bool = True, seed: int = 2003) -> CheckResult:
    """inverse_inertia(R, I_body_inv) -> I⁻¹(t) = R(t) · I⁻¹_body · R(t)ᵀ   (world axes).

    Half the inputs have R off SO(3) as Euler's steps leave it (R + Δt ω* R): there Rᵀ ≠ R⁻¹, so the
    slides' R · I⁻¹_body · Rᵀ is told from R · I⁻¹_body · R⁻¹."""
    spec = Spec("inverse_inertia", "I⁻¹(t) = R · I⁻¹_body · Rᵀ", EULER)

    def cases(rng):
        out = []
        for i in range(N):
            R, Ib = (drifted_rotation(rng) if i % 2 else random_rotation(rng)), random_spd(rng)

            def candidates(R=R, Ib=Ib):
                yield from inverse_inertia_variants(R, Ib)
                yield "elementwise", R * Ib * R.T, ""
                yield "elementwise", R * Ib @ R.T, ""
                yield "elementwise", R @ Ib * R.T, ""
            out.append(Case((R, Ib), ("R", "I_body_inv"), engine_inverse_inertia(R, Ib), candidates))
        return out
    return run(spec, inverse_inertia, cases, verbose, seed)


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
                yield "elementwise", (I_inv * L).sum(0), ""
                yield "omega_uses_inertia", np.linalg.solve(I_inv, L), ""
            out.append(Case((I_inv, L), ("I_inv", "L"), I_inv @ L, candidates))
        return out
    return run(spec, angular_velocity, cases, verbose, seed)


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


def check_resultants(resultants, *, verbose: bool = True, seed: int = 2005) -> CheckResult:
    """resultants(x, forces) -> (F, τ) for forces = [(r₁, F₁), (r₂, F₂), …] (world points, world forces):

        F = Σ Fᵢ          τ = Σ (rᵢ − x(t)) ∧ Fᵢ        (slide "Les Formules": les résultantes)
    """
    spec = Spec("resultants", "F = Σ Fᵢ, τ = Σ (rᵢ − x) ∧ Fᵢ", FORMULES, labels=("F", "τ"))

    def cases(rng):
        out = []
        for i in range(N):
            x = rng.normal(0.0, 1.0, 3)
            k = 0 if i == N - 1 else 4 if i == 0 else int(rng.integers(2, 5)) if i < 10 else int(rng.integers(1, 5))
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


def _dxdt_cases(rng, n=N, off_so3=0.0, with_dt=False):
    """Inputs (M, I_body_inv, X, forces[, dt]): masses 0.5–5 kg, 2–3 forces; every other R off SO(3) as
    Euler leaves it (drifted_rotation), where Rᵀ and R⁻¹ differ."""
    out = []
    for i in range(n):
        M, Ib = float(rng.uniform(0.5, 5.0)), random_spd(rng)
        X = random_state(rng, off_so3, drift=bool(i % 2))
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

    def last_resort(got, case):
        M, Ib, X, forces = case.args
        R = np.asarray(X[1], float)
        omega = R @ Ib @ R.T @ np.asarray(X[3], float)
        return _star_wrong(got[1] @ np.linalg.inv(R), omega)
    return run(spec, dxdt, cases, verbose, seed, last_resort=last_resort)


def _star_wrong(S, omega):
    """"star_wrong" when S (the student's Ṙ R⁻¹) looks like a cross-product matrix written wrongly: zero
    diagonal, each off-diagonal entry ± a component of ω, yet not ω*; else None."""
    if S.shape != (3, 3) or not np.all(np.isfinite(S)):
        return None
    scale = max(1e-12, float(np.abs(omega).max()))
    off = S[~np.eye(3, dtype=bool)]
    like = (np.abs(np.diag(S)).max() < 1e-6 * scale
            and all(np.abs(np.abs(omega) - abs(e)).min() < 1e-6 * scale for e in off))
    return "star_wrong" if like and not np.allclose(S, star(omega), atol=1e-6 * scale) else None


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
    for mistake, d, prefix in dxdt_variants(M, Ib, X, forces):     # a wrong dX/dt, stepped correctly
        yield mistake, tuple(a + dt * b for a, b in zip((x, R, P, L), d)), part("dX/dt") + prefix


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

    def last_resort(got, case):
        M, Ib, X, forces, dt = case.args
        R = np.asarray(X[1], float)
        omega = R @ Ib @ R.T @ np.asarray(X[3], float)
        return _star_wrong((got[1] - R) / dt @ np.linalg.inv(R), omega)
    return run(spec, euler_step, cases, verbose, seed, last_resort=last_resort)


def _is_rotation(Q) -> bool:
    return bool(np.all(np.isfinite(Q)) and np.abs(Q.T @ Q - np.eye(3)).max() < 1e-9
                and abs(np.linalg.det(Q) - 1.0) < 1e-9)


def check_project_so3(project_so3, *, verbose: bool = True, seed: int = 2008) -> CheckResult:
    """project_so3(R) -> the rotation nearest to R (R a little off SO(3), as after Euler steps):

        R = U Σ Vᵀ  (np.linalg.svd)   →   U Vᵀ
    """
    spec = Spec("project_so3", "formula_project", PROJECTION)

    def cases(rng):
        out = []
        for i in range(N):
            if i % 4 == 3:          # det(U Vᵀ) = −1: the nearest rotation flips U's last column
                s = np.sort(rng.uniform(0.2, 1.2, 3))[::-1] * [1.0, 1.0, -1.0]
                R = random_rotation(rng) @ np.diag(s) @ random_rotation(rng)
            else:                   # a little off SO(3), as after Euler's steps
                R = random_rotation(rng) + 0.08 * rng.normal(size=(3, 3))
            Q = engine_project_so3(R)

            def candidates(R=R, Q=Q):
                U, _, Vt = np.linalg.svd(R)
                flip = np.diag([1.0, 1.0, -1.0])
                if np.linalg.det(U @ Vt) < 0:
                    yield "svd_no_det_fix", U @ Vt, ""
                    yield "svd_negated", -(U @ Vt), ""
                    yield "svd_wrong_column", U @ np.diag([-1.0, 1.0, 1.0]) @ Vt, ""
                    yield "svd_wrong_column", U @ np.diag([1.0, -1.0, 1.0]) @ Vt, ""
                else:
                    yield "svd_flip_always", U @ flip @ Vt, ""
                yield "svd_factors_swapped", Vt @ U, ""
                yield "svd_U_only", U, ""
                yield "scaled_by_det", R / np.cbrt(np.linalg.det(R)), ""
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
            return tr("gram_schmidt")
        return None

    def last_resort(got, case):
        if got.shape != (3, 3):
            return None
        return "not_nearest" if _is_rotation(got) else "not_a_rotation"

    return run(spec, project_so3, cases, verbose, seed, accept, last_resort)



def check_euler_step_projected(euler_step_projected, *, verbose: bool = True, seed: int = 2009) -> CheckResult:
    """euler_step_projected(M, I_body_inv, X, forces, dt): the Euler step, then R(t+Δt) ← its nearest
    rotation U Vᵀ (the fix for R drifting off SO(3))."""
    spec = Spec("euler_step_projected", "formula_projected", PROJECTION, labels=_STATE_LABELS)

    def variants(M, Ib, X, forces, dt):
        x, R, P, L = ref.euler_step(M, Ib, X, forces, dt)
        yield "step_not_projected", (x, R, P, L), ""
        x0, R0, P0, L0 = as_floats(X)
        yield "projected_before", tuple(ref.euler_step(M, Ib, (x0, engine_project_so3(R0), P0, L0), forces, dt)), ""
        for mistake, (xb, Rb, Pb, Lb), prefix in euler_variants(M, Ib, X, forces, dt):
            if np.shape(Rb) == (3, 3):          # (a variant with the parts out of order has no R to project)
                yield mistake, (xb, engine_project_so3(Rb), Pb, Lb), part(tr("the_euler_step")) + prefix

    def cases(rng):
        return [Case(args, ("M", "I_body_inv", "X", "forces", "dt"), tuple(ref.euler_step_projected(*args)),
                     lambda args=args: variants(*args))
                for args in _dxdt_cases(rng, off_so3=0.05, with_dt=True)]
    return run(spec, euler_step_projected, cases, verbose, seed)
