"""A scene: the bodies, and the effects it calls for — and nothing else is computed.

``Scene(body, effects=[Gravity(), ...])`` or ``Scene([body_a, body_b], effects=[...])``.
The engine steps the N bodies as arrays: x (N, 3), R (N, 3, 3), P (N, 3), L (N, 3).
A scene with no effect is a free body: no force is ever evaluated.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .body import RigidBody
from .engine import system as kernel_data
from .effects import Effect, Spring, body_selection
from .impulse import check_times, entries, kick_due
from .methods import get_method
from .pivot import Pivots
from .profiles import Profile
from .state import State, from_matrix, to_matrix
from .support import checks
from .support.language import say


class Compiled(NamedTuple):
    """A scene as the kernel reads it: its System (engine/system.py) and the forces f(t) the driver evaluates
    (one per slot, in slot order)."""
    system: kernel_data.System
    functions: tuple          # (PointForce, ...) whose force is a function of t (or a Profile: the kernel's)
    has_forces: bool


class Scene:
    """Bodies plus effects.  Constants only: simulating a scene never changes it."""

    def __init__(self, bodies, effects=(), *, name: str | None = None):
        bodies = _tuple_of(bodies, RigidBody, "bodies must be a RigidBody or a sequence of RigidBody")
        if not bodies or not all(isinstance(b, RigidBody) for b in bodies):
            raise ValueError(f"bodies must be a RigidBody or a non-empty sequence of RigidBody, got {bodies!r}")
        effects = _tuple_of(effects, Effect, "effects must be a sequence of effects (Gravity(), PointForce(...), ...)")
        for e in effects:
            if not isinstance(e, Effect):
                raise ValueError(f"effects must contain effect objects (Gravity(), PointForce(...), ...), got {e!r}")
        name = checks.text("name", name, optional=True)
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
        kinds = {"force", "constraint", "event", "contact"}
        for e in effects:
            if e.kind not in kinds:
                raise ValueError(f"effect {e!r} has an unknown kind {e.kind!r}")
        self._forces = [(e, self._indices(e.body, e)) + self._other(e) for e in effects if e.kind == "force"]
        self._impulses = [(e, self._indices(e.body, e)) for e in effects if e.kind == "event"]
        self._kicks = entries(self._impulses, self.n_bodies)     # as arrays, for the table the loop walks
        self._setup_pivots([(e, self._indices(e.body, e)) for e in effects if e.kind == "constraint"])
        self._contacts = [(e, idx, e.prepare(self, idx))   # each contact's own data: its bodies' contact points
                          for e, idx in ((e, self._indices(e.body, e)) for e in effects if e.kind == "contact")]

    def _setup_pivots(self, pivots):
        """Pivoted bodies turn about their pivot p (pivot.py): inertia about p, I_p = I_body + M (|b|² Id − b bᵀ)."""
        self.pivots = Pivots(self.bodies, pivots)
        self.pivoted, self.pivot_body_point = self.pivots.pivoted, self.pivots.body_point
        self.pivot_world_point = self.pivots.world_point
        self.I_rot, self.I_rot_inv = self.pivots.I_rot, self.pivots.I_rot_inv
        for arr in (self.pivoted, self.pivot_body_point, self.pivot_world_point, self.I_rot, self.I_rot_inv):
            arr.setflags(write=False)

    # --- which bodies an effect acts on -------------------------------------------
    def bodies_of(self, effect) -> np.ndarray:
        """The indices of the bodies `effect` acts on (all of them if it names none)."""
        return np.arange(self.n_bodies)[self._indices(effect.body, effect)]

    def other_body_of(self, effect) -> int | None:
        """The index of a two-body effect's second body (a Spring's other_body), or None."""
        other = getattr(effect, "other_body", None)
        return None if other is None else int(self._indices(other, effect, "other_body")[0])

    def _indices(self, body, effect, name: str = "body"):
        """An effect's body selection (effects.body_selection) -> slice(None) for every body, or an index array."""
        n = self.n_bodies
        body = body_selection(body, name)
        if body is None:
            return slice(None)
        if isinstance(body, RigidBody):
            hits = [i for i, b in enumerate(self.bodies) if b is body]
            if len(hits) != 1:
                raise ValueError(f"{name} of {effect!r} must be one body of the scene (found {len(hits)} matches): "
                                 "pass its index instead")
            return np.array(hits)
        items = [body] if isinstance(body, int) else list(body)
        for i in items:
            if not 0 <= i < n:
                raise ValueError(f"{name} of {effect!r} must be an index in [0, {n - 1}], got {i}")
        return np.array(items, dtype=int)

    def _other(self, e):
        """A two-body effect (a Spring with other_body): its body must select one body, not other_body."""
        other = getattr(e, "other_body", None)
        if other is None:
            return ()
        if isinstance(other, (list, tuple, np.ndarray)):
            raise ValueError(f"other_body of {e!r} must be one body (an index or a RigidBody), got {other!r}")
        idx = self._indices(other, e, "other_body")
        mine = np.arange(self.n_bodies)[self._indices(e.body, e)]
        if mine.size != 1 or mine[0] == idx[0]:
            raise ValueError(f"body of {e!r} must select exactly one body, other than other_body = {int(idx[0])}, "
                             f"when other_body is given; got body = {e.body!r} (bodies {mine.tolist()})")
        return (idx,)

    # --- what the scene computes ---------------------------------------------------
    @property
    def velocity_dependent(self) -> bool:
        """True if some force depends on the velocities (drag, damping)."""
        return any(e.velocity_dependent for e, *_ in self._forces)

    @property
    def has_forces(self) -> bool:
        """True if any effect produces a force or a torque (False: a free body)."""
        return bool(self._forces)

    # --- pivots: the rotation centre, and the engine's coordinates ------------------
    def centre(self, x: np.ndarray) -> np.ndarray:
        """The point each body turns about: its centre of mass x, or its pivot p."""
        return self.pivots.centre(x)

    def constrain(self, X: State) -> State:
        """Pivoted bodies: x = p − R b and P = M ω × (x − p), from R and L_p (a no-op without pivots)."""
        return self.pivots.constrain(X, self.system)

    def to_engine(self, X: State) -> State:
        """A State (L about the centre of mass) -> the engine's coordinates (L about the rotation centre).

        For a pivoted body, X must hold the body point b at p (x = p − R b) and move with it
        (v = ω × (x − p)); Pivot.state(body, R, omega) builds such a state.
        """
        return self.pivots.to_engine(self.batch(X), self.system)

    def to_state_arrays(self, x, R, P, L):
        """The engine's arrays (..., N, 3) -> L about the centre of mass:  L = L_p − (x − p) × P."""
        return self.pivots.to_state_arrays(x, R, P, L)

    # --- events between steps: impulses and contacts -------------------------------
    @property
    def has_pivots(self) -> bool:
        return self.pivots.any

    @property
    def has_contacts(self) -> bool:
        return bool(self._contacts)

    def apply_impulses(self, t0: float, t1: float, X: State) -> State:
        """Kicks due in [t0, t1) on X (the engine's coordinates):  ΔP = J,  ΔL = (r − c) × J  (c the rotation
        centre; engine/motion.py: kick, run as Python).  X itself if none is due."""
        if not any(e.due(t0, t1) for e, _ in self._impulses):
            return X
        from .engine import interpreted
        S = to_matrix(X)
        kick_due(self._impulses, t0, t1, self.system(), S, interpreted.module("motion"))
        return from_matrix(S)

    def check_start(self, X0: State, t_end: float):
        """Refuse a run whose start the engine would simulate silently wrong (ValueError naming X0 or Impulse.time):
        a body below a Ground (Ground.check_start), a Spring with both ends at one point and a rest length > 0
        (Spring.check_start), an Impulse outside [0, t_end] (Impulse.check_time), a force over time that t_end would
        make non-finite (Profile.check_time: a Sine's phase).  simulate calls this."""
        check_times(self._impulses, self._kicks.times, t_end)
        for e, *_ in self._forces:                   # (not every effect: a scene may hold 10⁵ Impulses)
            if isinstance(getattr(e, "force", None), Profile):
                e.force.check_time("t_end", t_end)
        springs = [e for e, *_ in self._forces if isinstance(e, Spring) and e.rest_length > 0]
        if not self._contacts and not springs:
            return
        X = self.batch(X0)
        for e, _, geo in self._contacts:
            e.check_start(X, geo)
        for e in springs:
            e.check_start(self, X)

    def compile(self) -> Compiled:
        """The scene as the kernel's data: its constants and one row per smooth effect on a body, each effect
        laying out its own rows (Effect.engine_rows); its forces over time given as data (profiles.py), its ground
        planes and their bodies' contact points.  Pivots are the System's pivot arrays; impulses are applied
        between steps by the driver, and are not rows.  Built at each call: a run keeps what it
        computes, the scene stays as it was."""
        functions: list = []
        rows = [row._replace(velocity=e.velocity_dependent) for e, *_ in self._forces
                for row in e.engine_rows(self, functions)]
        time_rows = [e.force.time_row(slot) for slot, e in enumerate(functions) if isinstance(e.force, Profile)]
        grounds = [ground.ground_rows(geo) for ground, idx, geo in self._contacts]
        sys = kernel_data.system(self.mass, self.I_rot, self.I_rot_inv, self.pivoted, self.pivot_body_point,
                                 self.pivot_world_point, rows, time_rows, grounds)
        return Compiled(sys, tuple(functions), bool(rows))

    def same_physics(self, other) -> bool:
        """Is `other` this scene, or one the engine runs alike (a scene built again the same way, a pickled run's
        copy)?  The same System (compile(): the bodies' masses, inertia and pivots, every effect's rows, the forces
        over time given as data, the grounds and their contact points, all equal), the same forces given as
        functions f(t) (one function, or one code with equal defaults and closure), and the same impulses (body,
        body point, J and time)."""
        if other is self:
            return True
        if not isinstance(other, Scene) or other.n_bodies != self.n_bodies:
            return False
        a, b = self.compile(), other.compile()
        if not all(np.shape(x) == np.shape(y) and np.array_equal(x, y) for x, y in zip(a.system, b.system)):
            return False
        calls = [[e.force for e in c.functions if not isinstance(e.force, Profile)] for c in (a, b)]
        if len(calls[0]) != len(calls[1]) or not all(map(_same_function, *calls)):
            return False
        kicks = [[(e.time, tuple(e.body_point), tuple(e.impulse), tuple(np.arange(s.n_bodies)[idx]))
                  for e, idx in s._impulses] for s in (self, other)]
        return kicks[0] == kicks[1]

    def system(self) -> kernel_data.System:
        """The scene as the kernel's arrays (compile().system)."""
        return self.compile().system

    # --- single body <-> arrays over N bodies -------------------------------------
    def batch(self, X: State) -> State:
        """The state as arrays over N bodies (a single-body state gets a leading axis of 1)."""
        if not isinstance(X, State):
            raise ValueError(f"X0 must be a State, got {X!r}")
        if X.x.ndim == 1:
            if not self.single:
                raise ValueError(f"X0 holds 1 body but the scene has {self.n_bodies}: use State.stack")
            return State.unchecked(X.x[None], X.R[None], X.P[None], X.L[None])
        if X.x.shape[0] != self.n_bodies:
            raise ValueError(f"X0 holds {X.x.shape[0]} bodies but the scene has {self.n_bodies}")
        return X

    def describe(self, method: str | None = None) -> str:
        """One short paragraph: which bodies, which effects (and so which physics) this scene simulates; with a
        method (a name in rb.METHODS or a Method, as simulate takes it), the integrator too."""
        method = None if method is None else get_method(method).name
        if self.single:
            who = repr(self.bodies[0])
        else:
            kinds = ", ".join(sorted({b.name for b in self.bodies}))
            who = say(f"{self.n_bodies} bodies ({kinds}), stepped together as arrays",
                      f"{self.n_bodies} corps ({kinds}), avancés ensemble en tableaux")
        name = " " + repr(self.name) if self.name else ""
        lines = [say(f"Scene{name}: {who}.", f"Scène{name} : {who}.")]
        if not self.effects:
            lines.append(say("No effect: a free body in space, no force or torque is ever evaluated "
                             "(P and L stay constant; the torque-free motion can be advanced exactly).",
                             "Aucun effet : un corps libre dans l'espace, aucune force ni aucun moment n'est jamais "
                             "calculé (P et L restent constants ; le mouvement sans moment peut être avancé exactement)."))
        else:
            effects = say("; ", " ; ").join(e.describe() for e in self.effects)
            lines.append(say(f"Effects computed, and only these: {effects}.",
                             f"Effets calculés, et eux seuls : {effects}."))
            if not self._contacts:
                lines.append(say("No contact detection.", "Pas de détection de contact."))
        if method is not None:
            lines.append(say(f"Integrator: {method}.", f"Intégrateur : {method}."))
        return " ".join(lines)

    def __repr__(self) -> str:
        return self.describe()


def _tuple_of(value, cls, message: str) -> tuple:
    """One `cls` object, or a sequence of them -> a tuple (the items are checked by the caller);
    ValueError(message + ", got value") if value is neither."""
    if isinstance(value, cls):
        return (value,)
    try:
        return tuple(value)
    except TypeError:
        raise ValueError(f"{message}, got {value!r}") from None


def _same_function(f, g) -> bool:
    """f is g, or both run one code with equal defaults and closure values (a function built again alike)."""
    if f is g:
        return True
    code = getattr(f, "__code__", None)
    if code is None or code is not getattr(g, "__code__", None):
        return False
    cells = [tuple(c.cell_contents for c in (h.__closure__ or ())) for h in (f, g)]
    return _same_value(f.__defaults__, g.__defaults__) and _same_value(*cells)


def _same_value(a, b) -> bool:
    """a and b equal: one object, equal arrays, or == saying True (anything that cannot tell: False)."""
    if a is b:
        return True
    if isinstance(a, (tuple, list)) and isinstance(b, (tuple, list)):
        return type(a) is type(b) and len(a) == len(b) and all(map(_same_value, a, b))
    try:
        if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
            return np.shape(a) == np.shape(b) and bool(np.array_equal(a, b))
        return bool(a == b)
    except Exception:                       # an object whose == raises or is not a truth value
        return False


def as_scene(scene) -> Scene:
    """A Scene, or a bare RigidBody taken as a free-body scene."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, RigidBody):
        return Scene(scene)
    raise ValueError(f"scene must be a Scene or a RigidBody, got {scene!r}")
