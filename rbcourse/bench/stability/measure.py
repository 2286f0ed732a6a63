"""Running one cell: one method on one hard case, recorded sparsely (at most MAX_RECORDS states), and
what it kept (run_cell: a Cell with its invariants, errors and outcome)."""
from __future__ import annotations

import math

import numpy as np

from ...simulate import simulate
from ..hardcases import HardCase
from .cell import Cell
from .invariants import INVARIANTS, relative_energy_error, total_energy
from .outcomes import outcome
from .references import end_errors, reference_end

MAX_RECORDS = 4000


def run_cell(case: HardCase, method: str, quick: bool = False, reference=None) -> Cell:
    """Run one method on one case and measure what it kept (reference: reference_end(case, T), computed
    here if not given; an (3,3) R alone is accepted too)."""
    T = case.duration(quick)
    n = round(T / case.dt)
    every = max(1, n // MAX_RECORDS)
    traj = simulate(case.scene, case.X0, T, case.dt, method, record_every=every, on_divergence="stop")
    finished = not traj.diverged
    ref = reference_end(case, T) if reference is None else reference
    if isinstance(ref, np.ndarray):
        ref = (ref, None)
    with np.errstate(all="ignore"):
        E = total_energy(traj)
        e = relative_energy_error(traj, case.X0)
        half = len(e) // 2
        drift = float(e[half:].max() / max(e[:max(half, 1)].max(), 1e-300)) if len(e) > 2 else math.nan
        inv = tuple((name, float(np.max(INVARIANTS[name][1](traj, case.X0)))) for name in case.invariants)
        rot, pos = end_errors(traj, ref) if finished else (math.nan, math.nan)
        gain = float(np.max((E - E[0]) / abs(E[0])))
        d = dict(inv)
        return Cell(case.name, method, finished, float(traj.t[-1]), float(e.max()), gain, drift,
                    d.get("L", d.get("L_z", math.nan)), d.get("norm_L", math.nan),
                    float(np.max(traj.orthogonality_error())), rot,
                    traj.divergence.t if traj.diverged else math.nan, inv, pos, outcome(finished, inv, rot, pos))
