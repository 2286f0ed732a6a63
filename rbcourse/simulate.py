"""The driver: simulate(scene, X0, t_end, dt, method) -> Trajectory.

The run is N = round(t_end/dt) steps of size h = t_end/N.  Each step is:
    1. impulses due in [t, t + h) kick the momenta (only if the scene has Impulse effects);
    2. the method advances the smooth dynamics (the scene's forces and torques) by h, with what it
       prepared for the run (method.prepare(scene), once, before the first step);
    3. contacts are resolved: collisions and resting contact (only if the scene has a Ground,
       and only on a state that passed the check);
    4. the state is checked, every component on its own (trajectory.blow_up): a NaN, an inf or a
       component beyond 1e100 stops the run with SimulationDiverged, which keeps the trajectory
       computed so far (all finite) — or, with on_divergence="stop", returns it, marked diverged.
"""
from __future__ import annotations

import math

import numpy as np

from . import checks
from .outputs import progress as progress_bar
from .integrators import get_method, kernels
from .scene import as_scene
from .state import State
from .trajectory import OVERFLOW, Divergence, SimulationDiverged, Trajectory, blow_up, first_blow_up

MAX_RECORD_BYTES = 4e9   # a run whose recorded states would need more memory than this is refused


def simulate(scene, X0: State, t_end: float, dt: float, method="rk4", *,
             record_every: int = 1, progress: bool = False, rtol: float | None = None,
             atol: float | None = None, fast: bool = True, on_divergence: str = "raise") -> Trajectory:
    """Integrate the scene from X0 over [0, t_end] with steps of about dt.

    scene: a Scene, or a bare RigidBody (a free body).
    X0: the initial State (one body, or N bodies stacked).
    method: a name in METHODS (e.g. "euler", the slides' method) or a Method.
    record_every: keep every k-th state (long runs stay small); the last state is always kept.
    progress: show a progress bar (True or False).
    rtol, atol: tolerances of the error-controlled method "adaptive" (dt is then its output interval).
    fast: run the compiled engine (rbcourse/engine: the slides' physics written once per body, compiled
        by numba) for the methods it has (euler, euler_project, quaternion_euler, rk4), on every scene;
        adaptive and exact_splitting on one free or pivoted body under gravity run their float kernels;
        the rest runs the numpy engine.  False: always the numpy engine.  traj.implementation says
        which ran, and why.
    on_divergence: what a blow-up (NaN, inf, a component beyond 1e100) does —
        "raise": raise SimulationDiverged, whose .trajectory keeps the steps computed before;
        "stop": return that trajectory, with traj.diverged True and traj.divergence saying when and why
        (for runs that are expected to blow up, as the slides' Euler does: part of the lesson, not an error).
    """
    scene = as_scene(scene)
    if not isinstance(X0, State):
        raise ValueError(f"X0 must be a State, got {X0!r}")
    t_end = checks.real("t_end", t_end, low=0.0)
    dt = checks.positive("dt", dt)
    tolerances = {k: checks.positive(k, v) for k, v in (("rtol", rtol), ("atol", atol)) if v is not None}
    method = get_method(method).configured(**tolerances)
    record_every = checks.integer("record_every", record_every, low=1)
    progress = checks.boolean("progress", progress)
    fast = checks.boolean("fast", fast)
    on_divergence = checks.choice("on_divergence", on_divergence, ("raise", "stop"))
    X = scene.to_engine(X0)
    too_big = _blown_up(X)
    if too_big:
        raise ValueError(f"X0 must hold components within ±{OVERFLOW:g} (the blow-up limit), but its {too_big}")
    steps = t_end / dt                              # may be inf (t_end = 1e308, dt = 5e-324): check before round
    if not steps <= 10**9:
        raise ValueError(f"dt must give at most 1e9 steps over t_end = {t_end:g}, got dt = {dt:g} ({steps:.3g} steps)")
    n = 0 if t_end == 0 else max(1, round(steps))
    _check_memory(n, record_every, scene.n_bodies)
    h = t_end / n if n else dt
    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):   # a blow-up is detected below
            why_not = "fast=False: the numpy engine"
            if fast:
                from .engine import driver      # numba loads at the first compiled run, not at `import rbcourse`
                why_not = driver.supports(method, scene)
                if not why_not:
                    return _run_compiled(scene, X, n, h, method, record_every, progress)
            prep = method.prepare(scene)            # what the numpy method or the kernel precomputes for this run
            if fast and kernels.available(method, scene):
                return _run_kernel(scene, prep, X, n, h, method, record_every, why_not)
            traj = _run(scene, prep, X, n, h, method, record_every, progress, events=scene.has_events,
                        contacts=scene.has_contacts, implementation=f"numpy ({why_not})")
            return traj
    except SimulationDiverged as err:
        if on_divergence == "stop":
            return err.trajectory
        raise


def _check_memory(n: int, every: int, n_bodies: int):
    """Refuse a run whose recorded states would not fit: (n/every + 2) states of 19 floats per body."""
    need = (n // every + 2) * (1 + 18 * n_bodies) * 8
    if need > MAX_RECORD_BYTES:
        k = int(math.ceil(need / MAX_RECORD_BYTES * every))
        raise ValueError(f"record_every = {every} would record {n // every + 1} states, about {need / 1e9:.3g} GB "
                         f"(the limit is {MAX_RECORD_BYTES / 1e9:g} GB): pass record_every >= {k}, or a shorter t_end")


def _run(scene, prep, X, n, h, method, record_every, progress, events, contacts, implementation) -> Trajectory:
    """The step loop of the general path (see the module docstring for its phases)."""
    rec = _Recorder(X, n, record_every)
    encode, decode = method.encode, method.decode
    Y = encode(scene, X)                       # the method's own representation of X
    t, good = 0.0, (0.0, Y)
    with progress_bar(n, "step", "simulate", progress and n >= 1000) as bar:
        for k in range(n):
            t1 = (k + 1) * h
            if events:                                                      # 1. impulses due in [t, t1)
                Y = encode(scene, scene.apply_impulses(t, t1, decode(scene, Y)))
            Y = method(scene, t, Y, h, prep)                                # 2. the method's step
            reason = _blown_up(Y)
            if contacts and not reason:                                     # 3. collisions, resting contact
                Y, reason = _resolve_contacts(scene, decode(scene, Y), h, encode)
            t = t1
            reason = reason or _blown_up(Y)                                 # 4. the check
            if not reason and rec.wants(k + 1):
                X = scene.constrain(decode(scene, Y))
                reason = _blown_up(X)
            if reason:
                t_good, Y_good = good
                rec.keep_last(t_good, scene.constrain(decode(scene, Y_good)))
                raise _diverged(rec.trajectory(scene, method.name, h, implementation), method, n, h, k + 1, reason)
            good = (t, Y)
            if rec.wants(k + 1):
                rec.add(t, X)
            if (k + 1) % 1000 == 0:
                bar.update(1000)
    return rec.trajectory(scene, method.name, h, implementation)


def _resolve_contacts(scene, X, h, encode):
    """Contacts on a finite state; a contact system the solver cannot handle is a blow-up, not a crash."""
    try:
        return encode(scene, scene.resolve_contacts(X, h)), ""
    except np.linalg.LinAlgError as err:
        return None, f"the contact solver failed ({err}) on a state that is no longer physical"


def _diverged(traj: Trajectory, method, n: int, h: float, step: int, reason: str) -> SimulationDiverged:
    """The error for a blow-up at `step`; traj (the good part, all finite) learns when and why."""
    t = step * h
    traj.divergence = Divergence(t, step, reason)
    msg = (f"simulation diverged at t = {t:.6g} s (step {step} of {n}, method {method.name!r}, dt = {h:g}): "
           f"{reason}; the trajectory up to t = {traj.t[-1]:.6g} s is kept in .trajectory")
    return SimulationDiverged(msg, traj, t, step, reason)


def _run_compiled(scene, X, n, h, method, every, progress) -> Trajectory:
    """The run through the compiled engine (rbcourse/engine), checked as _run checks."""
    from .engine import driver
    with progress_bar(n, "step", "simulate", progress and n >= 1000) as bar:
        out = driver.simulate_compiled(scene, method, X, n, h, every, bar)
    rows = out.rows
    t, x, R, P, L = (a[:rows] for a in out.record)
    _to_state_L(scene, x, R, P, L)
    if scene.single:
        x, R, P, L = (a[:, 0] for a in (x, R, P, L))
    traj = Trajectory(t, x, R, P, L, scene=scene, method=method.name, dt=h, implementation=driver.implementation())
    if out.bad_step:
        raise _diverged(traj, method, n, h, out.bad_step, out.why)
    return traj


def _run_kernel(scene, prep, X, n, h, method, every, why_not: str) -> Trajectory:
    """The same run through the method's float kernel (integrators/kernels.py), checked as _run checks."""
    (t, x, R, P, L), reason, k = kernels.run(method, scene, X, n, h, every, prep)
    _to_state_L(scene, x[:, None], R[:, None], P[:, None], L[:, None])     # in place, no copy of the record
    # the kernels step the rotation; the translation is in closed form: check every recorded state as a whole
    bad, why = first_blow_up([("x", x), ("R", R), ("P", P), ("L", L)])
    if bad < len(t):
        k, reason = int(round(t[bad] / h)), why
        t, x, R, P, L = (a[:bad] for a in (t, x, R, P, L))
    traj = Trajectory(t, x, R, P, L, scene=scene, method=method.name, dt=h,
                      implementation=f"float kernel (integrators/kernels.py, one body: {why_not})")
    if reason:
        raise _diverged(traj, method, n, h, k, reason)
    return traj


def _blown_up(Y) -> str:
    """'' if Y (a State, a method's array, or a tuple whose first item is one) is finite and not huge;
    else why not (trajectory.blow_up: every component tested on its own)."""
    if isinstance(Y, tuple):          # a method's state with extra data (adaptive)
        Y = Y[0]
    if isinstance(Y, State):
        return blow_up((name, getattr(Y, name)) for name in State.__slots__)
    if Y.shape[:1] == (13,):          # a quaternion method's Y = [x, q, P, L_b] (13, N)
        return blow_up([("x", Y[0:3]), ("q", Y[3:7]), ("P", Y[7:10]), ("L", Y[10:13])])
    return blow_up([("the state", Y)])


class _Recorder:
    """The recorded states, in arrays preallocated once for the whole run: (n/every + 2) rows of
    t, x, R, P, L (the zeros are not resident until written).  The Trajectory gets views of them:
    the record is never copied."""

    def __init__(self, X0: State, n: int, every: int):
        self.every, self.n = every, n
        m = n // every + 2
        self.t = np.zeros(m)
        self.arrays = [np.zeros((m,) + getattr(X0, k).shape) for k in State.__slots__]
        self.count = 0
        self._done = None
        self.add(0.0, X0)

    def wants(self, k: int) -> bool:
        """Is step k one to record?"""
        return k % self.every == 0 or k == self.n

    def add(self, t: float, X: State):
        i = self.count
        self.t[i] = t
        for arr, name in zip(self.arrays, State.__slots__):
            arr[i] = getattr(X, name)
        self.count += 1

    def keep_last(self, t: float, X: State):
        """Record the last good state before a blow-up, if it is not recorded yet."""
        if self.t[self.count - 1] != t:
            self.add(t, X)

    def trajectory(self, scene, method: str, dt: float, implementation: str) -> Trajectory:
        """The recorded rows as a Trajectory of views (L converted to the centre of mass in place, once)."""
        if self._done is None:
            i = self.count
            x, R, P, L = (a[:i] for a in self.arrays)
            _to_state_L(scene, x, R, P, L)
            arrays = (x, R, P, L)
            if scene.single:
                arrays = tuple(a[:, 0] for a in arrays)
            self._done = (self.t[:i],) + arrays
        return Trajectory(*self._done, scene=scene, method=method, dt=dt, implementation=implementation)


_CHUNK = 1 << 16   # recorded rows converted at a time: the temporaries stay small


def _to_state_L(scene, x, R, P, L):
    """Engine L (about the rotation centre) -> L about the centre of mass (scene.to_state_arrays),
    written into L in place, _CHUNK rows at a time (arrays (m, N, ...))."""
    for s in range(0, len(L), _CHUNK):
        part = L[s:s + _CHUNK]
        out = scene.to_state_arrays(x[s:s + _CHUNK], R[s:s + _CHUNK], P[s:s + _CHUNK], part)
        if out is not part:
            part[...] = out
