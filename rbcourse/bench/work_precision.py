"""Work-precision benchmark: what accuracy costs in time, on problems A, B, C, beside the peers.

    python -m rbcourse bench [--problems A B C] [--methods rk4 adaptive ...] [--quick] [--out DIR]

For every method it sweeps dt (or rtol for `adaptive` and scipy), measures the rotation error
at T against the reference and the wall time (median of repeats), and writes results.csv,
results.md (the tables) and work_precision.png (error vs time, log-log: viz.plots.plot_work_precision).
Timed runs are made here, one at a time (two timed at once on these cores slow each other down).

    python -m rbcourse bench --errors-only [--workers N] [--scheduler ADDRESS] ...

sweeps the same settings untimed (seconds: nan) for the errors alone — the observed order of each
method — on N worker processes (default: every core) or a Dask cluster (parallel.run_tasks): each run
is deterministic, so the errors are the same, to the bit, whatever runs them, and equal the timed
sweep's.  It writes results.csv and results.md (per method: the error range and the observed order).
Peers run in the same process (peers.py): scipy's solve_ivp (RK45, DOP853) and MuJoCo (Euler,
implicit, implicitfast, RK4) when installed; one run is measured by runs.py.  Compare ratios measured in one run, never absolute times across runs.
"""
from __future__ import annotations

import functools
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..support import checks
from ..support.outputs import (Interrupted, RowLog, progress as progress_bar, remove,
                       shielded, write_text, write_with, writable_folder)
from ..methods import METHODS
from ..support.language import say
from ..viz.plots import WORK_PRECISION_LEVELS, plot_work_precision
from .peers import MUJOCO_INTEGRATORS, RUNNERS as PEER_RUNNERS, SCIPY_SOLVERS, mujoco_installed
from ..support.parallel import check_workers, run_tasks
from .problems import PROBLEMS, Problem
from .runs import Run, is_adaptive, run_rbcourse

THRESHOLDS = WORK_PRECISION_LEVELS     # the tables' columns: the diagram's grey lines


# --- sweeps ----------------------------------------------------------------------------

def step_sizes(problem: Problem, quick: bool, whole: bool = False) -> list[float]:
    """dt from coarse to fine: about 0.25 s … 2e-4 s, 16 values with T/dt whole (fewer in quick mode).
    whole=True starts with dt = T: one step over the whole interval, for methods built on the
    exact torque-free flow (on a torque-free problem that one step is exact)."""
    dts = problem.T / np.round(problem.T / np.geomspace(0.25, 2e-4, 16))
    dts = list(dts[::3] if quick else dts)
    return [problem.T] + dts if whole else dts


def tolerances(quick: bool) -> list[float]:
    """rtol from 1e-3 to 1e-12, four per decade (the same sweep for ours and the peers)."""
    return [1e-3, 1e-6, 1e-9] if quick else list(np.geomspace(1e-3, 1e-12, 37))


def plan(problems, methods, quick: bool, peers: bool) -> list:
    """The runs to make, as (kind, problem, method, setting)."""
    todo = []
    for p in problems:
        for m in methods:
            method = METHODS[m]
            settings = (tolerances(quick) if is_adaptive(m)
                        else step_sizes(p, quick, whole=method.uses_exact_flow))
            todo += [("rbcourse", p, m, s) for s in settings]
        if peers:
            todo += [("scipy", p, s, r) for s in SCIPY_SOLVERS for r in tolerances(quick)]
            if mujoco_installed():
                todo += [("mujoco", p, i, dt) for i in MUJOCO_INTEGRATORS for dt in step_sizes(p, quick)]
    return todo


def run_all(problems, methods, *, quick=False, peers=True, repeats=None, budget=None, progress=True,
            min_total=None, on_run=None) -> list[Run]:
    """Every planned run; a method's sweep stops once a run takes longer than `budget` seconds.
    Each setting is timed `repeats` times at least, and until its runs add up to `min_total` s.
    on_run(run): called as each run finishes (the command line writes it at once, so that an
    interrupted sweep keeps what it measured)."""
    repeats = repeats or (1 if quick else 5)
    min_total = (0.0 if quick else 0.3) if min_total is None else min_total
    budget = budget or (0.5 if quick else 3.0)
    todo = plan(problems, methods, quick, peers)
    runs, too_slow = [], set()
    runners = {"rbcourse": run_rbcourse, **PEER_RUNNERS}
    with progress_bar(len(todo), "run", "bench", progress) as bar:
        for kind, p, m, s in todo:
            key = (kind, p.name, m)
            if key not in too_slow:
                run = runners[kind](p, m, s, repeats, min_total)
                runs.append(run)
                if on_run is not None:
                    on_run(run)
                if run.seconds > budget:
                    too_slow.add(key)          # finer settings would take longer still
            bar.update(1)
    return runs


@functools.lru_cache(maxsize=None)
def _problem(name: str) -> Problem:
    """The named problem, built once per process (a worker builds its own)."""
    return PROBLEMS[name]()


def error_task(task) -> Run:
    """One planned run (tool, problem name, method, setting) made once, untimed (its seconds: nan): what a
    worker process or a Dask worker runs for the error sweep.  Deterministic: the same error wherever it runs."""
    kind, name, method, setting = task
    runner = run_rbcourse if kind == "rbcourse" else PEER_RUNNERS[kind]
    return replace(runner(_problem(name), method, setting, 1, 0.0), seconds=math.nan)


def errors(problems, methods, *, quick=False, peers=True, workers=1, scheduler=None, progress=True,
           on_run=None) -> list[Run]:
    """The error of every planned run (plan), untimed: here (workers = 1), on `workers` processes, or on
    the Dask cluster at `scheduler`; in the plan's order whatever finishes first.  No budget: every setting
    runs.  on_run(run): called as each run finishes."""
    tasks = [(kind, p.name, m, s) for kind, p, m, s in plan(problems, methods, quick, peers)]
    runs = [None] * len(tasks)
    with progress_bar(len(tasks), "run", "errors", progress) as bar:
        for i, run in run_tasks(error_task, tasks, check_workers(workers), scheduler):
            runs[i] = run
            if on_run is not None:
                on_run(run)
            bar.update(1)
    return runs


def observed_order(runs: list[Run]) -> float:
    """The slope of log(error) against log(setting) over the finest four settings in the asymptotic range:
    error below 0.1 rad (a larger one may have wrapped around) and above rounding, 100 ε per step
    (a long run's rounding, ~1e-11 at 10⁵ steps): a method's order for a dt sweep; nan with fewer than two."""
    eps = np.finfo(float).eps
    ok = [r for r in runs if np.isfinite(r.error) and 100 * eps * max(r.steps, 1) < r.error < 0.1]
    ok = sorted(ok, key=lambda r: r.setting)[:4]
    if len(ok) < 2:
        return math.nan
    return float(np.polyfit(np.log([r.setting for r in ok]), np.log([r.error for r in ok]), 1)[0])


def errors_markdown(runs: list[Run]) -> str:
    """The error sweep's report: per problem and method, the settings swept, the error range and the observed
    order (observed_order)."""
    labels = list(dict.fromkeys(r.label for r in runs))
    out = [say("# Error sweep: rotation error at T against the setting (untimed)",
               "# Balayage d'erreur : erreur de rotation à T selon le réglage (non chronométré)"), "",
           say("Settings: dt, or rtol for adaptive and scipy. Order: the slope of log error against log setting "
               "over the finest four settings with an error below 0.1 rad and above rounding (100 ε per step); "
               "for rtol, how the error follows the tolerance.",
               "Réglages : dt, ou rtol pour adaptive et scipy. Ordre : la pente de log erreur selon log réglage sur "
               "les quatre réglages les plus fins dont l'erreur est sous 0.1 rad et au-dessus de l'arrondi (100 ε "
               "par pas) ; pour rtol, comment l'erreur suit la tolérance."), ""]
    for p in dict.fromkeys(r.problem for r in runs):
        out += [say(f"## Problem {p}", f"## Problème {p}"), "",
                say("| method | settings | largest error | smallest error | diverged | order |",
                    "| méthode | réglages | plus grande erreur | plus petite erreur | divergés | ordre |"),
                "|---|---|---|---|---|---|"]
        for label in labels:
            rs = [r for r in runs if r.problem == p and r.label == label]
            if not rs:
                continue
            finite = [r.error for r in rs if np.isfinite(r.error)]
            order = observed_order(rs)
            out.append(f"| {label} | {min(r.setting for r in rs):.3g} … {max(r.setting for r in rs):.3g} | "
                       + (f"{max(finite):.2e} | {min(finite):.2e}" if finite else "— | —")
                       + f" | {sum(not np.isfinite(r.error) for r in rs)} | "
                       + ("—" if math.isnan(order) else f"{order:.2f}") + " |")
        out.append("")
    return "\n".join(out) + "\n"


# --- reports ---------------------------------------------------------------------------

def cheapest(runs: list[Run], problem: str, label: str, threshold: float):
    """The fastest run of one method on one problem with error <= threshold (or None)."""
    ok = [r for r in runs if r.problem == problem and r.label == label and r.error <= threshold]
    return min(ok, key=lambda r: r.seconds) if ok else None


def per_step_us(runs: list[Run], label: str):
    """Median µs per step of a fixed-step method over its runs of at least 200 steps."""
    costs = [r.seconds / r.steps * 1e6 for r in runs
             if r.label == label and r.steps >= 200 and r.tool != "scipy" and np.isfinite(r.error)]
    return float(np.median(costs)) if costs else None


def markdown(runs: list[Run]) -> str:
    labels = list(dict.fromkeys(r.label for r in runs))
    problems = list(dict.fromkeys(r.problem for r in runs))
    out = [say("# Work-precision: time to reach a rotation error at T",
               "# Travail-précision : temps pour atteindre une erreur de rotation à T"), "",
           say("Cheapest run reaching each error (wall time in ms, median of repeats; the setting in brackets: "
               "dt, or rtol for adaptive and scipy). '—': not reached in the sweep.",
               "Le run le moins cher qui atteint chaque erreur (temps réel en ms, médiane des répétitions ; le "
               "réglage entre parenthèses : dt, ou rtol pour adaptive et scipy). « — » : pas atteint dans le "
               "balayage."), ""]
    for p in problems:
        out += [say(f"## Problem {p}", f"## Problème {p}"), "",
                say("| method | ", "| méthode | ") + " | ".join(f"≤ {t:g} rad" for t in THRESHOLDS) + " |",
                "|---|" + "---|" * len(THRESHOLDS)]
        for label in labels:
            cells = []
            for thr in THRESHOLDS:
                r = cheapest(runs, p, label, thr)
                cells.append("—" if r is None else f"{r.seconds * 1e3:.3g} ({r.setting:.3g})")
            if any(c != "—" for c in cells) or any(r.problem == p and r.label == label for r in runs):
                out.append(f"| {label} | " + " | ".join(cells) + " |")
        out.append("")
        out += target_lines(runs, p)
        out.append("")
    out += [say("## Cost per step (µs, one body)", "## Coût par pas (µs, un corps)"), "",
            say("| method | µs per step |", "| méthode | µs par pas |"), "|---|---|"]
    for label in labels:
        c = per_step_us(runs, label)
        if c is not None:
            out.append(f"| {label} | {c:.3g} |")
    return "\n".join(out) + "\n"


def target_lines(runs: list[Run], problem: str) -> list[str]:
    """Time to 1e-6 rad: the best rbcourse method, and the best time-stepping one, against the fastest peer."""
    def best(pred):
        rs = [cheapest(runs, problem, label, 1e-6) for label in {r.label for r in runs if r.problem == problem and pred(r)}]
        rs = [r for r in rs if r is not None]
        return min(rs, key=lambda r: r.seconds) if rs else None
    peer = best(lambda r: r.tool != "rbcourse")
    ours = best(lambda r: r.tool == "rbcourse")
    stepping = best(lambda r: r.tool == "rbcourse" and not r.uses_exact_flow)
    if peer is None:
        return [say("(no peer reached 1e-6 rad in this run)", "(aucun concurrent n'a atteint 1e-6 rad dans ce run)")]
    lines = [say(f"To reach 1e-6 rad on {problem}: fastest peer {peer.label}, {peer.seconds * 1e3:.3g} ms.",
                 f"Pour atteindre 1e-6 rad sur {problem} : concurrent le plus rapide {peer.label}, "
                 f"{peer.seconds * 1e3:.3g} ms.")]
    for name, r in ((say("best rbcourse method", "meilleure méthode de rbcourse"), ours),
                    (say("best time-stepping method (no exact flow)", "meilleure méthode à pas de temps (sans flot "
                         "exact)"), stepping)):
        if r is None:
            lines.append(say(f"- {name}: not reached", f"- {name} : pas atteint"))
        else:
            ratio = r.seconds / peer.seconds
            lines.append(say(f"- {name}: {r.label}, {r.seconds * 1e3:.3g} ms = {ratio:.2f} × the fastest peer",
                             f"- {name} : {r.label}, {r.seconds * 1e3:.3g} ms = {ratio:.2f} × le concurrent le plus "
                             "rapide"))
    return lines


CSV_HEADER = "problem,tool,method,setting,steps,seconds,error"


def csv_row(r: Run) -> str:
    return f"{r.problem},{r.tool},{r.method},{r.setting:.6g},{r.steps},{r.seconds:.6g},{r.error:.6g}"


def write_csv(runs: list[Run], path: Path):
    """results.csv, written whole or not at all."""
    write_text(path, "\n".join([CSV_HEADER] + [csv_row(r) for r in runs]) + "\n")


def read_csv(path) -> list[Run]:
    """The runs of a results.csv (as `write_csv` and the command line write it), in its order.
    A results.csv still being written (or left by an interrupted sweep) holds the runs finished so
    far: every complete row is read, a last line cut short is left out.  A file that is not a
    results.csv raises a ValueError naming it and the line."""
    path = Path(path)
    lines = path.read_text(encoding="utf-8").splitlines()
    if not lines or lines[0].strip() != CSV_HEADER:
        raise ValueError(f"{path} must begin with the header {CSV_HEADER!r} (a results.csv of `python -m rbcourse "
                         f"bench`), got {lines[0][:80] if lines else 'an empty file'!r}")
    runs = []
    for number, line in enumerate(lines[1:], start=2):
        fields = line.strip().split(",")
        if fields == [""]:
            continue
        try:
            problem, tool, method, setting, steps, seconds, error = fields
            runs.append(Run(problem, tool, method, float(setting), int(steps), float(seconds), float(error)))
        except ValueError:
            if number == len(lines):          # the row being written when the file was read
                break
            raise ValueError(f"{path}, line {number}: expected {CSV_HEADER}, got {line[:120]!r}") from None
    return runs


def read_results(out="bench_output") -> tuple[list[Run], str]:
    """What `python -m rbcourse bench --out OUT` wrote: (the runs of OUT/results.csv, why they are
    partial or '').  results.md begins "# partial: …" while the sweep runs and after an interrupted
    one; that reason is returned so that a plot of the runs can say it."""
    out = Path(out)
    runs = read_csv(out / "results.csv")
    md = out / "results.md"
    first = md.read_text(encoding="utf-8").split("\n", 1)[0] if md.is_file() else "# partial: no results.md"
    partial = first[len("# partial: "):].split(" (results.csv")[0].strip() if first.startswith("# partial:") else ""
    return runs, partial


OUTPUTS = ("results.csv", "results.md", "work_precision.png")
MAX_REPEATS = 100       # the median of more repeats changes nothing, and each repeat costs a whole run


def check_arguments(problems=("A", "B", "C"), methods=None, repeats=None):
    """The benchmark's arguments, checked before anything runs: (problems, methods) as lists.
    A ValueError names the first bad one."""
    if isinstance(problems, str) or not all(isinstance(p, str) for p in problems) or not len(problems):
        raise ValueError(f"problems must be a non-empty list among {sorted(PROBLEMS)}, got {problems!r}")
    unknown = [p for p in problems if p not in PROBLEMS]
    if unknown:
        raise ValueError(f"problems must be among {sorted(PROBLEMS)}, got {unknown}")
    if isinstance(methods, str):
        raise ValueError(f"methods must be a list of names among {sorted(METHODS)}, got {methods!r}")
    methods = list(METHODS) if methods is None else list(methods)
    bad = [m for m in methods if m not in METHODS]
    if bad or not methods:
        raise ValueError(f"methods must be among {sorted(METHODS)}, got {bad or methods}")
    if repeats is not None:
        checks.integer("repeats", repeats, low=1, high=MAX_REPEATS)
    return list(problems), methods


def check_parallel(errors_only: bool, workers=1, scheduler=None) -> int:
    """workers (an integer >= 1) and scheduler apply to the untimed error sweep only: timed runs stay serial,
    one at a time.  Returns workers; ValueError naming the parameter otherwise."""
    workers = check_workers(workers)
    if not errors_only and (workers != 1 or scheduler is not None):
        raise ValueError("workers (--workers) and scheduler (--scheduler) apply to the untimed error sweep "
                         "(--errors-only) only: timed runs stay serial, one at a time")
    return workers


def main(problems=("A", "B", "C"), methods=None, quick=False, out="bench_output", peers=True, repeats=None,
         progress=True, errors_only=False, workers=1, scheduler=None):
    """Run the benchmark and write results.csv, results.md and work_precision.png into `out`.

    Every argument (and that `out` takes files) is checked first.  The previous outputs in `out`
    are removed as the run starts; results.csv grows one flushed row per finished run, and
    results.md says "# partial: …" until the end, when the three files are written whole
    (temporary file, then os.replace).  Ctrl-C: the finished runs are written, results.md and the
    plot marked partial, and `Interrupted` (a KeyboardInterrupt) is raised, with the paths.
    errors_only: the untimed error sweep (errors) on `workers` processes or the Dask `scheduler`, written
    to results.csv (seconds: nan) and results.md (errors_markdown); no plot.  workers and scheduler apply
    to it alone: timed runs stay serial (ValueError otherwise).
    Returns (runs, paths)."""
    problems, methods = check_arguments(problems, methods, repeats)
    workers = check_parallel(errors_only, workers, scheduler)
    out = writable_folder(out, "out", OUTPUTS)
    built = [PROBLEMS[p]() for p in problems]
    total = len(plan(built, methods, quick, peers))
    paths = [out / name for name in OUTPUTS]
    remove(out, OUTPUTS)
    write_text(paths[1], f"# partial: started, not finished ({total} runs planned); results.csv holds the runs "
                         "finished so far\n")
    runs = []
    log = RowLog(paths[0], CSV_HEADER)

    def finished(run: Run):
        runs.append(run)
        log.add(csv_row(run))
    try:
        if errors_only:                   # results.csv in the order they finish; the report in the plan's
            runs[:] = errors(built, methods, quick=quick, peers=peers, workers=workers, scheduler=scheduler,
                             progress=progress, on_run=finished)
        else:
            run_all(built, methods, quick=quick, peers=peers, repeats=repeats, progress=progress, on_run=finished)
    except KeyboardInterrupt:
        with shielded():
            log.close()
            written = write(runs, paths, partial=f"interrupted after {len(runs)} of {total} planned runs",
                            errors_only=errors_only)
        raise Interrupted(len(runs), total, written) from None
    finally:
        log.close()
    with shielded():
        written = write(runs, paths, errors_only=errors_only)
    return runs, written


def write(runs: list[Run], paths, partial: str = "", errors_only: bool = False) -> list[Path]:
    """results.csv, results.md and (with at least one run, unless errors_only) the plot, each written whole;
    with `partial` (why the runs are not all there), results.md begins "# partial: …" and the plot says it.
    Returns the paths written."""
    csv_path, md_path, png_path = paths
    write_csv(runs, csv_path)
    head = f"# partial: {partial} (results.csv holds them)\n\n" if partial else ""
    report = errors_markdown if errors_only else markdown
    write_text(md_path, head + (report(runs) if runs else "No run finished.\n"))
    if not runs or errors_only:
        return [csv_path, md_path]
    write_with(png_path, lambda tmp: plot_work_precision(runs, tmp, note=f"partial: {partial}" if partial else ""))
    return [csv_path, md_path, png_path]
