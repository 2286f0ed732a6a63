"""Property tests: random bodies, states and forces never crash (except the documented errors),
claimed invariants hold, states round-trip, and garbage inputs always give the clear ValueError."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rbcourse as rb

from helpers import rotations

moment = st.floats(1e-3, 10.0)


@st.composite
def physical_bodies(draw):
    """Principal moments obeying the triangle inequality (flat plates allowed), in random axes."""
    a, b = draw(moment), draw(moment)
    c = draw(st.floats(abs(a - b), a + b)) if abs(a - b) < a + b else a + b
    c = max(c, 1e-6)
    Q = draw(rotations())
    mass = draw(st.floats(1e-3, 1e3))
    return rb.RigidBody(mass, Q @ np.diag([a, b, c]) @ Q.T)


vec = st.tuples(*[st.floats(-3, 3)] * 3).map(np.array)


@st.composite
def states(draw, body):
    return rb.State.from_velocities(body, draw(vec), draw(rotations()), draw(vec), draw(vec))


effects = st.lists(st.one_of(
    st.builds(rb.Gravity, st.floats(0, 20)),
    st.builds(rb.PointForce, vec, vec, st.sampled_from(["world", "body"])),
    st.builds(rb.Spring, vec, vec, st.floats(0, 50), st.floats(0, 2), st.floats(0, 1)),
    st.builds(rb.LinearDrag, st.floats(0, 1)),
    st.builds(rb.AngularDrag, st.floats(0, 1)),
), max_size=3)


@settings(max_examples=25)
@given(data=st.data(), method=st.sampled_from(sorted(rb.METHODS)))
def test_random_scenes_never_crash(data, method):
    body = data.draw(physical_bodies())
    X0 = data.draw(states(body))
    scene = rb.Scene(body, data.draw(effects))
    try:
        traj = rb.simulate(scene, X0, 0.05, 0.01, method)
    except rb.SimulationDiverged as err:          # the one documented way a run may end early
        traj = err.trajectory
    assert np.all(np.isfinite(traj.x)) and np.all(np.isfinite(traj.R)) and np.all(np.isfinite(traj.L))


@settings(max_examples=20)
@given(data=st.data(), method=st.sampled_from(sorted(rb.METHODS)))
def test_claimed_invariants_on_random_free_bodies(data, method):
    body = data.draw(physical_bodies())
    X0 = data.draw(states(body))
    m = rb.METHODS[method]
    traj = rb.simulate(body, X0, 0.2, 0.01, method)
    L0 = traj.angular_momentum()[0]
    # L about the origin includes x × P, whose rounding scales with |x| |P|
    scale = np.linalg.norm(L0) + np.abs(traj.x).max() * np.linalg.norm(X0.P) + 1e-300
    # rounding grows with the inertia's condition number: ω = I⁻¹ L has components up to |L| / I_min,
    # and each step rounds R (and so L = R L_b, E = ½ L·ω) at that size — a near-rod (1 : 1 : 1e-6)
    # keeps its invariants to about 1e-16 × 1e6 per step, not 1e-16
    moments = np.linalg.eigvalsh(body.I_body)
    tol = 1e-12 * max(1.0, moments.max() / moments.min())
    if "SO(3)" in m.keeps:
        assert traj.orthogonality_error().max() < 1e-12
    if "L" in m.keeps:
        assert np.abs(traj.angular_momentum() - L0).max() <= tol * scale + 1e-300
    if "|L|" in m.keeps:
        norms = np.linalg.norm(traj.L, axis=1)
        assert np.ptp(norms) <= tol * norms[0] + 1e-300
    if "energy" in m.keeps and np.linalg.norm(X0.L) == 0:
        return
    if "energy" in m.keeps:
        E = traj.kinetic_energy()
        assert np.ptp(E) <= tol * E[0] + 1e-300


@given(data=st.data())
def test_state_round_trips(data):
    body = data.draw(physical_bodies())
    x, R, v, w = data.draw(vec), data.draw(rotations()), data.draw(vec), data.draw(vec)
    X = rb.State.from_velocities(body, x, R, v, w)
    d = rb.derived(body, X)
    np.testing.assert_allclose(d.v, v, atol=1e-9)
    np.testing.assert_allclose(d.omega, w, atol=1e-8 * (1 + np.abs(w).max()))
    assert X.replace() == X and rb.State(X.x, X.R, X.P, X.L) == X
    S = rb.State.stack([X, X.replace(x=x + 1)])
    assert S.body(0) == X
    q = rb.rotation.quat_from_matrix(X.R)
    np.testing.assert_allclose(rb.rotation.matrix_from_quat(q), X.R, atol=1e-13)


garbage = st.one_of(st.none(), st.text(max_size=5), st.booleans(), st.integers(-5, 5),
                    st.floats(allow_nan=True, allow_infinity=True), st.lists(st.floats(allow_nan=True), max_size=5),
                    st.lists(st.text(max_size=2), min_size=3, max_size=3), st.dictionaries(st.text(max_size=2), st.integers(), max_size=2),
                    st.just(np.array([[1.0, 2.0], [3.0, 4.0]])), st.just(np.full(3, np.nan)), st.just(-1.0), st.just(0.0))


def _finite_array(value, shape):
    if isinstance(value, (bool, str, dict)) or value is None:
        return False
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return arr.shape == shape and bool(np.all(np.isfinite(arr)))


def _positive(value):
    return (not isinstance(value, (bool, str)) and value is not None and _finite_array(value, ())
            and float(value) > 0)


def _nonnegative(value):
    return (not isinstance(value, (bool, str)) and value is not None and _finite_array(value, ())
            and float(value) >= 0)


# each call, and which of the garbage values would be valid input for it
CALLS = {
    "mass": (lambda g: rb.RigidBody(g, [1.0, 1.0, 1.0]), _positive),
    "inertia": (lambda g: rb.RigidBody(1.0, g),
                lambda g: _finite_array(g, (3,)) and np.asarray(g, float).min() > 0
                and 2 * np.asarray(g, float).max() <= np.asarray(g, float).sum() * (1 + 1e-9)),
    "box size": (lambda g: rb.RigidBody.box(1.0, g), lambda g: _finite_array(g, (3,)) and np.asarray(g, float).min() > 0),
    "State.x": (lambda g: rb.State(g, np.eye(3), np.zeros(3), np.zeros(3)), lambda g: _finite_array(g, (3,))),
    "State.R": (lambda g: rb.State(np.zeros(3), g, np.zeros(3), np.zeros(3)), lambda g: False),
    "dt": (lambda g: rb.simulate(rb.RigidBody.sphere(1, 1), rb.State.at_rest(), 0.1, g),
           lambda g: _positive(g) and 0.1 / float(g) < 1e9),
    "t_end": (lambda g: rb.simulate(rb.RigidBody.sphere(1, 1), rb.State.at_rest(), g, 0.01),
              lambda g: _nonnegative(g) and float(g) / 0.01 < 1e9),
    "method": (lambda g: rb.simulate(rb.RigidBody.sphere(1, 1), rb.State.at_rest(), 0.1, 0.01, g), lambda g: False),
    "Gravity.g": (lambda g: rb.Gravity(g), _nonnegative),
    "PointForce.body_point": (lambda g: rb.PointForce(g, (0, 0, 1)), lambda g: _finite_array(g, (3,))),
    "Spring.stiffness": (lambda g: rb.Spring((0, 0, 0), stiffness=g), _nonnegative),
    "walkthrough.forces": (lambda g: rb.walkthrough(rb.RigidBody.sphere(1, 1), rb.State.at_rest(), g, 0.01),
                           lambda g: isinstance(g, list) and len(g) == 0),
    "exact_free_body.t": (lambda g: rb.exact_free_body(rb.RigidBody.sphere(1, 1), rb.State.at_rest(), g),
                          lambda g: not isinstance(g, (bool, str)) and g is not None and
                          (_finite_array(g, ()) or (_finite_array(g, (len(g),)) if isinstance(g, list) and g else False))),
    "Ground.restitution": (lambda g: rb.Ground(restitution=g), lambda g: _nonnegative(g) and float(g) <= 1),
}


@pytest.mark.parametrize("name", sorted(CALLS))
@settings(max_examples=40)
@given(g=garbage)
def test_garbage_gives_the_clear_error(name, g):
    call, valid = CALLS[name]
    try:
        call(g)
    except ValueError as err:
        assert str(err), "an empty message names nothing"
    except rb.SimulationDiverged:
        pytest.fail("garbage reached the integrator")
    else:
        assert valid(g), f"{name} accepted {g!r}"
