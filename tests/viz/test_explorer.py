"""The accuracy explorer, Python side: the grid's numbers (against rb.simulate and rb.exact_free_body
recomputed here), what is plotted for each scene (checked on the physics: a quantity called conserved is
conserved by a fine run), divergence, the timing (warm-ups first; perf_counter around rb.simulate only),
every bad input, the link fragment and default run, the meshes, the package data.  The page itself:
test_explorer_page.py."""
import json
import math
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import rbcourse as rb
from rbcourse.rotation import rotation_angle
from rbcourse.viz import explorer as xp
from rbcourse.viz import quantities
from rbcourse.viz.explorer import page, runs, text as xtext
from rbcourse.examples import (SCENES, Pulse, box_on_spring, dropped_box, heavy_top, many_bodies,
                                        pushed_box, tennis_racket)

from rbcourse.viz.viewer.assets import decompress  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def page_json(html: str) -> dict:
    """The page's data: its JSON block holds {lzma, size, json}: the data's JSON and its float32 arrays' buffer (bytes
    regrouped by place) compressed (assets.compress); each array reference {"f32": [start, count]} is read here."""
    block = json.loads(re.search(r'<script type="application/json" id="rb-data">(.*?)</script>', html, re.S).group(1))
    raw = decompress(block["lzma"])
    assert len(raw) == block["size"]
    planes = np.frombuffer(raw[block["json"]:], dtype=np.uint8).reshape(4, -1)
    floats = np.ascontiguousarray(planes.T).view("<f4").ravel()

    def resolve(x):
        if isinstance(x, dict):
            if set(x) == {"f32"}:
                return floats[x["f32"][0]: x["f32"][0] + x["f32"][1]]
            return {k: resolve(v) for k, v in x.items()}
        return [resolve(v) for v in x] if isinstance(x, list) else x
    return resolve(json.loads(raw[: block["json"]]))


def f32(a) -> np.ndarray:
    """An array of the page's data (page_json has read it)."""
    assert isinstance(a, np.ndarray) and a.dtype == np.float32
    return a


@pytest.fixture(scope="module")
def racket():
    """A free body: the exact torque-free motion is the reference."""
    return xp.explore(tennis_racket(), methods=["rk4", "splitting", "euler"], dts=[0.02, 0.01], t_end=2.0)


@pytest.fixture(scope="module")
def pushed():
    """A scene with a force: the fine rk4 reference; the slides' Euler diverges at dt = 0.02 s."""
    return xp.explore(pushed_box(), methods=["euler", "rk4"], dts=[0.02, 0.01], t_end=1.0)


# --- the numbers ---------------------------------------------------------------------------------

def test_free_body_runs_are_measured_against_the_exact_motion(racket):
    ex = tennis_racket()
    assert racket.reference.exact and "exact torque-free" in racket.reference.label
    for r in racket.runs:
        traj = rb.simulate(ex.scene, ex.X0, 2.0, r.dt, r.method)
        exact = rb.exact_free_body(ex.scene.bodies[0], ex.X0, traj.t)
        assert r.steps == len(traj.t) - 1 == round(2.0 / r.dt) and not r.diverged
        assert r.error == pytest.approx(float(rotation_angle(exact.R[-1], traj.R[-1])), rel=1e-9, abs=1e-15)
        # each curve point is the largest value since the previous point: the largest of all is kept
        E = traj.total_energy()
        drift = np.abs(E - E[0]) / abs(E[0])
        assert np.nanmax(r.curves["energy"]) == pytest.approx(drift.max(), rel=1e-12, abs=1e-300)
        assert np.nanmax(r.curves["rotation"]) == pytest.approx(rotation_angle(exact.R, traj.R).max(), rel=1e-9)
        assert np.nanmax(r.curves["orthogonality"]) == pytest.approx(traj.orthogonality_error().max(), rel=1e-9)
        assert r.curve_t[0] == 0 and r.curve_t[-1] == pytest.approx(2.0) and np.all(np.diff(r.curve_t) > 0)
        assert r.seconds > 0 and math.isfinite(r.seconds)
    # the measurement tells the orders apart: rk4 gains ~2⁴ when dt halves, splitting ~2², Euler keeps L exactly
    rk4 = racket.run("rk4", 0.02).error / racket.run("rk4", 0.01).error
    split = racket.run("splitting", 0.02).error / racket.run("splitting", 0.01).error
    assert 10 < rk4 < 25 and 3 < split < 5.5
    assert np.nanmax(racket.run("euler", 0.01).curves["momentum"]) < 1e-13
    euler, rk4_drift = (np.nanmax(racket.run(m, 0.01).curves["energy"]) for m in ("euler", "rk4"))
    assert euler > 1e3 * rk4_drift > 0                                         # the slides' Euler gains energy


def test_the_ghost_is_the_reference_at_the_frames(racket):
    ex = tennis_racket()
    g = racket.grid.ghost
    exact = rb.exact_free_body(ex.scene.bodies[0], ex.X0, g.t.astype(float))
    q = rb.rotation.quat_from_matrix(exact.R)
    assert np.allclose(np.abs(np.sum(q * g.q[:, 0], -1)), 1.0, atol=1e-6)       # the same rotation (q or −q)
    assert g.t[0] == 0 and g.t[-1] == pytest.approx(2.0) and len(g.t) == racket.settings.track_frames


def test_a_run_that_diverges_is_kept_up_to_its_blow_up_and_says_why(pushed):
    r = pushed.run("euler", 0.02)
    ex = pushed_box()
    alone = rb.simulate(ex.scene, ex.X0, 1.0, 0.02, "euler", on_divergence="stop")
    assert alone.diverged and r.diverged
    assert r.reason == alone.outcome and "diverged at t =" in r.reason
    assert r.t_last == alone.t[-1] < 1.0 and r.curve_t[-1] == r.t_last
    assert not math.isfinite(r.error) and r.track.t[-1] <= r.t_last
    assert np.all(np.isfinite(r.track.x)) and np.all(np.abs(r.track.x) < 1e6)
    data = page_json(pushed.html())
    d = next(x for x in data["runs"] if x["method"] == "euler" and x["dt"] == 0.02)
    assert d["diverged"] and d["error"] is None and d["reason"] == r.reason and d["t_last"] == r.t_last
    ok = pushed.run("rk4", 0.01)
    assert not ok.diverged and ok.t_last == pytest.approx(1.0) and math.isfinite(ok.error)


def test_a_scene_with_forces_is_measured_against_fine_rk4_at_the_runs_own_times(pushed):
    ref = pushed.reference
    assert not ref.exact and ref.label.startswith("rk4 at dt =")
    assert ref.h_star == pytest.approx(0.01 / 8)
    assert 0 < ref.accuracy < 1 and "twice its step" in ref.detail
    ex = pushed_box()
    r = pushed.run("rk4", 0.02)
    traj = rb.simulate(ex.scene, ex.X0, 1.0, 0.02, "rk4")
    m = 16                                        # the finest step is 0.01 s: every reference steps <= 0.01 / 8 s
    assert ref.fine_steps == 800 and ref.for_run(0.02, 50) is ref.for_run(0.02, 50)
    fine = rb.simulate(ex.scene, ex.X0, 1.0, 0.02 / m, "rk4", record_every=m)
    assert np.allclose(fine.t, traj.t)
    assert r.error == pytest.approx(float(rotation_angle(fine.R[-1], traj.R[-1])), rel=1e-9)


def test_the_references_of_steps_that_divide_the_fine_count_are_read_off_one_run_with_the_same_states(monkeypatch):
    from rbcourse.viz.explorer import reference as xref
    ex = pushed_box()
    runs_made = []
    real = xref.simulate
    monkeypatch.setattr(xref, "simulate", lambda *a, **k: runs_made.append(k.get("record_every")) or real(*a, **k))
    shared = xref.FineReference(ex.scene, ex.X0, 1.0, 400)      # h* = 1/3200 s
    shared.prepare([50, 100, 400, 300])                           # 300 does not divide 3200: a run of its own
    assert runs_made == [8]                                       # gcd(64, 32, 8) = 8: one run recorded every 8 steps
    for n in (50, 100, 400, 300):
        ref = shared.for_run(1.0 / n, n)
        m = math.ceil(3200 / n)
        alone = real(ex.scene, ex.X0, 1.0, 1.0 / (m * n), "rk4", record_every=m)
        assert len(ref.t) == n + 1 and ref.dt == alone.dt
        for key in "txRPL":
            assert np.array_equal(getattr(ref, key), getattr(alone, key)), (n, key)
    assert runs_made == [8, 11]                                   # only 300 ran again (m = 11, recorded every 11)
    wide = xref.FineReference(ex.scene, ex.X0, 1.0, 400)
    runs_made.clear()
    wide.prepare([400, 128])                                      # gcd(8, 25) = 1: 3200 states > 2 × 400, not kept
    assert runs_made == []


# --- what is plotted, and why ----------------------------------------------------------------------

@pytest.mark.parametrize("make, energy, momentum", [
    (tennis_racket, "drift", "com"), (pushed_box, "drift", "com"), (heavy_top, "drift", "vertical"),
    (box_on_spring, "error", "vertical"), (dropped_box, "error", "origin"), (many_bodies, "error", "origin"),
])
def test_what_is_plotted_follows_what_the_scene_conserves(make, energy, momentum):
    ex = make()
    p = quantities.plan(ex.scene, ex.drift_from, 2.0, 1e-3)
    assert p["energy"].mode == energy and p.momentum == momentum
    assert [q.key for q in p.quantities] == list(quantities.KEYS)
    assert all(q.title and q.note and q.unit for q in p.quantities)


@pytest.mark.parametrize("make", [heavy_top, box_on_spring, pushed_box, tennis_racket])
def test_a_quantity_called_conserved_is_conserved_by_a_fine_run(make):
    """The classification is checked on the physics: a fine rk4 run keeps what the plan calls conserved
    (to ~1e-8), and changes the energy it calls not conserved (the damped spring)."""
    ex = make()
    p = quantities.plan(ex.scene, ex.drift_from, 1.0, 1e-3)
    traj = rb.simulate(ex.scene, ex.X0, 1.0, ex.dt / 2, "rk4")
    v = quantities.values(p, traj, traj)
    if p.momentum in ("com", "vertical"):
        assert np.nanmax(v["momentum"]) < 1e-8
    if p.energy_conserved:
        assert np.nanmax(v["energy"]) < 1e-6
    else:                                            # not conserved: measured against the reference (here itself)
        assert np.nanmax(v["energy"]) == 0
        E = traj.total_energy()
        assert abs(E[-1] - E[0]) / abs(E[0]) > 1e-3
    if ex.drift_from > 0:                            # drifts start at t₀ (the end of the push)
        k0 = quantities.first_at(traj.t, ex.drift_from)
        assert traj.t[k0] == pytest.approx(ex.drift_from) and np.all(np.isnan(v["energy"][:k0]))


def test_a_force_that_keeps_acting_makes_the_energy_an_error_a_push_that_ended_does_not():
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    pushing = rb.Scene(body, [rb.PointForce((0.15, 0.1, 0.025), (0.0, 0.0, 1.0))])
    p = quantities.plan(pushing, 0.0, 1.0, 1e-2)
    assert p["energy"].mode == "error" and "keeps acting" in p["energy"].note and p.momentum == "origin"
    ended = rb.Scene(body, [rb.PointForce((0.15, 0.1, 0.025), Pulse((0, 0, 10.0), 0.0, 0.1))])
    assert quantities.plan(ended, 0.1, 1.0, 1e-2)["energy"].mode == "drift"
    assert quantities.plan(ended, 0.05, 1.0, 1e-2)["energy"].mode == "error"      # still pushing after t₀


# --- timing ----------------------------------------------------------------------------------------

def test_each_run_is_timed_around_simulate_after_one_warm_up_per_method(monkeypatch):
    """A fake clock that only simulate() advances (by 1 s per full-length run): every run's wall time is
    then exactly 1 s, so the timing wraps simulate and nothing else; the warm-ups come first, one per method."""
    calls, clock = [], [0.0]
    real = runs.simulate

    def simulate(scene, X0, t_end, dt, method, **kw):
        calls.append((method, t_end))
        if t_end == 1.0:
            clock[0] += 1.0
        return real(scene, X0, t_end, dt, method, **kw)
    monkeypatch.setattr(runs, "simulate", simulate)
    monkeypatch.setattr(runs.time, "perf_counter", lambda: clock[0])
    e = xp.explore(tennis_racket(), methods=["rk4", "euler"], dts=[0.05, 0.025], t_end=1.0)
    assert [r.seconds for r in e.runs] == [1.0] * 4
    assert [m for m, _ in calls[:2]] == ["rk4", "euler"] and all(t < 1.0 for _, t in calls[:2])
    assert sorted(calls[2:]) == sorted((m, 1.0) for m in ("rk4", "euler") for _ in range(2))
    assert "warm-up" in e.html() and "compile time excluded" in e.html()


def late_kick(ex, time: float = 1.5):
    """ex's scene with an Impulse at `time` (after the warm-up's 10 coarse steps), and that Impulse."""
    kick = rb.Impulse([0.1, 0.0, 0.0], [0.0, 0.0, 0.5], time)
    return rb.Scene(ex.scene.bodies, [*ex.scene.effects, kick], name="kicked"), kick


def test_a_scene_with_an_impulse_after_the_warm_up_explores_as_simulate_runs_it(monkeypatch):
    """The warm-up runs 10 coarse steps (0.5 s here); an Impulse at 1.5 s once made it raise "Impulse.time must be
    in [0, t_end] = [0, 0.5] s", a t_end the user never gave.  Now each run is simulate's on the user's scene, the
    kick included, and the scene given is not changed."""
    ex = tennis_racket()
    scene, kick = late_kick(ex)
    effects = scene.effects
    calls = []
    real = runs.simulate

    def simulate(sc, X0, t_end, dt, method, **kw):
        calls.append((sc, t_end))
        return real(sc, X0, t_end, dt, method, **kw)
    monkeypatch.setattr(runs, "simulate", simulate)
    e = xp.explore(scene, ex.X0, methods=["rk4", "euler"], dts=[0.05, 0.025], t_end=2.0)
    assert scene.effects == effects and scene.effects[-1] is kick and kick.time == 1.5
    warm = [(sc, t) for sc, t in calls if t < 2.0]
    assert len(warm) == 2 and all(t == pytest.approx(0.5) for _, t in warm)
    for sc, _ in warm:                                # the warm-up's own scene: the kick there, of J = 0
        kicks = [k for k in sc.effects if isinstance(k, rb.Impulse)]
        assert sc is not scene and len(kicks) == 1 and 0 < kicks[0].time < 0.5 and not np.any(kicks[0].impulse)
    assert all(sc is scene for sc, t in calls if t == 2.0)
    for method, dt in (("rk4", 0.05), ("euler", 0.025)):
        run = e.grid.run(method, dt)
        traj = rb.simulate(scene, ex.X0, 2.0, dt, method)
        unkicked = rb.simulate(ex.scene, ex.X0, 2.0, dt, method)
        assert not run.diverged and run.t_last == 2.0
        assert np.allclose(run.track.x[-1, 0], traj.x[-1], atol=1e-5)
        assert not np.allclose(run.track.x[-1, 0], unkicked.x[-1], atol=1e-2)     # the kick at 1.5 s was applied


def test_the_warm_up_scene_is_the_scene_itself_unless_a_kick_falls_after_it():
    ex = tennis_racket()
    scene, kick = late_kick(ex, 0.3)
    assert runs.warmup_scene(scene, 0.5) is scene and runs.warmup_scene(ex.scene, 0.5) is ex.scene
    early = rb.Impulse([0.0, 0.1, 0.0], [1.0, 0.0, 0.0], 0.2, body=0)
    both = rb.Scene(ex.scene.bodies, [early, rb.Impulse([0.1, 0, 0], [0, 0, 2.0], 1.9, body=0)])
    warm = runs.warmup_scene(both, 0.5)
    kept, moved = warm.effects
    assert kept is early and moved.time == 0.25 and moved.body == 0 and not np.any(moved.impulse)
    assert list(moved.body_point) == [0.1, 0, 0] and both.effects[1].time == 1.9 and both.effects[1].impulse[2] == 2


def test_an_impulse_after_the_explorers_t_end_is_refused_naming_it_before_anything_runs(nothing_runs):
    ex = tennis_racket()
    scene, _ = late_kick(ex, 2.5)
    with pytest.raises(ValueError, match=r"Impulse.time \(t\) must be in \[0, t_end\] = \[0, 2\] s"):
        xp.explore(scene, ex.X0, methods=["rk4"], dts=[0.05], t_end=2.0)


# --- bad inputs ------------------------------------------------------------------------------------

BAD = [
    (dict(methods=["verlet"]), "method must be one of"),
    (dict(methods=[]), "methods must be a non-empty list"),
    (dict(methods="rk4"), "methods must be a non-empty list"),
    (dict(methods=["rk4", "rk4"]), "must not repeat"),
    (dict(methods=sorted(rb.METHODS)[:7]), "at most 6 methods"),
    (dict(dts=[]), "dts must be a non-empty list"),
    (dict(dts=0.01), "dts must be a non-empty list"),
    (dict(dts=[0.01, -0.01]), "dts[1] must be > 0"),
    (dict(dts=[float("nan")]), "dts[0] must be finite"),
    (dict(dts=[float("inf")]), "dts[0] must be finite"),
    (dict(dts=["0.01"]), "dts[0] must be a real number"),
    (dict(dts=[0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001]), "at most 6 steps"),
    (dict(dts=[3.0]), "dts[0] must be <= t_end"),
    (dict(dts=[0.01, 0.0100001]), "both give 200 steps"),
    (dict(dts=[1e-6]), "MAX_STEPS = 1,000,000"),
    (dict(t_end=1e308, dts=[1e-300]), "gives inf steps"),
    (dict(t_end=1e308, dts=[1e300]), "MAX_STEPS = 1,000,000"),
    (dict(t_end=0.0), "t_end must be > 0"),
    (dict(t_end=-1.0), "t_end must be > 0"),
    (dict(t_end=float("nan")), "t_end must be finite"),
    (dict(t_end=0.001, dts=None), "shorter than the default steps"),
    (dict(frames=10), "frames must be an integer in [30, 1000]"),
    (dict(frames=5000), "frames must be an integer in [30, 1000]"),
    (dict(frames=100.0), "frames must be an integer"),
    (dict(drift_from=2.0), "drift_from must be < 2"),
    (dict(drift_from=-0.1), "drift_from must be >= 0"),
    (dict(default=("euler", 0.01)), "default's method must be one of"),
    (dict(default=("rk4", 0.03)), "default's dt must be one of"),
    (dict(default="rk4"), "default must be None or a pair"),
    (dict(name=3), "name must be a string"),
    (dict(progress="yes"), "progress must be True or False"),
]


@pytest.fixture
def nothing_runs(monkeypatch):
    def forbidden(*args, **kwargs):
        raise AssertionError("a bad argument must be refused before anything is computed")
    monkeypatch.setattr(runs, "simulate", forbidden)
    monkeypatch.setattr(xp, "run_grid", forbidden)


@pytest.mark.parametrize("kwargs, words", BAD, ids=[str(k) for k, _ in BAD])
def test_a_bad_argument_is_a_value_error_naming_it_before_anything_runs(kwargs, words, nothing_runs):
    args = dict(methods=["rk4"], dts=[0.01], t_end=2.0)
    args.update(kwargs)
    with pytest.raises(ValueError) as info:
        xp.explore(tennis_racket(), **args)
    assert words in str(info.value), str(info.value)


def test_an_unknown_method_lists_the_allowed_ones(nothing_runs):
    with pytest.raises(ValueError, match="verlet") as info:
        xp.explore(tennis_racket(), methods=["rk4", "verlet"], dts=[0.01], t_end=1.0)
    assert all(m in str(info.value) for m in rb.METHODS)


def test_bad_scenes_and_states_are_refused(nothing_runs):
    ex = tennis_racket()
    with pytest.raises(ValueError, match="scene must be a Scene or a RigidBody"):
        xp.explore("tennis_racket", ex.X0)
    with pytest.raises(ValueError, match="X0 must be a State"):
        xp.explore(ex.scene)
    with pytest.raises(ValueError, match="X0 holds 1 body but the scene has 2"):
        xp.explore(rb.Scene([ex.scene.bodies[0]] * 2), ex.X0)


def test_too_many_bodies_for_one_page_is_refused_with_the_limit(nothing_runs):
    ex = many_bodies()
    with pytest.raises(ValueError, match="MAX_BODY_FRAMES = 120,000") as info:
        xp.explore(ex, methods=sorted(rb.METHODS)[:6], dts=[0.04, 0.02, 0.01, 0.005, 0.0025, 0.00125], t_end=2.0)
    assert "200 bodies" in str(info.value)
    s = runs.check_arguments(ex, methods=["euler", "rk4"], dts=[0.04, 0.02], t_end=2.0)   # a smaller grid fits
    assert runs.MIN_FRAMES <= s.track_frames < s.frames and s.track_frames * 200 * 5 <= runs.MAX_BODY_FRAMES


# --- defaults, the fragment ------------------------------------------------------------------------

def test_the_defaults_come_from_the_example():
    ex = pushed_box()
    s = runs.check_arguments(ex)
    assert s.methods == runs.DEFAULT_METHODS and s.t_end == ex.t_end and s.drift_from == ex.drift_from
    assert s.dts == tuple(ex.dt * f for f in runs.DEFAULT_DT_FACTORS)
    assert s.default == ("rk4", s.dts[0]) and s.name == "pushed box" and s.description == ex.description
    bare = runs.check_arguments(ex.scene.bodies[0], rb.State.at_rest())
    assert bare.dts == runs.BARE_DEFAULTS["dts"] and bare.t_end == runs.BARE_DEFAULTS["t_end"] and bare.drift_from == 0
    s = runs.check_arguments(ex, methods=["euler", "rk4"], dts=[0.02, 0.01], default=("rk4", 0.01 + 1e-15))
    assert s.default == ("rk4", 0.01)


def test_the_link_fragment_of_a_run_and_the_default_in_the_page(racket):
    assert racket.fragment("rk4", 0.01) == "#method=rk4&dt=0.01"
    assert racket.fragment("euler") == "#method=euler" and racket.fragment(dt=0.02) == "#dt=0.02"
    assert racket.fragment() == ""
    for bad in (dict(method="verlet"), dict(dt=0.03), dict(dt="0.01")):
        with pytest.raises(ValueError):
            racket.fragment(**bad)
    data = page_json(racket.html())
    assert data["methods"][data["default"]["method"]]["name"] == "rk4" and data["dts"][data["default"]["dt"]] == 0.02
    # the page writes each dt as the shortest text that reads back as the same float (JS Number() does the same)
    for d in (0.02, 1 / 3, 2.5e-4, 0.1 + 0.2):
        assert float(xtext.dt_text(d)) == d


# --- shapes, packaging, imports ------------------------------------------------------------------

def view_commands(data: dict) -> list:
    """The meshcat commands of a page's 3-D view (view.py), decoded as the page's rbCommands reads them."""
    import umsgpack
    from rbcourse.viz.viewer import assets
    buf, out, i = assets.decompress(data["view"]["commands"]), [], 0
    assert len(buf) == data["view"]["size"]
    while i < len(buf):
        n = int.from_bytes(buf[i:i + 4], "little")
        out.append(umsgpack.unpackb(buf[i + 4:i + 4 + n]))
        i += 4 + n
    return out


def test_the_3d_view_is_meshcats_scene_of_the_bodies_the_ghost_and_the_links(racket):
    data = page_json(racket.html())
    cmds = view_commands(data)
    objs = {c["path"]: c["object"] for c in cmds if c["type"] == "set_object"}
    box = objs["/meshcat/bodies/0/shape"]["geometries"][0]
    assert box["type"] == "BoxGeometry"
    assert [box["width"], box["height"], box["depth"]] == pytest.approx(list(tennis_racket().scene.bodies[0].size))
    ghost = objs["/meshcat/ghost/0/shape"]["materials"][0]
    assert ghost["transparent"] and ghost["opacity"] == 0.22 and "/meshcat/bodies/0/axes" in objs
    shell = next(c["matrix"] for c in cmds if c["type"] == "set_transform" and c["path"] == "/meshcat/ghost/0/shape")
    assert np.allclose(np.diag(np.reshape(shell, (4, 4)))[:3], 1.02)          # a shell just around the body
    assert not any(c["type"] == "set_animation" for c in cmds)      # moved by the page's own cursor (js/scene.js)
    assert data["view"]["links"] == [] and data["view"]["follow"] is False
    assert data["bodies"] == [{"color": "#f28e2b"}] and data["ghost_color"] == "#17becf"   # the viewer's colours
    # a spring: its coil, stretched from its anchor to its body point; a pivot: its stem, from the pivot to the centre
    spring = box_on_spring()
    e = next(e for e in spring.scene.effects if isinstance(e, rb.Spring))
    k = spring.scene.effects.index(e)
    sd = page_json(xp.explore(spring, methods=["rk4"], dts=[0.05], t_end=0.5).html())
    assert sd["view"]["links"] == [{"path": ["meshcat", "springs", str(k)], "body": 0, "b": e.body_point.tolist(),
                                    "anchor": e.world_point.tolist(), "other": None, "ob": None}]
    assert f"/meshcat/springs/{k}/coil" in {c["path"] for c in view_commands(sd)}
    top = heavy_top()
    p = next(e for e in top.scene.effects if isinstance(e, rb.Pivot))
    td = page_json(xp.explore(top, methods=["rk4"], dts=[0.01], t_end=0.2).html())
    (stem,) = td["view"]["links"]
    assert stem["anchor"] == p.world_point.tolist() and stem["b"] == [0.0, 0.0, 0.0] and stem["path"][1] == "stems"
    # one body that moves far is followed
    assert page_json(xp.explore(pushed_box(), methods=["rk4"], dts=[0.02], t_end=5.0).html())["view"]["follow"]


def test_the_script_and_styles_are_package_data():
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert set(cfg["tool"]["setuptools"]["package-data"]["rbcourse.viz.explorer"]) == {"js/*.js", "explorer.css"}
    assert sorted(page.SCRIPTS) == sorted(p.name for p in (ROOT / "rbcourse/viz/explorer/js").glob("*.js"))
    assert "requestAnimationFrame" in page.script() and "#rb-main" in page.asset("explorer.css")


def test_importing_rbcourse_viz_loads_neither_the_explorer_nor_the_engine_nor_meshcat():
    code = ("import sys, rbcourse; before = set(sys.modules); import rbcourse.viz as v; new = set(sys.modules) - before;"
            "print(sorted(new)); v.explore; print('meshcat' in sys.modules, 'numba' in sys.modules,"
            "'rbcourse.viz.explorer' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120)
    first, second = out.stdout.splitlines()
    assert first == "['rbcourse.viz']"
    assert second == "False False True"


def test_the_rotation_error_is_evaluated_at_every_step_of_a_short_run_and_every_kth_of_a_long_one():
    assert np.array_equal(quantities.rotation_rows(1000, 1), np.arange(1000))
    rows = quantities.rotation_rows(200_001, 1, keep=[7, 199_999])
    k = math.ceil(200_001 / quantities.ROTATION_EVALS)
    assert k == 5 and set(range(0, 200_001, k)) | {7, 199_999, 200_000} == set(rows.tolist())
    assert len(quantities.rotation_rows(1000, 200)) == len(range(0, 1000, 4)) + 1     # 200 bodies: every 4th, and the last
