"""The stability matrix: every hard case × every method, and what each run kept.

    python -m rbcourse stability [--quick] [--cases ...] [--methods ...] [--out DIR] [--workers N]
                                 [--scheduler ADDRESS]

For each run: finished or diverged (and when), the max relative error of every invariant the
case's physics keeps (INVARIANTS: energy, world L, |L|, L_z about the pivot, the spin L₃, P, rest),
max ‖RᵀR − I‖, the energy drift (late error / early error), the rotation (and position) error at
the end against the exact or reference motion, and the outcome (OUTCOMES: faithful, stable but
wrong, ran away, diverged; thresholds FAITHFUL_*, RUNAWAY).  The cells run here, on --workers
processes or on a Dask cluster (--scheduler): the same cells, to the bit, whatever runs them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from ..outputs import (Interrupted, RowLog, progress as progress_bar, remove,
                       shielded, write_text, writable_folder)
from .claims import CLAIMS
from .hardcases import HardCase, catalogue
from .parallel import check_workers, connect, default_workers, run_tasks  # noqa: F401 (stability.connect …)
from ..integrators import METHODS
from ..rotation import rotation_angle
from ..simulate import simulate

MAX_RECORDS = 4000


@dataclass
class Cell:
    """What one method did on one hard case."""
    case: str
    method: str
    finished: bool
    t_end: float                  # where it stopped (the case's T if it finished)
    energy_error: float           # max |E − E0| / |E0|  (E summed over the bodies)
    energy_gain: float            # max (E − E0) / |E0|  (> 0: energy was gained)
    energy_drift: float           # max |E − E0| over the last half / over the first half
    momentum_error: float         # the "L" invariant if declared, else "L_z" (nan if neither)
    norm_L_error: float           # the "norm_L" invariant (nan if not declared)
    orthogonality: float          # max ‖RᵀR − I‖
    rotation_error: float         # at the end, against the reference (nan if none)
    diverged_at: float = math.nan  # the time of the blow-up (nan if it finished); t_end is the last good state
    invariants: tuple = ()        # ((name, max relative error), ...): every invariant the case declares
    position_error: float = math.nan   # ‖x − x_ref‖ at the end (m, largest over the bodies; nan if no reference)
    outcome: str = ""             # one of OUTCOMES (stability.outcome)

    def invariant(self, name: str) -> float:
        """The max relative error of a declared invariant (nan if the case does not declare it)."""
        return dict(self.invariants).get(name, math.nan)


# ---- the invariants, each defined once (on the engine's energy and momentum: Trajectory's methods) ----

def _summed(a: np.ndarray, tail: int) -> np.ndarray:
    """A per-body quantity summed over the bodies of a many-body trajectory: (n+1, N, …) -> (n+1, …)."""
    return a.sum(axis=1) if a.ndim == tail + 2 else a


def total_energy(traj) -> np.ndarray:
    """E = Σ_bodies (T + U), shape (n+1,)."""
    return _summed(traj.total_energy(), 0)


def _relative(a: np.ndarray, scale: float) -> np.ndarray:
    return np.abs(a) / (scale if scale > 0 else 1.0)


def _energy(traj, X0) -> np.ndarray:
    E = total_energy(traj)
    return _relative(E - E[0], abs(E[0]))


def _world_L(traj, X0) -> np.ndarray:
    L = _summed(traj.angular_momentum(), 1)
    return np.linalg.norm(L - L[0], axis=1) / np.linalg.norm(L[0])


def _norm_L(traj, X0) -> np.ndarray:
    n = np.linalg.norm(traj.L, axis=-1)
    return _relative(n - n[0], n[0])


def _L_z(traj, X0) -> np.ndarray:
    L = traj.angular_momentum(about=np.zeros(3))
    return np.abs(L[:, 2] - L[0, 2]) / np.linalg.norm(L[0])


def _L3(traj, X0) -> np.ndarray:
    L3 = np.einsum("nji,nj->ni", traj.R, traj.L)[:, 2]          # (Rᵀ L)₃ = I₃ ω₃
    return _relative(L3 - L3[0], abs(L3[0]))


def _P(traj, X0) -> np.ndarray:
    P = _summed(traj.linear_momentum(), 1)
    return np.linalg.norm(P - P[0], axis=1) / np.linalg.norm(P[0])


def _rest(traj, X0) -> np.ndarray:
    x = traj.x
    return np.linalg.norm(x - x[0], axis=-1) / abs(x[0, 2])


INVARIANTS = {
    # name: (what it is, relative error over the run, shape (n+1,))
    "energy": ("E = T + U, summed over the bodies: |E − E0| / |E0|", _energy),
    "L": ("world L about the origin, summed over the bodies (no external torque): ‖L − L0‖ / ‖L0‖", _world_L),
    "norm_L": ("|L| about the centre of mass (free rotation): ||L| − |L0|| / |L0|", _norm_L),
    "L_z": ("vertical L about the pivot (gravity's torque is horizontal): |L_z − L_z0| / ‖L0‖", _L_z),
    "L3": ("the spin L₃ = (RᵀL)₃ = I₃ω₃ of a symmetric top: |L₃ − L₃0| / |L₃0|", _L3),
    "P": ("total linear momentum (no external force): ‖P − P0‖ / ‖P0‖", _P),
    "rest": ("a body at rest stays put: ‖x − x0‖ / (its centre's height x0_z)", _rest),
}
"""Every invariant a hard case may declare (HardCase.invariants), each defined once, on the engine's
energy and momenta (Trajectory.total_energy, angular_momentum, linear_momentum)."""


# ---- the outcome of a cell, with the thresholds defined once ----

FAITHFUL_INVARIANT = 1e-3   # faithful: every declared invariant within 1e-3 (relative, max over the run)
FAITHFUL_ROTATION = 1e-2    # and the attitude within 1e-2 rad of the reference at the end
FAITHFUL_POSITION = 1e-3    # and the centres within 1 mm of it (where the reference gives them)
RUNAWAY = 1.0               # ran away: an invariant off by more than its own size (energy error > 1: E > 2 E0)
OUTCOMES = ("faithful", "stable but wrong", "ran away", "diverged")
"""What a cell's outcome means:
faithful          finished; every declared invariant within FAITHFUL_INVARIANT, and (where the case has a
                  reference) the end within FAITHFUL_ROTATION rad and FAITHFUL_POSITION m of it;
stable but wrong  finished, every invariant bounded (<= RUNAWAY), but an invariant or the motion off;
ran away          finished, but an invariant off by more than its own size (> RUNAWAY), or not finite;
diverged          overflow / NaN: the engine's divergence error, at diverged_at."""


def outcome(finished: bool, invariants, rotation_error: float, position_error: float) -> str:
    """The cell's category among OUTCOMES (thresholds above)."""
    if not finished:
        return "diverged"
    errors = [v for _, v in invariants]
    if not all(v <= RUNAWAY for v in errors):          # nan counts as ran away
        return "ran away"
    motion_ok = all(math.isnan(v) or v <= tol for v, tol in ((rotation_error, FAITHFUL_ROTATION),
                                                             (position_error, FAITHFUL_POSITION)))
    return "faithful" if motion_ok and all(v <= FAITHFUL_INVARIANT for v in errors) else "stable but wrong"


def reference_end(case: HardCase, T: float):
    """The case's reference at T: (R, x) with R (3,3) or (N,3,3) and x (3,), (N,3) or None; None if it has none."""
    if case.reference == "exact":
        from ..exact.free_body import exact_free_body
        return exact_free_body(case.scene.bodies[0], case.X0, np.array([T])).R[-1], None
    if case.reference == "dop853":
        from .problems import problem_C
        p = problem_C()
        p.T = T
        return p.reference_R(), None
    if case.reference == "rest":
        return np.array(case.X0.R), np.array(case.X0.x)
    if case.reference == "fine":
        traj = simulate(case.scene, case.X0, T, case.dt, "adaptive", rtol=1e-12, atol=1e-12, record_every=10**9)
        return traj.R[-1], traj.x[-1]
    return None


def reference_R(case: HardCase, T: float) -> np.ndarray | None:
    """R(T) of the case's reference solution (None if it has none)."""
    ref = reference_end(case, T)
    return None if ref is None else ref[0]


def _end_errors(traj, ref) -> tuple[float, float]:
    """(rotation error, position error) of the last state against the reference (nan where none)."""
    if ref is None:
        return math.nan, math.nan
    R_ref, x_ref = ref
    R, Rr = traj.R[-1].reshape(-1, 3, 3), np.asarray(R_ref).reshape(-1, 3, 3)
    rot = max(float(rotation_angle(a, b)) for a, b in zip(Rr, R))
    pos = math.nan if x_ref is None else float(np.max(np.linalg.norm(traj.x[-1] - x_ref, axis=-1)))
    return rot, pos


def run_cell(case: HardCase, method: str, quick: bool = False, reference=None) -> Cell:
    """Run one method on one case and measure what it kept (reference: reference_end(case, T), computed
    here if not given; an (3,3) R alone is accepted too)."""
    T = case.duration(quick)
    n = round(T / case.dt)
    every = max(1, n // MAX_RECORDS)
    traj = simulate(case.scene, case.X0, T, case.dt, method, record_every=every, on_divergence="stop")
    finished = not traj.diverged
    ref = reference_end(case, T) if reference is None else reference
    if isinstance(ref, np.ndarray):
        ref = (ref, None)
    with np.errstate(all="ignore"):
        E = total_energy(traj)
        e = _energy(traj, case.X0)
        half = len(e) // 2
        drift = float(e[half:].max() / max(e[:max(half, 1)].max(), 1e-300)) if len(e) > 2 else math.nan
        inv = tuple((name, float(np.max(INVARIANTS[name][1](traj, case.X0)))) for name in case.invariants)
        rot, pos = _end_errors(traj, ref) if finished else (math.nan, math.nan)
        gain = float(np.max((E - E[0]) / abs(E[0])))
        d = dict(inv)
        return Cell(case.name, method, finished, float(traj.t[-1]), float(e.max()), gain, drift,
                    d.get("L", d.get("L_z", math.nan)), d.get("norm_L", math.nan),
                    float(np.max(traj.orthogonality_error())), rot,
                    traj.divergence.t if traj.diverged else math.nan, inv, pos, outcome(finished, inv, rot, pos))


ROUNDING_STEPS = 10**4
LONG_CASES = ("racket_long", "long_run")      # many periods: where "no drift" means something


def rounding_budget(tol: float, steps: int) -> float:
    """A claim "kept to rounding" (so3, free_L, free_norm_L, free_energy) is a tolerance for up to
    10⁴ steps; rounding errors add up from step to step, so over n steps it is tol × n / 10⁴."""
    return tol * max(1.0, steps / ROUNDING_STEPS)


def broken_claims(cell: Cell, case: HardCase, steps: int) -> list[str]:
    """The claims of CLAIMS[cell.method] (bench/claims.py) that this run did not keep (empty: all kept)."""
    claims = CLAIMS[cell.method]
    if case.name in claims.diverges_on:
        return [] if not cell.finished else [f"expected to blow up on {case.name}, but finished"]
    if not cell.finished:
        return [f"claims to finish every case, but diverged at t = {cell.diverged_at:.6g} s"] if claims.finite else []
    broken = []
    kept_to_rounding = [("so3", "‖RᵀR − I‖", cell.orthogonality, True),
                        ("free_L", "world L error", cell.momentum_error, case.free),
                        ("free_norm_L", "|L| error", cell.norm_L_error, case.free),
                        ("free_energy", "energy error", cell.energy_error, case.free)]
    for key, what, value, applies in kept_to_rounding:
        tol = getattr(claims, key)
        if applies and tol is not None and not value <= rounding_budget(tol, steps):
            broken.append(f"{what} {value:.2e} > {rounding_budget(tol, steps):.1e} ({key})")
    for key, tol in claims.keeps.items():
        if key in case.invariants and not cell.invariant(key) <= rounding_budget(tol, steps):
            broken.append(f"{key} error {cell.invariant(key):.2e} > {rounding_budget(tol, steps):.1e} (keeps {key})")
    claimed = claims.outcomes.get(case.name)
    if claimed is not None and cell.outcome != claimed:
        broken.append(f"outcome {cell.outcome!r}, claimed {claimed!r} (outcomes)")
    if case.free and claims.energy_bounded and case.name in LONG_CASES \
            and not (cell.energy_drift <= 3.0 or cell.energy_error <= 1e-10):
        broken.append(f"energy drifts: last half / first half = {cell.energy_drift:.2g} (energy_bounded)")
    if case.free and claims.dissipative and not cell.energy_gain <= 1e-12:
        broken.append(f"energy increased by {cell.energy_gain:.2e} (dissipative)")
    if not math.isfinite(cell.energy_error):
        broken.append("the energy error is not finite")
    return broken


# ---- who runs the cells: this process, a pool of worker processes, or a Dask cluster ----

_CASES: dict = {}


def _case(name: str) -> HardCase:
    """The named hard case, built once per process (a worker builds its own)."""
    if not _CASES:
        _CASES.update(catalogue())
    return _CASES[name]


def run_task(task) -> Cell:
    """One cell from (case name, method, quick, reference): what a worker process or a Dask worker runs.
    Deterministic: the same cell, to the bit, wherever it runs."""
    name, method, quick, ref = task
    return run_cell(_case(name), method, quick, ref)


def matrix(cases=None, methods=None, quick: bool = False, progress: bool = True, on_cell=None,
           workers: int = 1, scheduler=None) -> list[Cell]:
    """Every case × every method, in that order.  on_cell(cell): called as each run finishes (the command
    line writes it at once, so that an interrupted matrix keeps what it measured).

    workers: cells run at once on that many spawned processes (1: here, one after the other);
    scheduler: a Dask scheduler address (or Client) to run them on instead.  Each cell is deterministic,
    so the cells are the same, to the bit, whatever runs them; the references are computed here first."""
    workers = check_workers(workers)
    all_cases = catalogue()
    cases = [all_cases[c] for c in (cases or all_cases)]
    methods = list(methods or METHODS)
    refs = {case.name: reference_end(case, case.duration(quick)) for case in cases}
    tasks = [(case.name, m, quick, refs[case.name]) for case in cases for m in methods]
    runs = run_tasks(run_task, tasks, workers, scheduler)
    cells = [None] * len(tasks)
    with progress_bar(len(tasks), "run", "stability", progress) as bar:
        for i, cell in runs:
            cells[i] = cell
            if on_cell is not None:
                on_cell(cell)
            bar.update(1)
    return cells


def _g(v: float) -> str:
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.1e}"


def markdown(cells: list[Cell], quick: bool) -> str:
    cases = catalogue()
    out = ["# Stability matrix" + (" (short runs: the catalogue's short durations)" if quick else ""), "",
           "Written by `python -m rbcourse stability" + (" --quick" if quick else "") + "` (the shipped full-length "
           "copy in rbcourse/bench/results: `python -m rbcourse stability --workers 2 --out rbcourse/bench/results`).",
           "",
           "Per case: each method's outcome, the largest relative error of every invariant the case's physics "
           "keeps, the largest ‖RᵀR − I‖ and the rotation error at the end against the exact (or reference) "
           "solution (and, where a centre moves, its position error at the end).", "",
           f"Outcomes: **faithful** — finished, every invariant within {FAITHFUL_INVARIANT:g} and the end within "
           f"{FAITHFUL_ROTATION:g} rad (and {FAITHFUL_POSITION:g} m) of the reference; **stable but wrong** — "
           f"finished, every invariant bounded (error <= {RUNAWAY:g}) but the motion or an invariant off; "
           f"**ran away** — an invariant off by more than its own size (error > {RUNAWAY:g}: energy ×2); "
           "**diverged** — overflow or NaN (the time given).", "",
           "Invariants: " + "; ".join(f"{k}: {v[0]}" for k, v in INVARIANTS.items()) + ".", ""]
    broken = [(c, why) for c in cells
              for why in broken_claims(c, cases[c.case], round(cases[c.case].duration(quick) / cases[c.case].dt))]
    out += ["## Claims", "", "Every run against what bench/claims.py claims for its method (kept to rounding: the claim's "
            "tolerance per 10⁴ steps):", ""]
    out += [f"- **{c.method}** on {c.case}: {why}" for c, why in broken] or ["- every claim held."]
    out.append("")
    for name in dict.fromkeys(c.case for c in cells):
        case = cases[name]
        T = case.duration(quick)
        inv = list(case.invariants)
        ref = "rotation err" if case.reference else "rotation err (no reference: chaotic)"
        rows = [c for c in cells if c.case == name]
        moves = any(c.finished and c.position_error > 0 for c in rows)   # a centre that moves: its error too
        cols = len(inv) + 2 + moves
        out += [f"## {name} — T = {T:g} s, dt = {case.dt:g} s", "", f"What goes wrong: {case.goes_wrong}.", "",
                "| method | outcome | " + " | ".join(f"{k} err" for k in inv) + f" | ‖RᵀR − I‖ | {ref} |" +
                (" position err (m) |" if moves else ""), "|---|---|" + "---|" * cols]
        for c in rows:
            if not c.finished:        # its last numbers are overflow, not physics: say when it blew up instead
                out.append(f"| {c.method} | diverged at t = {c.diverged_at:.3g} s |" + " |" * cols)
                continue
            out.append(f"| {c.method} | {c.outcome} | " + " | ".join(_g(c.invariant(k)) for k in inv) +
                       f" | {_g(c.orthogonality)} | {_g(c.rotation_error)} |" +
                       (f" {_g(c.position_error)} |" if moves else ""))
        out.append("")
    return "\n".join(out)


OUTPUTS = ("stability.md", "stability.csv", "stability_outcomes.csv")
CSV_HEADER = ("case,method,finished,t_end,energy_error,energy_gain,energy_drift,momentum_error,norm_L_error,"
              "orthogonality,rotation_error,diverged_at")
OUTCOMES_HEADER = "case,method,outcome,position_error,invariants"


def csv_row(c: Cell) -> str:
    return (f"{c.case},{c.method},{int(c.finished)},{c.t_end:.6g},{c.energy_error:.6g},{c.energy_gain:.6g},"
            f"{c.energy_drift:.6g},{c.momentum_error:.6g},{c.norm_L_error:.6g},{c.orthogonality:.6g},"
            f"{c.rotation_error:.6g},{c.diverged_at:.6g}")


def outcomes_row(c: Cell) -> str:
    """stability_outcomes.csv's row: the outcome, the position error and every declared invariant (name=error;…)."""
    return f"{c.case},{c.method},{c.outcome},{c.position_error:.6g}," + ";".join(f"{k}={v:.6g}" for k, v in c.invariants)


def write(cells: list[Cell], out: Path, quick: bool, partial: str = "") -> list[Path]:
    """stability.md, stability.csv and stability_outcomes.csv in `out`, each written whole (temporary file, then os.replace);
    with `partial` (why the runs are not all there), stability.md begins "# partial: …"."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    md, csv, outcomes = (out / name for name in OUTPUTS)
    head = f"# partial: {partial} (stability.csv holds them)\n\n" if partial else ""
    write_text(md, head + (markdown(cells, quick) if cells else "No run finished.") + "\n")
    write_text(csv, "\n".join([CSV_HEADER] + [csv_row(c) for c in cells]) + "\n")
    write_text(outcomes, "\n".join([OUTCOMES_HEADER] + [outcomes_row(c) for c in cells]) + "\n")
    return [md, csv, outcomes]


RESULTS = Path(__file__).parent / "results"
"""The shipped full-length matrix (stability.md, stability.csv, stability_outcomes.csv), regenerated by
    python -m rbcourse stability --workers 2 --out rbcourse/bench/results"""


NUMBERS = tuple(f.name for f in fields(Cell) if f.type == "float")     # every float of a Cell
MATCH_RTOL, MATCH_ATOL = 1e-4, 1e-12
"""Two matrices match when every cell has the same outcome and finished flag and every number agrees within
MATCH_ATOL + MATCH_RTOL × its size: the cells are bit-identical whatever runs them on one machine (workers, Dask:
tests/bench/test_sweeps.py), but another CPU or another build of the libraries rounds the references' last
digits differently (seen: rotation errors of 1e-16 to 2e-10 changed in their 2nd to 5th digit)."""


def differences(cells, reference, rtol: float = MATCH_RTOL, atol: float = MATCH_ATOL) -> list[str]:
    """What differs between two matrices (lists of Cells, e.g. read_results() of two folders), one line per
    difference: a cell in one only, another outcome or finished flag, a number (or invariant) beyond
    atol + rtol·max(|a|, |b|) (nan matches nan, inf the same inf).  [] when they match."""
    ours, theirs = {(c.case, c.method): c for c in cells}, {(c.case, c.method): c for c in reference}
    out = [f"{k[0]} × {k[1]}: only in the {'first' if k in ours else 'second'}"
           for k in sorted(set(ours) ^ set(theirs))]
    for key in [k for k in ours if k in theirs]:
        a, b = ours[key], theirs[key]
        if (a.outcome, a.finished) != (b.outcome, b.finished):
            out.append(f"{key[0]} × {key[1]}: {a.outcome} / {b.outcome}")
            continue
        numbers = [(f, getattr(a, f), getattr(b, f)) for f in NUMBERS] + \
                  [(k, x, dict(b.invariants).get(k, math.nan)) for k, x in a.invariants]
        for name, x, y in numbers:
            same = x == y or (math.isnan(x) and math.isnan(y)) or abs(x - y) <= atol + rtol * max(abs(x), abs(y))
            if not same:
                out.append(f"{key[0]} × {key[1]}: {name} {x:.6g} / {y:.6g}")
    return out


def read_results(folder=RESULTS) -> list[Cell]:
    """The cells written by write() into `folder` (stability.csv and stability_outcomes.csv), as Cells:
    each float read back from its 6 significant digits."""
    folder = Path(folder)
    rows = (folder / "stability.csv").read_text(encoding="utf-8").splitlines()[1:]
    extra = {tuple(r.split(",")[:2]): r.split(",")[2:]
             for r in (folder / "stability_outcomes.csv").read_text(encoding="utf-8").splitlines()[1:]}
    cells = []
    for row in rows:
        f = row.split(",")
        outcome_, pos, inv = extra[(f[0], f[1])]
        inv = tuple((k, float(v)) for k, v in (kv.split("=") for kv in inv.split(";") if kv))
        cells.append(Cell(f[0], f[1], f[2] == "1", *map(float, f[3:11]), float(f[11]), inv, float(pos), outcome_))
    return cells


def check_arguments(cases=None, methods=None):
    """The matrix's arguments, checked before anything runs: (cases, methods) as lists (None: all).
    A ValueError names the first bad one."""
    known = catalogue()
    for name, given, allowed in (("cases", cases, known), ("methods", methods, METHODS)):
        if given is None:
            continue
        if isinstance(given, str) or not len(given):
            raise ValueError(f"{name} must be a non-empty list of names among {sorted(allowed)}, got {given!r}")
        bad = [g for g in given if g not in allowed]
        if bad:
            raise ValueError(f"{name} must be among {sorted(allowed)}, got {bad}")
    return (None if cases is None else list(cases)), (None if methods is None else list(methods))


def main(cases=None, methods=None, quick: bool = False, out="stability_output", progress: bool = True,
         workers: int = 1, scheduler=None):
    """Run the matrix and write stability.md, stability.csv and stability_outcomes.csv into `out`.

    Every argument (and that `out` takes files) is checked first.  The previous outputs in `out`
    are removed as the run starts; stability.csv grows one flushed row per finished run, and
    stability.md says "# partial: …" until the end, when both are written whole.  Ctrl-C: the
    finished runs are written, stability.md marked partial, and `Interrupted` (a KeyboardInterrupt)
    is raised, with the paths (with workers, the pending runs are cancelled and the workers stopped).
    workers, scheduler: as matrix().  Returns (cells, paths)."""
    cases, methods = check_arguments(cases, methods)
    workers = check_workers(workers)
    out = writable_folder(out, "out", OUTPUTS)
    total = len(cases or catalogue()) * len(methods or METHODS)
    remove(out, OUTPUTS)
    write_text(out / "stability.md", f"# partial: started, not finished ({total} runs planned); stability.csv "
                                     "holds the runs finished so far\n")
    done = []                                         # in finishing order
    log = RowLog(out / "stability.csv", CSV_HEADER)
    log2 = RowLog(out / "stability_outcomes.csv", OUTCOMES_HEADER)

    def finished(cell: Cell):
        done.append(cell)
        log.add(csv_row(cell))
        log2.add(outcomes_row(cell))
    try:
        cells = matrix(cases, methods, quick=quick, progress=progress, on_cell=finished, workers=workers,
                       scheduler=scheduler)          # in the matrix's order (the CSV grew in finishing order)
    except KeyboardInterrupt:
        with shielded():
            log.close()
            log2.close()
            paths = write(done, out, quick, partial=f"interrupted after {len(done)} of {total} runs")
        raise Interrupted(len(done), total, paths) from None
    finally:
        log.close()
        log2.close()
    with shielded():
        paths = write(cells, out, quick)
    return cells, paths
