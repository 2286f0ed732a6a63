"""Arrays of any leading shape as rows, for the engine's row functions (engine/rows.py).

The engine writes each formula once, for one body (engine/motion.py, engine/algebra.py); the numpy side
(a State's bodies, a trajectory's recorded states, the rotation helpers) applies the same functions
row by row instead of writing them again:

    lead, (R, L) = as_rows(R, L, tails=((3, 3), (3,)))     # broadcast, flatten to (n, 3, 3), (n, 3)
    out = np.empty_like(L); engine_rows().angular_velocity_rows(R_inv, L, out)
    out.reshape(lead + (3,))

Importing this module loads no numba: the engine loads at the first call of engine_rows().
"""
from __future__ import annotations

import numpy as np


def as_rows(*arrays, tails):
    """The arrays broadcast against each other over their leading axes and laid out as rows (contiguous
    float copies), with their trailing shapes `tails`: -> (lead, [rows...])."""
    lead = np.broadcast_shapes(*(np.shape(a)[:np.ndim(a) - len(t)] for a, t in zip(arrays, tails)))
    return lead, [np.array(np.broadcast_to(np.asarray(a, dtype=float), lead + t).reshape((-1,) + t))
                  for a, t in zip(arrays, tails)]


def engine_rows():
    """engine/rows.py: the engine's per-body formulas applied to every row (numba loads here)."""
    from .engine import rows
    return rows
