"""Starts the engine would simulate silently wrong are refused by simulate, with a ValueError naming the parameter
(issue 26, item 5; item 4's check): a body below a Ground (its lowest contact point: engine/contact_points.py's
lowest_gap), a Spring whose two ends coincide while its rest length is not zero, an Impulse outside [0, t_end],
a t_end / dt whose step count overflows."""
import math
import re
import time

import numpy as np
import pytest

import rbcourse as rb
from rbcourse.workbook import warmup
from rbcourse.engine import interpreted
from rbcourse.rotation import exp_so3, rotation_about
from rbcourse.scene import as_scene
from rbcourse.examples import EXAMPLES

CUBE = rb.RigidBody.box(1.0, (1.0, 1.0, 1.0))
BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
BALL = rb.RigidBody.sphere(1.0, 0.2)
CAN = rb.RigidBody.cylinder(1.0, 0.1, 0.4)                  # radius 0.1, height 0.4
SEMI = np.array([0.1, 0.2, 0.3])                            # a body with no shape: the ellipsoid of its inertia
EGG = rb.RigidBody(2.0, 2.0 / 5 * np.array([SEMI[1] ** 2 + SEMI[2] ** 2, SEMI[0] ** 2 + SEMI[2] ** 2,
                                             SEMI[0] ** 2 + SEMI[1] ** 2]))
CORNER_DOWN = exp_so3(np.cross([-1.0, -1.0, -1.0], [0.0, 0.0, -1.0]) / math.sqrt(2.0)
                      * math.acos(1.0 / math.sqrt(3.0)))    # turns the corner (−, −, −) of a box straight down


def start(scene, X0, t_end=0.01, dt=0.005):
    """A short run of the scene from X0 as Python (no compile): what simulate says of the start."""
    return rb.simulate(scene, X0, t_end, dt, "euler", fast=False)


def on_ground(body, height=0.0, restitution=0.5):
    return rb.Scene(body, [rb.Gravity(), rb.Ground(height, restitution=restitution)])


# --- a body that starts inside the ground ---------------------------------------------------------------------

def test_a_box_half_a_metre_in_the_ground_is_refused_naming_X0_the_body_the_depth_and_the_height():
    with pytest.raises(ValueError) as err:
        start(on_ground(CUBE), rb.State.at_rest((0, 0, 0.0)))
    msg = str(err.value)
    assert msg.startswith("X0 puts body 0 0.5 m below the ground z = 0 (its lowest point at z = -0.5)"), msg
    assert "start every body on or above it" in msg


def test_the_ground_height_counts():
    with pytest.raises(ValueError, match=r"X0 puts body 0 0\.25 m below the ground z = 2 \(its lowest point at "
                                         r"z = 1\.75\)"):
        start(on_ground(CUBE, height=2.0), rb.State.at_rest((0, 0, 2.25)))
    start(on_ground(CUBE, height=2.0), rb.State.at_rest((0, 0, 2.5)))          # resting on it


def test_a_tilted_box_with_only_a_corner_in_the_ground_is_refused():
    R = CORNER_DOWN
    corners = np.array([[sx, sy, sz] for sx in (-0.5, 0.5) for sy in (-0.5, 0.5) for sz in (-0.5, 0.5)]) @ R.T
    z = 0.85                                                                 # the corner √3/2 = 0.866 below
    assert (z + corners[:, 2] < 0).sum() == 1                                # only one corner is under
    with pytest.raises(ValueError, match=r"X0 puts body 0 0\.0160254 m below the ground z = 0"):
        start(on_ground(CUBE), rb.State.at_rest((0, 0, z), R))
    start(on_ground(CUBE), rb.State.at_rest((0, 0, math.sqrt(3.0) / 2), R))   # on its corner: accepted


def test_a_sphere_a_cylinder_and_a_body_with_no_shape_are_checked_by_their_own_lowest_point():
    with pytest.raises(ValueError, match=r"X0 puts body 0 0\.1 m below"):
        start(on_ground(BALL), rb.State.at_rest((0, 0, 0.1)))
    start(on_ground(BALL), rb.State.at_rest((0, 0, 0.2)))
    with pytest.raises(ValueError, match=r"X0 puts body 0 0\.05 m below"):       # upright: the bottom rim, h/2 down
        start(on_ground(CAN), rb.State.at_rest((0, 0, 0.15)))
    side = rotation_about([1, 0, 0], math.pi / 2)
    start(on_ground(CAN), rb.State.at_rest((0, 0, 0.15), side))              # on its side: the radius, 0.1 down
    with pytest.raises(ValueError, match=r"X0 puts body 0 0\.05 m below"):       # upright: semi-axis c = 0.3 down
        start(on_ground(EGG), rb.State.at_rest((0, 0, 0.25)))
    start(on_ground(EGG), rb.State.at_rest((0, 0, 0.25), side))              # its z axis turned level: b = 0.2 down
    start(on_ground(EGG), rb.State.at_rest((0, 0, 0.3)))


def test_a_body_resting_on_the_ground_is_accepted_within_the_contact_tolerance():
    tol = interpreted.module("contact").CONTACT_TOL                         # 1e-6 m
    start(on_ground(BOX), rb.State.at_rest((0, 0, 0.025)))
    start(on_ground(BOX), rb.State.at_rest((0, 0, 0.025 - 0.5 * tol)))
    with pytest.raises(ValueError, match=r"X0 puts body 0 2e-06 m below the ground z = 0"):
        start(on_ground(BOX), rb.State.at_rest((0, 0, 0.025 - 2 * tol)))


# --- the tolerance is CONTACT_TOL at every height (issue 46) -----------------------------------------------------

def check(scene, X0):
    """What the start check says of X0 (no run: the far coordinates would need none)."""
    scene.check_start(X0, 1.0)


@pytest.mark.parametrize("height", [1e15, -1e15, 1e9, -1.0000001e8, 1e300])
def test_a_ground_beyond_1e8_m_is_refused_naming_height_and_the_range(height):
    """A body 1000 m below a Ground at 1e15 m was accepted (the tolerance was 1e-12 of the coordinates: 1000 m
    there, 2 mm at 1e9 m) and lifted in one step; float64 rounds a height near 1e15 m to 0.125 m."""
    from rbcourse.contact import MAX_HEIGHT
    assert MAX_HEIGHT == 1e8
    with pytest.raises(ValueError, match=r"^height must be a real number within ±1e\+08 m \(where the contact "
                                         r"tolerance, 1e-6 m, is resolved by float64\), got"):
        rb.Ground(height)
    rb.Ground(1e8), rb.Ground(-1e8)


@pytest.mark.parametrize("height", [1e8, -1e8, 3.3e7, 1e6, 12345.678])
def test_the_tolerance_is_one_micrometre_at_every_height(height):
    tol = interpreted.module("contact").CONTACT_TOL
    scene = on_ground(BOX, height=height)
    for depth in (1000.0, 1e-4, 3 * tol, 1.2 * tol):                       # 1e-4 m: accepted at 1e8 m before
        with pytest.raises(ValueError) as err:
            check(scene, rb.State.at_rest((0, 0, height + 0.025 - depth)))
        said = re.match(rf"X0 puts body 0 (\S+) m below the ground z = {re.escape(f'{height:g}')} ", str(err.value))
        assert said and abs(float(said.group(1)) - depth) < 1e-7, str(err.value)    # the depth, to rounding
    for depth in (0.0, 0.8 * tol, 0.5 * tol, -1e-3):                        # on it, within CONTACT_TOL, above
        check(scene, rb.State.at_rest((0, 0, height + 0.025 - depth)))
    R = CORNER_DOWN                                                         # on a corner, √3/2 above the centre
    check(on_ground(CUBE, height=height), rb.State.at_rest((0, 0, height + math.sqrt(3.0) / 2), R))
    with pytest.raises(ValueError, match=r"X0 puts body 0 2\.\d*e-06 m below"):
        check(on_ground(CUBE, height=height), rb.State.at_rest((0, 0, height + math.sqrt(3.0) / 2 - 2.5 * tol), R))


def test_far_coordinates_are_refused_as_below_or_as_out_of_reach_of_the_tolerance_never_accepted_unchecked():
    """On a Ground at 0: a body at z = −1e15 m is 1e15 m below; one at +1e15 m is far above (accepted); a sphere
    of radius 1e9 m resting on it cannot be placed to 1e-6 m by float64 (its lowest point to ±4e-6 m): refused,
    naming X0 and the range — as is one a metre lower, surely below."""
    check(on_ground(CUBE), rb.State.at_rest((0, 0, 1e15)))
    with pytest.raises(ValueError, match=r"X0 puts body 0 1e\+15 m below the ground z = 0"):
        check(on_ground(CUBE), rb.State.at_rest((0, 0, -1e15)))
    huge = rb.RigidBody.sphere(1.0, 1e9)
    with pytest.raises(ValueError, match=r"X0 puts body 0 \(at z = 1e\+09 m, of size \|half\| = 1\.73e\+09 m\) "
                                         r"within .* of the ground z = 0, where float64 places its lowest point to "
                                         r"±.* m only: .*\|z\| \+ \|height\| \+ 16 \|half\| within 4\.5e\+08 m"):
        check(on_ground(huge), rb.State.at_rest((0, 0, 1e9)))
    with pytest.raises(ValueError, match=r"X0 puts body 0 1 m below the ground z = 0"):
        check(on_ground(huge), rb.State.at_rest((0, 0, 1e9 - 1.0)))
    check(on_ground(huge), rb.State.at_rest((0, 0, 1e9 + 1.0)))                 # 1 m above: surely above


def test_only_the_bodies_a_ground_acts_on_are_checked():
    X0 = rb.State.stack([rb.State.at_rest((0, 0, 1.0)), rb.State.at_rest((2, 0, -3.0))])
    start(rb.Scene([CUBE, CUBE], [rb.Ground(body=0)]), X0)                   # body 1 is not on this ground
    with pytest.raises(ValueError, match=r"X0 puts body 1 3\.5 m below the ground z = 0"):
        start(rb.Scene([CUBE, CUBE], [rb.Ground(body=1)]), X0)
    with pytest.raises(ValueError, match=r"X0 puts body 1 "):
        start(rb.Scene([CUBE, CUBE], [rb.Ground()]), X0)


def test_the_lowest_point_is_the_solvers_own_and_exact_for_every_shape():
    """lowest_gap (engine/contact_points.py) against each shape's lowest point written another way, on random
    orientations: a box z − Σ_j |R_zj| h_j, a cylinder z − (r √(1 − a_z²) + h/2 |a_z|), an ellipsoid
    z − |A Qᵀ e_z| (Q = R axes, A = diag(semi-axes))."""
    lowest_gap = interpreted.module("contact_points").lowest_gap
    rng = np.random.default_rng(7)
    ellipsoid_axes = EGG.principal_axes
    half = EGG.half_extents()
    np.testing.assert_allclose(np.sort(half), SEMI, rtol=1e-12)
    for _ in range(50):
        R = exp_so3(rng.normal(size=3) * 2.0)
        z, h = rng.normal(), rng.normal()
        box = np.array([0.15, 0.1, 0.025])
        want = z - np.abs(R[2]) @ box - h
        assert abs(lowest_gap(0, R.tolist(), box.tolist(), np.zeros((3, 3)).tolist(), z, h) - want) < 1e-12
        a_z = R[2, 2]
        want = z - (0.1 * math.sqrt(max(1.0 - a_z * a_z, 0.0)) + 0.2 * abs(a_z)) - h
        assert abs(lowest_gap(1, R.tolist(), [0.1, 0.1, 0.2], np.zeros((3, 3)).tolist(), z, h) - want) < 1e-12
        Q = R @ ellipsoid_axes
        want = z - np.linalg.norm(half * Q[2]) - h
        assert abs(lowest_gap(2, R.tolist(), half.tolist(), ellipsoid_axes.tolist(), z, h) - want) < 1e-12


def test_ten_thousand_boxes_are_checked_well_under_a_second_and_the_one_below_is_named():
    n = 10_000
    rng = np.random.default_rng(1)
    sizes = rng.uniform(0.05, 0.3, (n, 3))
    bodies = rb.RigidBody.boxes(np.ones(n), sizes)
    R = exp_so3(rng.normal(size=(n, 3)))
    x = np.zeros((n, 3))
    x[:, 2] = np.einsum("nj,nj->n", np.abs(R[:, 2]), sizes / 2)          # every box on one of its corners
    still = np.zeros((n, 3))
    rb.Scene(bodies, [rb.Gravity(), rb.Ground()]).check_start(rb.State(x, R, still, still), 1.0)
    x[-1, 2] -= 0.01                                                         # the last one 1 cm in
    scene = rb.Scene(bodies, [rb.Gravity(), rb.Ground()])
    X0 = rb.State(x, R, still, still)
    t = time.perf_counter()
    with pytest.raises(ValueError, match=rf"X0 puts body {n - 1} 0\.01 m below the ground z = 0"):
        scene.check_start(X0, 1.0)
    took = time.perf_counter() - t
    assert took < 1.0, f"checking 10⁴ boxes on the ground took {took:.2f} s"


# --- a Spring whose two ends coincide ---------------------------------------------------------------------------

def test_a_spring_with_both_ends_at_one_point_and_a_rest_length_is_refused_naming_X0_it_and_its_rest_length():
    spring = rb.Spring((0, 0, 0.5), (0, 0, 1.5), stiffness=10.0, rest_length=0.5)
    with pytest.raises(ValueError) as err:
        start(rb.Scene(BOX, [spring]), rb.State.at_rest((0, 0, 1.0)))
    msg = str(err.value)
    assert msg.startswith(f"X0 puts both ends of {spring!r} (on body 0) at the same point [0.0, 0.0, 1.5] "
                          "while its rest_length is 0.5 m: its direction is undefined"), msg
    assert "start with the ends apart (or rest_length=0)" in msg


def test_a_spring_with_its_ends_apart_or_no_rest_length_is_accepted():
    start(rb.Scene(BOX, [rb.Spring((0, 0, 0.5), (0, 0, 1.5), rest_length=0.5)]), rb.State.at_rest((0, 0, 0.9)))
    start(rb.Scene(BOX, [rb.Spring((0, 0, 0.5), (0, 0, 1.5), rest_length=0.0)]), rb.State.at_rest((0, 0, 1.0)))


def test_the_ends_turn_with_the_body_and_a_two_body_spring_is_checked_on_both_bodies():
    turned = rotation_about([0, 0, 1], math.pi / 2)                          # body y → world −x
    spring = rb.Spring((0, -0.5, 0), rest_length=1.0, body=0, other_body=1, other_point=(-0.5, 0, 0))
    X0 = rb.State.stack([rb.State.at_rest((0, 0, 0), turned), rb.State.at_rest((1, 0, 0))])
    with pytest.raises(ValueError, match=r"X0 puts both ends of Spring\(.*\) \(on body 0\) at the same point "
                                         r"\[0\.5, .*\] while its rest_length is 1 m"):
        start(rb.Scene([BOX, BOX], [spring]), X0)
    apart = rb.State.stack([rb.State.at_rest((0, 0, 0)), rb.State.at_rest((1, 0, 0))])   # R = I: b at (0, −0.5, 0)
    start(rb.Scene([BOX, BOX], [spring]), apart)


def test_a_spring_on_every_body_names_the_body_whose_ends_coincide():
    spring = rb.Spring((0, 0, 0.5), (3, 0, 1.5), rest_length=0.2)
    X0 = rb.State.stack([rb.State.at_rest((0, 0, 1.0)), rb.State.at_rest((3, 0, 1.0))])
    with pytest.raises(ValueError, match=r"\(on body 1\) at the same point \[3\.0, 0\.0, 1\.5\]"):
        start(rb.Scene([BOX, BOX], [spring]), X0)


def test_a_pivoted_bodys_spring_ends_are_taken_from_its_centre_of_mass():
    pivot = rb.Pivot((0, 0, 0.5), (0, 0, 0))                                  # the centre of mass hangs at z = −0.5
    spring = rb.Spring((0, 0, -0.5), (0, 0, -1.0), rest_length=0.3)
    X0 = pivot.state(BOX, np.eye(3), np.zeros(3))
    with pytest.raises(ValueError, match=r"X0 puts both ends of Spring\(.*\) \(on body 0\) at the same point "
                                         r"\[0\.0, 0\.0, -1\.0\]"):
        start(rb.Scene(BOX, [pivot, spring]), X0)
    start(rb.Scene(BOX, [pivot, rb.Spring((0, 0, -0.5), (0, 0, -1.1), rest_length=0.3)]), X0)


# --- impulses outside the run -----------------------------------------------------------------------------------

def test_an_impulse_after_t_end_is_refused_naming_impulse_time_its_value_and_the_range():
    kick = rb.Impulse((0, 0, 0), (0, 0, 1.0), time=2.5)
    with pytest.raises(ValueError) as err:
        start(rb.Scene(BOX, [kick]), rb.State.at_rest(), t_end=2.0, dt=0.5)
    msg = str(err.value)
    assert msg.startswith(f"Impulse.time (t) must be in [0, t_end] = [0, 2] s (the run), got 2.5 for {kick!r}"), msg


def test_an_impulse_at_zero_or_at_t_end_is_accepted():
    for t in (0.0, 0.01, 0.005):
        start(rb.Scene(BOX, [rb.Impulse((0, 0, 0), (0, 0, 1.0), time=t)]), rb.State.at_rest(), t_end=0.01)


def test_a_negative_impulse_time_is_refused_when_the_impulse_is_built():
    with pytest.raises(ValueError, match=r"time must be >= 0"):
        rb.Impulse((0, 0, 0), (0, 0, 1.0), time=-0.1)


# --- what the package itself runs starts validly ---------------------------------------------------------------

@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_every_named_example_starts_validly(name):
    ex = EXAMPLES[name]()
    ex.scene.check_start(ex.X0, ex.t_end)


def test_every_warmup_scene_starts_validly():
    """`python -m rbcourse compile` runs these (warmup.py): the box on the ground rests on it."""
    for name, scene, X0 in warmup.scenes():
        as_scene(scene).check_start(X0, warmup.STEPS * warmup.DT)


# --- step counts that overflow (item 5: the API; the CLI's are in test_cli.py) ---------------------------------

@pytest.mark.parametrize("t_end, dt", [(1e308, 1e-300), (1.0, 5e-324), (1e308, 5e-324), (1e10, 1e-1)])
def test_a_step_count_beyond_1e9_or_infinite_is_refused_naming_t_end_and_dt(t_end, dt):
    with pytest.raises(ValueError) as err:
        rb.simulate(BOX, rb.State.at_rest(), t_end, dt)
    msg = str(err.value)
    assert msg.startswith(f"dt must give at most 1e9 steps over t_end = {t_end:g}, got dt = {dt:g}"), msg


@pytest.mark.parametrize("name, t_end, dt", [("t_end", math.inf, 0.1), ("t_end", math.nan, 0.1),
                                             ("dt", 1.0, math.inf), ("dt", 1.0, math.nan)])
def test_an_infinite_t_end_or_dt_is_refused_by_its_name(name, t_end, dt):
    with pytest.raises(ValueError, match=rf"^{name} must be finite, got"):
        rb.simulate(BOX, rb.State.at_rest(), t_end, dt)
