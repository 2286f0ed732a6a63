"""The work-precision benchmark runs, measures real errors, and writes its reports."""
import math

import numpy as np
import pytest

from rbcourse.bench import peers
from rbcourse.bench.runs import run_rbcourse, timed
from rbcourse.bench import work_precision as bench
from rbcourse.__main__ import main
from rbcourse.bench.problems import PROBLEMS


def test_references_agree_with_an_independent_integration():
    from rbcourse.rotation import rotation_angle
    A = PROBLEMS["A"]()
    # the exact solution (A) against scipy's DOP853 on the peers' right-hand side
    from scipy.integrate import solve_ivp
    from rbcourse.rotation import matrix_from_quat
    sol = solve_ivp(A.rhs(), (0, A.T), A.y0(), method="DOP853", rtol=1e-12, atol=1e-12)
    assert rotation_angle(A.reference_R(), matrix_from_quat(sol.y[3:, -1])) < 1e-8


def test_quick_bench_measures_and_reports(tmp_path, capsys):
    assert main(["bench", "--problems", "A", "--methods", "rk4", "adaptive", "euler", "--quick", "--no-peers",
                 "--out", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    for name in ("results.csv", "results.md", "work_precision.png"):
        assert (tmp_path / name).stat().st_size > 100 and f"wrote {tmp_path / name}" in printed
    rows = (tmp_path / "results.csv").read_text().splitlines()[1:]
    runs = [r.split(",") for r in rows]
    rk4 = sorted((float(r[3]), float(r[6])) for r in runs if r[2] == "rk4")
    # smaller steps, smaller errors, at 4th order
    assert rk4[0][1] < rk4[-1][1]
    clean = [(d, e) for d, e in rk4 if 1e-10 < e < 1e-2]           # above rounding, below saturation
    assert len(clean) >= 2
    slope = np.polyfit(np.log([d for d, _ in clean]), np.log([e for _, e in clean]), 1)[0]
    assert 3.3 < slope < 4.7
    eu = [float(r[6]) for r in runs if r[2] == "euler"]
    assert all(e > 1e-3 or math.isinf(e) for e in eu)            # the slides' Euler never gets close
    assert "## Problem A" in printed and "rk4" in printed


def test_peers_run_in_the_same_process():
    p = PROBLEMS["A"]()
    r = peers.run_scipy(p, "DOP853", 1e-9, repeats=1)
    assert r.tool == "scipy" and r.error < 1e-5 and r.seconds > 0
    if peers.mujoco_installed():
        m = peers.run_mujoco(p, "RK4", 0.005, repeats=1)
        assert m.error < 1e-5 and m.steps == 4000
        blown = peers.run_mujoco(PROBLEMS["B"](), "Euler", 2e-3, repeats=1)
        assert blown.error > 1e-2                                  # semi-implicit Euler fails on B


def test_bad_bench_arguments(tmp_path):
    for bad in (["bench", "--problems", "D"], ["bench", "--methods", "verlet"], ["bench", "--repeats", "0"]):
        with pytest.raises(SystemExit) as info:
            main(bad + ["--out", str(tmp_path)])
        assert info.value.code == 2


def test_timing_repeats_short_runs_and_pauses_the_garbage_collector():
    import gc
    import time
    seen = []

    def run():
        seen.append(gc.isenabled())
        time.sleep(0.01)
        return len(seen)
    seconds, last = timed(run, 2, min_total=0.05)
    assert 4 <= len(seen) <= 6 and last == len(seen)           # repeated until 0.05 s were spent
    assert seconds >= 0.01 and not any(seen) and gc.isenabled()  # paused while timed, then back on
    seen.clear()
    timed(run, 1, min_total=10.0, max_repeats=3)
    assert len(seen) == 3
    seen.clear()
    timed(run, 3)
    assert len(seen) == 3


def test_exact_flow_methods_also_try_one_step_over_the_whole_interval():
    A = PROBLEMS["A"]()
    todo = bench.plan([A], ["exact_splitting", "rk4"], quick=True, peers=False)
    exact = [s for kind, p, m, s in todo if m == "exact_splitting"]
    rk4 = [s for kind, p, m, s in todo if m == "rk4"]
    assert exact[0] == A.T and exact[1:] == rk4 and A.T not in rk4
    one_step = run_rbcourse(A, "exact_splitting", A.T, repeats=1)
    assert one_step.steps == 1 and one_step.error < 1e-9          # torque-free: one exact step


def test_a_sweep_without_progress_bar_never_imports_tqdm():
    """In a notebook without ipywidgets, importing tqdm.auto writes a warning to stderr (red text at "Run All")."""
    import subprocess
    import sys

    code = ("import sys; from rbcourse.bench import work_precision as wp, stability; "
            "from rbcourse.bench.problems import problem_A; "
            "wp.run_all([problem_A()], ['euler'], quick=True, peers=False, progress=False); "
            "stability.matrix(['principal_axis_spin'], ['euler'], quick=True, progress=False); "
            "assert 'tqdm' not in sys.modules, 'tqdm imported'")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
