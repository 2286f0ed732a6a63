"""Effects and States are truly immutable (issue 26, item 5): their arrays are private copies in read-only memory
(checks.frozen) that cannot be written nor made writable again, and no attribute can be set after construction."""
import copy
import pickle

import numpy as np
import pytest

import rbcourse as rb
from rbcourse.support import checks
from rbcourse.state import from_matrix

BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))


def effects():
    """One of each effect class, with its array parameters: (effect, names of its arrays)."""
    return [
        (rb.Gravity(9.81), []),
        (rb.PointForce((0.15, 0, 0), (0, 1.0, 0)), ["body_point", "force"]),
        (rb.Spring((0.15, 0.1, 0.025), (0, 0, 1.0), stiffness=50.0, rest_length=0.2),
         ["body_point", "world_point", "other_point"]),
        (rb.LinearDrag(0.1), []),
        (rb.AngularDrag(0.1), []),
        (rb.Pivot((0, 0, -0.05), (0, 0, 1.0)), ["body_point", "world_point"]),
        (rb.Impulse((0.15, 0, 0), (0, 0, 0.2), time=0.5), ["body_point", "impulse"]),
        (rb.Ground(0.0, restitution=0.3), []),
    ]


IDS = [type(e).__name__ for e, _ in effects()]


@pytest.mark.parametrize("effect, arrays", effects(), ids=IDS)
def test_an_effects_arrays_cannot_be_written_nor_made_writable(effect, arrays):
    for name in arrays:
        a = getattr(effect, name)
        before = a.copy()
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 9.0
        with pytest.raises(ValueError):
            a.setflags(write=True)
        with pytest.raises(ValueError):
            a[:].setflags(write=True)                                        # nor through a view
        np.testing.assert_array_equal(a, before)


@pytest.mark.parametrize("effect, arrays", effects(), ids=IDS)
def test_an_effects_attributes_cannot_be_set_nor_deleted(effect, arrays):
    name = type(effect).__name__
    for attr in list(vars(effect)) + ["anything_new"]:
        with pytest.raises(AttributeError, match=rf"^{name} is immutable: cannot set '{attr}'; build a new {name}"):
            setattr(effect, attr, 5)
    for attr in vars(effect):
        with pytest.raises(AttributeError, match=rf"^{name} is immutable: cannot delete '{attr}'"):
            delattr(effect, attr)


@pytest.mark.parametrize("make, arg", [
    (lambda a: rb.PointForce(a, (0, 1.0, 0)), "body_point"),
    (lambda a: rb.PointForce((0.1, 0, 0), a), "force"),
    (lambda a: rb.Spring(a, (0, 0, 1.0)), "body_point"),
    (lambda a: rb.Spring((0.1, 0, 0), a), "world_point"),
    (lambda a: rb.Spring((0.1, 0, 0), body=0, other_body=1, other_point=a), "other_point"),
    (lambda a: rb.Pivot(a, (0, 0, 1.0)), "body_point"),
    (lambda a: rb.Pivot((0, 0, -0.05), a), "world_point"),
    (lambda a: rb.Impulse(a, (0, 0, 0.2), time=0.5), "body_point"),
    (lambda a: rb.Impulse((0.1, 0, 0), a, time=0.5), "impulse"),
])
def test_the_array_given_changed_later_does_not_change_the_effect(make, arg):
    given = np.array([0.1, 0.2, 0.3])
    effect = make(given)
    given[0] = 9.0
    assert getattr(effect, arg).tolist() == [0.1, 0.2, 0.3]


@pytest.mark.parametrize("effect, arrays", effects(), ids=IDS)
def test_a_pickled_or_copied_effect_is_as_immutable(effect, arrays):
    for other in (pickle.loads(pickle.dumps(effect)), copy.copy(effect), copy.deepcopy(effect)):
        assert repr(other) == repr(effect)
        for name in arrays:
            np.testing.assert_array_equal(getattr(other, name), getattr(effect, name))
            with pytest.raises(ValueError):
                getattr(other, name).setflags(write=True)
        with pytest.raises(AttributeError, match="is immutable"):
            other.body = 0


def test_a_subclass_of_an_effect_is_immutable_once_built():
    class Floor(rb.Ground):
        def __init__(self, height):
            super().__init__(height)
            self.mark = np.array([1.0, 2.0])                                 # set in its own __init__: allowed
    floor = Floor(1.0)
    assert vars(floor).keys() == {"height", "restitution", "friction", "body", "mark"}
    with pytest.raises(ValueError):
        floor.mark.setflags(write=True)
    with pytest.raises(AttributeError, match="^Floor is immutable: cannot set 'height'"):
        floor.height = 2.0


def test_a_scenes_next_run_is_the_same_whatever_is_tried_on_its_effects():
    kick = rb.Impulse((0.15, 0, 0), (0, 0, 0.2), time=0.01)
    spring = rb.Spring((0.15, 0.1, 0.025), (0, 0, 1.0), stiffness=50.0)
    push = rb.PointForce((0, 0.1, 0), (1.0, 0, 0))
    scene = rb.Scene(BOX, [rb.Gravity(), spring, push, kick])
    X0 = rb.State.at_rest((0, 0, 0.5))
    first = rb.simulate(scene, X0, 0.02, 0.005, "rk4", fast=False)
    for effect, attr in ((spring, "body_point"), (push, "force"), (kick, "impulse")):
        a = getattr(effect, attr)
        with pytest.raises(ValueError):
            a[0] = 9.0
        with pytest.raises(ValueError):
            a.setflags(write=True)
        with pytest.raises(AttributeError):
            setattr(effect, attr, np.zeros(3))
    with pytest.raises(AttributeError):
        spring.stiffness = 5.0
    for name in ("x", "R", "P", "L"):
        with pytest.raises(ValueError):
            getattr(X0, name).setflags(write=True)
    again = rb.simulate(scene, X0, 0.02, 0.005, "rk4", fast=False)
    for name in ("t", "x", "R", "P", "L"):
        np.testing.assert_array_equal(getattr(again, name), getattr(first, name))


# --- States -------------------------------------------------------------------------------------------------------

def state(how: str) -> rb.State:
    """A State built one way: checked, unchecked, stacked, a body of a stack, from the engine's rows, a trajectory's,
    pickled or copied."""
    X = rb.State(np.zeros(3), np.eye(3), [1.0, 2.0, 3.0], [0.1, 0.2, 0.3])
    two = lambda: rb.State.stack([X, X.replace(x=[1.0, 0, 0])])            # noqa: E731
    return {"State(...)": lambda: X,
            "unchecked": lambda: rb.State.unchecked(np.zeros(3), np.eye(3), np.ones(3), np.ones(3)),
            "stack": two, "body(i)": lambda: two().body(1), "from_matrix": lambda: from_matrix(np.zeros((2, 18))),
            "replace": lambda: X.replace(P=[0, 0, 1.0]), "at_rest": rb.State.at_rest,
            "from_velocities": lambda: rb.State.from_velocities(BOX, np.zeros(3), np.eye(3), np.ones(3), np.ones(3)),
            "trajectory state": lambda: rb.simulate(BOX, X, 0.01, 0.005, "euler", fast=False).state(1),
            "pickled": lambda: pickle.loads(pickle.dumps(X)),
            "copy": lambda: copy.copy(X), "deepcopy": lambda: copy.deepcopy(X)}[how]()


HOW = ["State(...)", "unchecked", "stack", "body(i)", "from_matrix", "replace", "at_rest", "from_velocities",
       "trajectory state", "pickled", "copy", "deepcopy"]


@pytest.mark.parametrize("how", HOW)
def test_a_states_arrays_cannot_be_written_nor_made_writable(how):
    X = state(how)
    for name in ("x", "R", "P", "L"):
        a = getattr(X, name)
        assert a.dtype == np.float64
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 9.0
        with pytest.raises(ValueError):
            a.setflags(write=True)
        with pytest.raises(ValueError):
            a[...].setflags(write=True)


@pytest.mark.parametrize("how", HOW)
def test_a_states_attributes_cannot_be_set_nor_deleted(how):
    X = state(how)
    for name in ("x", "R", "P", "L"):
        with pytest.raises(AttributeError, match=rf"^State is immutable: cannot set '{name}'; build a new one with "
                                                 rf"State\(\.\.\.\) or state\.replace\({name}=\.\.\.\)"):
            setattr(X, name, np.zeros(3))
        with pytest.raises(AttributeError, match=rf"^State is immutable: cannot delete '{name}'"):
            delattr(X, name)


def test_the_arrays_a_state_is_built_from_changed_later_do_not_change_it():
    x, R, P, L = np.zeros(3), np.eye(3), np.ones(3), np.ones(3)
    checked, unchecked = rb.State(x, R, P, L), rb.State.unchecked(x, R, P, L)
    S = np.zeros((1, 18))
    rows = from_matrix(S)
    record = np.zeros((3, 3))
    x[0] = R[0, 0] = P[0] = L[0] = 9.0
    S[0, :] = 9.0
    record[1] = 9.0
    for X in (checked, unchecked):
        assert X.x.tolist() == [0, 0, 0] and X.R[0, 0] == 1.0 and X.P[0] == 1.0 and X.L[0] == 1.0
    assert rows.x.tolist() == [[0, 0, 0]] and rows.R.tolist() == [np.zeros((3, 3)).tolist()]


def test_a_trajectory_state_is_a_copy_of_the_record_which_is_read_only():
    traj = rb.simulate(BOX, rb.State.at_rest(), 0.01, 0.005, "euler", fast=False)
    X = traj.state(1)
    for name in ("x", "R", "P", "L"):
        assert not np.shares_memory(getattr(X, name), getattr(traj, name))
    with pytest.raises(ValueError, match="read-only"):
        traj.x[1, 0] = 9.0                                                   # the trajectory's own arrays
    assert X.x[0] == 0.0 and traj.x[1, 0] == 0.0


def test_a_pickled_or_copied_state_equals_it():
    X = rb.State(np.zeros(3), np.eye(3), [1.0, 2.0, 3.0], [0.1, 0.2, 0.3])
    for Y in (pickle.loads(pickle.dumps(X)), copy.copy(X), copy.deepcopy(X)):
        assert Y == X and type(Y) is rb.State


def test_frozen_is_one_helper_a_copy_once_and_none_for_what_is_frozen_already():
    a = np.arange(6.0).reshape(2, 3)
    f = checks.frozen(a)
    assert f.shape == (2, 3) and f.dtype == a.dtype and not np.shares_memory(f, a)
    assert checks.frozen(f) is f and checks.is_frozen(f[0]) and checks.frozen(f[0]).base is not None
    ro = a.copy()
    ro.setflags(write=False)                                                 # read-only, but could be made writable
    assert not checks.is_frozen(ro) and checks.is_frozen(checks.frozen(ro))
    strided = checks.frozen(a[:, ::2])
    assert strided.tolist() == [[0.0, 2.0], [3.0, 5.0]]


def test_a_rigid_body_pickles_as_its_constants_and_stays_constant():
    import pickle
    body = rb.RigidBody.cylinder(2.0, 0.1, 0.3)
    copy = pickle.loads(pickle.dumps(body))
    assert repr(copy) == repr(body) and copy.shape == "cylinder" and copy.size == body.size
    for name in ("I_body", "I_body_inv", "principal_moments", "principal_axes"):
        np.testing.assert_array_equal(getattr(copy, name), getattr(body, name))
        assert not getattr(copy, name).flags.writeable
    with pytest.raises(AttributeError):
        copy.mass = 3.0
