"""exact_splitting compiled (rbcourse/engine/exact_flow.py) against the numpy engine (fast=False).

The method is not registered in the engine yet: here it is registered by monkeypatching the driver
(its loop run.run_exact, with steps.exact_step, an EngineMethod whose table and
nodes are those of the composition), and rb.simulate runs it through the driver (encode, force values
at the nodes, record, decode).  Compared with rb.simulate(..., fast=False) over 1000 steps, per array
as max |a − b| / (1 + max |b|) <= 1e-12, for the three compositions.
"""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse import driver
from rbcourse.engine import exact_flow
from rbcourse.engine.motion import work
from rbcourse.methods import get_method
from rbcourse import examples

DT = 1e-3
STEPS = 1000
TOL = 1e-12
CYL = rb.RigidBody.cylinder(mass=1.0, radius=0.04, height=0.3)          # I₁ = I₂ (axis z)
SQUARE = rb.RigidBody.box(2.0, (0.3, 0.3, 0.1))                          # I₁ = I₂ exactly
ROD = rb.RigidBody.box(0.5, (0.4, 0.1, 0.1))                             # I₂ = I₃ (axis x)
CUBE = rb.RigidBody.box(1.0, (0.2, 0.2, 0.2))                            # spherical
BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))                            # asymmetric
R_TILT = rb.rotation.rotation_about([1.0, 2.0, 3.0], 0.4)
COMPOSITIONS = ("strang", "yoshida4", "blanes_moan4")


def spinning(body, x=(0.0, 0.0, 1.0), v=(0.1, -0.2, 0.3), omega=(0.3, 2.0, 0.5), R=None):
    return rb.State.from_velocities(body, x=x, R=np.eye(3) if R is None else R, v=v, omega=omega)


def push(t):
    return (np.sin(3.0 * t), 0.5 * np.cos(2.0 * t), 1.0 + t)


def heavy_top():
    ex = examples.heavy_top()
    return ex.scene, ex.X0


def tilted_top():
    pivot = rb.Pivot(body_point=(0.0, 0.0, -0.1))
    return rb.Scene(CYL, [rb.Gravity(), pivot, rb.AngularDrag(0.001)]), pivot.state(CYL, R_TILT, [0.5, 0.0, 20.0])


def three_bodies():
    scene = rb.Scene([CYL, SQUARE, ROD],
                     [rb.Gravity(), rb.Spring((0.1, 0.0, 0.0), stiffness=20.0, damping=0.2, rest_length=0.3, body=0,
                                              other_body=1, other_point=(0.0, 0.1, 0.0))])
    X0 = rb.State.stack([spinning(CYL), spinning(SQUARE, x=(0.5, 0.2, 1.0), v=(0.0, 0.3, 0.0),
                                                 omega=(-1.0, 0.4, 1.5), R=R_TILT),
                         spinning(ROD, x=(-0.4, 0.1, 0.0), omega=(2.0, -1.0, 3.0), R=R_TILT.T)])
    return scene, X0


CASES = {
    "free_cylinder": lambda: (rb.Scene(CYL), spinning(CYL, R=R_TILT)),
    "free_square_box": lambda: (rb.Scene(SQUARE), spinning(SQUARE, omega=(1.0, -2.0, 7.0))),
    "free_rod": lambda: (rb.Scene(ROD), spinning(ROD, omega=(5.0, 1.0, -0.5))),
    "free_cube": lambda: (rb.Scene(CUBE, [rb.Gravity()]), spinning(CUBE)),
    "gravity_square_box": lambda: (rb.Scene(SQUARE, [rb.Gravity()]), spinning(SQUARE, R=R_TILT)),
    "heavy_top": heavy_top,
    "tilted_top_drag": tilted_top,
    "spring_drag": lambda: (rb.Scene(CYL, [rb.Spring((0.02, 0.0, 0.1), (0.0, 0.2, 1.5), stiffness=50.0,
                                                     damping=0.3, rest_length=0.4), rb.LinearDrag(0.2),
                                           rb.AngularDrag(0.001)]), spinning(CYL, R=R_TILT)),
    "point_body_f(t)": lambda: (rb.Scene(SQUARE, [rb.PointForce((0.15, -0.1, 0.0), push, frame="body")]),
                                spinning(SQUARE)),
    "three_bodies_spring": three_bodies,
}



@pytest.fixture
def registered():
    """exact_splitting with a given composition (the driver takes its kick table and nodes from it)."""
    def register(composition):
        return get_method("exact_splitting").configured(composition=composition)
    return register


def spread(a, b) -> float:
    """max |a − b| / (1 + max |b|)."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    return float(np.max(np.abs(a - b)) / (1.0 + np.max(np.abs(b))))


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("composition", COMPOSITIONS)
def test_compiled_equals_numpy(registered, composition, case):
    scene, X0 = CASES[case]()
    assert exact_flow.exact_flow_supported(scene.system()) == ""
    method = registered(composition)
    dt = 2.5e-4 if case == "heavy_top" else DT
    slow = rb.simulate(scene, X0, STEPS * dt, dt, method, fast=False)
    fast = rb.simulate(scene, X0, STEPS * dt, dt, method)
    assert fast.implementation.startswith("compiled"), fast.implementation
    assert not slow.implementation.startswith("compiled"), slow.implementation
    np.testing.assert_allclose(fast.t, slow.t, rtol=0, atol=1e-12)
    for k in "xRPL":
        d = spread(getattr(fast, k), getattr(slow, k))
        assert d <= TOL, f"{composition}, {case}: {k} differs by {d:.3g}"
    assert spread(slow.R[-1], slow.R[0]) > 1e-3          # the run moved


def test_heavy_top_is_symmetric_about_its_pivot_axis():
    scene, _ = heavy_top()
    assert exact_flow.body_kind(scene.compile().system.I_moments[0]) == exact_flow.SYMMETRIC


def test_every_body_is_accepted():
    assert exact_flow.exact_flow_supported(rb.Scene(BOX).system()) == ""
    assert exact_flow.exact_flow_supported(rb.Scene([CYL, BOX], [rb.Gravity()]).system()) == ""
    assert exact_flow.body_kind(rb.Scene(BOX).compile().system.I_moments[0]) == exact_flow.ASYMMETRIC


ASYM = {"box": rb.RigidBody.box(1.0, (0.3, 0.2, 0.05)),
        "flat": rb.RigidBody(mass=1.0, inertia=[1.0, 2.0, 3.0]),
        "nearly_symmetric": rb.RigidBody(mass=1.0, inertia=[1.0, 2.0, 2.0 + 1e-9])}
OMEGAS = {"generic": (0.3, 2.0, 0.5), "middle_axis": (1e-3, 5.0, 1e-3), "near_major": (0.1, 0.1, 20.0)}


@pytest.mark.parametrize("omega", sorted(OMEGAS))
@pytest.mark.parametrize("name", sorted(ASYM))
def test_free_asymmetric_equals_the_exact_motion(name, omega):
    """No force: exact_splitting is the exact flow — 1000 steps of h = 0.05 equal rb.exact_free_body
    (scipy.special, independent of the engine) to 1e-10, tilted principal axes included."""
    body = ASYM[name]
    X0 = spinning(body, R=R_TILT, omega=OMEGAS[omega])
    traj = rb.simulate(rb.Scene(body), X0, 50.0, 0.05, "exact_splitting")
    assert traj.implementation.startswith("compiled"), traj.implementation
    ref = rb.exact_free_body(body, X0, traj.t)
    for k in "xRL":
        assert spread(getattr(traj, k), getattr(ref, k)) <= 1e-10, k


def asym_top():
    pivot = rb.Pivot(body_point=(0.0, 0.0, -0.05))
    return rb.Scene(BOX, [rb.Gravity(), pivot]), pivot.state(BOX, R_TILT, [0.5, 0.3, 30.0])


def test_pivoted_asymmetric_top_converges_at_order_4():
    scene, X0 = asym_top()
    T = 0.5
    ref = rb.simulate(scene, X0, T, T / 1600, "exact_splitting").R[-1]
    errs = [np.abs(rb.simulate(scene, X0, T, T / n, "exact_splitting").R[-1] - ref).max() for n in (50, 100)]
    order = np.log2(errs[0] / errs[1])
    assert 3.6 <= order <= 4.6, (errs, order)


def box_spring_drag():
    return (rb.Scene(BOX, [rb.Spring((0.02, 0.0, 0.1), (0.0, 0.2, 1.5), stiffness=50.0, damping=0.3, rest_length=0.4),
                           rb.LinearDrag(0.2), rb.AngularDrag(0.001)]), spinning(BOX, R=R_TILT))


def three_bodies_two_asymmetric():
    flat = ASYM["flat"]
    scene = rb.Scene([BOX, CYL, flat],
                     [rb.Gravity(), rb.Spring((0.1, 0.0, 0.0), stiffness=20.0, damping=0.2, rest_length=0.3, body=0,
                                              other_body=1, other_point=(0.0, 0.1, 0.0))])
    X0 = rb.State.stack([spinning(BOX), spinning(CYL, x=(0.5, 0.2, 1.0), omega=(-1.0, 0.4, 1.5), R=R_TILT),
                         spinning(flat, x=(-0.4, 0.1, 0.0), omega=(2.0, -1.0, 3.0), R=R_TILT.T)])
    return scene, X0


@pytest.mark.parametrize("case", [asym_top, box_spring_drag, three_bodies_two_asymmetric])
def test_asymmetric_compiled_equals_interpreted(case):
    """The compiled run and the same engine run as Python (fast=False) agree to 1e-12 over 200 steps."""
    scene, X0 = case()
    fast = rb.simulate(scene, X0, 0.2, 1e-3, "exact_splitting")
    slow = rb.simulate(scene, X0, 0.2, 1e-3, "exact_splitting", fast=False)
    assert fast.implementation.startswith("compiled"), fast.implementation
    assert not slow.implementation.startswith("compiled"), slow.implementation
    for k in "xRPL":
        assert spread(getattr(fast, k), getattr(slow, k)) <= 1e-12, k
    assert spread(fast.R[-1], fast.R[0]) > 1e-3


def test_nodes_and_options_follow_the_composition():
    from rbcourse.engine.compositions import COMPOSITIONS as TABLES
    for name, table in TABLES.items():
        s = {"composition": name}
        stages = exact_flow.kick_table(s).stages
        c = exact_flow.nodes(s)
        assert len(c) == stages * len(table["kicks"])
        assert c[0] == 0.0 and c[-1] == pytest.approx(1.0, abs=1e-14)
        opts = exact_flow.options(None, s)
        assert opts[0] == len(table["flows"]) and len(opts) == 1 + 2 * len(table["flows"]) + 1
    assert exact_flow.kick_table({}).stages == 4      # default blanes_moan4: order 4, RK4 kicks


def test_a_free_symmetric_body_is_exact_whatever_the_step():
    """No force: one step of h equals many steps (the flow is exact), L is kept, Y is left as it was."""
    scene, X0 = CASES["free_cylinder"]()
    sys = scene.compile().system
    Y = driver.encode("matrix", scene.to_engine(scene.batch(X0)))
    Y0 = Y.copy()
    em_opts = exact_flow.options(scene, {"composition": "strang"})
    from rbcourse.engine.tableaus import MIDPOINT
    A, b = np.ascontiguousarray(MIDPOINT.A), np.ascontiguousarray(MIDPOINT.b)
    K, U, w = np.empty((3,) + Y.shape), np.empty_like(Y), work(1)
    values = np.zeros((4, 0, 3))
    big = np.empty_like(Y)
    exact_flow.exact_splitting_step(sys, values, em_opts, A, b, 1.0, Y, big, 2.0, K, U, w)
    assert np.array_equal(Y, Y0)
    small, nxt = Y.copy(), np.empty_like(Y)
    for _ in range(200):
        exact_flow.exact_splitting_step(sys, values, em_opts, A, b, 1.0, small, nxt, 0.01, K, U, w)
        small, nxt = nxt, small
    assert np.abs(big[0, 3:12] - small[0, 3:12]).max() < 1e-12
    assert np.abs(big[0, 3:12] - Y[0, 3:12]).max() > 0.1
    assert np.array_equal(big[0, 15:18], Y[0, 15:18])


def test_configure_gives_the_kick_table_and_nodes():
    for name in COMPOSITIONS:
        s = {"composition": name}
        assert exact_flow.configure(None, s)[:2] == (exact_flow.kick_table(s), exact_flow.nodes(s))
