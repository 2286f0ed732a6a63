"""The exercise checks (rbcourse.workbook.exercises), what every check does alike: the solution passes; a stub
is "not done yet"; an exception is a clean message; a bad output is named; a check never raises, prints once
in a notebook; and the pushed box runs your code or the reference engine.  The solution and the wrong
implementations are test_exercises.py's (loaded here by path, as test_mistakes.py does)."""
import importlib.util
import pathlib
import re
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import rbcourse as rb
from rbcourse.workbook import exercises as ex
from rbcourse.workbook.exercises import result

_spec = importlib.util.spec_from_file_location("_exercise_tests", pathlib.Path(__file__).with_name("test_exercises.py"))
base = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(base)

SOLUTION, check, box_inertia, velocity, inverse_inertia = (base.SOLUTION, base.check, base.box_inertia, base.velocity,
                                                           base.inverse_inertia)
dxdt, euler_step, euler_step_projected, simulate = base.dxdt, base.euler_step, base.euler_step_projected, base.simulate
_dxdt_with, _gram_schmidt, _projected_with, _semi_implicit_P, _sim = (base._dxdt_with, base._gram_schmidt,
                                                                      base._projected_with, base._semi_implicit_P,
                                                                      base._sim)


# =====================================================================================
# The solution passes; stubs; exceptions; checks never raise
# =====================================================================================

@pytest.mark.parametrize("name", list(SOLUTION))
def test_the_solution_passes_every_check(name, capsys):
    r = getattr(ex, f"check_{name}")(SOLUTION[name])
    assert r.passed and r.mistake is None, r.message
    out = capsys.readouterr().out
    assert out == r.message + "\n"
    assert re.fullmatch(rf"✓ {name}: .+ — correct on \d+ random (inputs|runs)", r.message)


def test_pass_line_reads_as_the_brief_says():
    assert check("velocity", velocity).message == "✓ velocity: v = P/M — correct on 20 random inputs"


def test_solution_with_other_spellings_passes():
    """Namedtuples, np.dot, rbcourse's own functions: all right (a list is not: see test_mistakes.py)."""
    assert check("angular_velocity", lambda I, L: np.dot(L, I)).passed              # I⁻¹ is symmetric
    assert check("resultants", lambda x, fs: rb.resultants(x, fs)).mistake == "library_call"        # issue 45
    assert check("resultants", lambda x, fs: np.array(rb.resultants(x, fs))).mistake == "library_call"
    assert check("dxdt", lambda M, Ib, X, fs: rb.StateDerivative(*dxdt(M, Ib, X, fs))).passed
    assert check("euler_step", lambda *a: ex.StateTuple(*euler_step(*a))).passed
    assert check("simulate", lambda *a, **k: ex.StateTuple(*simulate(*a, **k))).passed
    assert check("box_inertia", lambda m, s: rb.RigidBody.box(m, s).I_body).mistake == "library_call"


def test_simulate_with_accumulated_time_passes():
    def sim(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
        X, t, out = X0, 0.0, [X0]
        for _ in range(n_steps):
            X = step(M, Ib, X, forces_at(t, X), dt)
            t += dt
            out.append(X)
        return tuple(np.array([s[i] for s in out]) for i in range(4))
    assert check("simulate", sim).passed


def test_gram_schmidt_is_named_not_accepted():
    """Issue 45: Gram–Schmidt gives a rotation close to R, not the nearest one the fix asks (nor is any other rotation
    a step may make of the Euler step's R): named, in project_so3 and in the fixed step."""
    r = check("project_so3", _gram_schmidt)
    assert (r.passed, r.mistake) == (False, "not_nearest") and "Gram–Schmidt" in r.message
    r = check("euler_step_projected", _projected_with(euler_step, _gram_schmidt))
    assert (r.passed, r.mistake) == (False, "not_nearest") and "Gram–Schmidt" in r.message


def _stub(*args, **kwargs):
    raise NotImplementedError("write it")


@pytest.mark.parametrize("name", list(SOLUTION))
def test_a_stub_is_not_done_yet(name, capsys):
    r = getattr(ex, f"check_{name}")(_stub)
    assert (r.passed, r.mistake) == (False, "not_done")
    assert r.message == f"○ {name}: not done yet (it raises NotImplementedError)"
    assert capsys.readouterr().out == r.message + "\n"


def test_calling_a_stub_names_it():
    def velocity(P, M):
        raise NotImplementedError("v = P/M")

    def my_dxdt(M, Ib, X, forces):
        x, R, P, L = X
        return velocity(P, M), None, None, None
    r = check("dxdt", my_dxdt)
    assert r.mistake == "not_done"
    assert r.message == "○ dxdt: not done yet (it calls velocity, which raises NotImplementedError)"


def test_an_exception_is_reported_cleanly():
    def velocity(P, M):
        return P @ M            # matmul of a vector and a number
    r = check("velocity", velocity)
    assert (r.passed, r.mistake) in ((False, "error"), (False, "crashes_when"))
    assert r.message.startswith("✗ velocity raised ValueError: ")
    assert "(in velocity, line " in r.message and "return P @ M" in r.message
    assert "on the input P = [" in r.message
    assert "Traceback" not in r.message and "File " not in r.message


def test_errors_inside_numpy_point_at_the_students_line():
    def inverse_inertia(R, Ib):
        R_T = np.transpose(R, (0, 1, 2))
        return R @ Ib @ R_T
    r = check("inverse_inertia", inverse_inertia)
    assert r.mistake in ("error", "crashes_when") and "in inverse_inertia, line" in r.message and "np.transpose" in r.message


@pytest.mark.parametrize("out, mistake", [
    (None, "returned_none"), ("hello", "not_numbers"), (object(), "not_numbers"), (np.zeros((3, 1)), "column_vector"),
    (np.zeros(4), "wrong_shape"), (np.full(3, np.nan), "probed"), (np.ones(3), "probed"),
])
def test_bad_outputs(out, mistake):
    r = check("velocity", lambda P, M: out)
    assert (r.passed, r.mistake) == (False, mistake), r.message
    assert "\n   → reread the slide “Evolution temporelle (Euler)”" in r.message


def test_wrong_result_shows_input_expected_and_got():
    r = check("velocity", lambda P, M: P / M + 1.0)
    assert r.mistake == "probed"          # issue 45: the simplest input that shows it, and the numbers there
    assert re.search(r"the result is wrong even on the simplest input \(P along x, M = 1\) — expected \[.+\], "
                     r"got \[.+\] \(on the input P = \[.+\], M = 1\)", r.message), r.message


def test_tuple_results_wrong_part_is_named():
    r = check("dxdt", lambda M, Ib, X, fs: (*dxdt(M, Ib, X, fs)[:3], np.ones(3)))
    assert r.mistake == "probed" and "dL/dt is wrong even at rest" in r.message, r.message
    assert "does not change with the input" in r.message
    r = check("euler_step", lambda *a: euler_step(*a)[:3])
    assert r.mistake == "wrong_return" and "returned 3 values; expected 4" in r.message
    r = check("resultants", lambda x, fs: 5)
    assert r.mistake == "wrong_return"


def test_two_mistakes_name_the_first_wrong_part():
    wrong = _dxdt_with(R_dot=lambda S, R: R @ S, dP=lambda F, M: F / M)
    r = check("dxdt", wrong)
    assert r.mistake == "R_dot_order" and "dP/dt is wrong too" in r.message


def test_simulate_returning_a_list_of_states():
    def sim(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
        X, out = X0, [X0]
        for k in range(n_steps):
            X = step(M, Ib, X, forces_at(k * dt, X), dt)
            out.append(X)
        return out
    r = check("simulate", sim)
    assert r.mistake == "wrong_return" and "return four arrays (x, R, P, L)" in r.message


def test_not_a_function():
    r = check("velocity", velocity(np.ones(3), 2.0))
    assert r.mistake == "not_a_function" and "check_velocity(velocity)" in r.message


def test_system_exit_is_caught():
    def quits(P, M):
        raise SystemExit(3)
    assert check("velocity", quits).mistake == "crashes_when"


def test_the_checks_are_deterministic():
    wrong = lambda P, M: P / M + 0.5  # noqa: E731
    assert check("velocity", wrong).message == check("velocity", wrong).message
    assert check("simulate", _sim(record_to=-1)).message == check("simulate", _sim(record_to=-1)).message


def test_the_check_prints_once_in_a_notebook(capsys, monkeypatch):
    cell = [7]
    monkeypatch.setattr(result, "execution_count", lambda: cell[0])
    r = ex.check_velocity(velocity)
    r._ipython_display_()                           # the value of the same cell: nothing more
    assert capsys.readouterr().out == r.message + "\n"
    cell[0] = 8
    r._ipython_display_()                           # shown in a later cell: the message
    assert capsys.readouterr().out == r.message + "\n"
    assert repr(r) == "CheckResult(name='velocity', passed=True, mistake=None)" and str(r) == r.message


_garbage = st.one_of(
    st.none(), st.integers(), st.floats(allow_nan=True), st.text(max_size=5), st.binary(max_size=4),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=5),
    st.tuples(st.floats(allow_nan=True), st.floats()),
    st.lists(st.lists(st.floats(-1e300, 1e300), min_size=3, max_size=3), max_size=4),
    st.dictionaries(st.text(max_size=2), st.integers(), max_size=2),
    st.builds(lambda n: np.full((n, 3), np.inf), st.integers(0, 4)),
    st.sampled_from([np.eye(3), np.zeros((4, 3, 3)), ex.StateTuple(1, 2, 3, 4), (np.zeros(3),) * 4,
                     [np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3)], (np.zeros(5),) * 4]),
)


@settings(max_examples=40, deadline=None)
@given(out=_garbage, name=st.sampled_from(list(SOLUTION)))
def test_checks_never_raise_whatever_the_function_returns(out, name):
    r = check(name, lambda *a, **k: out)
    assert isinstance(r, ex.CheckResult)
    assert not r.passed and r.mistake != "check_failed", r.message
    assert r.message.startswith("✗ ")


@settings(max_examples=20, deadline=None)
@given(exc=st.sampled_from([ValueError("v"), TypeError("t"), ZeroDivisionError("z"), KeyError("k"),
                            IndexError("i"), RecursionError("r"), AttributeError("a"), Exception(""),
                            np.linalg.LinAlgError("Singular matrix")]),
       name=st.sampled_from(list(SOLUTION)))
def test_checks_never_raise_whatever_the_function_raises(exc, name):
    def raises(*a, **k):
        raise exc
    r = check(name, raises)
    assert (r.passed, r.mistake) in ((False, "error"), (False, "crashes_when")) or r.mistake in ("empty_forces",
                                                                                                "no_step_parameter")
    assert type(exc).__name__ in r.message


# =====================================================================================
# The pushed box: your code or the reference engine
# =====================================================================================

def test_pushed_box_is_the_slides_box():
    box = ex.pushed_box()
    assert box.M == 1.0 and box.size == (0.3, 0.2, 0.05)
    assert np.allclose(box.I_body, box_inertia(1.0, (0.3, 0.2, 0.05)))
    assert np.allclose(box.corner, [0.15, 0.1, 0.025])
    assert len(box.forces_at(0.0, box.X0)) == 1 and box.forces_at(0.1, box.X0) == []
    assert len(box.forces_at(0.1 - 1e-6, box.X0)) == 1


def test_simulate_or_reference_uses_your_code_when_ready(capsys):
    mine = ex.simulate_or_reference(simulate, euler_step, 0.3, 1e-3)
    assert capsys.readouterr().out.startswith("your simulate() with euler_step(): 300 steps")
    assert mine.method == "euler (your code)" and len(mine.t) == 301
    ref = ex.simulate_or_reference(_stub, euler_step, 0.3, 1e-3)
    out = capsys.readouterr().out
    assert out.startswith("simulate() is not done yet → the reference engine instead: rbcourse.simulate(")
    assert "method='euler'" in out and ref.method == "euler"
    for a, b in zip((mine.x, mine.R, mine.P, mine.L), (ref.x, ref.R, ref.P, ref.L)):
        assert np.allclose(a, b, rtol=1e-10, atol=1e-12)
    assert np.allclose(ref.P[-1], [0, 0, 1.0])                       # 10 N for 0.1 s


def test_simulate_or_reference_falls_back_when_a_step_is_wrong(capsys):
    ex.simulate_or_reference(simulate, _semi_implicit_P, 0.05, 1e-2)
    assert capsys.readouterr().out.startswith("euler_step() does not pass its check yet → the reference engine")
    projected = ex.simulate_or_reference(simulate, _projected_with(euler_step, project=_stub), 0.05, 1e-2,
                                         reference="euler_project")
    assert "euler_step_projected() is not done yet" in capsys.readouterr().out
    assert projected.method == "euler_project"
    mine = ex.simulate_or_reference(simulate, euler_step_projected, 0.05, 1e-2, reference="euler_project")
    assert mine.method == "euler_project (your code)" and mine.orthogonality_error().max() < 1e-12


def test_simulate_or_reference_stops_a_blow_up_as_the_engine_does(capsys):
    # the slides' Euler at dt = 10 ms blows up at t = 0.37 s: no exception, no warning, the run marked
    # diverged at the same step whether your code or the reference engine ran it
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mine = ex.simulate_or_reference(simulate, euler_step, 1.0, 1e-2)
        ref = ex.simulate_or_reference(_stub, euler_step, 1.0, 1e-2)
    out = capsys.readouterr().out
    assert out.count("diverged at t = 0.37 s") == 2, out
    for run in (mine, ref):
        assert run.diverged and run.divergence.step == 37 and len(run.t) == 37
        assert np.all(np.abs(run.R) < 1e100)
    assert np.allclose(mine.R, ref.R, rtol=1e-9)


def test_show_iterations_from_rest(capsys):
    ex.show_iterations(euler_step)
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "with your euler_step"
    assert out[1].startswith("● Itération 1") and "τ = [1, -1.5, 0]" in out[1]
    assert out[2].endswith("unchanged") and out[3].endswith("unchanged")          # x, R: not yet
    assert out[4] == "    P(t+Δt) = [0, 0, 0.1]" and out[5] == "    L(t+Δt) = [0.01, -0.015, 0]"
    assert out[7].endswith("moved") and out[8].endswith("turned")                  # iteration 2
    ex.show_iterations(_semi_implicit_P)           # a finished but wrong step: shown, as the student's own
    out = capsys.readouterr().out
    assert out.startswith("with your euler_step — it does not pass check_euler_step yet"), out
    assert "✗ euler_step: you moved x or R with the new momentum" in out
    ex.show_iterations(_stub)
    assert capsys.readouterr().out.startswith("with the reference Euler step")
