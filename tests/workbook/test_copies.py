"""`python -m rbcourse notebooks`: the student's copies (rbcourse/workbook/copies.py) — copied once, never
overwritten; a course notebook changed since is written beside as NAME.updated.ipynb; a bad --to is one line."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

from rbcourse.workbook import copies

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def course(tmp_path):
    """A small workbook standing for notebooks/: two notebooks, a French one, a solution."""
    src = tmp_path / "course"
    for rel in ("00_a.ipynb", "01_b.ipynb", "fr/00_a.ipynb", "solutions/01_b.ipynb"):
        (src / rel).parent.mkdir(parents=True, exist_ok=True)
        (src / rel).write_text(json.dumps({"cells": [], "name": rel}), encoding="utf-8")
    return src


def test_copies_every_notebook_but_the_solutions(course, tmp_path):
    to = tmp_path / "mine"
    done = copies.copy_workbook(to, source=course)
    assert sorted(Path(p).relative_to(to).as_posix() for what, p in done if what == "copied") == \
        ["00_a.ipynb", "01_b.ipynb", "fr/00_a.ipynb"]
    assert (to / "fr/00_a.ipynb").read_bytes() == (course / "fr/00_a.ipynb").read_bytes()
    assert not (to / "solutions").exists()
    done = copies.copy_workbook(to, solutions=True, source=course)
    assert ("copied", str(to / "solutions/01_b.ipynb")) in done


def test_a_rerun_keeps_the_students_edits_and_puts_a_newer_version_beside(course, tmp_path):
    to = tmp_path / "mine"
    copies.copy_workbook(to, source=course)
    (to / "00_a.ipynb").write_text("my work", encoding="utf-8")
    done = copies.copy_workbook(to, source=course)
    assert {what for what, _ in done} == {"kept"}
    assert (to / "00_a.ipynb").read_text(encoding="utf-8") == "my work"
    (course / "00_a.ipynb").write_text('{"cells": [], "v": 2}', encoding="utf-8")      # the course changes it
    done = copies.copy_workbook(to, source=course)
    assert ("updated", str(to / "00_a.updated.ipynb")) in done
    assert (to / "00_a.ipynb").read_text(encoding="utf-8") == "my work"
    assert (to / "00_a.updated.ipynb").read_text(encoding="utf-8") == '{"cells": [], "v": 2}'
    assert "00_a.updated.ipynb" in copies.report(done, to)
    (to / "01_b.ipynb").unlink()                                                         # deleted: copied again
    assert ("copied", str(to / "01_b.ipynb")) in copies.copy_workbook(to, source=course)


def test_bad_to_is_refused_naming_it(course, tmp_path):
    a_file = tmp_path / "file"
    a_file.write_text("x")
    with pytest.raises(ValueError, match="--to must be a folder, but .* is a file"):
        copies.copy_workbook(a_file, source=course)
    with pytest.raises(ValueError, match="--to must be a folder outside the workbook"):
        copies.copy_workbook(course / "fr", source=course)
    with pytest.raises(ValueError, match="solutions must be True or False"):
        copies.copy_workbook(tmp_path / "x", solutions="yes", source=course)


def test_the_command_copies_the_real_workbook_and_refuses_a_file(tmp_path):
    run = [sys.executable, "-m", "rbcourse", "notebooks"]
    out = subprocess.run(run, cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "my_notebooks/02_drift.ipynb").read_bytes() == (ROOT / "notebooks/02_drift.ipynb").read_bytes()
    assert (tmp_path / "my_notebooks/fr/02_derive.ipynb").is_file()
    assert not (tmp_path / "my_notebooks/solutions").exists()
    assert "copied" in out.stdout and "0 with a newer version" in out.stdout
    (tmp_path / "f").write_text("x")
    bad = subprocess.run(run + ["--to", "f"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "--to must be a folder" in bad.stderr
    assert "my_notebooks/" in (ROOT / ".gitignore").read_text().splitlines()
