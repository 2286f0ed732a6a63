"""python -m rbcourse grade: a bad argument is one line on stderr and exit code 2, before any hand-in runs
and with nothing written; so is a machine without the sandbox, unless --no-sandbox is given (then the grades
say they are not protected)."""
import csv
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from rbcourse.__main__ import main
from rbcourse.workbook.grading import plan, runner

PROG = "python -m rbcourse grade"

# {subs}: a folder with two hand-ins; {one}: a folder with one; {empty}: an empty folder; {file}: a file;
# {out}: a folder that does not exist yet.  (A hand-in folder with two notebooks is a row "invalid", not an error.)
BAD = [
    (["{out}/nothing", "--out", "{out}/g.csv"], "does not exist"),
    (["{file}", "--out", "{out}/g.csv"], "not a folder"),
    (["", "--out", "{out}/g.csv"], "SUBMISSIONS"),
    (["{empty}", "--out", "{out}/g.csv"], "no hand-in"),
    (["{subs}"], "--out"),
    (["{subs}", "--out", ""], "--out"),
    (["{subs}", "--out", "{empty}"], "is a folder"),
    (["{subs}", "--out", "{file}/g.csv"], "--out"),
    (["{subs}", "--out", "/proc/x/g.csv"], "--out"),
    (["{subs}", "--out", "{subs}/g.csv"], "inside SUBMISSIONS"),
    (["{subs}", "--out", "{out}/g.csv", "--timeout", "0"], "--timeout"),
    (["{subs}", "--out", "{out}/g.csv", "--timeout", "-1"], "--timeout"),
    (["{subs}", "--out", "{out}/g.csv", "--timeout", "nan"], "--timeout"),
    (["{subs}", "--out", "{out}/g.csv", "--timeout", "ten"], "--timeout"),
    (["{subs}", "--out", "{out}/g.csv", "--timeout", "4"], "--timeout must be from 5 to 3600"),
    (["{subs}", "--out", "{out}/g.csv", "--timeout", "3601"], "--timeout must be from 5 to 3600"),
    (["{subs}", "--out", "{out}/g.csv", "--feedback", "{file}"], "--feedback"),
    (["{subs}", "--out", "{out}/g.csv", "--feedback", "{subs}/fb"], "inside SUBMISSIONS"),
    (["{subs}", "--out", "{out}/g.csv", "--feedback", "/proc/x"], "--feedback"),
    (["{subs}", "--out", "{out}/g.csv", "--gradescope", "{out}/results.json"], "one submission"),
    (["{one}", "--out", "{out}/g.csv", "--gradescope", "{empty}"], "--gradescope"),
    (["{one}", "--out", "{out}/g.csv", "--gradescope", "/proc/x/results.json"], "--gradescope"),
    (["{subs}", "--out", "{out}/g.csv", "--frobnicate"], "--frobnicate"),
    (["{subs}", "--out", "{out}/g.csv", "--workers", "0"], "--workers) must be an integer >= 1, got 0"),
    (["{subs}", "--out", "{out}/g.csv", "--workers", "two"], "--workers) must be an integer >= 1, got 'two'"),
    (["{subs}", "--out", "{out}/g.csv", "--timeout", "true"], "--timeout"),
    ([], "SUBMISSIONS"),
]


@pytest.fixture
def folders(tmp_path, monkeypatch):
    def forbidden(*args, **kwargs):
        raise AssertionError("a bad argument must be refused before any hand-in runs")
    monkeypatch.setattr(runner, "grade_one", forbidden)
    monkeypatch.setattr(plan, "grade", forbidden)
    monkeypatch.chdir(tmp_path)
    subs, one, empty = (tmp_path / n for n in ("subs", "one", "empty"))
    for f in (subs, one, empty):
        f.mkdir(parents=True)
    (subs / "ann.ipynb").write_text("{}")
    (subs / "ben.ipynb").write_text("{}")
    (one / "ann.ipynb").write_text("{}")
    (tmp_path / "a_file").write_text("not a folder")
    return {"subs": subs, "one": one, "empty": empty, "file": tmp_path / "a_file", "out": tmp_path / "out"}


@pytest.mark.parametrize("argv, word", BAD, ids=[" ".join(a) or "(none)" for a, _ in BAD])
def test_a_bad_argument_is_one_line_and_exit_code_2_before_anything_runs(argv, word, folders, tmp_path, capsys):
    if any("/proc/x" in a for a in argv) and not Path("/proc").is_dir():
        pytest.skip("no /proc on this system")
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    with pytest.raises(SystemExit) as info:
        main(["grade", *(a.format(**folders) for a in argv)])
    assert info.value.code == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and err.startswith(f"{PROG}: error: ") and word in err, err
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before     # nothing written


def test_from_a_fresh_process(tmp_path):
    (tmp_path / "empty").mkdir()
    run = subprocess.run([sys.executable, "-m", "rbcourse", "grade", str(tmp_path / "empty"), "--out",
                          str(tmp_path / "g.csv")], capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and run.stdout == "" and not (tmp_path / "g.csv").exists()
    assert len(run.stderr.splitlines()) == 1 and run.stderr.startswith(f"{PROG}: error: SUBMISSIONS: no hand-in")


def test_an_unreachable_scheduler_is_one_line(folders, tmp_path, capsys):
    with pytest.raises(SystemExit) as info:
        main(["grade", str(folders["subs"]), "--out", str(tmp_path / "out" / "g.csv"), "--scheduler",
              "tcp://127.0.0.1:9"])
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.count("\n") == 1 and "scheduler: cannot reach a Dask scheduler" in err


def _one_notebook(folder: Path) -> None:
    folder.mkdir()
    cells = [{"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
              "source": "import os\ndef velocity(P, M):\n    return P / M\nprint(sorted(os.environ))"}]
    (folder / "ann.ipynb").write_text(json.dumps({"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 5}))


def test_without_bubblewrap_grade_refuses_unless_told(tmp_path):
    """No bwrap on the PATH: one line saying how to install it, exit 2, nothing written; with --no-sandbox the
    class is graded, and stderr and every row say that the grades are not protected."""
    _one_notebook(tmp_path / "subs")
    (tmp_path / "empty_bin").mkdir()
    env = {**os.environ, "PATH": str(tmp_path / "empty_bin"), "RBCOURSE_QUICK": "1"}
    command = [sys.executable, "-m", "rbcourse", "grade", str(tmp_path / "subs"), "--out", str(tmp_path / "g.csv")]
    run = subprocess.run(command, capture_output=True, text=True, timeout=120, env=env)
    assert run.returncode == 2 and run.stdout == "" and not (tmp_path / "g.csv").exists()
    assert len(run.stderr.splitlines()) == 1 and "bubblewrap (bwrap) is not installed" in run.stderr
    assert "apt-get install bubblewrap" in run.stderr and "--no-sandbox" in run.stderr
    run = subprocess.run(command + ["--no-sandbox", "--workers", "1"], capture_output=True, text=True, timeout=300,
                         env=env)
    assert run.returncode == 0, run.stderr
    assert "the grades are not protected" in run.stderr
    (row,) = csv.DictReader(open(tmp_path / "g.csv", encoding="utf-8"))
    assert row["protected"] == "no" and "not protected" in row["note"] and row["velocity"] == "passed"
