"""A frame the hand-in's process sends about itself is its own word (it may forge it): a field missing, of the wrong
type, or not finite gives that row a "?", and every report is still written (grading/runner.py: _report, _cell)."""
import math

import pytest

from rbcourse.workbook.grading import report, runner

FORGED = [{}, {"cell": "three", "cells": None, "seconds": "long"}, {"cell": True, "seconds": math.inf},
          {"cell": 2, "cells": 9, "seconds": float("nan"), "first_line": 12, "error": ["not", "text"]}]


@pytest.mark.parametrize("event", FORGED)
def test_a_forged_cell_event_reads_as_question_marks_and_every_report_is_written(event):
    cell = runner._cell(event)
    assert all(isinstance(v, str) for v in cell.values())
    assert cell["seconds"] == "?"
    g = runner.Graded("forger", "timeout", timeout=60.0, language="en")
    g.interrupted, g.cell_errors = cell, [cell]
    names = [name for name, _ in runner.checks()]
    text = report.feedback_text(g, names)
    assert "still running at its time limit (? s)" in text
    g.language = "fr"
    assert "(? s)" in report.feedback_text(g, names)
    report.csv_text([g], names)


def test_a_true_cell_event_keeps_its_numbers():
    cell = runner._cell({"cell": 3, "cells": 12, "seconds": 61.5, "first_line": "while True:", "error": "KeyboardInterrupt"})
    assert (cell["cell"], cell["cells"], cell["seconds"]) == ("3", "12", "61.5")


def test_a_huge_answer_is_shown_by_its_first_values_and_its_size():
    """A student's function may return 2 million values: the check's message shows six and the size (it formatted
    each before: minutes of the grader's own time, a 12 MB feedback file)."""
    import numpy as np
    from rbcourse.workbook.exercises.harness import MAX_SHOWN, fmt, fmt_pair
    want, got = fmt_pair(np.zeros(3), np.arange(2_000_000.0))
    assert got == "[0, 1, 2, 3, 4, 5, … (2,000,000 values, shape (2000000,))]" and want == "[0, 0, 0]"
    assert len(fmt([(1.0, 2.0)] * 1_000_000)) < 20 * MAX_SHOWN
    assert fmt(np.eye(3)) == "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]"          # a matrix, as always


def test_the_arguments_a_hand_in_passes_back_to_a_check_are_bounded():
    """A student's simulate may call the check's forces_at with huge arrays, again and again: the check keeps what it
    is given, so past checker.MAX_PASSED bytes in one call the calls raise in the student's code instead of reaching
    it (1.6 GB held in 6 s before, and an out-of-memory kill of a pool worker ends the class)."""
    import os
    import threading

    import numpy as np

    from rbcourse.workbook.grading import checker, wire
    to_student, from_grader = os.pipe()
    to_grader, from_student = os.pipe()
    grader = wire.Channel(to_grader, from_grader, blocking=False)
    student = wire.Channel(to_student, from_student)
    kept, replies = [], []

    def forces_at(t, X):
        kept.append(X)
        return np.zeros(3)

    def sandbox():
        call = student.receive()
        big = wire.encode(np.ones(500_000))                # 4 MB of floats, some 5 MB on the wire
        for _ in range(40):
            student.send({"op": "callback", "id": call["id"], "fn": 0, "args": [wire.encode(0.0), big]})
            replies.append(student.receive())
        student.send({"op": "result", "id": call["id"], "value": wire.encode(1.0), "args": []})
    worker = threading.Thread(target=sandbox)
    worker.start()
    link = checker.Link(grader)
    link.remaining = 60.0
    try:
        assert link.call("simulate", (forces_at,), {}) == 1.0
    finally:
        worker.join()
        for fd in (to_student, from_grader, to_grader, from_student):
            os.close(fd)
    assert len(kept) * 5.3e6 <= checker.MAX_PASSED + 6e6                     # what reached the check: bounded
    refused = [r for r in replies if r["op"] == "raise"]
    assert len(refused) == 40 - len(kept) > 0
    assert "MB of arguments passed to forces_at in one run" in refused[0]["message"]
