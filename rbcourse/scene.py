"""A scene: the bodies, and the effects it calls for — and nothing else is computed.

``Scene(body, effects=[Gravity(), ...])`` or ``Scene([body_a, body_b], effects=[...])``.
The engine steps the N bodies as arrays: x (N, 3), R (N, 3, 3), P (N, 3), L (N, 3).
A scene with no effect is a free body: no force is ever evaluated.
"""
from __future__ import annotations

import numpy as np

from .body import RigidBody
from .effects import Effect, Kinematics
from .state import State


class Scene:
    """Bodies plus effects.  Constants only: simulating a scene never changes it."""

    def __init__(self, bodies, effects=(), *, name: str | None = None):
        if isinstance(bodies, RigidBody):
            bodies = [bodies]
        try:
            bodies = tuple(bodies)
        except TypeError:
            raise ValueError(f"bodies must be a RigidBody or a sequence of RigidBody, got {bodies!r}") from None
        if not bodies or not all(isinstance(b, RigidBody) for b in bodies):
            raise ValueError(f"bodies must be a RigidBody or a non-empty sequence of RigidBody, got {bodies!r}")
        if isinstance(effects, Effect):
            effects = [effects]
        try:
            effects = tuple(effects)
        except TypeError:
            raise ValueError(f"effects must be a sequence of effects (Gravity(), PointForce(...), ...), got {effects!r}") from None
        for e in effects:
            if not isinstance(e, Effect):
                raise ValueError(f"effects must contain effect objects (Gravity(), PointForce(...), ...), got {e!r}")
        self.bodies = bodies
        self.effects = effects
        self.name = name
        self.n_bodies = len(bodies)
        self.single = len(bodies) == 1
        self.mass = np.array([b.mass for b in bodies])
        self.I_body = np.stack([b.I_body for b in bodies])
        self.I_body_inv = np.stack([b.I_body_inv for b in bodies])
        for arr in (self.mass, self.I_body, self.I_body_inv):
            arr.setflags(write=False)
        self._forces = [(e, self._indices(e.body, e)) + self._other(e) for e in effects if e.kind == "force"]
        self._torques = [(e, idx) for e, idx, *_ in self._forces if type(e).torque is not Effect.torque]
        self._pointforces = [(e, idx, *rest) for e, idx, *rest in self._forces if type(e).applied is not Effect.applied]

    # --- which bodies an effect acts on -------------------------------------------
    def _indices(self, body, effect):
        n = self.n_bodies
        if body is None:
            return slice(None)
        if isinstance(body, RigidBody):
            hits = [i for i, b in enumerate(self.bodies) if b is body]
            if len(hits) != 1:
                raise ValueError(f"body of {effect!r} must be one body of the scene (found {len(hits)} matches): "
                                 "pass its index instead")
            return np.array(hits)
        items = [body] if isinstance(body, (int, np.integer)) else list(body)
        for i in items:
            if not 0 <= i < n:
                raise ValueError(f"body of {effect!r} must be an index in [0, {n - 1}], got {i}")
        return np.array(items, dtype=int)

    def _other(self, e):
        other = getattr(e, "other_body", None)
        if other is None:
            return ()
        idx = self._indices(other, e)
        return (idx,)

    # --- what the scene computes ---------------------------------------------------
    @property
    def has_forces(self) -> bool:
        """True if any effect produces a force or a torque (False: a free body)."""
        return bool(self._forces)

    def resultants(self, t: float, x, R, v, omega):
        """F = Σ Fᵢ and τ = Σ (rᵢ − x) × Fᵢ (+ pure torques) over the scene's effects only.

        Arrays over the N bodies; returns (F, tau), each (N, 3), or (None, None)
        for a scene with no force (nothing is evaluated then).
        """
        if not self._forces:
            return None, None
        k = Kinematics(t, x, R, v, omega, self.mass)
        F = np.zeros_like(x)
        tau = np.zeros_like(x)
        for e, idx, *other in self._pointforces:
            for j, r, Fi in e.applied(k, idx, *other):
                F[j] += Fi                               # F = Σ Fᵢ
                tau[j] += np.cross(r - x[j], Fi)         # τ = Σ (rᵢ − x) ∧ Fᵢ
        for e, idx in self._torques:
            tau[idx] += e.torque(k, idx)
        return F, tau

    def potential_energy(self, x: np.ndarray, R: np.ndarray) -> np.ndarray | None:
        """Σ of the effects' potentials per body, arrays (..., N, 3): -> (..., N), or None if none has one."""
        total = None
        for e, idx, *other in self._forces:
            u = e.potential(x, R, self.mass, idx, *other)
            if u is None:
                continue
            if total is None:
                total = np.zeros(x.shape[:-1])
            total[..., idx] += u
        return total

    # --- single body <-> arrays over N bodies -------------------------------------
    def batch(self, X: State) -> State:
        """The state as arrays over N bodies (a single-body state gets a leading axis of 1)."""
        if not isinstance(X, State):
            raise ValueError(f"X0 must be a State, got {X!r}")
        if X.x.ndim == 1:
            if not self.single:
                raise ValueError(f"X0 holds 1 body but the scene has {self.n_bodies}: use State.stack")
            return State._raw(X.x[None], X.R[None], X.P[None], X.L[None])
        if X.x.shape[0] != self.n_bodies:
            raise ValueError(f"X0 holds {X.x.shape[0]} bodies but the scene has {self.n_bodies}")
        return X

    def describe(self, method: str | None = None) -> str:
        """One short paragraph: which bodies, which effects (and so which physics) this scene simulates."""
        if self.single:
            who = repr(self.bodies[0])
        else:
            kinds = sorted({b.name for b in self.bodies})
            who = f"{self.n_bodies} bodies ({', '.join(kinds)}), stepped together as arrays"
        lines = [f"Scene{' ' + repr(self.name) if self.name else ''}: {who}."]
        if not self.effects:
            lines.append("No effect: a free body in space, no force or torque is ever evaluated "
                         "(P and L stay constant; the torque-free motion can be advanced exactly).")
        else:
            lines.append("Effects computed, and only these: " + "; ".join(e.describe() for e in self.effects) + ".")
            kinds = {type(e).__name__ for e in self.effects}
            if "Ground" not in kinds:
                lines.append("No contact detection.")
        if method is not None:
            lines.append(f"Integrator: {method}.")
        return " ".join(lines)

    def __repr__(self) -> str:
        return self.describe()


def as_scene(scene) -> Scene:
    """A Scene, or a bare RigidBody taken as a free-body scene."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, RigidBody):
        return Scene(scene)
    raise ValueError(f"scene must be a Scene or a RigidBody, got {scene!r}")
