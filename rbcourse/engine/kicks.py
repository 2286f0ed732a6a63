"""Impulses inside the loop: the scene's kicks as a table sorted by time, which the loop (run.py) walks, each kick
applied at its own time.

A kick J at the body point b of body i (motion.kick):   ΔP = J,   ΔL = (r − c) × J,   r = x + R b.

Its time t falls in step k of the run (kick_step: k = ⌊t/h⌋; a time on a step boundary j h, to rounding, is that
boundary, applied before step j — or at t_end = n h, at the end of the last step).  A step that holds kicks is
split at their times (run.split_step), as the driver splits a step it makes in Python (rbcourse/simulate.py:
_python_step): from t = k h, for each time t' of its kicks, in order,

    the method steps from t to t' (a piece: size t' − t; none if t' = t), then the kicks at t' are applied;

then the method steps on to (k + 1) h.  A piece from k h to (k + 1) h is the whole step (size h).  The kicks of one
time are applied in the order the scene gives them, each to the slides' state S read from the method's (the
layout's decode), S then laid out back as the method's (its encode): the same numbers as the driver's.

The table is the scene's, made once (rbcourse/impulse.py: entries, sorted by time): a run adds no array per kick.
"""
from __future__ import annotations

import bisect
import math
from typing import NamedTuple

import numpy as np

from .jit import inline
from .motion import kick, mat, put_state, vec


class Kicks(NamedTuple):
    """A run's kicks as the loop walks them: one entry per body an Impulse acts on, sorted by time (an Impulse's
    bodies in its order; Impulses of one time in the scene's order): time (E,) its Impulse's time, owner (E,) its
    Impulse (the scene's order), body (E,) its body row i, point (E, 3) its body point b, impulse (E, 3) J; and the
    loop's work: state (N, m) the step's state between its pieces, S (N, 18) the slides' state of a kick, x, R, P,
    L (1, N, …) the decoded state (a record row)."""
    time: np.ndarray
    owner: np.ndarray
    body: np.ndarray
    point: np.ndarray
    impulse: np.ndarray
    state: np.ndarray
    S: np.ndarray
    x: np.ndarray
    R: np.ndarray
    P: np.ndarray
    L: np.ndarray


def table(time, owner, body, point, impulse, Y) -> Kicks:
    """The table of a scene's kicks (entries sorted by time: rbcourse/impulse.py, entries) for a run from the
    method's state Y (N, m): the entries as they are, and the loop's work arrays."""
    N = Y.shape[0]
    return Kicks(time, owner, body, point, impulse, np.empty_like(Y), np.empty((N, 18)), np.empty((1, N, 3)),
                 np.empty((1, N, 3, 3)), np.empty((1, N, 3)), np.empty((1, N, 3)))


@inline
def kick_step(t, n, h):
    """(k, t'): the step k of n (size h) that holds a kick at time t, and the time it is applied at.  t/h within
    1e-9 steps of an integer j (its nearest): the boundary j h, before step j (k = j, t' = j h), or at t_end
    (j = n: k = n − 1, t' = n h); else k = ⌊t/h⌋ and t' = t."""
    s = t / h
    j = np.rint(s)
    if abs(s - j) <= 1e-9 * max(1.0, abs(s)):
        if j < n:
            return int(j), j * h
        return n - 1, n * h
    return min(int(math.floor(s)), n - 1), t


@inline
def next_kick(kicks, e, n, h):
    """kick_step of entry e's kick: (its step, its time); (n, 0.0), no step, when e is past the last entry."""
    if e < len(kicks.time):
        return kick_step(kicks.time[e], n, h)
    return n, 0.0


@inline
def first_kick(kicks, k0, n, h):
    """The first entry whose kick is in step k0 or later (len(kicks.time) if none): a binary search, the entries'
    steps ascending with their times."""
    lo, hi = 0, len(kicks.time)
    while lo < hi:
        mid = (lo + hi) // 2
        if kick_step(kicks.time[mid], n, h)[0] < k0:
            lo = mid + 1
        else:
            hi = mid
    return lo


@inline
def kick_state(decode, encode, sys, Y, new, kicks, lo, hi):
    """new := the method's state Y (N, m) after the kicks of entries lo … hi − 1 (one time): Y read as the slides' S
    (decode, as a record row, then S row by row), the kicks applied to S (in_order), S laid out as new (encode; new
    may be Y itself)."""
    decode(sys, Y, 0, kicks.x, kicks.R, kicks.P, kicks.L)
    S = kicks.S
    for i in range(Y.shape[0]):
        put_state(S, i, vec(kicks.x[0], i), mat(kicks.R[0], i), vec(kicks.P[0], i), vec(kicks.L[0], i))
    in_order(sys, S, kicks, lo, hi)
    encode(S, new)


@inline
def in_order(sys, S, kicks, lo, hi):
    """Each entry lo … hi − 1 on S (motion.kick: ΔP = J, ΔL = (r − c) × J), Impulse by Impulse in the scene's order
    (kicks.owner ascending; an Impulse's entries are side by side): the entries are sorted by time, and one time on
    a step boundary may gather kicks whose own times differed by a rounding, in another order."""
    done = -1
    while True:
        first = -1
        for e in range(lo, hi):
            if kicks.owner[e] > done and (first < 0 or kicks.owner[e] < kicks.owner[first]):
                first = e
        if first < 0:
            return
        done = kicks.owner[first]
        e = first
        while e < hi and kicks.owner[e] == done:
            kick(sys, S, kicks.body[e], vec(kicks.point, e), vec(kicks.impulse, e))
            e += 1


def pieces(kicks: Kicks, k0: int, k1: int, n: int, h: float):
    """(starts, sizes) of the pieces that are not a whole step, of the steps k0 … k1 − 1 that hold kicks, in the
    order the loop makes them (run.split_step): the driver evaluates the forces f(t) at their stage times.  Run as
    Python (kick_step's own code)."""
    step_of = getattr(kick_step, "py_func", kick_step)
    time, end = kicks.time, len(kicks.time)
    e = bisect.bisect_left(range(end), k0, key=lambda e: step_of(time[e], n, h)[0])
    starts, sizes = [], []
    while e < end and step_of(time[e], n, h)[0] < k1:
        k = step_of(time[e], n, h)[0]
        t0, t1 = k * h, (k + 1) * h
        t = t0
        while True:
            step, at = step_of(time[e], n, h) if e < end else (-1, t1)
            kicked = step == k
            at = at if kicked else t1
            if at > t:
                if not (t == t0 and at == t1):
                    starts.append(t)
                    sizes.append(at - t)
                t = at
            if not kicked:
                break
            while e < end and step_of(time[e], n, h) == (k, at):
                e += 1
    return np.array(starts, dtype=float), np.array(sizes, dtype=float)
