"""The throughput report's section "Contacts, many bodies, forces over time" (bench/contact_rows.py,
contact_table; its boxes: bench/box_scenes.py; its measuring: bench/timing.py) and its MuJoCo peers
(bench/peers.py: mujoco_ground_model, mujoco_boxes_model, mujoco_state, mujoco_stepper, run_mujoco_steps).
Not timed: tiny sizes and budgets, the warm demo faked (its subprocess is checked apart); the test checks
that the table has its rows and that each cell is a measured number or says why not."""
import re
import subprocess

import numpy as np
import pytest

from rbcourse.bench import box_scenes, peers, timing
from rbcourse.bench import contact_rows as cr

CASES = ("one box dropped on the ground", "boxes resting on the ground", "free boxes (rk4",
         "free boxes / the memory limit", "the pushed box", "the warm demo")
NUMBER = r"\d[\d.,]*(?:e[+-]?\d+)? (?:µs|ns|s)(?: \(ran on \w+\))?(?: \(N = [\d,]+\))?"
WHY = r"(?:n/a \(.+\)|failed: .+|skipped .+|—)"
mujoco = pytest.mark.skipif(not peers.mujoco_installed(), reason="MuJoCo not installed (requirements-peers.txt)")


@pytest.fixture
def tiny(monkeypatch):
    """Tiny sizes and budgets, the warm demo faked (1.25 s): the section in a second or two."""
    monkeypatch.setattr(cr, "N_CONTACT", 12)
    monkeypatch.setattr(cr, "MUJOCO_SMALL_N", 5)
    monkeypatch.setattr(cr, "TRIAD_N", 10**4)
    monkeypatch.setattr(cr, "LANDED", 0.004)
    monkeypatch.setattr(cr, "MAX_STEPS", 1024)     # long enough that a step's time is more than the timer's noise
    monkeypatch.setattr(cr, "CONTACT_BUDGET", {True: 0.002, False: 0.002})
    monkeypatch.setattr(cr, "BUDGET", {True: 0.002, False: 0.002})
    monkeypatch.setattr(cr, "demo_seconds", lambda: 1.25)


def rows_of(lines):
    """{case: [ours, MuJoCo, ratio, target, met]} of the section's table."""
    table = [line for line in lines if line.startswith("| ") and not line.startswith("| case")]
    out = {}
    for line in table:
        cells = [c.strip() for c in line.strip("|").split(" | ")]
        assert len(cells) == 6, line
        case = next(c for c in CASES if c in cells[0])
        assert case not in out, f"two rows for {case!r}"
        out[case] = cells[1:]
    return out


def test_the_section_has_every_row_and_each_cell_is_a_number_or_why(tiny):
    lines = cr.contact_table(quick=True, peers=True)
    assert lines[0] == "## Contacts, many bodies, forces over time"
    assert "soft" in lines[2] and "impulses" in lines[2]            # the note: MuJoCo's contact model is not ours
    rows = rows_of(lines)
    assert set(rows) == set(CASES)
    for case, (ours, mj, ratio, target, met) in rows.items():
        assert re.fullmatch(f"{NUMBER}|{WHY}", ours), (case, ours)
        assert re.fullmatch(f"{NUMBER}|{WHY}", mj), (case, mj)
        assert re.fullmatch(r"[\d.e+-]+×(?: the limit)?|—", ratio), (case, ratio)
        assert met in ("yes", "no", "—"), (case, met)
        if ratio != "—" and "limit" not in ratio:                  # a ratio only beside two numbers
            assert re.fullmatch(NUMBER, ours) and re.fullmatch(NUMBER, mj), case
    assert "12 boxes resting" in lines[[i for i, line in enumerate(lines) if "resting" in line][0]]
    assert rows["the warm demo"][0] == "1.25 s" and rows["the warm demo"][-1] == "yes"   # ≤ 1.5 s
    assert rows["the pushed box"][1].startswith("n/a (")
    notes = "\n".join(line for line in lines if line.startswith("- "))
    assert "type(scene.effects[0].force)" in notes and "GB/s" in notes and "write-allocate" in notes
    if peers.mujoco_installed():
        for case in ("one box dropped on the ground", "boxes resting on the ground", "free boxes (rk4"):
            assert re.fullmatch(NUMBER, rows[case][1]), (case, rows[case][1])
        assert "MuJoCo at t = " in notes


def test_without_peers_or_mujoco_the_mujoco_cells_say_why(tiny, monkeypatch):
    rows = rows_of(cr.contact_table(quick=True, peers=False))
    for case in ("one box dropped on the ground", "boxes resting on the ground", "free boxes (rk4"):
        assert rows[case][1] == "skipped (--no-peers)" and rows[case][2] == "—"
    monkeypatch.setattr(peers, "mujoco_installed", lambda: False)
    rows = rows_of(cr.contact_table(quick=True, peers=True))
    for case in ("one box dropped on the ground", "boxes resting on the ground", "free boxes (rk4"):
        assert rows[case][1] == "n/a (MuJoCo not installed)", rows[case]


def test_a_case_that_breaks_says_so_and_the_others_are_still_measured(tiny, monkeypatch):
    def broken():
        raise RuntimeError("no demo today")
    monkeypatch.setattr(cr, "demo_seconds", broken)
    monkeypatch.setattr(cr, "triad_bandwidth", lambda n, repeats=5: 1 / 0)
    rows = rows_of(cr.contact_table(quick=True, peers=False))
    assert rows["the warm demo"][0] == "failed: RuntimeError: no demo today" and rows["the warm demo"][-1] == "—"
    assert rows["free boxes / the memory limit"][0].startswith("failed: ZeroDivisionError")
    assert re.fullmatch(NUMBER, rows["free boxes (rk4"][0])


def test_the_warm_demo_is_the_best_of_warm_fresh_processes_that_write_bytecode_and_a_failure_names_its_exit_code(
        monkeypatch):
    """One run warms (numba's cache, Python's bytecode), then DEMO_WARM_RUNS fresh processes are timed and the
    fastest is the figure; each runs with PYTHONDONTWRITEBYTECODE unset, as on a newcomer's machine."""
    calls, n = [], 1 + cr.DEMO_WARM_RUNS
    monkeypatch.setenv("PYTHONDONTWRITEBYTECODE", "1")

    def run(argv, **kw):
        calls.append((argv, kw))
        code = 0 if len(calls) <= n + 1 else 3
        return subprocess.CompletedProcess(argv, code, "", "" if code == 0 else "Traceback\nValueError: boom\n")
    monkeypatch.setattr(subprocess, "run", run)
    ticks = iter([0.0, 9.0, 10.0, 12.0, 13.0, 14.5, 20.0, 21.5, *range(30, 60)])   # the first run 9 s, then 2, 1.5, 1.5
    monkeypatch.setattr(cr, "clock", lambda: next(ticks))
    assert cr.demo_seconds() == 1.5
    assert len(calls) == n
    for argv, kw in calls:
        assert argv[1:4] == ["-m", "rbcourse", "demo"] and "--out" in argv and "--open" not in argv
        assert kw["timeout"] > 0 and kw["cwd"]
        assert "PYTHONDONTWRITEBYTECODE" not in kw["env"]
    with pytest.raises(RuntimeError, match="exit code 3: ValueError: boom"):
        cr.demo_seconds()


def test_the_difference_method_sizes_by_time_and_keeps_under_its_cap():
    ks = []

    def run(k):              # a fake clock: 1 ms per step
        ks.append(k)
        return k * 1e-3
    per, k = timing.difference_per_step(run, budget=0.4, min_steps=3, max_steps=1000, repeats=3)
    assert per == pytest.approx(1e-3) and k == 192 and ks[0] == 3           # 3, 6, …, 192: 192 ms ≥ 0.4 / 4
    per, k = timing.difference_per_step(run, budget=100.0, max_steps=16)
    assert k == 16                                                           # never beyond max_steps
    ks.clear()
    timing.difference_per_step(run, budget=0.0, min_steps=1000, repeats=5, max_seconds=7.0)
    assert ks == [1000] + [2000, 1000] * 2                                   # 5 repeats of 3 s cut to 2
    with pytest.raises(timing.TooSlow, match="one repeat would take"):
        timing.difference_per_step(run, budget=0.0, min_steps=1000, max_seconds=2.0)


def test_mujoco_size_falls_back_to_the_small_model_and_says_why(monkeypatch):
    if not peers.mujoco_installed():
        pytest.skip("MuJoCo not installed")
    bodies, _ = box_scenes.boxes(12)
    assert cr.mujoco_size(bodies, n_small=5) == (12, "")
    monkeypatch.setattr(cr, "MUJOCO_MAX_BUILD", 0.0)
    used, why = cr.mujoco_size(bodies, n_small=5)
    assert used == 5 and "12 boxes" in why and "build" in why


def test_the_dropped_box_and_the_resting_boxes_start_as_the_brief_says():
    body, scene, X0 = box_scenes.dropped_box()
    assert body.mass == 1.0 and body.size == (0.3, 0.2, 0.05)
    assert [type(e).__name__ for e in scene.effects] == ["Gravity", "Ground"]
    ground = scene.effects[1]
    assert (ground.height, ground.restitution, ground.friction) == (0.0, 0.5, 0.5)
    assert np.asarray(X0.x)[2] == pytest.approx(0.225) and not np.allclose(X0.R, np.eye(3))
    bodies, _ = box_scenes.boxes(7)
    X = box_scenes.resting_state(bodies)
    half = np.array([b.size[2] for b in bodies]) / 2
    assert np.array_equal(np.asarray(X.x)[:, 2], half)
    assert np.array_equal(np.asarray(X.R), np.broadcast_to(np.eye(3), (7, 3, 3)))
    assert not np.any(X.P) and not np.any(X.L)


@mujoco
def test_the_mujoco_boxes_start_where_ours_do():
    import mujoco as mj
    body, scene, X0 = box_scenes.dropped_box()
    model = peers.mujoco_ground_model([body.mass], [body.size], "RK4", 1e-3, friction=0.5)
    assert model.opt.integrator == mj.mjtIntegrator.mjINT_RK4 and model.opt.timestep == 1e-3
    assert np.allclose(model.body_inertia[1], np.diag(body.I_body), rtol=1e-15) and model.body_mass[1] == 1.0
    assert model.ngeom == 2 and model.geom_friction[1][0] == 0.5 and model.geom_condim[1] == 3
    assert np.allclose(model.geom_size[1], np.array(body.size) / 2)
    data = peers.mujoco_stepper(model, body, X0)(0)
    mj.mj_forward(model, data)
    assert np.allclose(data.xpos[1], X0.x) and np.allclose(data.xmat[1].reshape(3, 3), X0.R, atol=1e-15)
    omega_world = np.asarray(X0.R) @ np.linalg.solve(body.I_body, np.asarray(X0.R).T @ np.asarray(X0.L))
    assert np.allclose(data.qvel[3:6], np.asarray(X0.R).T @ omega_world)      # MuJoCo: ω in body axes
    assert np.allclose(data.qvel[:3], np.asarray(X0.P) / body.mass)
    seconds, (qpos, qvel) = peers.run_mujoco_steps(model, body, X0, 600, repeats=1)
    assert seconds > 0 and abs(qpos[2] - 0.025) < 1e-3 and np.abs(qvel).max() < 1e-2   # landed, at rest
    bodies, Xn = box_scenes.boxes(3)
    free = peers.mujoco_boxes_model([b.mass for b in bodies], [b.size for b in bodies], "RK4", 1e-3)
    assert free.ngeom == 3 and not free.geom_contype.any() and np.allclose(free.opt.gravity, 0.0)
    qpos, qvel = peers.mujoco_state(bodies, Xn)
    assert qpos.shape == (21,) and qvel.shape == (18,)


def test_noise_is_never_reported_as_a_negative_time():
    """Runs that differ by the timer's noise only are measured again over longer runs; never a time <= 0."""
    from rbcourse.bench.timing import TooSlow, difference_per_step
    noisy = lambda k: 1e-3 + 1e-7 * max(k, 64)                          # noqa: E731  (flat up to k = 64)
    per, k = difference_per_step(noisy, budget=0.0, min_steps=2, max_steps=4096)
    assert per == pytest.approx(1e-7) and k == 64
    with pytest.raises(TooSlow, match="noise only"):
        difference_per_step(lambda k: 1e-3 - k * 1e-9, budget=0.0, min_steps=2, max_steps=64)


def test_a_burst_of_noise_on_the_shorter_runs_does_not_make_a_step_look_cheaper():
    """1 ms per step and 50 ms of fixed cost; two of the three runs of k steps are slowed by 40 ms (another
    process): a median of the differences would report 1 ms − 40 ms / k; the fastest runs give 1 ms."""
    from rbcourse.bench.timing import difference_per_step
    calls = []

    def run(k):
        calls.append(k)
        shorter = [c for c in calls if c == 8]
        burst = 0.04 if k == 8 and len(shorter) in (2, 3) else 0.0
        return 0.05 + k * 1e-3 + burst
    per, k = difference_per_step(run, budget=0.0, min_steps=8, max_steps=8, repeats=3)
    assert k == 8 and per == pytest.approx(1e-3)


def test_the_one_body_table_sends_a_scene_with_a_ground_to_the_contacts_table(monkeypatch):
    """MuJoCo's contacts are soft: its one-body cell says where the contacts table compares the dropped box."""
    from rbcourse.bench import throughput
    monkeypatch.setattr(peers, "mujoco_installed", lambda: True)
    examples = throughput.one_body_examples()
    assert "contacts table" in throughput.mujoco_seconds_per_step(examples["dropped_box"], 10)[1]
    assert throughput.mujoco_seconds_per_step(examples["pushed_box"], 10)[1] == "n/a (no comparable model)"
