"""Every public call checks what it is given (issue 46, in part): a Trajectory's methods, its arrays read-only, a
trajectory of no state drawn or plotted, the time profiles at the ends of the float range, Scene.describe's
method.  A bad argument gives a ValueError whose message names the parameter and what is allowed — never numpy's
IndexError, an einsum broadcast error, "slice step cannot be zero", or a silently wrong answer — and what is
accepted gives finite results.

The rules (Trajectory's docstring): a state is taken by an index as Python indexes a list (-m <= k < m), head(k)
by a count (0 <= k <= m), every(k) by a step (1 <= k <= max(1, m − 1)), a body by its index in the scene
(0 <= body < N), a point (body_point's b, angular_momentum's about) within ±1e100, the blow-up limit of a state."""
import copy
import math
import pickle
import re
import sys
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rbcourse as rb
from rbcourse.viz import plots, viewer

BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
F = np.array([1.0, -2.0, 3.0])
SPIN = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), [1.0, 0.0, 0.5], [0.3, 5.0, 0.2])
TRAJ = rb.simulate(BOX, SPIN, 0.1, 0.01, "rk4", fast=False)                         # 11 states, one body
TWO = rb.simulate(rb.Scene([BOX, BOX]), rb.State.stack([SPIN, SPIN.replace(x=[1.0, 0, 0])]), 0.1, 0.01, "rk4",
                  fast=False)                                                        # 11 states, two bodies
M = len(TRAJ)


def refused(call, name: str, *words: str) -> str:
    """call() raises a ValueError naming `name` (and saying each of `words`); its message."""
    with pytest.raises(ValueError) as err:
        call()
    message = str(err.value)
    assert name in message, message
    for word in words:
        assert word in message, message
    return message


# --- Trajectory: state, head, every ---------------------------------------------------------------------------

@pytest.mark.parametrize("k", [0, -1, M, 10**6, -M - 1])
def test_every_takes_a_step_from_1_to_the_recorded_steps(k):
    refused(lambda: TRAJ.every(k), "k", f"[1, {M - 1}]", f"got {k}")


@pytest.mark.parametrize("k", [1.0, True, "2", None])
def test_every_takes_an_integer_step(k):
    refused(lambda: TRAJ.every(k), "k", "integer")


def test_every_keeps_every_kth_state():
    assert TRAJ.every(M - 1).t.tolist() == [TRAJ.t[0], TRAJ.t[-1]]
    np.testing.assert_array_equal(TRAJ.every(3).x, TRAJ.x[::3])


@pytest.mark.parametrize("k", [M, 10**6, -M - 1, 2**70])
def test_state_takes_an_index_as_python_and_refuses_any_other(k):
    refused(lambda: TRAJ.state(k), "k", f"[{-M}, {M - 1}]", str(k))


def test_a_negative_index_counts_from_the_end_as_in_python():
    assert TRAJ.state(-1) == TRAJ.final == TRAJ.state(M - 1)
    assert TRAJ.state(-M) == TRAJ.state(0)
    for k in (1.0, True, np.float64(2), "1"):
        refused(lambda: TRAJ.state(k), "k", "integer")
    assert TRAJ.state(np.int64(3)) == TRAJ.state(3)


@pytest.mark.parametrize("k", [-1, M + 1, 10**30, 1.0, True, False, None])
def test_head_takes_a_count_from_0_to_the_recorded_states(k):
    words = ("integer",) if isinstance(k, (bool, float)) or k is None else (f"[0, {M}]",)
    refused(lambda: TRAJ.head(k), "k", *words)


def test_an_empty_head_says_it_holds_no_state_wherever_it_is_used():
    empty = TRAJ.head(0)
    assert len(empty) == 0 and len(TRAJ.head(M)) == M
    assert "no state" in repr(empty) and "no state" in empty.outcome and "no state" in empty.describe()
    refused(lambda: empty.final, "final", "no state")
    refused(lambda: empty.state(0), "k", "none")
    assert empty.kinetic_energy().shape == (0,) and empty.body_point([0.1, 0, 0]).shape == (0, 3)
    message = refused(lambda: viewer.draw_trajectory(empty), "traj", "no state")
    assert "got x of shape" not in message
    for plot in (plots.drift, plots.plot_drift, plots.plot_energy_momentum):
        refused(lambda: plot(empty), "traj", "no state")
    refused(lambda: plots.drift(TRAJ, t_from=True), "t_from")


# --- Trajectory: body_point, angular_momentum, body ----------------------------------------------------------

@pytest.mark.parametrize("b, words", [
    ([0.1, 0], ("shape (3,)",)), ([[0.1, 0, 0]], ("shape (3,)",)), ([np.nan, 0, 0], ("finite",)),
    ([np.inf, 0, 0], ("finite",)), ([1e300, 0, 0], ("±1e+100",)), ([True, 0, 0], ("booleans",)), ("0.1", ()),
    (None, ()),
])
def test_body_point_takes_a_finite_3_vector(b, words):
    refused(lambda: TRAJ.body_point(b), "b", *words)


@pytest.mark.parametrize("traj, body", [(TWO, 5), (TWO, -1), (TWO, 2), (TRAJ, 1), (TRAJ, 5), (TWO, True),
                                        (TWO, 1.0)])
def test_body_point_takes_a_body_of_the_scene(traj, body):
    """A 1-body run asked for body 5 used to answer with body 0's path; a 2-body run raised numpy's IndexError."""
    refused(lambda: traj.body_point([0.1, 0, 0], body=body), "body")


def test_body_point_is_x_plus_R_b_of_the_body_asked_for():
    b = np.array([0.1, 0.0, 0.02])
    np.testing.assert_allclose(TWO.body_point(b, body=1), TWO.x[:, 1] + TWO.R[:, 1] @ b, rtol=1e-15, atol=1e-15)
    np.testing.assert_allclose(TRAJ.body_point(b), TRAJ.x + TRAJ.R @ b, rtol=1e-15, atol=1e-15)


@pytest.mark.parametrize("about", ["centre", "", True, 1.0, None, [1, 2], [np.nan, 0, 0], [True, 0, 0],
                                   [1e300, 0, 0], np.zeros((3, 3))])
def test_angular_momentum_takes_origin_com_or_a_point(about):
    refused(lambda: TRAJ.angular_momentum(about=about), "about")


def test_angular_momentum_about_a_point():
    np.testing.assert_array_equal(TRAJ.angular_momentum(about="com"), TRAJ.L)
    np.testing.assert_array_equal(TRAJ.angular_momentum(), TRAJ.angular_momentum(about=(0, 0, 0)))


def test_the_body_of_a_run_of_several_bodies_is_refused_not_body_0():
    assert TRAJ.body is BOX
    refused(lambda: TWO.body, "body", "2 bodies")


# --- Trajectory: its construction, its arrays read-only -------------------------------------------------------

@pytest.mark.parametrize("change, name", [
    (dict(t=np.zeros((M, 1))), "t"), (dict(t=["a"] * M), "t"), (dict(x=np.zeros((M, 4))), "x"),
    (dict(x=np.zeros((M + 1, 3))), "x"), (dict(R=np.zeros((M, 3))), "R"), (dict(P=np.ones((M, 3), dtype=bool)), "P"),
    (dict(L=np.zeros((M, 2, 3))), "L"), (dict(scene="box"), "scene"), (dict(dt=0.0), "dt"), (dict(dt=True), "dt"),
    (dict(method=3), "method"), (dict(divergence="x"), "divergence"), (dict(implementation=None), "implementation"),
])
def test_a_trajectory_built_by_hand_is_checked(change, name):
    args = dict(t=TRAJ.t, x=TRAJ.x, R=TRAJ.R, P=TRAJ.P, L=TRAJ.L, scene=TRAJ.scene)
    args.update(change)
    refused(lambda: rb.Trajectory(**args), name)


@pytest.mark.parametrize("traj", [TRAJ, TWO, TRAJ.head(3), TRAJ.every(2),
                                  rb.Trajectory(np.arange(2.0), np.zeros((2, 3)), np.stack([np.eye(3)] * 2),
                                                np.zeros((2, 3)), np.zeros((2, 3)), BOX)],
                         ids=["run", "two bodies", "head", "every", "by hand"])
def test_a_trajectorys_arrays_are_read_only(traj):
    for name in ("t", "x", "R", "P", "L"):
        a = getattr(traj, name)
        before = a.copy()
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 0
        with pytest.raises(ValueError, match="read-only"):
            a[...] += 1.0
        np.testing.assert_array_equal(a, before)
    with pytest.raises(ValueError, match="read-only"):
        traj.linear_momentum()[0] = 0


class Marked(rb.Trajectory):
    """A subclass with an attribute of its own (as the demo's Computed): kept by pickling and copies."""

    def __init__(self, traj):
        super().__init__(traj.t, traj.x, traj.R, traj.P, traj.L, traj.scene, traj.method, traj.dt)
        self.mark = np.arange(3.0)


def test_a_pickled_or_copied_trajectory_is_as_read_only():
    for other in (pickle.loads(pickle.dumps(TWO)), copy.copy(TWO), copy.deepcopy(TWO)):
        assert type(other) is rb.Trajectory and repr(other) == repr(TWO) and other.describe() == TWO.describe()
        for name in ("t", "x", "R", "P", "L"):
            np.testing.assert_array_equal(getattr(other, name), getattr(TWO, name))
            with pytest.raises(ValueError, match="read-only"):
                getattr(other, name)[0] = 0
    marked = Marked(TRAJ)
    for other in (pickle.loads(pickle.dumps(marked)), copy.deepcopy(marked)):
        assert type(other) is Marked and other.mark.tolist() == [0.0, 1.0, 2.0] and not other.R.flags.writeable


def test_a_run_is_read_only_without_a_copy_and_the_arrays_given_stay_the_callers():
    x = np.zeros((2, 3))
    traj = rb.Trajectory(np.arange(2.0), x, np.stack([np.eye(3)] * 2), np.zeros((2, 3)), np.zeros((2, 3)), BOX)
    assert np.shares_memory(traj.x, x) and x.flags.writeable
    head = TRAJ.head(4)
    assert np.shares_memory(head.R, TRAJ.R) and not head.R.flags.writeable


# --- the time profiles at the ends of the float range --------------------------------------------------------

BIGGEST = sys.float_info.max


def test_a_ramp_is_exact_over_any_span_even_one_whose_duration_overflows():
    """Over (−1e308, 1e308) t_stop − t_start overflows: F(0) was 0 (t − t_start)/inf; it is half the force, as the
    formula says, compiled (fill_profiles) and run as Python alike, bit for bit."""
    from rbcourse.engine import profiles as kernel
    cases = [(-1e308, 1e308, [(0.0, 0.5), (-1e308, 0.0), (1e308, 1.0), (-5e307, 0.25), (5e307, 0.75)]),
             (-BIGGEST, BIGGEST, [(0.0, 0.5), (BIGGEST / 2, 0.75), (-BIGGEST, 0.0), (BIGGEST, 1.0)]),
             (-8e307, 8e307, [(0.0, 0.5), (-8e307, 0.0), (8e307, 1.0)]),
             (0.0, 1.5e-323, [(5e-324, 1 / 3), (1e-323, 2 / 3)]),                   # subnormal times: exact too
             (2.0 ** 1022, 1.5 * 2.0 ** 1023, [(2.0 ** 1023, 0.5), (1.5 * 2.0 ** 1022, 0.25)])]
    for t0, t1, at in cases:
        ramp = rb.Ramp(F, t0, t1)
        sys_ = rb.Scene(BOX, [rb.PointForce((0, 0, 0), ramp)]).compile().system
        times = np.array([[t] for t, _ in at])
        values = np.zeros((len(at), 1, 1, 3))
        kernel.fill_profiles(sys_, times, values)
        for k, (t, s) in enumerate(at):
            np.testing.assert_array_equal(ramp(t), s * F, err_msg=f"Ramp over ({t0}, {t1}) at t = {t}")
            np.testing.assert_array_equal(values[k, 0, 0], ramp(t))


def exact_fraction(t: float, t0: float, t1: float) -> Fraction:
    """(t − t0)/(t1 − t0) clipped to [0, 1], in exact rational arithmetic."""
    if t < t0:
        return Fraction(0)
    if t >= t1:
        return Fraction(1)
    return (Fraction(t) - Fraction(t0)) / (Fraction(t1) - Fraction(t0))


extreme = st.one_of(st.floats(allow_nan=False, allow_infinity=False),
                    st.sampled_from([BIGGEST, -BIGGEST, 1e308, -1e308, 8.98846567431158e307, 5e-324, -5e-324, 0.0]))


@settings(max_examples=300, deadline=None)
@given(t0=extreme, t1=extreme, t=extreme)
def test_a_ramp_is_its_formula_to_rounding_at_any_finite_times(t0, t1, t):
    """F(t) = force s, s = (t − t0)/(t1 − t0) on [t0, t1): within 2 roundings of the exact quotient (a subtraction and
    a division), never inf or NaN, over the whole float range."""
    t0, t1 = min(t0, t1), max(t0, t1)
    force = np.array([1.0, -BIGGEST, 3.0])
    s = rb.Ramp(force, t0, t1)(t)[0]
    want = exact_fraction(t, t0, t1)
    assert 0.0 <= s <= 1.0 and np.all(np.isfinite(rb.Ramp(force, t0, t1)(t)))
    assert abs(Fraction(s) - want) <= want * Fraction(3 * sys.float_info.epsilon / 2) + Fraction(5e-324), (s, want)


def test_a_sine_whose_value_or_phase_would_overflow_is_refused():
    refused(lambda: rb.Sine([1e308] * 3, 1.0, offset=[1e308] * 3), "offset", "amplitude", "1.798e+308")
    refused(lambda: rb.Sine([1e308] * 3, 1.0, offset=[-1e308] * 3), "offset")     # offset − amplitude: −2e308
    refused(lambda: rb.Sine(F, 1e308), "frequency", "<= 1e+307")
    refused(lambda: rb.Sine(F, 1.0, phase=True), "phase")
    fast = rb.Sine(F, 1e307)
    refused(lambda: fast(1e10), "t", "|t| <= 2.86 s")
    assert np.all(np.isfinite(fast(2.0)))
    scene = rb.Scene(BOX, [rb.PointForce((0, 0, 0), rb.Sine(F, 1e300))])
    refused(lambda: rb.simulate(scene, rb.State.at_rest(), 1e10, 1e9, "euler"), "t_end", "phase")


@pytest.mark.parametrize("build, name", [
    (lambda: rb.Steps([0.0, True], [F, F]), "times"), (lambda: rb.Steps(True, [F]), "times"),
    (lambda: rb.Steps([[True]], [F]), "times"), (lambda: rb.Steps([0.0, 1.0], [F, [True, 0, 0]]), "forces"),
    (lambda: rb.Pulse(F, True, 2.0), "t_start"), (lambda: rb.Ramp(F, 0.0, False), "t_stop"),
    (lambda: rb.Constant([True, 0, 0]), "force"),
])
def test_a_profile_refuses_booleans_as_numbers(build, name):
    refused(build, name)


@pytest.mark.parametrize("t0", ["1", True, None, math.nan, math.inf])
def test_acts_after_takes_a_finite_time(t0):
    refused(lambda: rb.Pulse(F, 0.0, 1.0).acts_after(t0), "t0")


@pytest.mark.parametrize("t", ["0.5", True, np.bool_(False), None, math.nan, -math.inf, [0.5], 10**400])
def test_pulse_on_takes_a_finite_time(t):
    """Pulse.on(t) compared whatever it was given: "0.5" raised Python's TypeError, True and NaN answered."""
    refused(lambda: rb.Pulse(F, 0.0, 1.0).on(t), "t")


def test_pulse_on_says_where_the_force_acts_at_the_ends_of_the_float_range():
    pulse = rb.Pulse(F, -BIGGEST, BIGGEST)
    assert pulse.on(0.0) and pulse.on(-BIGGEST) and not pulse.on(BIGGEST) and pulse.on(np.float32(1.0))
    assert all(pulse.on(t) == bool(np.any(pulse(t))) for t in (-BIGGEST, -1e308, 0.0, 5e-324, 1e308, BIGGEST))


@pytest.mark.parametrize("slot", [True, -1, 1.0, "0", None])
def test_a_profiles_time_row_takes_a_slot_index(slot):
    refused(lambda: rb.Pulse(F, 0.0, 1.0).time_row(slot), "slot")


GROUND = rb.Ground()


@pytest.mark.parametrize("call, name", [
    (lambda T: rb.PointForce((0, 0, 0), lambda t: (0.0, 0.0, t)).force_at(T), "t"),
    (lambda T: rb.Sine(F, 1.0).check_time("t_end", T), "t_end"),
    (lambda T: rb.velocity([T, 0, 0], 1.0), "P"), (lambda T: rb.velocity([1.0, 0, 0], T), "M"),
    (lambda T: rb.inverse_inertia(np.eye(3), np.full((3, 3), T)), "I_body_inv"),
    (lambda T: rb.inverse_inertia([[T, 0, 0], [0, 1, 0], [0, 0, 1]], np.eye(3)), "R"),
    (lambda T: rb.angular_velocity(np.eye(3), [T, 0, 0]), "L"),
    (lambda T: rb.angular_velocity(np.eye(3, dtype=bool) if T else np.eye(3), [1.0, 0, 0]), "I_inv"),
    (lambda T: GROUND.resolve(rb.Scene(BOX, [GROUND]), SPIN.replace(x=[0, 0, 1.0]), dt=T), "dt"),
])
@pytest.mark.parametrize("T", [True, np.bool_(True)])
def test_a_boolean_is_never_a_number(call, name, T):
    """One rule for booleans, as for every number of the package (support/checks.py): refused, the parameter
    named (rb.velocity([True, 0, 0], 1.0) answered [1, 0, 0]; force_at(True) called f(True))."""
    refused(lambda: call(T), name)


@pytest.mark.parametrize("call, name, said", [
    (lambda: rb.velocity([1.0, 0, 0], 0.0), "M", "> 0"), (lambda: rb.velocity([1.0, 0, 0], -2.0), "M", "> 0"),
    (lambda: rb.velocity(None, 1.0), "P", "array of numbers"), (lambda: rb.velocity(["a", 0, 0], 1.0), "P", ""),
    (lambda: rb.velocity([np.nan, 0, 0], 1.0), "P", "finite"), (lambda: rb.velocity([1.0, 0], 1.0), "P", "(..., 3)"),
    (lambda: rb.velocity(np.ones((2, 3)), [1.0, 2.0, 3.0]), "P and M", "broadcast"),
    (lambda: rb.velocity([1e308, 0, 0], 1e-10), "P and M", "overflows"),
    (lambda: rb.inverse_inertia(np.eye(3) * 1e200, np.eye(3)), "R and I_body_inv", "overflows"),
    (lambda: rb.angular_velocity(np.eye(2), [1.0, 0, 0]), "I_inv", "(..., 3, 3)"),
    (lambda: rb.angular_velocity(np.eye(3), [np.inf, 0, 0]), "L", "finite"),
])
def test_the_formula_functions_check_what_they_are_given(call, name, said):
    refused(call, name, said)


def test_the_formula_functions_answer_as_before_on_numbers():
    I_inv = rb.inverse_inertia(SPIN.R, BOX.I_body_inv)
    np.testing.assert_allclose(I_inv, SPIN.R @ BOX.I_body_inv @ SPIN.R.T, rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(rb.angular_velocity(I_inv, SPIN.L), I_inv @ SPIN.L, rtol=1e-14)
    np.testing.assert_array_equal(rb.velocity(np.ones((2, 3)), [1.0, 2.0])[1], [0.5] * 3)
    np.testing.assert_array_equal(rb.velocity([2, 4, 6], 2), [1.0, 2.0, 3.0])          # ints are numbers
    np.testing.assert_array_equal(TRAJ.velocity(), TRAJ.P / BOX.mass)


# --- the linked view: a list of runs is runs of one scene -------------------------------------------------------

def pushed(k: float = 1.0, kick: float = 0.5) -> rb.Scene:
    """BOX pushed by a force f(t) built here (a new function each call, of one code) and kicked at 0.05 s."""
    return rb.Scene(BOX, [rb.PointForce((0.1, 0, 0), lambda t: (0.0, k * t, 0.0)),
                          rb.Impulse((0, 0, 0.02), (kick, 0, 0), 0.05)])


@pytest.mark.parametrize("runs, said", [
    ([TRAJ, TWO], "traj[1] is a run of a scene of 2 bodies, traj[0] of 1"),
    ([TWO, TRAJ], "traj[1] is a run of a scene of 1 body, traj[0] of 2"),
    ([TRAJ, TRAJ, TWO], "traj[2] is a run of a scene of 2 bodies"),
    ([TRAJ, rb.simulate(rb.Scene(BOX, [rb.Gravity()]), SPIN, 0.1, 0.01, "rk4", fast=False)], "other bodies or effects"),
    ([TRAJ, rb.simulate(rb.RigidBody.box(2.0, (0.3, 0.2, 0.05)), SPIN, 0.1, 0.01, "rk4", fast=False)],
     "other bodies or effects"),
])
def test_draw_trajectory_refuses_runs_of_several_scenes(runs, said):
    """The page draws the first run and plots every one by what the first one's scene conserves: runs of a 1-body
    and a 2-body scene were plotted as one scene."""
    refused(lambda: viewer.draw_trajectory(runs, plots=True), "traj", "runs of one scene", said)


def test_draw_trajectory_plots_runs_of_one_scene_built_again_or_copied():
    euler = rb.simulate(BOX, SPIN, 0.1, 0.02, "euler", fast=False)       # a bare body: a scene built again
    d = viewer.draw_trajectory([TRAJ, euler, pickle.loads(pickle.dumps(TRAJ))], plots=True)
    assert [s["label"] for s in d.plots["series"]] == ["rk4", "euler", "rk4"]
    assert all(len(p["curves"]) == 3 for p in d.plots["panels"])
    a, b = (rb.simulate(pushed(), SPIN, 0.1, 0.01, m, fast=False) for m in ("rk4", "euler"))
    assert len(viewer.draw_trajectory([a, b], plots=True).plots["series"]) == 2
    refused(lambda: viewer.draw_trajectory([a, rb.simulate(pushed(k=2.0), SPIN, 0.1, 0.01, "rk4", fast=False)],
                                           plots=True), "traj[1]", "other bodies or effects")


def test_same_physics_compares_what_the_engine_runs():
    scene = pushed()
    assert scene.same_physics(scene) and scene.same_physics(pushed()) and pushed().same_physics(scene)
    assert not scene.same_physics(pushed(k=2.0))                        # the function's closure differs
    assert not scene.same_physics(pushed(kick=0.6))                     # the impulse differs
    assert not scene.same_physics(rb.Scene(BOX, [rb.PointForce((0.1, 0, 0), lambda t: (0.0, t, 0.0)),
                                                 rb.Impulse((0, 0, 0.02), (0.5, 0, 0), 0.05)]))   # another code
    assert not scene.same_physics(rb.Scene([BOX, BOX])) and not scene.same_physics("scene")
    assert rb.Scene(BOX, [rb.PointForce((0.1, 0, 0), rb.Ramp(F, 0, 1))]).same_physics(
        rb.Scene(BOX, [rb.PointForce((0.1, 0, 0), rb.Ramp(F, 0, 1))]))
    assert not rb.Scene(BOX, [rb.PointForce((0.1, 0, 0), rb.Ramp(F, 0, 1))]).same_physics(
        rb.Scene(BOX, [rb.PointForce((0.1, 0, 0), rb.Ramp(F, 0, 2))]))


# --- Scene.describe ----------------------------------------------------------------------------------------------

@pytest.mark.parametrize("method", [42, "rk5", True, ["rk4"]])
def test_describe_takes_a_method_of_the_list(method):
    refused(lambda: TRAJ.scene.describe(method), "method", "'rk4'")


def test_describe_names_the_method_given_by_name_or_as_a_method():
    assert TRAJ.scene.describe("rk4").endswith("Integrator: rk4.")
    assert TRAJ.scene.describe(rb.METHODS["euler"]).endswith("Integrator: euler.")


# --- properties: whatever is given, finite checked results or the parameter named ---------------------------

anything = st.one_of(
    st.none(), st.booleans(), st.text(max_size=3), st.integers(-2**70, 2**70),
    st.floats(allow_nan=True, allow_infinity=True), st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4),
    st.lists(st.one_of(st.floats(-1e101, 1e101), st.booleans(), st.integers(-3, 3)), min_size=3, max_size=3),
    st.sampled_from(["origin", "com", "centre", np.zeros((3, 3)), np.float32(2.0), np.int64(-2), 1e300]))
small = st.floats(-10.0, 10.0)


def mostly(usual, other):
    """usual 4 times in 5, else other: most calls are accepted, and their results checked."""
    return st.integers(0, 4).flatmap(lambda i: usual if i else other)     # (one_of would weigh each branch of other)


indices = mostly(st.integers(-15, 15), anything)
points = mostly(st.lists(small, min_size=3, max_size=3),
                st.one_of(st.lists(st.floats(-1e101, 1e101), min_size=3, max_size=3), anything))


def finite(result) -> bool:
    """Every number in the result (an array, a State, a Trajectory) is finite."""
    if isinstance(result, (rb.State, rb.Trajectory)):
        return all(np.all(np.isfinite(getattr(result, k))) for k in ("x", "R", "P", "L"))
    return bool(np.all(np.isfinite(result)))


def names_one(err: Exception, names) -> bool:
    """The message names one of `names`, as a word ("t" in "t must be finite", not in "t_stop" or "must")."""
    return any(re.search(rf"(?<![\w.]){re.escape(n)}(?!\w)", str(err)) for n in names)


def answers_or_names(call, *names):
    """call() returns finite results, or raises a ValueError/TypeError naming one of `names`."""
    try:
        result = call()
    except (ValueError, TypeError) as err:
        assert names_one(err, names), (names, str(err))
        return None
    assert finite(result), result
    return result


@settings(max_examples=150, deadline=None)
@given(traj=st.sampled_from([TRAJ, TWO]), k=indices, b=points, body=mostly(st.integers(-2, 3), anything),
       about=points)
def test_trajectory_methods_answer_finite_or_name_the_parameter(traj, k, b, body, about):
    for method in ("state", "head", "every"):
        got = answers_or_names(lambda: getattr(traj, method)(k), "k")
        if got is not None and method != "state":
            assert 0 <= len(got) <= len(traj)
    got = answers_or_names(lambda: traj.body_point(b, body=body), "b", "body")
    if got is not None:
        assert got.shape == (len(traj), 3)
    got = answers_or_names(lambda: traj.angular_momentum(about=about), "about")
    if got is not None:
        assert got.shape == traj.L.shape


numbers = mostly(small, st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.booleans(),
                                  st.integers(-2**1100, 2**1100),
                                  st.sampled_from([1e308, -1e308, 8e307, 1e307, 5e-324, 0.0])))
vectors = mostly(st.lists(small, min_size=3, max_size=3), st.one_of(st.lists(numbers, min_size=3, max_size=3),
                                                                    st.lists(st.floats(), min_size=3, max_size=3),
                                                                    anything))
PROFILE_PARAMETERS = ("force", "t_start", "t_stop", "amplitude", "frequency", "phase", "offset", "times", "forces")


@st.composite
def steps(draw):
    """Steps(times, forces): often a valid table (increasing times, a force each), else anything."""
    if draw(st.booleans()):
        times = sorted(draw(st.lists(numbers, min_size=1, max_size=4, unique=True)))
        forces = [draw(vectors) for _ in times]
        return lambda: rb.Steps(times, forces)
    times = draw(st.one_of(st.lists(numbers, max_size=4), anything))
    forces = draw(st.one_of(st.lists(st.lists(numbers, min_size=3, max_size=3), max_size=4), anything))
    return lambda: rb.Steps(times, forces)


@st.composite
def profiles(draw):
    """A profile of each kind, built from any parameters (many of them refused)."""
    kind = draw(st.sampled_from(["Constant", "Pulse", "Ramp", "Sine", "Steps"]))
    if kind == "Constant":
        force = draw(vectors)
        return lambda: rb.Constant(force)
    if kind in ("Pulse", "Ramp"):
        force, t_start, t_stop = draw(vectors), draw(numbers), draw(numbers)
        if all(isinstance(v, float) for v in (t_start, t_stop)) and t_stop < t_start:
            t_start, t_stop = t_stop, t_start                                # an interval, often
        return lambda: getattr(rb, kind)(force, t_start, t_stop)
    if kind == "Sine":
        args = draw(vectors), draw(numbers), draw(numbers), draw(vectors)
        return lambda: rb.Sine(*args)
    return draw(steps())


@settings(max_examples=200, deadline=None)
@given(build=profiles(), t=numbers, t0=numbers)
def test_profiles_answer_finite_or_name_the_parameter(build, t, t0):
    try:
        profile = build()
    except (ValueError, TypeError) as err:
        assert names_one(err, PROFILE_PARAMETERS), str(err)
        return
    value = answers_or_names(lambda: profile(t), "t")
    if value is not None and isinstance(profile, (rb.Ramp, rb.Pulse, rb.Constant)):
        assert np.all(np.abs(value) <= np.abs(profile.force))
    if value is not None and isinstance(profile, rb.Sine):
        assert np.all(np.abs(value) <= np.abs(profile.offset) + np.abs(profile.amplitude))
    acts = answers_or_names(lambda: profile.acts_after(t0), "t0")
    assert acts in (None, True, False)
    if isinstance(profile, rb.Pulse):
        on = answers_or_names(lambda: profile.on(t), "t")
        assert on in (None, True, False) and (on is None) == (value is None)
        if on is not None:
            assert on == (profile.t_start <= float(t) < profile.t_stop)


@pytest.mark.parametrize("make", [lambda n: rb.Scene(rb.RigidBody.box(1.0, (1.0, 1.0, 1.0)), [], name=n),
                                  lambda n: rb.RigidBody(1.0, np.eye(3), name=n)])
def test_a_name_that_cannot_be_written_is_refused_when_given(make):
    """A lone surrogate cannot be written to a page or a file: refused where the name is given, not at save."""
    with pytest.raises(ValueError, match=r"name must be text that can be written as UTF-8, got .* lone surrogate"):
        make("box\ud800")
    with pytest.raises(ValueError, match="name must be a string or None, got 3"):
        make(3)
    assert make("boîte é").name == "boîte é"


@pytest.mark.parametrize("bad, said", [("page\0.html", "no NUL byte"), ("", "not empty"), (3, "got 3")])
def test_a_page_is_saved_to_a_file_path_or_refused_in_the_api_s_words(tmp_path, bad, said):
    """One check for every page written (viewer pages, their stills, the explorer): a NUL byte gave pathlib's own
    "embedded null byte"."""
    from rbcourse.support import checks
    with pytest.raises(ValueError, match=f"path must be a file path.*{re.escape(said)}"):
        checks.file_path("path", bad)
    with pytest.raises(ValueError, match="is a folder"):
        checks.file_path("path", tmp_path)
    with pytest.raises(ValueError, match="does not exist"):
        checks.file_path("path", tmp_path / "no" / "page.html")


# --- the plots: what they draw, on what, between which bounds ----------------------------------------------------

@pytest.mark.parametrize("call, name, said", [
    (lambda: plots.plot_drift([]), "trajs", "non-empty"),
    (lambda: plots.plot_drift("traj"), "trajs", "Trajectory"),
    (lambda: plots.plot_drift([TRAJ, "traj"]), "trajs[1]", "Trajectory"),
    (lambda: plots.plot_drift(TRAJ, labels=["a", "b"]), "labels", "one string per trajectory (1), got 2"),
    (lambda: plots.plot_drift(TRAJ, labels="a"), "labels", "list of 1 string"),
    (lambda: plots.plot_drift(TRAJ, labels=[3]), "labels[0]", "string"),
    (lambda: plots.plot_drift(TRAJ, floor=0.0), "floor", "[1e-300, 1e+300]"),
    (lambda: plots.plot_drift(TRAJ, floor=-1.0), "floor", "[1e-300, 1e+300]"),
    (lambda: plots.plot_drift(TRAJ, ceiling=math.inf), "ceiling", "finite"),
    (lambda: plots.plot_drift(TRAJ, floor=10.0, ceiling=1.0), "floor", "below ceiling"),
    (lambda: plots.plot_drift(TRAJ, axes="ax"), "axes", "3 matplotlib Axes"),
    (lambda: plots.plot_energy_momentum(TRAJ, axes="ax"), "axes", "2 matplotlib Axes"),
    (lambda: plots.plot_work_precision([], "wp.png"), "runs", "at least one"),
    (lambda: plots.plot_work_precision("x", "a\0b.png"), "runs", "bench.Run"),
    (lambda: plots.plot_work_precision(["x"], "wp.png"), "runs[0]", "bench.Run"),
])
def test_the_plots_check_what_they_are_given(call, name, said):
    import matplotlib.pyplot as plt
    refused(call, name, said)
    plt.close("all")


def test_plot_energy_momentum_refuses_axes_of_the_wrong_count():
    import matplotlib.pyplot as plt
    refused(lambda: plots.plot_energy_momentum(TRAJ, axes=plt.subplots(1, 3)[1]), "axes", "2 matplotlib Axes")
    assert len(plots.plot_energy_momentum(TRAJ, axes=plt.subplots(1, 2)[1])) == 2
    assert len(plots.plot_drift([TRAJ, TRAJ], labels=("a", "b"), axes=list(plt.subplots(1, 3)[1]))) == 3
    plt.close("all")


def test_momentum_sphere_takes_a_3d_axes_and_a_positive_energy():
    import matplotlib.pyplot as plt
    flat = plt.figure().add_subplot()
    refused(lambda: plots.momentum_sphere(flat, [1.0, 2.0, 2.5], L_norm=1.0), "ax", "3-D")
    ax = plt.figure().add_subplot(projection="3d")
    for energy in (-1.0, 0.0, math.nan, True):
        refused(lambda: plots.momentum_sphere(ax, [1.0, 2.0, 2.5], L_norm=1.0, energy=energy), "energy")
    refused(lambda: plots.momentum_sphere(ax, [1.0, 2.0, 1e308], L_norm=1.0, energy=10.0), "energy", "finite")
    assert plots.momentum_sphere(ax, [1.0, 2.0, 2.5], L_norm=1.0, energy=0.25) is ax
    plt.close("all")


def test_plot_work_precision_checks_its_path(tmp_path):
    from types import SimpleNamespace
    run = SimpleNamespace(problem="A", label="rk4", tool="rbcourse", seconds=0.1, error=1e-6)
    refused(lambda: plots.plot_work_precision([run], tmp_path / "no" / "wp.png"), "path", "does not exist")
    plots.plot_work_precision([run], tmp_path / "wp.png")
    assert (tmp_path / "wp.png").stat().st_size > 0


# --- file and folder names the file system cannot take -----------------------------------------------------------

@pytest.mark.parametrize("name, said", [("p" * 300 + ".html", "got a name of 305 bytes"),
                                        ("é" * 128 + ".html", "got a name of 261 bytes"),   # 133 characters
                                        ("/".join(["a" * 200] * 21) + "/page.html", "at most 4095 bytes")])
def test_a_name_or_path_too_long_is_refused_in_the_api_s_words(tmp_path, name, said):
    """The file system's own "[Errno 36] File name too long" was raised at save, or as a traceback by a command."""
    from rbcourse.support import checks, outputs
    message = refused(lambda: checks.file_path("path", tmp_path / name), "path", said)
    assert "255 bytes" in message or "4095 bytes" in message
    refused(lambda: viewer.draw_trajectory(TRAJ).save(tmp_path / name), "path", said)
    refused(lambda: outputs.writable_folder(tmp_path / name, "--out"), "--out", said)
    assert sorted(tmp_path.iterdir()) == []
    ok = tmp_path / ("p" * 250 + ".html")                    # 255 bytes: the longest name allowed
    assert viewer.draw_trajectory(TRAJ).save(ok) == ok and ok.stat().st_size > 0


# --- rotation: ω* ------------------------------------------------------------------------------------------------

def test_star_refuses_what_is_not_finite_as_velocity_does():
    """ω* is a user's matrix, not a step's: a NaN or inf in ω is refused, naming omega (it gave NaN silently)."""
    for w in ([np.nan, 1.0, 2.0], [0.0, np.inf, 0.0], [[1.0, 2.0, 3.0], [0.0, 0.0, -np.inf]]):
        with pytest.raises(ValueError, match=r"omega must contain only finite numbers \(no NaN or inf\)"):
            rb.star(w)
    np.testing.assert_array_equal(rb.star([1e308, 0, 0]), [[0, 0, 0], [0, 0, -1e308], [0, 1e308, 0]])


@pytest.mark.parametrize("phase", [1e308, -1e308, 1e15, 2.0 ** 32 * (1 + 2 ** -52)])
def test_a_sine_refuses_a_phase_float64_cannot_resolve(phase):
    """sin(2π f t + 1e308) is the same number at every t (the sum rounds to the phase): it was accepted and run."""
    refused(lambda: rb.Sine(F, 1.0, phase=phase), "phase", "±4.295e+09 rad", "modulo 2π")


def test_a_sine_takes_any_phase_float64_resolves():
    s = rb.Sine(F, 1.0, phase=2.0 ** 32)
    np.testing.assert_allclose(s(0.25), F * math.sin(math.pi / 2 + 2.0 ** 32), rtol=1e-6)
    assert rb.Sine(F, 1.0, phase=-2.0 ** 32).phase == -2.0 ** 32


# --- a force given as a function of t -----------------------------------------------------------------------------

@pytest.mark.parametrize("f, shown", [(lambda: (0, 0, 1.0), "<lambda>()"), (lambda t, x: (0, 0, 1.0), "<lambda>(t, x)")])
def test_a_force_function_that_cannot_be_called_as_f_of_t_is_refused_when_given(f, shown):
    """lambda: (0, 0, 1) was accepted, then the run raised Python's "takes 0 positional arguments but 1 was given"."""
    refused(lambda: rb.PointForce((0.15, 0.1, 0.025), f), "force", "function of time, f(t)", shown,
            "cannot be called as force(t)")


def test_a_force_function_without_a_readable_signature_is_told_at_its_first_call():
    import operator
    pf = rb.PointForce((0, 0, 0), operator.itemgetter(0))          # no signature to read: accepted, then said
    message = refused(lambda: pf.force_at(0.5), "force", "function of time, f(t)", "TypeError")
    assert "force(0.5)" in message
    scene = rb.Scene(BOX, [pf])
    refused(lambda: rb.simulate(scene, rb.State.at_rest(), 0.1, 0.01, "rk4"), "force", "function of time")


@pytest.mark.parametrize("f", [lambda t: (0, 0, t), lambda *a: (0, 0, 1.0), lambda t, k=2.0: (0, 0, k),
                               rb.Sine((0, 0, 1.0), 1.0), np.cos])
def test_a_force_function_of_t_is_taken(f):
    pf = rb.PointForce((0, 0, 0), (lambda t: np.full(3, f(t))) if f is np.cos else f)
    assert np.all(np.isfinite(pf.force_at(0.25)))


# --- a trajectory built by hand holds finite numbers, as a State ---------------------------------------------------

@pytest.mark.parametrize("name, at", [("x", (2, 0)), ("t", (3,)), ("R", (0, 1, 1)), ("P", (M - 1, 2)), ("L", (4, 1))])
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_trajectory_built_with_a_nan_or_inf_is_refused_as_a_state_is(name, at, bad):
    """A NaN position was accepted, and kinetic_energy() etc. answered for it (a State refuses one)."""
    args = dict(t=TRAJ.t, x=TRAJ.x, R=TRAJ.R, P=TRAJ.P, L=TRAJ.L, scene=TRAJ.scene)
    a = np.array(args[name])
    a[at] = bad
    args[name] = a
    refused(lambda: rb.Trajectory(**args), name, "finite", f"{name}[{', '.join(map(str, at))}] = {bad}")
    two = dict(t=TWO.t, x=np.array(TWO.x), R=TWO.R, P=TWO.P, L=TWO.L, scene=TWO.scene)
    two["x"][1, 1, 2] = bad
    refused(lambda: rb.Trajectory(**two), "x", "x[1, 1, 2]")


def test_a_run_its_slices_and_copies_stay_trajectories_and_unchecked_builds_one_of_known_finite_arrays():
    assert len(TRAJ.head(3)) == 3 and len(pickle.loads(pickle.dumps(TRAJ))) == M
    t = rb.Trajectory.unchecked(TRAJ.t, TRAJ.x, TRAJ.R, TRAJ.P, TRAJ.L, TRAJ.scene, method="rk4")
    np.testing.assert_array_equal(t.kinetic_energy(), TRAJ.kinetic_energy())


# --- the exact free body: the times it resolves ---------------------------------------------------------------------

@pytest.mark.parametrize("t", [1e308, -1e308, [0.0, 1e50], 1e12])
def test_exact_free_body_refuses_times_it_does_not_resolve(t):
    """At t = 1e308 it returned NaN silently: the angle |ω| t is beyond what float64 resolves."""
    refused(lambda: rb.exact_free_body(BOX, SPIN, t), "t", "|L| |t| / I_min", "4.295e+09 rad", "|t| <=")


def test_exact_free_body_refuses_a_position_that_overflows_and_answers_within_its_range():
    still = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), [1e300, 0, 0], np.zeros(3))
    refused(lambda: rb.exact_free_body(BOX, still, 1e10), "t", "x(t) = x0 + (P/M) t must stay finite")
    spin = float(np.linalg.norm(SPIN.L)) / float(min(BOX.principal_moments))
    longest = 2.0 ** 32 / spin
    far = rb.exact_free_body(BOX, SPIN, [0.0, 0.99 * longest, -0.99 * longest])
    assert np.all(np.isfinite(far.R)) and np.all(np.isfinite(far.x))
    refused(lambda: rb.exact_free_body(BOX, SPIN, 1.01 * longest), "t", f"{longest:.4g} s")
