"""The matrix's cells are the same, to the bit, whoever runs them: here, 2 worker processes, a Dask cluster.

Cells are compared by repr (exact floats, nan included); bad --workers / --scheduler exit 2 with one line.
"""
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
