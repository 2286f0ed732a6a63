"""A cell against what its method claims (CLAIMS, bench/claims.py): broken_claims lists the claims a run did
not keep, a tolerance "kept to rounding" growing with the number of steps (rounding_budget)."""
from __future__ import annotations

import math

from ...support.language import say

from ..claims import CLAIMS
from ..hardcases import HardCase
from .cell import Cell
from .outcomes import outcome_said


ROUNDING_STEPS = 10**4
LONG_CASES = ("racket_long", "long_run")      # many periods: where "no drift" means something


def rounding_budget(tol: float, steps: int) -> float:
    """A claim "kept to rounding" (so3, free_L, free_norm_L, free_energy) is a tolerance for up to
    10⁴ steps; rounding errors add up from step to step, so over n steps it is tol × n / 10⁴."""
    return tol * max(1.0, steps / ROUNDING_STEPS)


def broken_claims(cell: Cell, case: HardCase, steps: int) -> list[str]:
    """The claims of CLAIMS[cell.method] (bench/claims.py) that this run did not keep (empty: all kept)."""
    claims = CLAIMS[cell.method]
    if case.name in claims.diverges_on:
        return [] if not cell.finished else [say(f"expected to blow up on {case.name}, but finished",
                                                  f"devait diverger sur {case.name}, mais a terminé")]
    if not cell.finished:
        return [say(f"claims to finish every case, but diverged at t = {cell.diverged_at:.6g} s",
                    f"promet de terminer chaque cas, mais a divergé à t = {cell.diverged_at:.6g} s")] if claims.finite else []
    broken = []
    kept_to_rounding = [("so3", "‖RᵀR − I‖", cell.orthogonality, True),
                        ("free_L", say("world L error", "erreur sur L du monde"), cell.momentum_error, case.free),
                        ("free_norm_L", say("|L| error", "erreur sur |L|"), cell.norm_L_error, case.free),
                        ("free_energy", say("energy error", "erreur d'énergie"), cell.energy_error, case.free)]
    for key, what, value, applies in kept_to_rounding:
        tol = getattr(claims, key)
        if applies and tol is not None and not value <= rounding_budget(tol, steps):
            broken.append(f"{what} {value:.2e} > {rounding_budget(tol, steps):.1e} ({key})")
    for key, tol in claims.keeps.items():
        if key in case.invariants and not cell.invariant(key) <= rounding_budget(tol, steps):
            broken.append(say(f"{key} error {cell.invariant(key):.2e} > {rounding_budget(tol, steps):.1e} (keeps {key})",
                              f"erreur sur {key} {cell.invariant(key):.2e} > {rounding_budget(tol, steps):.1e} "
                              f"(garde {key})"))
    claimed = claims.outcomes.get(case.name)
    if claimed is not None and cell.outcome != claimed:
        broken.append(say(f"outcome {cell.outcome!r}, claimed {claimed!r} (outcomes)",
                          f"issue {outcome_said(cell.outcome)!r}, promise {outcome_said(claimed)!r} (outcomes)"))
    if case.free and claims.energy_bounded and case.name in LONG_CASES \
            and not (cell.energy_drift <= 3.0 or cell.energy_error <= 1e-10):
        broken.append(say(f"energy drifts: last half / first half = {cell.energy_drift:.2g} (energy_bounded)",
                          f"l'énergie dérive : seconde moitié / première moitié = {cell.energy_drift:.2g} (energy_bounded)"))
    if case.free and claims.dissipative and not cell.energy_gain <= 1e-12:
        broken.append(say(f"energy increased by {cell.energy_gain:.2e} (dissipative)",
                          f"l'énergie a augmenté de {cell.energy_gain:.2e} (dissipative)"))
    if not math.isfinite(cell.energy_error):
        broken.append(say("the energy error is not finite", "l'erreur d'énergie n'est pas finie"))
    return broken
