"""The throughput report's section "Contacts, many bodies, forces over time" (contact_table), beside MuJoCo's
RK4 where it has the same scene:

1. one box dropped on the ground, timed once it rests (drop_row; target ≤ 0.25× MuJoCo),
2. N_CONTACT boxes resting on the ground (resting_row; ≤ 1 µs per body-step),
3. N_CONTACT free boxes and what memory bandwidth allows them, a triad's GB/s (free_rows; ≤ 40 ns per
   body-step),
4. the pushed box with its pulse (≤ 2 µs per step) and the warm demo's wall time in a fresh process
   (pushed_rows, demo_seconds; ≤ 1.5 s).

MuJoCo's many-box rows run all N_CONTACT boxes, or MUJOCO_SMALL_N of them when a model of all is too slow to
build or step (mujoco_size).  Times by the difference method (bench/timing.py), for ours and MuJoCo alike.
"""
from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from ..effects import Gravity
from ..engine import jit
from ..scene import Scene
from ..simulate import simulate
from ..state import State
from .box_scenes import bench_ground, boxes, dropped_box, resting_state
from .timing import (BUDGET, MAX_STEPS, REPEATS, TARGET_RK4_NS, attempt, difference_per_step, engine_name,
                     fresh_python, seconds_per_step, timed_run)

N_CONTACT = 10**4           # the many-body cases of this section
MUJOCO_SMALL_N = 1000       # MuJoCo's many-box models when a model of N_CONTACT boxes is too slow to build or step
MUJOCO_MAX_BUILD = 20.0     # s: … its build estimated (or taking) longer than this
MUJOCO_MAX_STEP = 1.0       # s: … or one step of it longer than this
MAX_MEASURE = 20.0          # s: one ground measurement of N_CONTACT boxes (fewer repeats, or skipped, beyond)
CONTACT_BUDGET = {True: 0.2, False: 1.0}   # seconds a run of k steps should take, quick or not
DROP_DT = 1e-3
LANDED = 1.0                # s: the dropped box has landed and rests by then; its steps are timed from here on
TRIAD_N = 10**7             # float64s per array of the bandwidth test
QUAT_STATE_BYTES = 2 * 13 * 8   # the rk4 state (x, q, P, L_b) of one body read once and written once
DEMO_TIMEOUT = 300.0

TARGET_GROUND_VS_MUJOCO = 0.25  # one box on the ground: ours / MuJoCo RK4
TARGET_RESTING_US = 1.0         # N_CONTACT boxes resting on the ground: µs per body-step
TARGET_PUSHED_US = 2.0          # the pushed box: µs per step
TARGET_DEMO_S = 1.5             # the warm demo's wall time


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
    stepper = peers.mujoco_stepper(big, bodies, resting_state(bodies))
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
        per, _ = difference_per_step(timed_run(stepper), budget, max_seconds=MAX_MEASURE)
        return per / used
    return attempt(go)


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
    got, why = attempt(lambda: seconds_per_step(scene, X0, "rk4", DROP_DT, budget, fast=True, **kw))
    if got is None:
        return None, why
    return (got[0], engine_name(got[1]), got[2]), None


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
        state, why_state = attempt(rest)
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
                per, k = difference_per_step(timed_run(stepper), budget, min_steps=min_steps,
                                             max_steps=max(MAX_STEPS, min_steps), max_seconds=MAX_MEASURE)
                data = stepper(k)
                notes.append(f"MuJoCo at t = {k * DROP_DT:.3g} s (its timed steps {k:,} … {2 * k:,}): "
                             f"{_speeds(data.qvel[:3], data.qvel[3:6])}, centre at z = {data.qpos[2]:.4g} m")
                return per
            mj, why_mj = attempt(go)
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
    X0 = resting_state(bodies)
    scene = Scene(bodies, [Gravity(), bench_ground()])
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
    bw, why_bw = attempt(lambda: triad_bandwidth(TRIAD_N))
    if bw is None:
        rows.append(f"| {n:,} free boxes / the memory limit | {why_bw} | — | — | — | — |")
        return rows, notes
    limit = QUAT_STATE_BYTES / bw[0]
    small, why_small = attempt(lambda: triad_bandwidth(13 * n, repeats=50))
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


DEMO_WARM_RUNS = 3              # the warm demo: its best of this many runs after the first
clock = time.perf_counter       # the warm demo's clock (a test gives its own)


def demo_seconds(timeout: float = DEMO_TIMEOUT) -> float:
    """The wall time of `python -m rbcourse demo --out TMP` in a fresh process: the best of DEMO_WARM_RUNS runs
    after a first one, which warms numba's cache, the files' folder and Python's bytecode — as on a newcomer's
    machine: PYTHONDONTWRITEBYTECODE, which a CI image may set, is unset for these runs (with it, every run
    compiles rbcourse's ~80 modules from their source again: some 0.1-0.2 s)."""
    with tempfile.TemporaryDirectory(prefix="rbcourse-demo-") as folder:
        took = []
        for _ in range(1 + DEMO_WARM_RUNS):
            t0 = clock()
            fresh_python(["-m", "rbcourse", "demo", "--out", str(Path(folder) / "out")], folder, timeout,
                         unset=("PYTHONDONTWRITEBYTECODE",))
            took.append(clock() - t0)
    return min(took[1:])


def pushed_rows(quick: bool) -> tuple[list[str], list[str]]:
    """Case 4, the pushed box and the warm demo: (rows, notes)."""
    from ..examples import pushed_box
    ex = pushed_box()
    forces = [getattr(e, "force", None) for e in ex.scene.effects]
    kind = ", ".join(f"{type(f).__module__}.{type(f).__qualname__}" for f in forces if f is not None) or "none"
    got, why = attempt(lambda: seconds_per_step(ex.scene, ex.X0, ex.method, ex.dt, BUDGET[quick], fast=True))
    ran = engine_name(got[1]) if got else "compiled"
    ok = got[0] <= TARGET_PUSHED_US * 1e-6 if got and ran == "compiled" else None
    rows = [f"| the pushed box ({ex.method}, dt = {ex.dt * 1e3:g} ms, its force a {kind.rsplit('.', 1)[-1]}; µs per "
            f"step) | {_cell(got and got[0], why, 'µs', 1e6, ran)} | n/a (a force at a body point, on for 0.1 s: "
            f"MuJoCo would need Python between steps) | — | ≤ {TARGET_PUSHED_US:g} µs | {_met(ok)} |"]
    notes = [f"the pushed box's force ran as {kind} (type(scene.effects[0].force))"
             + (f"; {got[2]:,}-step runs: steps {got[2]:,} … {2 * got[2]:,} timed, the push lasting the first "
                f"{round(0.1 / ex.dt):,}" if got else "")]
    demo, why_demo = attempt(demo_seconds)
    notes.append(f"the warm demo: the best of {DEMO_WARM_RUNS} runs of `python -m rbcourse demo`, each a fresh process, "
                 "after a first run that warms numba's cache and Python's bytecode (PYTHONDONTWRITEBYTECODE unset for "
                 "them, as on a newcomer's machine)")
    rows.append(f"| the warm demo: `python -m rbcourse demo` (a fresh process, best of {DEMO_WARM_RUNS} warm runs; s) | "
                f"{_cell(demo, why_demo, 's')} | — | — | ≤ {TARGET_DEMO_S:g} s | "
                f"{_met(demo <= TARGET_DEMO_S if demo is not None else None)} |")
    return rows, notes


def contact_table(quick: bool, peers: bool) -> list[str]:
    out = ["## Contacts, many bodies, forces over time", "",
           "Each beside MuJoCo's RK4 where it has the same scene: the same bodies, start and step. Its contacts are "
           "soft (default solref/solimp, condim 3, friction 0.5, box–plane pairs only), ours are impulses: the "
           "scenes match in bodies, start and step, not in contact model. Times per step by the difference method "
           f"((fastest of {REPEATS} runs of 2k steps − fastest of {REPEATS} runs of k steps) / k, runs of ≈ "
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
            got, why = attempt(lambda: mujoco_size(bodies))
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
