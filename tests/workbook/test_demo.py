import subprocess
import sys

import pytest

from rbcourse.__main__ import main


def test_demo_writes_its_files(tmp_path, capsys):
    assert main(["demo", "--t-end", "0.3", "--dt", "0.01", "--out", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    for name in ["trajectory.csv", "drift.png", "energy.png", "summary.txt"]:
        assert (tmp_path / f"pushed_box_{name}").stat().st_size > 100
        assert f"wrote {tmp_path / f'pushed_box_{name}'}" in printed
    summary = (tmp_path / "pushed_box_summary.txt").read_text()
    assert "pushed box" in summary and "rk4" in summary and "euler" in summary
    rows = (tmp_path / "pushed_box_trajectory.csv").read_text().splitlines()
    assert rows[0].startswith("t,x,y,z") and len(rows) == 32


def test_demo_rejects_bad_arguments(tmp_path):
    for bad in (["demo", "--dt", "-1", "--out", str(tmp_path)], ["demo", "--method", "nope", "--out", str(tmp_path)],
                ["demo", "no_such_scene"]):
        with pytest.raises(SystemExit) as info:
            main(bad)
        assert info.value.code == 2


def test_module_entry_point(tmp_path):
    out = subprocess.run([sys.executable, "-m", "rbcourse", "demo", "--t-end", "0.05", "--dt", "0.01",
                          "--out", str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "pushed_box_summary.txt" in out.stdout


def test_the_csv_of_many_bodies_has_one_row_per_step_and_body(tmp_path):
    from rbcourse.workbook.demo import write_csv
    from rbcourse.examples import get_scene
    from rbcourse.simulate import simulate
    ex = get_scene("many_bodies")
    traj = simulate(ex.scene, ex.X0, 0.004, 0.002, "rk4")
    write_csv(tmp_path / "t.csv", traj)
    rows = (tmp_path / "t.csv").read_text().splitlines()
    assert rows[0].startswith("t,body,x,y,z") and len(rows) == 1 + 3 * 200
    assert [r.split(",")[1] for r in rows[1:4]] == ["0", "1", "2"] and rows[201].split(",")[:2] == ["0.002", "0"]
    assert float(rows[201 + 7].split(",")[2]) == pytest.approx(traj.x[1, 7, 0])       # step 1, body 7, x


def test_every_named_set_up_runs_and_the_bench_takes_its_scenes_from_the_table():
    import numpy as np
    from rbcourse.bench.hardcases import CASES, catalogue
    from rbcourse.bench.problems import PROBLEMS
    from rbcourse.simulate import simulate
    from rbcourse.examples import EXAMPLES, SCENES
    assert set(SCENES) <= set(EXAMPLES)
    for name, make in EXAMPLES.items():
        ex = make()
        assert ex.name == name and ex.description
        traj = simulate(ex.scene, ex.X0, 10 * ex.dt, ex.dt, ex.method)
        assert len(traj) == 11 and np.all(np.isfinite(traj.R))
    for problem, setup in zip("ABC", ("tennis_racket", "fast_spin", "heavy_top")):
        p, ex = PROBLEMS[problem](), EXAMPLES[setup]()
        assert p.scene.describe() == ex.scene.describe() and np.array_equal(p.X0.L, ex.X0.L)
        assert np.array_equal(p.omega0_body, ex.omega_body)
    cases = catalogue()
    for name, setup, *_ in CASES:
        assert cases[name].scene.describe() == EXAMPLES[setup]().scene.describe()


def test_the_plots_beside_say_their_failure_and_run_here_where_fork_is_not_the_way(monkeypatch, tmp_path):
    """demo.Beside: the data files and plots are made in a forked process beside the demo's (Linux, one thread:
    checked in a fresh process, as the command line runs it); its error comes back as a RuntimeError naming it;
    where processes do not fork (or other threads run: here, pytest's), the same work runs in-process."""
    import multiprocessing
    import subprocess
    import sys
    import pytest
    from rbcourse.workbook.demo import Beside
    script = """
from pathlib import Path
from rbcourse.workbook.demo import Beside
def fails(path):
    raise ValueError(f"no room for {path}")
beside = Beside(lambda: None, fails)
assert beside.process is not None
beside.give("plot.png")
try:
    beside.result()
    raise SystemExit("no error came back")
except RuntimeError as err:
    assert "plots failed: ValueError: no room for plot.png" in str(err), err
beside = Beside(lambda: None, lambda path: [Path(path)])
assert beside.process is not None
beside.give("a.png")
assert beside.result() == [Path("a.png")]
print("forked: ok")
"""
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and "forked: ok" in run.stdout, run.stderr
    monkeypatch.setattr(multiprocessing, "get_all_start_methods", lambda: ["spawn"])
    beside = Beside(lambda: None, lambda path: [tmp_path / path])
    assert beside.process is None
    beside.give("b.png")
    assert beside.result() == [tmp_path / "b.png"]
    with pytest.raises(ValueError, match="no room"):
        Beside(lambda: None, lambda path: (_ for _ in ()).throw(ValueError("no room"))).give("c.png")
    from rbcourse.workbook import demo
    written = demo.run_demo("box_on_spring", t_end=0.2, dt=0.01, out=tmp_path / "out")    # in-process, all files
    assert sorted(p.name for p in written) == sorted(demo.output_names("box_on_spring"))
    assert all(p.exists() and p.stat().st_size > 0 for p in written)


def test_a_process_beside_that_fails_while_warming_is_said_and_nothing_hangs():
    """Its warm-up fails before it reads its arguments (a large pickle the pipe cannot hold): the error comes
    back, the sending thread ends (a broken pipe), nothing waits forever."""
    import subprocess
    import sys
    script = """
import numpy as np
from rbcourse.workbook.demo import Beside
def warm():
    raise OSError("no matplotlib here")
beside = Beside(warm, lambda big: [])
beside.give(np.zeros(10**6))          # 8 MB: more than a pipe holds
try:
    beside.result()
    raise SystemExit("no error came back")
except RuntimeError as err:
    assert "OSError: no matplotlib here" in str(err), err
print("said: ok")
"""
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and "said: ok" in run.stdout, run.stderr


@pytest.mark.parametrize("name", ["pushed_box", "tennis_racket", "box_on_spring", "heavy_top", "many_bodies",
                                  "dropped_box"])
def test_a_summary_reports_as_a_drift_only_what_the_scene_conserves(name):
    """The heavy top once had "|L| drift 9.8e-01" for rk4, where gravity's torque turns L: each drift in the
    summary must be of a quantity the scene's physics keeps (energy; L for a free body; L_z about a pivot),
    and every quantity it keeps is reported."""
    import re
    from rbcourse.simulate import simulate
    from rbcourse.viz.plots import conserved
    from rbcourse.workbook import demo
    from rbcourse.examples import get_scene
    ex = get_scene(name)
    t_end = max(0.2, 2 * ex.drift_from)
    run = simulate(ex.scene, ex.X0, t_end, ex.dt * (2 if ex.scene.n_bodies > 1 else 1), ex.method)
    text = demo._summary(ex, [run], [ex.method], ex.drift_from).splitlines()[4]
    plan = conserved(run, ex.drift_from)
    reported = set(re.findall(r"\b(energy drift|L_z drift|L drift|\|L\| drift)", text))
    expected = ({"energy drift"} if plan.energy_conserved else set()) | \
        {"com": {"L drift"}, "vertical": {"L_z drift"}, "origin": set()}[plan.momentum]
    assert reported == expected, f"{name}: the summary reports {reported}, the scene conserves {expected}: {text}"
    if name == "heavy_top":
        assert expected == {"energy drift", "L_z drift"}
        values = [float(v) for v in re.findall(r"[-+]?\d\.\d+e[-+]\d+", text.split("‖RᵀR")[0])]
        assert len(values) == 2 and max(abs(v) for v in values) < 1e-6       # rk4 at the demo's step: small


def test_the_demos_explorer_holds_its_own_run_and_an_euler_that_survives():
    """The demo runs rk4 at dt = 0.001 s; its explorer once had only 0.02 … 0.0025 s (its address
    #method=rk4&dt=0.001 fell back), and its four Euler runs all blew up before 1.5 s."""
    import math
    from rbcourse.simulate import simulate
    from rbcourse.workbook import demo
    from rbcourse.examples import get_scene
    ex = get_scene("pushed_box")
    euler = simulate(ex.scene, ex.X0, ex.t_end, ex.dt, "euler", on_divergence="stop")
    assert euler.diverged
    explorer = demo._explorer(ex, ex.method, ex.dt, euler, ex.t_end)
    assert explorer.settings.default == (ex.method, ex.dt)
    own = [r for r in explorer.runs if r.method == ex.method and math.isclose(r.dt, ex.dt)]
    assert len(own) == 1 and not own[0].diverged
    survivors = [r for r in explorer.runs if r.method == "euler" and not r.diverged]
    assert survivors and all(math.isclose(r.t_last, ex.t_end) for r in survivors)
    assert demo.euler_survives(ex, euler, ex.t_end) == pytest.approx(ex.dt / 2)


COMPUTE = """
import pickle, sys
from rbcourse.simulate import simulate
from rbcourse.workbook.demo import Computed
from rbcourse.examples import SCENES, get_scene
out = []
for name in SCENES:
    ex = get_scene(name)
    t_end = min(ex.t_end, 200 * ex.dt)
    runs = [simulate(ex.scene, ex.X0, t_end, ex.dt, m, on_divergence="stop") for m in (ex.method, "euler")]
    out.append((name, ex.method, [Computed(r) for r in runs], min(ex.drift_from, t_end / 2)))
pickle.dump(out, open(sys.argv[1], "wb"))
"""

BESIDE = """
import pickle, sys
from pathlib import Path
class Refuse:                                   # numba may not be imported here
    def find_spec(self, name, path=None, target=None):
        if name == "numba" or name.startswith("numba."):
            raise ImportError("numba imported beside: " + name)
sys.meta_path.insert(0, Refuse())
from rbcourse.workbook import demo
from rbcourse.examples import get_scene
for name, method, runs, t_from in pickle.load(open(sys.argv[1], "rb")):
    out = Path(sys.argv[2]) / name
    out.mkdir()
    written = demo._plots(out, get_scene(name), method, runs, [method, "euler"], t_from)
    assert [p.name for p in written] == demo.output_names(name)[:4], written
    assert all(p.stat().st_size > 0 for p in written)
print("numba" in sys.modules)
"""


def test_the_files_beside_need_no_compiled_engine(tmp_path):
    """The demo's process beside gets its runs as Computed (energies and quaternions computed where the engine is
    loaded): it writes the CSV, the two plots and the summary of every scene with numba never imported."""
    runs = tmp_path / "runs.pickle"
    done = subprocess.run([sys.executable, "-c", COMPUTE, str(runs)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    done = subprocess.run([sys.executable, "-c", BESIDE, str(runs), str(tmp_path)], capture_output=True, text=True,
                          timeout=600, env={**__import__("os").environ, "MPLBACKEND": "Agg"})
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"
