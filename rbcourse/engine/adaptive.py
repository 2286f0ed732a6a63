"""The adaptive method, compiled: DOP853 substeps under step-size control on Y = [x, q, P, L_b] (N, 13).

One call advances by the output interval h, in as many accepted substeps as rtol, atol need:

    k_i = f(y + sub Σ_j a_ij k_j)  (12 stages),   y_new = y + sub Σ_i b_i k_i,   k_13 = f(y_new)
    err = combined_error(‖e5 / scale‖², ‖e3 / scale‖²),  e5 = Σ_j E5_j k_j,  e3 = Σ_j E3_j k_j
    err <= 1: accept (y ← y_new with q normalised; k_1 ← k_13, first same as last), sub ← sub · min(10, 0.9 err^(−1/8))
    err > 1:  reject, sub ← sub · max(0.2, 0.9 err^(−1/8))

The run's data (its opts array, slots RTOL … WANTED below): rtol, atol, the substep to try next (carried
from one output step to the next; 0 means "not yet chosen": initial_substep), the number of output steps
done (so the substeps' times are t = k h + …), counters of the accepted and rejected substeps, and DOP853's
error weights E5, E3 (numba cannot cache functions that read global arrays).  adaptive_step updates
opts[SUB], opts[STEPS], opts[ACCEPTED], opts[REJECTED]: one opts array per run.  The table A (12, 12),
b (12,), den: its arguments (table()).

K (14, N, 13): K[0 … 11] the stages, K[12] = f(y_new), K[13] the substep's y_new.  values[i] are the
forces given as functions f(t) at the substep's stage times t + c_i sub (c_12 = 1 for f(y_new)): the
substeps are chosen here, by the error control, so before each attempt the step writes its t and sub
into opts[T_AT], opts[SUB_AT]; the run (rbcourse/forcing.py: SubstepForces, called by simulate.py) then evaluates the forces
f(t) in Python at those times and calls attempt() again, between compiled calls.
"""
from __future__ import annotations

import math

import numpy as np

from . import control
from .control import MAX_FACTOR, MIN_FACTOR, SAFETY
from .jit import inline, njit
from .motion import copy_into, stage
from .quaternion import normalize_quats, rates_quat
from .stages import rk_stages

# opts: the slot of each datum in the run's opts array
RTOL, ATOL, SUB, STEPS, ACCEPTED, REJECTED, E5_AT, E3_AT, T_AT, SUB_AT, WANTED = 0, 1, 2, 3, 4, 5, 6, 19, 32, 33, 34
N_OPTS = 35
STAGES = 12
F_NEW, Y_NEW = 12, 13          # the K slots of f(y_new) and y_new
SLOTS = 14                     # K slots needed: 12 stages + 2 scratch


def options(rtol: float = control.RTOL, atol: float = control.ATOL) -> np.ndarray:
    """A run's opts array (the module docstring): rtol, atol (by default control.RTOL, control.ATOL; RTOL and ATOL
    here are their slots in opts), no substep chosen yet, 0 steps done, 0 substeps, E5, E3 of tableaus.dop853()."""
    from .tableaus import dop853
    t = dop853()
    opts = np.zeros(N_OPTS)
    opts[RTOL], opts[ATOL] = rtol, atol
    opts[E5_AT:E5_AT + 13] = t.E5
    opts[E3_AT:E3_AT + 13] = t.E3
    return opts


def nodes() -> tuple:
    """The times t + c_i sub of the forces f(t) in a substep: DOP853's c, and 1 for f(y_new)."""
    from .tableaus import dop853
    return tuple(dop853().c) + (1.0,)


def configure(sys, settings: dict) -> tuple:
    """The family's run (run.py: LOOPS["adaptive"]): (table, nodes, opts) — DOP853, the times of the forces in a
    substep, the opts array from the method's settings (rtol, atol)."""
    from .tableaus import dop853
    return dop853(), nodes(), options(**settings)


@njit
def forget_substep(opts):
    """The substep is chosen again at the next step (the state changed between steps: an impulse, a contact)."""
    opts[SUB] = 0.0


def table() -> tuple:
    """DOP853's A (12, 12), b (12,), den as adaptive_step takes them (contiguous arrays)."""
    from .tableaus import dop853
    t = dop853()
    return np.ascontiguousarray(t.A), np.ascontiguousarray(t.b), float(t.den)


@inline
def py_min(a, b):
    """Python's min(a, b): a unless b < a."""
    return b if b < a else a


@inline
def py_max(a, b):
    """Python's max(a, b): a unless b > a."""
    return b if b > a else a


@inline
def larger(a, b):
    """np.maximum(a, b): the larger, NaN if either is NaN."""
    if a != a or b != b:
        return math.nan
    return a if a >= b else b


@inline
def block_size(Y, p, a, c):
    """|Y[p, a:c]|: the size of one block (x, P or L_b) of body p."""
    s = 0.0
    for q in range(a, c):
        s += Y[p, q] ** 2
    return math.sqrt(s)


@inline
def scale_of(Y, Y_new, p, q, rtol, atol):
    """The error scale of component q of body p: s = atol + rtol × the larger size of its block (|x|, |P|,
    |L_b|) at the start Y and the end Y_new of the substep; s = atol + rtol for q (|q| = 1)."""
    if 3 <= q < 7:
        return atol + rtol
    a = 0 if q < 3 else (7 if q < 10 else 10)
    return atol + rtol * larger(block_size(Y, p, a, a + 3), block_size(Y_new, p, a, a + 3))


@inline
def combined_error(n5, n3, n, h):
    """DOP853's error from the squared sums n5 = ‖e5 / s‖², n3 = ‖e3 / s‖² over n components:
    err = |h| n5 / sqrt((n5 + 0.01 n3) n)  (0 when both are 0)."""
    if n5 == 0.0 and n3 == 0.0:
        return 0.0
    return abs(h) * n5 / math.sqrt((n5 + 0.01 * n3) * n)


@inline
def squared_terms(opts, Y, K, p, q, s, errors):
    """(u / s)², (v / s)² at component q of body p: when errors, the error estimates u = e5 = Σ_j E5_j k_j,
    v = e3 = Σ_j E3_j k_j of the stages k_j = K[j] (error_norm); else u = y = Y[p, q], v = f(y) = K[0, p, q]
    (initial_substep)."""
    if not errors:
        return (Y[p, q] / s) ** 2, (K[0, p, q] / s) ** 2
    e5 = e3 = 0.0
    for j in range(STAGES + 1):
        e5 += opts[E5_AT + j] * K[j, p, q]
        e3 += opts[E3_AT + j] * K[j, p, q]
    e5 /= s
    e3 /= s
    return e5 * e5, e3 * e3


@inline
def scaled_sums(opts, Y, Y_new, K, errors):
    """Σ_pq (u_pq / s_pq)², Σ_pq (v_pq / s_pq)² over every component q of every body p, in that order, with
    s_pq = scale_of(Y, Y_new, p, q, rtol, atol) and u, v as squared_terms gives them (errors: e5, e3; else y, f)."""
    rtol, atol = opts[RTOL], opts[ATOL]
    a = b = 0.0
    for p in range(Y.shape[0]):
        for q in range(Y.shape[1]):
            u, v = squared_terms(opts, Y, K, p, q, scale_of(Y, Y_new, p, q, rtol, atol), errors)
            a += u
            b += v
    return a, b


@njit
def error_norm(opts, Y, Y_new, K, h):
    """The substep's error: combined_error(‖e5 / s‖², ‖e3 / s‖², N·13, h) with e5 = Σ_j E5_j k_j,
    e3 = Σ_j E3_j k_j (k_j = K[j], j = 0 … 12) and s the error scale of each component (scale_of)."""
    n5, n3 = scaled_sums(opts, Y, Y_new, K, True)
    return combined_error(n5, n3, Y.shape[0] * Y.shape[1], h)


@njit
def initial_substep(opts, Y, K, h):
    """The first substep to try, from y = Y and f = f(y) = K[0]: with d0, d1 the RMS sizes of y and f over the error
    scale s at y (d0 = sqrt(Σ (y / s)² / (N·13)), d1 likewise),
    min(h, 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 d0 / d1)."""
    s0, s1 = scaled_sums(opts, Y, Y, K, False)
    n = Y.shape[0] * Y.shape[1]
    d0, d1 = math.sqrt(s0 / n), math.sqrt(s1 / n)
    return py_min(h, 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1)


@njit
def begin_step(opts, sys, values, Y, out, h, K, w):
    """Start the output step [t, t + h], t = opts[STEPS] h: out := Y, K[0] = f(t, Y), and the first substep to
    attempt, opts[SUB] carried from the last output step (or initial_substep): opts[T_AT], opts[SUB_AT] := t, it
    (opts[WANTED] the size the control asked for).  values[0]: the forces given as functions, at t."""
    t = opts[STEPS] * h
    copy_into(out, Y)                                     # out: the state at t, as the substeps go
    opts[T_AT], opts[SUB_AT] = t, 0.0
    rates_quat(sys, stage(values, 0), out, K[0], w)
    sub = opts[SUB]
    if sub == 0.0:
        sub = initial_substep(opts, out, K, h)
    opts[WANTED] = sub
    opts[SUB_AT] = py_min(sub, (t + h) - t)


@njit
def attempt(A, b, den, opts, sys, values, out, h, K, U, w):
    """One attempt of the substep sub = opts[SUB_AT] from t = opts[T_AT] (module docstring): rejected, sub
    shrinks; accepted, out advances to t + sub and the next substep is chosen.  values[i]: the forces given as
    functions at t + c_i sub (values[12] at t + sub).  Returns True when the output step is done (out at
    t_end, opts[SUB] the substep to try next, opts[STEPS] + 1) — or when sub fell below 1e-14 max(1, |t|):
    out is then NaN, a blow-up."""
    t, sub, wanted = opts[T_AT], opts[SUB_AT], opts[WANTED]
    t_end = opts[STEPS] * h + h
    Y_new = K[Y_NEW]
    rk_stages(rates_quat, sys, values, A, b, den, out, Y_new, sub, K, U, w, 1)   # K[0] given: FSAL
    rates_quat(sys, stage(values, STAGES), Y_new, K[F_NEW], w)             # at t + sub
    err = error_norm(opts, out, Y_new, K, sub)
    if not err <= 1.0:                                    # reject (a NaN error too)
        opts[REJECTED] += 1
        sub *= py_max(MIN_FACTOR, SAFETY * err ** (-1 / 8))
        if sub < 1e-14 * py_max(1.0, abs(t)):
            for p in range(out.shape[0]):
                for q in range(out.shape[1]):
                    out[p, q] = math.nan
            opts[SUB] = sub
            opts[STEPS] += 1
            return True
        opts[SUB_AT] = sub
        return False
    t = t_end if t_end - (t + sub) < 1e-12 * sub else t + sub
    opts[ACCEPTED] += 1                                   # accept
    copy_into(out, Y_new)
    normalize_quats(out)
    if t < t_end:
        copy_into(K[0], K[F_NEW])
    grow = MAX_FACTOR if err == 0 else py_min(MAX_FACTOR, SAFETY * err ** (-1 / 8))
    sub = py_max(wanted, sub * grow) if sub < wanted else sub * grow
    if t < t_end:
        opts[T_AT], opts[WANTED], opts[SUB_AT] = t, sub, py_min(sub, t_end - t)
        return False
    opts[SUB] = sub
    opts[STEPS] += 1
    return True


@njit
def adaptive_step(A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """One output step of the adaptive method from Y into out: begin_step, then attempts until it is done
    (opts[SUB] := the substep to try next).  values: the forces given as functions (none in a compiled run:
    the driver then makes the same calls itself, with each attempt's values: driver.SubstepForces)."""
    begin_step(opts, sys, values, Y, out, h, K, w)
    while not attempt(A, b, den, opts, sys, values, out, h, K, U, w):
        pass
