"""The driver's Python side of a step: forces given as functions f(t), evaluated at the method's stage times,
and Ctrl-C held back while compiled code runs.

    stage_times(t, c, h)      t + c h (a stage at the step's end taken just before it)
    force_values(...)         the forces f(t) at t_k + c_i h for a chunk of steps, as the kernel reads them
                              (forces over time given as data, profiles.py: written by the kernel itself)
    SubstepForces             the same per attempt, for a method that picks its own substeps (adaptive)
    deferred_interrupt        Ctrl-C honoured between compiled calls, never inside numba
"""
from __future__ import annotations

import signal
import threading

import numpy as np


class deferred_interrupt:
    """Ctrl-C (SIGINT) held back while compiled code runs — or compiles: a KeyboardInterrupt raised inside
    numba's compiler (a ctypes callback of LLVM) kills the process with a segmentation fault — and raised
    as KeyboardInterrupt between calls (check()) or at the end.  Only when compiled (Python code stops
    anywhere), only in the main thread (the only one signals reach), and only over Python's own handler
    (another one is left as it is)."""

    def __init__(self, compiled: bool = True):
        self.compiled = compiled

    def __enter__(self):
        self.caught = False
        self.previous = None
        if self.compiled and threading.current_thread() is threading.main_thread():
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


def stage_times(t, c, h):
    """t + c h, the stage times of a step [t, t + h]; a stage at the step's end (c = 1) is taken just
    before it (the largest float below t + h): there the force is the one that acted during the step.
    A force that switches on a step boundary (a push that stops at t = 0.1 s) is then seen by every
    stage of a step as it was in that step, and a Runge–Kutta method keeps its order; for a smooth force
    the difference is one rounding of t."""
    times = np.asarray(t + c * h, dtype=float)
    return np.where(np.asarray(c) == 1.0, np.nextafter(times, -np.inf), times)


def force_values(functions, nodes, h: float, k0: int, k1: int, fill=None) -> np.ndarray:
    """The forces given as functions f(t), at t_k + c_i h (t_k = k h) for steps k0 … k1−1:
    (k1 − k0, stages, slots, 3) (forces_at, from the steps' starts)."""
    return forces_at(functions, nodes, np.arange(k0, k1) * h, h, fill)


def forces_at(functions, nodes, starts, h, fill=None) -> np.ndarray:
    """The forces over time at t + c_i h for steps [t, t + h] starting at `starts` (h a number, or one per step):
    (steps, stages, slots, 3).  A function f(t) is called here, once per distinct time (RK4's two midpoint stages
    share theirs; a step's end is often the next one's start); a force given as data (profiles.py: its slot left
    to the kernel) is written by fill(times, values) — the kernel's profiles.fill_profiles, compiled."""
    h = np.asarray(h, dtype=float)
    times = stage_times(np.asarray(starts, dtype=float)[:, None], np.asarray(nodes, dtype=float)[None, :],
                        h[:, None] if h.ndim else h)
    values = np.zeros(times.shape + (len(functions), 3))
    flat = times.ravel()
    for s, effect in enumerate(functions):
        if is_data(effect):
            continue
        seen = {}
        out = np.empty((len(flat), 3))
        for j, t in enumerate(flat.tolist()):
            f = seen.get(t)
            if f is None:
                f = seen[t] = effect.force_at(t)
            out[j] = f
        values[:, :, s] = out.reshape(times.shape + (3,))
    if fill is not None:
        fill(times, values)
    return values


def is_data(effect) -> bool:
    """Is this effect's force over time given as data (a profiles.Profile: the kernel evaluates it)?"""
    from .profiles import Profile
    return isinstance(getattr(effect, "force", None), Profile)


class SubstepForces:
    """A step of a method that picks its own substeps (adaptive) when forces are given as functions f(t): the
    method's own kernel pieces (adaptive.begin_step, then adaptive.attempt until the output step is done),
    with the forces evaluated here, in Python, before each attempt, at its stage times t + c_i sub (the attempt's
    t and sub are in opts[T_AT], opts[SUB_AT] once the previous attempt chose them).  adaptive: the kernel's
    module that runs (compiled, or run as Python)."""

    def __init__(self, functions, nodes, args, adaptive):
        self.functions, self.nodes, self.adaptive = functions, [float(c) for c in nodes], adaptive
        self.A, self.b, self.den, self.opts = args[3], args[4], args[5], args[6]
        self.values = np.zeros((len(self.nodes), len(functions), 3))

    def _at(self, t: float, sub: float, stages: int):
        for i in range(stages):
            ti = float(stage_times(t, self.nodes[i], sub))
            for s, effect in enumerate(self.functions):
                self.values[i, s] = effect.force_at(ti)

    def __call__(self, sys, Y, out, h, K, U, w):
        opts, adaptive = self.opts, self.adaptive
        self._at(opts[adaptive.STEPS] * h, 0.0, 1)                   # f at t, for K[0]
        adaptive.begin_step(opts, sys, self.values, Y, out, h, K, w)
        while True:
            self._at(float(opts[adaptive.T_AT]), float(opts[adaptive.SUB_AT]), len(self.nodes))
            if adaptive.attempt(self.A, self.b, self.den, opts, sys, self.values, out, h, K, U, w):
                return
