"""The kernel as the run sees it (simulate.py runs it): which kernel runs, a method's row resolved in it, the state
as the method's arrays and back, the record.

The kernel runs compiled (rbcourse.engine, numba) or as Python (engine/interpreted.py: the same files):
kernel(fast) is the one that runs; plan() resolves the method's row (methods.METHODS: its Stepping,
engine/plan.py) in it — its family's loop and step (engine/run.py: LOOPS), its table and options;
encode / decoder lay a State out as the method's arrays (a layout) and read it back; new_record holds the
recorded states; reason says why a state blew up; derivative is dX/dt of a State, for the walkthrough.
"""
from __future__ import annotations

import importlib
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from .engine.plan import COLUMNS, LAYOUTS
from .engine.system import evaluates_forces
from .rotation import quat_from_matrix, quat_rotate
from .rowwise import matrix_parts
from .state import State, to_matrix
from .support.language import say
from .trajectory import blow_up



class Kernel:
    """The kernel that runs: compiled (fast=True: rbcourse.engine, numba) or run as Python (engine/interpreted.py)."""

    def __init__(self, fast: bool):
        if fast:
            self.package = importlib.import_module("rbcourse.engine")
        else:
            from .engine import interpreted
            self.package = interpreted.package()
        self.fast = fast
        # the kernel's modules the run calls (engine/*.py, in the kernel that runs)
        (self.run, self.steps, self.motion, self.contact, self.grounds, self.adaptive, self.profiles, self.kicks,
         self.jit) = (importlib.import_module(f"{self.package.__name__}.{m}")
                      for m in ("run", "steps", "motion", "contact", "grounds", "adaptive", "profiles", "kicks", "jit"))

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
