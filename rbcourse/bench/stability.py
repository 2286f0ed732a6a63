"""The stability matrix: every hard case × every method, and what each run kept.

    python -m rbcourse stability [--quick] [--cases ...] [--methods ...] [--out DIR]

For each run: finished or diverged (and when), max relative energy error, max angular-
momentum error, max ‖RᵀR − I‖, the energy drift (late error / early error), and the
rotation error at the end against the exact or reference solution.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..outputs import (Interrupted, RowLog, progress as progress_bar, remove,
                       shielded, write_text, writable_folder)
from .claims import CLAIMS
from .hardcases import HardCase, catalogue
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
    energy_error: float           # max |E − E0| / |E0|
    energy_gain: float            # max (E − E0) / |E0|  (> 0: energy was gained)
    energy_drift: float           # max |E − E0| over the last half / over the first half
    momentum_error: float         # free: max ‖L − L0‖/‖L0‖ (world); pivot: max |L_z − L_z0|/‖L0‖
    norm_L_error: float           # max | |L| − |L0| | / |L0|  (centre-of-mass L; free bodies)
    orthogonality: float          # max ‖RᵀR − I‖
    rotation_error: float         # at the end, against the reference (nan if none)
    diverged_at: float = math.nan  # the time of the blow-up (nan if it finished); t_end is the last good state


def reference_R(case: HardCase, T: float) -> np.ndarray | None:
    """R(T) of the case's reference solution."""
    if case.reference == "exact":
        from ..exact.free_body import exact_free_body
        return exact_free_body(case.scene.bodies[0], case.X0, np.array([T])).R[-1]
    if case.reference == "dop853":
        from .problems import problem_C
        p = problem_C()
        p.T = T
        return p.reference_R()
    return None


def run_cell(case: HardCase, method: str, quick: bool = False, reference=None) -> Cell:
    """Run one method on one case and measure what it kept."""
    T = case.duration(quick)
    n = round(T / case.dt)
    every = max(1, n // MAX_RECORDS)
    traj = simulate(case.scene, case.X0, T, case.dt, method, record_every=every, on_divergence="stop")
    finished = not traj.diverged
    with np.errstate(all="ignore"):
        E = traj.total_energy()
        e = np.abs(E - E[0]) / abs(E[0])
        half = len(e) // 2
        drift = float(e[half:].max() / max(e[:max(half, 1)].max(), 1e-300)) if len(e) > 2 else math.nan
        L = traj.angular_momentum() if case.free else traj.angular_momentum(about=np.zeros(3))
        L0 = np.linalg.norm(L[0])
        dL = np.linalg.norm(L - L[0], axis=1) if case.free else np.abs(L[:, 2] - L[0, 2])
        nL = np.abs(np.linalg.norm(traj.L, axis=1) - np.linalg.norm(traj.L[0])) / np.linalg.norm(traj.L[0])
        R_ref = reference if reference is not None else reference_R(case, T)
        rot = float(rotation_angle(R_ref, traj.R[-1])) if (finished and R_ref is not None) else math.nan
        gain = float(np.max((E - E[0]) / abs(E[0])))
        return Cell(case.name, method, finished, float(traj.t[-1]), float(e.max()), gain, drift, float(dL.max() / L0),
                    float(nL.max()) if case.free else math.nan, float(traj.orthogonality_error().max()), rot,
                    traj.divergence.t if traj.diverged else math.nan)


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
    if case.free and claims.energy_bounded and case.name in LONG_CASES \
            and not (cell.energy_drift <= 3.0 or cell.energy_error <= 1e-10):
        broken.append(f"energy drifts: last half / first half = {cell.energy_drift:.2g} (energy_bounded)")
    if case.free and claims.dissipative and not cell.energy_gain <= 1e-12:
        broken.append(f"energy increased by {cell.energy_gain:.2e} (dissipative)")
    if not math.isfinite(cell.energy_error):
        broken.append("the energy error is not finite")
    return broken


def matrix(cases=None, methods=None, quick: bool = False, progress: bool = True, on_cell=None) -> list[Cell]:
    """Every case × every method.  on_cell(cell): called as each run finishes (the command line
    writes it at once, so that an interrupted matrix keeps what it measured)."""
    all_cases = catalogue()
    cases = [all_cases[c] for c in (cases or all_cases)]
    methods = list(methods or METHODS)
    cells = []
    with progress_bar(len(cases) * len(methods), "run", "stability", progress) as bar:
        for case in cases:
            ref = reference_R(case, case.duration(quick))
            for m in methods:
                cells.append(run_cell(case, m, quick, ref))
                if on_cell is not None:
                    on_cell(cells[-1])
                bar.update(1)
    return cells


def _g(v: float) -> str:
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.1e}"


def markdown(cells: list[Cell], quick: bool) -> str:
    cases = catalogue()
    out = ["# Stability matrix" + (" (short runs: the catalogue's short durations)" if quick else ""), "",
           "Per case: each method's outcome, the largest relative energy error, the largest angular-momentum error "
           "(world L for a free body; vertical L about the pivot for the top), the largest ‖RᵀR − I‖, the energy "
           "drift (largest error in the second half / in the first half) and the rotation error at the end against "
           "the exact (or reference) solution.", ""]
    broken = [(c, why) for c in cells
              for why in broken_claims(c, cases[c.case], round(cases[c.case].duration(quick) / cases[c.case].dt))]
    out += ["## Claims", "", "Every run against what bench/claims.py claims for its method (kept to rounding: the claim's "
            "tolerance per 10⁴ steps):", ""]
    out += [f"- **{c.method}** on {c.case}: {why}" for c, why in broken] or ["- every claim held."]
    out.append("")
    for name in dict.fromkeys(c.case for c in cells):
        case = cases[name]
        T = case.duration(quick)
        out += [f"## {name} — T = {T:g} s, dt = {case.dt:g} s", "", f"What goes wrong: {case.goes_wrong}.", "",
                "| method | outcome | energy err | L err | ‖RᵀR − I‖ | drift | rotation err |", "|---|---|---|---|---|---|---|"]
        for c in (c for c in cells if c.case == name):
            if not c.finished:        # its last numbers are overflow, not physics: say when it blew up instead
                out.append(f"| {c.method} | diverged at t = {c.diverged_at:.3g} s | | | | | |")
                continue
            out.append(f"| {c.method} | ok | {_g(c.energy_error)} | {_g(c.momentum_error)} | "
                       f"{_g(c.orthogonality)} | {c.energy_drift:.2g} | {_g(c.rotation_error)} |")
        out.append("")
    return "\n".join(out)


OUTPUTS = ("stability.md", "stability.csv")
CSV_HEADER = ("case,method,finished,t_end,energy_error,energy_gain,energy_drift,momentum_error,norm_L_error,"
              "orthogonality,rotation_error,diverged_at")


def csv_row(c: Cell) -> str:
    return (f"{c.case},{c.method},{int(c.finished)},{c.t_end:.6g},{c.energy_error:.6g},{c.energy_gain:.6g},"
            f"{c.energy_drift:.6g},{c.momentum_error:.6g},{c.norm_L_error:.6g},{c.orthogonality:.6g},"
            f"{c.rotation_error:.6g},{c.diverged_at:.6g}")


def write(cells: list[Cell], out: Path, quick: bool, partial: str = "") -> list[Path]:
    """stability.md and stability.csv in `out`, each written whole (temporary file, then os.replace);
    with `partial` (why the runs are not all there), stability.md begins "# partial: …"."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    md, csv = out / "stability.md", out / "stability.csv"
    head = f"# partial: {partial} (stability.csv holds them)\n\n" if partial else ""
    write_text(md, head + (markdown(cells, quick) if cells else "No run finished.") + "\n")
    write_text(csv, "\n".join([CSV_HEADER] + [csv_row(c) for c in cells]) + "\n")
    return [md, csv]


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


def main(cases=None, methods=None, quick: bool = False, out="stability_output", progress: bool = True):
    """Run the matrix and write stability.md and stability.csv into `out`.

    Every argument (and that `out` takes files) is checked first.  The previous outputs in `out`
    are removed as the run starts; stability.csv grows one flushed row per finished run, and
    stability.md says "# partial: …" until the end, when both are written whole.  Ctrl-C: the
    finished runs are written, stability.md marked partial, and `Interrupted` (a KeyboardInterrupt)
    is raised, with the paths.  Returns (cells, paths)."""
    cases, methods = check_arguments(cases, methods)
    out = writable_folder(out, "out", OUTPUTS)
    total = len(cases or catalogue()) * len(methods or METHODS)
    remove(out, OUTPUTS)
    write_text(out / "stability.md", f"# partial: started, not finished ({total} runs planned); stability.csv "
                                     "holds the runs finished so far\n")
    cells = []
    log = RowLog(out / "stability.csv", CSV_HEADER)

    def finished(cell: Cell):
        cells.append(cell)
        log.add(csv_row(cell))
    try:
        matrix(cases, methods, quick=quick, progress=progress, on_cell=finished)
    except KeyboardInterrupt:
        with shielded():
            log.close()
            paths = write(cells, out, quick, partial=f"interrupted after {len(cells)} of {total} runs")
        raise Interrupted(len(cells), total, paths) from None
    finally:
        log.close()
    with shielded():
        paths = write(cells, out, quick)
    return cells, paths
