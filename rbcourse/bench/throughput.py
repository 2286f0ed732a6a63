"""How fast the engines step: one body in every named scene, N free boxes, and what compiling costs.

    python -m rbcourse throughput [--bodies N] [--quick] [--no-peers] [--out DIR]

1. One body, every named scene (workbook/examples.py SCENES; many_bodies with n = 1), RK4 at the
   scene's dt: µs per step on the compiled engine (simulate(..., fast=True)), on the same engine run
   as Python (fast=False), and MuJoCo's RK4 on the same problem (bench/peers.py) where it has a comparable
   model (a free body, or a pivoted one under gravity).  Targets: ≤ 1 µs per step, ≤ 0.25× MuJoCo.
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
   `import rbcourse`.
5. Which implementation ran (engine.jit.describe()).

Each time is measured in this run, never written in: a step's cost is the median over 3 repeats
of (run of 2k steps − run of k steps) / k, after one warm-up run, so that a run's fixed costs
(checks, compiling, recording) cancel.  A cell that could not be measured says why.
"""
from __future__ import annotations

import dataclasses
import gc
import inspect
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .. import checks
from ..body import RigidBody
from ..effects import Gravity
from ..engine import jit
from ..scene import Scene
from ..simulate import simulate
from ..state import State
from ..workbook.examples import SCENES

MAX_BODIES = 10**6      # the largest N (the command line's --bodies is checked against it)
LADDER = (10, 100, 1000, 10**4, 10**5)
BIGGEST = 10**6         # run only without --quick, and only when estimated to take < BIG_BUDGET seconds
BIG_BUDGET = 60.0
PYTHON_MAX = 100        # the engine run as Python (fast=False, ~1000× slower): many-body runs stop here
GROUND_MAX = 1000       # with a Ground (its contacts are solved between steps): here
REPEATS = 3
MAX_STEPS = 8192        # runs of ≤ 2 × 8192 steps (16 s at 1 ms: euler's spinning boxes diverge near 38 s)
BUDGET = {True: 0.04, False: 0.6}   # seconds a run of k steps should take, quick or not

TARGET_US = 1.0             # one body, compiled: µs per step
TARGET_VS_MUJOCO = 0.25     # one body, compiled / MuJoCo RK4
TARGET_RK4_NS = 40.0        # N bodies: ns per body-step, rk4
TARGET_FIRST_ORDER_NS = 15.0


# ------------------------------------------------------------------ measuring


def _engine(implementation: str) -> str:
    """'compiled' / 'interpreted' / … : the first word of traj.implementation."""
    return implementation.split(":")[0].split("(")[0].strip() or "?"


class TooSlow(RuntimeError):
    """A measurement that would take longer than it may (difference_per_step's max_seconds)."""


def difference_per_step(run, budget: float, min_steps: int = 2, max_steps: int = MAX_STEPS, repeats: int = REPEATS,
                        max_seconds: float | None = None) -> tuple[float, int]:
    """(median seconds of one step, k) by the difference method, for run(k) → seconds of a run of k steps
    (after any warm-up): k doubles from min_steps (up to max_steps) until a run of k steps takes budget / 4;
    then `repeats` times (run of 2k steps − run of k steps) / k, the garbage collector paused.  max_seconds:
    fewer repeats (at least 1) when they would take longer, TooSlow when even one would."""
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
        per = [(run(2 * k) - run(k)) / k for _ in range(repeats)]
    finally:
        if paused:
            gc.enable()
    return float(np.median(per)), k


def seconds_per_step(scene, X0, method: str, dt: float, budget: float, fast: bool = True,
                     max_steps: int = MAX_STEPS, repeats: int = REPEATS, min_steps: int = 2,
                     max_seconds: float | None = None) -> tuple[float, str, int]:
    """(median wall time of one step, traj.implementation, k).  One warm-up run (it compiles, if
    need be); then difference_per_step: k doubles from min_steps (up to max_steps) until a run of k steps
    takes budget / 4; then `repeats` times (run of 2k steps − run of k steps) / k, the garbage collector
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


def _attempt(fn):
    """fn() → (value, None), or (None, 'failed: ErrorType: message') when it raises."""
    try:
        return fn(), None
    except Exception as err:        # a benchmark reports what broke and goes on
        return None, f"failed: {type(err).__name__}: {' '.join(str(err).split())[:80]}"


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
        return None, "n/a (no comparable model)"
    problem = dataclasses.replace(problem, T=steps * ex.dt)
    run, why = _attempt(lambda: peers.run_mujoco(problem, "RK4", ex.dt, REPEATS))
    if run is None:
        return None, why
    if not np.isfinite(run.error):
        return None, "MuJoCo diverged"
    return run.seconds / run.steps, None


def one_body_table(quick: bool, peers: bool) -> list[str]:
    budget, k_mujoco = BUDGET[quick], (2000 if quick else 20000)
    out = ["## One body, every named scene (rk4 at the scene's dt; µs per step)", "",
           f"Targets: compiled ≤ {TARGET_US:g} µs per step, and ≤ {TARGET_VS_MUJOCO:g}× MuJoCo's RK4. "
           f"Median of {REPEATS}; runs of k steps, k ≤ {MAX_STEPS:,} such that a run takes ≈ {budget * 1e3:g} ms; "
           f"MuJoCo: runs of {k_mujoco:,} steps.", "",
           "| scene | effects | compiled | ran on | as Python (fast=False) | MuJoCo RK4 | compiled / MuJoCo "
           f"| ≤ {TARGET_US:g} µs | ≤ {TARGET_VS_MUJOCO:g}× MuJoCo |",
           "|---|---|---|---|---|---|---|---|---|"]
    for name, ex in one_body_examples().items():
        effects = ", ".join(type(e).__name__ for e in ex.scene.effects) or "none"
        fast, why_fast = _attempt(lambda: seconds_per_step(ex.scene, ex.X0, "rk4", ex.dt, budget, fast=True))
        slow, why_slow = _attempt(lambda: seconds_per_step(ex.scene, ex.X0, "rk4", ex.dt, budget, fast=False))
        if peers:
            mj, why_mj = mujoco_seconds_per_step(ex, k_mujoco)
        else:
            mj, why_mj = None, "skipped (--no-peers)"
        c = fast[0] if fast else None
        ran = _engine(fast[1]) if fast else "—"
        ratio = f"{c / mj:.2f}×" if c is not None and mj else "—"
        meets_us = ("yes" if c <= TARGET_US * 1e-6 else "no") if c is not None and ran == "compiled" else "—"
        meets_mj = ("yes" if c / mj <= TARGET_VS_MUJOCO else "no") if c is not None and mj and ran == "compiled" else "—"
        out.append(f"| {name} | {effects} | {_us(c, why_fast)} | {ran} | {_us(slow[0] if slow else None, why_slow)} "
                   f"| {_us(mj, why_mj)} | {ratio} | {meets_us} | {meets_mj} |")
    return out


def _us(seconds, why) -> str:
    return f"{seconds * 1e6:.3g}" if seconds is not None else why


# ------------------------------------------------------------------ 2. N free boxes


def boxes(n: int, seed: int = 0):
    """n random boxes (0.5–2 kg, sides 0.05–0.3 m) with random spins, on a grid 1 m up, built as
    arrays (RigidBody.boxes, a stacked State.from_velocities): (bodies, their State)."""
    rng = np.random.default_rng(seed)
    bodies = RigidBody.boxes(rng.uniform(0.5, 2.0, n), rng.uniform(0.05, 0.3, (n, 3)))
    i = np.arange(n)
    x = np.stack([i % 100, i // 100, np.ones(n)], axis=1).astype(float)
    R = np.broadcast_to(np.eye(3), (n, 3, 3))
    X0 = State.from_velocities(bodies, x, R, rng.normal(0.0, 0.1, (n, 3)), rng.normal(0.0, 3.0, (n, 3)))
    return bodies, X0


def _ground():
    try:
        from ..contact import Ground
    except ImportError:
        return None
    return Ground(height=0.0, restitution=0.5, friction=0.5)


def many_rows(n: int, quick: bool, dt: float = 1e-3) -> list[str]:
    """The rows of N = n boxes: free and under gravity (and with a Ground, n ≤ GROUND_MAX)."""
    budget = BUDGET[quick]
    bodies, X0 = boxes(n)
    scenes = [("free", Scene(bodies), True), ("gravity", Scene(bodies, [Gravity()]), True)]
    ground = _ground()
    if ground is not None and n <= GROUND_MAX:
        scenes.append(("gravity + ground", Scene(bodies, [Gravity(), ground]), True))
    rows = []
    for label, scene, compiled in scenes:
        cells, meets = [], []
        for method, target in (("rk4", TARGET_RK4_NS), ("euler", TARGET_FIRST_ORDER_NS)):
            if not compiled:
                cells.append("—")
                continue
            got, why = _attempt(lambda: seconds_per_step(scene, X0, method, dt, budget, fast=True))
            if got is None:
                cells.append(why)
                continue
            ns = got[0] / n * 1e9
            ran = _engine(got[1])
            cells.append(f"{ns:.3g}" + ("" if ran == "compiled" else f" (ran on {ran})"))
            if ran == "compiled":
                meets.append(f"{method} ≤ {target:g}: {'yes' if ns <= target else 'no'}")
        if n <= PYTHON_MAX:
            got, why = _attempt(lambda: seconds_per_step(scene, X0, "rk4", dt, budget, fast=False))
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


# ------------------------------------------------------------------ 3. contacts, many bodies, forces over time


N_CONTACT = 10**4           # the many-body cases of this section
MUJOCO_SMALL_N = 1000       # MuJoCo's many-box models when a model of N_CONTACT boxes is too slow to build or step
MUJOCO_MAX_BUILD = 20.0     # s: … its build estimated (or taking) longer than this
MUJOCO_MAX_STEP = 1.0       # s: … or one step of it longer than this
MAX_MEASURE = 20.0          # s: one ground measurement of N_CONTACT boxes (fewer repeats, or skipped, beyond)
CONTACT_BUDGET = {True: 0.2, False: 1.0}   # seconds a run of k steps should take, quick or not
DROP_DT = 1e-3
DROP_FROM = 0.2             # m: the dropped box's lowest point … its centre at DROP_FROM + half its height
LANDED = 1.0                # s: the dropped box has landed and rests by then; its steps are timed from here on
TRIAD_N = 10**7             # float64s per array of the bandwidth test
QUAT_STATE_BYTES = 2 * 13 * 8   # the rk4 state (x, q, P, L_b) of one body read once and written once
DEMO_TIMEOUT = 300.0

TARGET_GROUND_VS_MUJOCO = 0.25  # one box on the ground: ours / MuJoCo RK4
TARGET_RESTING_US = 1.0         # N_CONTACT boxes resting on the ground: µs per body-step
TARGET_PUSHED_US = 2.0          # the pushed box: µs per step
TARGET_DEMO_S = 1.5             # the warm demo's wall time


def dropped_box():
    """The slides' box (1 kg, 0.3 × 0.2 × 0.05 m) over Ground(0, e = 0.5, μ = 0.5) under gravity, its lowest
    point DROP_FROM up before the tilt (centre at DROP_FROM + 0.025), tilted by exp_so3((0.3, 0.2, 0)), spinning
    at ω = (1, −0.5, 2) rad/s: (body, scene, X0)."""
    from ..rotation import exp_so3
    body = RigidBody.box(1.0, (0.3, 0.2, 0.05))
    scene = Scene(body, [Gravity(), _ground()])
    X0 = State.from_velocities(body, [0.0, 0.0, DROP_FROM + 0.025], exp_so3(np.array([0.3, 0.2, 0.0])),
                               np.zeros(3), [1.0, -0.5, 2.0])
    return body, scene, X0


def _resting_state(bodies):
    """The bodies (boxes) at rest flat on the ground z = 0: centres half their height up, R = I, on boxes()'s
    1 m grid."""
    n = len(bodies)
    i = np.arange(n)
    half = np.array([b.size[2] for b in bodies], dtype=float) / 2
    x = np.stack([i % 100, i // 100, half], axis=1).astype(float)
    return State.from_velocities(bodies, x, np.broadcast_to(np.eye(3), (n, 3, 3)), np.zeros((n, 3)), np.zeros((n, 3)))


def _timed_run(go):
    """run(k) → seconds of go(k)."""
    def run(k):
        t0 = time.perf_counter()
        go(k)
        return time.perf_counter() - t0
    return run


def _mujoco_model(peers, bodies, ground: bool):
    """(model, seconds to build it): bodies as one MuJoCo RK4 model at DROP_DT, over the ground under gravity
    (peers.mujoco_ground_model) or free (no gravity, no contacts)."""
    masses = [b.mass for b in bodies]
    sizes = [b.size for b in bodies]
    t0 = time.perf_counter()
    if ground:
        model = peers.mujoco_ground_model(masses, sizes, "RK4", DROP_DT, friction=0.5, gravity=9.81)
    else:
        model = peers.mujoco_boxes_model(masses, sizes, "RK4", DROP_DT)
    return model, time.perf_counter() - t0


def mujoco_size(bodies, n_small: int | None = None) -> tuple[int, str]:
    """How many of the boxes MuJoCo's many-box rows run, and why (a note, '' for all of them): all len(bodies)
    when a model of them (over the ground: the larger) is estimated, from builds of n_small and 2 n_small boxes,
    to build in < MUJOCO_MAX_BUILD s, and then builds so and steps in < MUJOCO_MAX_STEP s; else n_small."""
    from . import peers
    n, n_small = len(bodies), n_small or MUJOCO_SMALL_N
    if n <= n_small:
        return n, ""
    _, built = _mujoco_model(peers, bodies[:n_small], True)
    _, built2 = _mujoco_model(peers, bodies[:2 * n_small], True)
    # MuJoCo's compile of free joints grows faster than N (here N^1.6 from 1000 to 2000 boxes, N^1.9 from 2000 to
    # 4000, N^2.3 from 1000 to 10⁴: 0.15 s to 31 s): the estimate takes the measured power, and at least 2.5, so
    # that a model too slow to build is not built to find out
    power = min(3.0, max(2.5, np.log2(max(built2, 1e-9) / max(built, 1e-9))))
    estimate = built * (n / n_small) ** power
    if estimate >= MUJOCO_MAX_BUILD:
        return n_small, (f"a model of {n:,} boxes would take ≈ {estimate:.0f} s to build ≥ {MUJOCO_MAX_BUILD:g} s "
                         f"(as N^{power:.1f}, from builds of {n_small:,} and {2 * n_small:,} boxes on a plane: "
                         f"{built:.2g} s and {built2:.2g} s)")
    big, built_big = _mujoco_model(peers, bodies, True)
    stepper = peers.mujoco_stepper(big, bodies, _resting_state(bodies))
    t0 = time.perf_counter()
    stepper(1)
    one = time.perf_counter() - t0
    if built_big < MUJOCO_MAX_BUILD and one < MUJOCO_MAX_STEP:
        return n, ""
    return n_small, (f"a model of {n:,} boxes on a plane built in {built_big:.1f} s (limit {MUJOCO_MAX_BUILD:g} s), "
                     f"its first step {one:.2g} s (limit {MUJOCO_MAX_STEP:g} s)")


def mujoco_many(bodies, X, ground: bool, budget: float, used: int):
    """MuJoCo RK4 on the first `used` boxes (over the ground, or free) from X: (seconds per body-step, None),
    or (None, why not)."""
    from . import peers
    if not peers.mujoco_installed():
        return None, "n/a (MuJoCo not installed)"

    def go():
        model, _ = _mujoco_model(peers, bodies[:used], ground)
        sub = X if used == len(bodies) else State.unchecked(X.x[:used], X.R[:used], X.P[:used], X.L[:used])
        stepper = peers.mujoco_stepper(model, bodies[:used], sub)
        stepper(2)
        per, _ = difference_per_step(_timed_run(stepper), budget, max_seconds=MAX_MEASURE)
        return per / used
    return _attempt(go)


_TRIAD = []


def _triad():
    """The triad a[i] = b[i] + s c[i] as a numba loop (compiled once per process)."""
    if not _TRIAD:
        import numba

        @numba.njit(nogil=True)
        def triad(a, b, c, s):
            for i in range(a.size):
                a[i] = b[i] + s * c[i]
        x = np.zeros(8)
        triad(x, x, x, 3.0)
        _TRIAD.append(triad)
    return _TRIAD[0]


def triad_bandwidth(n: int, repeats: int = 5) -> tuple[float, str]:
    """(bytes per second, how) of the triad a[:] = b + s·c over arrays of n float64s, best of `repeats`, one
    thread (as the engine): a compiled loop (numba) moves 3 × 8 B per element (b and c read, a written; the
    write-allocate read of a's cache lines, which would make it 32 B, not counted); without numba, numpy's
    two passes (a = s·c, then a += b) move 5 × 8 B."""
    a, b, c = np.zeros(n), np.full(n, 1.0), np.full(n, 2.0)
    if jit.COMPILED:
        triad = _triad()

        def go():
            triad(a, b, c, 3.0)
        moved, how = 3 * 8 * n, "a numba loop, 24 B per element"
    else:
        def go():
            np.multiply(c, 3.0, out=a)
            np.add(a, b, out=a)
        moved, how = 5 * 8 * n, "numpy (numba not compiling), two passes, 40 B per element"
    best = np.inf
    go()
    for _ in range(repeats):
        t0 = time.perf_counter()
        go()
        best = min(best, time.perf_counter() - t0)
    if not a[-1] == 7.0:
        raise RuntimeError(f"the triad computed {a[-1]!r}, not 7")
    return moved / best, how


def _cell(value, why, unit: str, scale: float = 1.0, ran: str = "compiled") -> str:
    if value is None:
        return why
    text = f"{value * scale:.3g} {unit}"
    return text if ran == "compiled" else f"{text} (ran on {ran})"


def _met(ok) -> str:
    return "—" if ok is None else ("yes" if ok else "no")


def _ours(scene, X0, budget, **kw):
    """Our rk4 at DROP_DT (seconds_per_step): ((seconds per step, the engine it ran on, k), None), or (None, why)."""
    got, why = _attempt(lambda: seconds_per_step(scene, X0, "rk4", DROP_DT, budget, fast=True, **kw))
    if got is None:
        return None, why
    return (got[0], _engine(got[1]), got[2]), None


def _speeds(v, w) -> str:
    return f"|v| = {np.linalg.norm(v):.1g} m/s, |ω| = {np.linalg.norm(w):.1g} rad/s"


def drop_row(quick: bool, peers: bool) -> tuple[str, list[str]]:
    """Case 1, the box dropped on the ground: (row, notes)."""
    budget, notes = CONTACT_BUDGET[quick], []
    body, scene, X0 = dropped_box()
    min_steps = int(np.ceil(LANDED / DROP_DT))
    ours, why = _ours(scene, X0, budget, min_steps=min_steps, max_seconds=MAX_MEASURE)
    if ours is not None:
        k = ours[2]

        def rest():
            traj = simulate(scene, X0, k * DROP_DT, DROP_DT, "rk4", record_every=k)
            return f"{_speeds(traj.velocity()[-1], traj.angular_velocity()[-1])}, centre at z = {traj.x[-1][2]:.4g} m"
        state, why_state = _attempt(rest)
        notes.append(f"the dropped box: steps {k:,} … {2 * k:,} timed (t = {k * DROP_DT:.3g} … "
                     f"{2 * k * DROP_DT:.3g} s); at t = {k * DROP_DT:.3g} s ours has {state or why_state}")
    mj, why_mj = None, "skipped (--no-peers)"
    if peers:
        from . import peers as peer
        if not peer.mujoco_installed():
            why_mj = "n/a (MuJoCo not installed)"
        else:
            def go():
                model = peer.mujoco_ground_model([body.mass], [body.size], "RK4", DROP_DT, friction=0.5)
                stepper = peer.mujoco_stepper(model, body, X0)
                per, k = difference_per_step(_timed_run(stepper), budget, min_steps=min_steps,
                                             max_steps=max(MAX_STEPS, min_steps), max_seconds=MAX_MEASURE)
                data = stepper(k)
                notes.append(f"MuJoCo at t = {k * DROP_DT:.3g} s (its timed steps {k:,} … {2 * k:,}): "
                             f"{_speeds(data.qvel[:3], data.qvel[3:6])}, centre at z = {data.qpos[2]:.4g} m")
                return per
            mj, why_mj = _attempt(go)
    ratio = ours[0] / mj if ours and mj else None
    row = (f"| one box dropped on the ground (rk4, dt = 1 ms; µs per step) | "
           f"{_cell(ours and ours[0], why, 'µs', 1e6, ours[1] if ours else 'compiled')} | "
           f"{_cell(mj, why_mj, 'µs', 1e6)} | "
           f"{f'{ratio:.3g}×' if ratio else '—'} | ≤ {TARGET_GROUND_VS_MUJOCO:g}× MuJoCo | "
           f"{_met(ratio <= TARGET_GROUND_VS_MUJOCO if ratio and ours[1] == 'compiled' else None)} |")
    return row, notes


def _mujoco_cell(mj, why, unit: str, scale: float, used, n: int) -> str:
    return _cell(mj, why, unit, scale) + (f" (N = {used:,})" if mj is not None and used != n else "")


def resting_row(quick: bool, peers: bool, bodies, mujoco_n) -> tuple[str, list[str]]:
    """Case 2, the boxes resting on the ground (MuJoCo: the first mujoco_n of them, or why not, a str): (row, notes)."""
    budget, notes, n = CONTACT_BUDGET[quick], [], len(bodies)
    X0 = _resting_state(bodies)
    scene = Scene(bodies, [Gravity(), _ground()])
    ours, why = _ours(scene, X0, budget, max_seconds=MAX_MEASURE)
    per = ours[0] / n if ours else None
    mj, why_mj = (None, mujoco_n) if isinstance(mujoco_n, str) else mujoco_many(bodies, X0, True, budget, mujoco_n)
    ratio = per / mj if per and mj else None
    ok = per <= TARGET_RESTING_US * 1e-6 if per is not None and ours[1] == "compiled" else None
    mj_cell = _mujoco_cell(mj, why_mj, "µs", 1e6, mujoco_n, n)
    row = (f"| {n:,} boxes resting on the ground (rk4, dt = 1 ms; µs per body-step) | "
           f"{_cell(per, why, 'µs', 1e6, ours[1] if ours else 'compiled')} | {mj_cell} | "
           f"{f'{ratio:.3g}×' if ratio else '—'} | ≤ {TARGET_RESTING_US:g} µs per body-step | {_met(ok)} |")
    return row, notes


def free_rows(quick: bool, peers: bool, n: int, mujoco_n) -> tuple[list[str], list[str]]:
    """Case 3, n free boxes (boxes(n); MuJoCo: the first mujoco_n of them, or why not, a str), and the memory
    limit: (rows, notes)."""
    budget, notes = CONTACT_BUDGET[quick], []
    bodies, X0 = boxes(n)
    ours, why = _ours(Scene(bodies), X0, budget)
    per = ours[0] / n if ours else None
    ran = ours[1] if ours else "compiled"
    mj, why_mj = (None, mujoco_n) if isinstance(mujoco_n, str) else mujoco_many(bodies, X0, False, budget, mujoco_n)
    ratio = per / mj if per and mj else None
    ok = per <= TARGET_RK4_NS * 1e-9 if per is not None and ran == "compiled" else None
    mj_cell = _mujoco_cell(mj, why_mj, "ns", 1e9, mujoco_n, n)
    rows = [f"| {n:,} free boxes (rk4, no gravity, dt = 1 ms; ns per body-step) | {_cell(per, why, 'ns', 1e9, ran)} | "
            f"{mj_cell} | {f'{ratio:.3g}×' if ratio else '—'} | ≤ {TARGET_RK4_NS:g} ns per body-step | "
            f"{_met(ok)} |"]
    bw, why_bw = _attempt(lambda: triad_bandwidth(TRIAD_N))
    if bw is None:
        rows.append(f"| {n:,} free boxes / the memory limit | {why_bw} | — | — | — | — |")
        return rows, notes
    limit = QUAT_STATE_BYTES / bw[0]
    small, why_small = _attempt(lambda: triad_bandwidth(13 * n, repeats=50))
    rows.append(f"| {n:,} free boxes / the memory limit ({QUAT_STATE_BYTES} B per body-step at the triad's "
                f"{bw[0] / 1e9:.3g} GB/s = {limit * 1e9:.3g} ns) | {_cell(per, why, 'ns', 1e9, ran)} | — | "
                f"{f'{per / limit:.3g}× the limit' if per else '—'} | — | — |")
    notes.append(f"memory limit: the triad a[:] = b + s·c over {TRIAD_N:.0e} float64s per array, best of 5 ({bw[1]}; "
                 f"write-allocate not counted): {bw[0] / 1e9:.3g} GB/s; an rk4 step reads and writes each body's "
                 f"13-float state (x, q, P, L_b) at least once: {QUAT_STATE_BYTES} B per body-step.  At N = {n:,} "
                 f"that state is {13 * 8 * n / 1e6:.2g} MB, which caches can hold: the same triad over {13 * n:,} "
                 "float64s (the state's size) runs at "
                 + (f"{small[0] / 1e9:.3g} GB/s" if small else why_small))
    return rows, notes


def demo_seconds(timeout: float = DEMO_TIMEOUT) -> float:
    """The wall time of `python -m rbcourse demo --out TMP` in a fresh process, the second of two runs (the
    first warms numba's cache and the files' folder)."""
    root = str(Path(__file__).resolve().parents[2])
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (root, os.environ.get("PYTHONPATH", "")) if p))
    with tempfile.TemporaryDirectory(prefix="rbcourse-demo-") as folder:
        took = None
        for _ in range(2):
            t0 = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "rbcourse", "demo", "--out", str(Path(folder) / "out")],
                                  env=env, cwd=folder, capture_output=True, text=True, timeout=timeout)
            took = time.perf_counter() - t0
            if done.returncode != 0:
                last = (done.stderr.strip().splitlines() or ["no output"])[-1]
                raise RuntimeError(f"exit code {done.returncode}: {last}")
    return took


def pushed_rows(quick: bool) -> tuple[list[str], list[str]]:
    """Case 4, the pushed box and the warm demo: (rows, notes)."""
    from ..workbook.examples import pushed_box
    ex = pushed_box()
    forces = [getattr(e, "force", None) for e in ex.scene.effects]
    kind = ", ".join(f"{type(f).__module__}.{type(f).__qualname__}" for f in forces if f is not None) or "none"
    got, why = _attempt(lambda: seconds_per_step(ex.scene, ex.X0, ex.method, ex.dt, BUDGET[quick], fast=True))
    ran = _engine(got[1]) if got else "compiled"
    ok = got[0] <= TARGET_PUSHED_US * 1e-6 if got and ran == "compiled" else None
    rows = [f"| the pushed box ({ex.method}, dt = {ex.dt * 1e3:g} ms, its force a {kind.rsplit('.', 1)[-1]}; µs per "
            f"step) | {_cell(got and got[0], why, 'µs', 1e6, ran)} | n/a (a force at a body point, on for 0.1 s: "
            f"MuJoCo would need Python between steps) | — | ≤ {TARGET_PUSHED_US:g} µs | {_met(ok)} |"]
    notes = [f"the pushed box's force ran as {kind} (type(scene.effects[0].force))"
             + (f"; {got[2]:,}-step runs: steps {got[2]:,} … {2 * got[2]:,} timed, the push lasting the first "
                f"{round(0.1 / ex.dt):,}" if got else "")]
    demo, why_demo = _attempt(demo_seconds)
    rows.append(f"| the warm demo: `python -m rbcourse demo` (a fresh process, its second run; s) | "
                f"{_cell(demo, why_demo, 's')} | — | — | ≤ {TARGET_DEMO_S:g} s | "
                f"{_met(demo <= TARGET_DEMO_S if demo is not None else None)} |")
    return rows, notes


def contact_table(quick: bool, peers: bool) -> list[str]:
    out = ["## Contacts, many bodies, forces over time", "",
           "Each beside MuJoCo's RK4 where it has the same scene: the same bodies, start and step. Its contacts are "
           "soft (default solref/solimp, condim 3, friction 0.5, box–plane pairs only), ours are impulses: the "
           "scenes match in bodies, start and step, not in contact model. Times per step by the difference method "
           f"(median of {REPEATS} of (run of 2k steps − run of k steps) / k, runs of ≈ "
           f"{CONTACT_BUDGET[quick] * 1e3:g} ms or more), for ours and MuJoCo alike.", "",
           "| case | ours | MuJoCo | ratio | target | met |",
           "|---|---|---|---|---|---|"]
    notes, t0 = [], time.perf_counter()
    n = N_CONTACT
    bodies, _ = boxes(n)
    if not peers:
        mujoco_n = "skipped (--no-peers)"
    else:
        from . import peers as peer
        if not peer.mujoco_installed():
            mujoco_n = "n/a (MuJoCo not installed)"
        else:
            got, why = _attempt(lambda: mujoco_size(bodies))
            mujoco_n = why if got is None else got[0]
            if got and got[1]:
                notes.append(f"N = {got[0]:,} for MuJoCo's many-box rows: {got[1]}; their ratios are per body-step")
    took = {"MuJoCo's size": time.perf_counter() - t0}
    for label, make in (("dropped box", lambda: drop_row(quick, peers)),
                        ("resting boxes", lambda: resting_row(quick, peers, bodies, mujoco_n)),
                        ("free boxes and bandwidth", lambda: free_rows(quick, peers, n, mujoco_n)),
                        ("pushed box and demo", lambda: pushed_rows(quick))):
        t1 = time.perf_counter()
        rows, more = make()
        took[label] = time.perf_counter() - t1
        out += [rows] if isinstance(rows, str) else rows
        notes += more
    notes.append(f"this section took {time.perf_counter() - t0:.0f} s ("
                 + ", ".join(f"{label} {seconds:.1f} s" for label, seconds in took.items()) + ")")
    out += [""] + [f"- {line}" for line in notes]
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
    root = str(Path(__file__).resolve().parents[2])      # the folder holding this rbcourse
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir,
               PYTHONPATH=os.pathsep.join(p for p in (root, os.environ.get("PYTHONPATH", "")) if p))
    done = subprocess.run([sys.executable, "-c", _PROBE], env=env, cwd=cache_dir, capture_output=True, text=True,
                          timeout=timeout)
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        raise RuntimeError(f"exit code {done.returncode}: {last}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def compile_table() -> list[str]:
    out = ["## Compile cost (rk4, one free box, 10 steps; each a fresh process)", "",
           "| process | numba cache | import rbcourse | first simulate() | second simulate() | ran on |",
           "|---|---|---|---|---|---|"]
    cache = tempfile.mkdtemp(prefix="rbcourse-numba-cache-")
    try:
        for label in ("cold", "warm"):
            got, why = _attempt(lambda: probe(cache))
            state = "empty (fresh NUMBA_CACHE_DIR)" if label == "cold" else "filled by the cold process"
            if got is None:
                out.append(f"| {label} | {state} | {why} | | | |")
            else:
                out.append(f"| {label} | {state} | {got['import']:.2f} s | {got['first']:.2f} s | "
                           f"{got['second'] * 1e3:.2f} ms | {_engine(got['implementation'])} |")
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    return out


# ------------------------------------------------------------------ the report


def _load() -> str:
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
    t0, load0 = time.perf_counter(), _load()
    out = ["# Throughput" + (" (quick: short runs)" if quick else ""), "",
           f"Implementation: {jit.describe()}", ""]
    out += one_body_table(quick, peers) + [""]
    out += many_table(n, quick) + [""]
    out += contact_table(quick, peers) + [""]
    out += compile_table() + [""]
    out.append(f"Measured in {time.perf_counter() - t0:.0f} s (load average {load0} at the start, {_load()} at the end: "
               f"other processes on the machine slow the runs); Python {sys.version.split()[0]}, numpy {np.__version__}.")
    return "\n".join(out) + "\n"
