"""The Python side of a run: a Scene and a State in, the recorded arrays out (simulate.py makes the Trajectory).

    1. the scene becomes the kernel's data (Scene.compile), the state the method's arrays (encode);
    2. forces given as functions f(t) are evaluated here, in Python, at the times the method needs
       (t_k + c_i h for its stages c_i), a chunk of steps at a time, and passed in;
    3. the family's loop (engine/run.py) advances the chunk, recording into the trajectory's own arrays, the
       contacts with the scene's grounds solved after each step inside it (engine/contact.py);
    4. a step that holds an impulse is made here: split at the impulse's time, the kick applied at that time.
Forces over time given as data (profiles.py) are evaluated by the kernel (engine/profiles.py), not here.

The kernel runs compiled (rbcourse.engine, numba) or as Python (engine/interpreted.py: the same files):
kernel(fast) is the one that runs, and the method's row (methods.METHODS: its Stepping,
engine/plan.py) says which of its functions step the method.
"""
from __future__ import annotations

import importlib
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from . import compiling
from .engine.plan import ADAPTIVE, COLUMNS, LAYOUTS
from .engine.system import evaluates_forces
from .forcing import SubstepForces, deferred_interrupt, forces_at
from .impulse import kick
from .rotation import quat_from_matrix, quat_rotate
from .rowwise import matrix_parts
from .state import State, from_matrix, to_matrix
from .support.language import say
from .trajectory import blow_up

CHUNK = 1 << 14          # steps per call when forces are functions of t (their values are evaluated per chunk)
WORK = 1 << 22           # body-steps per call at most (about a second): Ctrl-C is honoured between calls


class Kernel:
    """The kernel that runs: compiled (fast=True: rbcourse.engine, numba) or run as Python (engine/interpreted.py)."""

    def __init__(self, fast: bool):
        if fast:
            self.package = importlib.import_module("rbcourse.engine")
        else:
            from .engine import interpreted
            self.package = interpreted.package()
        self.fast = fast
        self.run, self.steps, self.motion, self.contact, self.jit = (
            self.module(m) for m in ("run", "steps", "motion", "contact", "jit"))

    def module(self, name: str):
        return importlib.import_module(f"{self.package.__name__}.{name}")

    def describe(self) -> str:
        """Which implementation runs, and why (one line: jit.describe of this kernel)."""
        return self.jit.describe()


class Plan(NamedTuple):
    """A method's Stepping resolved in the kernel that runs, for one run: its family's loop and step, its
    table, the times its forces are evaluated at, the work slots it needs, and its arguments as data."""
    loop: object
    step: object
    layout: str
    stage_times: np.ndarray
    stages: int
    scratch: int
    args: tuple                 # (kind, layout, finish, A, b, den, opts): what the loop and the step take
    time_forces: bool
    family: str


@lru_cache(maxsize=None)
def kernel(fast: bool) -> Kernel:
    """The kernel that runs (one per process and implementation)."""
    return Kernel(fast)


def supports(kernel: Kernel, method, sys) -> str:
    """'' if the kernel runs this method on this scene (its System: Scene.compile), else why not (one line)."""
    s = method.kernel
    if s is None:
        return f"method {method.name!r} has no step in the kernel"
    supported = kernel.run.LOOPS[s.family].supported
    return supported(sys) if supported else ""


def plan(kernel: Kernel, method, sys, N: int) -> Plan:
    """The method's row resolved in `kernel` for a run of N bodies (built once per run)."""
    s, settings = method.kernel, method.settings
    family = kernel.run.LOOPS[s.family]
    if family.configure is not None:
        table, nodes, opts = family.configure(sys, settings)
    else:
        table, nodes, opts = s.table, s.nodes, np.array([float(v) for v in settings.values()], dtype=float)
    table = table() if callable(table) else table
    c = np.array(nodes, dtype=float) if len(nodes) else table.c
    args = (s.kind, LAYOUTS[s.layout], s.finish, np.ascontiguousarray(table.A), np.ascontiguousarray(table.b),
            float(table.den), opts)
    return Plan(family.loop, family.step, s.layout, c, table.stages, kernel.steps.work_slots(s.scratch, N), args,
                s.time_forces, s.family)


def encode(layout: str, X: State) -> np.ndarray:
    """The engine's state (L about the rotation centre, N bodies) -> the method's arrays (engine/plan.py:
    COLUMNS): S = [x, R, P, L] ("matrix"), Y = [x, q, P, L_b = Rᵀ L] ("quat"), Y = [x, q, P, L] ("quat_world")."""
    if layout == "matrix":
        return to_matrix(X)
    if layout not in COLUMNS:
        raise ValueError(f"layout must be one of {sorted(COLUMNS)}, got {layout!r}")
    q = quat_from_matrix(X.R)
    L = X.L if layout == "quat_world" else quat_rotate(q, X.L, inverse=True)
    return np.ascontiguousarray(np.concatenate([X.x, q, X.P, L], axis=1))


def decoder(kernel: Kernel, layout: str):
    """The kernel's decode of a layout: its arrays -> a record row (x, R, P, L)."""
    return kernel.run.DECODE[layout]


class Record(NamedTuple):
    """The recorded rows (preallocated for the whole run): t (m,), x (m, N, 3), R (m, N, 3, 3), P, L."""
    t: np.ndarray
    x: np.ndarray
    R: np.ndarray
    P: np.ndarray
    L: np.ndarray


def new_record(X: State, n: int, every: int) -> Record:
    m = n // every + 2
    N = X.x.shape[0]
    rec = Record(np.zeros(m), np.zeros((m, N, 3)), np.zeros((m, N, 3, 3)), np.zeros((m, N, 3)), np.zeros((m, N, 3)))
    rec.x[0], rec.R[0], rec.P[0], rec.L[0] = X.x, X.R, X.P, X.L
    return rec


def reason(layout: str, Y: np.ndarray) -> str:
    """Why the state Y is a blow-up (trajectory.blow_up on its named parts)."""
    return blow_up([(name, Y[:, a:b]) for name, a, b in COLUMNS[layout]])


class Outcome(NamedTuple):
    """What a run returns to simulate: the record (rows used), and the blow-up if any."""
    record: Record
    rows: int
    bad_step: int        # the step (1-based) whose result blew up, or 0
    why: str


def contact_failed() -> str:
    """Why a run stopped when a contact system was not finite, in the active language."""
    return say("the contact solver failed (a contact system is not finite) on a state that is no longer physical",
               "le solveur de contact a échoué (un système de contact n'est pas fini) sur un état qui n'est "
               "plus physique")




class Run:
    """One run's arrays and state: the method's plan, its arrays Y, out, K, U, w, the contact solver's work cw,
    the record, and the steps that hold impulses (kicks)."""

    def __init__(self, kernel: Kernel, scene, data, method, X: State, n: int, h: float, every: int):
        self.kernel, self.scene, self.sys, self.functions = kernel, scene, data.system, data.functions
        self.n, self.h, self.every = n, h, every
        self.Y = encode(method.kernel.layout, X)
        N = self.Y.shape[0]
        self.plan = p = plan(kernel, method, self.sys, N)
        self.decode = decoder(kernel, p.layout)
        self.out, self.U = np.empty_like(self.Y), np.empty_like(self.Y)
        self.K = np.empty((max(p.stages, len(p.stage_times)) + p.scratch,) + self.Y.shape)
        self.w = kernel.motion.work(N)
        self.cw = kernel.contact.work(N) if scene.has_contacts else None    # None: no contact code compiled
        self.rec = new_record(X, n, every)
        self.substeps = (SubstepForces(self.functions, p.stage_times, p.args, kernel.module("adaptive"))
                         if self.functions and not p.time_forces else None)
        self.fill = (None if not len(self.sys.profiles)
                     else lambda times, values: kernel.module("profiles").fill_profiles(self.sys, times, values))
        self.kicks = kick_plan(scene._impulses, n, h)
        self.forces = evaluates_forces(self.sys)      # else no force code is compiled (values None: motion.stage)

    def chunk(self) -> int:
        """Steps per compiled call: as many as fit (a chunk of forces f(t) at a time; 1 with substep forces)."""
        most = max(1, WORK // self.Y.shape[0])
        return 1 if self.substeps is not None else min(CHUNK if self.functions else max(self.n, 1), most)

    def values(self, starts, h: float):
        """The forces over time at the stage times of steps of size h from `starts` (zeros: no slot); None for a
        scene that evaluates no force (a free body: engine/motion.stage — no force code is compiled for it)."""
        if not self.forces:
            return None
        if not self.functions or self.substeps is not None:
            return np.zeros((len(starts), len(self.plan.stage_times), 0, 3))
        return forces_at(self.functions, self.plan.stage_times, starts, h, self.fill)


def kick_plan(impulses, n: int, h: float) -> dict:
    """{step k: {time t: [(Impulse, rows), ...]}}: each impulse in the step that holds its time, at its time.
    A time on a step boundary (to rounding: within 1e-9 steps) is the boundary k h itself, applied before step
    k — or, at t_end = n h, after the last step, before its state is recorded (step n − 1, t = n h).  A run of
    no step (t_end = 0) has none here: simulate_compiled applies its impulses to the one state it records."""
    plan: dict = {}
    if n == 0:
        return plan
    for e, idx in impulses:
        s = e.time / h
        j = round(s)
        if abs(s - j) <= 1e-9 * max(1.0, abs(s)):
            k, t = (j, j * h) if j < n else (n - 1, n * h)
        else:
            k, t = min(int(np.floor(s)), n - 1), e.time
        plan.setdefault(k, {}).setdefault(t, []).append((e, idx))
    return plan


def simulate_compiled(kernel: Kernel, scene, data, method, X: State, n: int, h: float, every: int, bar) -> Outcome:
    """n steps of the method from X (engine coordinates) in `kernel`; data: scene.compile(); `bar` a progress bar
    (update(k)).  Chunks of steps run in the compiled loop (engine/run.py: contacts included); a step that holds
    an impulse, or whose forces f(t) are evaluated per attempt (adaptive), is made here (_python_step)."""
    r = Run(kernel, scene, data, method, X, n, h, every)
    p, rec = r.plan, r.rec
    chunk = r.chunk()
    row, k = 1, 0
    if n == 0 and scene._impulses:          # t_end = 0: its impulses (all at t = 0) are in the one state recorded
        r.Y = _kick(r, r.Y, scene._impulses)
        r.decode(r.sys, r.Y, 0, *rec[1:])
    with deferred_interrupt(kernel.fast) as held:     # Ctrl-C: honoured between calls, never inside numba
        while k < n:
            held.check()
            if k in r.kicks or r.substeps is not None:
                Y_good = r.Y
                why = _python_step(r, k)
                if why:
                    return _stopped(r, row, k + 1, why, Y_good, k)
                k += 1
                bar.update(1)
                if k % every == 0 or k == n:
                    r.decode(r.sys, r.Y, row, *rec[1:])
                    why = blow_up([(name, getattr(rec, name)[row]) for name in "xRPL"])
                    if why:
                        return _stopped(r, row, k, why, Y_good, k - 1)
                    rec.t[row] = k * h
                    row += 1
                continue
            k1 = min([n, k + chunk] + [j for j in r.kicks if j > k])
            values = r.values(np.arange(k, k1) * h, h)
            args = (p.args, r.sys, values, r.Y, r.out, h, k, k1, n, every, row, tuple(rec), r.K, r.U, r.w, r.cw)
            with compiling.announced(p.loop, args, p.family, r.forces, r.cw is not None):   # says so if it compiles
                k_done, row, bad = p.loop(*args)
            bar.update(k_done - k)
            if bad:
                why = (reason(p.layout, r.out) or blow_up([(name, getattr(rec, name)[row]) for name in "xRPL"])
                       or contact_failed())
                return _stopped(r, row, k_done + 1, why, r.Y, k_done)
            k = k_done
    return Outcome(rec, row, 0, "")


def _stopped(r: Run, row, step, why, Y_good, k_good) -> Outcome:
    """A blow-up at `step`: the last good state (after k_good steps) recorded if it is not yet."""
    rec = r.rec
    if rec.t[row - 1] != k_good * r.h:
        rec.t[row] = k_good * r.h
        r.decode(r.sys, Y_good, row, *rec[1:])
        row += 1
    return Outcome(rec, row, step, why)


def _python_step(r: Run, k: int) -> str:
    """Step k made here, between compiled calls: split at the times of its impulses (each kick applied at its
    own time: the method steps to it, kicks, steps on), the contacts after each piece.  r.Y := the new state
    (a copy; r.Y is left as it was if a piece blew up).  Returns why it blew up, or ''."""
    h = r.h
    t0, t1 = k * h, (k + 1) * h
    Y, t = r.Y, t0
    kicks = sorted(r.kicks.get(k, {}).items())
    for t_kick, impulses in kicks + [(t1, None)]:
        if t_kick > t:
            whole = (t, t_kick) == (t0, t1)
            why = _piece(r, Y, t, h if whole else t_kick - t, k if whole else None)
            if why:
                return why
            Y, t = np.ascontiguousarray(r.out).copy(), t_kick
        if impulses:
            Y = _kick(r, Y, impulses)
            why = reason(r.plan.layout, Y)
            if why:
                return why
    if r.plan.args[0] == ADAPTIVE:
        r.plan.args[-1][r.kernel.module("adaptive").STEPS] = k + 1     # its output steps: t = STEPS h
    r.Y = Y if Y is not r.Y else Y.copy()
    return ""


def _piece(r: Run, Y, t: float, h: float, k=None) -> str:
    """One step of the method from Y at time t, of size h, into r.out, then the contacts: why it blew up, or ''.
    k: the step's number when the piece is the whole step k (t = k h)."""
    p = r.plan
    if p.args[0] == ADAPTIVE:                  # its forces f(t) are at t = STEPS h
        adaptive = r.kernel.module("adaptive")
        if k is None or r.kicks:                   # the state, or the step, changed: the substep is chosen again
            adaptive.forget_substep(p.args[-1])
        p.args[-1][adaptive.STEPS] = k if k is not None else t / h
    if r.substeps is not None:
        r.substeps(r.sys, Y, r.out, h, r.K, r.U, r.w)
    else:
        values = r.values(np.array([t]), h)
        args = (*p.args, r.sys, None if values is None else values[0], Y, r.out, h, r.K, r.U, r.w)
        with compiling.announced(p.step, args, p.family, r.forces):    # checked at the step's first call only
            p.step(*args)
    why = reason(p.layout, r.out)
    if not why and r.scene.has_contacts:
        if r.kernel.module("grounds").contacts(p.args[1], r.sys, r.out, h, r.cw) < 0:
            return contact_failed()
        why = reason(p.layout, r.out)
    return why


def _kick(r: Run, Y, impulses):
    """The kicks of `impulses` [(Impulse, rows)] on the method's state Y (a new array): engine/motion.py's kick
    on the slides' state (impulse.kick), laid out back as the method's."""
    S = encode("matrix", _state(r, Y))
    kick(impulses, r.sys, S, r.kernel.motion)
    return S if r.plan.layout == "matrix" else encode(r.plan.layout, from_matrix(S))


def _state(r: Run, Y) -> State:
    """The engine's State of the method's arrays Y."""
    N = Y.shape[0]
    x, R, P, L = np.zeros((1, N, 3)), np.zeros((1, N, 3, 3)), np.zeros((1, N, 3)), np.zeros((1, N, 3))
    r.decode(r.sys, Y, 0, x, R, P, L)
    return State.unchecked(x[0], R[0], P[0], L[0])


def derivative(kernel: Kernel, scene, t: float, X: State):
    """dX/dt = (v, ω* R, F, τ) of the N bodies of X (engine coordinates: L about the rotation centre) at time t:
    motion.dxdt on the scene as data, forces given as functions f(t) evaluated at t.
    Returns v (N, 3), Ṙ (N, 3, 3), F (N, 3), τ (N, 3)."""
    data = scene.compile()
    S = encode("matrix", X)
    dS = np.empty_like(S)
    values = (np.array([effect.force_at(t) for effect in data.functions], dtype=float).reshape(-1, 3)
              if evaluates_forces(data.system) else None)
    kernel.motion.dxdt(data.system, values, S, dS, kernel.motion.work(S.shape[0]))
    return matrix_parts(dS)
