"""A trajectory: the states over time as arrays, plus the diagnostics a student plots.

traj.t (n+1,), traj.x (n+1, 3), traj.R (n+1, 3, 3), traj.P (n+1, 3), traj.L (n+1, 3)
for one body; with N bodies a body axis follows the time axis: x (n+1, N, 3), ...
"""
from __future__ import annotations

import math
from contextlib import nullcontext
from typing import NamedTuple

import numpy as np

from .support import checks, language
from .support.language import say
from .rotation import matvec, orthogonality_error, transpose
from .rowwise import as_rows, engine_rows, matrix_rows
from .scene import as_scene
from .state import State, unchecked_angular_velocity, unchecked_inverse_inertia, unchecked_velocity  # a run's own

_ENERGY_CHUNK = 1 << 15   # states per engine call in potential_energy (~4.7 MB per body of scratch)


class Trajectory:
    """States X(t_k) = (x, R, P, L) at times t_k, and what derives from them.

    t (m,), x (m, 3), R (m, 3, 3), P and L (m, 3) for a one-body scene; with N bodies a body axis follows the time
    axis: x (m, N, 3), R (m, N, 3, 3), ...  The arrays are read-only (checks.read_only: views of what is given, no
    copy — a run's record can be gigabytes); build a new Trajectory to change one.

    The arguments, checked as simulate's: a state is taken by its index k as Python indexes a list (state(k):
    -m <= k < m, -1 the last); head(k) takes a count (0 <= k <= m: head(0) holds no state); every(k) a step
    (1 <= k <= max(1, m − 1): a larger step would keep the first state only); a body by its index in the scene
    (0 <= body < N); points (body_point's b, angular_momentum's about) within ±OVERFLOW = 1e100 m, the blow-up
    limit of a state, so that x + R b and (x − p) × P stay finite on any state a run records.
    """

    def __init__(self, t, x, R, P, L, scene, method: str = "", dt: float | None = None,
                 divergence: "Divergence | None" = None, implementation: str = "", *, _finite: bool = True):
        self.scene = as_scene(scene)
        self.t, self.x, self.R, self.P, self.L = _record(self.scene, t, x, R, P, L, finite=_finite)
        self.method = checks.text("method", method)
        self.dt = None if dt is None else checks.positive("dt", dt)
        if divergence is not None and not isinstance(divergence, Divergence):
            raise ValueError(f"divergence must be None or a Divergence(t, step, reason), got {divergence!r}")
        self.divergence = divergence      # None, or why and when the run stopped early (a Divergence)
        self.implementation = checks.text("implementation", implementation)    # "compiled: numba …", "interpreted (…)"

    @classmethod
    def unchecked(cls, t, x, R, P, L, scene, method: str = "", dt: float | None = None,
                  divergence: "Divergence | None" = None, implementation: str = "") -> "Trajectory":
        """A Trajectory of arrays known finite (a run's own record, checked state by state by its blow-up check;
        a slice of a trajectory): as the constructor, without reading every number again for NaN or inf."""
        return cls(t, x, R, P, L, scene, method, dt, divergence, implementation, _finite=False)

    def __reduce__(self):
        """Pickling and copy.copy/deepcopy: rebuilt through Trajectory's constructor (checked, its arrays read-only
        again), as its own class (a subclass too), with any other attribute it holds."""
        fields = (self.t, self.x, self.R, self.P, self.L, self.scene, self.method, self.dt, self.divergence,
                  self.implementation)
        return _rebuilt, (type(self), fields), {k: v for k, v in vars(self).items() if k not in _FIELDS}

    def _quiet(self):
        """Diagnostics of a diverged run may overflow (R far off SO(3)): inf then, without a warning."""
        return np.errstate(over="ignore", invalid="ignore") if self.diverged else nullcontext()

    # --- how the run ended ----------------------------------------------------------
    @property
    def diverged(self) -> bool:
        """True if the run blew up: the arrays then end at the last good state, before the blow-up."""
        return self.divergence is not None

    @property
    def outcome(self) -> str:
        """One line a notebook can print: "diverged at t = 26.9 s (R overflowed to inf)" or
        "ran to t = 40 s (40000 steps)"."""
        if self.divergence is not None:
            return say(f"diverged at t = {self.divergence.t:.4g} s ({self.divergence.reason})",
                       f"a divergé à t = {self.divergence.t:.4g} s ({self.divergence.reason})")
        if not len(self.t):
            return say("no state (an empty head(0))", "aucun état (un head(0) vide)")
        return say(f"ran to t = {self.t[-1]:.4g} s ({len(self.t) - 1} recorded steps)",
                   f"a tourné jusqu'à t = {self.t[-1]:.4g} s ({len(self.t) - 1} pas enregistrés)")

    # --- access --------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.t)

    def state(self, k: int) -> State:
        """X(t_k) as a State (not checked: R may have left SO(3) under Euler); k an index as Python's,
        -len(traj) <= k < len(traj) (-1 the last)."""
        k = checks.index("k", k, len(self.t), "recorded states")
        return State.unchecked(self.x[k], self.R[k], self.P[k], self.L[k])

    def head(self, k: int) -> "Trajectory":
        """The first k recorded states, 0 <= k <= len(traj), as a Trajectory of the same run (views, not copies)."""
        return self._rows(slice(checks.integer("k", k, low=0, high=len(self.t))))

    def every(self, k: int) -> "Trajectory":
        """Every k-th recorded state, from the first (views, not copies): a run recorded every step,
        read as if it had been recorded every k steps (the last state kept only if k divides the count).
        1 <= k <= max(1, len(traj) − 1): a larger k would keep the first state only."""
        return self._rows(slice(None, None, checks.integer("k", k, low=1, high=max(1, len(self.t) - 1))))

    def _rows(self, rows: slice) -> "Trajectory":
        return Trajectory.unchecked(self.t[rows], self.x[rows], self.R[rows], self.P[rows], self.L[rows], scene=self.scene,
                          method=self.method, dt=self.dt, divergence=self.divergence,
                          implementation=self.implementation)

    @property
    def final(self) -> State:
        """The last state (a ValueError if the trajectory holds none: an empty head(0))."""
        if not len(self.t):
            raise ValueError("final: this trajectory holds no state (an empty head(0)), so it has no last state")
        return self.state(-1)

    @property
    def body(self):
        """The body of a single-body scene (a ValueError with N bodies: take traj.scene.bodies[i])."""
        if not self.scene.single:
            raise ValueError(f"body: this trajectory holds {self.scene.n_bodies} bodies; take one of "
                             f"traj.scene.bodies[0 … {self.scene.n_bodies - 1}]")
        return self.scene.bodies[0]

    def _mass(self):
        return self.scene.mass[0] if self.x.ndim == 2 else self.scene.mass

    def _I_body_inv(self):
        return self.scene.I_body_inv[0] if self.x.ndim == 2 else self.scene.I_body_inv

    # --- derived quantities over time ----------------------------------------------
    def velocity(self) -> np.ndarray:
        """v = P / M."""
        return unchecked_velocity(self.P, self._mass())

    def angular_velocity(self) -> np.ndarray:
        """ω = I⁻¹(t) L,  I⁻¹(t) = R I⁻¹_body Rᵀ  (world frame)."""
        with self._quiet():
            I_inv = unchecked_inverse_inertia(self.R, self._I_body_inv())
            return unchecked_angular_velocity(I_inv, self.L)

    def kinetic_energy(self) -> np.ndarray:
        """T = ½ P·v + ½ L·ω  (translation + rotation), shape (n+1,) (or (n+1, N)).
        (engine/motion.py: kinetic_energy, row by row.)"""
        lead, (R, P, L, M, J) = as_rows(self.R, self.P, self.L, self._mass(), self._I_body_inv(),
                                        tails=((3, 3), (3,), (3,), (), (3, 3)))
        T = np.empty(P.shape[0])
        with self._quiet():
            engine_rows().kinetic_energy_rows(R, P, L, M, J, T)
        return T.reshape(lead)

    def potential_energy(self) -> np.ndarray:
        """U of the scene's conservative effects per body (gravity M g z, springs ½ k (|r_a − r_b| − ℓ₀)²);
        zeros if it has none (no effect that has_potential).  (engine/motion.py: potential, state by state.)"""
        shape = self.t.shape if self.x.ndim == 2 else self.x.shape[:-1]
        if not any(e.has_potential for e in self.scene.effects):
            return np.zeros(shape)
        sys = self.scene.compile().system
        x, R = self._batched(self.x), self._batched(self.R)
        U = np.empty(x.shape[:2])
        for s in range(0, len(x), _ENERGY_CHUNK):           # the states in chunks: bounded extra memory
            S = matrix_rows(x[s:s + _ENERGY_CHUNK], R[s:s + _ENERGY_CHUNK])
            with self._quiet():
                engine_rows().potential_rows(sys, S, U[s:s + _ENERGY_CHUNK])
        return U.reshape(shape)

    def total_energy(self) -> np.ndarray:
        """E = T + U."""
        return self.kinetic_energy() + self.potential_energy()

    def linear_momentum(self) -> np.ndarray:
        """P (world)."""
        return self.P

    def angular_momentum(self, about="origin") -> np.ndarray:
        """Angular momentum in world axes about the origin (L + x × P), the centre of mass
        (about="com": the slides' L) or any fixed world point p (a 3-vector within ±1e100: L + (x − p) × P)."""
        if isinstance(about, str):
            if about not in ("origin", "com"):
                raise ValueError(f"about must be 'origin', 'com' or a 3-vector, got {about!r}")
            if about == "com":
                return self.L
            about = np.zeros(3)
        point = checks.vector3("about", about, bound=OVERFLOW)
        return self.L + np.cross(self.x - point, self.P)

    def orthogonality_error(self) -> np.ndarray:
        """‖RᵀR − I‖ over time: 0 on SO(3)."""
        with self._quiet():
            return orthogonality_error(self.R)

    def det_R(self) -> np.ndarray:
        """det R over time: 1 for a rotation."""
        with self._quiet():
            return np.linalg.det(self.R)

    def body_point(self, b, body: int = 0) -> np.ndarray:
        """World path r(t) = x + R b of a body point b (body axes: a finite 3-vector within ±1e100 m) of the body
        of index `body` (0 <= body < N; 0 for a single-body scene)."""
        b = checks.vector3("b", b, bound=OVERFLOW)
        body = checks.integer("body", body, low=0, high=self.scene.n_bodies - 1)
        if self.scene.single:
            return self.x + matvec(self.R, b)
        return self.x[:, body] + matvec(self.R[:, body], b)

    def body_angular_momentum(self) -> np.ndarray:
        """Rᵀ L: the angular momentum in body axes (the polhode lives here)."""
        return matvec(transpose(self.R), self.L)

    def _batched(self, a):
        return a[:, None] if self.x.ndim == 2 else a

    def describe(self) -> str:
        """A few lines: the scene, the method and step, how the run ended, and which implementation ran
        (the engine compiled, or its functions run as Python) and why."""
        dt = f", dt = {self.dt:g} s" if self.dt else ""
        ran = implementation_said(self.implementation)
        return say(f"{self.scene.describe()}\nMethod {self.method!r}{dt}: {self.outcome}.\nImplementation: {ran}.",
                   f"{self.scene.describe()}\nIntégrateur {self.method!r}{dt} : {self.outcome}.\n"
                   f"Implémentation : {ran}.")

    def __repr__(self) -> str:
        n, bodies = len(self.t) - 1, self.scene.n_bodies
        ended = f", {self.outcome}" if self.diverged else ""
        if n < 0:
            return say(f"Trajectory(no state, method {self.method!r}, {bodies} bod{'y' if bodies == 1 else 'ies'})",
                       f"Trajectory(aucun état, méthode {self.method!r}, {bodies} corps)")
        return say(f"Trajectory({n} steps, t = {self.t[0]:g} … {self.t[-1]:g} s, method {self.method!r}, "
                   f"{bodies} bod{'y' if bodies == 1 else 'ies'}{ended})",
                   f"Trajectory({n} pas, t = {self.t[0]:g} … {self.t[-1]:g} s, méthode {self.method!r}, "
                   f"{bodies} corps{ended})")


_FIELDS = ("t", "x", "R", "P", "L", "scene", "method", "dt", "divergence", "implementation")


def _rebuilt(cls, fields) -> Trajectory:
    """A trajectory of class cls (Trajectory or a subclass) built by Trajectory's constructor from its fields."""
    traj = cls.__new__(cls)
    Trajectory.__init__(traj, *fields)
    return traj


def shown(name: str, traj) -> Trajectory:
    """traj, if it is a Trajectory holding at least one state (what a plot or a drawing shows); else a ValueError
    naming it — a trajectory of no state (an empty head(0)) has nothing to show."""
    if not isinstance(traj, Trajectory):
        raise ValueError(f"{name} must be a Trajectory (from rbcourse.simulate), got {traj!r}")
    if not len(traj.t):
        raise ValueError(f"{name} must hold at least one state, got a trajectory of no state "
                         f"(len({name}) == 0: an empty head(0))")
    return traj


def _record(scene, t, x, R, P, L, finite: bool = True) -> tuple:
    """t, x, R, P, L as read-only float arrays (checks.read_only: no copy) of one run of `scene`: t (m,) and, a row
    per time, x (m, 3) for one body or (m, N, 3) for N, R (m, [N,] 3, 3), P and L as x.  Numbers only (checks.numbers),
    finite (no NaN or inf, as a State's) unless finite=False (Trajectory.unchecked)."""
    t = checks.numbers("t", t, "a 1-D array of times", copy=False)
    if t.ndim != 1:
        raise ValueError(f"t must be a 1-D array of times, got shape {t.shape}")
    if finite:
        _all_finite("t", t)
    rows = (len(t),) if scene.single else (len(t), scene.n_bodies)
    arrays = [t]
    for name, a, tail in (("x", x, (3,)), ("R", R, (3, 3)), ("P", P, (3,)), ("L", L, (3,))):
        want = rows + tail
        a = checks.numbers(name, a, f"an array of numbers of shape {want}", copy=False)
        if a.shape != want:
            raise ValueError(f"{name} must have shape {want} (a row per time of t, of the scene's "
                             f"{scene.n_bodies} bod{'y' if scene.n_bodies == 1 else 'ies'}), got shape {a.shape}")
        if finite:
            _all_finite(name, a)
        arrays.append(a)
    return tuple(checks.read_only(a) for a in arrays)


def _all_finite(name: str, a: np.ndarray) -> None:
    """A ValueError naming `name` if a holds a NaN or an inf: read by its min and max (NaN spreads to both), two
    passes without a copy of a run's record."""
    if a.size and not (math.isfinite(a.min()) and math.isfinite(a.max())):
        where = np.argwhere(~np.isfinite(a))[0]
        raise ValueError(f"{name} must contain only finite numbers (no NaN or inf, as a State's), got {name}"
                         f"[{', '.join(map(str, where))}] = {a[tuple(where)]}")


def implementation_said(implementation: str | None) -> str:
    """Which implementation ran, for describe(): the engine's own line in English (compiled, or interpreted, and
    why); in French, the same in a few words (the engine's line names numba's and Python's own terms)."""
    if not implementation:
        return say("not recorded (a trajectory built by hand)", "non enregistrée (une trajectoire construite à la main)")
    if language.current() == "en":
        return implementation
    if implementation.startswith("compiled"):
        return "compilée : numba compile les fonctions du moteur (code machine gardé sur le disque)"
    return "interprétée : les fonctions du moteur tournent en Python (engine/interpreted.py)"


# --- divergence: one check, one overflow limit, for every code path --------------------------------
OVERFLOW = 1e100   # a state component beyond this (in absolute value) is taken as a blow-up


class Divergence(NamedTuple):
    """When and why a run blew up: t (s) and step of the first bad state; reason, in words."""
    t: float
    step: int
    reason: str


def blow_up(named_arrays) -> str:
    """'' if every array of (name, array) pairs is finite and within ±OVERFLOW, component by component;
    else why not ("R became NaN", "L overflowed to inf", "x grew beyond 1e+100 (overflow)").

    Each component is tested on its own (not a sum, in which two mirrored bodies would cancel)."""
    for name, a in named_arrays:
        a = np.asarray(a)
        if a.size and not np.abs(a).max() < OVERFLOW:     # NaN compares False: caught here too
            if np.isnan(a).any():
                return say(f"{name} became NaN", f"{name} est devenu NaN")
            if not np.isfinite(a).all():
                return say(f"{name} overflowed to inf", f"{name} a débordé jusqu'à l'infini")
            return say(f"{name} grew beyond {OVERFLOW:g} (overflow)", f"{name} a dépassé {OVERFLOW:g} (débordement)")
    return ""


def first_blow_up(named_arrays) -> tuple[int, str]:
    """For arrays over time (a leading time axis): the index of the first row that fails `blow_up`
    (len if none) and its reason."""
    named_arrays = [(name, np.asarray(a)) for name, a in named_arrays]
    m = len(named_arrays[0][1])
    bad = np.zeros(m, dtype=bool)
    for _, a in named_arrays:
        with np.errstate(invalid="ignore"):
            bad |= ~(np.abs(a.reshape(m, -1)) < OVERFLOW).all(axis=1)
    if not bad.any():
        return m, ""
    k = int(np.argmax(bad))
    return k, blow_up([(name, a[k]) for name, a in named_arrays])


class SimulationDiverged(RuntimeError):
    """A run blew up (NaN, inf or overflow).  .trajectory holds the steps computed before (all finite);
    .t and .step say when, .reason why.  simulate(..., on_divergence="stop") returns that trajectory instead."""

    def __init__(self, message: str, trajectory: Trajectory, t: float, step: int, reason: str):
        super().__init__(message)
        self.trajectory = trajectory
        self.t = t
        self.step = step
        self.reason = reason
