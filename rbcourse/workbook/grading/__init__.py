"""Bulk grading of the exercise's hand-ins: ``python -m rbcourse grade SUBMISSIONS/ --out grades.csv``.

The arguments are checked and the hand-ins read first (`plan.py`).  SUBMISSIONS/ holds one hand-in
per student: ``STUDENT.ipynb``, or a folder ``STUDENT/`` holding exactly
one notebook (its other files are not used); the student's name is the file's stem or the folder's
name; hidden entries (``.ipynb_checkpoints``) are skipped.  Every notebook is read into memory first,
so a hand-in that deletes files cannot change what the others are graded on.

Each hand-in runs alone, in a process of its own (its own process group, killed whole at its time
limit), in a fresh temporary folder holding only a copy of its notebook, which is also its cwd, HOME
and TMPDIR (`worker.py`).  The process runs the notebook's code cells one after the other in an
IPython shell (as "Run All" does, but going on after a cell that raises: later checks still count),
then calls every check of the exercise again, on the student's functions as the namespace holds them
at the end (the **final** results: what the student's functions do, whatever the notebook printed).
Each check's outcome is also recorded as the notebook calls it (``record``), so a hand-in killed at
its limit keeps the checks it reached.  SUBMISSIONS and the output locations are snapshotted before
and after each hand-in: one that changed them is reported "wrote-outside" (`runner.py`).

The outputs (`report.py`): grades.csv, one row per student (status ok / error / timeout /
wrote-outside; each check: passed, the mistake's id, not-done, crashed, or not-run; the number
passed; the seconds taken), a feedback file per student (``FEEDBACK/STUDENT.md``: each mistake, its
explanation and the slide to reread, in the notebook's language), and optionally Gradescope's
results.json (for one hand-in: Gradescope grades one submission at a time).

The hand-in's language (runner.notebook_language): its last ``ex.langue("…")`` (or ``language("…")``) call
in a code cell, else its metadata ``rbcourse.language``, else English.  The worker starts in it, so the
checks' messages and slides are in it even for a notebook that only declares it; the language active after
the cells is logged and is the feedback's.  The CSV is language-neutral (the mistakes' ids).

``record(result)`` is the hook for the checks: it appends the result as a JSON line to the file named
by the environment variable RBCOURSE_GRADE_LOG, and does nothing when it is unset (as in class).
"""
from __future__ import annotations

import json
import os

LOG_VARIABLE = "RBCOURSE_GRADE_LOG"
_count = 0


def recorded() -> int:
    """How many results record() has written in this process (the worker's wrappers read it)."""
    return _count


def record(result, phase: str = "notebook") -> None:
    """Append a check's result (a CheckResult: name, passed, mistake, message) to $RBCOURSE_GRADE_LOG as one
    JSON line; nothing when the variable is unset.  Never raises (a check must not fail for grading's sake)."""
    global _count
    path = os.environ.get(LOG_VARIABLE)
    if not path:
        return
    try:
        line = json.dumps({"event": "check", "phase": phase, **outcome(result)}, ensure_ascii=False)
        with open(path, "a", encoding="utf-8") as log:
            log.write(line + "\n")
        _count += 1
    except Exception:      # noqa: BLE001
        pass


def outcome(result) -> dict:
    """A CheckResult as plain data: name, passed, mistake, message, slide (the slide to reread, or None)."""
    mistake = getattr(result, "mistake", None)
    slide = getattr(result, "slide", None)
    if slide is None and mistake:
        from ..exercises.mistakes import MISTAKES
        known = MISTAKES.get(mistake)
        slide = known.slide if known else None
    return {"name": str(getattr(result, "name", "?")), "passed": bool(getattr(result, "passed", False)),
            "mistake": None if mistake is None else str(mistake), "message": str(getattr(result, "message", "")),
            "slide": slide}
