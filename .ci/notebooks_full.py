"""Run every notebook top to bottom at full length, exactly as a student's "Run All" does.

No RBCOURSE_QUICK (it is removed from the environment), the notebook's own folder as the working
directory, the stored outputs ignored: a notebook passes when every cell runs without an error and
nothing is written to stderr (a RuntimeWarning, a traceback, a progress bar gone wrong).  Nothing is
compared with the stored outputs (the shortened run under nbval does that).  Prints one line per
notebook with its wall time, and exits 1 if any notebook failed.

    python .ci/notebooks_full.py [--cell-times] [NOTEBOOK ...]   (default: every notebook under notebooks/)

--cell-times: also one line per code cell run, with its wall time as the client saw it (from the request to
the kernel's reply), and a line "slowest cell #K: N s" per notebook (K: the cell's index in the notebook,
counting from 0 and counting markdown cells, as the stderr lines' "cell K").
"""
from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

ROOT = Path(__file__).resolve().parents[1]
CELL_TIMEOUT = 900      # s: a cell a student waits longer for is a bug, not a slow machine


def notebooks(args) -> list[Path]:
    if args:
        return [Path(a).resolve() for a in args]
    return sorted(p for p in (ROOT / "notebooks").rglob("*.ipynb") if ".ipynb_checkpoints" not in p.parts)


def stderr_of(nb) -> list[str]:
    """What the cells wrote to stderr (a student sees it in red)."""
    found = []
    for i, cell in enumerate(nb.cells):
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream" and out.get("name") == "stderr":
                found.append(f"cell {i}: {''.join(out['text']).strip()[:300]}")
    return found


def run(path: Path, cells: dict | None = None) -> tuple[bool, float, str]:
    """Run the notebook: (passed, wall time, why not).  cells: a dict filled with {cell index: seconds} of
    every code cell run (the one that failed included)."""
    nb = nbformat.read(path, as_version=4)
    cells = {} if cells is None else cells
    started = {}

    def before(cell, cell_index, **_):
        started[cell_index] = time.perf_counter()

    def after(cell, cell_index, **_):
        if cell_index in started:
            cells[cell_index] = time.perf_counter() - started[cell_index]
    client = NotebookClient(nb, timeout=CELL_TIMEOUT, kernel_name="python3",
                            resources={"metadata": {"path": str(path.parent)}},
                            on_cell_execute=before, on_cell_executed=after)
    start = time.perf_counter()
    try:
        client.execute()
    except CellExecutionError as err:
        return False, time.perf_counter() - start, str(err).strip().splitlines()[-1][:300]
    except Exception as err:            # a dead kernel, a time-out
        return False, time.perf_counter() - start, f"{type(err).__name__}: {err}"[:300]
    wall = time.perf_counter() - start
    errs = stderr_of(nb)
    return (not errs), wall, "; ".join(errs)


def main(args) -> int:
    os.environ.pop("RBCOURSE_QUICK", None)
    os.environ.setdefault("MPLBACKEND", "Agg")
    cell_times = "--cell-times" in args
    args = [a for a in args if a != "--cell-times"]
    failed, total = [], 0.0
    for path in notebooks(args):
        cells = {}
        ok, wall, why = run(path, cells)
        total += wall
        name = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
        print(f"{'ok  ' if ok else 'FAIL'} {wall:7.1f} s  {name}{'' if ok else '  — ' + why}", flush=True)
        if cell_times and cells:
            for index, seconds in sorted(cells.items()):
                print(f"       cell #{index}: {seconds:7.2f} s", flush=True)
            slowest = max(cells, key=cells.get)
            print(f"       slowest cell #{slowest}: {cells[slowest]:.1f} s", flush=True)
        if not ok:
            failed.append(str(name))
    print(f"full-length notebooks: {len(failed)} failed, {total:.0f} s in all", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
