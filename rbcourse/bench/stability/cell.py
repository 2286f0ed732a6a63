"""One cell of the stability matrix: what one method did on one hard case (Cell)."""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass
class Cell:
    """What one method did on one hard case."""
    case: str
    method: str
    finished: bool
    t_end: float                  # where it stopped (the case's T if it finished)
    energy_error: float           # max |E − E0| / |E0|  (E summed over the bodies)
    energy_gain: float            # max (E − E0) / |E0|  (> 0: energy was gained)
    energy_drift: float           # max |E − E0| over the last half / over the first half
    momentum_error: float         # the "L" invariant if declared, else "L_z" (nan if neither)
    norm_L_error: float           # the "norm_L" invariant (nan if not declared)
    orthogonality: float          # max ‖RᵀR − I‖
    rotation_error: float         # at the end, against the reference (nan if none)
    diverged_at: float = math.nan  # the time of the blow-up (nan if it finished); t_end is the last good state
    invariants: tuple = ()        # ((name, max relative error), ...): every invariant the case declares
    position_error: float = math.nan   # ‖x − x_ref‖ at the end (m, largest over the bodies; nan if no reference)
    outcome: str = ""             # one of OUTCOMES (stability.outcome)

    def invariant(self, name: str) -> float:
        """The max relative error of a declared invariant (nan if the case does not declare it)."""
        return dict(self.invariants).get(name, math.nan)
