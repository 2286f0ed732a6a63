"""No control group, file or process is left after any row, failed or not (grading/runner.py: grade_one's
finally; sandbox.start)."""
import glob
from pathlib import Path

import pytest

from rbcourse.workbook.grading import cgroups, plan, runner, sandbox, submissions

SOLUTION = Path(__file__).resolve().parents[2] / "notebooks" / "solutions" / "01_exercise_euler.ipynb"


def groups_left() -> set:
    return set(glob.glob(str(cgroups.MOUNTS / "*" / "**" / "rbcourse-grade-*"), recursive=True))


def needs_a_sandbox():
    if sandbox.missing():
        pytest.skip(sandbox.missing())
    probe = cgroups.made(1 << 30, 64)
    cgroups.remove(probe, wait=0)
    if not probe:
        pytest.skip("control groups cannot be made here (not root, or read-only)")


def test_a_row_whose_grading_fails_leaves_no_control_group(monkeypatch, tmp_path):
    needs_a_sandbox()
    before = groups_left()

    def fails(*args, **kwargs):
        raise RuntimeError("the grader failed here")
    monkeypatch.setattr(runner, "check_all", fails)
    g = runner.grade_task((submissions.Handin("ann", "ann.ipynb", SOLUTION.read_text("utf-8")),
                           runner.Settings(plan.MIN_TIMEOUT)))
    assert g.status == "error" and "the grader failed here" in g.note
    assert groups_left() - before == set()


def test_a_sandbox_that_cannot_start_leaves_no_control_group(monkeypatch, tmp_path):
    needs_a_sandbox()
    before = groups_left()

    def cannot(*args, **kwargs):
        raise OSError("no such program")
    monkeypatch.setattr(sandbox.subprocess, "Popen", cannot)
    with pytest.raises(OSError):
        sandbox.start("run", {"total_memory": 1 << 30, "processes": 64}, tmp_path, True)
    assert groups_left() - before == set()
