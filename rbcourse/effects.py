"""Effects a scene can call for.  Each is a small immutable object; a scene computes only its own.

Smooth effects give forces Fᵢ at world points rᵢ (and, for drag, pure torques); the engine
computes them (rbcourse/engine/motion.py: effect_on_body, the formula of each effect written once)
and sums them with the slides' resultant formula.  Here are their parameters, their formulas in
words (their potentials, for the energy diagnostics, are engine/motion.py: potential) and what they
say of themselves.  The
constraint (Pivot, pivot.py), the event (Impulse, impulse.py) and the contact
(Ground, contact.py) live in their own modules.

``body`` selects which bodies of the scene an effect acts on: None (every body),
an index (an int: not a bool, a float or a string), a RigidBody of the scene, or a
non-empty list of distinct indices.  ``body=[]`` is refused: an effect on no body is no
effect, leave it out of the scene.
"""
from __future__ import annotations

import math
import numpy as np

from .support import checks
from .engine.system import ANGULAR_DRAG, EVERY, GRAVITY, LINEAR_DRAG, POINT_FORCE, SPRING, Row
from .support.language import say


class Immutable(type):
    """The effects' metaclass: once an effect is built (its whole __init__, a subclass's too, has run), its arrays
    are frozen (checks.frozen: private copies in read-only memory, which setflags cannot make writable again)
    and no attribute can be set or deleted (Effect.__setattr__): an effect is a constant of the scenes that hold it."""

    def __call__(cls, *args, **kwargs):
        self = object.__new__(cls) if cls.__new__ is object.__new__ else cls.__new__(cls, *args, **kwargs)
        _BUILDING.add(id(self))            # its __init__ may set attributes; nothing stays behind in the effect
        try:
            self.__init__(*args, **kwargs)
        finally:
            _BUILDING.discard(id(self))
        self._freeze()
        return self


_BUILDING: set = set()     # the ids of the effects whose __init__ is running (Immutable.__call__)


class Effect(metaclass=Immutable):
    """Base class.  Subclasses set ``kind`` and implement the methods of their kind.

    The scene recognises an effect by its kind: "force" (smooth forces at points and pure torques,
    computed by the kernel: each lays itself out as its rows (engine_rows; engine/system.py), engine/motion.py has their
    formulas and potentials), "constraint" (Pivot), "event" (Impulse: due) or "contact"
    (Ground: prepare, resolve).

    Immutable once built: its arrays cannot be written (nor made writable), its attributes cannot be set
    (AttributeError); build a new effect to change one.
    """
    kind = "force"
    body = None
    velocity_dependent = False   # does the force depend on v or ω (drag, damping)?
    has_potential = False        # does it store energy, a potential U (engine/motion.py: potential)?

    def _freeze(self):
        """Every array attribute -> a frozen copy (checks.frozen)."""
        state = self.__dict__
        for key, value in state.items():
            if isinstance(value, np.ndarray):
                state[key] = checks.frozen(value)

    def __setattr__(self, key, value):
        if id(self) not in _BUILDING:
            name = type(self).__name__
            raise AttributeError(f"{name} is immutable: cannot set {key!r}; build a new {name}(...) instead")
        object.__setattr__(self, key, value)

    def __delattr__(self, key):
        if id(self) not in _BUILDING:
            raise AttributeError(f"{type(self).__name__} is immutable: cannot delete {key!r}")
        object.__delattr__(self, key)

    def __setstate__(self, state):
        """Unpickling and copy.copy/deepcopy (which build no __init__): the same attributes, frozen again."""
        self.__dict__.update(state)
        self._freeze()

    def describe(self) -> str:
        raise NotImplementedError

    def engine_rows(self, scene, functions: list) -> list[Row]:
        """A force effect as the kernel's data (engine/system.py): one Row per body it acts on (EVERY: all).
        functions: the scene's forces given as functions f(t), in slot order (an effect with one appends itself)."""
        raise NotImplementedError


def on_bodies(scene, effect) -> list[int]:
    """The bodies an effect acts on, as the kernel's rows name them: [EVERY] for all of them, else their indices."""
    return [EVERY] if effect.body is None else [int(i) for i in scene.bodies_of(effect)]


def body_selection(body, name: str = "body"):
    """A body selection: None (every body), an index (int, not bool or float), a RigidBody, or a
    non-empty list of distinct indices.  An empty list is refused (an effect on no body is no
    effect: leave it out).  The range is checked by the Scene, which knows how many bodies it has."""
    if body is None:
        return None
    if isinstance(body, (int, np.integer)) and not isinstance(body, (bool, np.bool_)):
        return int(body)
    from .body import RigidBody
    if isinstance(body, RigidBody):
        return body
    if isinstance(body, (bool, np.bool_, float, np.floating)):
        raise ValueError(f"{name} must be None, an index, a RigidBody or a list of indices (an index is an int, "
                         f"not a bool, a float or a string), got {body!r}")
    return checks.indices(name, body)


def force_value(f, t: float) -> np.ndarray:
    """What a force function returned at time t, checked: a finite 3-vector of real numbers
    (ints or floats; not strings, bools or complex numbers) -> a float array (3,).
    The engine's driver evaluates f(t) through force_at, which checks with this."""
    if type(f) in (tuple, list) and len(f) == 3 and all(type(c) is float or type(c) is int for c in f):
        try:                                      # the common case, checked without numpy's conversions
            f0, f1, f2 = float(f[0]), float(f[1]), float(f[2])
        except OverflowError:                     # an int beyond the floats: refused below
            f0 = math.inf
        if math.isfinite(f0) and math.isfinite(f1) and math.isfinite(f2):
            return np.array((f0, f1, f2))
    try:
        arr = checks.numbers("force(t)", f)
    except ValueError:
        arr = None
    if arr is None or arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"force(t) must return a finite 3-vector of real numbers (3 ints or floats), "
                         f"got {f!r} at t = {t:g}")
    return arr


_F_OF_T = "a 3-vector of real numbers or a function of time, f(t) -> a 3-vector (called with one argument, t)"


def _force_arg(name: str, force):
    """force as given: a function f(t) (one that can be called with one positional argument, when its signature can
    be read) or a finite 3-vector; else a ValueError naming it."""
    if callable(force):
        if one_argument(force) is False:
            raise ValueError(f"{name} must be {_F_OF_T}, got {_callable_named(force)}, which cannot be called as "
                             f"{name}(t)")
        return force
    return checks.vector3(name, force)


def one_argument(f) -> bool | None:
    """Can f be called with one positional argument, f(t)?  True or False from its signature (inspect); None when
    it has none to read (some builtins and extension functions)."""
    import inspect
    try:
        signature = inspect.signature(f)
    except (TypeError, ValueError):
        return None
    try:
        signature.bind(0.0)
    except TypeError:
        return False
    return True


def _callable_named(f) -> str:
    name = getattr(f, "__qualname__", None) or getattr(f, "__name__", None)
    if name is None:
        return repr(f)
    import inspect
    try:
        return f"{name}{inspect.signature(f)}"
    except (TypeError, ValueError):
        return name


class Gravity(Effect):
    """Uniform gravity: a force M g (0, 0, −1) at the centre of mass of each body (no torque about it).

    Potential energy  U = M g z.
    """
    has_potential = True

    def __init__(self, g: float = 9.81, *, body=None):
        self.g = checks.real("g", g, low=0.0)
        self.body = body_selection(body)

    def describe(self):
        return say(f"gravity g = {self.g:g} m/s² along −z (a force M·g at each centre of mass)",
                   f"gravité g = {self.g:g} m/s² selon −z (une force M·g au centre de masse de chaque corps)")

    def engine_rows(self, scene, functions):
        return [Row(GRAVITY, b, (self.g,)) for b in on_bodies(scene, self)]

    def __repr__(self):
        return f"Gravity(g={self.g:g})"


class PointForce(Effect):
    """A force Fᵢ applied at a body-fixed point rᵢ = x + R b (the slides' forces at points).

    body_point: b, in body axes from the centre of mass.
    force: a 3-vector or a function t -> 3-vector; in world axes (frame="world")
    or body axes (frame="body": the force turns with the body, F = R f).
    """

    def __init__(self, body_point, force, frame: str = "world", *, body=None):
        self.body_point = checks.vector3("body_point", body_point)
        self.force = _force_arg("force", force)
        self.frame = checks.choice("frame", frame, {"world", "body"})
        self.body = body_selection(body)
        if callable(force) and one_argument(force) is None:
            self._f_of_t_unread = True

    _f_of_t_unread = False      # a function whose signature could not be read: its first call tells (force_at)

    def force_at(self, t: float) -> np.ndarray:
        """The force vector (in its own frame) at time t (a finite real number)."""
        if not (isinstance(t, float) and math.isfinite(t)):   # the driver's times (floats) pass at once
            t = checks.real("t", t)
        if not callable(self.force):
            return self.force
        if self._f_of_t_unread:
            try:
                return force_value(self.force(t), t)
            except TypeError as err:       # called with the wrong number of arguments, most likely: said as such
                raise ValueError(f"force must be {_F_OF_T}: force({t:g}) raised TypeError: {err}") from err
        return force_value(self.force(t), t)

    def engine_rows(self, scene, functions):
        slot, f = -1, (0.0, 0.0, 0.0)
        if callable(self.force):                 # evaluated by the driver, in Python, at the stage times
            slot = len(functions)
            functions.append(self)
        else:
            f = tuple(self.force)
        params = (*self.body_point, *f, 1.0 if self.frame == "body" else 0.0)
        return [Row(POINT_FORCE, b, params, slot=slot) for b in on_bodies(scene, self)]

    def describe(self):
        if callable(self.force):
            f = "f(t)" if getattr(self.force, "__name__", None) else repr(self.force)
        else:
            f = np.round(self.force, 6).tolist()
        point = np.round(self.body_point, 6).tolist()
        frame = {"world": "du monde", "body": "du corps"}.get(self.frame, self.frame)
        return say(f"a force {f} ({self.frame} axes) at body point {point}",
                   f"une force {f} (axes {frame}) au point {point} du corps")

    def __repr__(self):
        return f"PointForce(body_point={self.body_point.tolist()}, force={'<function>' if callable(self.force) else self.force.tolist()}, frame={self.frame!r})"


class Spring(Effect):
    """A damped spring from a body point to a world anchor, or to a point of another body.

        d = r_a − r_b,  ℓ = |d|,  u = d/ℓ
        F_a = −k (ℓ − ℓ₀) u − c (ḋ·u) u      (on the body; −F_a on the other body, if any)

    With rest_length ℓ₀ = 0 this is the linear spring F_a = −k d − c ḋ.
    Potential energy U = ½ k (ℓ − ℓ₀)².
    """
    has_potential = True

    def __init__(self, body_point, world_point=(0.0, 0.0, 0.0), stiffness: float = 1.0, damping: float = 0.0,
                 rest_length: float = 0.0, *, body=None, other_body=None, other_point=(0.0, 0.0, 0.0)):
        self.body_point = checks.vector3("body_point", body_point)
        self.world_point = checks.vector3("world_point", world_point)
        self.stiffness = checks.real("stiffness", stiffness, low=0.0)
        self.damping = checks.real("damping", damping, low=0.0)
        self.rest_length = checks.real("rest_length", rest_length, low=0.0)
        self.body = body_selection(body)
        from .body import RigidBody
        if isinstance(other_body, (int, np.integer)) and not isinstance(other_body, (bool, np.bool_)):
            other_body = int(other_body)
        elif other_body is not None and not isinstance(other_body, RigidBody):
            raise ValueError(f"other_body must be None, an index (int) or a RigidBody, got {other_body!r}")
        self.other_body = other_body
        self.other_point = checks.vector3("other_point", other_point)
        self.velocity_dependent = self.damping > 0

    def engine_rows(self, scene, functions):
        two = self.other_body is not None
        params = (*self.body_point, *(self.other_point if two else self.world_point), self.stiffness, self.damping,
                  self.rest_length)
        other = scene.other_body_of(self) if two else -1
        return [Row(SPRING, b, params, other=other) for b in on_bodies(scene, self)]

    def check_start(self, scene, X):
        """Refuse a start with both ends at one point while rest_length > 0 (the direction u = d/ℓ is undefined
        there: the engine applies no force, engine/motion.py: spring_force): ValueError naming X0, the spring
        and its rest length.  X: the start over the scene's N bodies (scene.batch(X0): x the centres of mass).
        The ends are engine/motion.py's body_point (run as Python), r_a = x + R b on each body it acts on and
        r_b the world point or the other body's point; "at one point": |r_a − r_b| <= 1e-12 max(1, ℓ₀, |r_a|,
        |r_b|) (rounding: a distance below that is noise, its direction arbitrary)."""
        if self.rest_length == 0.0:
            return
        from .engine import interpreted
        body_point = interpreted.module("motion").body_point
        b = tuple(self.body_point.tolist())
        if self.other_body is None:
            r_b = tuple(self.world_point.tolist())
        else:
            o = scene.other_body_of(self)
            r_b = body_point(tuple(X.x[o].tolist()), X.R[o].tolist(), tuple(self.other_point.tolist()))
        rows = scene.bodies_of(self)
        for i, x, R in zip(rows.tolist(), X.x[rows].tolist(), X.R[rows].tolist()):
            r_a = body_point(x, R, b)
            d = math.dist(r_a, r_b)
            if d <= 1e-12 * max(1.0, self.rest_length, math.hypot(*r_a), math.hypot(*r_b)):
                raise ValueError(f"X0 puts both ends of {self!r} (on body {i}) at the same point {list(r_a)} while "
                                 f"its rest_length is {self.rest_length:g} m: its direction is undefined; start with "
                                 f"the ends apart (or rest_length=0)")

    def describe(self):
        if self.other_body is None:
            to = say(f"world point {self.world_point.tolist()}", f"le point {self.world_point.tolist()} du monde")
        else:
            to = say(f"point {self.other_point.tolist()} of body {self.other_body}",
                     f"le point {self.other_point.tolist()} du corps {self.other_body}")
        return say(f"a spring k = {self.stiffness:g} N/m, damping {self.damping:g} N s/m, rest length "
                   f"{self.rest_length:g} m, from body point {self.body_point.tolist()} to {to}",
                   f"un ressort k = {self.stiffness:g} N/m, amortissement {self.damping:g} N s/m, longueur à vide "
                   f"{self.rest_length:g} m, du point {self.body_point.tolist()} du corps vers {to}")

    def __repr__(self):
        return (f"Spring(body_point={self.body_point.tolist()}, world_point={self.world_point.tolist()}, "
                f"stiffness={self.stiffness:g}, damping={self.damping:g}, rest_length={self.rest_length:g})")


class Drag(Effect):
    """A drag proportional to a velocity, with a coefficient c >= 0 (LinearDrag, AngularDrag)."""
    velocity_dependent = True

    def __init__(self, coefficient: float, *, body=None):
        self.coefficient = checks.real("coefficient", coefficient, low=0.0)
        self.body = body_selection(body)


class LinearDrag(Drag):
    """Linear drag on the centre of mass:  F = −c v  (at x, so no torque about it)."""

    def engine_rows(self, scene, functions):
        return [Row(LINEAR_DRAG, b, (self.coefficient,)) for b in on_bodies(scene, self)]

    def describe(self):
        return say(f"linear drag F = −{self.coefficient:g}·v at the centre of mass",
                   f"frottement fluide F = −{self.coefficient:g}·v au centre de masse")

    def __repr__(self):
        return f"LinearDrag({self.coefficient:g})"


class AngularDrag(Drag):
    """Angular drag: a pure torque  τ = −c ω."""

    def engine_rows(self, scene, functions):
        return [Row(ANGULAR_DRAG, b, (self.coefficient,)) for b in on_bodies(scene, self)]

    def describe(self):
        return say(f"angular drag τ = −{self.coefficient:g}·ω", f"frottement fluide en rotation τ = −{self.coefficient:g}·ω")

    def __repr__(self):
        return f"AngularDrag({self.coefficient:g})"
