"""The matrix's cells are the same, to the bit, whoever runs them: here, 2 worker processes, a Dask cluster.

Cells are compared by repr (exact floats, nan included); bad --workers / --scheduler exit 2 with one line.
"""
import math

import numpy as np
import pytest

from rbcourse.bench import stability

SAMPLE = dict(cases=["sphere", "stiff_spring", "heavy_top_coarse"], methods=["splitting", "euler", "symplectic_euler"], quick=True,
              progress=False)


@pytest.fixture(scope="module")
def serial():
    return stability.matrix(**SAMPLE)


def _same(a, b):
    assert [repr(c) for c in a] == [repr(c) for c in b]


def test_the_sample_reaches_distinct_outcomes(serial):
    # the comparison below means something: a diverged cell, a ran-away one and finished ones
    assert {c.outcome for c in serial} >= {"diverged", "ran away", "stable but wrong"}
    assert [(c.case, c.method) for c in serial] == [(k, m) for k in SAMPLE["cases"] for m in SAMPLE["methods"]]


def test_two_workers_give_identical_cells(serial):
    _same(serial, stability.matrix(**SAMPLE, workers=2))


def test_a_dask_local_cluster_gives_identical_cells(serial):
    from dask.distributed import Client, LocalCluster
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        _same(serial, stability.matrix(**SAMPLE, scheduler=client))
        _same(serial, stability.matrix(**SAMPLE, scheduler=cluster.scheduler_address))


def test_a_changed_cell_is_seen(serial):
    # the comparison can fail: one float changed in its last bit
    import dataclasses
    import math
    changed = list(serial)
    changed[0] = dataclasses.replace(changed[0], energy_error=math.nextafter(changed[0].energy_error, 1.0))
    with pytest.raises(AssertionError):
        _same(serial, changed)


@pytest.mark.parametrize("bad", ["0", "-1", "two", "1.5"])
def test_bad_workers_exit_2_naming_the_parameter_and_range(bad, tmp_path, capsys):
    from rbcourse.__main__ import main
    with pytest.raises(SystemExit) as info:
        main(["stability", "--quick", f"--workers={bad}", "--out", str(tmp_path)])
    assert info.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--workers" in err and ">= 1" in err and bad in err
    assert not (tmp_path / "stability.csv").exists()


def test_bad_scheduler_is_a_clear_error(tmp_path, capsys):
    from rbcourse.__main__ import main
    with pytest.raises(SystemExit) as info:
        main(["stability", "--quick", "--scheduler", "tcp://127.0.0.1:9", "--out", str(tmp_path)])
    assert info.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "scheduler" in err and "tcp://127.0.0.1:9" in err
    with pytest.raises(ValueError, match="scheduler"):
        stability.connect("")


def test_workers_checked_by_the_library():
    for bad in (0, -3, True, 2.0, "x"):
        with pytest.raises(ValueError, match="workers"):
            stability.check_workers(bad)
    assert stability.check_workers("3") == 3 and stability.default_workers() >= 1


def test_the_command_line_runs_on_two_workers(tmp_path):
    from rbcourse.__main__ import main
    assert main(["stability", "--quick", "--cases", "sphere", "--methods", "rk4", "euler", "--workers", "2",
                 "--out", str(tmp_path)]) == 0
    rows = (tmp_path / "stability.csv").read_text().splitlines()
    cells = stability.matrix(["sphere"], ["rk4", "euler"], quick=True, progress=False)
    assert rows[1:] == [stability.csv_row(c) for c in cells]
    outcomes = (tmp_path / "stability_outcomes.csv").read_text().splitlines()
    assert outcomes[1:] == [stability.outcomes_row(c) for c in cells] and "energy=" in outcomes[1]


# --- the work-precision benchmark's error sweep (bench --errors-only) -------------------------------------

from rbcourse.bench import work_precision as wp      # noqa: E402
from rbcourse.bench.problems import PROBLEMS          # noqa: E402

ERRORS = dict(methods=["rk4", "splitting", "euler", "adaptive"], quick=True, peers=True, progress=False)


@pytest.fixture(scope="module")
def problems():
    return [PROBLEMS["A"]()]


@pytest.fixture(scope="module")
def serial_errors(problems):
    return wp.errors(problems, **ERRORS)


def test_the_error_sweep_is_the_plan_untimed(serial_errors, problems):
    planned = wp.plan(problems, ERRORS["methods"], True, True)
    assert [(r.problem, r.method, r.setting) for r in serial_errors] == [(p.name, m, s) for _, p, m, s in planned]
    assert all(np.isnan(r.seconds) for r in serial_errors)
    assert any(r.error == math.inf for r in serial_errors) and any(r.tool == "scipy" for r in serial_errors)


def test_error_sweep_on_two_workers_and_dask_is_identical(serial_errors, problems):
    from dask.distributed import Client, LocalCluster
    _same(serial_errors, wp.errors(problems, **ERRORS, workers=2))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        _same(serial_errors, wp.errors(problems, **ERRORS, scheduler=client))


def test_error_sweep_equals_the_timed_sweeps_errors(serial_errors, problems):
    timed = wp.run_all(problems, ERRORS["methods"], quick=True, peers=True, repeats=1, budget=1e9, progress=False)
    assert [(r.problem, r.label, r.setting, r.error) for r in timed] == \
        [(r.problem, r.label, r.setting, r.error) for r in serial_errors]


def test_observed_order():
    runs = [wp.Run("A", "rbcourse", "rk4", h, 100, math.nan, 3.0 * h ** 4) for h in (0.1, 0.05, 0.025, 0.0125, 0.2)]
    assert wp.observed_order(runs) == pytest.approx(4.0, abs=1e-9)
    runs.append(wp.Run("A", "rbcourse", "rk4", 0.001, 20000, math.nan, 1e-11))    # at rounding: left out
    runs.append(wp.Run("A", "rbcourse", "rk4", 2.0, 10, math.nan, 2.5))          # wrapped around: left out
    assert wp.observed_order(runs) == pytest.approx(4.0, abs=1e-9)
    assert math.isnan(wp.observed_order(runs[:1]))


def test_the_sweep_measures_the_orders(serial_errors):
    # rk4 on the racket (A): order 4; splitting: 2
    for method, order in [("rk4", 4.0), ("splitting", 2.0)]:
        got = wp.observed_order([r for r in serial_errors if r.problem == "A" and r.method == method])
        assert abs(got - order) <= 0.3, (method, got)


def test_bench_errors_only_on_the_command_line(tmp_path):
    from rbcourse.__main__ import main
    assert main(["bench", "--quick", "--errors-only", "--workers", "2", "--problems", "A", "--methods", "rk4",
                 "--no-peers", "--out", str(tmp_path)]) == 0
    runs = wp.read_csv(tmp_path / "results.csv")
    expect = wp.errors([PROBLEMS["A"]()], ["rk4"], quick=True, peers=False, progress=False)
    assert sorted((r.setting, r.error) for r in runs) == sorted((float(f"{r.setting:.6g}"), float(f"{r.error:.6g}"))
                                                             for r in expect)
    md = (tmp_path / "results.md").read_text()
    assert md.startswith("# Error sweep") and "| rk4 |" in md and not (tmp_path / "work_precision.png").exists()


@pytest.mark.parametrize("args, word", [(["--workers", "2"], "--errors-only"), (["--scheduler", "tcp://127.0.0.1:9"], "--errors-only"),
                                        (["--errors-only", "--workers", "0"], ">= 1")])
def test_bench_parallel_arguments_exit_2(args, word, tmp_path, capsys):
    from rbcourse.__main__ import main
    with pytest.raises(SystemExit) as info:
        main(["bench", "--quick", "--problems", "A", "--methods", "rk4", "--no-peers", *args, "--out", str(tmp_path)])
    assert info.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and word in err
    assert not (tmp_path / "results.csv").exists()
    with pytest.raises(ValueError, match="serial"):
        wp.main(["A"], ["rk4"], quick=True, peers=False, workers=2, out=str(tmp_path))
