"""The compiled engine (rbcourse/engine) against the numpy engine (fast=False), itself, and the course's numbers.

Agreement is measured per array (x, R, P, L) as  max |a − b| / (1 + max |b|):  relative to the array's
size when it is large, absolute when it is small (a velocity that stays near 0 would make a pure relative
error meaningless, a position of order 10 would make a pure absolute one too strict).  1e-12 is a few
thousand roundings of a double: the two engines do the same arithmetic in a different order, so they
agree to rounding, not to the bit; a wrong formula, a wrong sign or a wrong stage time gives 1e-6 or more.
"""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import rbcourse as rb
from rbcourse import driver

DT = 1e-3
STEPS = 1000
TOL = 1e-12
INTERPRETED_STEPS = 200
BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def spread(a, b) -> float:
    """max |a − b| / (1 + max |b|) (see the module docstring)."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, (a.shape, b.shape)
    if a.size == 0:
        return 0.0
    return float(np.max(np.abs(a - b)) / (1.0 + np.max(np.abs(b))))


def assert_same_run(a, b, tol=TOL, what=""):
    assert len(a.t) == len(b.t), f"{what}: {len(a.t)} vs {len(b.t)} recorded states"
    np.testing.assert_allclose(a.t, b.t, rtol=0, atol=1e-12)
    for k in ("x", "R", "P", "L"):
        d = spread(getattr(a, k), getattr(b, k))
        assert d <= tol, f"{what}: {k} differs by {d:.3g} (relative, > {tol:g})"


def spinning(body=BOX, x=(0.0, 0.0, 1.0), v=(0.1, -0.2, 0.3), omega=(0.3, 2.0, 0.5), R=None):
    R = np.eye(3) if R is None else R
    return rb.State.from_velocities(body, x=x, R=R, v=v, omega=omega)


R_TILT = rb.rotation.rotation_about([1.0, 2.0, 3.0], 0.4)
PIVOT = rb.Pivot(body_point=(0.0, 0.0, -0.05))


def push(t):
    """A force that is a function of t (the driver evaluates it at every stage time)."""
    return (np.sin(3.0 * t), 0.5 * np.cos(2.0 * t), 1.0 + t)


# every smooth effect, one scene each (and a few combinations): name -> () -> (scene, X0)
CASES = {
    "free": lambda: (rb.Scene(BOX), spinning()),
    "gravity": lambda: (rb.Scene(BOX, [rb.Gravity()]), spinning()),
    "point_world": lambda: (rb.Scene(BOX, [rb.PointForce((0.15, 0.1, 0.025), (0.0, 0.0, 10.0))]), spinning()),
    "point_body": lambda: (rb.Scene(BOX, [rb.PointForce((0.15, 0.1, 0.025), (0.0, 0.0, 1.0), frame="body")]),
                           spinning()),
    # 10 N turning with the body spins it up without bound: the slides' Euler (and quaternion Euler) blow up
    "point_body_spin_up": lambda: (rb.Scene(BOX, [rb.PointForce((0.15, 0.1, 0.025), (0.0, 0.0, 10.0),
                                                                frame="body")]), spinning()),
    "point_world_f(t)": lambda: (rb.Scene(BOX, [rb.PointForce((0.15, 0.1, 0.025), push)]), spinning()),
    "point_body_f(t)": lambda: (rb.Scene(BOX, [rb.PointForce((0.15, -0.1, 0.0), push, frame="body")]),
                                spinning()),
    "spring_rest0": lambda: (rb.Scene(BOX, [rb.Spring((0.1, 0.05, 0.0), (0.0, 0.0, 0.0), stiffness=5.0)]),
                             spinning(R=R_TILT)),
    "spring_rest_damped": lambda: (rb.Scene(BOX, [rb.Spring((0.1, 0.05, 0.0), (0.0, 0.2, 1.5), stiffness=50.0,
                                                            damping=0.3, rest_length=0.4)]), spinning(R=R_TILT)),
    "two_bodies_spring": lambda: (
        rb.Scene([BOX, rb.RigidBody.box(2.0, (0.1, 0.4, 0.2))],
                 [rb.Spring((0.1, 0.0, 0.0), stiffness=20.0, damping=0.2, rest_length=0.3, body=0, other_body=1,
                            other_point=(0.0, 0.1, 0.0))]),
        rb.State.stack([spinning(), spinning(rb.RigidBody.box(2.0, (0.1, 0.4, 0.2)), x=(0.5, 0.2, 1.0),
                                             v=(0.0, 0.3, 0.0), omega=(-1.0, 0.4, 1.5), R=R_TILT)])),
    "linear_drag": lambda: (rb.Scene(BOX, [rb.LinearDrag(0.7), rb.Gravity()]), spinning()),
    "angular_drag": lambda: (rb.Scene(BOX, [rb.AngularDrag(0.02)]), spinning(omega=(0.3, 5.0, 0.5))),
    "heavy_top": lambda: (rb.Scene(BOX, [rb.Gravity(), PIVOT]), PIVOT.state(BOX, R_TILT, [0.5, 0.0, 10.0])),
    "impulse": lambda: (rb.Scene(BOX, [rb.Gravity(), rb.Impulse((0.15, 0.1, 0.0), (0.0, 0.05, 0.2), time=0.4)]),
                        spinning()),
    "ground": lambda: (rb.Scene(BOX, [rb.Gravity(), rb.Ground(restitution=0.5, friction=0.5)]),
                       spinning(x=(0.0, 0.0, 0.3), v=(0.3, 0.0, -1.0), omega=(1.0, 2.0, 0.5), R=R_TILT)),
    "spring_gravity_force": lambda: (rb.Scene(BOX, [rb.Gravity(), rb.Spring((0.1, 0.05, 0.0), (0.0, 0.0, 1.0),
                                                                            stiffness=50.0, damping=0.1),
                                                    rb.PointForce((0.15, 0.1, 0.025), push)]), spinning(R=R_TILT)),
}


def one_ulp_sensitivity(scene, X0, method, steps=STEPS):
    """Per recorded row, how far the numpy engine moves when L(0) changes by one rounding (relative 2^-52):
    the amplification of rounding by the dynamics themselves (max over x, R, P, L, as `spread`)."""
    base = rb.simulate(scene, X0, steps * DT, DT, method, fast=False, on_divergence="stop")
    nudged = rb.State(x=X0.x, R=X0.R, P=X0.P, L=X0.L * (1.0 + 2.0**-52))
    other = rb.simulate(scene, nudged, steps * DT, DT, method, fast=False, on_divergence="stop")
    m = min(len(base.t), len(other.t))
    return np.array([max(spread(getattr(other, k)[i], getattr(base, k)[i]) for k in ("x", "R", "P", "L"))
                     for i in range(m)])


def not_compiled(method, scene) -> str:
    """'' if the compiled engine runs `method` on `scene`, else why not (the driver's own answer)."""
    return driver.supports(driver.kernel(fast=True), rb.METHODS[method], scene.system())


def run_both(name, method, steps=STEPS):
    scene, X0 = CASES[name]()
    fast = rb.simulate(scene, X0, steps * DT, DT, method, fast=True, on_divergence="stop")
    slow = rb.simulate(scene, X0, steps * DT, DT, method, fast=False, on_divergence="stop")
    return fast, slow


# --- 1. the compiled engine is the numpy engine, to rounding: every method x every effect -------------

@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("method", sorted(rb.METHODS))
def test_compiled_equals_numpy(method, name):
    fast, slow = run_both(name, method)
    if name == "point_body_spin_up" and method == "euler":
        assert slow.diverged          # the case the divergence branch below is for
    why = not_compiled(method, CASES[name]()[0])
    if why:     # adaptive with forces f(t) (its substep times are its own), exact_splitting on an asymmetric body
        assert why in fast.implementation, fast.implementation
        return
    assert fast.implementation.startswith("compiled"), fast.implementation
    assert slow.implementation.startswith("interpreted (fast=False)"), slow.implementation
    assert fast.diverged == slow.diverged, (fast.divergence, slow.divergence)
    if not slow.diverged:
        assert_same_run(fast, slow, what=f"{method}, {name}")
        return
    # A run that blows up: both engines stop at the same step, with as many recorded states, the same
    # array blowing up.  Approaching the blow-up the dynamics amplify rounding (by 1e30 and more): the states
    # are compared to 1e-12 on the rows where the numpy engine itself, started one rounding away,
    # stays within 1e-14 (rounding not yet amplified 100-fold) -- at least a third of the run.
    assert fast.divergence.step == slow.divergence.step, (fast.divergence, slow.divergence)
    # the same array blew up; whether it overflowed to inf or became NaN (inf − inf) depends on the order
    # of operations on states beyond 1e100, which the two engines need not share
    assert fast.divergence.reason.split()[0] == slow.divergence.reason.split()[0], (fast.divergence, slow.divergence)
    assert len(fast.t) == len(slow.t)
    scene, X0 = CASES[name]()
    amplified = one_ulp_sensitivity(scene, X0, method) > 1e-14
    tame = int(np.argmax(amplified)) if amplified.any() else len(amplified)
    assert tame > len(slow.t) // 3, tame
    assert_same_run(fast.head(tame), slow.head(tame), what=f"{method}, {name}, first {tame} states")


def test_the_cases_exercise_what_they_are_named_for():
    """On the compiled path: the box lands on the ground and bounces, the kick arrives, the top stays pivoted."""
    scene, X0 = CASES["ground"]()
    traj = rb.simulate(scene, X0, STEPS * DT, DT, "rk4")
    assert traj.P[:, 2].min() < -1.5 and traj.P[:, 2].max() > 0.1          # falls, then bounces up
    assert abs(traj.x[-1, 2] - 0.025) < 1e-6                                  # at rest on its face
    scene, X0 = CASES["impulse"]()
    traj = rb.simulate(scene, X0, STEPS * DT, DT, "rk4")
    k = int(round(0.4 / DT))                # the kick is applied at the start of the step containing t = 0.4
    np.testing.assert_allclose(traj.P[k + 1] - traj.P[k], (0.0, 0.05, 0.2 - 9.81 * DT), atol=1e-12)
    scene, X0 = CASES["heavy_top"]()
    traj = rb.simulate(scene, X0, STEPS * DT, DT, "rk4")
    tip = traj.x + np.einsum("nij,j->ni", traj.R, PIVOT.body_point)
    np.testing.assert_allclose(tip, 0.0, atol=1e-12)                          # the pivot point stays put
    assert traj.implementation.startswith("compiled")


# --- 2. N bodies --------------------------------------------------------------------------------------

BODIES = [rb.RigidBody.box(1.0, (0.3, 0.2, 0.05)), rb.RigidBody.box(2.5, (0.1, 0.4, 0.2)),
          rb.RigidBody.box(0.4, (0.05, 0.05, 0.6))]
STARTS = [spinning(BODIES[0], x=(0.0, 0.0, 1.0), omega=(0.3, 2.0, 0.5)),
          spinning(BODIES[1], x=(1.0, 0.0, 0.5), v=(0.0, 0.2, 0.0), omega=(-1.0, 0.4, 1.5), R=R_TILT),
          spinning(BODIES[2], x=(0.0, 1.0, 2.0), v=(0.3, 0.0, -0.1), omega=(0.2, -0.7, 3.0))]

# effects selected per body, none coupling two bodies: (effect for the N-body scene, [bodies], the single-body one)
SELECTED = [
    (lambda: rb.Gravity(body=[1, 2]), [1, 2], lambda: rb.Gravity()),
    (lambda: rb.PointForce((0.15, 0.1, 0.025), (0.0, 0.0, 10.0), body=0), [0],
     lambda: rb.PointForce((0.15, 0.1, 0.025), (0.0, 0.0, 10.0))),
    (lambda: rb.PointForce((0.0, 0.1, 0.05), push, frame="body", body=2), [2],
     lambda: rb.PointForce((0.0, 0.1, 0.05), push, frame="body")),
    (lambda: rb.Spring((0.05, 0.0, 0.1), (0.0, 0.0, 1.0), stiffness=30.0, damping=0.2, rest_length=0.2, body=[0, 1]),
     [0, 1], lambda: rb.Spring((0.05, 0.0, 0.1), (0.0, 0.0, 1.0), stiffness=30.0, damping=0.2, rest_length=0.2)),
    (lambda: rb.LinearDrag(0.5, body=1), [1], lambda: rb.LinearDrag(0.5)),
    (lambda: rb.AngularDrag(0.03), [0, 1, 2], lambda: rb.AngularDrag(0.03)),   # every body
]


def selected(method):
    """SELECTED: every effect, forces given as f(t) included (adaptive evaluates them before each attempt)."""
    return list(SELECTED)


# The implicit midpoint's Newton loop stops on the largest change over all the bodies of a scene, as the
# numpy step does: a body stepped with others may take one iteration more than alone, a change of a
# rounding per step (1.03e-12 after 500 steps measured).
ALONE_TOL = {"implicit_midpoint": 1e-11}


@pytest.mark.parametrize("method", sorted(rb.METHODS))
def test_independent_bodies_of_a_scene_are_their_single_body_runs(method):
    SELECTED = selected(method)
    scene = rb.Scene(BODIES, [make() for make, _, _ in SELECTED])
    if not_compiled(method, scene):
        pytest.skip(not_compiled(method, scene))
    both = rb.simulate(scene, rb.State.stack(STARTS), 0.5, DT, method)
    assert both.implementation.startswith("compiled") and both.x.shape == (501, 3, 3)
    for i, (body, X0) in enumerate(zip(BODIES, STARTS)):
        alone = rb.simulate(rb.Scene(body, [single() for _, on, single in SELECTED if i in on]), X0, 0.5, DT, method)
        assert alone.implementation.startswith("compiled")
        for k in ("x", "R", "P", "L"):
            d = spread(getattr(both, k)[:, i], getattr(alone, k))
            assert d <= ALONE_TOL.get(method, TOL), f"{method}, body {i}: {k} differs from its single-body run by {d:.3g}"
    # and the selection matters: body 0 has no gravity, body 1 has
    assert both.P[-1, 0, 2] > both.P[-1, 1, 2] + 1.0


@pytest.mark.parametrize("method", sorted(rb.METHODS))
def test_coupled_bodies_agree_with_the_numpy_engine(method):
    SELECTED = selected(method)
    effects = [make() for make, _, _ in SELECTED] + [
        rb.Spring((0.1, 0.0, 0.0), stiffness=40.0, damping=0.3, rest_length=0.5, body=0, other_body=1,
                  other_point=(0.0, 0.1, 0.0)),
        rb.Spring((0.0, 0.0, 0.3), stiffness=25.0, body=2, other_body=0, other_point=(0.0, 0.1, 0.0))]
    scene = rb.Scene(BODIES, effects)
    if not_compiled(method, scene):
        pytest.skip(not_compiled(method, scene))
    X0 = rb.State.stack(STARTS)
    fast = rb.simulate(scene, X0, STEPS * DT, DT, method)
    slow = rb.simulate(scene, X0, STEPS * DT, DT, method, fast=False)
    assert fast.implementation.startswith("compiled") and slow.implementation.startswith("interpreted (fast=False)")
    assert_same_run(fast, slow, what=f"{method}, 3 coupled bodies")
    # the coupling springs act (the bodies are not independent): body 0 differs from its uncoupled run
    free = rb.simulate(rb.Scene(BODIES, [make() for make, _, _ in SELECTED]), X0, STEPS * DT, DT, method)
    assert spread(fast.x[:, 0], free.x[:, 0]) > 1e-3


# --- 3. interpreted (NUMBA_DISABLE_JIT=1): the same functions, run as Python, give the same numbers ------

INTERPRETED_CASES = [("spring_gravity_force", "rk4"), ("spring_gravity_force", "euler")] + [
    ("two_bodies_spring", m) for m in sorted(rb.METHODS) if not not_compiled(m, CASES["two_bodies_spring"]()[0])]


def interpreted(tmp_path, mode: str, out: str):
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    subprocess.run([sys.executable, str(HERE / "engine_interpreted_check.py"), mode, str(tmp_path / out)],
                   check=True, cwd=ROOT, env=env, timeout=120)
    return tmp_path / out


def test_interpreted_runs_equal_the_compiled_runs(tmp_path):
    path = interpreted(tmp_path, "runs", "runs.npz")
    info = json.loads(path.with_suffix(".json").read_text())
    assert info["IMPLEMENTATION"] == "interpreted", info
    with np.load(path) as saved:
        for name, method in INTERPRETED_CASES:
            assert info[f"{name}|{method}|implementation"].startswith("interpreted"), info
            scene, X0 = CASES[name]()
            traj = rb.simulate(scene, X0, INTERPRETED_STEPS * DT, DT, method)
            assert traj.implementation.startswith("compiled")
            np.testing.assert_array_equal(saved[f"{name}|{method}|t"], traj.t)
            for k in ("x", "R", "P", "L"):
                d = spread(saved[f"{name}|{method}|{k}"], getattr(traj, k))
                assert d <= TOL, f"{method}, {name}: interpreted {k} differs from compiled by {d:.3g}"


# --- 4. a scene with no effect calls no force code ---------------------------------------------------------

def test_a_free_body_calls_no_force_code(tmp_path):
    counts = json.loads(interpreted(tmp_path, "calls", "calls.json").read_text())
    assert counts["IMPLEMENTATION"] == "interpreted"
    assert counts["free|implementation"].startswith("interpreted")
    assert counts["free"] == {"effect_on": 0, "effect_on_body": 0, "resultants": 0, "body_resultants": 0}, counts
    # the counting wrappers do count (the patch reaches the callers): 20 rk4 steps of 4 stages; a drag, which
    # changes with the motion, is evaluated at each stage (the resultants on every body, or body by body: one
    # body); gravity alone (a central scene: M g, the same at every stage) once per step, before its stages
    drag = counts["drag"]
    assert drag["resultants"] + drag["body_resultants"] == 80 and drag["effect_on_body"] == 80, counts
    gravity = counts["gravity"]
    assert gravity["resultants"] + gravity["body_resultants"] == 20 and gravity["effect_on_body"] == 20, counts


# --- 5. divergence on the compiled path ---------------------------------------------------------------------

def test_the_slides_euler_on_a_fast_spinning_box_diverges_cleanly():
    X0 = rb.State.from_velocities(BOX, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), omega=(0.1, 0.1, 50.0))
    with pytest.raises(rb.SimulationDiverged) as err:
        rb.simulate(BOX, X0, 60.0, 1e-2, "euler")
    traj = err.value.trajectory
    assert traj.implementation.startswith("compiled")
    assert len(traj.t) > 1
    assert all(np.isfinite(getattr(traj, k)).all() for k in ("t", "x", "R", "P", "L"))
    assert traj.t[-1] < err.value.t <= 60.0
    stopped = rb.simulate(BOX, X0, 60.0, 1e-2, "euler", on_divergence="stop")
    reference = rb.simulate(BOX, X0, 60.0, 1e-2, "euler", on_divergence="stop", fast=False)
    assert stopped.diverged and reference.diverged
    assert stopped.divergence.step == reference.divergence.step == err.value.step
    assert stopped.divergence.step < 6000


# --- 6. measured order on the compiled path -------------------------------------------------------------------

def order(method, dt, t_end=1.0):
    """log2 of the error ratio at dt and dt/2, against a run at dt/16 (at the final time, all of x, R, P, L)."""
    scene = rb.Scene(BOX, [rb.Gravity(), rb.Spring((0.1, 0.05, 0.0), (0.0, 0.0, 1.0), stiffness=20.0)])
    X0 = spinning(R=R_TILT)

    def final(h):
        traj = rb.simulate(scene, X0, t_end, h, method)
        assert traj.implementation.startswith("compiled")
        return np.concatenate([traj.x[-1], traj.R[-1].ravel(), traj.P[-1], traj.L[-1]])

    ref = final(dt / 16)
    e1, e2 = (np.max(np.abs(final(h) - ref)) for h in (dt, dt / 2))
    return np.log2(e1 / e2)


def test_rk4_is_fourth_order():
    assert 3.6 < order("rk4", 0.02) < 4.4


@pytest.mark.parametrize("method", ["euler", "euler_project", "quaternion_euler", "quaternion_euler_body"])
def test_euler_methods_are_first_order(method):
    # the reference at dt/16 is itself first-order wrong: the ratio (e(h) / e(h/2)) is (1 − 1/16) / (1/2 − 1/16)
    p = order(method, 1e-3)
    assert 0.8 < p < 1.3, p
