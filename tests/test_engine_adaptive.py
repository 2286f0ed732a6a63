"""The compiled adaptive method (rbcourse/engine/adaptive.py) against the same functions run as Python.

Both are stepped from Python, output step by output step, on the same scene (Y (N, 13)), and the substeps each
takes (accepted + rejected) must be the same count.
Agreement as tests/test_engine.py measures it: max |a − b| / (1 + max |b|) <= 1e-12.  The output intervals are
chosen so that the substep control works (many substeps per output step, rejections) but the run is not so long
that the scene's own instability (the tennis racket's flip, a swinging spring) amplifies rounding beyond 1e-12:
a perturbation of L by 1e-15 grows as much as the engine's difference does (checked when this was written).
"""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.engine import adaptive as ead
from rbcourse import driver
from rbcourse.engine import interpreted
from rbcourse.engine.motion import work
from rbcourse.methods import METHODS
from rbcourse import examples

TOL = 1e-12
STEPS = 100
BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
B2 = rb.RigidBody.box(2.0, (0.1, 0.4, 0.2))
B3 = rb.RigidBody(mass=0.5, inertia=[0.01, 0.02, 0.025])
R_TILT = rb.rotation.rotation_about([1.0, 2.0, 3.0], 0.4)


def spinning(body=BOX, x=(0.0, 0.0, 1.0), v=(0.1, -0.2, 0.3), omega=(0.3, 2.0, 0.5), R=None):
    return rb.State.from_velocities(body, x=x, R=np.eye(3) if R is None else R, v=v, omega=omega)


def _example(make):
    e = make()
    return e.scene, e.X0


# name -> (() -> (scene, X0), output interval h)
CASES = {
    "tennis_racket": (lambda: _example(examples.tennis_racket), 0.05),
    "gravity": (lambda: (rb.Scene(BOX, [rb.Gravity()]), spinning()), 0.1),
    "spring": (lambda: (rb.Scene(BOX, [rb.Spring((0.1, 0.05, 0.0), (0.0, 0.2, 1.5), stiffness=50.0, damping=0.3,
                                                 rest_length=0.4)]), spinning(R=R_TILT)), 0.02),
    "heavy_top": (lambda: _example(examples.heavy_top), 0.05),
    "three_bodies": (lambda: (
        rb.Scene([BOX, B2, B3], [rb.Gravity(), rb.LinearDrag(0.1), rb.AngularDrag(0.01),
                                 rb.Spring((0.1, 0.0, 0.0), stiffness=40.0, damping=0.3, rest_length=0.5, body=0,
                                           other_body=1, other_point=(0.0, 0.1, 0.0)),
                                 rb.Spring((0.0, 0.0, 0.3), stiffness=25.0, body=2, other_body=0,
                                           other_point=(0.0, 0.1, 0.0))]),
        rb.State.stack([spinning(), spinning(B2, x=(0.5, 0, 1), omega=(1, -2, 3)),
                        spinning(B3, x=(0, 0.5, 1), omega=(4, 1, -2))])), 0.02),
}


def engine_run(scene, X0, n, h, opts=None, Y=None, python=False):
    """The engine's adaptive_step, n times (from X0, or from the engine state Y), compiled — or, python=True, the
    same functions run as Python (engine/interpreted.py): states (n+1, N, 13), opts[SUB] after each step, the opts."""
    mod = interpreted.module("adaptive") if python else ead
    Y = driver.encode("quat", scene.to_engine(scene.batch(X0))) if Y is None else np.array(Y)
    out, U, w = np.empty_like(Y), np.empty_like(Y), work(Y.shape[0])
    K = np.empty((mod.SLOTS,) + Y.shape)
    A, b, den = mod.table()
    opts = mod.options() if opts is None else opts
    values = np.zeros((mod.STAGES + 1, 0, 3))
    states, subs = [Y.copy()], []
    sys = scene.compile().system
    for _ in range(n):
        mod.adaptive_step(A, b, den, opts, sys, values, Y, out, h, K, U, w)
        Y, out = out, Y
        states.append(Y.copy())
        subs.append(opts[mod.SUB])
    return np.array(states), np.array(subs), opts


def spread(a, b) -> float:
    return float(np.max(np.abs(a - b)) / (1.0 + np.max(np.abs(b))))


@pytest.mark.parametrize("name", sorted(CASES))
def test_compiled_adaptive_equals_the_same_functions_run_as_python(name):
    make, h = CASES[name]
    scene, X0 = make()
    a, sub_a, py = engine_run(scene, X0, STEPS, h, python=True)
    attempts = py[ead.ACCEPTED] + py[ead.REJECTED]
    b, sub_b, opts = engine_run(scene, X0, STEPS, h)
    # the same substeps: as many tried (accepted + rejected), each output step ending on the same next substep
    assert opts[ead.ACCEPTED] + opts[ead.REJECTED] == attempts
    assert opts[ead.ACCEPTED] > STEPS                   # the control works: more than one substep per output step
    # the next substep's size follows err^(-1/8), and err of the short substep cut at the output time is
    # rounding noise (e5 = Σ E5_j k_j cancels to ~1e-16 |k|): that noise, not a different sequence, is all
    # they differ by
    np.testing.assert_allclose(sub_b, sub_a, rtol=1e-2)
    for part, cols in (("x", slice(0, 3)), ("q", slice(3, 7)), ("P", slice(7, 10)), ("L_b", slice(10, 13))):
        d = spread(b[..., cols], a[..., cols])
        assert d <= TOL, f"{name}: {part} differs by {d:.3g}"


def test_rejected_substeps_are_the_same_compiled_and_run_as_python():
    """With output steps longer than the substeps (h = 0.05: 66 rejections of 258), the same substeps are
    tried; the states agree to 3e-12, not 1e-12: the substep carried to the next output step grows as
    err^(-1/8) of the last substep, cut short at the output time, whose err is rounding noise (Σ E5_j k_j
    cancels): 1e-3 relative between two summation orders, so the next substeps differ by that much and their
    results by that fraction of the local error (rtol 1e-8)."""
    make, _ = CASES["three_bodies"]
    scene, X0 = make()
    a, _, py = engine_run(scene, X0, STEPS, 0.05, python=True)
    attempts = py[ead.ACCEPTED] + py[ead.REJECTED]
    b, _, opts = engine_run(scene, X0, STEPS, 0.05)
    assert opts[ead.REJECTED] > 10
    assert opts[ead.ACCEPTED] + opts[ead.REJECTED] == attempts
    assert spread(b, a) <= 1e-11


def test_the_substep_is_carried_from_one_output_step_to_the_next():
    """Two runs of 50 steps on one opts array are the run of 100, to the bit (opts[SUB], opts[STEPS] carry on);
    the second 50 with a fresh opts array (SUB = 0: initial_substep again, t = 0) are a different run."""
    make, h = CASES["heavy_top"]
    scene, X0 = make()
    whole, _, _ = engine_run(scene, X0, 100, h)
    first, _, opts = engine_run(scene, X0, 50, h)
    assert opts[ead.STEPS] == 50 and opts[ead.SUB] > 0
    second, _, _ = engine_run(scene, X0, 50, h, opts=opts, Y=first[-1])
    np.testing.assert_array_equal(second[-1], whole[-1])
    again, _, _ = engine_run(scene, X0, 50, h, Y=first[-1])
    assert not np.array_equal(again[-1], whole[-1])
    assert spread(again[-1], whole[-1]) < 1e-8


def test_tolerances_come_from_opts():
    """A tighter rtol takes more substeps, run as Python too, and they agree."""
    make, h = CASES["heavy_top"]
    scene, X0 = make()
    a, _, py = engine_run(scene, X0, 20, h, opts=ead.options(rtol=1e-11, atol=1e-13), python=True)
    attempts = py[ead.ACCEPTED] + py[ead.REJECTED]
    b, _, opts = engine_run(scene, X0, 20, h, opts=ead.options(rtol=1e-11, atol=1e-13))
    _, _, loose = engine_run(scene, X0, 20, h)
    assert opts[ead.ACCEPTED] + opts[ead.REJECTED] == attempts
    assert opts[ead.ACCEPTED] > 1.5 * loose[ead.ACCEPTED]
    assert spread(b, a) <= TOL


def test_the_defaults_are_the_methods_settings():
    opts = ead.options()
    assert (opts[ead.RTOL], opts[ead.ATOL]) == (METHODS["adaptive"].settings["rtol"],
                                               METHODS["adaptive"].settings["atol"])


def test_a_substep_below_the_floor_is_a_blow_up():
    """A state the control cannot step (NaN momentum) gives NaN, not an endless loop."""
    make, h = CASES["gravity"]
    scene, X0 = make()
    Y = driver.encode("quat", scene.to_engine(scene.batch(X0)))
    Y[0, 10] = np.nan
    out, U, w = np.empty_like(Y), np.empty_like(Y), work(1)
    K = np.empty((ead.SLOTS,) + Y.shape)
    opts = ead.options()
    opts[ead.SUB] = h
    ead.adaptive_step(*ead.table(), opts, scene.compile().system, np.zeros((ead.STAGES + 1, 0, 3)), Y, out, h, K, U, w)
    assert np.isnan(out).all()


def test_forces_given_as_functions_are_read_at_the_substeps_own_times():
    """adaptive picks its substep times, so a force f(t) is evaluated in Python before each attempt, at its
    stages' t + c_i sub (forcing.SubstepForces, between the compiled begin_step and attempt calls): a function
    returning a constant gives the constant force's run to the bit, and a force varying in time converges to
    the fine rk4 run; compiled and run as Python agree."""
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    X0 = spinning(body)
    constant = rb.Scene(body, [rb.Gravity(), rb.PointForce((0.1, 0, 0), (0, 0, 1.0))])
    as_function = rb.Scene(body, [rb.Gravity(), rb.PointForce((0.1, 0, 0), lambda t: (0.0, 0.0, 1.0))])
    a = rb.simulate(constant, X0, 1.0, 0.1, "adaptive")
    b = rb.simulate(as_function, X0, 1.0, 0.1, "adaptive")
    assert a.implementation.startswith("compiled") and b.implementation.startswith("compiled")
    for name in "xRPL":
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    times = []

    def pushed(t):
        times.append(t)
        return (0.0, 0.0, float(np.sin(7.0 * t)))
    varying = rb.Scene(body, [rb.Gravity(), rb.PointForce((0.1, 0, 0), pushed, frame="body")])
    ref = rb.simulate(varying, X0, 1.0, 1e-4, "rk4")
    times.clear()
    errors = []
    for rtol in (1e-6, 1e-9, 1e-12):
        run = rb.simulate(varying, X0, 1.0, 0.25, "adaptive", rtol=rtol, atol=rtol * 1e-3)
        errors.append(max(np.abs(run.L[-1] - ref.L[-1]).max(), np.abs(run.R[-1] - ref.R[-1]).max()))
    assert errors[-1] < 1e-11 and errors[0] > errors[-1]
    python = rb.simulate(varying, X0, 1.0, 0.25, "adaptive", rtol=1e-9, atol=1e-12, fast=False)
    compiled = rb.simulate(varying, X0, 1.0, 0.25, "adaptive", rtol=1e-9, atol=1e-12)
    assert python.implementation.startswith("interpreted")
    for name in "xRPL":
        np.testing.assert_allclose(getattr(python, name), getattr(compiled, name), rtol=0, atol=1e-12)
    off_grid = [t for t in times if abs(t / 0.25 - round(t / 0.25)) > 1e-9]
    assert len(off_grid) > 100      # the substeps' own stage times, not only the output times
