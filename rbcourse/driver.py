"""The Python side of a run: a Scene and a State in, the recorded arrays out (simulate.py makes the Trajectory).

    1. the scene becomes the kernel's data (Scene.compile), the state the method's arrays (encode);
    2. forces given as functions f(t) are evaluated here, in Python, at the times the method needs
       (t_k + c_i h for its stages c_i), a chunk of steps at a time, and passed in;
    3. the family's loop (engine/run.py) advances the chunk, recording into the trajectory's own arrays;
       impulses and contacts, when the scene has them, are applied between steps here.

The kernel runs compiled (rbcourse.engine, numba) or as Python (engine/interpreted.py: the same files):
kernel(fast) is the one that runs, and the method's row (integrators.METHODS: its Stepping,
engine/plan.py) says which of its functions step the method.
"""
from __future__ import annotations

import importlib
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from . import compiling
from .engine.plan import ADAPTIVE, COLUMNS, LAYOUTS
from .forcing import SubstepForces, deferred_interrupt, force_values
from .impulse import kick_due
from .rotation import quat_from_matrix, quat_rotate
from .rowwise import matrix_parts, matrix_rows
from .state import State, from_matrix, to_matrix
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
        self.run, self.motion, self.contact, self.jit = (self.module(m) for m in ("run", "motion", "contact", "jit"))

    def module(self, name: str):
        return importlib.import_module(f"{self.package.__name__}.{name}")

    def function(self, dotted: str):
        """A kernel function named "module.function" (a method's Stepping names them so)."""
        module, name = dotted.rsplit(".", 1)
        return getattr(self.module(module), name)

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
    return kernel.function(s.supported)(sys) if s.supported else ""


def plan(kernel: Kernel, method, sys, N: int) -> Plan:
    """The method's row resolved in `kernel` for a run of N bodies (built once per run)."""
    s, settings = method.kernel, method.settings
    table, nodes = s.table, s.nodes
    if s.of_settings:
        table, nodes = kernel.function(s.of_settings)(settings)
    table = table() if callable(table) else table
    if isinstance(nodes, str):
        nodes = kernel.function(nodes)()
    c = np.array(nodes, dtype=float) if len(nodes) else table.c
    scratch = kernel.function(s.scratch)(N) if isinstance(s.scratch, str) else s.scratch
    opts = (kernel.function(s.opts)(sys, settings) if s.opts
            else np.array([float(v) for v in settings.values()], dtype=float))
    args = (s.kind, LAYOUTS[s.layout], s.finish, np.ascontiguousarray(table.A), np.ascontiguousarray(table.b),
            float(table.den), opts)
    return Plan(kernel.run.loop_for(s.family, s.layout), kernel.module("steps").FAMILY_STEP[s.family],
                s.layout, c, table.stages, scratch, args, s.time_forces, s.family)


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


class Run:
    """One run's arrays and state: the method's plan, its arrays Y, out, K, U, w, the record."""

    def __init__(self, kernel: Kernel, scene, data, method, X: State, n: int, h: float, every: int):
        self.kernel, self.scene, self.sys, self.functions = kernel, scene, data.system, data.functions
        self.n, self.h, self.every = n, h, every
        self.Y = encode(method.kernel.layout, X)
        self.plan = p = plan(kernel, method, self.sys, self.Y.shape[0])
        self.decode = decoder(kernel, p.layout)
        self.out, self.U = np.empty_like(self.Y), np.empty_like(self.Y)
        self.K = np.empty((max(p.stages, len(p.stage_times)) + p.scratch,) + self.Y.shape)
        self.w = kernel.motion.work(self.Y.shape[0])
        self.rec = new_record(X, n, every)
        self.substeps = (SubstepForces(self.functions, p.stage_times, p.args, kernel.module("adaptive"))
                         if self.functions and not p.time_forces else None)
        self.contacts = Contacts(kernel, scene, self.Y.shape[0]) if scene.has_contacts else None
        self.between = scene.has_events or scene.has_contacts or self.substeps is not None

    def chunk(self) -> int:
        """Steps per compiled call: 1 when something happens between steps, else as many as fit."""
        most = max(1, WORK // self.Y.shape[0])
        return 1 if self.between else min(CHUNK if self.functions else max(self.n, 1), most)


def simulate_compiled(kernel: Kernel, scene, data, method, X: State, n: int, h: float, every: int, bar) -> Outcome:
    """n steps of the method from X (engine coordinates) in `kernel`; data: scene.compile(); `bar` a progress bar
    (update(k))."""
    r = Run(kernel, scene, data, method, X, n, h, every)
    p, rec = r.plan, r.rec
    chunk = r.chunk()
    functions = () if r.substeps is not None else r.functions   # adaptive + f(t): evaluated per attempt
    no_values = np.zeros((chunk, len(p.stage_times), 0, 3))
    row, k = 1, 0
    with deferred_interrupt(kernel.fast) as held:     # Ctrl-C: honoured between calls, never inside numba
        while k < n:
            held.check()
            k1 = min(n, k + chunk)
            values = force_values(functions, p.stage_times, h, k, k1) if functions else no_values
            if r.between:
                Y_good = r.Y
                bad, why = _between_steps(r, values, k)
                if bad:
                    return _stopped(r, row, k + 1, why, r.Y, k)
                k += 1
                if k % every == 0 or k == n:
                    r.decode(r.sys, r.Y, row, *rec[1:])
                    why = blow_up([(name, getattr(rec, name)[row]) for name in "xRPL"])
                    if why:
                        return _stopped(r, row, k, why, Y_good, k - 1)
                    rec.t[row] = k * h
                    row += 1
                continue
            args = (p.args, r.sys, values, r.Y, r.out, h, k, k1, n, every, row, tuple(rec), r.K, r.U, r.w)
            with compiling.announced(p.loop, args, p.family):        # says so when this call compiles
                k_done, row, bad = p.loop(*args)
            bar.update(k_done - k)
            if bad:
                why = reason(p.layout, r.out) or blow_up([(name, getattr(rec, name)[row]) for name in "xRPL"])
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


def _between_steps(r: Run, values, k: int):
    """One step with impulses before it and contacts after it (applied here, between compiled calls); the
    step of a method that evaluates forces f(t) per attempt (SubstepForces), if any.  Returns (bad, why);
    r.Y is the new state (a copy), or the last good one when bad."""
    scene, p, h = r.scene, r.plan, r.h
    t0, t1 = k * h, (k + 1) * h
    Y = r.Y
    if scene.has_events and any(e.due(t0, t1) for e, _ in scene._impulses):
        S = encode("matrix", _state(r, Y))       # a copy: r.Y stays the last good state
        kick_due(scene._impulses, t0, t1, r.sys, S, r.kernel.motion)
        Y = S if p.layout == "matrix" else encode(p.layout, from_matrix(S))
    if p.args[0] == ADAPTIVE and (scene.has_events or scene.has_contacts):
        r.kernel.module("adaptive").forget_substep(p.args[-1])   # the state may change between steps
    if r.substeps is not None:
        r.substeps(r.sys, Y, r.out, h, r.K, r.U, r.w)
    else:
        args = (*p.args, r.sys, values[0], Y, r.out, h, r.K, r.U, r.w)
        with compiling.announced(p.step, args, p.family):      # checked at the step's first call only
            p.step(*args)
    why = reason(p.layout, r.out)
    if not why and r.contacts is not None:
        if r.contacts.resolve(p.layout, r, r.out, h) < 0:
            return True, "the contact solver failed (a contact system is not finite) on a state that is no longer physical"
        why = reason(p.layout, r.out)
    if why:
        return True, why
    r.Y = np.ascontiguousarray(r.out).copy()
    return False, ""


class Contacts:
    """The scene's contacts (its Grounds), solved after each step on the engine's state S (N, 18), in place
    (contact.Ground.resolve_matrix: engine/contact.py, in the kernel that runs).  A method on (x, q, P, L_b) or
    (x, q, P, L) has its state laid out as S for the solver, and back only when a body touched."""

    def __init__(self, kernel: Kernel, scene, N: int):
        self.kernel, self.scene, self.grounds = kernel, scene, [(e, geo) for e, idx, geo in scene._contacts]
        self.S = np.zeros((N, 18))
        self.rows = tuple(np.zeros((1, N) + shape) for shape in ((3,), (3, 3), (3,), (3,)))

    def resolve(self, layout: str, r: Run, Y, h: float) -> int:
        """Contacts on Y (the method's state), in place: bodies touched, or −1 if the solver failed."""
        S = Y
        if layout != "matrix":
            r.decode(r.sys, Y, 0, *self.rows)
            S = matrix_rows(*(a[0] for a in self.rows), out=self.S)
        touched = 0
        for ground, geo in self.grounds:
            n = ground.resolve_matrix(self.scene, S, h, geo, self.kernel.contact)
            if n < 0:
                return -1
            touched += n
        if touched and layout != "matrix":
            Y[:] = encode(layout, from_matrix(S))
        return touched


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
    values = np.array([effect.force_at(t) for effect in data.functions], dtype=float).reshape(-1, 3)
    kernel.motion.dxdt(data.system, values, S, dS, kernel.motion.work(S.shape[0]))
    return matrix_parts(dS)
