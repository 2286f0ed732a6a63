"""The compile-cost report (`python -m rbcourse throughput --compile`): the notice's figure read in any language, the
tables from made-up timings (a failed cell, a missing notice), the verdicts against the targets, and its arguments
checked before anything runs.  Nothing here compiles: the measurements are replaced."""
import subprocess

import pytest

from rbcourse.__main__ import main
from rbcourse.bench import compile_cost as cost
from rbcourse.bench.compile_cost import Cell


@pytest.mark.parametrize("stderr, seconds", [
    ("compiling the engine for this machine, once (~12 s)…\n", 12.0),
    ("compilation du moteur pour cette machine, une seule fois (~12 s)…\n", 12.0),
    ("Kompilieren der Engine für diesen Rechner, einmalig (~7 s)…", 7.0),        # the figure, not the words
    ("compilation du moteur pour cette machine, une seule fois (~2,5 s)…", 2.5),  # a decimal comma
    ("compiling the engine for this machine, once (~9 s)…\nsome warning\n"
     "compiling the engine for this machine, once (~12 s)…\n", 21.0),             # two families: summed
    ("", None),
    ("wrote demo_output/pushed_box.png\nUserWarning: ~12 s\n", None),             # no "(~N s)"
])
def test_the_notice_figure_is_read_in_any_language(stderr, seconds):
    assert cost.notice_seconds(stderr) == seconds


def test_ratios_and_verdicts():
    assert cost.ratio(30.0, 2.0) == 15.0 and cost.ratio(None, 2.0) is None and cost.ratio(3.0, None) is None
    assert cost.ratio(3.0, 0.0) is None
    assert cost.verdict(15.0, 15.0) == "yes" and cost.verdict(15.1, 15.0) == "no"
    assert cost.verdict(3.0, None) == "—" and cost.verdict(None, 15.0) == "—"
    # the notice: within ×2 either way
    assert cost.notice_verdict(24.0, 12.0) == "yes" and cost.notice_verdict(6.0, 12.0) == "yes"
    assert cost.notice_verdict(24.1, 12.0) == "no" and cost.notice_verdict(5.9, 12.0) == "no"
    assert cost.notice_verdict(10.0, None) == "—"
    # the targets stated: a free box 15× for euler and rk4 only, the ground 30× for every family, the demo 20×
    assert cost.TARGETS[("free", "euler")] == cost.TARGETS[("free", "rk4")] == 15.0
    assert ("free", "adaptive") not in cost.TARGETS and cost.TARGETS[("ground", "exact_splitting")] == 30.0
    assert cost.TARGET_DEMO == 20.0
    assert cost.failure(subprocess.TimeoutExpired(["python"], 900.0)) == "timed out after 900 s"
    assert cost.failure(RuntimeError("exit code 1: ImportError:\n no numba")) == \
        "failed: RuntimeError: exit code 1: ImportError: no numba"


def test_the_table_from_made_up_timings():
    cells = {("euler", "free"): Cell(cold=12.0, warm=1.0, estimate=9.0, ran_on="compiled"),     # 12×, notice 1.3×
             ("euler", "ground"): Cell(cold=40.0, warm=1.0, estimate=None, ran_on="compiled"),  # 40×, no notice
             ("rk4", "free"): Cell(why="cold: timed out after 900 s"),
             ("adaptive", "free"): Cell(cold=50.0, warm=2.0, estimate=16.0, ran_on="compiled")}
    lines = cost.table(cells, Cell(cold=30.0, warm=1.2, estimate=12.0, ran_on="—"))
    text = "\n".join(lines)
    rows = {" / ".join(line.split(" | ")[:2]).lstrip("| "): line for line in lines if line.startswith("| ")}
    free, ground = rows["euler (euler) / free box"], rows["euler (euler) / box on the ground"]
    assert free.endswith("| 12.00 s | 1.00 s | 12.0× | ≤ 15× | yes | ~9 s | 1.3× | yes | compiled |")
    assert ground.endswith("| 40.0× | ≤ 30× | no | no notice | — | — | compiled |")
    assert "| free box | cold: timed out after 900 s |" in rows["rk4 (explicit_quat) / free box"]
    # no target; the notice off by more than ×2
    assert "| 25.0× | — | — | ~16 s | 3.1× | no |" in rows["adaptive (adaptive) / free box"]
    assert "| 30.00 s | 1.20 s | 25.0× | ≤ 20× | no | ~12 s | 2.5× | no |" in text                # the demo
    # every row of a table has as many cells as its header
    for block in text.split("\n\n"):
        table = [line for line in block.splitlines() if line.startswith("|")]
        assert len({line.count("|") for line in table}) <= 1, table
    assert "## The demo" in text and "≤ 15×" in text and "≤ 30×" in text and "×2" in text


def test_a_failed_demo_a_remark_and_no_demo():
    lines = cost.table({}, Cell(cold=None, why="cold: failed: RuntimeError: exit code 1: boom"))
    assert lines[-1] == "| cold: failed: RuntimeError: exit code 1: boom |" + "  |" * 7      # 8 columns
    lines = cost.table({("rk4", "free"): Cell(cold=9.0, warm=9.0, why="the warm process compiled again", ran_on="c")},
                       None)
    assert lines[-2].endswith("| 9.00 s | 9.00 s | 1.0× | ≤ 15× | yes | no notice | — | — | c |")
    assert lines[-1] == "|  |  | note: the warm process compiled again |" + "  |" * 8       # 11 columns
    assert "## The demo" not in "\n".join(lines)


def test_main_measures_each_cell_once_in_order_and_reports(monkeypatch):
    seen = []

    def measure(method, scene):
        seen.append((method, scene))
        if method == "rk4":
            raise AssertionError("only the methods asked for are measured")
        return Cell(cold=5.0, warm=0.5, estimate=9.0, ran_on="compiled")
    text = cost.main(["euler"], measure=measure, measure_demo=lambda: Cell(cold=8.0, warm=0.8))
    assert seen == [("euler", "free"), ("euler", "ground")]
    assert text.startswith("# Compile cost") and "numba " in text and "load average" in text
    assert "Python " in text and "measured in" in text and "10.0×" in text


def test_check_methods():
    assert cost.check_methods(None) == list(cost.FAMILIES)
    assert cost.check_methods("rk4, euler,rk4") == ["rk4", "euler"]
    with pytest.raises(ValueError, match="choose among " + ", ".join(cost.FAMILIES)):
        cost.check_methods("nosuch")


@pytest.mark.parametrize("argv, word", [
    (["throughput", "--compile", "--methods", "nosuch"], ", ".join(cost.FAMILIES)),
    (["throughput", "--compile", "--methods", ""], "--methods"),
    (["throughput", "--methods", "euler"], "--compile"),
    (["throughput", "--compile", "--quick"], "--quick"),
])
def test_bad_compile_arguments_are_one_line_and_exit_code_2(argv, word, monkeypatch, tmp_path, capsys):
    def forbidden(*args, **kwargs):
        raise AssertionError("a bad argument must be refused before anything is measured")
    monkeypatch.setattr(cost, "main", forbidden)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and "python -m rbcourse throughput: error: " in err and word in err, err
    assert list(tmp_path.iterdir()) == []                      # not even the output folder


def test_compile_writes_its_report(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(cost, "main", lambda methods: f"# Compile cost\n\n{','.join(methods)}\n")
    assert main(["throughput", "--compile", "--methods", "euler", "--out", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    assert (tmp_path / "compile_cost.md").read_text() == "# Compile cost\n\neuler\n"
    assert f"wrote {tmp_path / 'compile_cost.md'}" in printed and not (tmp_path / "throughput.md").exists()
