"""python -m rbcourse explore: a bad argument is one line and exit code 2 before anything is computed or
written; a good run writes SCENE_explorer.html into --out (demo_output by default), and says so."""
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from rbcourse.__main__ import main
from rbcourse.viz.explorer import runs

PROG = "python -m rbcourse explore"

BAD = [
    (["no_such_scene"], "scene"),
    ([""], "scene"),
    (["--methods", "verlet"], "--methods"),
    (["--methods"], "--methods"),
    (["--methods", "rk4", "rk4"], "--methods"),
    (["--methods", "euler", "euler_project", "quaternion_euler", "rk4", "rkmk4", "splitting", "adaptive"], "at most 6"),
    (["--dts", "0"], "--dts"),
    (["--dts", "-0.01"], "--dts"),
    (["--dts", "nan"], "--dts"),
    (["--dts", "fast"], "--dts"),
    (["--dts"], "--dts"),
    (["--dts", "0.1", "0.05", "0.02", "0.01", "0.005", "0.002", "0.001"], "at most 6"),
    (["--dts", "10"], "--dts"),                                       # longer than the scene's 5 s
    (["--dts", "1e-7"], "MAX_STEPS"),
    (["--t-end", "1e308", "--dts", "1e-300"], "gives inf steps"),     # t_end / dt overflows: no OverflowError
    (["--dts", "1e-300"], "gives 5e+300 steps × 1 body"),               # a count, not 300 digits
    (["--dts", "0.01", "0.0100001"], "--dts"),
    (["--t-end", "0"], "--t-end"),
    (["--t-end", "inf"], "--t-end"),
    (["--t-end", "0.01"], "--t-end"),                                 # shorter than the default steps
    (["many_bodies", "--methods", "euler", "splitting", "rk4", "rkmk4", "adaptive", "exact_splitting",
      "--dts", "0.04", "0.02", "0.01", "0.005", "0.004", "0.002"], "200 bodies"),
    (["--out", "{file}"], "--out"),
    (["--out", "{file}/sub"], "--out"),
    (["--out", ""], "--out"),
    (["--out", "{tmp}/has_a_folder"], "is a folder"),                 # pushed_box_explorer.html there is a folder
    (["--frobnicate"], "--frobnicate"),
    (["tennis_racket", "stray"], "stray"),
]


@pytest.fixture
def nothing_runs(monkeypatch, tmp_path):
    def forbidden(*args, **kwargs):
        raise AssertionError("a bad argument must be refused before anything is computed")
    monkeypatch.setattr(runs, "run_grid", forbidden)
    monkeypatch.setattr(runs, "simulate", forbidden)
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    return cwd


@pytest.mark.parametrize("argv, word", BAD, ids=[" ".join(a) or "(none)" for a, _ in BAD])
def test_a_bad_argument_is_one_line_and_exit_code_2_before_anything_runs(argv, word, tmp_path, nothing_runs, capsys):
    afile, folder = tmp_path / "a_file", tmp_path / "folder"
    afile.write_text("not a folder")
    (folder / "has_a_folder" / "pushed_box_explorer.html").mkdir(parents=True)
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    with pytest.raises(SystemExit) as info:
        main(["explore", *(a.format(file=afile, tmp=folder) for a in argv)])
    assert info.value.code == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and err.startswith(f"{PROG}: error: ") and word in err, err
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before     # nothing written


def test_explore_writes_the_page_of_a_named_scene(tmp_path, capsys):
    out = tmp_path / "pages"
    assert main(["explore", "tennis_racket", "--methods", "euler", "rk4", "--dts", "0.05", "0.025",
                 "--t-end", "1", "--out", str(out)]) == 0
    page = out / "tennis_racket_explorer.html"
    printed = capsys.readouterr().out
    assert f"wrote {page}" in printed and "rk4" in printed and "euler" in printed
    html = page.read_text(encoding="utf-8")
    from tests.viz.test_explorer import page_json
    data = page_json(html)
    assert [m["name"] for m in data["methods"]] == ["euler", "rk4"] and data["dts"] == [0.05, 0.025]
    assert data["t_end"] == 1.0 and data["name"] == "tennis racket" and data["reference"]["exact"]
    assert sorted(p.name for p in out.iterdir()) == ["tennis_racket_explorer.html"]


def test_the_default_folder_is_demo_output_beside_the_demo(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["explore", "box_on_spring", "--methods", "rk4", "--dts", "0.05", "--t-end", "0.5"]) == 0
    assert (tmp_path / "demo_output" / "box_on_spring_explorer.html").is_file()


def test_a_bad_argument_from_a_fresh_process(tmp_path):
    run = subprocess.run([sys.executable, "-m", "rbcourse", "explore", "--dts", "0", "--out", str(tmp_path / "x")],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and run.stdout == "" and not (tmp_path / "x").exists()
    assert len(run.stderr.splitlines()) == 1 and run.stderr.startswith(f"{PROG}: error: argument --dts: "), run.stderr
