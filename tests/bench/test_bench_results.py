"""Reading a benchmark's saved results back (bench.read_csv, bench.read_results) and drawing them
(plots.work_precision_png, plots.plot_work_precision): what notebook 03 shows of a full `python -m rbcourse bench`."""
import math

import pytest

from rbcourse.bench import work_precision as bench
from rbcourse.bench.runs import Run
from rbcourse.viz import plots

RUNS = [Run("A", "rbcourse", "rk4", 0.01, 2000, 0.0123, 5.8e-7),
        Run("A", "rbcourse", "euler", 0.25, 80, 0.0004, math.inf),
        Run("C", "scipy", "DOP853", 1e-9, 812, 0.25, 2.1e-8)]


def test_results_read_back_as_written(tmp_path):
    bench.write_csv(RUNS, tmp_path / "results.csv")
    (tmp_path / "results.md").write_text(bench.markdown(RUNS), encoding="utf-8")
    runs, partial = bench.read_results(tmp_path)
    assert partial == ""
    assert runs == RUNS                       # csv_row keeps 6 digits: these values survive it exactly
    assert runs[1].error == math.inf and runs[0].label == "rk4" and runs[2].label == "scipy DOP853"


def test_a_partial_sweep_is_read_and_said(tmp_path):
    bench.write_csv(RUNS[:2], tmp_path / "results.csv")
    with open(tmp_path / "results.csv", "a", encoding="utf-8") as f:
        f.write("C,scipy,DOP8")                # the row being written when the file was read
    (tmp_path / "results.md").write_text("# partial: interrupted after 2 of 9 planned runs (results.csv holds them)\n")
    runs, partial = bench.read_results(tmp_path)
    assert runs == RUNS[:2]
    assert partial == "interrupted after 2 of 9 planned runs"


def test_what_is_not_a_results_csv_is_refused(tmp_path):
    path = tmp_path / "results.csv"
    path.write_text("a,b,c\n1,2,3\n")
    with pytest.raises(ValueError, match="must begin with the header"):
        bench.read_csv(path)
    path.write_text(bench.CSV_HEADER + "\nA,rbcourse,rk4,x,1,1,1\nA,rbcourse,rk4,0.1,1,1,1\n")
    with pytest.raises(ValueError, match="line 2"):
        bench.read_csv(path)


def test_the_work_precision_figure_as_png():
    png = plots.work_precision_png(RUNS, note="partial: a test")
    assert png.startswith(b"\x89PNG\r\n\x1a\n") and len(png) > 10_000
    with pytest.raises(ValueError, match="at least one"):
        plots.work_precision_png([])
