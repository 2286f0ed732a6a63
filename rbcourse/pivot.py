"""A pivot (ball joint): a body point b stays at a world point p, the body only turns about p.

For a pivoted body the engine integrates R and the angular momentum about the pivot

    L_p = L + (x − p) × P

with the inertia about the pivot (parallel-axis theorem, RigidBody.inertia_about)

    I_p = I_body + M (|b|² Id − b bᵀ),   ω = R I_p⁻¹ Rᵀ L_p,

and torques taken about p; the centre of mass follows the rotation:

    x = p − R b,   P = M ω × (x − p).

(Benchmark C, the heavy top.)  ``Pivot`` is the effect a scene calls for; ``Pivots`` holds
what a scene's pivots mean for its N bodies and converts between a State (L about the centre
of mass) and the engine's coordinates (L about the rotation centre).
"""
from __future__ import annotations

import numpy as np

from .support import checks
from .effects import Effect, body_selection
from .rotation import cross
from .state import State, from_matrix, to_matrix
from .support.language import say


class Pivot(Effect):
    """A ball joint: the body point b (body axes, from the centre of mass) stays at the world point p.

    The body then only turns about p: the engine integrates R and the angular momentum
    about the pivot, L_p = L + (x − p) × P, with the inertia about the pivot
    I_p = I_body + M (|b|² Id − b bᵀ) and torques about p; the centre of mass follows,
    x = p − R b and P = M ω × (x − p).  (Benchmark C, the heavy top.)
    """
    kind = "constraint"

    def __init__(self, body_point, world_point=(0.0, 0.0, 0.0), *, body=None):
        self.body_point = checks.vector3("body_point", body_point)
        self.world_point = checks.vector3("world_point", world_point)
        self.body = body_selection(body)

    def state(self, body, R, omega):
        """A State consistent with this pivot: x = p − R b, v = ω × (x − p), ω in world axes."""
        R = checks.array("R", R, (3, 3))
        omega = checks.vector3("omega", omega)
        x = self.world_point - R @ self.body_point
        return State.from_velocities(body, x, R, cross(omega, x - self.world_point), omega)

    def describe(self):
        b, p = np.round(self.body_point, 6).tolist(), np.round(self.world_point, 6).tolist()
        return say(f"a pivot holding body point {b} at world point {p} (rotation about it only)",
                   f"un pivot qui tient le point {b} du corps au point {p} du monde (rotation autour de lui seulement)")

    def __repr__(self):
        return f"Pivot(body_point={self.body_point.tolist()}, world_point={self.world_point.tolist()})"


class Pivots:
    """The pivots of a scene, over its N bodies (constants: arrays are read-only).

    pivoted (N,) bool, body_point b (N, 3), world_point p (N, 3) (zeros for free bodies),
    I_rot (N, 3, 3): I_p for a pivoted body, I_body otherwise; I_rot_inv its inverse.
    """

    def __init__(self, bodies, pivots):
        """bodies: the scene's RigidBody tuple; pivots: [(Pivot, rows)] with rows the indices it holds."""
        n = len(bodies)
        self.bodies = tuple(bodies)
        self.mass = np.array([b.mass for b in bodies])
        self.any = bool(pivots)
        self.pivoted = np.zeros(n, dtype=bool)
        self.body_point = np.zeros((n, 3))
        self.world_point = np.zeros((n, 3))
        for e, idx in pivots:
            rows = np.arange(n)[idx]
            if self.pivoted[rows].any():
                raise ValueError(f"{e!r}: a body can have at most one Pivot")
            self.pivoted[rows] = True
            self.body_point[rows] = e.body_point
            self.world_point[rows] = e.world_point
        self.I_rot = np.stack([b.inertia_about(c) if p else b.I_body
                               for b, c, p in zip(bodies, self.body_point, self.pivoted)])
        self.I_rot_inv = np.linalg.inv(self.I_rot)
        for arr in (self.mass, self.pivoted, self.body_point, self.world_point, self.I_rot, self.I_rot_inv):
            arr.setflags(write=False)

    def centre(self, x: np.ndarray) -> np.ndarray:
        """The point each body turns about: its centre of mass x, or its pivot p."""
        if not self.any:
            return x
        return np.where(self.pivoted[:, None], self.world_point, x)

    def constrain(self, X: State, system) -> State:
        """Pivoted bodies: x = p − R b and P = M ω × (x − p), from R and L_p (a no-op without pivots):
        engine/motion.py's constrain_state (run as Python) on the scene's System, system() (a callable:
        built only where a pivot needs it)."""
        if not self.any:
            return X
        sys = system()
        from .engine import interpreted
        S = to_matrix(X)
        interpreted.module("motion").constrain_state(sys, S)
        return from_matrix(S)

    def to_engine(self, X: State, system) -> State:
        """A State over the N bodies (L about the centre of mass) -> the engine's coordinates (L_p).

        For a pivoted body, X must hold the body point b at p (x = p − R b) and move with it
        (v = ω × (x − p)): constraining it (constrain) must leave x and P as they are; Pivot.state(body,
        R, omega) builds such a state.  L_p = L + (x − p) × P.
        """
        if not self.any:
            return X
        L = X.L + np.where(self.pivoted[:, None], cross(X.x - self.centre(X.x), X.P), 0.0)
        E = self.constrain(State.unchecked(X.x, X.R, X.P, L), system)
        for i in np.flatnonzero(self.pivoted):
            p = self.world_point[i]
            scale = 1.0 + np.abs(p).max() + np.abs(self.body_point[i]).max()
            if np.abs(X.x[i] - E.x[i]).max() > 1e-9 * scale:
                raise ValueError(f"X0.x of body {i} must put its pivot point at {p.tolist()}: expected x = "
                                 f"{E.x[i].tolist()}, got {X.x[i].tolist()} (use Pivot.state(body, R, omega))")
            if np.abs(X.P[i] - E.P[i]).max() > 1e-9 * (1.0 + np.abs(E.P[i]).max()):
                raise ValueError(f"X0.P of body {i} must move with its pivot, P = M ω × (x − p) = "
                                 f"{E.P[i].tolist()}, got {X.P[i].tolist()} (use Pivot.state(body, R, omega))")
        return E

    def to_state_arrays(self, x, R, P, L):
        """The engine's arrays (..., N, 3) -> L about the centre of mass:  L = L_p − (x − p) × P."""
        if not self.any:
            return L
        return L - np.where(self.pivoted[:, None], cross(x - self.world_point, P), 0.0)
