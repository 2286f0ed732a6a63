"""Every bad input gives a ValueError that names the parameter (issue 11, item 6), and what is
documented as accepted is accepted.

The rules (rbcourse/support/checks.py): a real number is an int or a float (numpy scalars too), never a
bool, a string, a complex number or None; an array of numbers has an int or float dtype (lists of
ints/floats, numpy arrays of any int/float dtype), never strings, bools, complex numbers or
objects; a body index is an int, a body selection None, an index, a RigidBody or a non-empty list
of distinct indices in range (``body=[]`` is refused: an effect on no body is no effect).
"""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.viz import viewer
from rbcourse.support import checks
from rbcourse.methods.adaptive import ATOL_RANGE, RTOL_RANGE

NAN = float("nan")
TINY = np.finfo(float).tiny
SPH = rb.RigidBody.sphere(1.0, 0.5)
BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
X0 = rb.State.at_rest()
X2 = rb.State.stack([rb.State.at_rest(), rb.State.at_rest(x=(1.0, 0.0, 0.0))])
SPIN = rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), np.zeros(3), [0.01, 5.0, 0.01])
TRAJ = rb.simulate(SPH, X0, 0.1, 0.01, "rk4")


def state(**kw):
    fields = dict(x=np.zeros(3), R=np.eye(3), P=np.zeros(3), L=np.zeros(3))
    fields.update(kw)
    return rb.State(**fields)


def two_bodies(*effects):
    return rb.Scene([SPH, BOX], list(effects))


def push(force, method="euler", fast=True):
    """A run with a force function: the float kernel (euler, fast) or numpy (fast=False, rk4)."""
    scene = rb.Scene(BOX, [rb.PointForce((0.15, 0.1, 0.025), force)])
    return rb.simulate(scene, X0, 0.05, 0.01, method, fast=fast)


BAD = {
    # --- RigidBody: mass, inertia (numbers only; normal floats with finite inverses) --------
    "mass str": (lambda: rb.RigidBody("1.0", [1, 1, 1]), "mass"),
    "mass bool": (lambda: rb.RigidBody(True, [1, 1, 1]), "mass"),
    "mass zero": (lambda: rb.RigidBody(0.0, [1, 1, 1]), "mass"),
    "mass nan": (lambda: rb.RigidBody(NAN, [1, 1, 1]), "mass"),
    "mass denormal": (lambda: rb.RigidBody(1e-320, [1, 1, 1]), "mass"),
    "mass whose inverse is denormal": (lambda: rb.RigidBody(1e308, [1, 1, 1]), "mass"),
    "inertia numeric strings": (lambda: rb.RigidBody(1, ["1", "1", "1"]), "inertia"),
    "inertia bools": (lambda: rb.RigidBody(1, [True, True, True]), "inertia"),
    "inertia complex": (lambda: rb.RigidBody(1, [1j, 1, 1]), "inertia"),
    "inertia with None": (lambda: rb.RigidBody(1, [None, 1, 1]), "inertia"),
    "inertia ragged": (lambda: rb.RigidBody(1, [[1, 0], [0, 1, 0]]), "inertia"),
    "inertia string": (lambda: rb.RigidBody(1, "123"), "inertia"),
    "inertia denormal moments": (lambda: rb.RigidBody(1, [1e-320] * 3), "inertia"),
    "inertia matrix whose inverse overflows": (lambda: rb.RigidBody(1, 1e-310 * np.eye(3)), "inertia"),
    "inertia huge (eigh overflowed)": (lambda: rb.RigidBody(1, [1e308] * 3), "inertia"),
    "inertia not positive": (lambda: rb.RigidBody(1, [-1, 1, 1]), "inertia"),
    "inertia not symmetric": (lambda: rb.RigidBody(1, [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "inertia"),
    "inertia triangle inequality": (lambda: rb.RigidBody(1, [1, 1, 3]), "inertia"),
    # --- RigidBody: shape and size -----------------------------------------------------------
    "shape int": (lambda: rb.RigidBody(1, [1, 1, 1], shape=42), "shape"),
    "shape unknown name": (lambda: rb.RigidBody(1, [1, 1, 1], shape="cube"), "shape"),
    "shape list": (lambda: rb.RigidBody(1, [1, 1, 1], shape=["box"]), "shape"),
    "box without a size": (lambda: rb.RigidBody(1, [1, 1, 1], shape="box"), "size"),
    "box size NaN": (lambda: rb.RigidBody(1, [1, 1, 1], shape="box", size=[NAN, 1, 1]), "size"),
    "box size string": (lambda: rb.RigidBody(1, [1, 1, 1], shape="box", size="123"), "size"),
    "box size negative": (lambda: rb.RigidBody(1, [1, 1, 1], shape="box", size=[1, -1, 1]), "size"),
    "cylinder size of 1": (lambda: rb.RigidBody(1, [1, 1, 1], shape="cylinder", size=(1,)), "size"),
    "cylinder negative height": (lambda: rb.RigidBody(1, [1, 1, 1], shape="cylinder", size=(1, -1)), "size"),
    "sphere radius 0": (lambda: rb.RigidBody(1, [1, 1, 1], shape="sphere", size=(0,)), "size"),
    "sphere without a size": (lambda: rb.RigidBody(1, [1, 1, 1], shape="sphere"), "size"),
    "size for shape body": (lambda: rb.RigidBody(1, [1, 1, 1], size=(1, 2, 3)), "size"),
    "name int": (lambda: rb.RigidBody(1, [1, 1, 1], name=42), "name"),
    # --- factories ------------------------------------------------------------------------------
    "box(size='123')": (lambda: rb.RigidBody.box(1, "123"), "size"),
    "box(size=b'123')": (lambda: rb.RigidBody.box(1, b"123"), "size"),
    "box size bools": (lambda: rb.RigidBody.box(1, [True, True, True]), "size"),
    "box size numeric strings": (lambda: rb.RigidBody.box(1, ["1", "2", "3"]), "size"),
    "box size 2-D": (lambda: rb.RigidBody.box(1, [[1, 2, 3]]), "size"),
    "box size too small for floats": (lambda: rb.RigidBody.box(1, [1e-200] * 3), "size"),
    "box mass denormal": (lambda: rb.RigidBody.box(1e-320, (1, 1, 1)), "mass"),
    "box mass bool": (lambda: rb.RigidBody.box(True, (1, 1, 1)), "mass"),
    "cylinder radius str": (lambda: rb.RigidBody.cylinder(1, "1", 1), "radius"),
    "cylinder height str": (lambda: rb.RigidBody.cylinder(1, 1, "1"), "height"),
    "sphere radius bool": (lambda: rb.RigidBody.sphere(1, True), "radius"),
    "inertia_about string": (lambda: SPH.inertia_about("123"), "body_point"),
    # --- State -----------------------------------------------------------------------------------
    "x numeric strings": (lambda: state(x=["1", "2", "3"]), "x"),
    "x bools": (lambda: state(x=[True, False, True]), "x"),
    "x bool mixed with numbers": (lambda: state(x=[1.5, True, 0]), "x"),
    "x huge int": (lambda: state(x=[10**400, 0, 0]), "x"),
    "R bool matrix": (lambda: state(R=np.eye(3, dtype=bool)), "R"),
    "R not a rotation": (lambda: state(R=2 * np.eye(3)), "R"),
    "R reflection": (lambda: state(R=-np.eye(3)), "R"),
    "P complex": (lambda: state(P=np.zeros(3, dtype=complex)), "P"),
    "L object with None": (lambda: state(L=np.array([1, 2, None])), "L"),
    "x NaN": (lambda: state(x=[NAN, 0, 0]), "x"),
    "no bodies (N = 0)": (lambda: state(x=np.zeros((0, 3)), R=np.zeros((0, 3, 3)), P=np.zeros((0, 3)),
                                        L=np.zeros((0, 3))), "x"),
    "from_velocities v strings": (lambda: rb.State.from_velocities(SPH, np.zeros(3), np.eye(3), ["1", "2", "3"],
                                                                   np.zeros(3)), "v"),
    "from_velocities omega bools": (lambda: rb.State.from_velocities(SPH, np.zeros(3), np.eye(3), np.zeros(3),
                                                                     [True, False, False]), "omega"),
    "from_velocities body": (lambda: rb.State.from_velocities("box", np.zeros(3), np.eye(3), np.zeros(3),
                                                              np.zeros(3)), "body"),
    "at_rest x string": (lambda: rb.State.at_rest(x="123"), "x"),
    "replace with bools": (lambda: X0.replace(x=[True, False, True]), "x"),
    "stack of mixed shapes": (lambda: rb.State.stack([X0, X2]), "states"),
    "stack empty": (lambda: rb.State.stack([]), "states"),
    "stack of non-states": (lambda: rb.State.stack([1, 2]), "states"),
    "stack of one State": (lambda: rb.State.stack(X0), "states"),
    "body(1.5)": (lambda: X2.body(1.5), "i"),
    "body(5)": (lambda: X2.body(5), "i"),
    "body(True)": (lambda: X2.body(True), "i"),
    "body('0')": (lambda: X0.body("0"), "i"),
    "derived(X, body) swapped": (lambda: rb.derived(X0, SPH), "body"),
    "derived X": (lambda: rb.derived(SPH, "X"), "X"),
    "Pivot.state R bools": (lambda: rb.Pivot((0, 0, 1)).state(SPH, np.eye(3, dtype=bool), np.zeros(3)), "R"),
    # --- body selections ---------------------------------------------------------------------
    "body='0'": (lambda: rb.Scene(SPH, [rb.Gravity(body="0")]), "body"),
    "body=True (a bool is not index 1)": (lambda: two_bodies(rb.Gravity(body=True)), "body"),
    "body=[True]": (lambda: two_bodies(rb.Gravity(body=[True])), "body"),
    "body=[0.7] (was truncated to 0)": (lambda: two_bodies(rb.Gravity(body=[0.7])), "body"),
    "body=0.0": (lambda: two_bodies(rb.Gravity(body=0.0)), "body"),
    "body=[] (no body)": (lambda: two_bodies(rb.Gravity(body=[])), "body"),
    "body=[0, 0] repeated": (lambda: two_bodies(rb.Gravity(body=[0, 0])), "body"),
    "body=bool mask": (lambda: two_bodies(rb.Gravity(body=np.array([True, False]))), "body"),
    "body=[[0]]": (lambda: two_bodies(rb.Gravity(body=[[0]])), "body"),
    "body out of range": (lambda: two_bodies(rb.Gravity(body=2)), "body"),
    "body negative": (lambda: two_bodies(rb.Gravity(body=-1)), "body"),
    "body in a list out of range": (lambda: two_bodies(rb.PointForce((0, 0, 0), (0, 0, 1), body=[0, 5])), "body"),
    "body not of the scene": (lambda: two_bodies(rb.Gravity(body=rb.RigidBody.sphere(1, 1))), "body"),
    "Ground body='0'": (lambda: rb.Ground(body="0"), "body"),
    "Ground body=[]": (lambda: rb.Ground(body=[]), "body"),
    "Spring other_body=True": (lambda: rb.Spring((0, 0, 0), body=0, other_body=True), "other_body"),
    "Spring other_body='1'": (lambda: rb.Spring((0, 0, 0), body=0, other_body="1"), "other_body"),
    "Spring other_body=1.0": (lambda: rb.Spring((0, 0, 0), body=0, other_body=1.0), "other_body"),
    "Spring other_body out of range": (lambda: two_bodies(rb.Spring((0, 0, 0), body=0, other_body=5)), "other_body"),
    "Spring to itself": (lambda: two_bodies(rb.Spring((0, 0, 0), body=0, other_body=0)), "body"),
    "Spring from every body to one": (lambda: two_bodies(rb.Spring((0, 0, 0), other_body=1)), "body"),
    "Spring from two bodies to one": (lambda: two_bodies(rb.Spring((0, 0, 0), body=[0, 1], other_body=1)), "body"),
    # --- effects' parameters -----------------------------------------------------------------
    "g negative": (lambda: rb.Gravity(-1.0), "g"),
    "g NaN": (lambda: rb.Gravity(NAN), "g"),
    "g string": (lambda: rb.Gravity("9.81"), "g"),
    "g bool": (lambda: rb.Gravity(True), "g"),
    "stiffness negative": (lambda: rb.Spring((0, 0, 0), stiffness=-1), "stiffness"),
    "stiffness inf": (lambda: rb.Spring((0, 0, 0), stiffness=np.inf), "stiffness"),
    "damping NaN": (lambda: rb.Spring((0, 0, 0), damping=NAN), "damping"),
    "rest_length negative": (lambda: rb.Spring((0, 0, 0), rest_length=-0.1), "rest_length"),
    "world_point string": (lambda: rb.Spring((0, 0, 0), world_point="abc"), "world_point"),
    "body_point wrong shape": (lambda: rb.PointForce((0, 0), (0, 0, 1)), "body_point"),
    "body_point bools": (lambda: rb.PointForce([True, False, True], (0, 0, 1)), "body_point"),
    "force string": (lambda: rb.PointForce((0, 0, 0), "123"), "force"),
    "force complex": (lambda: rb.PointForce((0, 0, 0), (1j, 0, 0)), "force"),
    "frame 'World'": (lambda: rb.PointForce((0, 0, 0), (0, 0, 1), frame="World"), "frame"),
    "frame a list (unhashable)": (lambda: rb.PointForce((0, 0, 0), (0, 0, 1), frame=["world"]), "frame"),
    "coefficient string": (lambda: rb.LinearDrag("1"), "coefficient"),
    "coefficient negative": (lambda: rb.AngularDrag(-1), "coefficient"),
    "Impulse time NaN": (lambda: rb.Impulse((0, 0, 0), (0, 0, 1), NAN), "time"),
    "Impulse time string": (lambda: rb.Impulse((0, 0, 0), (0, 0, 1), "1"), "time"),
    "impulse bools": (lambda: rb.Impulse((0, 0, 0), [True, False, False], 1.0), "impulse"),
    "Pivot world_point complex": (lambda: rb.Pivot((0, 0, 0), (1j, 0, 0)), "world_point"),
    "restitution above 1": (lambda: rb.Ground(restitution=2), "restitution"),
    "friction negative": (lambda: rb.Ground(friction=-1), "friction"),
    "height string": (lambda: rb.Ground(height="0"), "height"),
    # --- force functions: the float kernel (euler) and numpy (rk4, fast=False) say the same ------
    "force(t) complex, kernel": (lambda: push(lambda t: (1j, 0, 0)), r"force\(t\) must return a finite 3-vector of real"),
    "force(t) complex, numpy": (lambda: push(lambda t: (1j, 0, 0), "euler", False), r"force\(t\) must return"),
    "force(t) complex, rk4": (lambda: push(lambda t: (1j, 0, 0), "rk4"), r"force\(t\) must return"),
    "force(t) strings, kernel": (lambda: push(lambda t: ("1", 0, 0)), r"force\(t\) must return"),
    "force(t) strings, rk4": (lambda: push(lambda t: ("1", 0, 0), "rk4"), r"force\(t\) must return"),
    "force(t) bools, kernel": (lambda: push(lambda t: (True, 0, 0)), r"force\(t\) must return"),
    "force(t) bools, numpy": (lambda: push(lambda t: (True, 0, 0), "euler", False), r"force\(t\) must return"),
    "force(t) an iterator, kernel": (lambda: push(lambda t: iter([1, 2, 3])), r"force\(t\) must return"),
    "force(t) a huge int, kernel": (lambda: push(lambda t: (10**400, 0, 0)), r"force\(t\) must return"),
    "force(t) None, kernel": (lambda: push(lambda t: None), r"force\(t\) must return"),
    "force(t) NaN later, kernel": (lambda: push(lambda t: (0, 0, NAN if t > 0.02 else 1.0)), r"force\(t\) must return"),
    # --- exact_free_body: times are real numbers ---------------------------------------------
    "t '0'": (lambda: rb.exact_free_body(SPH, X0, "0"), "t must"),
    "t numeric strings": (lambda: rb.exact_free_body(SPH, X0, ["0", "1"]), "t must"),
    "t bool": (lambda: rb.exact_free_body(SPH, X0, True), "t must"),
    "t bools": (lambda: rb.exact_free_body(SPH, X0, [True, False]), "t must"),
    "t complex": (lambda: rb.exact_free_body(SPH, X0, 1j), "t must"),
    "t None": (lambda: rb.exact_free_body(SPH, X0, None), "t must"),
    "t NaN": (lambda: rb.exact_free_body(SPH, X0, [0.0, NAN]), "t must"),
    "t 2-D": (lambda: rb.exact_free_body(SPH, X0, np.zeros((2, 2))), "t must"),
    "t huge int": (lambda: rb.exact_free_body(SPH, X0, 10**400), "t must"),
    "exact X0": (lambda: rb.exact_free_body(SPH, "X0", 0.0), "X0"),
    # --- simulate and the adaptive method's tolerances ----------------------------------------
    "rtol = atol = 1e-170, kernel": (lambda: rb.simulate(BOX, SPIN, 0.1, 0.1, "adaptive", rtol=1e-170, atol=1e-170),
                                     r"rtol must be in \[1e-14, 1\]"),
    "rtol = atol = 1e-170, numpy": (lambda: rb.simulate(BOX, SPIN, 0.1, 0.1, "adaptive", rtol=1e-170, atol=1e-170,
                                                        fast=False), "rtol must be in"),
    "rtol above 1": (lambda: rb.simulate(BOX, SPIN, 0.1, 0.1, "adaptive", rtol=10.0), "rtol must be in"),
    "rtol just below the range": (lambda: rb.simulate(BOX, SPIN, 0.1, 0.1, "adaptive", rtol=1e-15), "rtol must be in"),
    "atol 1e-170": (lambda: rb.simulate(BOX, SPIN, 0.1, 0.1, "adaptive", atol=1e-170), r"atol must be in \[1e-100, 1e\+100\]"),
    "atol 1e200": (lambda: rb.simulate(BOX, SPIN, 0.1, 0.1, "adaptive", atol=1e200), "atol must be in"),
    "rtol negative": (lambda: rb.simulate(BOX, SPIN, 0.1, 0.1, "adaptive", rtol=-1.0), "rtol"),
    "rtol string": (lambda: rb.simulate(BOX, SPIN, 0.1, 0.1, "adaptive", rtol="1e-6"), "rtol"),
    "configured(rtol='x')": (lambda: rb.METHODS["adaptive"].configured(rtol="x"), "rtol"),
    "configured(atol=0)": (lambda: rb.METHODS["adaptive"].configured(atol=0.0), "atol"),
    "dt zero": (lambda: rb.simulate(SPH, X0, 1.0, 0.0), "dt"),
    "dt negative": (lambda: rb.simulate(SPH, X0, 1.0, -0.1), "dt"),
    "dt NaN": (lambda: rb.simulate(SPH, X0, 1.0, NAN), "dt"),
    "dt string": (lambda: rb.simulate(SPH, X0, 1.0, "0.01"), "dt"),
    "dt bool": (lambda: rb.simulate(SPH, X0, 1.0, True), "dt"),
    "dt huge int": (lambda: rb.simulate(SPH, X0, 1.0, 10**400), "dt"),
    "t_end negative": (lambda: rb.simulate(SPH, X0, -1.0, 0.1), "t_end"),
    "t_end NaN": (lambda: rb.simulate(SPH, X0, NAN, 0.1), "t_end"),
    "record_every bool": (lambda: rb.simulate(SPH, X0, 0.1, 0.01, record_every=True), "record_every"),
    "method unknown": (lambda: rb.simulate(SPH, X0, 0.1, 0.01, "eulr"), "method"),
    # --- Scene ------------------------------------------------------------------------------------
    "bodies a string": (lambda: rb.Scene("abc"), "bodies"),
    "bodies numbers": (lambda: rb.Scene([1, 2]), "bodies"),
    "bodies empty": (lambda: rb.Scene([]), "bodies"),
    "effects a string": (lambda: rb.Scene(SPH, effects="abc"), "effects"),
    "effects numbers": (lambda: rb.Scene(SPH, effects=[1]), "effects"),
    # --- walkthrough ------------------------------------------------------------------------------
    "walkthrough forces not pairs": (lambda: rb.walkthrough(SPH, X0, [1], 0.01), "forces"),
    "walkthrough forces a triple": (lambda: rb.walkthrough(SPH, X0, [(1, 2, 3)], 0.01), "forces"),
    "walkthrough forces strings": (lambda: rb.walkthrough(SPH, X0, [("123", "456")], 0.01), "forces"),
    "walkthrough forces numeric strings": (lambda: rb.walkthrough(SPH, X0, [(("1", "2", "3"), (0, 0, 1))], 0.01),
                                           "forces"),
    "walkthrough forces bools": (lambda: rb.walkthrough(SPH, X0, [([True] * 3, (0, 0, 1))], 0.01), "forces"),
    "walkthrough forces None": (lambda: rb.walkthrough(SPH, X0, None, 0.01), "forces"),
    "walkthrough forces a dict": (lambda: rb.walkthrough(SPH, X0, {1: 2}, 0.01), "forces"),
    "walkthrough iterations=True": (lambda: rb.walkthrough(SPH, X0, [], 0.01, iterations=True), "iterations"),
    "walkthrough iterations=2.0": (lambda: rb.walkthrough(SPH, X0, [], 0.01, iterations=2.0), "iterations"),
    "walkthrough iterations=0": (lambda: rb.walkthrough(SPH, X0, [], 0.01, iterations=0), "iterations"),
    "walkthrough dt='0.01'": (lambda: rb.walkthrough(SPH, X0, [], "0.01"), "dt"),
    "walkthrough dt=0": (lambda: rb.walkthrough(SPH, X0, [], 0.0), "dt"),
    "walkthrough body a Scene": (lambda: rb.walkthrough(rb.Scene(SPH), X0, [], 0.01), "body"),
    "walkthrough X0 stacked": (lambda: rb.walkthrough(SPH, X2, [], 0.01), "X0"),
    "resultants x string": (lambda: rb.resultants("123", []), "x"),
    "resultants forces a string": (lambda: rb.resultants((0, 0, 0), "ab"), "forces"),
    # --- viewer -----------------------------------------------------------------------------------
    "draw_trajectory a string": (lambda: viewer.draw_trajectory("traj"), "traj"),
    "ghost a string": (lambda: viewer.draw_trajectory(TRAJ, ghost="x"), "ghost"),
    "ghost_offset a string": (lambda: viewer.draw_trajectory(TRAJ, ghost_offset="123"), "ghost_offset"),
    "ghost_offset NaN": (lambda: viewer.draw_trajectory(TRAJ, ghost_offset=(NAN, 0, 0)), "ghost_offset"),
    "ghost_offset bools": (lambda: viewer.draw_trajectory(TRAJ, ghost_offset=[True, False, False]), "ghost_offset"),
    "ghost_label int": (lambda: viewer.draw_trajectory(TRAJ, ghost_label=1), "ghost_label"),
    "trail bools": (lambda: viewer.draw_trajectory(TRAJ, trail=[True, True, True]), "trail"),
    "trail_body bool": (lambda: viewer.draw_trajectory(TRAJ, trail_body=True), "trail_body"),
    "speed string": (lambda: viewer.draw_trajectory(TRAJ, speed="1"), "speed"),
    "speed 1e-320 (frame count overflows)": (lambda: viewer.draw_trajectory(TRAJ, speed=1e-320), "speed"),
    "fps 0": (lambda: viewer.draw_trajectory(TRAJ, fps=0), "fps"),
    "max_frames 0": (lambda: viewer.draw_trajectory(TRAJ, max_frames=0), "max_frames"),
    "follow '0'": (lambda: viewer.draw_trajectory(TRAJ, follow="0"), "follow"),
    "loop 1": (lambda: viewer.draw_trajectory(TRAJ, loop=1), "loop"),
    "arrow_scales value string": (lambda: viewer.draw_trajectory(TRAJ, arrow_scales={"omega": "1"}), "arrow_scales"),
    "draw_state t string": (lambda: viewer.draw_state(SPH, X0, t="0"), "t"),
    "draw_state X": (lambda: viewer.draw_state(SPH, "X"), "X"),
    "Drawing.html title int": (lambda: viewer.draw_state(SPH, X0).html(title=1), "title"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input_gives_a_value_error_naming_the_parameter(name):
    call, match = BAD[name]
    with pytest.raises(ValueError, match=match):
        call()


# --- what is accepted ------------------------------------------------------------------------

def test_ints_and_numpy_numbers_are_accepted_as_floats():
    body = rb.RigidBody(mass=2, inertia=[1, 2, 3])
    assert type(body.mass) is float and body.mass == 2.0
    np.testing.assert_array_equal(body.principal_moments, [1.0, 2.0, 3.0])
    f32 = rb.RigidBody(np.float32(2.0), np.array([1, 2, 3], dtype=np.float32))
    assert f32.mass == 2.0 and f32.I_body.dtype == np.float64
    assert rb.RigidBody(np.int64(1), np.array([1, 1, 1], dtype=np.uint8)).mass == 1.0
    assert rb.RigidBody.box(1, np.array([1, 2, 3])).size == (1.0, 2.0, 3.0)
    assert rb.RigidBody.sphere(np.float32(1), np.float32(0.5)).size == (0.5,)
    X = rb.State(x=np.array([1, 2, 3], dtype=np.float32), R=np.eye(3, dtype=int), P=[0, 0, 0], L=(0, 0, 1))
    assert X.x.dtype == np.float64 and X.x.tolist() == [1.0, 2.0, 3.0] and X.L.tolist() == [0.0, 0.0, 1.0]
    traj = rb.simulate(SPH, X0, np.float32(0.1), np.float32(0.05), "rk4")
    assert len(traj.t) == 3
    assert len(rb.walkthrough(SPH, X0, (((0, 0, 0), (0, 0, 1)),), np.float64(0.01), iterations=np.int64(2))) == 2


def test_a_3x3_spd_inertia_is_accepted():
    Q = rb.rotation.rotation_about([1, 2, 3], 0.7)
    body = rb.RigidBody(2.0, Q @ np.diag([1.0, 2.0, 2.5]) @ Q.T)
    np.testing.assert_allclose(body.principal_moments, [1.0, 2.0, 2.5])
    np.testing.assert_allclose(body.I_body @ body.I_body_inv, np.eye(3), atol=1e-12)


def test_the_smallest_and_largest_normal_masses_and_moments_give_finite_numbers():
    """1e-320 is refused (1/M = inf: NaN at t = 0); the smallest normal float is fine."""
    huge = 1 / TINY
    for body in (rb.RigidBody(TINY, [TINY] * 3), rb.RigidBody(huge, [huge] * 3)):
        assert np.all(np.isfinite(body.I_body_inv))
        for method in ("euler", "rk4", "adaptive"):
            traj = rb.simulate(body, X0, 0.02, 0.01, method)
            assert np.all(np.isfinite(traj.x)) and np.all(np.isfinite(traj.R))
            assert np.all(np.isfinite(traj.kinetic_energy()))
    with pytest.raises(ValueError, match="mass must be in"):
        rb.RigidBody(TINY / 2, [1, 1, 1])


def test_shapes_with_their_sizes():
    assert rb.RigidBody(1, [1, 1, 1], shape="box", size=(1, 1, 1)).size == (1.0, 1.0, 1.0)
    assert rb.RigidBody(1, [1, 1, 1], shape="cylinder", size=(1, 0)).size == (1.0, 0.0)   # a flat disk
    assert rb.RigidBody.cylinder(1, 1, 0).size == (1.0, 0.0)
    assert rb.RigidBody(1, [1, 1, 1], shape="sphere", size=[0.5]).half_extents().tolist() == [0.5] * 3
    assert rb.RigidBody(1, [1, 1, 1]).shape == "body" and rb.RigidBody(1, [1, 1, 1], name="rod").name == "rod"


def test_body_selections_that_are_accepted():
    scene = two_bodies(rb.Gravity(body=np.int64(1)), rb.Gravity(body=[1]), rb.Gravity(body=np.array([0, 1])),
                       rb.Gravity(body=(0,)), rb.Gravity(body=BOX), rb.Gravity())
    assert [scene.bodies_of(e).tolist() for e in scene.effects] == [[1], [1], [0, 1], [0], [1], [0, 1]]
    spring = two_bodies(rb.Spring((0, 0, 0), body=[0], other_body=np.int64(1)))
    assert spring.bodies_of(spring.effects[0]).tolist() == [0]
    assert X2.body(np.int64(1)).x.tolist() == [1.0, 0.0, 0.0] and X0.body(0) is X0


def test_empty_body_selection_is_refused_with_its_reason():
    with pytest.raises(ValueError, match=r"body must not be an empty list: name at least one body \(or None"):
        rb.Gravity(body=[])


@pytest.mark.parametrize("value", [
    [1.0, 2.0, 3.0], [1, 2, 3], (np.float64(1), 2.0, 3), np.array([1, 2, 3], dtype=np.float32)])
def test_force_functions_returning_real_numbers_work_on_both_paths(value):
    runs = [push(lambda t: value, fast=fast) for fast in (True, False)]
    np.testing.assert_allclose(runs[0].P[-1], 0.05 * np.array([1.0, 2.0, 3.0]), rtol=1e-12)
    np.testing.assert_allclose(runs[0].L, runs[1].L, rtol=0, atol=1e-14)


def test_exact_times_that_are_accepted():
    for t, expected in ((0, [0.0]), (np.float32(1.5), [1.5]), (np.array(2.0), [2.0]), (range(3), [0.0, 1.0, 2.0]),
                        ([0, 1.5], [0.0, 1.5]), (np.arange(2, dtype=np.int32), [0.0, 1.0])):
        assert rb.exact_free_body(SPH, X0, t).t.tolist() == expected


def test_tolerances_at_the_ends_of_their_ranges_run():
    assert RTOL_RANGE == (1e-14, 1.0) and ATOL_RANGE == (1e-100, 1e100)
    for fast in (True, False):
        for rtol, atol in ((RTOL_RANGE[0], ATOL_RANGE[0]), (RTOL_RANGE[1], ATOL_RANGE[1])):
            traj = rb.simulate(BOX, SPIN, 0.1, 0.05, "adaptive", rtol=rtol, atol=atol, fast=fast)
            assert np.all(np.isfinite(traj.R))
    method = rb.METHODS["adaptive"].configured(rtol=1, atol=np.float32(1e-6))
    assert method.settings["rtol"] == 1.0 and type(method.settings["atol"]) is float


def test_the_shared_validators():
    assert checks.real("a", np.float32(0.5)) == 0.5
    assert checks.integer("n", np.int16(3), low=1) == 3
    with pytest.raises(ValueError, match="n must be an integer >= 1, got 0"):
        checks.integer("n", 0, low=1)
    with pytest.raises(ValueError, match="flag must be True or False"):
        checks.boolean("flag", 1)
    assert checks.boolean("flag", np.bool_(True)) is True
    with pytest.raises(ValueError, match=r"v must be an array of numbers with shape \(3,\) or \(N, 3\)"):
        checks.array("v", "abc", (3,), batch=True)
    assert checks.indices("body", np.array([2, 0])) == (2, 0)


# --- the public helpers of rotation.py and dynamics.py, and the run-length check -------------------------------

@pytest.mark.parametrize("call", [
    lambda: rb.star(["1", "2", "3"]), lambda: rb.star([1, 2]), lambda: rb.exp_so3("abc"),
    lambda: rb.project_so3("abc"), lambda: rb.project_so3(np.full((3, 3), np.nan)),
    lambda: rb.rotation_angle(np.eye(3), [[True] * 3] * 3),
    lambda: rb.dxdt(rb.RigidBody.box(mass=1.0, size=(1, 1, 1)), "t", rb.State.at_rest()),
    lambda: rb.dxdt(rb.RigidBody.box(mass=1.0, size=(1, 1, 1)), 0.0, "X"),
    lambda: rb.simulate(rb.RigidBody.box(mass=1.0, size=(1, 1, 1)), rb.State.at_rest(), 1e308, 5e-324),
    lambda: rb.METHODS["exact_splitting"].configured(composition="nope"),
    lambda: rb.Scene(rb.RigidBody.box(mass=1.0, size=(1, 1, 1)), name=42),
], ids=["star-strings", "star-shape", "exp-string", "project-string", "project-nan", "angle-bools", "dxdt-t",
        "dxdt-X", "steps-overflow", "composition", "scene-name"])
def test_public_helpers_refuse_garbage(call):
    with pytest.raises(ValueError):
        call()


def test_public_helpers_accept_numbers():
    np.testing.assert_array_equal(rb.star([1, 2, 3])[0], [0, -3, 2])
    np.testing.assert_allclose(rb.project_so3(2 * np.eye(3)), np.eye(3))
    assert rb.rotation_angle(np.eye(3), np.eye(3)) == 0.0
