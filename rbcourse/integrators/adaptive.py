"""An error-controlled method: the Dormand–Prince 8(5,3) pair (DOP853, Hairer, Nørsett & Wanner,
Solving ODEs I, §II.10) on Y = (x, q, P, L), with step-size control.

Each call advances exactly by the output interval h, in as many accepted substeps as the
tolerances need; the substep size that worked last is carried to the next call.  The
local error of a substep is kept below  atol + rtol·|y|  (RMS over the components).

The tolerances must lie in RTOL_RANGE = [1e-14, 1] and ATOL_RANGE = [1e-100, 1e100]:
below ~100 rounding units (2.2e-16) no substep can meet rtol in floats, and with atol
under 1e-100 the scaled error (e / (atol + rtol |y|))² overflows or its scale² underflows
to zero (a division by zero); rtol > 1 asks for no accuracy at all.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.integrate._ivp import dop853_coefficients as dop

from .. import checks
from . import quaternion as quat
from .base import Method, register

_S = dop.N_STAGES                     # 12 stages, and the 13th is f at the new point
_A, _B, _C = dop.A[:_S, :_S], dop.B, dop.C[:_S]
_E3, _E5 = dop.E3, dop.E5
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
    """The adaptive method's state: Y = (x, q, P, L) (N, 13) and the next substep to try."""
    Y: np.ndarray
    h_next: float

    def sum(self):
        return self.Y.sum()


def encode(scene, X):
    return AdaptiveY(quat.encode(scene, X), 0.0)


def decode(scene, A):
    return quat.decode(scene, A.Y)


def dop853_substep(scene, t: float, Y: np.ndarray, f0: np.ndarray, h: float):
    """One DOP853 substep: y_new = y + h Σ b_i k_i, and the error estimate's two parts (E5, E3)."""
    K = np.empty((_S + 1,) + Y.shape)      # Y: (13, N)
    K[0] = f0
    for s in range(1, _S):
        dY = np.tensordot(_A[s, :s], K[:s], axes=1)
        K[s] = quat.rates(scene, t + _C[s] * h, Y + h * dY)
    Y_new = Y + h * np.tensordot(_B, K[:_S], axes=1)
    K[_S] = quat.rates(scene, t + h, Y_new)
    return Y_new, K


def error_norm(K, h: float, scale: np.ndarray) -> float:
    """DOP853's error norm: |h| ‖e5‖² / sqrt((‖e5‖² + 0.01 ‖e3‖²) n), each part scaled by atol + rtol |y|."""
    e5 = np.tensordot(_E5, K, axes=1) / scale
    e3 = np.tensordot(_E3, K, axes=1) / scale
    n5, n3 = np.sum(e5 * e5), np.sum(e3 * e3)
    if n5 == 0.0 and n3 == 0.0:
        return 0.0
    return abs(h) * n5 / np.sqrt((n5 + 0.01 * n3) * e5.size)


def adaptive_step(scene, t: float, A: AdaptiveY, h: float, rtol: float = 1e-8, atol: float = 1e-10) -> AdaptiveY:
    """Advance by h with error-controlled DOP853 substeps (rtol, atol as in scipy's solve_ivp)."""
    Y, t_end = A.Y, t + h
    f = quat.rates(scene, t, Y)
    sub = A.h_next or _initial_substep(Y, f, h, rtol, atol)
    while t < t_end:
        wanted, sub = sub, min(sub, t_end - t)
        while True:
            Y_new, K = dop853_substep(scene, t, Y, f, sub)
            scale = error_scale(Y, Y_new, rtol, atol)
            err = error_norm(K, sub, scale)
            if err <= 1.0:
                break
            sub *= max(MIN_FACTOR, SAFETY * err ** (-1 / 8))
            if sub < 1e-14 * max(1.0, abs(t)):
                raise FloatingPointError(f"adaptive: the substep fell below {sub:.3g} s at t = {t:.6g}")
        t = t_end if t_end - (t + sub) < 1e-12 * sub else t + sub
        Y = quat.normalized(Y_new)
        f = K[_S] if t < t_end else f
        grow = MAX_FACTOR if err == 0 else min(MAX_FACTOR, SAFETY * err ** (-1 / 8))
        sub = max(wanted, sub * grow) if sub < wanted else sub * grow   # a substep cut at t_end says little
    return AdaptiveY(Y, sub)


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


def _initial_substep(Y, f, h, rtol, atol) -> float:
    """A first substep from the sizes of y and f (Hairer's rule of thumb, simplified)."""
    scale = error_scale(Y, Y, rtol, atol)
    d0 = np.sqrt(np.mean((Y / scale) ** 2))
    d1 = np.sqrt(np.mean((f / scale) ** 2))
    guess = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    return min(h, guess)


register(Method(
    "adaptive", adaptive_step, order=8, keeps=frozenset({"SO(3)"}),
    cost="12 force evaluations per substep; as many substeps as rtol/atol need",
    reference="Dormand & Prince 8(5,3), as in Hairer, Nørsett & Wanner, Solving ODEs I (DOP853); scipy's solve_ivp "
              "(here with a rotation-invariant error scale: |L_b|, not each component)",
    summary="error-controlled DOP853 on (x, q, P, L): you set rtol/atol, it picks the substeps",
    stable="finite on every hard case (the substep shrinks as needed); energy drift set by rtol",
    encode=encode, decode=decode, options=("rtol", "atol"), settings={"rtol": 1e-8, "atol": 1e-10},
    check_options=check_tolerances,
    claims=dict(finite=True, so3=1e-12)))
