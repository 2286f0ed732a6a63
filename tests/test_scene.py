"""Scenes compose effects; only the effects a scene calls for are computed."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse import effects as fx
from rbcourse.examples import SCENES

BOX = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))
EFFECT_CLASSES = [fx.Gravity, fx.PointForce, fx.Spring, fx.LinearDrag, fx.AngularDrag]


@pytest.fixture
def counters(monkeypatch):
    """Count every evaluation of every effect, by kind, in the engine run as Python (fast=False): the engine's
    effect_on_body (engine/motion.py), which computes each effect row's force and torque on a body, and
    effect_on for a spring that joins two bodies (its own branch)."""
    from rbcourse.engine import interpreted
    motion, system = interpreted.module("motion"), interpreted.module("system")
    names = {system.GRAVITY: "Gravity", system.POINT_FORCE: "PointForce", system.SPRING: "Spring",
             system.LINEAR_DRAG: "LinearDrag", system.ANGULAR_DRAG: "AngularDrag"}
    counts = {cls.__name__: 0 for cls in EFFECT_CLASSES}
    on_body, on = motion.effect_on_body, motion.effect_on

    def counted_on_body(sys, e, *args):
        counts[names[int(sys.code[e])]] += 1
        return on_body(sys, e, *args)

    def counted_on(sys, e, *args):
        if sys.code[e] == system.SPRING and sys.other[e] >= 0:      # joins two bodies: not through effect_on_body
            counts["Spring"] += 1
        return on(sys, e, *args)
    monkeypatch.setattr(motion, "effect_on_body", counted_on_body)
    monkeypatch.setattr(motion, "effect_on", counted_on)
    return counts


def _all_effects():
    return {"Gravity": rb.Gravity(), "PointForce": rb.PointForce((0.1, 0, 0), (0, 0, 1.0)),
            "Spring": rb.Spring((0, 0, 0), (0, 0, 1), stiffness=5.0), "LinearDrag": rb.LinearDrag(0.1),
            "AngularDrag": rb.AngularDrag(0.01)}


@pytest.mark.parametrize("method", ["euler", "rk4", "splitting", "implicit_midpoint"])
@pytest.mark.parametrize("chosen", [[], ["Gravity"], ["Spring"], ["Gravity", "AngularDrag"], ["PointForce", "LinearDrag"]])
def test_only_the_scene_effects_are_evaluated(counters, method, chosen):
    effects = _all_effects()
    scene = rb.Scene(BOX, [effects[name] for name in chosen])
    X0 = rb.State.from_velocities(BOX, [0, 0, 0.5], np.eye(3), [0.1, 0, 0], [1.0, 2.0, 3.0])
    rb.simulate(scene, X0, 0.05, 0.01, method, fast=False)   # the engine run as Python: its calls can be counted
    for name, count in counters.items():
        if name in chosen:
            assert count > 0, f"{name} is in the scene but was never evaluated"
        else:
            assert count == 0, f"{name} is not in the scene but was evaluated {count} times"


def test_free_scene_evaluates_nothing_and_detects_no_contact(monkeypatch):
    def forbidden(*args, **kwargs):
        raise AssertionError("called in a scene that does not ask for it")
    import importlib
    run = importlib.import_module("rbcourse.simulate")          # the module (rb.simulate is the function)
    monkeypatch.setattr(rb.Ground, "ground_rows", forbidden)     # a ground's rows in the kernel's System
    monkeypatch.setattr(run, "_kick", forbidden)                 # an impulse, applied between compiled calls
    monkeypatch.setattr(rb.Scene, "apply_impulses", forbidden)
    monkeypatch.setattr(rb.Scene, "constrain", lambda self, X: X if not self.has_pivots else forbidden())
    scene = rb.Scene(BOX)
    assert not scene.has_forces
    X0 = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), [1, 0, 0], [0.01, 5.0, 0.01])
    assert len(scene.compile().system.grounds) == 0            # the loop solves no contact (engine/run.py)
    for method in rb.METHODS:
        traj = rb.simulate(scene, X0, 0.05, 0.01, method)
        np.testing.assert_allclose(traj.P, np.broadcast_to(traj.P[0], traj.P.shape))


def test_describe_says_what_is_simulated():
    free = rb.Scene(BOX)
    assert "No effect" in free.describe() and "free body" in free.describe()
    scene = rb.Scene(BOX, [rb.Gravity(9.81), rb.Spring((0, 0, 0), (0, 0, 1), stiffness=50.0)])
    text = scene.describe("rk4")
    assert "gravity g = 9.81" in text and "spring k = 50" in text and "No contact detection" in text
    assert "Integrator: rk4" in text and "Pivot" not in text
    assert repr(scene) == scene.describe()


def test_many_bodies_step_like_each_alone():
    rng = np.random.default_rng(3)
    bodies = [rb.RigidBody.box(float(rng.uniform(0.5, 2)), rng.uniform(0.05, 0.5, 3)) for _ in range(6)]
    states = [rb.State.from_velocities(b, rng.normal(size=3), rb.rotation.rotation_about(rng.normal(size=3), 1.0),
                                       rng.normal(size=3), rng.normal(size=3) * 3) for b in bodies]
    effects = [rb.Gravity(), rb.AngularDrag(0.01), rb.Spring((0.02, 0, 0), (0, 0, 2), stiffness=4.0, damping=0.1)]
    many = rb.Scene(bodies, effects)
    for method in ["rk4", "splitting", "symplectic_euler", "adaptive"]:
        traj = rb.simulate(many, rb.State.stack(states), 0.5, 0.01, method)
        assert traj.x.shape == (51, 6, 3) and traj.R.shape == (51, 6, 3, 3)
        for i, (b, X) in enumerate(zip(bodies, states)):
            alone = rb.simulate(rb.Scene(b, effects), X, 0.5, 0.01, method)
            tol = 1e-6 if method == "adaptive" else 1e-12        # adaptive: one step size for all bodies
            np.testing.assert_allclose(traj.R[:, i], alone.R, atol=tol)
            np.testing.assert_allclose(traj.x[:, i], alone.x, atol=tol)


def test_effect_on_selected_bodies():
    a, b = rb.RigidBody.sphere(1.0, 0.1), rb.RigidBody.sphere(2.0, 0.1)
    scene = rb.Scene([a, b], [rb.Gravity(body=1), rb.PointForce((0, 0, 0), (1.0, 0, 0), body=a)])
    X0 = rb.State.stack([rb.State.at_rest(), rb.State.at_rest(x=[1, 0, 0])])
    traj = rb.simulate(scene, X0, 1.0, 0.01, "rk4")
    np.testing.assert_allclose(traj.x[-1, 0], [0.5, 0, 0], atol=1e-12)          # pushed, no gravity
    np.testing.assert_allclose(traj.x[-1, 1], [1, 0, -9.81 / 2], atol=1e-12)     # falls, not pushed


def test_spring_period_and_damping_closed_form():
    k, m, c = 50.0, 1.0, 0.4
    for damping in (0.0, c):
        scene = rb.Scene(BOX, [rb.Spring((0, 0, 0), (0, 0, 0), stiffness=k, damping=damping)])
        X0 = rb.State.at_rest(x=[0.1, 0, 0])
        traj = rb.simulate(scene, X0, 5.0, 1e-3, "rk4")
        w0, zeta = np.sqrt(k / m), damping / (2 * np.sqrt(k * m))
        wd = w0 * np.sqrt(1 - zeta**2)
        exact = 0.1 * np.exp(-zeta * w0 * traj.t) * (np.cos(wd * traj.t) + zeta * w0 / wd * np.sin(wd * traj.t))
        np.testing.assert_allclose(traj.x[:, 0], exact, atol=1e-9)
        if damping == 0.0:
            x = traj.x[:, 0]
            up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
            tc = traj.t[up] - x[up] * (traj.t[up + 1] - traj.t[up]) / (x[up + 1] - x[up])
            assert np.diff(tc).mean() == pytest.approx(2 * np.pi * np.sqrt(m / k), rel=1e-6)


def test_spring_between_two_bodies_keeps_momentum_and_has_the_reduced_mass_period():
    a, b = rb.RigidBody.sphere(1.0, 0.05), rb.RigidBody.sphere(3.0, 0.05)
    k = 30.0
    scene = rb.Scene([a, b], [rb.Spring((0, 0, 0), stiffness=k, body=0, other_body=1, other_point=(0, 0, 0))])
    X0 = rb.State.stack([rb.State.at_rest(x=[-0.2, 0, 0]), rb.State.at_rest(x=[0.2, 0, 0])])
    traj = rb.simulate(scene, X0, 3.0, 1e-3, "rk4")
    np.testing.assert_allclose(traj.P.sum(axis=1), 0, atol=1e-12)
    E = traj.total_energy().sum(axis=1)
    assert np.ptp(E) < 1e-9 * E[0]
    d = traj.x[:, 1, 0] - traj.x[:, 0, 0]
    mu = 1.0 * 3.0 / 4.0
    np.testing.assert_allclose(d, 0.4 * np.cos(np.sqrt(k / mu) * traj.t), atol=1e-9)


def test_linear_and_angular_drag_decay():
    scene = rb.Scene(BOX, [rb.LinearDrag(0.5), rb.AngularDrag(0.002)])
    X0 = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), [1.0, 0, 0], [0, 0, 3.0])   # spin about a principal axis
    traj = rb.simulate(scene, X0, 2.0, 1e-3, "rk4")
    np.testing.assert_allclose(traj.velocity()[:, 0], np.exp(-0.5 * traj.t), rtol=1e-10)
    np.testing.assert_allclose(traj.angular_velocity()[:, 2], 3.0 * np.exp(-0.002 / BOX.I_body[2, 2] * traj.t), rtol=1e-9)


@pytest.mark.parametrize("call, match", [
    (lambda: rb.Gravity(g=-1), "g must be >= 0"),
    (lambda: rb.Gravity(g=np.nan), "g must be finite"),
    (lambda: rb.PointForce((0, 0), (0, 0, 1)), "body_point must have shape"),
    (lambda: rb.PointForce((0, 0, 0), (0, 0, np.inf)), "force must contain only finite"),
    (lambda: rb.PointForce((0, 0, 0), (0, 0, 1), frame="local"), "frame must be one of"),
    (lambda: rb.Spring((0, 0, 0), stiffness=-1), "stiffness must be >= 0"),
    (lambda: rb.Spring((0, 0, 0), damping=-0.1), "damping must be >= 0"),
    (lambda: rb.Spring((0, 0, 0), rest_length=-1), "rest_length must be >= 0"),
    (lambda: rb.Spring((0, 0, 0), other_body="b"), "other_body must be"),
    (lambda: rb.LinearDrag(-1.0), "coefficient must be >= 0"),
    (lambda: rb.AngularDrag(np.nan), "coefficient must be finite"),
    (lambda: rb.Impulse((0, 0, 0), (1, 0, 0), time=-1), "time must be >= 0"),
    (lambda: rb.Impulse((0, 0, 0), (1, 0), time=1), "impulse must have shape"),
    (lambda: rb.Pivot((0, 0, np.nan)), "body_point must contain only finite"),
    (lambda: rb.Gravity(body="first"), "body must be None, an index"),
    (lambda: rb.Scene(BOX, [rb.Gravity(body=3)]), r"must be an index in \[0, 0\]"),
    (lambda: rb.Scene([BOX, BOX], [rb.Gravity(body=BOX)]), "pass its index"),
    (lambda: rb.Scene(BOX, [rb.Pivot((0, 0, 0)), rb.Pivot((0, 0, 1))]), "at most one Pivot"),
    (lambda: rb.Scene(BOX, ["gravity"]), "effects must contain effect objects"),
    (lambda: rb.Scene([], []), "non-empty sequence"),
    (lambda: rb.Scene("box"), "bodies must be"),
])
def test_bad_effect_parameters(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_force_function_with_bad_output_is_a_clear_error():
    scene = rb.Scene(BOX, [rb.PointForce((0, 0, 0), lambda t: (0, 1))])
    with pytest.raises(ValueError, match="force.t. must return a finite 3-vector"):
        rb.simulate(scene, rb.State.at_rest(), 0.1, 0.01, "rk4")


@pytest.mark.parametrize("name", sorted(SCENES))
def test_named_scenes_run(name):
    ex = SCENES[name]()
    traj = rb.simulate(ex.scene, ex.X0, 10 * ex.dt, ex.dt, ex.method)
    assert len(traj) == 11 and np.all(np.isfinite(traj.R))
    assert ex.scene.describe()


def test_bodies_of_names_the_bodies_an_effect_acts_on():
    a, b = rb.RigidBody.box(1.0, (1, 2, 3)), rb.RigidBody.box(2.0, (1, 1, 1))
    push = rb.PointForce((0, 0, 0.5), (0, 0, 1), body=b)
    scene = rb.Scene([a, b], [rb.Gravity(), push, rb.PointForce((0.5, 0, 0), (1, 0, 0), body=0)])
    assert scene.bodies_of(scene.effects[0]).tolist() == [0, 1]
    assert scene.bodies_of(push).tolist() == [1]
    assert scene.bodies_of(scene.effects[2]).tolist() == [0]
