"""python -m rbcourse grade: a class folder built from the solution notebook — a correct hand-in, a wrong one,
one that raises, one that loops, one that tries to write outside its sandbox — graded in one run; the CSV and
the feedback say exactly what each did, and no hand-in affects another.  Plus the pieces: the layouts, the CSV's
cells, Gradescope's results.json, the sandbox's environment, SUBMISSIONS' fingerprint, the language.  (The
hostile class, each hand-in an attack, is test_grade_hostile.py.)"""
import csv
import json
import os
import shutil
import subprocess
import sys
import uuid
from pathlib import Path

import numpy as np
import pytest
from helpers import processes_with

from rbcourse.workbook import exercises as ex
from rbcourse.workbook import grading
from rbcourse.workbook.exercises import MISTAKES
from rbcourse.workbook.grading import plan, report, runner, sandbox, submissions
from rbcourse.workbook.grading.checker import checks

pytestmark = pytest.mark.skipif(shutil.which("bwrap") is None, reason="bubblewrap (bwrap) is not installed: the "
                                "grader refuses to run without its sandbox (CI installs it)")

SOLUTION = Path(__file__).resolve().parents[2] / "notebooks" / "solutions" / "01_exercise_euler.ipynb"
TIMEOUT = 30                     # the cells get 20 s (runner.budgets), the checks 10 s
CHECKS = [name for name, _ in checks()]


def _code(cell_source: str) -> dict:
    return {"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
            "source": cell_source.splitlines(keepends=True)}


def edited(replace=(), after=None, insert=None) -> str:
    """The solution notebook with `old` replaced by `new` in its code (each pair must occur once), and a code
    cell `insert` added after the code cell holding `after`."""
    nb = json.loads(SOLUTION.read_text(encoding="utf-8"))
    cells = nb["cells"]
    for old, new in replace:
        hits = [c for c in cells if c["cell_type"] == "code" and old in "".join(c["source"])]
        assert len(hits) == 1, old
        hits[0]["source"] = "".join(hits[0]["source"]).replace(old, new).splitlines(keepends=True)
    if insert is not None:
        k = next(i for i, c in enumerate(cells) if c["cell_type"] == "code" and after in "".join(c["source"]))
        cells.insert(k + 1, _code(insert))
    return json.dumps(nb, ensure_ascii=False)


@pytest.fixture(scope="module")
def class_run(tmp_path_factory):
    """The class folder, graded once: (csv rows by student, feedback texts, paths, the loop's marker)."""
    root = tmp_path_factory.mktemp("class")
    subs, out, scratch = root / "SUBMISSIONS", root / "grades", root / "scratch"
    subs.mkdir()
    scratch.mkdir()                      # the grader's temporary folders go there (TMPDIR): none may be left
    marker = f"rbcourse-grade-test-{uuid.uuid4().hex}"
    (subs / "zoe.ipynb").write_text(SOLUTION.read_text(encoding="utf-8"), encoding="utf-8")        # correct
    (subs / "bob.ipynb").write_text(edited([("return P / M", "return P * M")]), encoding="utf-8")  # wrong v
    (subs / "carol").mkdir()                                          # the folder layout: carol/anything.ipynb
    (subs / "carol" / "exercise.ipynb").write_text(edited(
        [("    F, tau = np.zeros(3), np.zeros(3)\n", "    F, tau = np.zeros(3), np.zeros(3) / 0.0 + 1 // 0\n")],
        after="ex.check_velocity(velocity)", insert='raise RuntimeError("carol\'s own bug")'), encoding="utf-8")
    (subs / "carol" / "notes.txt").write_text("not a notebook")
    (subs / "dave.ipynb").write_text(edited(after="ex.check_velocity(velocity)", insert=(
        "import subprocess, sys\n"
        f"child = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(600)', '{marker}'])\n"
        "while True:\n    pass\n")), encoding="utf-8")
    (subs / "adam.ipynb").write_text(edited(after="ex.check_box_inertia(box_inertia)", insert=(
        "import os\n"
        f"os.remove({str(subs / 'zoe.ipynb')!r})\n"
        f"open({str(out / 'hacked.txt')!r}, 'w').write('a grade of 20/20 for everyone')\n")), encoding="utf-8")
    before = submissions.fingerprint(subs)
    run = subprocess.run([sys.executable, "-m", "rbcourse", "grade", str(subs), "--seed", "0", "--out", str(out / "grades.csv"),
                          "--timeout", str(TIMEOUT)], capture_output=True, text=True, timeout=600,
                         env={**os.environ, "RBCOURSE_QUICK": "1", "TMPDIR": str(scratch)})
    assert run.returncode == 0, run.stderr
    assert submissions.fingerprint(subs) == before
    with open(out / "grades.csv", encoding="utf-8", newline="") as f:
        rows = {r["student"]: r for r in csv.DictReader(f)}
    feedback = {p.stem: p.read_text(encoding="utf-8") for p in (out / "feedback").iterdir()}
    return rows, feedback, subs, out, marker, run.stdout, scratch


def test_one_row_per_student_with_the_columns(class_run):
    rows, feedback, *_ = class_run
    assert sorted(rows) == ["adam", "bob", "carol", "dave", "zoe"]
    assert list(next(iter(rows.values()))) == ["student", "status", *CHECKS, "passed", "protected", "note"]
    assert all(r["protected"] == "yes" for r in rows.values())
    assert sorted(feedback) == sorted(rows)
    for r in rows.values():
        assert int(r["passed"]) == [r[c] for c in CHECKS].count("passed")


def test_the_correct_hand_in_passes_everything_though_another_tried_to_delete_it(class_run):
    rows, feedback, subs, *_ = class_run
    assert (subs / "zoe.ipynb").exists()                   # adam tried to delete it: SUBMISSIONS is not in his sandbox
    zoe = rows["zoe"]
    assert zoe["status"] == "ok" and zoe["note"] == ""
    assert all(zoe[c] == "passed" for c in CHECKS) and zoe["passed"] == str(len(CHECKS))
    assert "**ok**" in feedback["zoe"] and f"Checks passed: {len(CHECKS)} of {len(CHECKS)}" in feedback["zoe"]
    assert "What to fix" not in feedback["zoe"]


def test_the_wrong_hand_in_is_named_by_its_mistake_and_slide(class_run):
    rows, feedback, *_ = class_run
    bob = rows["bob"]
    diagnosis = ex.check_velocity(lambda P, M: P * M, verbose=False).mistake     # what the check says of v = P·M
    assert diagnosis in MISTAKES
    assert bob["status"] == "ok" and bob["velocity"] == diagnosis and bob["note"] == ""
    for independent in ("box_inertia", "inverse_inertia", "angular_velocity", "resultants", "project_so3"):
        assert bob[independent] == "passed"
    assert bob["dxdt"] not in ("passed", "not-done", "not-run", "crashed")      # dxdt calls velocity: a mistake
    mistake = MISTAKES[diagnosis]
    text = feedback["bob"]
    assert f"### velocity — mistake `{diagnosis}`" in text and mistake.text in text
    assert f"Reread: the slide “{mistake.slide}”." in text


def test_the_hand_in_that_raises_goes_on_and_names_the_crash(class_run):
    rows, feedback, *_ = class_run
    carol = rows["carol"]
    assert carol["status"] == "error"
    assert carol["resultants"] == "crashed" and carol["velocity"] == "passed" and carol["project_so3"] == "passed"
    assert "RuntimeError: carol's own bug" in carol["note"] and "raise RuntimeError" in carol["note"]
    assert "ZeroDivisionError" in feedback["carol"] and "RuntimeError: carol's own bug" in feedback["carol"]


def test_the_hand_in_that_loops_is_interrupted_at_its_limit_and_its_children_killed(class_run):
    rows, feedback, _, _, marker, *_ = class_run
    dave = rows["dave"]
    cells, _ = runner.budgets(TIMEOUT)
    assert dave["status"] == "timeout" and f"was still running after {cells:g} s" in dave["note"]
    assert "(import subprocess, sys) was still running" in dave["note"]    # the cell that loops, by its first line
    assert dave["box_inertia"] == dave["velocity"] == "passed"            # checked again after the interrupt
    assert all(dave[c] == "not-run" for c in CHECKS[2:])                 # defined by cells that never ran
    assert f"was still running at its time limit ({cells:g} s)" in feedback["dave"] and "Not run" in feedback["dave"]
    assert processes_with(marker) == []                                  # its child died with it


def test_a_hand_in_that_ignores_the_interrupt_is_killed_with_its_children(tmp_path):
    marker = f"rbcourse-grade-test-{uuid.uuid4().hex}"
    nb = {"cells": [_code("from rbcourse.workbook import exercises as ex\n"
                          "def velocity(P, M):\n    return P / M"),
                    _code("import subprocess, sys, time\n"
                          f"child = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(600)', '{marker}'],"
                          " start_new_session=True)\n"
                          "while True:\n    try:\n        time.sleep(1)\n    except BaseException:\n        pass\n")],
          "metadata": {}, "nbformat": 4, "nbformat_minor": 5}
    handin = submissions.Handin("stubborn", "stubborn.ipynb", json.dumps(nb))
    g = runner.grade_one(handin, runner.Settings(plan.MIN_TIMEOUT))
    assert g.timed_out and g.status == "timeout" and not g.finished, (g.status, g.note, g.seconds)
    # its checked run killed at its cells' limit and grace, then its run with the library at its limit and grace
    cells, _ = runner.budgets(plan.MIN_TIMEOUT)
    assert cells + plan.MIN_TIMEOUT + 2 * runner.GRACE <= g.seconds < cells + plan.MIN_TIMEOUT + 2 * runner.GRACE + 8
    assert f"killed at {plan.MIN_TIMEOUT + runner.GRACE:g} s" in g.note
    # its functions are checked only if its checked run reports its cells: this one never does
    assert report.cell(g.checks.get("velocity"), report.stopped(g)) == "not-run"
    assert processes_with(marker) == []                 # its child, in a session of its own, died with its sandbox
    assert "killed 10 s after its start" in report.feedback_text(g, CHECKS)


def test_the_hand_in_that_writes_outside_cannot(class_run):
    rows, feedback, subs, out, _, printed, _ = class_run
    adam = rows["adam"]
    assert adam["status"] == "error" and "FileNotFoundError" in adam["note"]      # SUBMISSIONS is not in its sandbox
    assert all(adam[c] == "passed" for c in CHECKS)                      # graded all the same
    assert not (out / "hacked.txt").exists() and "20/20" not in (out / "grades.csv").read_text()
    for other in ("bob", "zoe"):
        assert rows[other]["status"] == "ok" and rows[other]["note"] == ""
    assert "graded 5 hand-ins: 2 ok, 2 error, 1 timeout" in printed


def test_no_worker_or_temporary_folder_is_left(class_run):
    scratch = class_run[-1]
    assert processes_with(str(scratch)) == []          # a worker's command line names its log in its folder
    assert list(scratch.iterdir()) == []


# --- the pieces ---------------------------------------------------------------------------------

def test_the_layouts(tmp_path):
    nb = json.dumps({"cells": [], "metadata": {}})
    (tmp_path / "ann.ipynb").write_text(nb)
    (tmp_path / "ben").mkdir()
    (tmp_path / "ben" / "sub").mkdir()
    (tmp_path / "ben" / "sub" / "mine.ipynb").write_text(nb)
    (tmp_path / "ben" / ".ipynb_checkpoints").mkdir()
    (tmp_path / "ben" / ".ipynb_checkpoints" / "mine-checkpoint.ipynb").write_text(nb)
    (tmp_path / "ben" / "notes.txt").write_text("")
    found = {h.name: h for h in submissions.read(tmp_path)}
    assert [(n, h.source, h.text is not None) for n, h in found.items()] == [("ann", "ann.ipynb", True),
                                                                             ("ben", "ben/sub/mine.ipynb", True)]
    (tmp_path / "ben" / "two.ipynb").write_text(nb)
    (tmp_path / "cat").mkdir()
    (tmp_path / "ann").mkdir()
    (tmp_path / "ann" / "x.ipynb").write_text(nb)
    (tmp_path / ".hidden.ipynb").write_text(nb)
    (tmp_path / "readme.txt").write_text("")
    found = submissions.read(tmp_path)
    problems = {(h.name, h.source): h.problem for h in found}
    assert all(h.text is None for h in found) and len(found) == 6
    assert "it holds 2: ben/sub/mine.ipynb, ben/two.ipynb" in problems[("ben", "ben/")]
    assert "it holds 0" in problems[("cat", "cat/")]
    assert "its name is also that of 'ann/x.ipynb'" in problems[("ann 'ann.ipynb'", "ann.ipynb")]   # each its name
    assert "its name is also that of 'ann.ipynb'" in problems[("ann 'ann'", "ann/x.ipynb")]
    assert "hidden" in problems[(".hidden", ".hidden.ipynb")]
    assert "extension is .txt" in problems[("readme.txt", "readme.txt")]


def test_the_cells_of_the_csv():
    assert report.cell({"passed": True, "mistake": None}, False) == "passed"
    assert report.cell({"passed": False, "mistake": "tau_sign"}, False) == "tau_sign"
    assert report.cell({"passed": False, "mistake": "not_done"}, False) == "not-done"
    assert report.cell({"passed": False, "mistake": "error"}, False) == "crashed"
    assert report.cell({"passed": False, "mistake": "out_of_time"}, False) == "timed-out"
    assert report.cell(None, True) == "not-run" and report.cell(None, False) == "not-done"


def test_gradescope_results_json():
    wrong = grading.outcome(ex.check_velocity(lambda P, M: P * M, verbose=False))
    right = grading.outcome(ex.check_box_inertia(lambda m, s: m / 12 * np.diag([s[1] ** 2 + s[2] ** 2, s[0] ** 2 + s[2] ** 2,
                                                                                s[0] ** 2 + s[1] ** 2]), verbose=False))
    g = runner.Graded("ann", "ok", checks={"velocity": wrong, "box_inertia": right}, seconds=3.21, finished=True)
    data = json.loads(report.gradescope(g, ["box_inertia", "velocity", "dxdt"]))
    assert data["score"] == 1.0 and data["max_score"] == 3.0 and data["execution_time"] == 3.2
    assert [(t["name"], t["score"], t["status"]) for t in data["tests"]] == [
        ("box_inertia", 1.0, "passed"), ("velocity", 0.0, "failed"), ("dxdt", 0.0, "failed")]
    assert MISTAKES[wrong["mistake"]].slide in data["tests"][1]["output"]
    assert data["tests"][2]["output"] == "not-done"


def test_the_environment_of_a_hand_in_is_reduced(monkeypatch):
    monkeypatch.setenv("SECRET_TOKEN", "x")
    monkeypatch.setenv("RBCOURSE_QUICK", "1")
    env = sandbox.environment("/tmp/home", "/tmp")
    assert "SECRET_TOKEN" not in env and env["RBCOURSE_QUICK"] == "1"
    assert env["HOME"] == "/tmp/home" and env["TMPDIR"] == "/tmp" and env["MPLBACKEND"] == "Agg"


def test_a_change_in_submissions_is_seen(tmp_path):
    (tmp_path / "a").write_text("1")
    before = submissions.fingerprint(tmp_path)
    stamp = (tmp_path / "a").stat()
    (tmp_path / "a").write_text("2")                          # same size, and the same time again: still seen
    os.utime(tmp_path / "a", ns=(stamp.st_atime_ns, stamp.st_mtime_ns))
    (tmp_path / "b").mkdir()
    assert submissions.changes(before, submissions.fingerprint(tmp_path)) == ["modified a", "created b"]


# --- the hand-in's language ---------------------------------------------------------------------

def _notebook(*sources, metadata=None) -> str:
    return json.dumps({"cells": [_code(s) for s in sources], "metadata": metadata or {}, "nbformat": 4,
                       "nbformat_minor": 5}, ensure_ascii=False)


def test_the_language_of_a_hand_in_is_its_langue_call_else_its_metadata():
    call = "from rbcourse.workbook import exercises as ex\nex.langue(\"fr\")"
    assert runner.notebook_language(_notebook(call)) == "fr"
    assert runner.notebook_language(_notebook("ex.language('fr')", "ex.langue('en')")) == "en"     # the last call
    assert runner.notebook_language(_notebook("x = 1", metadata={"rbcourse": {"language": "fr"}})) == "fr"
    assert runner.notebook_language(_notebook("ex.langue('en')", metadata={"rbcourse": {"language": "fr"}})) == "en"
    assert runner.notebook_language(_notebook("ex.langue('de')")) == "en"                   # not a language we have
    assert runner.notebook_language(_notebook("x = 1", metadata={"kernelspec": {"language": "python"}})) == "en"
    assert runner.notebook_language("not json") == "en"


FRENCH_HANDIN = ("from rbcourse.workbook import exercises as ex\nex.langue(\"fr\")",
                 "def velocity(P, M):\n    return P * M",
                 "ex.check_velocity(velocity)",
                 "def box_inertia(mass, size):\n    raise NotImplementedError")


@pytest.mark.parametrize("how", ["call", "metadata"])
def test_a_french_hand_in_gets_french_feedback(tmp_path, how):
    """The worker runs in the hand-in's language: the checks' messages, the slide to reread and the feedback's
    own words are French; the CSV's cells are the same ids as in English."""
    no_call = ["from rbcourse.workbook import exercises as ex", *FRENCH_HANDIN[1:]]      # French by its metadata
    sources = FRENCH_HANDIN if how == "call" else no_call
    nb = _notebook(*sources, metadata={"rbcourse": {"language": "fr"}} if how == "metadata" else None)
    g = runner.grade_one(submissions.Handin("eve", "eve.ipynb", nb), runner.Settings(plan.MIN_TIMEOUT * 4))
    assert g.language == "fr" and g.finished, g.note
    assert report.cell(g.checks["velocity"], False) == "velocity_times_mass"        # language-neutral CSV
    ex.langue("fr")
    try:
        french_text = MISTAKES["velocity_times_mass"].text
    finally:
        ex.langue("en")
    text = report.feedback_text(g, CHECKS)
    assert "# Retour sur votre notebook d'exercice — eve" in text
    assert "### velocity — erreur `velocity_times_mass`" in text and french_text in text
    assert "✗ velocity : v = P / M : vous avez multiplié P par M" in text
    assert "À relire : la slide « Evolution temporelle (Euler) »." in text
    assert "○ box_inertia : pas encore écrite" in text and "Vérifications réussies : 0 sur" in text
    assert "## À corriger" in text and "Pas encore fait" in text
    for english in ("What to fix", "Reread", "mistake `", "not done", "you multiplied"):
        assert english not in text, english
    assert "the slide" not in report.csv_text([g], CHECKS)


def test_an_english_hand_in_keeps_english_feedback(tmp_path):
    nb = _notebook("from rbcourse.workbook import exercises as ex", *FRENCH_HANDIN[1:])
    g = runner.grade_one(submissions.Handin("ann", "ann.ipynb", nb), runner.Settings(plan.MIN_TIMEOUT * 4))
    assert g.language == "en"
    text = report.feedback_text(g, CHECKS)
    assert "✗ velocity: v = P / M: you multiplied P by M" in text and "Reread: the slide “Evolution temporelle (Euler)”." in text


# --- who grades: one process, two workers, a Dask cluster: the same CSV ---------------------------------------

def _class_for_the_workers(subs: Path) -> None:
    subs.mkdir()
    (subs / "zoe.ipynb").write_text(SOLUTION.read_text(encoding="utf-8"), encoding="utf-8")
    (subs / "ann.ipynb").write_text(_notebook("import numpy as np\nimport rbcourse as rb",
                                              "def velocity(P, M):\n    return P / M",
                                              "def box_inertia(mass, size):\n    return rb.RigidBody.box(mass, size).I_body"))
    (subs / "ben.ipynb").write_text(_notebook("def velocity(P, M):\n    return P * M", "1 / 0"))
    (subs / "junk.ipynb").write_text("{ not json")


def test_two_workers_and_a_dask_cluster_write_the_same_csv_as_one_process(tmp_path):
    from dask.distributed import Client, LocalCluster
    subs = tmp_path / "SUBMISSIONS"
    _class_for_the_workers(subs)

    def graded(label, **who):
        p = plan.check_arguments(subs, tmp_path / label / "grades.csv", TIMEOUT, **who)
        plan.grade(p, progress=None)
        return (tmp_path / label / "grades.csv").read_text(encoding="utf-8")
    serial = graded("serial", workers=1)
    rows = {r["student"]: r for r in csv.DictReader(serial.splitlines())}
    assert rows["zoe"]["passed"] == "10" and rows["junk"]["status"] == "invalid"
    assert rows["ann"]["velocity"] == "passed" and rows["ann"]["box_inertia"] == "library_call"
    assert rows["ben"]["status"] == "error" and rows["ben"]["velocity"] == "velocity_times_mass"
    assert graded("two", workers=2) == serial
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        assert graded("dask", scheduler=client) == serial


def test_the_methods_compiled_for_the_sandboxes_are_the_exercises():
    """The grader compiles the exercise's methods once for the sandboxes (plan.engine_cache); they are those the
    notebook runs."""
    import re
    code = "".join("".join(c["source"]) for c in json.loads(SOLUTION.read_text(encoding="utf-8"))["cells"])
    used = set(re.findall(r'(?:method|reference)="([a-z_0-9]+)"', code)) | {"euler"}    # simulate_or_reference's
    assert len(used) >= 5
    assert used == set(plan.EXERCISE_METHODS)


def test_a_failure_of_the_grader_on_one_hand_in_is_that_hand_ins_row(monkeypatch):
    def no_room(*args, **kwargs):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(sandbox, "start", no_room)
    g = runner.grade_task((submissions.Handin("ann", "ann.ipynb", _notebook("x = 1")), runner.Settings(plan.MIN_TIMEOUT)))
    assert g.status == "error" and "the grader failed on this hand-in (OSError" in g.note
    assert report.cell(g.checks.get("velocity"), report.stopped(g)) == "not-run"
