"""Impulses: a kick J at a body point, applied between two steps (Baraff 2001, notes part II).

An impulse J (N s, world axes) at the world point r = x + R b changes the momenta at once:

    ΔP = J,    ΔL = (r − c) × J

with c the point the body turns about (its centre of mass x, or its pivot p: then x and P
follow from R and L_p, pivot.py).  The driver applies a kick at the start of the step that
contains its time, so within one step of it.
"""
from __future__ import annotations

import numpy as np

from . import checks
from .effects import Effect, body_selection
from .rotation import cross, matvec
from .state import State


class Impulse(Effect):
    """A kick J (N s, world axes) at a body point b at time t:  ΔP = J,  ΔL = (r − x) × J,  r = x + R b.

    Applied at the start of the step that contains t (so within one step of t).
    """
    kind = "event"

    def __init__(self, body_point, impulse, time: float, *, body=None):
        self.body_point = checks.vector3("body_point", body_point)
        self.impulse = checks.vector3("impulse", impulse)
        self.time = checks.real("time", time, low=0.0)
        self.body = body_selection(body)

    def due(self, t0: float, t1: float) -> bool:
        """True if this kick falls in the step [t0, t1)."""
        return t0 <= self.time < t1

    def describe(self):
        return (f"an impulse {np.round(self.impulse, 6).tolist()} N s at body point "
                f"{np.round(self.body_point, 6).tolist()} at t = {self.time:g} s")

    def __repr__(self):
        return f"Impulse(body_point={self.body_point.tolist()}, impulse={self.impulse.tolist()}, time={self.time:g})"


def apply_impulses(impulses, pivots, t0: float, t1: float, X: State) -> State:
    """The kicks due in [t0, t1):  ΔP = J,  ΔL = (r − c) × J,  r = x + R b  (X itself if none is due).

    impulses: [(Impulse, rows)] with rows the bodies it kicks; pivots: the scene's Pivots
    (c = pivots.centre(x); pivoted bodies then get x and P from R and L_p).
    X: the state over N bodies, in the engine's coordinates.
    """
    P, L = X.P, X.L
    for e, idx in impulses:
        if not e.due(t0, t1):
            continue
        P, L = P.copy(), L.copy()
        r = X.x[idx] + matvec(X.R[idx], e.body_point)
        P[idx] += e.impulse
        L[idx] += cross(r - pivots.centre(X.x)[idx], e.impulse)
    if P is X.P:
        return X
    return pivots.constrain(State.unchecked(X.x, X.R, P, L))
