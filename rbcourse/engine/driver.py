"""The Python side of a compiled run: a Scene and a State in, a Trajectory out.

    1. the scene becomes data (system.compile_scene), the state the method's arrays (encode);
    2. forces given as functions f(t) are evaluated here, in Python, at the times the method
       needs (t_k + c_i h for its stages c_i), a chunk of steps at a time, and passed in;
    3. the family's compiled loop (run.py) advances the chunk, recording into the trajectory's own arrays;
       impulses and contacts, when the scene has them, are applied between steps here.
"""
from __future__ import annotations

import signal
import threading
from typing import NamedTuple

import numpy as np

from ..integrators.tableaus import EULER, MIDPOINT, RK4, dop853
from ..rotation import quat_from_matrix, quat_rotate
from ..impulse import kick_due
from ..state import State, from_matrix, to_matrix
from ..trajectory import blow_up
from . import adaptive, contact, exact_flow, implicit, jit, motion, run, steps
from .motion import work
from .system import compile_scene


def _settings_as_floats(scene, settings: dict) -> np.ndarray:
    """A method's numerical settings as the floats its step reads (e.g. implicit_midpoint: none)."""
    return np.array([float(v) for v in settings.values()], dtype=float)


def _adaptive_opts(scene, settings: dict) -> np.ndarray:
    """adaptive: rtol, atol, and the run's own step-size state (engine/adaptive.py: one array per run)."""
    return adaptive.options(**settings)


class EngineMethod(NamedTuple):
    """A method of the compiled engine, as data: the kind of step (steps.py), the state it steps,
    its Butcher table, and how it finishes a step."""
    kind: int
    layout: str          # "matrix": S (N, 18) = [x, R, P, L];  "quat": Y (N, 13) = [x, q, P, L_b];
                         # "quat_world": Y (N, 13) = [x, q, P, L] (L world, Baraff's)
    table: object        # integrators.tableaus.Tableau (or a function giving it, built at first use)
    finish: int          # steps.NO_FINISH, PROJECT_R or NORMALIZE_Q
    nodes: tuple = ()    # the times t + c_i h its forces are evaluated at, if not its table's c
    scratch: object = 0  # work slots it needs in K beyond its table's stages (or a function of N, the bodies)
    opts: object = _settings_as_floats   # (scene, settings) -> the floats its step reads, once per run
    time_forces: bool = True             # are its stage times known before its step (forces f(t) evaluated ahead;
                                         # else per attempt, between compiled calls: SubstepForces)?
    of_settings: object = None           # settings -> (table, nodes), for a method whose table is an option
    supported: object = None             # scene -> '' or why this method cannot run it compiled

    def resolved(self, settings: dict) -> "EngineMethod":
        """This method with the table and nodes its settings choose (exact_splitting: its composition)."""
        if self.of_settings is None:
            return self
        table, nodes = self.of_settings(settings)
        return self._replace(table=table, nodes=tuple(nodes), of_settings=None)

    @property
    def layout_code(self) -> int:
        return LAYOUTS[self.layout]

    @property
    def family(self) -> tuple:
        """(its family's compiled loop, its family's step): a run compiles only these (run.py, steps.py)."""
        return FAMILIES[self.kind]

    @property
    def butcher(self):
        return self.table() if callable(self.table) else self.table

    @property
    def stage_times(self) -> np.ndarray:
        """The c_i of the times t + c_i h at which the method evaluates its forces."""
        nodes = self.nodes() if callable(self.nodes) else self.nodes
        return np.array(nodes, dtype=float) if len(nodes) else self.butcher.c

    def arguments(self, scene, settings: dict) -> tuple:
        """What the compiled loop and step take to know the method: kind, layout, finish, A, b, den,
        opts (its numerical settings and run state, as floats) — built once per run."""
        t = self.butcher
        return (self.kind, self.layout_code, self.finish, np.ascontiguousarray(t.A), np.ascontiguousarray(t.b),
                float(t.den), self.opts(scene, settings))


LAYOUTS = {"matrix": steps.MATRIX, "quat": steps.QUAT, "quat_world": steps.QUAT_WORLD}

FAMILIES = {
    steps.EXPLICIT_RK: (run.run_explicit, steps.explicit_step),
    steps.SYMPLECTIC_EULER: (run.run_geometric, steps.geometric_step),
    steps.SPLITTING: (run.run_geometric, steps.geometric_step),
    steps.RKMK4: (run.run_geometric, steps.geometric_step),
    steps.VARIATIONAL: (run.run_geometric, steps.geometric_step),
    steps.IMPLICIT_GYRO: (run.run_implicit, steps.implicit_step),
    steps.IMPLICIT_MIDPOINT: (run.run_implicit, steps.implicit_step),
    steps.ADAPTIVE: (run.run_error_controlled, steps.error_controlled_step),
    steps.EXACT_SPLITTING: (run.run_exact, steps.exact_step),
}

ENGINE_METHODS = {
    "euler": EngineMethod(steps.EXPLICIT_RK, "matrix", EULER, steps.NO_FINISH),
    "euler_project": EngineMethod(steps.EXPLICIT_RK, "matrix", EULER, steps.PROJECT_R),
    "quaternion_euler": EngineMethod(steps.EXPLICIT_RK, "quat_world", EULER, steps.NORMALIZE_Q),
    "quaternion_euler_body": EngineMethod(steps.EXPLICIT_RK, "quat", EULER, steps.NORMALIZE_Q),
    "rk4": EngineMethod(steps.EXPLICIT_RK, "quat", RK4, steps.NORMALIZE_Q),
    "implicit_gyro": EngineMethod(steps.IMPLICIT_GYRO, "matrix", EULER, steps.NO_FINISH, nodes=(0.0,)),
    "implicit_midpoint": EngineMethod(steps.IMPLICIT_MIDPOINT, "matrix", EULER, steps.NO_FINISH, nodes=(0.5,),
                                      scratch=implicit.midpoint_scratch),
    "symplectic_euler": EngineMethod(steps.SYMPLECTIC_EULER, "matrix", EULER, steps.NO_FINISH, nodes=(0.0,)),
    "splitting": EngineMethod(steps.SPLITTING, "matrix", MIDPOINT, steps.NO_FINISH, nodes=(0.0, 0.0, 1.0, 1.0)),
    "variational": EngineMethod(steps.VARIATIONAL, "matrix", MIDPOINT, steps.NO_FINISH, nodes=(0.0, 0.0, 1.0, 1.0)),
    "rkmk4": EngineMethod(steps.RKMK4, "matrix", RK4, steps.NO_FINISH),
    "exact_splitting": EngineMethod(steps.EXACT_SPLITTING, "matrix", RK4, steps.NO_FINISH, nodes=exact_flow.nodes({}),
                                    scratch=1, opts=exact_flow.options, of_settings=exact_flow.table_and_nodes,
                                    supported=exact_flow.exact_flow_supported),
    "adaptive": EngineMethod(steps.ADAPTIVE, "quat", dop853, steps.NO_FINISH, scratch=2, opts=_adaptive_opts,
                             nodes=lambda: tuple(dop853().c) + (1.0,), time_forces=False),
}

COLUMNS = {"matrix": (("x", 0, 3), ("R", 3, 12), ("P", 12, 15), ("L", 15, 18)),
           "quat": (("x", 0, 3), ("q", 3, 7), ("P", 7, 10), ("L", 10, 13)),
           "quat_world": (("x", 0, 3), ("q", 3, 7), ("P", 7, 10), ("L", 10, 13))}
CHUNK = 1 << 14          # steps per call when forces are functions of t (their values are evaluated per chunk)
WORK = 1 << 22           # body-steps per call at most (about a second): Ctrl-C is honoured between calls


class deferred_interrupt:
    """Ctrl-C (SIGINT) held back while compiled code runs — or compiles: a KeyboardInterrupt raised inside
    numba's compiler (a ctypes callback of LLVM) kills the process with a segmentation fault — and raised
    as KeyboardInterrupt between calls (check()) or at the end.  Only in the main thread (the only one
    signals reach), and only over Python's own handler (another one is left as it is)."""

    def __enter__(self):
        self.caught = False
        self.previous = None
        if jit.COMPILED and threading.current_thread() is threading.main_thread():   # Python code stops anywhere
            self.previous = signal.getsignal(signal.SIGINT)
            if self.previous is signal.default_int_handler:
                signal.signal(signal.SIGINT, self._hold)
            else:
                self.previous = None      # someone else's handler (or SIG_IGN): left as it is
        return self

    def _hold(self, signum, frame):
        self.caught = True

    def check(self):
        """Between two compiled calls: a Ctrl-C held back is raised now (KeyboardInterrupt)."""
        if self.caught:
            self.caught = False
            raise KeyboardInterrupt

    def __exit__(self, kind, value, tb):
        if self.previous is not None:
            signal.signal(signal.SIGINT, self.previous)
        if self.caught and kind is None:
            raise KeyboardInterrupt
        return False


def supports(method, scene) -> str:
    """'' if the compiled engine runs this method on this scene, else why not (one line)."""
    if method.name not in ENGINE_METHODS:
        return f"method {method.name!r} is not in the compiled engine yet"
    em = ENGINE_METHODS[method.name]
    why = em.supported(scene) if em.supported is not None else ""
    if why:
        return why
    return ""


def encode(layout: str, X: State) -> np.ndarray:
    """The engine's state (L about the rotation centre, N bodies) -> the method's arrays:
    S = [x, R, P, L] ("matrix"), Y = [x, q, P, L_b = Rᵀ L] ("quat"), Y = [x, q, P, L] ("quat_world")."""
    if layout == "matrix":
        return to_matrix(X)
    if layout not in COLUMNS:
        raise ValueError(f"layout must be one of {sorted(COLUMNS)}, got {layout!r}")
    q = quat_from_matrix(X.R)
    L = X.L if layout == "quat_world" else quat_rotate(q, X.L, inverse=True)
    return np.ascontiguousarray(np.concatenate([X.x, q, X.P, L], axis=1))


def decoder(layout: str):
    """The compiled decode of a layout: its arrays -> a record row (x, R, P, L)."""
    return {"matrix": run.decode_matrix, "quat": run.decode_quat, "quat_world": run.decode_quat_world}[layout]


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


def stage_times(t, c, h):
    """t + c h, the stage times of a step [t, t + h]; a stage at the step's end (c = 1) is taken just
    before it (the largest float below t + h): there the force is the one that acted during the step.
    A force that switches on a step boundary (a push that stops at t = 0.1 s) is then seen by every
    stage of a step as it was in that step, and a Runge–Kutta method keeps its order; for a smooth force
    the difference is one rounding of t."""
    times = np.asarray(t + c * h, dtype=float)
    return np.where(np.asarray(c) == 1.0, np.nextafter(times, -np.inf), times)


def force_values(functions, nodes, h: float, k0: int, k1: int) -> np.ndarray:
    """The forces given as functions f(t), at t_k + c_i h (t_k = k h) for steps k0 … k1−1:
    (k1 − k0, stages, slots, 3).  Each function is called once per distinct time (RK4's two midpoint
    stages share theirs; a step's end is often the next one's start)."""
    times = stage_times((np.arange(k0, k1) * h)[:, None], np.asarray(nodes, dtype=float)[None, :], h)
    values = np.zeros((k1 - k0, len(nodes), len(functions), 3))
    flat = times.ravel()
    for s, effect in enumerate(functions):
        seen = {}
        out = np.empty((len(flat), 3))
        for j, t in enumerate(flat.tolist()):
            f = seen.get(t)
            if f is None:
                f = seen[t] = effect.force_at(t)
            out[j] = f
        values[:, :, s] = out.reshape(k1 - k0, len(nodes), 3)
    return values


class SubstepForces:
    """A step of a method that picks its own substeps (adaptive) when forces are given as functions f(t): the
    method's own compiled pieces (adaptive.begin_step, then adaptive.attempt until the output step is done),
    with the forces evaluated here, in Python, before each attempt, at its stage times t + c_i sub (the attempt's
    t and sub are in opts[T_AT], opts[SUB_AT] once the previous attempt chose them)."""

    def __init__(self, functions, nodes, args):
        self.functions, self.nodes = functions, [float(c) for c in nodes]
        self.A, self.b, self.den, self.opts = args[3], args[4], args[5], args[6]
        self.values = np.zeros((len(self.nodes), len(functions), 3))

    def _at(self, t: float, sub: float, stages: int):
        for i in range(stages):
            ti = float(stage_times(t, self.nodes[i], sub))
            for s, effect in enumerate(self.functions):
                self.values[i, s] = effect.force_at(ti)

    def __call__(self, sys, Y, out, h, K, U, w):
        opts = self.opts
        self._at(opts[adaptive.STEPS] * h, 0.0, 1)                   # f at t, for K[0]
        adaptive.begin_step(opts, sys, self.values, Y, out, h, K, w)
        while True:
            self._at(float(opts[adaptive.T_AT]), float(opts[adaptive.SUB_AT]), len(self.nodes))
            if adaptive.attempt(self.A, self.b, self.den, opts, sys, self.values, out, h, K, U, w):
                return


def reason(layout: str, Y: np.ndarray) -> str:
    """Why the state Y is a blow-up (trajectory.blow_up on its named parts)."""
    return blow_up([(name, Y[:, a:b]) for name, a, b in COLUMNS[layout]])


class Outcome(NamedTuple):
    """What a compiled run returns to simulate: the record (rows used), and the blow-up if any."""
    record: Record
    rows: int
    bad_step: int        # the step (1-based) whose result blew up, or 0
    why: str


def simulate_compiled(scene, method, X: State, n: int, h: float, every: int, bar) -> Outcome:
    """n steps of the compiled method from X (engine coordinates); `bar` a progress bar (update(k))."""
    em = ENGINE_METHODS[method.name].resolved(method.settings)
    data = compile_scene(scene)
    sys, functions = data.system, data.functions
    decode = decoder(em.layout)       # (from Python, per row)
    Y = encode(em.layout, X)
    out = np.empty_like(Y)
    scratch = em.scratch(Y.shape[0]) if callable(em.scratch) else em.scratch
    K = np.empty((max(em.butcher.stages, len(em.stage_times)) + scratch,) + Y.shape)
    args = em.arguments(scene, method.settings)          # the method as data, once per run
    U = np.empty_like(Y)
    w = work(Y.shape[0])
    rec = new_record(X, n, every)
    row, k = 1, 0
    substeps = SubstepForces(functions, em.stage_times, args) if functions and not em.time_forces else None
    between = scene.has_events or scene.has_contacts or substeps is not None
    contacts = Contacts(scene, Y.shape[0]) if scene.has_contacts else None
    most = max(1, WORK // Y.shape[0])
    chunk = 1 if between else min(CHUNK if functions else max(n, 1), most)
    no_values = np.zeros((chunk, len(em.stage_times), 0, 3))
    if substeps is not None:                  # its own substep times: the forces are evaluated per attempt
        functions = ()
    with deferred_interrupt() as held:          # Ctrl-C: honoured between calls, never inside numba
        while k < n:
            held.check()
            k1 = min(n, k + chunk)
            values = force_values(functions, em.stage_times, h, k, k1) if functions else no_values
            if between:
                Y_good = Y
                Y, bad, why = _between_steps(scene, args, em, decode, sys, values, Y, out, h, k, K, U, w, contacts,
                                             substeps)
                if bad:
                    return _stopped(rec, row, k + 1, why, decode, sys, Y, h, k)
                k += 1
                if k % every == 0 or k == n:
                    decode(sys, Y, row, *rec[1:])
                    why = blow_up([(name, getattr(rec, name)[row]) for name in "xRPL"])
                    if why:
                        return _stopped(rec, row, k, why, decode, sys, Y_good, h, k - 1)
                    rec.t[row] = k * h
                    row += 1
                continue
            k_done, row, bad = em.family[0](args, sys, values, Y, out, h, k, k1, n, every, row, tuple(rec), K, U, w)
            bar.update(k_done - k)
            if bad:
                why = reason(em.layout, out) or blow_up([(name, getattr(rec, name)[row]) for name in "xRPL"])
                return _stopped(rec, row, k_done + 1, why, decode, sys, Y, h, k_done)
            k = k_done
    return Outcome(rec, row, 0, "")


def _stopped(rec, row, step, why, decode, sys, Y_good, h, k_good) -> Outcome:
    """A blow-up at `step`: the last good state (after k_good steps) recorded if it is not yet."""
    if rec.t[row - 1] != k_good * h:
        rec.t[row] = k_good * h
        decode(sys, Y_good, row, *rec[1:])
        row += 1
    return Outcome(rec, row, step, why)


def _between_steps(scene, args, em, decode, sys, values, Y, out, h, k, K, U, w, contacts, substeps=None):
    """One step with impulses before it and contacts after it (applied here, between compiled calls);
    substeps: the step of a method that evaluates forces f(t) per attempt (SubstepForces), if any."""
    t0, t1 = k * h, (k + 1) * h
    if scene.has_events and any(e.due(t0, t1) for e, _ in scene._impulses):
        S = encode("matrix", _state(decode, sys, Y))       # a copy: Y stays the last good state
        kick_due(scene._impulses, t0, t1, sys, S, motion)
        Y = S if em.layout == "matrix" else encode(em.layout, from_matrix(S))
    if em.kind == steps.ADAPTIVE and (scene.has_events or scene.has_contacts):
        args[-1][adaptive.SUB] = 0.0     # the state may change between steps: the substep is chosen again
    if substeps is not None:
        substeps(sys, Y, out, h, K, U, w)
    else:
        em.family[1](*args, sys, values[0], Y, out, h, K, U, w)
    why = reason(em.layout, out)
    if not why and contacts is not None:
        if contacts.resolve(em.layout, sys, out, h) < 0:
            return Y, True, "the contact solver failed (a contact system is not finite) on a state that is no longer physical"
        why = reason(em.layout, out)
    if why:
        return Y, True, why
    return np.ascontiguousarray(out).copy(), False, ""


class Contacts:
    """The scene's contacts (its Grounds), solved after each step on the engine's state S (N, 18), in place
    (contact.Ground.resolve_matrix: engine/contact.py, compiled or run as Python as this driver is).  A method on
    (x, q, P, L_b) or (x, q, P, L) has its state laid out as S for the solver, and back only when a body touched."""

    def __init__(self, scene, N: int):
        self.scene, self.grounds = scene, [(e, geo) for e, idx, geo in scene._contacts]
        self.S = np.zeros((N, 18))
        self.rows = tuple(np.zeros((1, N) + shape) for shape in ((3,), (3, 3), (3,), (3,)))

    def resolve(self, layout: str, sys, Y, h: float) -> int:
        """Contacts on Y (the method's state), in place: bodies touched, or −1 if the solver failed."""
        S = Y
        if layout != "matrix":
            decoder(layout)(sys, Y, 0, *self.rows)
            x, R, P, L = (a[0] for a in self.rows)
            S = self.S
            S[:, 0:3], S[:, 3:12], S[:, 12:15], S[:, 15:18] = x, R.reshape(-1, 9), P, L
        touched = 0
        for ground, geo in self.grounds:
            n = ground.resolve_matrix(self.scene, S, h, geo, contact)
            if n < 0:
                return -1
            touched += n
        if touched and layout != "matrix":
            Y[:] = encode(layout, from_matrix(S))
        return touched


def _state(decode, sys, Y) -> State:
    """The engine's State of the method's arrays Y."""
    N = Y.shape[0]
    x, R, P, L = np.zeros((1, N, 3)), np.zeros((1, N, 3, 3)), np.zeros((1, N, 3)), np.zeros((1, N, 3))
    decode(sys, Y, 0, x, R, P, L)
    return State.unchecked(x[0], R[0], P[0], L[0])


def derivative(scene, t: float, X: State):
    """dX/dt = (v, ω* R, F, τ) of the N bodies of X (engine coordinates: L about the rotation centre) at time t:
    motion.rates_matrix on the scene as data, forces given as functions f(t) evaluated at t.
    Returns v (N, 3), Ṙ (N, 3, 3), F (N, 3), τ (N, 3)."""
    data = compile_scene(scene)
    S = encode("matrix", X)
    dS = np.empty_like(S)
    values = np.array([effect.force_at(t) for effect in data.functions], dtype=float).reshape(-1, 3)
    motion.rates_matrix(data.system, values, S, dS, work(S.shape[0]))
    return dS[:, 0:3], dS[:, 3:12].reshape(-1, 3, 3), dS[:, 12:15], dS[:, 15:18]


def implementation() -> str:
    """Which implementation of the engine runs compiled methods in this process, and why."""
    return jit.describe()
