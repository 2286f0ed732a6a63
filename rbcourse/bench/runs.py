"""One measured run of the work-precision benchmark: its record (Run), how it is timed (timed), and
our methods' runner (run_rbcourse).  The peers' runners (scipy, MuJoCo) are in peers.py; the sweep
and its reports in work_precision.py.

The error of a run is the rotation angle between its R(T) and the reference R(T):
    error = ∠(R_ref(T)ᵀ R(T))  (rad),  inf (DIVERGED) if the run blew up.
"""
from __future__ import annotations

import gc
import math
import time
from dataclasses import dataclass

import numpy as np

from ..methods import METHODS
from ..rotation import rotation_angle
from ..simulate import simulate
from ..trajectory import SimulationDiverged
from .problems import Problem

DIVERGED = math.inf


@dataclass
class Run:
    """One measured run."""
    problem: str
    tool: str            # "rbcourse", "scipy", "mujoco"
    method: str
    setting: float       # dt, or rtol
    steps: int
    seconds: float
    error: float         # rotation error at T (rad); inf if it diverged

    @property
    def label(self) -> str:
        return self.method if self.tool == "rbcourse" else f"{self.tool} {self.method}"

    @property
    def uses_exact_flow(self) -> bool:
        return self.tool == "rbcourse" and METHODS[self.method].uses_exact_flow


def timed(fn, repeats: int, min_total: float = 0.0, max_repeats: int = 100):
    """(median seconds, last result) of fn() over at least `repeats` runs, and more (up to
    max_repeats) until they add up to `min_total` seconds: a short run repeated for a while is
    not at the mercy of one busy moment of the machine.  As timeit does, the garbage collector
    is paused while runs are timed, so that a collection of the whole benchmark's objects is
    not charged to whichever run happened to trigger it."""
    times, out = [], None
    gc.collect()
    paused = gc.isenabled()
    gc.disable()
    try:
        while len(times) < repeats or (sum(times) < min_total and len(times) < max_repeats):
            t0 = time.perf_counter()
            out = fn()
            times.append(time.perf_counter() - t0)
    finally:
        if paused:
            gc.enable()
    return float(np.median(times)), out


def is_adaptive(method: str) -> bool:
    """Whether the method takes a tolerance (rtol) rather than a step size: its sweep is over rtol."""
    return bool(METHODS[method].options and "rtol" in METHODS[method].options)


def run_rbcourse(problem: Problem, method: str, setting: float, repeats: int, min_total: float = 0.0) -> Run:
    """One of our methods on the problem: setting is dt, or rtol (= atol, as the scipy peers) for an
    adaptive method, which then takes dt = T as its first trial step."""
    adaptive = is_adaptive(method)
    kwargs = dict(rtol=setting, atol=setting) if adaptive else {}      # as the scipy peers
    dt = problem.T if adaptive else setting

    def go():
        try:
            return simulate(problem.scene, problem.X0, problem.T, dt, method, record_every=10**9, **kwargs)
        except SimulationDiverged:
            return None
    _warm_up(problem, method, kwargs)
    seconds, traj = timed(go, repeats, min_total)
    error = DIVERGED if traj is None else float(rotation_angle(problem.reference_R(), traj.R[-1]))
    return Run(problem.name, "rbcourse", method, setting, 0 if adaptive else round(problem.T / dt), seconds, error)


_WARM: set = set()


def _warm_up(problem: Problem, method: str, kwargs: dict):
    """One short untimed run of the method on the problem, once per process: the first run of a method
    compiles its family (or loads it from numba's cache), which is not the cost of a step."""
    if (problem.name, method) not in _WARM:
        h = problem.T / 1000
        try:
            simulate(problem.scene, problem.X0, h, h, method, **kwargs)
        except SimulationDiverged:
            pass
        _WARM.add((problem.name, method))
