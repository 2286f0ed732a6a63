"""One hand-in's process: ``python -m rbcourse.workbook.grading.worker NOTEBOOK LOG``.

Run by runner.py in the hand-in's own temporary folder (its cwd, HOME and TMPDIR).  It runs the
notebook's code cells one after the other in an IPython shell, going on after a cell that raises;
each check the notebook calls is recorded as it returns (the exercise's check_* are wrapped so that
each call is recorded once, whether or not the checks call record() themselves).  Then it calls every
check again on the student's functions as the namespace holds them at the end (phase "final").  LOG
receives one JSON line per event:

    {"event": "cell_error", "cell": k, "cells": K, "first_line": …, "error": "TypeError: …"}
    {"event": "check", "phase": "notebook" | "final", "name": …, "passed": …, "mistake": …, "message": …, "slide": …}
    {"event": "notebook_done", "cells": K}      then the final checks, then {"event": "done"}
"""
from __future__ import annotations

import functools
import json
import os
import sys
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
    notebook_path, log = (argv if argv is not None else sys.argv[1:])
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

    for k, source in enumerate(sources, 1):
        result = shell.run_cell(source, store_history=True)
        error = result.error_before_exec or result.error_in_exec
        if error is not None:
            emit(event="cell_error", cell=k, cells=len(sources), first_line=_first_line(source),
                 error=f"{type(error).__name__}: {' '.join(str(error).split())}"[:300])
    emit(event="notebook_done", cells=len(sources))

    os.environ.pop(LOG_VARIABLE, None)          # the final checks are written here, not by record()
    namespace = shell.user_ns
    for name, check in table:
        fn = namespace.get(name)
        if fn is None and called.get(check.__name__):
            fn = namespace.get(called[check.__name__])
        if fn is None:
            emit(event="check", phase="final", name=name, passed=False, mistake="not_done",
                 message=f"○ {name}: not done (the notebook defines no function {name})", slide=None)
            continue
        emit(event="check", phase="final", **outcome(check(fn, verbose=False)))
    emit(event="done")
    return 0


if __name__ == "__main__":
    sys.exit(main())
