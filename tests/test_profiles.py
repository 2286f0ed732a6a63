"""Forces over time as data (rbcourse/profiles.py, engine/profiles.py): each profile's formula, the kernel's
compiled evaluation against the same formula run as Python, runs with a profile against the same force given
as a Python function f(t), and their bad inputs."""
import math

import numpy as np
import pytest

import rbcourse as rb
from rbcourse.engine import profiles as compiled
from rbcourse.profiles import Profile
from rbcourse.examples import pushed_box

F = np.array([1.0, -2.0, 3.0])
TIMES = np.concatenate([np.linspace(-0.5, 2.5, 301), [0.0, 0.1, 0.2, 0.7, 1.0, np.nextafter(0.1, 0), 1.7]])


def expected(profile, t):
    """Each profile's formula, written out here on its own."""
    if isinstance(profile, rb.Constant):
        return F
    if isinstance(profile, rb.Pulse):
        return F if 0.1 <= t < 0.7 else np.zeros(3)
    if isinstance(profile, rb.Ramp):
        return F * (0.0 if t < 0.2 else 1.0 if t >= 1.0 else (t - 0.2) / 0.8)
    if isinstance(profile, rb.Sine):
        return np.array([0.5, 0.0, -1.0]) + F * math.sin(2 * math.pi * 1.5 * t + 0.3)
    table = [(0.0, (1.0, 0, 0)), (0.5, (0, 2.0, 0)), (1.7, (0, 0, -3.0))]
    out = np.zeros(3)
    for tj, fj in table:
        if tj <= t:
            out = np.array(fj)
    return out


PROFILES = [rb.Constant(F), rb.Pulse(F, 0.1, 0.7), rb.Ramp(F, 0.2, 1.0), rb.Sine(F, 1.5, 0.3, (0.5, 0.0, -1.0)),
            rb.Steps([0.0, 0.5, 1.7], [(1.0, 0, 0), (0, 2.0, 0), (0, 0, -3.0)])]


@pytest.mark.parametrize("profile", PROFILES, ids=lambda p: type(p).__name__)
def test_each_profile_is_its_formula(profile):
    for t in TIMES:
        np.testing.assert_allclose(profile(t), expected(profile, t), rtol=1e-14, atol=1e-14)


ZERO = (0.0, 0.0, 0.0)
ACTS = [   # (profile, t₀, whether F(t) != 0 at some t >= t₀)
    (rb.Constant(F), 5.0, True), (rb.Constant(ZERO), 0.0, False),
    (rb.Pulse(F, 0.1, 0.7), 0.0, True), (rb.Pulse(F, 0.1, 0.7), 0.69, True), (rb.Pulse(F, 0.1, 0.7), 0.7, False),
    (rb.Pulse(F, 0.1, 0.1), 0.0, False), (rb.Pulse(ZERO, 0.1, 0.7), 0.0, False),
    (rb.Ramp(F, 0.2, 1.0), 9.0, True), (rb.Ramp(ZERO, 0.2, 1.0), 0.0, False),
    (rb.Sine(F, 1.5), 3.0, True), (rb.Sine(ZERO, 1.5, 0.3, (0.5, 0, 0)), 3.0, True), (rb.Sine(ZERO, 1.5), 0.0, False),
    (rb.Sine(F, 0.0, 0.0), 0.0, False), (rb.Sine(F, 0.0, 0.3), 0.0, True),
    (rb.Sine(F, 0.0, math.pi / 2, -F), 0.0, False),
    (rb.Steps([0.0, 0.5, 1.7], [(1.0, 0, 0), ZERO, ZERO]), 0.4, True),
    (rb.Steps([0.0, 0.5, 1.7], [(1.0, 0, 0), ZERO, ZERO]), 0.5, False),
    (rb.Steps([0.0, 0.5, 1.7], [(1.0, 0, 0), ZERO, ZERO]), -1.0, True),
    (rb.Steps([0.0, 0.5, 1.7], [ZERO, ZERO, (0, 0, 2.0)]), 9.0, True),
    (rb.Steps([0.5], [ZERO]), 0.0, False),
]


@pytest.mark.parametrize("profile, t0, acts", ACTS, ids=lambda v: type(v).__name__ if isinstance(v, Profile) else str(v))
def test_whether_a_profile_acts_after_t0_is_known_exactly(profile, t0, acts):
    """Profile.acts_after(t₀): the plots' question (is the energy conserved from t₀ on?), answered from the
    profile's data — and what its formula says at many times from t₀ on agrees."""
    assert profile.acts_after(t0) is acts
    samples = t0 + np.concatenate([[0.0], np.geomspace(1e-9, 50.0, 2000)])
    if profile.acts_after(t0):       # a nonzero value at a sample (a Sine at frequency > 0: somewhere)
        assert any(np.any(profile(t) != 0) for t in samples)
    else:
        assert not any(np.any(np.abs(profile(t)) > 1e-15 * np.abs(F).max()) for t in samples)


def test_the_plots_ask_a_profile_and_do_not_sample_it(monkeypatch):
    """quantities.acts_after asks the profile (no call of F(t)); a Python f(t) is still sampled."""
    from rbcourse.viz import quantities
    box = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    pulse = rb.Pulse((0, 0, 10.0), 0.0, 0.1)
    monkeypatch.setattr(type(pulse), "__call__", lambda self, t: (_ for _ in ()).throw(AssertionError("sampled")))
    times = np.linspace(0.0, 1.0, 1001)
    assert quantities.acts_after(rb.PointForce((0, 0, 0), pulse, body=box), 0.0, times)
    assert not quantities.acts_after(rb.PointForce((0, 0, 0), pulse, body=box), 0.1, times)
    f = lambda t: (0.0, 0.0, 10.0) if t < 0.5 else (0.0, 0.0, 0.0)    # noqa: E731
    assert quantities.acts_after(rb.PointForce((0, 0, 0), f, body=box), 0.3, times)
    assert not quantities.acts_after(rb.PointForce((0, 0, 0), f, body=box), 0.5, times)


def test_the_compiled_evaluation_is_the_python_one_bit_for_bit():
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    scene = rb.Scene(body, [rb.PointForce((0, 0, 0), p) for p in PROFILES])
    sys = scene.compile().system
    assert sys.profiles.shape == (len(PROFILES), compiled.PROFILE_COLUMNS) and sys.table.shape == (3, 4)
    times = TIMES.reshape(-1, 1)
    values = np.zeros((len(times), 1, len(PROFILES), 3))
    compiled.fill_profiles(sys, times, values)
    for s, p in enumerate(PROFILES):
        for k, t in enumerate(TIMES):
            np.testing.assert_array_equal(values[k, 0, s], p(t))


@pytest.mark.parametrize("method", ["euler", "rk4", "implicit_midpoint", "exact_splitting", "adaptive",
                                    "symplectic_euler", "quaternion_euler"])
@pytest.mark.parametrize("profile", PROFILES, ids=lambda p: type(p).__name__)
def test_a_profile_runs_as_the_same_force_given_as_a_function(method, profile):
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    X0 = rb.State.from_velocities(body, [0, 0, 0], np.eye(3), [0, 0, 0], [0.1, 0.5, 0.1])   # slow: euler stays finite
    as_data = rb.Scene(body, [rb.PointForce((0.015, 0.01, 0.0025), profile, frame="body")])
    as_function = rb.Scene(body, [rb.PointForce((0.015, 0.01, 0.0025), lambda t: expected(profile, t), frame="body")])
    a = rb.simulate(as_data, X0, 2.0, 0.01, method)
    b = rb.simulate(as_function, X0, 2.0, 0.01, method)
    for u, v in ((a.x, b.x), (a.R, b.R), (a.P, b.P), (a.L, b.L)):
        np.testing.assert_allclose(u, v, rtol=1e-12, atol=1e-12)
    assert np.abs(a.P[-1]).max() > 0.1                             # the force acted


def test_the_pushed_box_is_pushed_by_a_compiled_pulse_and_the_engine_run_as_python_agrees():
    ex = pushed_box()
    assert isinstance(ex.scene.effects[0].force, rb.Pulse)
    fast = rb.simulate(ex.scene, ex.X0, 0.3, ex.dt, ex.method)
    slow = rb.simulate(ex.scene, ex.X0, 0.3, ex.dt, ex.method, fast=False)
    np.testing.assert_allclose(fast.P[-1], [0, 0, 1.0], rtol=1e-12)       # 10 N for 0.1 s
    for u, v in ((fast.x, slow.x), (fast.R, slow.R), (fast.P, slow.P), (fast.L, slow.L)):
        np.testing.assert_allclose(u, v, rtol=1e-12, atol=1e-14)


def test_profiles_are_immutable():
    p = rb.Pulse(F, 0.1, 0.7)
    with pytest.raises(ValueError):
        p.force[0] = 9.0
    with pytest.raises(ValueError):
        p.force.setflags(write=True)
    with pytest.raises(AttributeError, match="immutable"):
        p.t_stop = 3.0
    f = F.copy()
    q = rb.Constant(f)
    f[0] = 100.0
    assert q(0.0)[0] == 1.0


@pytest.mark.parametrize("build, name", [
    (lambda: rb.Pulse(F, 0.5, 0.1), "t_stop"),
    (lambda: rb.Ramp(F, 1.0, 0.0), "t_stop"),
    (lambda: rb.Pulse("10 N", 0.0, 0.1), "force"),
    (lambda: rb.Pulse(F, "0", 0.1), "t_start"),
    (lambda: rb.Pulse(F, 0.0, float("nan")), "t_stop"),
    (lambda: rb.Sine(F, -1.0), "frequency"),
    (lambda: rb.Sine(F, 1.0, offset=(1, 2)), "offset"),
    (lambda: rb.Steps([0.0, 0.0], [F, F]), "times"),
    (lambda: rb.Steps([0.0, 1.0], [F]), "forces"),
    (lambda: rb.Steps([], []), "times"),
    (lambda: rb.Steps([0.0, "a"], [F, F]), "times"),
    (lambda: rb.Steps([0.0, 1.0], [F, [1, 2, np.inf]]), "forces"),
])
def test_bad_profiles_are_refused_naming_the_parameter(build, name):
    with pytest.raises(ValueError, match=name):
        build()
