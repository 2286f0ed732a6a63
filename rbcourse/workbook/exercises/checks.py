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
(check_simulate, the loop, is in loop.py.)  Here: the formulas of the state, box_inertia to resultants;
check_dxdt and check_euler_step are in stepping.py, check_project_so3 and check_euler_step_projected in
projection.py, the wrong formulas in variants.py.
"""
from __future__ import annotations

import numpy as np

from ...state import inverse_inertia as engine_inverse_inertia
from . import reference as ref
from .harness import N, drifted_rotation, random_forces, random_rotation, random_spd
from .result import CheckResult
from .slides import BOX, EULER, FORMULES
from .texts import tr
from .variants import inverse_inertia_variants, resultant_variants
from . import ladders
from .spec import Case, Spec
from .verdict import run


def check_box_inertia(box_inertia, *, verbose: bool = True, seed: int = 2001) -> CheckResult:
    """box_inertia(mass, size) -> I_body, the 3×3 inertia of a solid box of full sides size = (a, b, c)
    along the body axes x, y, z:

        I_body = M/12 · diag(b² + c², a² + c², a² + b²)
    """
    spec = Spec("box_inertia", "I_body = M/12 · diag(b² + c², a² + c², a² + b²)", BOX,
                ladder=ladders.scale_rungs(ladders.BOX, ladders.SCALES["box_inertia"]),
                reference=ref.box_inertia, scales=ladders.SCALES["box_inertia"])

    def cases(rng):
        out = []
        for i in range(N):
            M = float(rng.uniform(0.5, 5.0))
            a, b, c = (float(s) for s in rng.uniform(0.1, 2.0, 3))
            if i == N - 1:          # a square section, a = b ≠ c: a shortcut for a cube (or for a = b) shows
                b = a
            if i == N - 2:          # a cube: a shortcut for it shows
                b = c = a
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
                yield from box_slips(M, (a, b, c), moments)
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


def box_slips(M, size, moments):
    """The families of arithmetic slips on M/12 · (p² + q²), whatever their spelling: (id, I_body, "")."""
    pairs = [(size[1], size[2]), (size[0], size[2]), (size[0], size[1])]
    squares = np.array([p * p + q * q for p, q in pairs])
    for m in (M // 12 * 12, float(int(M)), float(round(M))):      # integer arithmetic: M // 12, int(M)
        if m != M:
            yield "floor_division", np.diag(m / 12 * squares), ""
    yield "floor_division", np.diag(np.floor(moments)), ""
    yield "precedence", np.diag([M / 12 * p * p + q * q for p, q in pairs]), ""          # M/12*b**2 + c**2
    yield "precedence", np.diag([M / 12 * q * q + p * p for p, q in pairs]), ""
    yield "precedence", np.diag(M / (12 * squares)), ""                                  # M/(12*(b**2 + c**2))
    yield "precedence", np.diag(M / 12 / squares), ""
    yield "square_of_sum", np.diag([M / 12 * (p + q) ** 2 for p, q in pairs]), ""      # (b + c)**2
    yield "moments_full_matrix", np.tile(moments, (3, 1)), ""                             # every row the moments
    yield "moments_full_matrix", np.tile(moments[:, None], (1, 3)), ""                    # every column


def check_velocity(velocity, *, verbose: bool = True, seed: int = 2002) -> CheckResult:
    """velocity(P, M) -> v(t) = P(t) / M."""
    spec = Spec("velocity", "v = P/M", EULER, ladder=ladders.scale_rungs(ladders.VELOCITY, ladders.SCALES["velocity"]),
                reference=lambda P, M: P / M, scales=ladders.SCALES["velocity"])

    def cases(rng):
        out = []
        for _ in range(N):
            P, M = rng.normal(0.0, 2.0, 3), float(rng.uniform(0.5, 5.0))
            out.append(Case((P, M), ("P", "M"), P / M,
                            lambda P=P, M=M: [("velocity_times_mass", P * M, ""), ("velocity_mass_over_P", M / P, ""),
                                              ("floor_division", P // M, ""),
                                              ("floor_division", P / max(int(M), 1), ""),
                                              ("velocity_no_mass", P, ""),
                                              ("velocity_mass_squared", P / M**2, "")]))
        return out
    return run(spec, velocity, cases, verbose, seed)


def check_inverse_inertia(inverse_inertia, *, verbose: bool = True, seed: int = 2003) -> CheckResult:
    """inverse_inertia(R, I_body_inv) -> I⁻¹(t) = R(t) · I⁻¹_body · R(t)ᵀ   (world axes).

    Half the inputs have R off SO(3) as Euler's steps leave it (R + Δt ω* R), the first among them: there
    Rᵀ ≠ R⁻¹ and R Rᵀ ≠ I, so the slides' R · I⁻¹_body · Rᵀ is told from R · I⁻¹_body · R⁻¹, and I⁻¹_body · R · Rᵀ
    from I⁻¹_body."""
    spec = Spec("inverse_inertia", "I⁻¹(t) = R · I⁻¹_body · Rᵀ", EULER,
                ladder=ladders.scale_rungs(ladders.INVERSE, ladders.SCALES["inverse_inertia"]),
                reference=engine_inverse_inertia, formulas=ladders.inverse_formulas,
                scales=ladders.SCALES["inverse_inertia"])

    def cases(rng):
        out = []
        for i in range(N):
            R, Ib = (random_rotation(rng) if i % 2 else drifted_rotation(rng)), random_spd(rng)
            if i == N - 1:          # I stretched by a few 1e-6 (np.allclose(R, I) holds): a shortcut for R = I shows
                R = np.diag(1.0 + rng.uniform(2e-6, 8e-6, 3))

            def candidates(R=R, Ib=Ib):
                yield from inverse_inertia_variants(R, Ib)
                yield "elementwise", R * Ib * R.T, ""
                yield "elementwise", R * Ib @ R.T, ""
                yield "elementwise", R @ Ib * R.T, ""
                yield "elementwise", R * (Ib @ R.T), ""
                yield "elementwise", R @ (Ib * R.T), ""
            out.append(Case((R, Ib), ("R", "I_body_inv"), engine_inverse_inertia(R, Ib), candidates))
        return out
    return run(spec, inverse_inertia, cases, verbose, seed)


def check_angular_velocity(angular_velocity, *, verbose: bool = True, seed: int = 2004) -> CheckResult:
    """angular_velocity(I_inv, L) -> ω(t) = I⁻¹(t) · L(t)."""
    spec = Spec("angular_velocity", "ω = I⁻¹(t) · L", EULER,
                ladder=ladders.scale_rungs(ladders.OMEGA, ladders.SCALES["angular_velocity"]),
                reference=lambda I_inv, L: I_inv @ L, formulas=ladders.omega_formulas,
                scales=ladders.SCALES["angular_velocity"])

    def cases(rng):
        out = []
        for i in range(N):
            I_inv, L = random_spd(rng), rng.normal(0.0, 2.0, 3) * (1e-8 if i == N - 1 else 1e4 if i == N - 2 else 1.0)

            def candidates(I_inv=I_inv, L=L):
                yield "elementwise", I_inv * L, ""
                yield "elementwise", L * np.diag(I_inv), ""
                yield "elementwise", (I_inv * L).sum(0), ""
                yield "omega_uses_inertia", np.linalg.solve(I_inv, L), ""
                omega = I_inv @ L
                for wrong in (np.cross(omega, L), np.cross(L, omega), np.cross(I_inv, L), np.cross(L, I_inv)):
                    yield "cross_for_product", wrong, ""
                    if wrong.ndim == 2:
                        yield "cross_for_product", wrong.sum(0), ""
                        yield "cross_for_product", wrong.sum(1), ""
            out.append(Case((I_inv, L), ("I_inv", "L"), I_inv @ L, candidates))
        return out
    return run(spec, angular_velocity, cases, verbose, seed)


def check_resultants(resultants, *, verbose: bool = True, seed: int = 2005) -> CheckResult:
    """resultants(x, forces) -> (F, τ) for forces = [(r₁, F₁), (r₂, F₂), …] (world points, world forces):

        F = Σ Fᵢ          τ = Σ (rᵢ − x(t)) ∧ Fᵢ        (slide "Les Formules": les résultantes)
    """
    spec = Spec("resultants", "F = Σ Fᵢ, τ = Σ (rᵢ − x) ∧ Fᵢ", FORMULES, labels=("F", "τ"),
                ladder=ladders.scale_rungs(ladders.RESULTANTS, ladders.SCALES["resultants"]),
                reference=lambda x, forces: tuple(np.asarray(a, float) for a in ref.resultants(x, forces)),
                scales=ladders.SCALES["resultants"])

    def cases(rng):
        out = []
        for i in range(N):
            x = rng.normal(0.0, 1.0, 3)
            k = (0 if i == N - 1 else 3 if i in (N - 2, N - 3, N - 4) else 4 if i == 0
                 else int(rng.integers(2, 5)) if i < 10 else int(rng.integers(1, 5)))
            forces = random_forces(rng, x, k)
            if i == N - 2:          # two forces at one point, and one of 1e-4 N: every force counts, however placed
                forces[1] = (forces[0][0].copy(), forces[1][1])
                forces[-1] = (forces[-1][0], 1e-4 * forces[-1][1])
            if i == N - 3:          # forces of 1e-8 N, one given twice: no threshold, no set of forces
                forces = [(r, 1e-8 * F) for r, F in forces]
                forces.append((forces[0][0].copy(), forces[0][1].copy()))
            if i == N - 4:          # a lever arm of 0.1 mm: every torque counts, however short its arm
                forces[0] = (x + 1e-4 * rng.normal(size=3), forces[0][1])
            expected = tuple(np.asarray(a, float) for a in ref.resultants(x, forces))
            out.append(Case((x, forces), ("x", "forces"), expected,
                            lambda x=x, forces=forces: ((m, v, "") for m, v in resultant_variants(x, forces)),
                            special="empty_forces" if k == 0 else None))
        return out
    return run(spec, resultants, cases, verbose, seed)
