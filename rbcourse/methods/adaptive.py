"""An error-controlled method: the Dormand–Prince 8(5,3) pair (DOP853, Hairer, Nørsett & Wanner,
Solving ODEs I, §II.10; its table in engine/tableaus.dop853) on Y = (x, q, P, L), with step-size control.

Each step advances exactly by the output interval h, in as many accepted substeps as the
tolerances need; the substep size that worked last is carried to the next step.  The
local error of a substep is kept below  atol + rtol·|y|  (RMS over the components).
The step is the engine's (rbcourse/engine/adaptive.py, its step-size control engine/control.py); here are the
ranges of its settings.

The tolerances must lie in RTOL_RANGE = [1e-14, 1] and ATOL_RANGE = [1e-100, 1e100]:
below ~100 rounding units (2.2e-16) no substep can meet rtol in floats, and with atol
under 1e-100 the scaled error (e / (atol + rtol |y|))² overflows or its scale² underflows
to zero (a division by zero); rtol > 1 asks for no accuracy at all.
"""
from __future__ import annotations

from ..support import checks

RTOL_RANGE = (1e-14, 1.0)              # what rtol and atol may be (see the module docstring)
ATOL_RANGE = (1e-100, 1e100)


def check_tolerances(options: dict) -> dict:
    """rtol in RTOL_RANGE and atol in ATOL_RANGE (real numbers), else a ValueError naming them."""
    out = dict(options)
    for name, (low, high) in (("rtol", RTOL_RANGE), ("atol", ATOL_RANGE)):
        if name in out:
            value = checks.real(name, out[name])
            if not low <= value <= high:
                raise ValueError(f"{name} must be in [{low:g}, {high:g}] (the adaptive method's tolerances), "
                                 f"got {value!r}")
            out[name] = value
    return out
