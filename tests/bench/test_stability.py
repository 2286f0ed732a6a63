"""Hard cases stay stable: every claim of bench/claims.py is asserted on every hard case.

The matrix is computed once (short runs under RBCOURSE_QUICK); each test checks one
(case, method) cell against the method's claims.
"""

import numpy as np
import pytest

import rbcourse as rb
from rbcourse.bench import stability
from rbcourse.bench.claims import CLAIMS
from rbcourse.bench.hardcases import catalogue
from rbcourse.support.config import quick_mode

CASES = catalogue()


@pytest.fixture(scope="module")
def cells():
    return {(c.case, c.method): c for c in stability.matrix(quick=quick_mode(), progress=False)}


def test_flag_shortens_the_runs():
    assert quick_mode()
    assert CASES["long_run"].duration(quick_mode()) == CASES["long_run"].T_quick < CASES["long_run"].T
    assert CASES["long_run"].duration() == CASES["long_run"].T          # the library's default: full length
    assert round(CASES["long_run"].T / CASES["long_run"].dt) == 10**6        # the full run: a million steps


@pytest.mark.parametrize("method", sorted(rb.METHODS))
@pytest.mark.parametrize("case", sorted(CASES))
def test_claims_hold(cells, case, method):
    c = cells[(case, method)]
    steps = round(CASES[case].duration(quick_mode()) / CASES[case].dt)
    assert steps <= stability.ROUNDING_STEPS                   # short runs: the claims' own tolerances
    assert stability.broken_claims(c, CASES[case], steps) == []
    if case in CLAIMS[method].diverges_on:
        assert not c.finished
    elif CLAIMS[method].finite:
        assert c.finished


def _cell(method, **changes):
    good = dict(case="long_run", method=method, finished=True, t_end=10.0, energy_error=1e-14, energy_gain=0.0,
                energy_drift=1.0, momentum_error=1e-14, norm_L_error=1e-14, orthogonality=1e-15, rotation_error=1e-9)
    good.update(changes)
    return stability.Cell(**good)


def test_broken_claims_names_each_broken_claim():
    long_run = CASES["long_run"]
    assert stability.broken_claims(_cell("implicit_midpoint"), long_run, 10**4) == []
    for changes, word in ((dict(momentum_error=5e-12), "free_L"), (dict(norm_L_error=5e-12), "free_norm_L"),
                          (dict(energy_error=5e-12), "free_energy"), (dict(orthogonality=5e-12), "so3"),
                          (dict(finished=False), "diverged")):
        (why,) = stability.broken_claims(_cell("exact_splitting", **changes), long_run, 10**4)
        assert word in why
    (why,) = stability.broken_claims(_cell("splitting", energy_drift=10.0, energy_error=1e-9), long_run, 10**4)
    assert "energy_bounded" in why
    assert "dissipative" in stability.broken_claims(_cell("implicit_gyro", energy_gain=1e-9), long_run, 10**4)[0]
    assert "expected to blow up" in stability.broken_claims(_cell("euler"), CASES["heavy_top_coarse"], 500)[0]
    # kept to rounding: the tolerance is per 10⁴ steps, and grows with the number of steps
    assert stability.broken_claims(_cell("implicit_midpoint", momentum_error=5e-12), long_run, 10**6) == []
    assert stability.rounding_budget(1e-12, 10**6) == pytest.approx(1e-10)
    assert stability.rounding_budget(1e-12, 500) == 1e-12


@pytest.mark.parametrize("case", ["fast_spin_large_step", "heavy_top_coarse"])
def test_expected_failure_is_the_clear_error_with_the_trajectory(case):
    c = CASES[case]
    with pytest.raises(rb.SimulationDiverged) as info:
        rb.simulate(c.scene, c.X0, c.duration(quick_mode()), c.dt, "euler")
    traj = info.value.trajectory
    assert len(traj) >= 2 and np.all(np.isfinite(traj.R)) and np.all(np.isfinite(traj.L))
    assert "diverged at t =" in str(info.value)


def test_accurate_methods_match_the_references(cells):
    # the reference itself is right: adaptive DOP853 meets it on every case but the near-separatrix one,
    # where any float64 integration departs within one flip (see hardcases.near_separatrix)
    for name in (n for n in CASES if CASES[n].reference):      # the chaotic case has none: its rotation error is nan
        c = cells[(name, "adaptive")]
        limit = 1e-4 if name == "near_separatrix" else 1e-6
        assert c.rotation_error < limit, (name, c.rotation_error)
    assert cells[("heavy_top_fine", "exact_splitting")].rotation_error < 1e-9


def test_implicit_gyro_lets_the_top_fall_slower_than_euler_explodes(cells):
    # the teaching point: the implicit step is stable but loses energy, and so the top's motion is wrong
    gyro = cells[("heavy_top_coarse", "implicit_gyro")]
    assert gyro.finished and gyro.rotation_error > 0.1
    assert not cells[("heavy_top_coarse", "euler")].finished


def test_stability_command_writes_the_matrix(tmp_path, capsys):
    from rbcourse.__main__ import main
    assert main(["stability", "--cases", "sphere", "principal_axis_spin", "--methods", "euler", "rk4",
                 "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "## sphere" in out and "| rk4 | faithful |" in out
    rows = (tmp_path / "stability.csv").read_text().splitlines()
    assert len(rows) == 1 + 4 and rows[0].startswith("case,method,finished")


def test_a_diverged_cell_is_reported_by_when_it_blew_up_not_by_its_numbers():
    blown = _cell("euler", case="fast_spin_large_step", finished=False, t_end=0.14, energy_error=7.7e129,
                  momentum_error=3e64, orthogonality=2e65, diverged_at=0.15)
    text = stability.markdown([blown], quick=True)
    row = next(line for line in text.splitlines() if line.startswith("| euler"))
    assert "diverged at t = 0.15 s" in row and "e+129" not in row and "e+64" not in row
    assert "RBCOURSE_QUICK" not in text
    assert stability.csv_row(blown).endswith(",0.15")


def test_the_position_error_is_a_column_where_a_centre_moves():
    """stiff_spring's implicit midpoint keeps its energy to rounding yet is 'stable but wrong' by its position:
    the table must show the number that decides it; a body whose centre stays put gets no such column."""
    spring = _cell("implicit_midpoint", case="stiff_spring", rotation_error=1.8e-13, position_error=0.13,
                   outcome="stable but wrong")
    text = stability.markdown([spring, _cell("rk4", case="stiff_spring", finished=False, diverged_at=2.9),
                               _cell("rk4", position_error=0.0)], quick=False)
    lines = text.splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("## stiff_spring"))
    header, rule, row, blown = lines[head + 4: head + 8]
    assert header.endswith("| position err (m) |") and row.endswith("| 1.3e-01 |")
    assert header.count("|") == rule.count("|") == row.count("|") == blown.count("|")
    start = next(i for i, line in enumerate(lines) if line.startswith("## long_run"))
    free = next(line for line in lines[start:] if line.startswith("| method"))
    assert "position" not in free


def test_run_cell_records_when_a_run_blew_up():
    case = CASES["fast_spin_large_step"]
    c = stability.run_cell(case, "euler", quick=True)
    assert not c.finished and c.diverged_at > c.t_end and c.diverged_at - c.t_end <= case.dt * 1.0001 * max(
        1, round(case.duration(True) / case.dt) // stability.MAX_RECORDS)


def test_every_outcome_is_reached_and_the_thresholds_decide_it(cells):
    assert {c.outcome for c in cells.values()} == set(stability.OUTCOMES)
    assert all(c.outcome == "diverged" for c in cells.values() if not c.finished)
    # Baraff's explicit L_b step on the fast thin disk: finished, but its energy error is astronomical
    disk = cells[("fast_thin_disk", "quaternion_euler_body")]
    assert disk.finished and disk.energy_error > 1e10 and disk.outcome == "ran away"
    inv = (("energy", 1e-4), ("L", 1e-6))
    assert stability.outcome(True, inv, 1e-3, float("nan")) == "faithful"
    assert stability.outcome(True, inv, 2 * stability.FAITHFUL_ROTATION, float("nan")) == "stable but wrong"
    assert stability.outcome(True, (("energy", 2 * stability.FAITHFUL_INVARIANT),), 0.0, 0.0) == "stable but wrong"
    assert stability.outcome(True, (("energy", 1.5),), 0.0, 0.0) == "ran away"
    assert stability.outcome(True, (("energy", float("nan")),), 0.0, 0.0) == "ran away"
    assert stability.outcome(True, inv, 0.0, 2 * stability.FAITHFUL_POSITION) == "stable but wrong"
    assert stability.outcome(False, inv, 0.0, 0.0) == "diverged"


def test_every_case_declares_known_invariants_and_each_is_reported(cells):
    for name, case in CASES.items():
        assert case.invariants and set(case.invariants) <= set(stability.INVARIANTS), name
        c = cells[(name, "adaptive")]
        assert [k for k, _ in c.invariants] == list(case.invariants)
        assert all(0 <= v < 1e-5 for _, v in c.invariants), (name, c.invariants)   # the accurate method keeps them
    assert CASES["heavy_top_coarse"].invariants == ("energy", "L_z", "L3")
    assert CASES["asymmetric_top"].invariants == ("energy", "L_z") and not CASES["asymmetric_top"].reference


def test_the_tops_keep_L_z_under_the_methods_that_claim_it(cells):
    kept = [m for m in rb.METHODS if "L_z" in CLAIMS[m].keeps]
    assert {"splitting", "exact_splitting", "rkmk4", "symplectic_euler"} <= set(kept)
    for case in ("heavy_top_coarse", "heavy_top_fine", "asymmetric_top"):
        for m in kept:
            assert cells[(case, m)].invariant("L_z") < 1e-13, (case, m)
    # rk4 on the body-frame L_b cannot keep L_z: the measure sees it
    assert cells[("heavy_top_coarse", "rk4")].invariant("L_z") > 1e-3


def test_invariants_measure_what_they_say():
    # a made-up trajectory: energy doubled at the end, P and L_z unchanged -> errors 1, 0, 0
    case = CASES["stiff_spring"]
    traj = rb.simulate(case.scene, case.X0, 0.05, 1e-3, "adaptive")
    e = stability.INVARIANTS["energy"][1](traj, case.X0)
    assert e[0] == 0 and e.max() < 1e-8
    P = traj.P.copy()                                   # a trajectory's arrays are read-only: a new one
    P[-1] = 2.0 * traj.P[0]
    traj = rb.Trajectory(traj.t, traj.x, traj.R, P, traj.L, traj.scene)
    assert stability.INVARIANTS["P"][1](traj, case.X0)[-1] == pytest.approx(1.0)
    rest = CASES["box_at_rest"]
    traj = rb.simulate(rest.scene, rest.X0, 0.01, 1e-3, "rk4")
    x = traj.x.copy()
    x[-1, 0] += 0.5 * rest.X0.x[2]
    traj = rb.Trajectory(traj.t, x, traj.R, traj.P, traj.L, traj.scene)
    assert stability.INVARIANTS["rest"][1](traj, rest.X0)[-1] == pytest.approx(0.5)


def test_broken_claims_names_the_per_case_promises():
    top = CASES["heavy_top_coarse"]
    c = _cell("splitting", case="heavy_top_coarse", invariants=(("energy", 1e-4), ("L_z", 1e-9), ("L3", 1e-5)),
              outcome="stable but wrong")
    assert any("keeps L_z" in why for why in stability.broken_claims(c, top, 500))
    rest = _cell("rk4", case="box_at_rest", invariants=(("energy", 0.0), ("rest", 0.0)), outcome="stable but wrong")
    assert any("claimed 'faithful'" in why for why in stability.broken_claims(rest, CASES["box_at_rest"], 1000))


# the shipped full-length matrix (rbcourse/bench/results; regenerated by
# `python -m rbcourse stability --workers 2 --out rbcourse/bench/results`): a sample of cheap cells re-run at full
# length must give its rows exactly
SAMPLE = [("sphere", "rk4"), ("sphere", "splitting"), ("stiff_spring", "euler"), ("stiff_spring", "splitting"),
          ("stiff_spring", "implicit_midpoint"), ("heavy_top_coarse", "splitting"),
          ("heavy_top_coarse", "quaternion_euler_body"), ("mass_ratio_pair", "rk4"), ("racket_coarse", "exact_splitting")]


def test_the_shipped_full_length_matrix_matches_a_sample_rerun():
    shipped = {(c.case, c.method): c for c in stability.read_results()}
    assert set(shipped) >= {(n, m) for n in CASES for m in rb.METHODS}, "the shipped matrix has every cell"
    assert {c.outcome for c in shipped.values()} == set(stability.OUTCOMES)
    refs = {n: stability.reference_end(CASES[n], CASES[n].T) for n, _ in SAMPLE}      # as matrix() computes them
    rerun = {(n, m): stability.run_cell(CASES[n], m, False, refs[n]) for n, m in SAMPLE}
    assert stability.differences([rerun[k] for k in SAMPLE], [shipped[k] for k in SAMPLE]) == []
    lines = (stability.RESULTS / "stability.csv").read_text().splitlines()
    assert len(set(lines)) == len(lines) and lines[0] == stability.CSV_HEADER


def test_differences_between_matrices():
    """differences(): [] for the same cells, and one line naming the cell for another outcome, a number beyond
    the tolerance, a missing cell; a last-digit change of a rounding-level number is not a difference."""
    import dataclasses
    shipped = stability.read_results()
    assert stability.differences(shipped, shipped) == []
    c = next(c for c in shipped if c.finished and c.rotation_error > 1e-3)
    changed = [dataclasses.replace(c, rotation_error=c.rotation_error * 1.001) if x is c else x for x in shipped]
    assert stability.differences(changed, shipped) == [f"{c.case} × {c.method}: rotation_error "
                                                       f"{c.rotation_error * 1.001:.6g} / {c.rotation_error:.6g}"]
    tiny = next(c for c in shipped if 0 < c.orthogonality < 1e-14)
    close = [dataclasses.replace(x, orthogonality=x.orthogonality * 1.3) if x is tiny else x for x in shipped]
    assert stability.differences(close, shipped) == []
    other = [dataclasses.replace(x, outcome="diverged") if x is c else x for x in shipped]
    assert stability.differences(other, shipped) == [f"{c.case} × {c.method}: diverged / {c.outcome}"]
    assert stability.differences(shipped[1:], shipped) == [f"{shipped[0].case} × {shipped[0].method}: only in the second"]
    inv = next(x for x in shipped if x.invariants and x.invariants[0][1] > 1e-6)
    moved = [dataclasses.replace(x, invariants=((x.invariants[0][0], x.invariants[0][1] * 2),) + x.invariants[1:])
             if x is inv else x for x in shipped]
    assert len(stability.differences(moved, shipped)) == 1
