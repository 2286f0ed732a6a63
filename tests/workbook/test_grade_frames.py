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
