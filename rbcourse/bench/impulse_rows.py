"""The throughput report's impulses: what a kick costs beside a compiled step (one free box, rk4, dt = 1 ms).

An impulse is applied inside the compiled loop, at its own time (engine/kicks.py): the step that holds it is split
there, so a kick inside a step costs the method's step once more (its two pieces) and the kick itself; a kick on a
step boundary splits nothing.  Measured here as (a run of n steps with I impulses − the same run without) / I,
each the fastest of REPEATS runs, beside a compiled step's cost (timing.seconds_per_step).  Target: an impulse
costs ≤ TARGET_STEPS compiled steps.

    python -m rbcourse throughput          10⁵ impulses (10⁴ with --quick)
"""
from __future__ import annotations

import time

import numpy as np

from ..body import RigidBody
from ..impulse import Impulse
from ..scene import Scene
from ..simulate import simulate
from ..state import State
from .timing import BUDGET, REPEATS, attempt, engine_name, seconds_per_step

TARGET_STEPS = 2.0      # an impulse: at most this many compiled steps' time
DT = 1e-3
EVERY = 4               # steps between two impulses


def kicked_box(impulses: int, inside: bool):
    """The slides' box spinning, free, and `impulses` kicks one every EVERY steps: at the middle of a step (inside)
    or on a step boundary.  (box, X0, the scene with the kicks, the number of steps)."""
    box = RigidBody.box(1.0, (0.3, 0.2, 0.05))
    X0 = State.from_velocities(box, np.zeros(3), np.eye(3), np.zeros(3), [0.01, 5.0, 0.01])
    steps = EVERY * impulses
    times = (np.arange(impulses) * EVERY + (1.5 if inside else 1.0)) * DT
    kicks = [Impulse((0.1, 0.05, 0.0), (0.0, 0.0, 1e-3), float(t)) for t in times]
    return box, X0, Scene(box, kicks), steps


def seconds_per_impulse(impulses: int, inside: bool, repeats: int = REPEATS) -> tuple[float, str]:
    """(seconds an impulse adds to a run, traj.implementation): the fastest of `repeats` runs with the kicks minus
    the fastest of as many without, over the number of kicks (after one warm-up run of each)."""
    box, X0, scene, steps = kicked_box(impulses, inside)

    def fastest(s):
        took = []
        for _ in range(repeats + 1):                        # the first a warm-up (it may compile): not kept
            t0 = time.perf_counter()
            traj = simulate(s, X0, steps * DT, DT, "rk4", record_every=steps)
            took.append(time.perf_counter() - t0)
        return min(took[1:]), traj.implementation
    with_kicks, implementation = fastest(scene)
    without, _ = fastest(box)
    return (with_kicks - without) / impulses, implementation


def impulse_table(quick: bool, impulses: int | None = None) -> list[str]:
    """The table's lines: a compiled step, an impulse inside a step, an impulse on a step boundary (impulses: how
    many in a run; 10⁵, 10⁴ quick)."""
    impulses = impulses or (10**4 if quick else 10**5)
    box, X0, _, _ = kicked_box(1, True)
    step, why_step = attempt(lambda: seconds_per_step(box, X0, "rk4", DT, BUDGET[quick]))
    out = ["## Impulses (one free box, rk4, dt = 1 ms; µs)", "",
           f"Target: an impulse costs ≤ {TARGET_STEPS:g} compiled steps. (Run of {EVERY * impulses:,} steps with "
           f"{impulses:,} impulses, one every {EVERY} steps − the same run without) / {impulses:,}, each the fastest "
           f"of {REPEATS}; a step: as in the one-body table.", "",
           "| what | µs | compiled steps | ran on | ≤ target |", "|---|---|---|---|---|"]
    if step is None:
        out.append(f"| a compiled step | {why_step} | | | |")
    else:
        out.append(f"| a compiled step | {step[0] * 1e6:.3g} | 1 | {engine_name(step[1])} | |")
    for label, inside in (("an impulse inside a step (the step split at it)", True),
                          ("an impulse on a step boundary", False)):
        got, why = attempt(lambda: seconds_per_impulse(impulses, inside))
        if got is None:
            out.append(f"| {label} | {why} | | | |")
            continue
        steps = got[0] / step[0] if step else None
        ran = engine_name(got[1])
        meets = ("yes" if steps <= TARGET_STEPS else "no") if steps is not None and ran == "compiled" else "—"
        out.append(f"| {label} | {got[0] * 1e6:.3g} | {'—' if steps is None else f'{steps:.2f}'} | {ran} | {meets} |")
    return out
