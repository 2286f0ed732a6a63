"""How fast the engines step: one body in every named scene, N free boxes, and what compiling costs.

    python -m rbcourse throughput [--bodies N] [--quick] [--no-peers] [--out DIR]

1. One body, every named scene (examples.py SCENES; many_bodies with n = 1), RK4 at the
   scene's dt: µs per step on the compiled engine (simulate(..., fast=True)), on the same engine run
   as Python (fast=False), and MuJoCo's RK4 on the same problem (bench/peers.py) where it has a comparable
   model (a free body, or a pivoted one under gravity).  Targets: ≤ 1 µs per step, ≤ 0.25× MuJoCo.
   Beside it, what an impulse costs (10⁵ kicks on a free box, rk4) against a compiled step: ≤ 2 steps
   (bench/impulse_rows.py).
2. N free boxes, N = 10 … 10⁵ (10⁶ too unless --quick, when it is estimated to take < 60 s; and
   --bodies N, when N is not among them): ns per body-step, free and under gravity, for rk4 and
   euler compiled (with a Ground too, N ≤ 1000) and rk4 run as Python (N ≤ 100).
   Targets: rk4 ≤ 40 ns, a first-order method ≤ 15 ns.
3. Contacts, many bodies, forces over time (beside MuJoCo's RK4 where it has the same scene): one box
   dropped on the ground (µs per step once it rests; target ≤ 0.25× MuJoCo), 10⁴ boxes resting on the
   ground (target ≤ 1 µs per body-step), 10⁴ free boxes (≤ 40 ns per body-step) and what memory
   bandwidth allows them (a triad's GB/s), the pushed box with its pulse (≤ 2 µs per step) and the warm
   demo's wall time in a fresh process (≤ 1.5 s).
4. Compile cost, each in a fresh process: the first simulate() of rk4 with an empty numba cache
   (a fresh NUMBA_CACHE_DIR: cold compile), the first again with that cache filled (warm), and
   `import rbcourse`.  Every family, a box on the ground and the demo: `throughput --compile` (compile_cost.py).
5. Which implementation ran (engine.jit.describe()).

Each time is measured in this run, never written in: a step's cost is (the fastest of 3 runs of 2k
steps − the fastest of 3 runs of k steps) / k, after one warm-up run, so that a run's fixed costs
(checks, compiling, recording) cancel.  A cell that could not be measured says why.

This file holds the command's entry (main), the report's assembly and tables 1, 2 and 4; table 3 is
bench/contact_rows.py, the measuring bench/timing.py, the boxes timed bench/box_scenes.py.
"""
from __future__ import annotations

import dataclasses
import inspect
import json
import os
import shutil
import sys
import tempfile
import time

import numpy as np

from ..support import checks
from ..effects import Gravity
from ..engine import jit
from ..scene import Scene
from ..examples import SCENES
from .box_scenes import MAX_BODIES, bench_ground, boxes
from .contact_rows import contact_table
from .impulse_rows import impulse_table
from .timing import (BUDGET, MAX_STEPS, REPEATS, TARGET_RK4_NS, attempt, engine_name, fresh_python,
                     seconds_per_step)

LADDER = (10, 100, 1000, 10**4, 10**5)
BIGGEST = 10**6         # run only without --quick, and only when estimated to take < BIG_BUDGET seconds
BIG_BUDGET = 60.0
PYTHON_MAX = 100        # the engine run as Python (fast=False, ~1000× slower): many-body runs stop here
GROUND_MAX = 1000       # with a Ground (its contacts are solved between steps): here

TARGET_US = 1.0             # one body, compiled: µs per step
TARGET_VS_MUJOCO = 0.25     # one body, compiled / MuJoCo RK4
TARGET_FIRST_ORDER_NS = 15.0


# ------------------------------------------------------------------ 1. one body, every named scene


def one_body_examples():
    """{name: Example} for every named scene, with one body (many_bodies(n=1))."""
    out = {}
    for name, factory in SCENES.items():
        ex = factory()
        if len(ex.scene.bodies) > 1 and "n" in inspect.signature(factory).parameters:
            ex = factory(n=1)
        out[name] = ex
    return out


def mujoco_problem(ex):
    """The example as a benchmark Problem MuJoCo can run (peers.mujoco_model), or None: a free
    body with no effect, or a pivoted body under gravity, given by ω(0) in body axes."""
    from ..pivot import Pivot
    from .problems import from_example
    kinds = [type(e) for e in ex.scene.effects]
    if ex.omega_body is None or len(ex.scene.bodies) != 1 or not set(kinds) <= {Gravity, Pivot}:
        return None
    if Gravity in kinds and Pivot not in kinds:
        return None
    return from_example(ex.name, ex.name, ex, 1.0)


def mujoco_seconds_per_step(ex, steps: int):
    """MuJoCo's RK4 on the example (peers.run_mujoco, median of REPEATS runs of `steps` steps at
    the example's dt): (seconds per step, None), or (None, why not)."""
    from . import peers
    if not peers.mujoco_installed():
        return None, "n/a (MuJoCo not installed)"
    problem = mujoco_problem(ex)
    if problem is None:
        from ..contact import Ground
        if any(isinstance(e, Ground) for e in ex.scene.effects):
            return None, "n/a here (its contacts are soft: the contacts table below compares it)"
        return None, "n/a (no comparable model)"
    problem = dataclasses.replace(problem, T=steps * ex.dt)
    run, why = attempt(lambda: peers.run_mujoco(problem, "RK4", ex.dt, REPEATS))
    if run is None:
        return None, why
    if not np.isfinite(run.error):
        return None, "MuJoCo diverged"
    return run.seconds / run.steps, None


def one_body_table(quick: bool, peers: bool) -> list[str]:
    budget, k_mujoco = BUDGET[quick], (2000 if quick else 20000)
    out = ["## One body, every named scene (rk4 at the scene's dt; µs per step)", "",
           f"Targets: compiled ≤ {TARGET_US:g} µs per step, and ≤ {TARGET_VS_MUJOCO:g}× MuJoCo's RK4. "
           f"(Fastest of {REPEATS} runs of 2k steps − fastest of {REPEATS} runs of k steps) / k, k ≤ {MAX_STEPS:,} "
           f"such that a run takes ≈ {budget * 1e3:g} ms; MuJoCo: median of {REPEATS} runs of {k_mujoco:,} steps.", "",
           "| scene | effects | compiled | ran on | as Python (fast=False) | MuJoCo RK4 | compiled / MuJoCo "
           f"| ≤ {TARGET_US:g} µs | ≤ {TARGET_VS_MUJOCO:g}× MuJoCo |",
           "|---|---|---|---|---|---|---|---|---|"]
    for name, ex in one_body_examples().items():
        effects = ", ".join(type(e).__name__ for e in ex.scene.effects) or "none"
        fast, why_fast = attempt(lambda: seconds_per_step(ex.scene, ex.X0, "rk4", ex.dt, budget, fast=True))
        slow, why_slow = attempt(lambda: seconds_per_step(ex.scene, ex.X0, "rk4", ex.dt, budget, fast=False))
        if peers:
            mj, why_mj = mujoco_seconds_per_step(ex, k_mujoco)
        else:
            mj, why_mj = None, "skipped (--no-peers)"
        c = fast[0] if fast else None
        ran = engine_name(fast[1]) if fast else "—"
        ratio = f"{c / mj:.2f}×" if c is not None and mj else "—"
        meets_us = ("yes" if c <= TARGET_US * 1e-6 else "no") if c is not None and ran == "compiled" else "—"
        meets_mj = ("yes" if c / mj <= TARGET_VS_MUJOCO else "no") if c is not None and mj and ran == "compiled" else "—"
        out.append(f"| {name} | {effects} | {_us(c, why_fast)} | {ran} | {_us(slow[0] if slow else None, why_slow)} "
                   f"| {_us(mj, why_mj)} | {ratio} | {meets_us} | {meets_mj} |")
    return out


def _us(seconds, why) -> str:
    return f"{seconds * 1e6:.3g}" if seconds is not None else why


# ------------------------------------------------------------------ 2. N free boxes


def many_rows(n: int, quick: bool, dt: float = 1e-3) -> list[str]:
    """The rows of N = n boxes: free and under gravity (and with a Ground, n ≤ GROUND_MAX)."""
    budget = BUDGET[quick]
    bodies, X0 = boxes(n)
    scenes = [("free", Scene(bodies), True), ("gravity", Scene(bodies, [Gravity()]), True)]
    ground = bench_ground()
    if ground is not None and n <= GROUND_MAX:
        scenes.append(("gravity + ground", Scene(bodies, [Gravity(), ground]), True))
    rows = []
    for label, scene, compiled in scenes:
        cells, meets = [], []
        for method, target in (("rk4", TARGET_RK4_NS), ("euler", TARGET_FIRST_ORDER_NS)):
            if not compiled:
                cells.append("—")
                continue
            got, why = attempt(lambda: seconds_per_step(scene, X0, method, dt, budget, fast=True))
            if got is None:
                cells.append(why)
                continue
            ns = got[0] / n * 1e9
            ran = engine_name(got[1])
            cells.append(f"{ns:.3g}" + ("" if ran == "compiled" else f" (ran on {ran})"))
            if ran == "compiled":
                meets.append(f"{method} ≤ {target:g}: {'yes' if ns <= target else 'no'}")
        if n <= PYTHON_MAX:
            got, why = attempt(lambda: seconds_per_step(scene, X0, "rk4", dt, budget, fast=False))
            cells.append(f"{got[0] / n * 1e9:.3g}" if got else why)
        else:
            cells.append("—")
        rows.append(f"| {n:,} | {label} | " + " | ".join(cells) + f" | {'; '.join(meets) or '—'} |")
    return rows


def many_table(n_extra: int, quick: bool) -> list[str]:
    sizes = sorted(set(LADDER) | {n_extra})
    out = ["## N free boxes (dt = 1 ms; ns per body-step)", "",
           f"Targets: rk4 ≤ {TARGET_RK4_NS:g} ns, a first-order method (euler) ≤ {TARGET_FIRST_ORDER_NS:g} ns per "
           f"body-step, compiled. As Python for N ≤ {PYTHON_MAX:,}; with a Ground for N ≤ {GROUND_MAX:,}.", "",
           "| N | scene | rk4 compiled | euler compiled | rk4 as Python (fast=False) | targets |",
           "|---|---|---|---|---|---|"]
    seconds = {}
    for n in sizes:
        t0 = time.perf_counter()
        out += many_rows(n, quick)
        seconds[n] = time.perf_counter() - t0
    if BIGGEST not in sizes:
        if quick:
            out.append(f"| {BIGGEST:,} | — | skipped (--quick) | | | |")
        else:
            base = LADDER[-1]
            estimate = seconds[base] * BIGGEST / base     # the compiled rows' cost grows as N
            if estimate < BIG_BUDGET:
                t0 = time.perf_counter()
                out += many_rows(BIGGEST, quick)
                out.append(f"| {BIGGEST:,} | | (took {time.perf_counter() - t0:.0f} s) | | | |")
            else:
                out.append(f"| {BIGGEST:,} | — | skipped: estimated {estimate:.0f} s ≥ {BIG_BUDGET:g} s | | | |")
    return out


# ------------------------------------------------------------------ 4. compile cost


_PROBE = """\
import json, time
t0 = time.perf_counter()
import rbcourse as rb
t_import = time.perf_counter() - t0
import numpy as np
body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
X0 = rb.State.from_velocities(body, np.zeros(3), np.eye(3), np.zeros(3), [0.01, 5.0, 0.01])
t0 = time.perf_counter()
traj = rb.simulate(body, X0, 0.01, 1e-3, "rk4")
t_first = time.perf_counter() - t0
t0 = time.perf_counter()
rb.simulate(body, X0, 0.01, 1e-3, "rk4")
t_second = time.perf_counter() - t0
print(json.dumps({"import": t_import, "first": t_first, "second": t_second, "implementation": traj.implementation}))
"""


def probe(cache_dir: str, timeout: float = 600.0) -> dict:
    """Run _PROBE in a fresh Python process with NUMBA_CACHE_DIR = cache_dir: its timings (s)."""
    done = fresh_python(["-c", _PROBE], cache_dir, timeout, NUMBA_CACHE_DIR=cache_dir)
    return json.loads(done.stdout.strip().splitlines()[-1])


def compile_table() -> list[str]:
    out = ["## Compile cost (rk4, one free box, 10 steps; each a fresh process)", "",
           "| process | numba cache | import rbcourse | first simulate() | second simulate() | ran on |",
           "|---|---|---|---|---|---|"]
    cache = tempfile.mkdtemp(prefix="rbcourse-numba-cache-")
    try:
        for label in ("cold", "warm"):
            got, why = attempt(lambda: probe(cache))
            state = "empty (fresh NUMBA_CACHE_DIR)" if label == "cold" else "filled by the cold process"
            if got is None:
                out.append(f"| {label} | {state} | {why} | | | |")
            else:
                out.append(f"| {label} | {state} | {got['import']:.2f} s | {got['first']:.2f} s | "
                           f"{got['second'] * 1e3:.2f} ms | {engine_name(got['implementation'])} |")
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    return out


# ------------------------------------------------------------------ the report


def load_average() -> str:
    """The 1-minute load average and the CPU count, e.g. '2.3 on 2 CPUs' ('?' where unknown)."""
    try:
        return f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs"
    except (AttributeError, OSError):
        return "?"


def main(n: int = 10000, quick: bool = False, peers: bool = True) -> str:
    """Measure the tables; return them as markdown.  n: an N of the many-body runs beside LADDER
    (2 … MAX_BODIES).  quick: shorter runs, no 10⁶ (well under a minute).  peers: MuJoCo too."""
    n = checks.integer("n", n, low=2, high=MAX_BODIES)
    for name, flag in (("quick", quick), ("peers", peers)):
        if not isinstance(flag, bool):
            raise ValueError(f"{name} must be True or False, got {flag!r}")
    t0, load0 = time.perf_counter(), load_average()
    out = ["# Throughput" + (" (quick: short runs)" if quick else ""), "",
           f"Implementation: {jit.describe()}", ""]
    out += one_body_table(quick, peers) + [""]
    out += impulse_table(quick) + [""]
    out += many_table(n, quick) + [""]
    out += contact_table(quick, peers) + [""]
    out += compile_table() + [""]
    out.append(f"Measured in {time.perf_counter() - t0:.0f} s (load average {load0} at the start, {load_average()} at the end: "
               f"other processes on the machine slow the runs); Python {sys.version.split()[0]}, numpy {np.__version__}.")
    return "\n".join(out) + "\n"
