"""The state vector of the rigid body, X(t) = (x(t), R(t), P(t), L(t)), and what derives from it.

    x  position of the centre of mass, world space      (position du barycentre)
    R  orientation: body axes X', Y', Z' as columns      (rotation / orientation)
    P  linear momentum                                   (quantité de mouvement)
    L  angular momentum about the centre of mass         (moment cinétique)

Derived ("auxiliary") quantities are computed from X when needed, never stored
(slide "Evolution temporelle (Euler)"):

    v(t)    = P(t) / M
    I⁻¹(t)  = R(t) · I⁻¹_body · R(t)ᵀ
    ω(t)    = I⁻¹(t) · L(t)

A State may also hold N bodies at once: x (N, 3), R (N, 3, 3), P (N, 3), L (N, 3).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .support import checks
from .body import RigidBody
from .rotation import matvec, orthogonality_error, transpose
from .rowwise import as_rows, engine_rows, matrix_parts, matrix_rows

R_TOLERANCE = 1e-6   # how far from SO(3) an initial R may be: ‖RᵀR − I‖ <= R_TOLERANCE


class State:
    """X = (x, R, P, L) in the world frame, immutable (the slides' "Vecteur d'état").

    Arrays are private copies that cannot be written, nor made writable again (checks.frozen: read-only
    memory), and no attribute can be set; build a new State (or use ``replace``) to change one.
    R must be a rotation (‖RᵀR − I‖ <= 1e-6, det R > 0).
    x, R, P, L are arrays of real numbers (ints or floats of any numpy dtype, e.g. float32;
    not strings, bools or complex numbers), finite; N >= 1 bodies when stacked.
    """

    __slots__ = ("x", "R", "P", "L")

    def __init__(self, x, R, P, L):
        x = checks.array("x", x, (3,), batch=True)
        lead = x.shape[:-1]
        R = checks.array("R", R, (3, 3), batch=True)
        P = checks.array("P", P, (3,), batch=True)
        L = checks.array("L", L, (3,), batch=True)
        for name, arr, tail in (("R", R, (3, 3)), ("P", P, (3,)), ("L", L, (3,))):
            if arr.shape != lead + tail:
                raise ValueError(f"{name} must have shape {lead + tail} to match x of shape {x.shape}, got {arr.shape}")
        err = np.max(orthogonality_error(R)) if R.size else 0.0
        if err > R_TOLERANCE or np.any(np.linalg.det(R) <= 0):
            raise ValueError(
                f"R must be a rotation matrix (RᵀR = I within {R_TOLERANCE:g}, det R = +1), "
                f"got ‖RᵀR − I‖ = {err:.3g}, det R = {np.linalg.det(R).round(6).tolist()}")
        _set(self, x, R, P, L)

    @classmethod
    def unchecked(cls, x, R, P, L) -> "State":
        """Build without checks (the engine's own states; R may have left SO(3) under Euler): float arrays,
        copied and frozen as any State's (checks.frozen: one copy each), never views of the caller's."""
        self = object.__new__(cls)
        for name, arr in zip(cls.__slots__, (x, R, P, L)):
            object.__setattr__(self, name, checks.frozen(np.asarray(arr, dtype=float)))
        return self

    @classmethod
    def from_velocities(cls, body, x, R, v, omega) -> "State":
        """State from velocities: P = M v,  L = I(t) ω = R I_body Rᵀ ω  (omega in world frame).

        One body: body a RigidBody, x, v, omega 3-vectors, R (3, 3).  N bodies at once: x, v, omega (N, 3),
        R (N, 3, 3), body a RigidBody (the same for all) or a sequence of N — checked once as arrays,
        the same State, to the bit, as State.stack of the N single ones."""
        if isinstance(body, RigidBody):
            bodies = None
        else:
            bodies = tuple(body) if isinstance(body, (list, tuple)) else None
            if not bodies or not all(isinstance(b, RigidBody) for b in bodies):
                raise ValueError(f"body must be a RigidBody or a sequence of RigidBody, got {body!r}")
        R = checks.array("R", R, (3, 3), batch=True)
        if R.ndim == 2 and bodies is None:
            v = checks.vector3("v", v)
            omega = checks.vector3("omega", omega)
            return cls(x, R, body.mass * v, R @ body.I_body @ R.T @ omega)
        n = len(R) if R.ndim == 3 else 0
        if bodies is not None and len(bodies) != n:
            raise ValueError(f"body must be one RigidBody or {n} of them to match R of shape {R.shape}, "
                             f"got {len(bodies)} bodies")
        v = checks.array("v", v, (3,), batch=True)
        omega = checks.array("omega", omega, (3,), batch=True)
        for name, arr in (("v", v), ("omega", omega)):
            if arr.shape != (n, 3):
                raise ValueError(f"{name} must have shape {(n, 3)} to match R of shape {R.shape}, got {arr.shape}")
        if bodies is None:
            M, I_body = np.full(n, body.mass), np.broadcast_to(body.I_body, (n, 3, 3))
        else:
            M, I_body = np.array([b.mass for b in bodies]), np.stack([b.I_body for b in bodies])
        L = (R @ I_body @ transpose(R) @ omega[:, :, None])[:, :, 0]
        return cls(x, R, M[:, None] * v, L)

    @classmethod
    def at_rest(cls, x=(0.0, 0.0, 0.0), R=None) -> "State":
        """A body at rest: P = 0, L = 0 (the start of the slides' "Itération 1")."""
        return cls(x, np.eye(3) if R is None else R, np.zeros(3), np.zeros(3))

    @classmethod
    def stack(cls, states) -> "State":
        """N single-body states -> one State holding N bodies."""
        if isinstance(states, (State, str, bytes, dict)):
            raise ValueError(f"states must be a non-empty sequence of single-body States, got {states!r}")
        try:
            states = list(states)
        except TypeError:
            raise ValueError(f"states must be a non-empty sequence of single-body States, got {states!r}") from None
        if not states:
            raise ValueError("states must be a non-empty sequence of single-body States, got an empty sequence")
        for i, s in enumerate(states):
            if not isinstance(s, State):
                raise ValueError(f"states must be a non-empty sequence of single-body States: states[{i}] is {s!r}")
            if s.x.shape != (3,) or s.R.shape != (3, 3) or s.P.shape != (3,) or s.L.shape != (3,):
                raise ValueError(f"states must be single-body States (x of shape (3,)): states[{i}] holds "
                                 f"{s.n_bodies} bodies (x of shape {s.x.shape}); stack single-body states only")
        return cls.unchecked(*(np.stack([getattr(s, k) for s in states]) for k in cls.__slots__))

    def replace(self, **changes) -> "State":
        """A copy with some of x, R, P, L changed (checked like a new State)."""
        unknown = set(changes) - set(self.__slots__)
        if unknown:
            raise ValueError(f"replace takes x, R, P, L; got {sorted(unknown)}")
        fields = {k: changes.get(k, getattr(self, k)) for k in self.__slots__}
        return State(**fields)

    @property
    def n_bodies(self) -> int:
        """1 for a single-body state, N for a stack."""
        return 1 if self.x.ndim == 1 else self.x.shape[0]

    def body(self, i: int) -> "State":
        """The state of body i of a stacked state."""
        i = checks.integer("i", i, low=0, high=self.n_bodies - 1)
        if self.x.ndim == 1:
            return self
        return State.unchecked(self.x[i], self.R[i], self.P[i], self.L[i])

    def __setattr__(self, key, value):
        how = f"State(...) or state.replace({key}=...)" if key in self.__slots__ else "State(...)"
        raise AttributeError(f"State is immutable: cannot set {key!r}; build a new one with {how}")

    def __delattr__(self, key):
        raise AttributeError(f"State is immutable: cannot delete {key!r}")

    def __reduce__(self):
        """Pickling and copy.copy/deepcopy: rebuilt through unchecked (frozen copies of the same arrays)."""
        return State.unchecked, tuple(getattr(self, k) for k in self.__slots__)

    def __eq__(self, other) -> bool:
        return isinstance(other, State) and all(
            np.array_equal(getattr(self, k), getattr(other, k)) for k in self.__slots__)

    __hash__ = None

    def __repr__(self) -> str:
        def f(a):
            return np.array2string(a, precision=6, suppress_small=True, separator=", ").replace("\n", "")
        return f"State(x={f(self.x)}, R={f(self.R)}, P={f(self.P)}, L={f(self.L)})"


def _set(self, x, R, P, L):
    for name, arr in zip(State.__slots__, (x, R, P, L)):
        object.__setattr__(self, name, checks.frozen(np.asarray(arr, dtype=float)))   # own copy, read-only memory


# --- derived quantities (slide "Evolution temporelle (Euler)") ---------------------

class Derived(NamedTuple):
    """The auxiliary quantities of one state: v, I⁻¹(t), ω."""
    v: np.ndarray
    I_inv: np.ndarray
    omega: np.ndarray


def to_matrix(X: State) -> np.ndarray:
    """The N bodies of X as the engine's state S (N, 18) = [x, R row by row, P, L] (rowwise.matrix_rows)."""
    return matrix_rows(X.x, X.R, X.P, X.L)


def from_matrix(S: np.ndarray) -> State:
    """The engine's state S (N, 18) as a State (unchecked: frozen copies of S's parts)."""
    return State.unchecked(*matrix_parts(S))


def velocity(P: np.ndarray, M) -> np.ndarray:
    """v(t) = P(t) / M        P (..., 3); M a mass > 0 or masses (N,), over P's leading axes.
    (engine/motion.py: velocity, row by row.)  Finite numbers (not booleans or strings), or a ValueError naming
    the parameter; a v that overflows is refused."""
    P, M = _given(("P", P, (3,)), ("M", M, ()))
    if not np.all(M > 0):
        raise ValueError(f"M must be > 0 (a mass, or one per body), got {_shown(M)}")
    return _finite("v = P / M", "P and M", unchecked_velocity(P, M))


def inverse_inertia(R: np.ndarray, I_body_inv: np.ndarray) -> np.ndarray:
    """I⁻¹(t) = R(t) · I⁻¹_body · R(t)ᵀ   (world frame; changes as the body turns).  R (..., 3, 3), I_body_inv
    (..., 3, 3).  (engine/motion.py: inverse_inertia, row by row.)  Finite numbers (not booleans or strings), or a
    ValueError naming the parameter."""
    R, J = _given(("R", R, (3, 3)), ("I_body_inv", I_body_inv, (3, 3)))
    return _finite("I⁻¹ = R I⁻¹_body Rᵀ", "R and I_body_inv", unchecked_inverse_inertia(R, J))


def angular_velocity(I_inv: np.ndarray, L: np.ndarray) -> np.ndarray:
    """ω(t) = I⁻¹(t) · L(t).  I_inv (..., 3, 3), L (..., 3).  (engine/motion.py: angular_velocity, row by row.)
    Finite numbers (not booleans or strings), or a ValueError naming the parameter."""
    J, L = _given(("I_inv", I_inv, (3, 3)), ("L", L, (3,)))
    return _finite("ω = I⁻¹ L", "I_inv and L", unchecked_angular_velocity(J, L))


def unchecked_velocity(P, M) -> np.ndarray:
    """velocity's formula (engine/motion.py), on arrays already checked: a run's own (Trajectory, the viewer),
    whose derived values may overflow near a blow-up."""
    lead, (P, M) = as_rows(P, M, tails=((3,), ()))
    v = np.empty_like(P)
    engine_rows().velocity_rows(P, M, v)
    return v.reshape(lead + (3,))


def unchecked_inverse_inertia(R, I_body_inv) -> np.ndarray:
    """inverse_inertia's formula on arrays already checked."""
    lead, (R, J) = as_rows(R, I_body_inv, tails=((3, 3), (3, 3)))
    out = np.empty_like(R)
    engine_rows().inverse_inertia_rows(R, J, out)
    return out.reshape(lead + (3, 3))


def unchecked_angular_velocity(I_inv, L) -> np.ndarray:
    """angular_velocity's formula on arrays already checked."""
    lead, (J, L) = as_rows(I_inv, L, tails=((3, 3), (3,)))
    out = np.empty_like(L)
    engine_rows().angular_velocity_rows(J, L, out)
    return out.reshape(lead + (3,))


def _given(*named) -> list:
    """Each (name, value, trailing shape): an array of finite real numbers (checks.numbers: no bool, no string)
    ending in that shape, the arrays broadcasting over their leading axes; else a ValueError naming it."""
    out = []
    for name, value, tail in named:
        want = f"(..., {', '.join(map(str, tail))})" if tail else "(...): a number or an array of numbers"
        a = checks.numbers(name, value, f"an array of numbers of shape {want}", copy=False)
        if a.ndim < len(tail) or a.shape[a.ndim - len(tail):] != tail:
            raise ValueError(f"{name} must have shape {want}, got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} must contain only finite numbers (no NaN or inf), got {_shown(a)}")
        out.append(a)
    try:
        np.broadcast_shapes(*(a.shape[:a.ndim - len(t)] for a, (_, _, t) in zip(out, named)))
    except ValueError:
        names = " and ".join(n for n, _, _ in named)
        raise ValueError(f"{names} must have leading axes that broadcast together, got shapes "
                         f"{', '.join(str(a.shape) for a in out)}") from None
    return out


def _finite(formula: str, names: str, out: np.ndarray) -> np.ndarray:
    """out, if finite: else a ValueError naming the parameters whose sizes overflowed the formula."""
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{names} are too large: {formula} overflows (beyond ±1.8e308)")
    return out


def _shown(a: np.ndarray) -> str:
    """An array for a message: its values when small, else its shape."""
    return str(a.tolist()) if a.size <= 12 else f"an array of shape {a.shape}"


def derived(body: RigidBody, X: State) -> Derived:
    """v, I⁻¹(t), ω of one body, in the slides' order (P → v; R → I⁻¹; L → ω)."""
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a RigidBody, got {body!r}")
    if not isinstance(X, State):
        raise ValueError(f"X must be a State, got {X!r}")
    v = velocity(X.P, body.mass)
    I_inv = inverse_inertia(X.R, body.I_body_inv)
    omega = angular_velocity(I_inv, X.L)
    return Derived(v, I_inv, omega)
