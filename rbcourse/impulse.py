"""Impulses: a kick J at a body point, applied between two steps (Baraff 2001, notes part II).

An impulse J (N s, world axes) at the world point r = x + R b changes the momenta at once:

    ΔP = J,    ΔL = (r − c) × J

with c the point the body turns about (its centre of mass x, or its pivot p: then x and P
follow from R and L_p, pivot.py); the formula is engine/motion.py's kick.  The driver applies a
kick at its own time: the step that holds it is split there (the method steps to t, the kick is applied,
the method steps on), inside the compiled loop, which walks a table of the run's kicks (engine/kicks.py); one at
t_end is in the last state recorded.  A scene lays its impulses out once, as arrays (entries), for that table.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .support import checks
from .effects import Effect, body_selection
from .support.language import say


class Impulse(Effect):
    """A kick J (N s, world axes) at a body point b at time t:  ΔP = J,  ΔL = (r − x) × J,  r = x + R b.

    Applied at t itself (the step that holds t is split there); t must be in [0, t_end] (simulate refuses others).
    """
    kind = "event"

    def __init__(self, body_point, impulse, time: float, *, body=None):
        self.body_point = checks.vector3("body_point", body_point)
        self.impulse = checks.vector3("impulse", impulse)
        self.time = checks.real("time", time, low=0.0)
        self.body = body_selection(body)

    def check_time(self, t_end: float):
        """Refuse a kick outside the run, whose time is not in [0, t_end] (it would never be applied):
        ValueError naming Impulse.time, its value and the range."""
        if not 0.0 <= self.time <= t_end:
            raise ValueError(f"Impulse.time (t) must be in [0, t_end] = [0, {t_end:g}] s (the run), got "
                             f"{self.time:g} for {self!r}: a kick outside the run is never applied")

    def due(self, t0: float, t1: float) -> bool:
        """True if this kick falls in the step [t0, t1)."""
        return t0 <= self.time < t1

    def describe(self):
        j, b = np.round(self.impulse, 6).tolist(), np.round(self.body_point, 6).tolist()
        return say(f"an impulse {j} N s at body point {b} at t = {self.time:g} s",
                   f"une impulsion {j} N s au point {b} du corps à t = {self.time:g} s")

    def __repr__(self):
        return f"Impulse(body_point={self.body_point.tolist()}, impulse={self.impulse.tolist()}, time={self.time:g})"


def kick_due(impulses, t0: float, t1: float, sys, S, motion) -> bool:
    """The kicks due in [t0, t1) on the engine's state S (N, 18), in place (kick).  True if any was due."""
    due = [(e, idx) for e, idx in impulses if e.due(t0, t1)]
    kick(due, sys, S, motion)
    return bool(due)


def kick(impulses, sys, S, motion) -> None:
    """The kicks of `impulses` [(Impulse, rows)] on the engine's state S (N, 18) (L about the rotation centre), in
    place: engine/motion.py's kick,  ΔP = J,  ΔL = (r − c) × J,  r = x + R b,  for each body an Impulse acts on.
    sys: the scene's System; motion: the engine module that runs (compiled, or engine/interpreted.py's)."""
    for e, idx in impulses:
        b, J = tuple(float(v) for v in e.body_point), tuple(float(v) for v in e.impulse)
        for i in np.arange(S.shape[0])[idx]:
            motion.kick(sys, S, int(i), b, J)


class Entries(NamedTuple):
    """A scene's impulses as arrays (entries): times (I,), one per Impulse, in the scene's order; and one entry per
    body an Impulse acts on, sorted by time (an Impulse's bodies in its order, Impulses of one time in the scene's):
    time (E,) its Impulse's time, owner (E,) its Impulse, body (E,) its body row, point (E, 3) the body point b,
    impulse (E, 3) J.  The table the compiled loop walks (engine/kicks.py) is these arrays themselves."""
    times: np.ndarray
    time: np.ndarray
    owner: np.ndarray
    body: np.ndarray
    point: np.ndarray
    impulse: np.ndarray


def entries(impulses, n_bodies: int) -> Entries:
    """The kicks of `impulses` [(Impulse, rows)] (rows: slice(None), every body, or an index array) as Entries."""
    every = np.arange(n_bodies)
    rows = [every if isinstance(idx, slice) and idx == slice(None) else every[idx] for _, idx in impulses]
    owner = np.repeat(np.arange(len(impulses)), [len(r) for r in rows])
    times = np.array([e.time for e, _ in impulses], dtype=float)
    vectors = np.array([(e.body_point, e.impulse) for e, _ in impulses], dtype=float).reshape(-1, 2, 3)
    body = np.concatenate(rows).astype(np.int64) if rows else np.zeros(0, np.int64)
    by_time = np.argsort(times[owner], kind="stable")
    out = Entries(times, times[owner][by_time], owner[by_time], body[by_time],
                  np.ascontiguousarray(vectors[owner, 0][by_time]), np.ascontiguousarray(vectors[owner, 1][by_time]))
    for a in out:
        a.setflags(write=False)
    return out


def check_times(impulses, times, t_end: float):
    """Impulse.check_time of every Impulse (times: Entries.times, in their order): the first outside [0, t_end],
    in the scene's order, raises."""
    if len(times) and not times.max() <= t_end:
        impulses[int(np.flatnonzero(~(times <= t_end))[0])][0].check_time(t_end)
