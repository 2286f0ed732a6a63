"""Ground contact: collisions by impulses (restitution e), Coulomb friction (μ), resting contact, no sinking.

Reference numbers are exact for the scheme: rk4 integrates a free flight under gravity exactly
(the motion is a polynomial of degree 2), so the only errors left are the contact's own, of
one step: a collision is resolved at the end of the step in which the point would cross the
plane, i.e. up to |v| Δt above it, and friction acts on the velocity at the end of each step.
"""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.rotation import rotation_about

G = 9.81
BOX = rb.RigidBody.box(1.5, (0.3, 0.2, 0.1))
BALL = rb.RigidBody.sphere(1.0, 0.1)
SIGNS = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], dtype=float)


def lowest_corner(traj, body=BOX, i=None):
    """z of the lowest corner of a box, over time."""
    pts = [traj.body_point(s * body.half_extents(), **({} if i is None else {"body": i})) for s in SIGNS]
    return np.min([p[:, 2] for p in pts], axis=0)


def drop(body, z, R=np.eye(3), v=(0, 0, 0), omega=(0, 0, 0), t_end=1.0, dt=2e-3, method="rk4", **ground):
    X0 = rb.State.from_velocities(body, [0.0, 0.0, z], R, v, omega)
    return rb.simulate(rb.Scene(body, [rb.Gravity(), rb.Ground(**ground)]), X0, t_end, dt, method)


# --- parameters -----------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, words", [
    ({"height": np.nan}, r"height must be a real number within ±1e\+08 m"),
    ({"height": np.inf}, r"height must be a real number within ±1e\+08 m"),
    ({"height": "low"}, r"height must be a real number within ±1e\+08 m"),
    ({"restitution": -0.1}, r"restitution must be a real number in \[0, 1\]"),
    ({"restitution": 1.5}, r"restitution must be a real number in \[0, 1\]"),
    ({"restitution": np.nan}, r"restitution must be a real number in \[0, 1\]"),
    ({"restitution": True}, r"restitution must be a real number in \[0, 1\]"),
    ({"friction": -0.5}, "friction must be a finite real number >= 0"),
    ({"friction": np.inf}, "friction must be a finite real number >= 0"),
    ({"friction": None}, "friction must be a finite real number >= 0"),
    ({"body": "all"}, "body must be None, an index, a RigidBody or a list of indices"),
])
def test_every_bad_parameter_gives_a_clear_error(kwargs, words):
    with pytest.raises(ValueError, match=words):
        rb.Ground(**kwargs)


def test_a_pivoted_body_is_refused_and_can_be_left_out():
    pivot = rb.Pivot((0, 0, 0.05), (0, 0, 1.0), body=0)
    X0 = rb.State.stack([pivot.state(BOX, np.eye(3), (0, 0, 1.0)), rb.State.at_rest((1.0, 0, 0.05))])
    with pytest.raises(ValueError, match="cannot act on pivoted bodies.*body="):
        rb.Scene([BOX, BOX], [rb.Gravity(), pivot, rb.Ground()])              # refused when the scene is built
    traj = rb.simulate(rb.Scene([BOX, BOX], [rb.Gravity(), pivot, rb.Ground(body=1)]), X0, 0.1, 5e-3)
    assert abs(traj.x[-1, 1, 2] - 0.05) < 1e-12                 # body 1 rests on the ground


def test_describe_and_repr():
    g = rb.Ground(0.25, restitution=0.3, friction=0.7)
    assert repr(g) == "Ground(height=0.25, restitution=0.3, friction=0.7)"
    text = rb.Scene(BOX, [rb.Gravity(), g]).describe()
    assert "ground plane z = 0.25 m" in text and "e = 0.3" in text and "μ = 0.7" in text
    assert "No contact detection" not in text
    assert g.kind == "contact" and rb.Ground in (type(e) for e in rb.Scene(BOX, [g]).effects)


def test_a_ground_is_recognised_by_its_kind_and_keeps_nothing_of_the_scenes_it_is_in():
    class Floor(rb.Ground):
        """Another name, the same contact effect."""
    floor = Floor(0.0, restitution=0.0)
    assert "No contact detection" not in rb.Scene(BOX, [floor]).describe()
    X0 = rb.State.at_rest((0, 0, 0.3))
    high = rb.simulate(rb.Scene(BALL, [rb.Gravity(), floor]), X0, 0.5, 2e-3)          # one Ground, two scenes
    both = rb.simulate(rb.Scene([BOX, BALL], [rb.Gravity(), floor]), rb.State.stack([X0, X0]), 0.5, 2e-3)
    assert all(v is None or isinstance(v, float) for v in vars(floor).values())   # its parameters, no per-scene data
    assert abs(high.x[-1, 2] - 0.1) < 1e-12 and abs(both.x[-1, 0, 2] - 0.05) < 1e-12   # each rests on z = 0
    np.testing.assert_allclose(both.x[:, 1], high.x, atol=1e-12)


def test_only_the_selected_bodies_touch_the_ground():
    X0 = rb.State.stack([rb.State.at_rest((0, 0, 0.2)), rb.State.at_rest((1, 0, 0.2))])
    traj = rb.simulate(rb.Scene([BOX, BOX], [rb.Gravity(), rb.Ground(restitution=0, body=[0])]), X0, 0.4, 4e-3)
    assert abs(traj.x[-1, 0, 2] - 0.05) < 1e-12                 # resting on z = 0
    np.testing.assert_allclose(traj.x[-1, 1, 2], 0.2 - 0.5 * G * 0.4**2, rtol=1e-12)   # fell through


# --- a box dropped: comes to rest, never sinks, never gains energy ------------------------------

@pytest.mark.parametrize("R", [np.eye(3), rotation_about([1, 0, 0], 0.5), rotation_about([1, 2, 0.5], 0.7)],
                         ids=["flat", "edge", "corner"])
def test_dropped_box_comes_to_rest_without_sinking_or_gaining_energy(R):
    height = 0.25
    traj = drop(BOX, height + 0.3, R, v=(0.3, -0.1, 0), omega=(0, 0, 1.0), t_end=0.9,
                height=height, restitution=0.3, friction=0.6)
    assert lowest_corner(traj).min() >= height - 1e-9            # no sinking, at any step
    E = traj.total_energy()
    assert np.diff(E).max() <= 1e-9 * E[0]                     # energy never increases (rk4 rounding)
    last = traj.t >= 0.7                                        # at rest over the last 0.2 s ...
    assert np.abs(traj.velocity()[last]).max() < 1e-9
    assert np.abs(traj.angular_velocity()[last]).max() < 1e-9
    assert np.abs(traj.x[last] - traj.x[-1]).max() < 1e-12
    # ... lying on a face: E = M g (height + a half side)
    faces = BOX.mass * G * (height + BOX.half_extents())
    assert np.min(np.abs(E[-1] - faces)) < 1e-9 * E[0]


def test_dropped_box_comes_to_rest_with_the_slides_euler_too():
    traj = drop(BOX, 0.35, v=(0.3, 0, 0), t_end=1.0, method="euler", restitution=0.3, friction=0.6)
    assert lowest_corner(traj).min() >= -1e-9
    assert np.abs(traj.velocity()[-100:]).max() < 1e-9
    assert abs(traj.x[-1, 2] - 0.05) < 1e-12


@pytest.mark.parametrize("method", ["rk4", "euler"])
def test_resting_box_stays_put_for_seconds(method):
    cyl = rb.RigidBody.cylinder(2.0, 0.1, 0.3)
    X0 = rb.State.stack([rb.State.at_rest((0.1, -0.2, 0.05), rotation_about([0, 0, 1], 0.3)),
                         rb.State.at_rest((1.0, 0.0, 0.15), rotation_about([0, 0, 1], 0.7))])   # standing
    traj = rb.simulate(rb.Scene([BOX, cyl], [rb.Gravity(), rb.Ground()]), X0, 5.0, 1e-2, method)
    assert np.abs(traj.x - X0.x).max() < 1e-12                             # no sinking, no creeping
    assert rb.rotation_angle(X0.R, traj.R).max() < 1e-12
    assert np.abs(traj.P).max() < 1e-12 and np.abs(traj.L).max() < 1e-12   # no jitter


# --- restitution --------------------------------------------------------------------------------

@pytest.mark.parametrize("R", [np.eye(3), rotation_about([1, 0, 0], 0.3)], ids=["flat", "edge"])
def test_restitution_zero_does_not_bounce(R):
    traj = drop(BOX, 0.35, R, t_end=0.6, restitution=0.0, friction=0.5)
    z, vz = traj.x[:, 2], traj.velocity()[:, 2]
    hit = np.argmax(np.diff(vz) > 0) + 1                        # the first impulse from the ground
    assert 0.2 < traj.t[hit] < 0.3
    assert np.diff(z[hit:]).max() <= 1e-12 and vz[hit:].max() <= 1e-12   # never rises again
    assert abs(z[-1] - 0.05) < 1e-12 and lowest_corner(traj).min() >= -1e-9
    ball = drop(BALL, 0.6, t_end=0.6, restitution=0.0)
    assert ball.velocity()[:, 2].max() <= 1e-12 and abs(ball.x[-1, 2] - 0.1) < 1e-12


@pytest.mark.parametrize("dt", [4e-3, 2e-3])
def test_restitution_one_returns_to_the_drop_height(dt):
    # Elastic, frictionless, flat: each bounce reverses v at the end of the step in which the box
    # would cross the floor, i.e. up to v_impact dt above it, so the flight is time-reversed
    # exactly: the apex is h0 to rounding, and the bounce comes early by at most dt per crossing.
    h0, body = 0.3, rb.RigidBody.box(2.0, (0.4, 0.3, 0.2))
    T = np.sqrt(2 * h0 / G)                                     # time to fall h0
    traj = drop(body, 0.1 + h0, t_end=4.5 * T, dt=dt, restitution=1.0, friction=0.0)
    z, vz = traj.x[:, 2] - 0.1, traj.velocity()[:, 2]
    assert np.ptp(traj.total_energy()) < 1e-12 * traj.total_energy()[0]
    bounces = np.flatnonzero((vz[:-1] < 0) & (vz[1:] > 0)) + 1
    assert len(bounces) == 2
    assert np.all(z[bounces] >= -1e-12) and np.all(z[bounces] <= np.sqrt(2 * G * h0) * dt)
    assert abs(z[bounces[0]:bounces[1]].max() - h0) < 1e-9 and abs(z[bounces[1]:].max() - h0) < 1e-9
    early = np.array([T, 3 * T]) - traj.t[bounces]
    assert np.all(early >= 0) and np.all(early <= np.array([1, 3]) * dt)


def test_restitution_one_timing_error_shrinks_with_dt():
    h0, body = 0.3, rb.RigidBody.box(2.0, (0.4, 0.3, 0.2))
    T = np.sqrt(2 * h0 / G)
    errors = []
    for dt in (4e-3, 1e-3):
        vz = drop(body, 0.1 + h0, t_end=1.2 * T, dt=dt, restitution=1.0, friction=0.0).velocity()[:, 2]
        errors.append(T - dt * (np.argmax(vz > 0)))
    assert errors[1] < 0.5 * errors[0]


def test_elastic_impacts_with_friction_never_create_energy():
    # Newton's restitution with friction can create energy (Kane's paradox); contact never does
    for R in (rotation_about([1, 2, 0.5], 0.7), rotation_about([1, 0, 0], 0.5)):
        traj = drop(BOX, 0.4, R, v=(0.5, 0, 0), omega=(0, 3, 0), t_end=0.5, restitution=1.0, friction=0.8)
        E, vz = traj.total_energy(), traj.velocity()[:, 2]
        assert np.diff(vz).max() > 1.0                              # it hit the ground ...
        assert np.diff(E).max() <= 1e-9 * E[0] and lowest_corner(traj).min() >= -1e-9   # ... creating nothing


@pytest.mark.parametrize("dt", [4e-3, 2e-3])
def test_sphere_bounces_to_e_squared_h(dt):
    # the ball reverses at a gap g in [0, v dt] above the floor with e times its speed there:
    # apex = g + e² (h0 − g) exactly, so 0 <= apex − e² h0 <= (1 − e²) v dt
    e, h0 = 0.6, 1.0
    traj = drop(BALL, 0.1 + h0, t_end=0.75, dt=dt, restitution=e, friction=0.5)
    z, vz = traj.x[:, 2] - 0.1, traj.velocity()[:, 2]
    hit = np.argmax(vz > 0)
    error = z[hit:].max() - e * e * h0
    assert -1e-12 <= error <= (1 - e * e) * np.sqrt(2 * G * h0) * dt
    assert z.min() >= -1e-12


# --- friction -----------------------------------------------------------------------------------

def test_sliding_box_stops_after_v0_squared_over_2_mu_g():
    v0, mu = 2.0, 0.4
    exact = v0**2 / (2 * mu * G)
    errors = []
    for dt in (4e-3, 2e-3):
        traj = drop(BOX, 0.05, v=(v0, 0, 0), t_end=0.7, dt=dt, friction=mu)
        vx = traj.velocity()[:, 0]
        stop = np.argmax(vx < 1e-9)
        assert abs(traj.t[stop] - v0 / (mu * G)) <= dt         # decelerates at μ g ...
        np.testing.assert_allclose(vx[:stop], v0 - mu * G * traj.t[:stop], atol=1e-9)
        after = traj.x[stop:]                                   # ... and stays stopped
        assert np.abs(after - after[0]).max() < 1e-9 and np.abs(traj.velocity()[stop:]).max() < 1e-9
        assert np.abs(traj.x[:, 1:] - [0, 0.05]).max() < 1e-9   # straight, flat: no yaw, no tipping
        assert rb.rotation_angle(np.eye(3), traj.R).max() < 1e-9
        errors.append(traj.x[-1, 0] - exact)
        assert 0 <= errors[-1] <= v0 * dt                       # the step's error: x moves with v before friction
    assert errors[1] < 0.6 * errors[0]


def test_spinning_sphere_starts_rolling():
    # slips with v = μ g t until v = ω r; then rolls at v = (2/7) ω0 r (angular momentum about the contact point)
    w0, mu, r, dt = 20.0, 0.3, 0.1, 2e-3
    traj = drop(BALL, r, omega=(0, w0, 0), t_end=0.4, dt=dt, friction=mu)
    v, w = traj.velocity(), traj.angular_velocity()
    slip = v[:, 0] - w[:, 1] * r                                # velocity of the contact point, x
    t_roll = 2 * w0 * r / (7 * mu * G)
    rolling = traj.t >= t_roll + dt
    np.testing.assert_allclose(v[rolling, 0], 2 / 7 * w0 * r, rtol=1e-12)
    assert np.abs(slip[rolling]).max() < 1e-12
    np.testing.assert_allclose(v[traj.t < t_roll - dt, 0], mu * G * traj.t[traj.t < t_roll - dt], atol=1e-12)
    assert np.abs(traj.x[:, 2] - r).max() < 1e-12


# --- other shapes, many bodies ---------------------------------------------------------------------

def test_cylinder_falls_over_and_rolls_without_sinking():
    cyl = rb.RigidBody.cylinder(1.0, 0.1, 0.3)
    traj = drop(cyl, 0.25, rotation_about([1, 0, 0], 1.2), v=(0.5, 0, 0), t_end=0.7, dt=2.5e-3,
                restitution=0.3, friction=0.5)
    az = traj.R[:, 2, 2]                                        # z of the axis
    lowest = traj.x[:, 2] - 0.15 * np.abs(az) - 0.1 * np.sqrt(np.clip(1 - az**2, 0, 1))
    assert lowest.min() >= -1e-9
    assert np.diff(traj.total_energy()).max() <= 1e-9 * traj.total_energy()[0]
    assert abs(az[-1]) < 1e-6 and abs(traj.x[-1, 2] - 0.1) < 1e-9   # lying on its side ...
    v, w = traj.velocity()[-1], traj.angular_velocity()[-1]
    assert np.linalg.norm(v - np.cross(w, [0, 0, 0.1])) < 1e-9     # ... rolling without slipping


def _scene_of(rng, n):
    bodies, states = [], []
    for i in range(n):
        kind = i % 3
        body = (rb.RigidBody.box(rng.uniform(0.5, 2), rng.uniform(0.05, 0.4, 3)) if kind == 0 else
                rb.RigidBody.sphere(rng.uniform(0.5, 2), rng.uniform(0.05, 0.2)) if kind == 1 else
                rb.RigidBody.cylinder(rng.uniform(0.5, 2), rng.uniform(0.05, 0.2), rng.uniform(0.1, 0.4)))
        z = 1.8 * body.half_extents().max() + rng.uniform(0, 0.3)
        states.append(rb.State.from_velocities(body, [rng.normal(), rng.normal(), z],
                                               rotation_about(rng.normal(size=3), rng.uniform(0, 1)),
                                               0.5 * rng.normal(size=3), 2 * rng.normal(size=3)))
        bodies.append(body)
    return bodies, states


def test_one_resolve_call_for_many_bodies_equals_one_call_per_body():
    rng = np.random.default_rng(7)
    bodies, states = _scene_of(rng, 50)
    ground = rb.Ground(0.0, 0.4, 0.6)
    scene = rb.Scene(bodies, [rb.Gravity(), ground])
    X = rb.State.stack([s.replace(x=s.x * [1, 1, 0] + [0, 0, rng.uniform(0.5, 1) * b.half_extents().min()])
                        for s, b in zip(states, bodies)])     # all of them touching, most penetrating
    Y = ground.resolve(scene, X, slice(None), 1e-3)
    touched = 0
    for i, b in enumerate(bodies):
        Xi = rb.State.unchecked(*(a[i:i + 1] for a in (X.x, X.R, X.P, X.L)))
        Yi = ground.resolve(rb.Scene(b, [rb.Gravity(), ground]), Xi, slice(None), 1e-3)
        for a, c in zip((Y.x, Y.R, Y.P, Y.L), (Yi.x, Yi.R, Yi.P, Yi.L)):
            np.testing.assert_allclose(a[i], c[0], rtol=1e-10, atol=1e-12)
        touched += not (np.array_equal(Y.x[i], X.x[i]) and np.array_equal(Y.P[i], X.P[i]))
    assert touched == 50


def test_many_bodies_in_one_scene_behave_as_alone():
    rng = np.random.default_rng(3)
    bodies, states = _scene_of(rng, 50)
    ground = rb.Ground(0.0, 0.4, 0.6)
    dt, t_end = 2.5e-3, 0.5
    scene = rb.Scene(bodies, [rb.Gravity(), ground])
    sys = scene.compile().system
    assert sys.contact_body.tolist() == list(range(50)) and len(sys.grounds) == 1   # all bodies, one ground
    traj = rb.simulate(scene, rb.State.stack(states), t_end, dt)
    assert np.all(np.diff(traj.velocity()[..., 2], axis=0).max(axis=0) > 0)   # each one hit the ground
    for i in (0, 1, 2, 33):
        alone = rb.simulate(rb.Scene(bodies[i], [rb.Gravity(), ground]), states[i], t_end, dt)
        for a, b in ((traj.x, alone.x), (traj.R, alone.R), (traj.P, alone.P), (traj.L, alone.L)):
            np.testing.assert_allclose(a[:, i], b, rtol=0, atol=1e-9)
    boxes = [i for i in range(50) if bodies[i].shape == "box"]
    assert min(lowest_corner(traj, bodies[i], i).min() for i in boxes) >= -1e-9
    E = traj.total_energy()
    assert np.all(np.diff(E, axis=0) <= 1e-9 * E[0])


# --- the mode systems' solve: A⁺ b without an SVD where A's rank is that of the body ---------

def _mode_system(rng, corners, kept):
    """B = D G (p, 6) and C = H E (6, p) of a tilted box's corners (indices in SIGNS; 0, 2, 4, 6: the
    bottom face, 0, 4: an edge of it): kept "stick" (3 equations each) or "slide" (the normal)."""
    from rbcourse.rotation import star
    R = rotation_about(rng.normal(size=3), 0.3)
    rho, I_inv = (SIGNS[corners] * BOX.half_extents()) @ R.T, R @ BOX.I_body_inv @ R.T
    G = np.concatenate([np.broadcast_to(np.eye(3), (len(corners), 3, 3)), -star(rho)], axis=-1)
    H = np.concatenate([np.broadcast_to(np.eye(3), (len(corners), 3, 3)) / BOX.mass, I_inv @ star(rho)], axis=-2)
    if kept == "stick":
        return G.reshape(-1, 6)[None], np.concatenate(list(H), axis=1)[None]
    return G[:, 2][None], H[..., 2].T[None]


def _solve(B, C, b):
    """The engine's mode solve (engine/least_norm.py min_norm_solve, re-exported by engine/contact.py) of B C y = b:
    (y, how it was solved)."""
    from rbcourse.engine import contact as solver
    p = B.shape[0]
    w = solver.work(1)
    w.B[:p], w.C[:, :p], w.b[:p] = B, C, b
    how = solver.min_norm_solve(w, p)
    return w.y[:p].copy(), how


@pytest.mark.parametrize("corners, kept, rank, direct", [
    ([0, 2, 4, 6], "stick", 6, True), (range(8), "stick", 6, True), ([0, 2, 4], "stick", 6, True),  # face, box, 3
    ([0, 2, 4, 6], "slide", 3, True), (range(8), "slide", 3, True),           # frictionless, the lift
    ([0, 4], "stick", 5, False), ([0], "stick", 3, False), ([0, 4], "slide", 2, False)])  # edge, corner: SVD
def test_the_mode_solve_is_the_least_norm_least_squares_solution(corners, kept, rank, direct):
    from rbcourse.engine.contact import DIRECT, SVD
    rng = np.random.default_rng(len(corners))
    B, C = _mode_system(rng, list(corners), kept)
    assert np.linalg.matrix_rank(B @ C) == rank                  # singular as soon as more than 6 equations
    for b in rng.normal(size=(2, B.shape[1])):                 # not in A's range: least squares
        y_ref = np.linalg.pinv(B[0] @ C[0], rcond=1e-9) @ b
        y, how = _solve(B[0], C[0], b)
        assert how == (DIRECT if direct else SVD)                # two 6×6 solves where A's rank is the body's
        np.testing.assert_allclose(y, y_ref, rtol=1e-10, atol=1e-12 * np.abs(y_ref).max())


@pytest.mark.parametrize("corners, kept, direct", [
    ([0, 2, 4, 6], "stick", True), (range(8), "stick", True), ([0, 2, 4], "stick", True),
    ([0, 2, 4, 6], "slide", True), (range(8), "slide", True),
    ([0, 4], "stick", False), ([0], "stick", False), ([0, 4], "slide", False)])
def test_the_symmetric_mode_solve_is_the_same_least_norm_solution(corners, kept, direct):
    """Sticking points, or frictionless ones (the lift), push along their own kept velocities: C = 𝓜⁻¹ Bᵀ, and
    symmetric_solve gives A⁺ b from one Gram matrix (to rounding, what min_norm_solve gives from two), or says
    SVD (nothing solved) where B's used columns are dependent (an edge, a corner)."""
    from rbcourse.engine import contact as solver
    from rbcourse.engine.contact import DIRECT, SVD
    rng = np.random.default_rng(7 + len(corners))
    R = rotation_about(np.random.default_rng(7 + len(corners)).normal(size=3), 0.3)    # _mode_system's tilt
    I_inv = R @ BOX.I_body_inv @ R.T
    B, C = _mode_system(rng, list(corners), kept)
    p = B.shape[1]
    for b in rng.normal(size=(2, p)):
        w = solver.work(1)
        w.B[:p], w.b[:p] = B[0], b
        w.C[:] = np.nan                                              # not read
        how = solver.symmetric_solve(w, p, BOX.mass, tuple(map(tuple, I_inv)))
        assert how == (DIRECT if direct else SVD)
        if direct:
            y_ref = np.linalg.pinv(B[0] @ C[0], rcond=1e-9) @ b
            np.testing.assert_allclose(w.y[:p], y_ref, rtol=1e-10, atol=1e-12 * np.abs(y_ref).max())


def test_the_symmetric_solve_tests_conditioning_as_the_padded_gram_matrix_says():
    """symmetric_solve tests G = P Bᵀ B Pᵀ through its 3×3 Schur complement (engine/symmetric.py: schur): it must solve
    directly exactly where the padded 6×6 (the unused places hold the trace) has λ_min > GRAM_RCOND |G|_F —
    checked by numpy's eigenvalues on random sets of 1 to 8 contact points, kept sticking or frictionless,
    every one on a line but one, which is off it by 1e-7 … 1 of the line's length: many of them within a factor
    5 of the threshold (but none at it, where rounding may decide either way)."""
    from rbcourse.engine import contact as solver
    from rbcourse.engine.contact import DIRECT, SVD
    from rbcourse.engine.least_norm import GRAM_RCOND
    from rbcourse.rotation import star
    rng = np.random.default_rng(11)
    seen, near = {DIRECT: 0, SVD: 0}, 0
    for trial in range(600):
        k = int(rng.integers(1, 9))
        a, d = rng.normal(size=3) * 0.1, rng.normal(size=3)
        rho = a + rng.uniform(-0.2, 0.2, (k, 1)) * d / np.linalg.norm(d)       # on a line …
        rho[0] += 10.0 ** rng.uniform(-7.0, 0.0) * 0.4 * rng.normal(size=3)   # … but one point
        G_k = np.concatenate([np.broadcast_to(np.eye(3), (k, 3, 3)), -star(rho)], axis=-1)
        B = G_k.reshape(-1, 6) if trial % 2 else G_k[:, 2]
        p = B.shape[0]
        used = np.any(B != 0.0, axis=0)
        G = B.T @ B
        G[~used] = 0.0
        G[:, ~used] = 0.0
        G[~used, ~used] = np.trace(G)
        ratio = np.linalg.eigvalsh(G)[0] / (GRAM_RCOND * np.linalg.norm(G))
        if abs(ratio - 1.0) < 1e-3:
            continue
        R = rotation_about(rng.normal(size=3), rng.uniform(0.0, 3.0))
        w = solver.work(1)
        w.B[:p], w.b[:p] = B, rng.normal(size=p)
        how = solver.symmetric_solve(w, p, BOX.mass, tuple(map(tuple, R @ BOX.I_body_inv @ R.T)))
        assert how == (DIRECT if ratio > 1.0 else SVD), (k, trial % 2, ratio)
        seen[how] += 1
        near += 0.2 < ratio < 5.0
    assert seen[DIRECT] > 50 and seen[SVD] > 50 and near > 20, (seen, near)


def test_the_mode_solve_of_a_blown_up_system_says_so_and_resolve_raises_linalgerror():
    from rbcourse.engine.contact import NOT_FINITE
    B, C = _mode_system(np.random.default_rng(0), [0, 2, 4, 6], "stick")
    assert _solve(B[0] * np.nan, C[0], np.ones(12))[1] == NOT_FINITE
    ground = rb.Ground()
    scene = rb.Scene(BOX, [rb.Gravity(), ground])
    X = rb.State.unchecked(np.array([[0, 0, 0.05]]), np.eye(3)[None], np.array([[0, 0, -np.inf]]), np.zeros((1, 3)))
    with pytest.raises(np.linalg.LinAlgError):                  # simulate turns it into a SimulationDiverged
        ground.resolve(scene, X, slice(None), 1e-3)


def test_a_run_as_python_solves_its_contacts_as_python(monkeypatch):
    """fast=False runs the engine's contact solver interpreted too (the driver passes its own module), to
    the same numbers as the compiled run."""
    from rbcourse.engine import contact as compiled
    box = rb.RigidBody.box(1.0, (0.2, 0.1, 0.05))
    scene = rb.Scene(box, [rb.Gravity(), rb.Ground(0.0, 0.3, 0.5)])
    X0 = rb.State.from_velocities(box, (0, 0, 0.1), rotation_about([1, 2, 0], 0.3), (0.3, 0, -1.0), (1.0, 2.0, 0))
    fast = rb.simulate(scene, X0, 0.2, 2e-3, "rk4")
    monkeypatch.setattr(compiled, "resolve", lambda *a: (_ for _ in ()).throw(AssertionError("compiled solver")))
    slow = rb.simulate(scene, X0, 0.2, 2e-3, "rk4", fast=False)
    assert "interpreted" in slow.implementation
    assert slow.x[:, 2].min() < 0.1 and np.diff(slow.P[:, 2]).max() > 0.05     # it hit the ground and bounced
    for a, c in ((fast.x, slow.x), (fast.R, slow.R), (fast.P, slow.P), (fast.L, slow.L)):
        np.testing.assert_allclose(a, c, rtol=1e-11, atol=1e-12)
