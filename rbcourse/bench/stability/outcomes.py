"""A cell's outcome (OUTCOMES: faithful, stable but wrong, ran away, diverged) and the thresholds that decide
it, each defined once (FAITHFUL_INVARIANT, FAITHFUL_ROTATION, FAITHFUL_POSITION, RUNAWAY)."""
from __future__ import annotations

import math

from ...support.language import say


FAITHFUL_INVARIANT = 1e-3   # faithful: every declared invariant within 1e-3 (relative, max over the run)
FAITHFUL_ROTATION = 1e-2    # and the attitude within 1e-2 rad of the reference at the end
FAITHFUL_POSITION = 1e-3    # and the centres within 1 mm of it (where the reference gives them)
RUNAWAY = 1.0               # ran away: an invariant off by more than its own size (energy error > 1: E > 2 E0)
OUTCOMES = ("faithful", "stable but wrong", "ran away", "diverged")
"""What a cell's outcome means:
faithful          finished; every declared invariant within FAITHFUL_INVARIANT, and (where the case has a
                  reference) the end within FAITHFUL_ROTATION rad and FAITHFUL_POSITION m of it;
stable but wrong  finished, every invariant bounded (<= RUNAWAY), but an invariant or the motion off;
ran away          finished, but an invariant off by more than its own size (> RUNAWAY), or not finite;
diverged          overflow / NaN: the engine's divergence error, at diverged_at."""


OUTCOMES_FR = {"faithful": "fidèle", "stable but wrong": "stable mais faux", "ran away": "emballé",
               "diverged": "divergé"}
"""The outcomes' names in French (the results keep the English ones: they are data)."""


def outcome_said(name: str) -> str:
    """An outcome's name in the active language (a cell not judged yet has none: '')."""
    return say(name, OUTCOMES_FR.get(name, name))


def outcome(finished: bool, invariants, rotation_error: float, position_error: float) -> str:
    """The cell's category among OUTCOMES (thresholds above)."""
    if not finished:
        return "diverged"
    errors = [v for _, v in invariants]
    if not all(v <= RUNAWAY for v in errors):          # nan counts as ran away
        return "ran away"
    motion_ok = all(math.isnan(v) or v <= tol for v, tol in ((rotation_error, FAITHFUL_ROTATION),
                                                             (position_error, FAITHFUL_POSITION)))
    return "faithful" if motion_ok and all(v <= FAITHFUL_INVARIANT for v in errors) else "stable but wrong"
