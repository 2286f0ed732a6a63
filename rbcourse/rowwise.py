"""Arrays of any leading shape as rows, for the engine's row functions (engine/rows.py).

The engine writes each formula once, for one body (engine/motion.py, engine/algebra.py); the numpy side
(a State's bodies, a trajectory's recorded states, the rotation helpers) applies the same functions
row by row instead of writing them again:

    lead, (R, L) = as_rows(R, L, tails=((3, 3), (3,)))     # broadcast, flatten to (n, 3, 3), (n, 3)
    out = np.empty_like(L); engine_rows().angular_velocity_rows(R_inv, L, out)
    out.reshape(lead + (3,))

The kernel's state rows, one per body, laid out as engine/plan.py's COLUMNS say (written there once):
matrix_rows(x, R, P, L) -> S (..., 18) = [x, R row by row, P, L] and matrix_parts(S) -> (x, R, P, L) (views).

Importing this module loads no numba: the engine loads at the first call of engine_rows().
"""
from __future__ import annotations

import numpy as np

from .engine.plan import COLUMNS

_MATRIX = {name: slice(a, b) for name, a, b in COLUMNS["matrix"]}


def matrix_rows(x, R, P=None, L=None, out=None) -> np.ndarray:
    """The slides' state rows S (..., 18) = [x, R row by row, P, L] of bodies x (..., 3), R (..., 3, 3), P, L (..., 3)
    (P, L: zeros if None): a new contiguous float array, or written into `out` (..., 18)."""
    x = np.asarray(x, dtype=float)
    S = np.zeros(x.shape[:-1] + (COLUMNS["matrix"][-1][2],)) if out is None else out
    if out is not None:
        S[...] = 0.0
    S[..., _MATRIX["x"]], S[..., _MATRIX["R"]] = x, np.asarray(R, dtype=float).reshape(x.shape[:-1] + (9,))
    if P is not None:
        S[..., _MATRIX["P"]] = P
    if L is not None:
        S[..., _MATRIX["L"]] = L
    return S


def matrix_parts(S: np.ndarray):
    """(x, R, P, L) of state rows S (..., 18): views of S, R (..., 3, 3)."""
    return (S[..., _MATRIX["x"]], S[..., _MATRIX["R"]].reshape(S.shape[:-1] + (3, 3)), S[..., _MATRIX["P"]],
            S[..., _MATRIX["L"]])


def as_rows(*arrays, tails):
    """The arrays broadcast against each other over their leading axes and laid out as rows (C-contiguous
    float copies, whatever the inputs' strides: one compiled specialisation of each row function), with their
    trailing shapes `tails`: -> (lead, [rows...])."""
    lead = np.broadcast_shapes(*(np.shape(a)[:np.ndim(a) - len(t)] for a, t in zip(arrays, tails)))
    return lead, [np.array(np.broadcast_to(np.asarray(a, dtype=float), lead + t).reshape((-1,) + t), order="C")
                  for a, t in zip(arrays, tails)]


def engine_rows():
    """engine/rows.py: the engine's per-body formulas applied to every row (numba loads here)."""
    from .engine import rows
    return rows
