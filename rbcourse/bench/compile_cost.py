"""What numba's compile costs a student the first time: `python -m rbcourse throughput --compile [--methods a,b]`.

Every number is measured in a FRESH Python process (sys.executable, this rbcourse first on its path), one process
at a time (the package ships no machine code: the engine compiles as on a student's machine), with RBCOURSE_QUICK
unset:

1. The first rb.simulate(scene, X0, 0.05, 1e-3, method) of a process, numba's import included (the engine loads
   numba inside its first simulate), for one method of each family (FAMILIES) on two scenes (SCENES): a free box
   spinning about its middle axis, and the same box falling under gravity onto rb.Ground.
   cold: NUMBA_CACHE_DIR a brand-new empty folder (tempfile.mkdtemp) for that one process, so that it compiles
   only what this family and scene need; warm: a second fresh process on that same, now filled, cache.  The
   ratio cold / warm is what a student's first run costs beside every later one.
2. The notice: a process that compiles says on stderr "compiling the engine for this machine, once (~12 s)…"
   (rbcourse/compiling.py, once per compiled family: a box on the ground may say it twice).  The cold process's
   stderr is read, its "(~N s)" figures summed (notice_seconds), and set beside the measured cold time.
3. The demo, `python -m rbcourse demo --out DIR`, as a whole process (its wall time seen from here): cold on an
   empty cache, then warm on the same cache (the best of 2).

A process that fails or runs past TIMEOUT gives its cell one line saying why; the rest of the report goes on.
"""
from __future__ import annotations

import json
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass

from ..support.checks import method_names
from .throughput import load_average
from .timing import engine_name, fresh_python

FAMILIES = {"euler": "euler", "rk4": "explicit_quat", "quaternion_euler": "explicit_quat_world",
            "symplectic_euler": "symplectic_euler", "splitting": "splitting", "rkmk4": "rkmk4",
            "variational": "variational", "implicit_gyro": "implicit_gyro", "implicit_midpoint": "implicit_midpoint",
            "adaptive": "adaptive", "exact_splitting": "exact"}
"""The method measured for each compiled loop (rbcourse/engine/run.py: LOOPS; compiling.py's SECONDS): {method: loop}."""

SCENES = {"free": "free box", "ground": "box on the ground"}
TIMEOUT = 900.0             # s per process
T_END, DT = 0.05, 1e-3
DEMO_WARM_RUNS = 2
TARGETS = {("free", "euler"): 15.0, ("free", "rk4"): 15.0, **{("ground", m): 30.0 for m in FAMILIES}}
"""cold / warm at most this, per (scene, method); none for the free box's other families."""
TARGET_DEMO = 20.0
NOTICE_FACTOR = 2.0         # measured cold / the notice's estimate, within ×2 either way
ENV = {"MPLBACKEND": "Agg"}

_FIRST = """\
import json, sys, time
import numpy as np
import rbcourse as rb
method, scene_name, t_end, dt = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
numba_before = "numba" in sys.modules
body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
if scene_name == "free":
    scene, X0 = body, rb.State.from_velocities(body, np.zeros(3), np.eye(3), np.zeros(3), [0.01, 5.0, 0.01])
else:
    scene = rb.Scene(body, [rb.Gravity(), rb.Ground(height=0.0, restitution=0.2, friction=0.5)])
    X0 = rb.State.from_velocities(body, [0.0, 0.0, 0.2], np.eye(3), np.zeros(3), np.zeros(3))
t0 = time.perf_counter()
traj = rb.simulate(scene, X0, t_end, dt, method)
first = time.perf_counter() - t0
print(json.dumps({"first": first, "implementation": traj.implementation, "numba_before": numba_before}))
"""
"""The first simulate, timed in the fresh process: argv method, scene (free|ground), t_end, dt; prints JSON."""

_NOTICE = re.compile(r"\(~\s*(\d+(?:[.,]\d+)?)\s*s\)")


def notice_seconds(stderr: str) -> float | None:
    """The seconds the compile notices promised: the sum of every "(~N s)" in stderr, in any language (the figure's
    form, not the words, is read: "… once (~12 s)…", "… une seule fois (~12 s)…"); None when there is none."""
    found = [float(m.group(1).replace(",", ".")) for m in _NOTICE.finditer(stderr)]
    return sum(found) if found else None


@dataclass
class Cell:
    """One measurement: cold and warm seconds (None: not measured, why says why), the notice's estimate."""
    cold: float | None = None
    warm: float | None = None
    why: str | None = None
    estimate: float | None = None
    ran_on: str = "?"


def ratio(a: float | None, b: float | None) -> float | None:
    return a / b if a is not None and b else None          # None: either missing (or b zero)


def verdict(value: float | None, target: float | None) -> str:
    """'yes' / 'no' for value ≤ target; '—' when either is missing."""
    if value is None or target is None:
        return "—"
    return "yes" if value <= target else "no"


def notice_verdict(cold: float | None, estimate: float | None) -> str:
    """'yes' / 'no': the measured cold time within ×NOTICE_FACTOR of the notice's estimate, either way."""
    r = ratio(cold, estimate)
    if r is None:
        return "—"
    return "yes" if 1 / NOTICE_FACTOR <= r <= NOTICE_FACTOR else "no"


def failure(err: BaseException) -> str:
    """One line saying why a process gave no time."""
    if isinstance(err, subprocess.TimeoutExpired):
        return f"timed out after {err.timeout:g} s"
    return f"failed: {type(err).__name__}: {' '.join(str(err).split())[:100]}"


def first_simulate(method: str, scene: str, timeout: float = TIMEOUT) -> Cell:
    """The first simulate of a process, cold (a new empty NUMBA_CACHE_DIR) then warm (that cache, filled)."""
    cell, cache = Cell(), tempfile.mkdtemp(prefix="rbcourse-compile-cost-")
    try:
        for label in ("cold", "warm"):
            try:
                done = fresh_python(["-c", _FIRST, method, scene, repr(T_END), repr(DT)], cache, timeout,
                                    unset=("RBCOURSE_QUICK",), NUMBA_CACHE_DIR=cache, **ENV)
                got = json.loads(done.stdout.strip().splitlines()[-1])
            except Exception as err:            # a cell says why and the report goes on
                cell.why = f"{label}: {failure(err)}"
                return cell
            setattr(cell, label, got["first"])
            if label == "cold":
                cell.estimate, cell.ran_on = notice_seconds(done.stderr), engine_name(got["implementation"])
            if got["numba_before"]:
                cell.why = "numba was loaded before the first simulate: the time leaves its import out"
            elif label == "warm" and notice_seconds(done.stderr) is not None:
                cell.why = "the warm process compiled again (it said the notice): the cache was not reused"
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    return cell


def demo(timeout: float = TIMEOUT) -> Cell:
    """`python -m rbcourse demo` as a whole process: cold on an empty cache, then warm (the best of DEMO_WARM_RUNS)."""
    cell, work = Cell(ran_on="—"), tempfile.mkdtemp(prefix="rbcourse-compile-cost-demo-")
    cache = tempfile.mkdtemp(prefix="numba-cache-", dir=work)
    try:
        runs = []
        for i in range(1 + DEMO_WARM_RUNS):
            t0 = time.perf_counter()
            try:
                done = fresh_python(["-m", "rbcourse", "demo", "--out", f"{work}/out"], work, timeout,
                                    unset=("RBCOURSE_QUICK",), NUMBA_CACHE_DIR=cache, **ENV)
            except Exception as err:
                cell.why = f"{'cold' if i == 0 else 'warm'}: {failure(err)}"
                break
            runs.append(time.perf_counter() - t0)
            if i == 0:
                cell.estimate = notice_seconds(done.stderr)
            elif notice_seconds(done.stderr) is not None:
                cell.why = "a warm demo compiled again (it said the notice): the cache was not reused"
        cell.cold, cell.warm = (runs[0] if runs else None), (min(runs[1:]) if len(runs) > 1 else None)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return cell


def _s(seconds: float | None) -> str:
    return "—" if seconds is None else f"{seconds:.2f} s"


def _x(r: float | None) -> str:
    return "—" if r is None else f"{r:.1f}×"


def _notice(cell: Cell) -> list[str]:
    if cell.estimate is None:
        return ["no notice", "—", "—"]
    return [f"~{cell.estimate:g} s", _x(ratio(cell.cold, cell.estimate)), notice_verdict(cell.cold, cell.estimate)]


def _rows(head: list[str], cell: Cell, target: float | None, tail: list[str]) -> list[str]:
    """A cell's row: head's columns, cold, warm, cold / warm, target, meets, the notice's three, tail's.  A failed
    cell says why in its cold column; a remark on a measured one (cell.why) is a row of its own below."""
    width = len(head) + 8 + len(tail)

    def line(columns):
        return "| " + " | ".join(columns + [""] * (width - len(columns))) + " |"
    if cell.cold is None:
        return [line(head + [str(cell.why)])]
    r = ratio(cell.cold, cell.warm)
    out = [line(head + [_s(cell.cold), _s(cell.warm) if cell.warm is not None else str(cell.why), _x(r),
                        "—" if target is None else f"≤ {target:g}×", verdict(r, target), *_notice(cell), *tail])]
    if cell.warm is not None and cell.why:
        out.append(line([""] * len(head) + [f"note: {cell.why}"]))
    return out


def table(cells: dict, demo_cell: Cell | None) -> list[str]:
    """The report's tables, markdown: cells {(method, scene): Cell}; demo_cell None when not measured."""
    columns = ("cold | warm | cold / warm | target | meets | notice's estimate | cold / estimate | "
               f"within ×{NOTICE_FACTOR:g}")
    out = ["## First simulate() of a process (numba's import included)", "",
           f"rb.simulate(scene, X0, {T_END:g}, {DT:g}, method) in a fresh process: cold on a brand-new empty "
           "NUMBA_CACHE_DIR (it compiles this family alone), warm in a second process on that cache. Targets: "
           f"cold / warm ≤ {TARGETS[('free', 'euler')]:g}× for a free box (euler, rk4), ≤ "
           f"{TARGETS[('ground', 'euler')]:g}× for a box on the ground; the measured cold time within "
           f"×{NOTICE_FACTOR:g} of the notice's estimate (\"compiling the engine … (~N s)…\", summed when it is "
           "said for more than one family).", "",
           f"| method (family) | scene | {columns} | ran on |", "|---" * 11 + "|"]
    for (method, scene), cell in cells.items():
        out += _rows([f"{method} ({FAMILIES.get(method, '?')})", SCENES.get(scene, scene)], cell,
                     TARGETS.get((scene, method)), [cell.ran_on])
    if demo_cell is not None:
        out += ["", "## The demo (`python -m rbcourse demo`, the whole process)", "",
                f"Wall time of the process: cold on an empty NUMBA_CACHE_DIR, then warm on that cache (the best of "
                f"{DEMO_WARM_RUNS}). Target: cold ≤ {TARGET_DEMO:g}× warm.", "",
                f"| {columns} |", "|---" * 8 + "|"]
        out += _rows([], demo_cell, TARGET_DEMO, [])
    return out


def check_methods(text: str | None) -> list[str]:
    """--methods a,b: the methods measured (every one of FAMILIES when None); ValueError naming the allowed ones."""
    return method_names(text, FAMILIES)


def _numba_version() -> str:
    from importlib import metadata
    try:
        return metadata.version("numba")
    except metadata.PackageNotFoundError:
        return "not installed"


def main(methods: list[str] | None = None, with_demo: bool = True, measure=first_simulate, measure_demo=demo) -> str:
    """Measure every (method, scene) one process after another, then the demo; return the report as markdown.
    measure(method, scene) -> Cell and measure_demo() -> Cell: the measurements (replaced in tests)."""
    methods = list(FAMILIES) if methods is None else methods
    t0, load0 = time.perf_counter(), load_average()
    cells = {(m, s): measure(m, s) for m in methods for s in SCENES}
    demo_cell = measure_demo() if with_demo else None
    head = ["# Compile cost (what a new machine compiles, cold and warm)", "",
            f"Python {sys.version.split()[0]}, numba {_numba_version()}, {platform.platform()}; load average "
            f"{load0} at the start, {load_average()} at the end; measured in {time.perf_counter() - t0:.0f} s, one fresh "
            f"process at a time (each at most {TIMEOUT:g} s).", ""]
    return "\n".join(head + table(cells, demo_cell)) + "\n"
