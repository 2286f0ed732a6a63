"""The throughput report's shared measuring: a step's cost by the difference method, and the helpers its
tables share.

difference_per_step ((fastest run of 2k steps − fastest run of k steps) / k, the run's fixed costs cancelling),
seconds_per_step (simulate()'s step timed so), TooSlow (a measurement over its cap), attempt (a cell that
broke says why), engine_name (the engine a run ran on), timed_run (a stepper as a timed run), fresh_python
(a fresh Python process running this rbcourse); REPEATS, MAX_STEPS and BUDGET, the runs' sizes, and
TARGET_RK4_NS, the free boxes' target in both tables.  Used by bench/throughput.py and bench/contact_rows.py.
"""
from __future__ import annotations

import gc
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from ..simulate import simulate

REPEATS = 3
MAX_STEPS = 8192        # runs of ≤ 2 × 8192 steps (16 s at 1 ms: euler's spinning boxes diverge near 38 s)
BUDGET = {True: 0.04, False: 0.6}   # seconds a run of k steps should take, quick or not
TARGET_RK4_NS = 40.0        # N bodies: ns per body-step, rk4


def engine_name(implementation: str) -> str:
    """'compiled' / 'interpreted' / … : the first word of traj.implementation."""
    return implementation.split(":")[0].split("(")[0].strip() or "?"


class TooSlow(RuntimeError):
    """A measurement that would take longer than it may (difference_per_step's max_seconds)."""


def difference_per_step(run, budget: float, min_steps: int = 2, max_steps: int = MAX_STEPS, repeats: int = REPEATS,
                        max_seconds: float | None = None) -> tuple[float, int]:
    """(seconds of one step, k) by the difference method, for run(k) → seconds of a run of k steps (after any
    warm-up): k doubles from min_steps (up to max_steps) until a run of k steps takes budget / 4; then `repeats`
    runs of 2k steps and of k steps, alternating, the garbage collector paused, and (fastest of 2k − fastest of
    k) / k.  The fastest run of each length: noise only ever adds time, so a burst of it in a run of k steps
    cannot make a step look cheaper (as a median of the differences can, when it falls on the shorter runs of two
    repeats of three).  max_seconds: fewer repeats (at least 1) when they would take longer, TooSlow when even
    one would.  A difference that is not positive (noise) is measured again over runs twice as long, up to
    max_steps (then TooSlow: no time to report, never a negative one)."""
    gc.collect()
    paused = gc.isenabled()
    gc.disable()
    try:
        k = max(1, min(min_steps, max_steps))
        took = run(k)
        while k < max_steps and took < budget / 4:
            k = min(2 * k, max_steps)
            took = run(k)
        if max_seconds is not None:
            if 3 * took > max_seconds:
                raise TooSlow(f"a run of {k:,} steps takes {took:.2g} s: one repeat would take > {max_seconds:g} s")
            repeats = max(1, min(repeats, int(max_seconds // (3 * took))))
        per = _fastest_difference(run, k, repeats)
        while not per > 0.0:                       # the runs differ by the timer's noise only: longer runs
            if k >= max_steps:
                raise TooSlow(f"runs of {k:,} and {2 * k:,} steps differ by noise only (a step is below the "
                              "timer's resolution at this size): no time to report")
            k = min(2 * k, max_steps)
            per = _fastest_difference(run, k, repeats)
    finally:
        if paused:
            gc.enable()
    return float(per), k


def _fastest_difference(run, k: int, repeats: int) -> float:
    """(fastest of `repeats` runs of 2k steps − fastest of as many runs of k steps) / k, the runs alternating."""
    twice, once = [], []
    for _ in range(repeats):
        twice.append(run(2 * k))
        once.append(run(k))
    return (min(twice) - min(once)) / k


def seconds_per_step(scene, X0, method: str, dt: float, budget: float, fast: bool = True,
                     max_steps: int = MAX_STEPS, repeats: int = REPEATS, min_steps: int = 2,
                     max_seconds: float | None = None) -> tuple[float, str, int]:
    """(wall time of one step, traj.implementation, k).  One warm-up run (it compiles, if need be); then
    difference_per_step: k doubles from min_steps (up to max_steps) until a run of k steps takes budget / 4;
    then (fastest of `repeats` runs of 2k steps − fastest of as many of k steps) / k, the garbage collector
    paused (steps k … 2k of a run from X0 are timed).  Only the last state is recorded (record_every = the
    run's length)."""
    def run(k):
        t0 = time.perf_counter()
        traj = simulate(scene, X0, k * dt, dt, method, record_every=k, fast=fast)
        return time.perf_counter() - t0, traj.implementation
    _, implementation = run(2)
    per, k = difference_per_step(lambda k: run(k)[0], budget, min_steps, max(max_steps, min_steps), repeats,
                                 max_seconds)
    return per, implementation, k


def attempt(fn):
    """fn() → (value, None), or (None, 'failed: ErrorType: message') when it raises."""
    try:
        return fn(), None
    except Exception as err:        # a benchmark reports what broke and goes on
        return None, f"failed: {type(err).__name__}: {' '.join(str(err).split())[:80]}"


def timed_run(go):
    """run(k) → seconds of go(k)."""
    def run(k):
        t0 = time.perf_counter()
        go(k)
        return time.perf_counter() - t0
    return run


def fresh_python(args, cwd: str, timeout: float, unset=(), **env):
    """subprocess.run([sys.executable, *args]) in a fresh process that imports this rbcourse (its folder first on
    PYTHONPATH), env's variables set and those named in unset removed: the CompletedProcess; RuntimeError with
    the exit code and the last line of stderr when it fails."""
    root = str(Path(__file__).resolve().parents[2])      # the folder holding this rbcourse
    env = dict(os.environ, **env, PYTHONPATH=os.pathsep.join(p for p in (root, os.environ.get("PYTHONPATH", "")) if p))
    for name in unset:
        env.pop(name, None)
    done = subprocess.run([sys.executable, *args], env=env, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        raise RuntimeError(f"exit code {done.returncode}: {last}")
    return done
