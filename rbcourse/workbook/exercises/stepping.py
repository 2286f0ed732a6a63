"""The checks of the rates and of the Euler step: check_dxdt, dX/dt = (v, ω* R, F, τ), and check_euler_step,
X(t+Δt) = X(t) + Δt · dX/dt — on inputs with R off SO(3) as Euler leaves it (dxdt_cases), a mistake named
from the wrong formulas of variants.py, or an ω* that is not the cross-product matrix (_star_wrong)."""
from __future__ import annotations

import numpy as np

from ...rotation import star
from . import reference as ref
from .harness import N, random_forces, random_rotation, random_spd, random_state
from .reference import StateTuple
from .result import CheckResult
from .slides import EULER, FORMULES
from .variants import dxdt_variants, euler_variants
from . import ladders
from .spec import Case, Spec
from .verdict import run


def dxdt_cases(rng, n=N, off_so3=0.0, with_dt=False):
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


def edge_cases(rng, with_dt=False, off_so3=0.0):
    """The inputs the notebook gives these functions later, after their random ones: (args, special) — one force;
    no force, forces = [] (the box after its push, Part 7: any failure there is "empty_forces"); X a plain tuple
    (x, R, P, L), as simulate passes back what a step returned (any failure there is "state_attributes")."""
    one, none, plain, scales, small, slow = dxdt_cases(rng, 6, off_so3, with_dt)
    one = one[:3] + ([one[3][0]],) + one[4:]
    none = none[:3] + ([],) + none[4:]
    plain = plain[:2] + (tuple(plain[2]),) + plain[3:]
    X = small[2]
    small = small[:2] + (StateTuple(X.x, random_rotation(rng), X.P, X.L),) + small[3:4] + ((1e-3,) if with_dt else ())
    X = slow[2]                 # a slow spin (|ω| about 1e-4 rad/s) and a long step (0.5 s): no threshold, no clamp
    slow = slow[:2] + (StateTuple(X.x, X.R, X.P, 1e-4 * X.L),) + slow[3:4] + ((0.5,) if with_dt else ())
    return [(one, None), (none, "empty_forces"), (plain, "state_attributes"), (far_and_fast(rng, scales), None),
            (small, None), (slow, None)]      # small: R a rotation, Δt = 1 ms: R off SO(3) by about 1e-6 only


def far_and_fast(rng, args):
    """The inputs at the ends of their scales, all valid: the body 1 km away and fast, spinning at some hundred rad/s
    with R a rotation (its Euler step drifts it off SO(3) by (Δt ω)², small for Δt = 1 ms), two of its forces the same
    force at the same point — a threshold, a clamp, a set of forces or a shortcut shows."""
    M, Ib, X, forces = args[:4]
    x, R, P, L = X
    X = StateTuple(x + 1e3, random_rotation(rng), 300.0 * P, 150.0 * L)
    return (M, Ib, X, forces + forces[:1]) + ((1e-3,) if len(args) > 4 else ())


def step_cases(rng, expected, variants, names, n=N, off_so3=0.0, with_dt=False):
    """A check's Cases: n random inputs (dxdt_cases), then the notebook's own (edge_cases)."""
    inputs = [(args, None) for args in dxdt_cases(rng, n, off_so3, with_dt)] + edge_cases(rng, with_dt, off_so3)
    return [Case(args, names, expected(*args), lambda args=args: variants(*args), special=special)
            for args, special in inputs]


def check_dxdt(dxdt, *, verbose: bool = True, seed: int = 2006) -> CheckResult:
    """dxdt(M, I_body_inv, X, forces) -> (v, ω* R, F, τ), the rates of X = (x, R, P, L):

        d/dt (x, R, P, L) = (v(t), ω(t)* R(t), F(t), τ(t))          (slide "Les Formules")
        v = P/M,  I⁻¹(t) = R I⁻¹_body Rᵀ,  ω = I⁻¹(t) L,  F = Σ Fᵢ,  τ = Σ (rᵢ − x) ∧ Fᵢ
    """
    spec = Spec("dxdt", "dX/dt = (v, ω* R, F, τ)", FORMULES, labels=("dx/dt", "dR/dt", "dP/dt", "dL/dt"),
                ladder=ladders.scale_rungs(ladders.STATE, ladders.SCALES["state"]), reference=ref.dxdt,
                scales=ladders.SCALES["state"])

    def cases(rng):
        return step_cases(rng, ref.dxdt, dxdt_variants, ("M", "I_body_inv", "X", "forces"))

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


STATE_LABELS = ("x(t+Δt)", "R(t+Δt)", "P(t+Δt)", "L(t+Δt)")


def check_euler_step(euler_step, *, verbose: bool = True, seed: int = 2007) -> CheckResult:
    """euler_step(M, I_body_inv, X, forces, dt) -> X(t+Δt), the slides' explicit Euler:

        X(t + Δt) = X(t) + Δt · dX/dt(t) = (x + Δt v,  R + Δt ω* R,  P + Δt F,  L + Δt τ)

    every rate taken at t (slide "Evolution temporelle (Euler)"; "Itération i").
    """
    spec = Spec("euler_step", "X(t+Δt) = X(t) + Δt · dX/dt", EULER, labels=STATE_LABELS,
                ladder=ladders.scale_rungs(ladders.STEP, ladders.SCALES["state"]),
                reference=lambda *a: tuple(ref.euler_step(*a)), scales=ladders.SCALES["state"])

    def cases(rng):
        return step_cases(rng, lambda *a: tuple(ref.euler_step(*a)), euler_variants,
                          ("M", "I_body_inv", "X", "forces", "dt"), with_dt=True)

    def last_resort(got, case):
        M, Ib, X, forces, dt = case.args
        R = np.asarray(X[1], float)
        omega = R @ Ib @ R.T @ np.asarray(X[3], float)
        return _star_wrong((got[1] - R) / dt @ np.linalg.inv(R), omega)
    return run(spec, euler_step, cases, verbose, seed, last_resort=last_resort)
