"""Who runs the cells: this process, a pool of worker processes, or a Dask cluster (support/parallel.py); each
cell is deterministic, so the matrix is the same, to the bit, whatever runs it."""
from __future__ import annotations

from ...methods import METHODS
from ...support.outputs import progress as progress_bar
from ..hardcases import HardCase, catalogue
from ...support.parallel import check_workers, run_tasks
from .cell import Cell
from .measure import run_cell
from .references import reference_end


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
