"""One hand-in's process: ``python -m rbcourse.workbook.grading.worker NOTEBOOK LOG CELLS_S CHECKS_S [LANGUAGE]``.

It starts in LANGUAGE (runner.notebook_language: the notebook's ex.langue call or its metadata; "en" by
default), and the notebook's own ex.langue(…) call runs as any cell; the language active after the cells is
the final checks' and is logged ({"event": "language", "code": …}), for the feedback.

Run by runner.py in the hand-in's own temporary folder (its cwd, HOME and TMPDIR).  It runs the
notebook's code cells one after the other in an IPython shell, going on after a cell that raises;
each check the notebook calls is recorded as it returns (the exercise's check_* are wrapped so that
each call is recorded once, whether or not the checks call record() themselves).  Then it calls every
check again on the student's functions as the namespace holds them at the end (phase "final").  
Time: the cells get CELLS_S seconds in all; a cell still running then is interrupted (an OutOfTime
exception raised in it, as Jupyter's "Interrupt" does) and the cells after it are not run.  The final
checks then get CHECKS_S seconds in all, check k being interrupted at k + 1 n-ths of it (what a check
leaves unused goes to the next ones).  A hand-in that ignores the interrupt is killed by runner.py.

LOG receives one JSON line per event:

    {"event": "cell_error", "cell": k, "cells": K, "first_line": …, "error": "TypeError: …"}
    {"event": "check", "phase": "notebook" | "final", "name": …, "passed": …, "mistake": …, "message": …, "slide": …}
    {"event": "interrupted", "cell": k, "seconds": CELLS_S}                 (the cells ran out of time)
    {"event": "notebook_done", "cells": K}      then the final checks, then {"event": "done"}
A final check whose run of the student's function ran out of time has the mistake "out_of_time".
"""
from __future__ import annotations

import functools
import json
import os
import signal
import sys
import time
from pathlib import Path

from . import LOG_VARIABLE, outcome, record, recorded


def checks():
    """The exercise's checks, [(the student's function name, check_*)], in the order of exercises.__all__."""
    from .. import exercises as ex
    return [(name[len("check_"):], getattr(ex, name)) for name in ex.__all__ if name.startswith("check_")]


def code_cells(notebook: dict) -> list[str]:
    """The source of each code cell, in order."""
    out = []
    for cell in notebook.get("cells", []):
        if cell.get("cell_type") == "code":
            source = cell.get("source", "")
            out.append("".join(source) if isinstance(source, list) else str(source))
    return out


class OutOfTime(BaseException):
    """Raised in the hand-in's code when its time is up (a BaseException: `except Exception` does not stop it)."""


def _out_of_time(signum, frame):
    raise OutOfTime("the time limit was reached")


def _alarm(seconds: float) -> None:
    """OutOfTime in `seconds` (0: no alarm)."""
    signal.setitimer(signal.ITIMER_REAL, max(seconds, 1e-3) if seconds else 0.0)


def _wrap(check, called: dict):
    """check, recording its result when it returns (once: not again if the check recorded it itself),
    and remembering the name of the function it was given (called[check name] = that name)."""
    @functools.wraps(check)
    def recording(*args, **kwargs):
        before = recorded()
        result = check(*args, **kwargs)
        if args and getattr(args[0], "__name__", None):
            called[check.__name__] = args[0].__name__
        if recorded() == before:
            record(result)
        return result
    return recording


def _first_line(source: str) -> str:
    lines = [s for s in source.splitlines() if s.strip() and not s.lstrip().startswith("#")]
    return (lines[0].strip() if lines else "")[:80]


def main(argv=None) -> int:
    args = list(argv if argv is not None else sys.argv[1:])
    notebook_path, log, cells_seconds, checks_seconds = args[:4]
    from ..language import current, langue
    from ..exercises.texts import tr
    langue(args[4] if len(args) > 4 else "en")
    log = str(Path(log).resolve())

    def emit(**event):
        with open(log, "a", encoding="utf-8") as f:
            f.write(json.dumps(event, ensure_ascii=False, default=str) + "\n")

    os.environ[LOG_VARIABLE] = log
    notebook = json.loads(Path(notebook_path).read_text(encoding="utf-8"))
    sources = code_cells(notebook)

    from traitlets.config import Config
    from IPython.core.interactiveshell import InteractiveShell
    config = Config()
    config.HistoryManager.enabled = False
    shell = InteractiveShell.instance(config=config)

    from .. import exercises as ex
    table = checks()
    called: dict = {}
    for name, check in table:
        setattr(ex, check.__name__, _wrap(check, called))

    signal.signal(signal.SIGALRM, _out_of_time)
    interrupted = _run_cells(shell, sources, float(cells_seconds), emit)
    emit(event="notebook_done", cells=len(sources))
    emit(event="language", code=current())

    os.environ.pop(LOG_VARIABLE, None)          # the final checks are written here, not by record()
    namespace = shell.user_ns
    start, budget = time.monotonic(), float(checks_seconds)
    for k, (name, check) in enumerate(table):
        fn = namespace.get(name)
        if fn is None and called.get(check.__name__):
            fn = namespace.get(called[check.__name__])
        if fn is None:
            if not interrupted:
                emit(event="check", phase="final", name=name, passed=False, mistake="not_done",
                     message=tr("not_defined").format(name=name), slide=None)
            continue
        try:
            _alarm(start + (k + 1) * budget / len(table) - time.monotonic())
            result = outcome(check(fn, verbose=False))
            _alarm(0)
        except OutOfTime:
            result = {"name": name, "passed": False, "mistake": "out_of_time", "slide": None,
                      "message": tr("out_of_time").format(name=name)}
        emit(event="check", phase="final", **result)
    emit(event="done")
    return 0


def _run_cells(shell, sources, seconds: float, emit) -> bool:
    """Run the cells, each after the other, within `seconds` in all; True if they ran out of time."""
    k = 0
    try:
        _alarm(seconds)
        for k, source in enumerate(sources, 1):
            result = shell.run_cell(source, store_history=True)
            error = result.error_before_exec or result.error_in_exec
            if isinstance(error, OutOfTime):
                raise error
            if error is not None:
                emit(event="cell_error", cell=k, cells=len(sources), first_line=_first_line(source),
                     error=f"{type(error).__name__}: {' '.join(str(error).split())}"[:300])
        _alarm(0)
        return False
    except OutOfTime:
        _alarm(0)
        emit(event="interrupted", cell=k, cells=len(sources), first_line=_first_line(sources[k - 1]) if k else "",
             seconds=seconds)
        return True


if __name__ == "__main__":
    sys.exit(main())
