"""A neighbour that forks many busy processes cannot make a hand-in graded beside it time out (issue 44, item 4): each
sandbox is a control group of the cpu controller (grading/cgroups.py), which shares the processors between sandboxes,
not between their processes, and each sandbox's processor time is counted."""
import json
import os
import shutil

import pytest

from rbcourse.workbook.grading import cgroups, plan

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SOLUTION = os.path.join(ROOT, "notebooks", "solutions", "01_exercise_euler.ipynb")
HOG = ("import subprocess, sys\n"
       "for _ in range(60):\n"
       "    try:\n"
       "        subprocess.Popen([sys.executable, '-c', 'while True: pass'], start_new_session=True)\n"
       "    except OSError:\n"
       "        break\n"
       "while True:\n"
       "    pass\n")


def _cpu_groups() -> bool:
    folders = cgroups.made(1 << 30, 64)
    try:
        return any(f.parent.name == "cpu" or "cpu" in f.parts for f in folders)
    finally:
        cgroups.remove(folders)


pytestmark = [pytest.mark.skipif(shutil.which("bwrap") is None, reason="bubblewrap (bwrap) is not installed"),
              pytest.mark.skipif(not _cpu_groups(), reason="the kernel's cpu control groups cannot be written here "
                                 "(the grader is not root): a neighbour's processes share the processors with it")]


def test_a_neighbour_that_forks_busy_processes_changes_no_mark(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    nb = {"cells": [{"cell_type": "code", "source": HOG, "metadata": {}, "outputs": [], "execution_count": None}],
          "metadata": {}, "nbformat": 4, "nbformat_minor": 5}
    (subs / "a_hog.ipynb").write_text(json.dumps(nb))
    shutil.copyfile(SOLUTION, subs / "b_honest.ipynb")
    # a limit of 15 s: the honest notebook's cells get 10 s, about 7 times what they take alone (at the smallest
    # limit, 3.3 s for its cells, 2.5 times, it timed out beside the hog in one CI run of three: a kernel's start and
    # imports on one processor, the caches shared with 61 busy processes); shared process by process instead, they
    # would get a thirtieth of the machine, some 40 s for their 1.3 s
    the_plan = plan.check_arguments(subs, tmp_path / "out" / "grades.csv", timeout=3 * plan.MIN_TIMEOUT,
                                    feedback=tmp_path / "out" / "feedback", workers=2)
    graded, _ = plan.grade(the_plan, progress=None)
    hog, honest = graded
    assert honest.status == "ok" and honest.finished, honest.note
    assert all(o.get("passed") for o in honest.checks.values()) and len(honest.checks) == 10
    assert hog.status == "timeout"
    # each one's processor time is counted: the hog's sandboxes held at most one processor each for their time
    assert honest.cpu_seconds is not None and 0 < honest.cpu_seconds < honest.seconds
    assert hog.cpu_seconds is not None and hog.cpu_seconds <= hog.seconds * cgroups.CPUS + 1.0
