"""Blow-ups: one check on every code path, the kept trajectory finite, and the two paths (the float
kernels, `fast=True`, and the numpy engine, `fast=False`) giving the same answer — on divergence and on
which bodies each effect acts on."""
import warnings

import numpy as np
import pytest

import rbcourse as rb
from rbcourse.trajectory import OVERFLOW, blow_up, first_blow_up

BOX = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))
KERNEL_METHODS = ["euler", "rk4", "adaptive", "exact_splitting"]


def finite_and_bounded(traj):
    return all(np.all(np.isfinite(a)) and np.abs(a).max() < OVERFLOW for a in (traj.x, traj.R, traj.P, traj.L))


def outcome(scene, X0, t_end, dt, method, **kw):
    """(diverged step or None, trajectory) of a run, with on_divergence='stop'."""
    traj = rb.simulate(scene, X0, t_end, dt, method, on_divergence="stop", **kw)
    return (traj.divergence.step if traj.diverged else None), traj


# --- the check itself ------------------------------------------------------------------------------

def test_the_check_tests_every_component_on_its_own():
    assert blow_up([("x", np.array([1e200, -1e200]))]) == "x grew beyond 1e+100 (overflow)"   # a sum would be 0
    assert blow_up([("x", np.zeros(3)), ("R", np.array([np.nan]))]) == "R became NaN"
    assert blow_up([("P", np.array([np.inf, -np.inf]))]) == "P overflowed to inf"
    assert blow_up([("L", np.array([1e99]))]) == ""
    k, why = first_blow_up([("x", np.array([[0.0], [1.0], [1e101], [np.nan]]))])
    assert (k, why) == (2, "x grew beyond 1e+100 (overflow)")


def test_an_overflowed_quaternion_normalises_to_nan_not_zero():
    from rbcourse.rotation import matrix_from_quat, quat_normalize

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        q = quat_normalize(np.array([[1e200, 1e200, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]]))
    assert np.isnan(q[0]).all() and np.isnan(q[1]).all() and np.allclose(q[2], [1, 0, 0, 0])
    assert np.isnan(matrix_from_quat(np.array([1e300, 0, 0, 0]))).all()


# --- mirrored bodies: a blow-up that a sum of the state would not see --------------------------------

def mirrored(k=1e4):
    ball = rb.RigidBody.sphere(mass=1.0, radius=0.1)
    scene = rb.Scene([ball, ball], effects=[
        rb.Spring(body_point=(0, 0, 0), world_point=(1, 0, 0), stiffness=k, body=0),
        rb.Spring(body_point=(0, 0, 0), world_point=(-1, 0, 0), stiffness=k, body=1)])
    X0 = rb.State.stack([rb.State.at_rest(x=(0.5, 0, 0)), rb.State.at_rest(x=(-0.5, 0, 0))])
    single = rb.Scene(ball, effects=[rb.Spring(body_point=(0, 0, 0), world_point=(1, 0, 0), stiffness=k)])
    return scene, X0, single, rb.State.at_rest(x=(0.5, 0, 0))


@pytest.mark.parametrize("method", sorted(rb.METHODS))
def test_two_mirrored_bodies_blow_up_when_one_does(method):
    scene, X0, single, X1 = mirrored()
    both, traj = outcome(scene, X0, 20.0, 0.05, method)
    one, _ = outcome(single, X1, 20.0, 0.05, method)
    assert both == one, f"{method}: the pair diverged at step {both}, the single body at step {one}"
    assert finite_and_bounded(traj)
    if both is None:                       # a method that survives keeps the motion bounded
        assert np.abs(traj.x).max() < 10


# --- kept trajectories are finite, whatever record_every ---------------------------------------------

@pytest.mark.parametrize("fast", [True, False])
@pytest.mark.parametrize("method", ["euler", "rk4", "quaternion_euler_body"])   # all three blow up here
@pytest.mark.parametrize("every", [1, 7])
def test_a_diverged_run_keeps_only_finite_states(method, fast, every):
    X0 = rb.State.from_velocities(BOX, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), omega=(3.0, 40.0, 300.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")            # no RuntimeWarning from a documented divergence
        with pytest.raises(rb.SimulationDiverged) as err:
            rb.simulate(BOX, X0, 50.0, 0.05, method, record_every=every, fast=fast)
        traj = err.value.trajectory
        assert err.value.t > traj.t[-1] and traj.diverged and traj.divergence.t == err.value.t
        assert finite_and_bounded(traj)
        assert "diverged at t = " in traj.outcome
        traj.kinetic_energy(), traj.det_R(), traj.orthogonality_error()     # diagnostics do not warn


def test_on_divergence_stop_returns_what_raise_keeps():
    X0 = rb.State.from_velocities(BOX, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), omega=(0.1, 0.1, 50.0))
    with pytest.raises(rb.SimulationDiverged) as err:
        rb.simulate(BOX, X0, 10.0, 1e-2, "euler")
    kept = rb.simulate(BOX, X0, 10.0, 1e-2, "euler", on_divergence="stop")
    assert kept.diverged and kept.divergence == err.value.trajectory.divergence
    np.testing.assert_array_equal(kept.R, err.value.trajectory.R)
    ok = rb.simulate(BOX, X0, 1.0, 1e-3, "rk4", on_divergence="stop")
    assert not ok.diverged and ok.divergence is None and ok.outcome.startswith("ran to t = 1 s")
    with pytest.raises(ValueError, match="on_divergence"):
        rb.simulate(BOX, X0, 1.0, 1e-3, "rk4", on_divergence="ignore")


# --- the two paths agree -------------------------------------------------------------------------------

BLOW_UPS = {   # scene, X0, t_end, dt: runs where some method blows up
    "fast spin, large step": (BOX, rb.State.from_velocities(BOX, x=np.zeros(3), R=np.eye(3), v=np.zeros(3),
                                                           omega=(0.1, 0.1, 50.0)), 10.0, 2e-2),
    "heavy top, Euler": "heavy_top",
    "huge momentum": (BOX, rb.State(x=np.zeros(3), R=np.eye(3), P=[1e98, 0, 0], L=[0, 0, 0.1]), 200.0, 1.0),
}


def blow_up_case(name):
    case = BLOW_UPS[name]
    if case == "heavy_top":
        from rbcourse.examples import heavy_top
        ex = heavy_top()
        return ex.scene, ex.X0, 2.0, 1e-3
    return case


@pytest.mark.parametrize("case", sorted(BLOW_UPS))
@pytest.mark.parametrize("method", KERNEL_METHODS)
def test_the_kernel_and_numpy_paths_diverge_alike(case, method):
    scene, X0, t_end, dt = blow_up_case(case)
    kernel, a = outcome(scene, X0, t_end, dt, method, fast=True)
    numpy, b = outcome(scene, X0, t_end, dt, method, fast=False)
    assert (kernel is None) == (numpy is None), f"{method} on {case}: kernel step {kernel}, numpy step {numpy}"
    if kernel is not None:
        assert abs(kernel - numpy) <= 1, f"{method} on {case}: kernel step {kernel}, numpy step {numpy}"
    assert finite_and_bounded(a) and finite_and_bounded(b)


def test_x0_beyond_the_limit_is_refused_on_both_paths():
    X = rb.State(x=np.zeros(3), R=np.eye(3), P=[1e200, 0, 0], L=[0, 0, 0.1])
    for fast in (True, False):
        with pytest.raises(ValueError, match="X0"):
            rb.simulate(BOX, X, 1.0, 0.01, "rk4", fast=fast)


SELECTIONS = [None, 0, [0]]


@pytest.mark.parametrize("body", SELECTIONS, ids=repr)
@pytest.mark.parametrize("method", KERNEL_METHODS)
def test_every_effects_body_selection_reads_alike_on_both_paths(method, body):
    from rbcourse.examples import pushed_box

    X0 = rb.State.from_velocities(BOX, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), omega=(0.3, 2.0, 0.5))
    scenes = [rb.Scene(BOX, [rb.Gravity(body=body)]),
              rb.Scene(BOX, [rb.Gravity(body=body), rb.Pivot(body_point=(0, 0, -0.05), body=body)])]
    if method == "euler":      # the Euler kernel also takes forces at points
        scenes.append(rb.Scene(BOX, [rb.PointForce(body_point=(0.15, 0.1, 0.025), force=(0, 0, 10.0), body=body),
                                     rb.Gravity(body=body)]))
        scenes.append(pushed_box().scene)
    for scene in scenes:
        if scene.has_pivots:
            X0 = rb.Pivot(body_point=(0, 0, -0.05)).state(BOX, np.eye(3), (0.3, 2.0, 0.5))
        a = rb.simulate(scene, X0, 0.5, 1e-3, method, fast=True)
        b = rb.simulate(scene, X0, 0.5, 1e-3, method, fast=False)
        for k in ("x", "R", "P", "L"):
            np.testing.assert_allclose(getattr(a, k), getattr(b, k), rtol=1e-9, atol=1e-11,
                                       err_msg=f"{method}, {scene.describe()}: {k} differs between the paths")


@pytest.mark.parametrize("method", KERNEL_METHODS + ["splitting"])
def test_an_effect_on_one_body_of_two_acts_on_that_body_only(method):
    """Body by body, a two-body scene (numpy path) is the two single-body scenes (kernel path)."""
    X = rb.State.from_velocities(BOX, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), omega=(0.3, 2.0, 0.5))
    pair = rb.Scene([BOX, BOX], [rb.Gravity(body=1), rb.Pivot(body_point=(0, 0, -0.05), body=1)])
    Xp = rb.Pivot(body_point=(0, 0, -0.05)).state(BOX, np.eye(3), (0.3, 2.0, 0.5))
    both = rb.simulate(pair, rb.State.stack([X, Xp]), 0.5, 1e-3, method)
    free = rb.simulate(BOX, X, 0.5, 1e-3, method)
    top = rb.simulate(rb.Scene(BOX, [rb.Gravity(), rb.Pivot(body_point=(0, 0, -0.05))]), Xp, 0.5, 1e-3, method)
    for k in ("x", "R", "P", "L"):
        np.testing.assert_allclose(getattr(both, k)[:, 0], getattr(free, k), rtol=1e-9, atol=1e-11)
        np.testing.assert_allclose(getattr(both, k)[:, 1], getattr(top, k), rtol=1e-9, atol=1e-11)


# --- other faults on the user path ---------------------------------------------------------------------

def test_the_slides_euler_on_the_ground_diverges_cleanly():
    """Box at ω = 100 rad/s, dt = 0.05: the contact solver never sees a blown-up state (no LinAlgError)."""
    scene = rb.Scene(BOX, effects=[rb.Gravity(), rb.Ground()])
    X0 = rb.State.from_velocities(BOX, x=(0, 0, 0.5), R=np.eye(3), v=np.zeros(3), omega=(100.0, 30.0, 10.0))
    with pytest.raises(rb.SimulationDiverged) as err:
        rb.simulate(scene, X0, 5.0, 0.05, "euler")
    assert finite_and_bounded(err.value.trajectory)


def test_the_walkthrough_stops_at_a_blow_up():
    X0 = rb.State.from_velocities(BOX, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), omega=(1e30, 1e30, 0.0))
    with pytest.raises(rb.SimulationDiverged, match="Itération 2") as err:
        rb.walkthrough(BOX, X0, forces=[], dt=1.0, iterations=50)
    assert len(err.value.trajectory.t) == 2 and finite_and_bounded(err.value.trajectory)


def test_a_run_too_large_to_record_is_refused_with_its_memory():
    with pytest.raises(ValueError, match=r"record_every.*GB"):
        rb.simulate(BOX, rb.State.at_rest(), t_end=1e6, dt=1e-3)
    rb.simulate(BOX, rb.State.at_rest(), t_end=1.0, dt=1e-3, record_every=1000)     # a small one runs


@pytest.mark.parametrize("name,value", [("fast", "no"), ("fast", 1), ("progress", "yes"), ("progress", None)])
def test_switches_are_booleans(name, value):
    with pytest.raises(ValueError, match=name):
        rb.simulate(BOX, rb.State.at_rest(), 1.0, 0.1, **{name: value})


@pytest.mark.parametrize("fast", [True, False])
@pytest.mark.parametrize("dt", [0.06, 0.0002])
def test_a_pivoted_run_whose_l_about_the_centre_of_mass_overflows_diverges(fast, dt):
    """A heavy top's Euler blows up in the pivot's coordinates: L about the pivot stays within 1e100 one row longer
    than L about the centre of mass, L_p − (x − p) × P, which overflows first — that row is the divergence, and the
    run keeps only the finite rows before it (a Trajectory holding inf was built, and refused)."""
    from rbcourse.bench.problems import PROBLEMS
    C = PROBLEMS["C"]()
    with pytest.raises(rb.SimulationDiverged) as err:
        rb.simulate(C.scene, C.X0, C.T, dt, "euler", fast=fast, record_every=1 if dt > 0.01 else 10**9)
    kept = err.value.trajectory
    assert finite_and_bounded(kept) and kept.t[-1] < err.value.t and kept.divergence.t == err.value.t
    assert err.value.reason.startswith("L" if dt < 0.01 else ("L", "P", "x", "R"))
