"""Bulk grading of the exercise's hand-ins: ``python -m rbcourse grade SUBMISSIONS/ --out grades.csv``.

A grade a class can trust: no hand-in can give itself a mark it did not earn, change another's, read the others,
the solution or the grader, or stop the class.

- ``submissions.py``  SUBMISSIONS read first, once, safely: one row per entry (a bad one is an "invalid" row)
- ``plan.py``         the arguments checked; the hand-ins run on every core or a Dask cluster; the outputs
                      written at the end, whole, by the grader only; SUBMISSIONS fingerprinted before and after
- ``runner.py``       one hand-in: its notebook run twice, each run in a sandbox — once as written (its status),
                      once with rbcourse absent, to be checked
- ``sandbox.py``      the sandbox: bubblewrap (bwrap), an unprivileged user, no network, its own processes, a
                      read-only system, a private /tmp, limits; nothing of the grader, the class or the solution
- ``worker.py``       the process inside the sandbox (nothing it does is trusted); ``wire.py`` the channel's
                      plain data; ``standin.py`` what ``import rbcourse`` finds where the functions are checked
- ``checker.py``      the checks, in the grader's process, calling the student's functions over the channel
- ``library.py``      a graded function whose source takes its answer from rbcourse
- ``report.py``       grades.csv, the feedback files, Gradescope's results.json

``outcome(result)``: a check's result as the plain data the report reads.
"""
from __future__ import annotations


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
