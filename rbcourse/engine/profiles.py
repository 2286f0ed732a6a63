"""Forces over time as data: the time profiles the kernel evaluates itself (rbcourse/profiles.py builds them).

A profile is one row of the System's `profiles` (Q, PROFILE_COLUMNS) = [slot, kind, p0 … p7], its force F(t)
(3,) written into the values the steps read (values[stage, slot], as a force given as a function f(t)):

    CONSTANT   F = f                                      p = f
    PULSE      F = f on t0 <= t < t1, 0 outside           p = f, t0, t1
    RAMP       F = 0 before t0, f (t − t0)/(t1 − t0) on [t0, t1), f after      p = f, t0, t1
               (t0 or t1 beyond ±HALF_LARGEST, where t1 − t0 may overflow, as from −1e308 to 1e308: the same
               quotient of the halves, (t/2 − t0/2)/(t1/2 − t0/2), each half exact there: no overflow)
    SINE       F = offset + a sin(2π ν t + φ)             p = a, ν, φ, offset
    STEPS      F = f_j on t_j <= t < t_(j+1) (f_last after the last t_j, 0 before the first)
               p = first row, rows of the System's `table` (T, 4) = [t_j, f_j]

fill_profiles writes them at the stage times of a chunk of steps (the driver's forcing.stage_times).
"""
from __future__ import annotations

import math

from .jit import njit
from .system import CONSTANT, PROFILE_COLUMNS, PULSE, RAMP, SINE, STEPS   # noqa: F401  (the kinds, the row's size)

HALF_LARGEST = 8.988465674311579e307   # half the largest float (sys.float_info.max / 2): two times within ± this
                                       # are less than the largest float apart


@njit
def profile_value(row, table, t):
    """F(t) (3-tuple) of the profile `row` (slot, kind, p0 … p7), `table` the steps' rows [t_j, f_j]."""
    kind, p = int(row[1]), row[2:]
    if kind == CONSTANT:
        return p[0], p[1], p[2]
    if kind == PULSE:
        if p[3] <= t < p[4]:
            return p[0], p[1], p[2]
        return 0.0, 0.0, 0.0
    if kind == RAMP:
        if t < p[3]:
            s = 0.0
        elif t >= p[4]:
            s = 1.0
        elif abs(p[3]) <= HALF_LARGEST and abs(p[4]) <= HALF_LARGEST:    # |t1 − t0| <= the largest float
            s = (t - p[3]) / (p[4] - p[3])
        else:                                         # t1 − t0 may overflow: the halves (exact at this size)
            s = (0.5 * t - 0.5 * p[3]) / (0.5 * p[4] - 0.5 * p[3])
        return s * p[0], s * p[1], s * p[2]
    if kind == SINE:
        s = math.sin(2.0 * math.pi * p[3] * t + p[4])
        return p[5] + s * p[0], p[6] + s * p[1], p[7] + s * p[2]
    first, rows = int(p[0]), int(p[1])          # STEPS: the last t_j <= t (bisection)
    lo, hi = 0, rows
    while lo < hi:
        mid = (lo + hi) // 2
        if table[first + mid, 0] <= t:
            lo = mid + 1
        else:
            hi = mid
    if lo == 0:
        return 0.0, 0.0, 0.0
    j = first + lo - 1
    return table[j, 1], table[j, 2], table[j, 3]


@njit
def fill_profiles(sys, times, values):
    """values[k, i, slot] := F(times[k, i]) for each profile of the scene (sys.profiles, sys.table);
    times (steps, stages) the stage times, values (steps, stages, slots, 3)."""
    for q in range(sys.profiles.shape[0]):
        row = sys.profiles[q]
        slot = int(row[0])
        for k in range(times.shape[0]):
            for i in range(times.shape[1]):
                f = profile_value(row, sys.table, times[k, i])
                values[k, i, slot, 0], values[k, i, slot, 1], values[k, i, slot, 2] = f[0], f[1], f[2]
