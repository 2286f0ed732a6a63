"""The stability matrix: every hard case × every method, and what each run kept.

    python -m rbcourse stability [--quick] [--cases ...] [--methods ...] [--out DIR] [--workers N]
                                 [--scheduler ADDRESS]

For each run: finished or diverged (and when), the max relative error of every invariant the
case's physics keeps (INVARIANTS: energy, world L, |L|, L_z about the pivot, the spin L₃, P, rest),
max ‖RᵀR − I‖, the energy drift (late error / early error), the rotation (and position) error at
the end against the exact or reference motion, and the outcome (OUTCOMES: faithful, stable but
wrong, ran away, diverged; thresholds FAITHFUL_*, RUNAWAY).  The cells run here, on --workers
processes or on a Dask cluster (--scheduler): the same cells, to the bit, whatever runs them.

The package, one concept a module (every name below importable from rbcourse.bench.stability):
    cell          Cell: what one method did on one case
    invariants    INVARIANTS, each defined once; total_energy
    outcomes      OUTCOMES, outcome() and its thresholds
    references    the case's reference at its end (reference_end, reference_R)
    measure       run_cell: one method on one case, measured
    claim_check   broken_claims: a cell against bench/claims.py (rounding_budget)
    runner        matrix: every case × every method, here, on worker processes or on Dask
    report        markdown: stability.md
    results       write, read_results, differences; RESULTS: the shipped matrix
and here: check_arguments, main (the command line's run: `python -m rbcourse stability`).
"""
from __future__ import annotations

from ...methods import METHODS
from ...support.outputs import Interrupted, RowLog, remove, shielded, write_text, writable_folder
from ..hardcases import catalogue
from ...support.parallel import check_workers, connect, default_workers, run_tasks  # noqa: F401 (stability.connect …)
from .cell import Cell
from .claim_check import LONG_CASES, ROUNDING_STEPS, broken_claims, rounding_budget  # noqa: F401
from .invariants import INVARIANTS, total_energy  # noqa: F401
from .measure import MAX_RECORDS, run_cell  # noqa: F401
from .outcomes import FAITHFUL_INVARIANT, FAITHFUL_POSITION, FAITHFUL_ROTATION, OUTCOMES, RUNAWAY, outcome  # noqa: F401
from .references import reference_R, reference_end  # noqa: F401
from .report import markdown  # noqa: F401
from .results import (CSV_HEADER, MATCH_ATOL, MATCH_RTOL, NUMBERS, OUTCOMES_HEADER, OUTPUTS, RESULTS,  # noqa: F401
                      csv_row, differences, outcomes_row, read_results, write)
from .runner import matrix, run_task  # noqa: F401


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
