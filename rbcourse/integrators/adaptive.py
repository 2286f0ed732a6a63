"""An error-controlled method: the Dormand–Prince 8(5,3) pair (DOP853, Hairer, Nørsett & Wanner,
Solving ODEs I, §II.10; its table in tableaus.dop853) on Y = (x, q, P, L), with step-size control.

Each call advances exactly by the output interval h, in as many accepted substeps as the
tolerances need; the substep size that worked last is carried to the next call.  The
local error of a substep is kept below  atol + rtol·|y|  (RMS over the components).
`controlled_substeps` is the one step-size controller (the float kernel runs it too).

The tolerances must lie in RTOL_RANGE = [1e-14, 1] and ATOL_RANGE = [1e-100, 1e100]:
below ~100 rounding units (2.2e-16) no substep can meet rtol in floats, and with atol
under 1e-100 the scaled error (e / (atol + rtol |y|))² overflows or its scale² underflows
to zero (a division by zero); rtol > 1 asks for no accuracy at all.
"""
from __future__ import annotations

import math
from typing import Callable, NamedTuple

import numpy as np

from .. import checks
from . import quaternion as quat
from .base import Prepared, prepare
from .tableaus import dop853, rk_stages

SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
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


class AdaptiveY(NamedTuple):
    """The adaptive method's state: Y = (x, q, P, L) (13, N) and the next substep to try."""
    Y: np.ndarray
    h_next: float

    def sum(self):
        return self.Y.sum()


def encode(scene, X):
    return AdaptiveY(quat.encode(scene, X), 0.0)


def decode(scene, A):
    return quat.decode(scene, A.Y)


def controlled_substeps(t: float, t_end: float, sub: float, attempt: Callable, accept: Callable) -> float:
    """The step-size controller: substeps over [t, t_end], starting with `sub`.

    err = attempt(t, sub): try a substep (the scaled error norm; accepted if err <= 1);
    rejected: sub ← sub · max(0.2, 0.9 err^(−1/8)), and again (FloatingPointError below 1e-14 |t|);
    accepted: accept(more) (more: the interval goes on), then sub ← sub · min(10, 0.9 err^(−1/8))
    (a substep cut short at t_end keeps the size wanted).  Returns the substep to try next."""
    while t < t_end:
        wanted, sub = sub, min(sub, t_end - t)
        while True:
            err = attempt(t, sub)
            if err <= 1.0:
                break
            sub *= max(MIN_FACTOR, SAFETY * err ** (-1 / 8))
            if sub < 1e-14 * max(1.0, abs(t)):
                raise FloatingPointError(f"adaptive: the substep fell below {sub:.3g} s at t = {t:.6g}")
        t = t_end if t_end - (t + sub) < 1e-12 * sub else t + sub
        accept(t < t_end)
        grow = MAX_FACTOR if err == 0 else min(MAX_FACTOR, SAFETY * err ** (-1 / 8))
        sub = max(wanted, sub * grow) if sub < wanted else sub * grow   # a substep cut at t_end says little
    return sub


def combined_error(n5: float, n3: float, n: int, h: float) -> float:
    """DOP853's error norm from ‖e5‖² and ‖e3‖² (scaled, over n components): |h| ‖e5‖² / sqrt((‖e5‖² + 0.01 ‖e3‖²) n)."""
    if n5 == 0.0 and n3 == 0.0:
        return 0.0
    return abs(h) * n5 / math.sqrt((n5 + 0.01 * n3) * n)


def first_substep(d0: float, d1: float, h: float) -> float:
    """A first substep from the scaled sizes d0 of y and d1 of f (Hairer's rule of thumb, simplified):
    0.01 d0 / d1 (1e-6 if either is tiny), at most h."""
    return min(h, 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1)


def dop853_substep(scene, t: float, Y: np.ndarray, f0: np.ndarray, h: float, prep: Prepared | None = None):
    """One DOP853 substep: y_new = y + h Σ b_i k_i, and K: the 12 stages and f(y_new) (13, 13, N)."""
    rates = quat.rates
    dY, K = rk_stages(dop853(), lambda c, U: rates(scene, t + c * h, Y + U, prep), h, Y.shape, extra=1, first=f0)
    Y_new = Y + dY
    K[-1] = rates(scene, t + h, Y_new, prep)
    return Y_new, K


def error_norm(K, h: float, scale: np.ndarray) -> float:
    """DOP853's error norm (combined_error), e5 = Σ E5_j k_j and e3 = Σ E3_j k_j each over atol + rtol |y|."""
    table = dop853()
    e5 = np.tensordot(table.E5, K, axes=1) / scale
    e3 = np.tensordot(table.E3, K, axes=1) / scale
    return combined_error(np.sum(e5 * e5), np.sum(e3 * e3), e5.size, h)


def adaptive_step(scene, t: float, A: AdaptiveY, h: float, prep: Prepared | None = None,
                  rtol: float = 1e-8, atol: float = 1e-10) -> AdaptiveY:
    """Advance by h with error-controlled DOP853 substeps (rtol, atol as in scipy's solve_ivp)."""
    prep = prepare(scene) if prep is None else prep
    now = {"Y": A.Y, "f": quat.rates(scene, t, A.Y, prep)}

    def attempt(t, sub):
        now["new"] = Y_new, K = dop853_substep(scene, t, now["Y"], now["f"], sub, prep)
        return error_norm(K, sub, error_scale(now["Y"], Y_new, rtol, atol))

    def accept(more):
        Y_new, K = now["new"]
        now["Y"] = quat.normalized(Y_new)
        if more:
            now["f"] = K[-1]

    sub = A.h_next or initial_substep(A.Y, now["f"], h, rtol, atol)
    sub = controlled_substeps(t, t + h, sub, attempt, accept)
    return AdaptiveY(now["Y"], sub)


def error_scale(Y: np.ndarray, Y_new: np.ndarray, rtol: float, atol: float) -> np.ndarray:
    """atol + rtol × size, each block's size taken as a whole (rotation-invariant): |x|, |q| = 1,
    |P|, |L_b| of each body, the larger at the start and the end of the substep.  (Per-component
    sizes would hold the small components of a vector to a far tighter absolute error.)"""
    def size(block):
        return np.maximum(np.sqrt(np.sum(Y[block] ** 2, axis=0)), np.sqrt(np.sum(Y_new[block] ** 2, axis=0)))
    scale = np.empty_like(Y)
    scale[quat.X_] = atol + rtol * size(quat.X_)
    scale[quat.Q_] = atol + rtol
    scale[quat.P_] = atol + rtol * size(quat.P_)
    scale[quat.L_] = atol + rtol * size(quat.L_)
    return scale


def initial_substep(Y, f, h, rtol, atol) -> float:
    """first_substep from the RMS sizes of y and f, scaled by error_scale."""
    scale = error_scale(Y, Y, rtol, atol)
    return first_substep(np.sqrt(np.mean((Y / scale) ** 2)), np.sqrt(np.mean((f / scale) ** 2)), h)
