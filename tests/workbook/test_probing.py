"""Issue 45: the checks diagnose what no family lists, by probing — the student's function climbs a ladder of inputs
from the simplest to the general one (exercises/ladders.py), and the first line says the first feature that breaks it
and the kind of difference there (exercises/probing.py); a crash says the input that triggers it.  Also: a function
that takes its answer from rbcourse is named in the notebook; check_simulate tries plain tuples, lists and the
student's own kind of step; one rule of precision in every check."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.workbook import exercises as ex
from rbcourse.workbook.exercises import reference as ref
from rbcourse.workbook.exercises.probing import constant_factor, factor_text, scalar_factor

from test_exercises import (SOLUTION, angular_velocity, box_inertia, dxdt, euler_step, inverse_inertia, project_so3,
                            resultants, simulate, star, velocity)

ENGLISH = ("as soon as", "even ", " is wrong", "on the input", "it raised", "expected", "the result")


def check(name, fn):
    return getattr(ex, f"check_{name}")(fn, verbose=False)


# =====================================================================================
# Mistakes no family lists: (check, function, feature words, kind words) in English and French
# =====================================================================================

GLOBAL_SIZE = (0.3, 0.2, 0.05)
GLOBAL_DT = 0.01


def _resultants_running_total(x, forces):       # crosses the lever arm with the running sum of the forces
    F, tau = np.zeros(3), np.zeros(3)
    for r, f in forces:
        F = F + f
        tau = tau + np.cross(r - x, F)
    return F, tau


def _hand_cross_y(x, forces):                   # a hand-written cross product with its y component's sign wrong
    F, tau = np.zeros(3), np.zeros(3)
    for r, f in forces:
        a = r - x
        F = F + f
        tau = tau + np.array([a[1] * f[2] - a[2] * f[1], a[0] * f[2] - a[2] * f[0], a[0] * f[1] - a[1] * f[0]])
    return F, tau


def _step_dt_ms(M, Ib, X, forces, dt):          # Δt read as milliseconds
    return euler_step(M, Ib, X, forces, dt / 1000)


def _step_global_dt(M, Ib, X, forces, dt):
    return euler_step(M, Ib, X, forces, GLOBAL_DT)


def _dxdt_omega_over_M(M, Ib, X, forces):        # ω = I⁻¹(t) L / M
    x, R, P, L = X
    v, _, F, tau = dxdt(M, Ib, X, forces)
    return v, star(R @ Ib @ R.T @ L / M) @ R, F, tau


def _dxdt_diagonal_inertia(M, Ib, X, forces):
    return dxdt(M, np.diag(np.diag(Ib)), X, forces)


def _step_third_column_frozen(M, Ib, X, forces, dt):
    x, R, P, L = euler_step(M, Ib, X, forces, dt)
    R = R.copy()
    R[:, 2] = np.asarray(X[1])[:, 2]
    return x, R, P, L


UNLISTED = [
    ("box_inertia", lambda m, s: box_inertia(m, GLOBAL_SIZE), "even on the simplest input", "it ignores size"),
    ("box_inertia", lambda m, s: box_inertia(m, s) * 12 / m, "even on the simplest input", "12/mass ×"),
    ("inverse_inertia", lambda R, Ib: Ib @ R @ Ib, "even with R = I", "it computes I⁻¹_body · R · I⁻¹_body"),
    ("inverse_inertia", lambda R, Ib: inverse_inertia(R, np.diag(np.diag(Ib))), "as soon as the inertia is not "
     "diagonal", "only the diagonal of I⁻¹_body"),
    ("angular_velocity", lambda I, L: L / np.diag(I), "as soon as I⁻¹(t) is a diagonal", "L / diag(I⁻¹(t))"),
    ("angular_velocity", lambda I, L: (I @ L) / np.linalg.norm(I @ L), "even with I⁻¹(t) = 1", "length 1"),
    ("resultants", _resultants_running_total, "as soon as there are two forces", "τ is wrong"),
    ("resultants", _hand_cross_y, "as soon as a force acts off the barycentre", "only its y component"),
    ("dxdt", _dxdt_omega_over_M, "as soon as L ≠ 0", "1/M ×"),
    ("dxdt", _dxdt_diagonal_inertia, "as soon as the inertia is not diagonal", "only the diagonal of I⁻¹_body"),
    ("euler_step", _step_dt_ms, "as soon as P ≠ 0", "0.001 × the right value, the same factor on every input"),
    ("euler_step", _step_global_dt, "as soon as Δt ≠ 0.01", "Δt"),
    ("euler_step", _step_third_column_frozen, "as soon as L ≠ 0", "only its column 3"),
]


@pytest.mark.parametrize("name, fn, feature, kind", UNLISTED, ids=[f"{n}-{i}" for i, (n, *_) in enumerate(UNLISTED)])
def test_a_mistake_no_family_lists_is_named_by_probing(name, fn, feature, kind):
    r = check(name, fn)
    assert (r.passed, r.mistake) == (False, "probed"), r.message
    first = r.message.splitlines()[0]
    assert feature in first and kind in first, first


@pytest.mark.parametrize("name, fn, feature, kind", UNLISTED[:7], ids=[f"{n}-{i}" for i, (n, *_) in
                                                                       enumerate(UNLISTED[:7])])
def test_the_probing_diagnosis_is_french_in_french(name, fn, feature, kind):
    ex.langue("fr")
    try:
        r = check(name, fn)
    finally:
        ex.langue("en")
    assert r.mistake == "probed" and (" dès " in r.message or " même " in r.message), r.message
    for english in ENGLISH:
        assert english not in r.message, (english, r.message)


def test_a_crash_says_the_input_that_triggers_it_in_its_first_line(language):
    def first_point(x, forces):
        r0 = forces[0][0]                       # IndexError with no force
        F, tau = np.zeros(3), np.zeros(3)
        for r, f in forces:
            F, tau = F + f, tau + np.cross(r - x, f)
        return F + 0.0 * r0, tau
    r = check("resultants", first_point)
    first = r.message.splitlines()[0]
    assert r.mistake == "empty_forces" and "forces = []" in first and "IndexError" in first, r.message

    def crashes_with_a_full_inertia(R, Ib):
        assert np.allclose(Ib, np.diag(np.diag(Ib))), "diagonal only"
        return R @ Ib @ R.T
    r = check("inverse_inertia", crashes_with_a_full_inertia)
    first = r.message.splitlines()[0]
    assert r.mistake == "crashes_when" and "AssertionError" in first and "I_body_inv = [[" in first
    assert ("not diagonal" if language == "en" else "pas diagonale") in first, first


def test_the_probe_finds_the_simplest_input_for_simulate(language):
    def breaks_at_zero_steps(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
        if n_steps == 0:
            return [][0]
        return simulate(M, Ib, X0, forces_at, dt, n_steps, step)
    r = check("simulate", breaks_at_zero_steps)
    first = r.message.splitlines()[0]
    assert r.mistake == "crashes_when" and "n_steps = 0" in first and "IndexError" in first, r.message


# =====================================================================================
# What a probe may and may not say
# =====================================================================================

def test_a_factor_is_constant_only_when_it_is_the_same_on_every_probe():
    w1, w2 = np.array([1.0, 2.0, 3.0]), np.array([-1.0, 0.5, 2.0])
    assert constant_factor([(2 * w1, w1), (2 * w2, w2)]) == pytest.approx(2.0)
    assert constant_factor([(2 * w1, w1), (3 * w2, w2)]) is None
    assert factor_text(-1.0) == "its sign is reversed" and "degrees" in factor_text(180 / np.pi)
    assert scalar_factor([12 / 2.0, 12 / 3.0], [[("M", 2.0)], [("M", 3.0)]]) == "12/M"
    assert scalar_factor([2.0, 3.0], [[("M", 2.0)], [("M", 3.0)]]) == "1·M"


def test_a_factor_close_to_one_is_not_called_scaled():
    r = check("velocity", lambda P, M: P / M * 1.00001)
    assert r.mistake == "probed" and " 1 × the right" not in r.message and "1.00001 × the right" in r.message
    r = check("velocity", lambda P, M: P / M + 1e-6 * P[0] ** 2)
    assert r.mistake == "probed" and "digits only" in r.message, r.message


def test_a_factor_that_changes_with_the_input_is_not_constant():
    r = check("angular_velocity", lambda I, L: I @ L * (1 + abs(L[0])))
    assert r.mistake == "probed" and "changes with the input" in r.message, r.message
    r = check("angular_velocity", lambda I, L: I @ L / 2)
    assert r.mistake == "scaled" and "0.5 ×" in r.message, r.message


def test_the_right_function_is_never_probed_wrong():
    for name, fn in SOLUTION.items():
        assert check(name, fn).passed, name


def test_a_known_formula_is_confirmed_on_other_inputs():
    """P / int(M) and P agree whenever 1 <= M < 2: the other inputs tell the two slips apart."""
    assert check("velocity", lambda P, M: P / int(M) if M >= 1 else P / M).mistake == "floor_division"
    assert check("velocity", lambda P, M: P).mistake == "velocity_no_mass"
    assert check("velocity", lambda P, M: P / 1.0).mistake == "velocity_no_mass"


# =====================================================================================
# The library is not an answer, in the notebook too
# =====================================================================================

LIBRARY = [
    ("velocity", lambda P, M: rb.velocity(P, M)),
    ("resultants", lambda x, forces: rb.resultants(x, forces)),
    ("dxdt", lambda M, Ib, X, forces: ref.dxdt(M, Ib, X, forces)),
    ("project_so3", lambda R: rb.rotation.project_so3(R).copy()),
    ("box_inertia", lambda m, s: rb.RigidBody.box(m, s).I_body),
    ("simulate", lambda M, Ib, X0, forces_at, dt, n_steps, step=None: ref.simulate(M, Ib, X0, forces_at, dt, n_steps)),
]


def _helper_with_library(R, Ib):
    return rb.rotation.project_so3(R) @ Ib @ rb.rotation.project_so3(R).T


@pytest.mark.parametrize("name, fn", LIBRARY + [("inverse_inertia", lambda R, Ib: _helper_with_library(R, Ib))],
                         ids=[n for n, _ in LIBRARY] + ["helper"])
def test_an_answer_from_rbcourse_is_named_in_the_notebook(name, fn, language):
    r = check(name, fn)
    assert (r.passed, r.mistake) == (False, "library_call"), r.message
    assert "rbcourse." in r.message.splitlines()[0]


def test_what_a_check_hands_the_student_is_not_the_library():
    """simulate calls the check's own forces_at and step (code of rbcourse): that is the exercise, not a library
    answer; the pushed box's run of the student's simulate is not either."""
    assert check("simulate", simulate).passed
    traj = ex.simulate_or_reference(simulate, euler_step, 0.05, 0.01, problem=ex.pushed_box())
    assert "(your code)" in str(traj.method), traj.method


# =====================================================================================
# check_simulate: plain tuples, lists, the student's own kind of step
# =====================================================================================

def _simulate_reading_attributes(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
    states = [X0]
    X = X0
    for k in range(n_steps):
        X = step(M, Ib, X, forces_at(k * dt, X), dt)
        states.append(X)
    return (np.array([s.x for s in states]), np.array([s.R for s in states]), np.array([s.P for s in states]),
            np.array([s.L for s in states]))


def _simulate_for_lists(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
    X = list(X0)
    out = [list(X)]
    for k in range(n_steps):
        X = list(step(M, Ib, X, forces_at(k * dt, X), dt))
        out.append(X)
    return tuple(np.array([s[i] for s in out], dtype=float) for i in range(4))


def test_simulate_meets_plain_tuples_and_lists(language):
    r = check("simulate", _simulate_reading_attributes)
    assert (r.passed, r.mistake) == (False, "state_attributes"), r.message
    assert check("simulate", _simulate_for_lists).passed


def test_the_check_step_returns_the_students_own_kind():
    from rbcourse.workbook.exercises.loop import own_kind

    def sim_with(step):
        def sim(M, Ib, X0, forces_at, dt, n_steps, step=step):
            return simulate(M, Ib, X0, forces_at, dt, n_steps, step)
        return sim
    assert own_kind(sim_with(euler_step)) == "tuple"
    assert own_kind(sim_with(lambda *a: list(euler_step(*a)))) == "list"
    assert own_kind(sim_with(lambda *a: ex.StateTuple(*euler_step(*a)))) == "state"
    assert own_kind(lambda M, Ib, X0, forces_at, dt, n_steps: None) == "tuple"


# =====================================================================================
# One rule of precision in every check
# =====================================================================================

def _float32(fn):
    def wrong(*args, **kwargs):
        out = fn(*args, **kwargs)
        if isinstance(out, tuple):
            return tuple(np.asarray(a, dtype=np.float32) for a in out)
        return np.asarray(out, dtype=np.float32)
    return wrong


def _nudged(fn, eps):
    def near(*args, **kwargs):
        out = fn(*args, **kwargs)
        if isinstance(out, tuple):
            return tuple(np.asarray(a, dtype=float) * (1 + eps) for a in out)
        return np.asarray(out, dtype=float) * (1 + eps)
    return near


@pytest.mark.parametrize("name", list(SOLUTION))
def test_float32_is_refused_by_every_check(name):
    r = check(name, _float32(SOLUTION[name]))
    assert (r.passed, r.mistake) == (False, "float32"), r.message


@pytest.mark.parametrize("name", [n for n in SOLUTION if n != "project_so3"])
def test_the_same_tolerance_in_every_check(name):
    """1e-7 relative: a result off by 1e-9 passes, one off by 1e-5 is refused, in every check."""
    assert check(name, _nudged(SOLUTION[name], 1e-9)).passed
    assert not check(name, _nudged(SOLUTION[name], 1e-5)).passed


# =====================================================================================
# A function right on every input, once: state kept between calls
# =====================================================================================

def _stateful_cases():
    by_id, by_mass, total = {}, {}, [np.zeros(3)]

    def velocity_by_id(P, M):                       # a cache keyed by the array: P changed in place → stale
        return by_id.setdefault((id(P), M), P / M)

    def box_by_mass(mass, size):                    # a cache keyed by the mass: another box of that mass → stale
        return by_mass.setdefault(mass, box_inertia(mass, size))

    def resultants_total(x, forces):                # a total kept between calls
        F, tau = resultants(x, forces)
        total[0] = total[0] + F
        return total[0].copy(), tau

    runs = {}

    def simulate_by_id(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):   # a run cached by id(X0)
        key = (id(X0), id(forces_at), dt, n_steps)
        if key not in runs:
            runs[key] = simulate(M, Ib, X0, forces_at, dt, n_steps, step)
        return runs[key]
    return [("velocity", velocity_by_id), ("box_inertia", box_by_mass), ("resultants", resultants_total),
            ("simulate", simulate_by_id)]


@pytest.mark.parametrize("index", range(4))
def test_an_answer_from_an_earlier_call_is_named(index, language):
    name, fn = _stateful_cases()[index]
    r = check(name, fn)
    if index == 0:          # a cache keyed by id(P): Python reuses ids, so it may also answer wrongly on a new input
        assert not r.passed and r.mistake in ("stateful", "probed"), r.message
        return
    assert (r.passed, r.mistake) == (False, "stateful"), r.message
    assert ("earlier call" if language == "en" else "appel précédent") in r.message


def test_a_library_error_never_stands_for_the_students_mistake(language):
    """rbcourse's own validation (in English or French) is not the student's line: the call itself is named."""
    r = check("velocity", lambda P, M: rb.velocity(P, -M))
    assert r.mistake == "library_call" and "must be" not in r.message and "doit" not in r.message, r.message


def test_special_case_shortcuts_meet_the_inputs_that_break_them():
    """A shortcut for a cube (a = b taken for a = b = c) or for R = I (np.allclose(R, I)) is wrong on inputs the
    checks hold: a square section, an R stretched by a few 1e-6."""
    def box_square(mass, size):
        a, b, c = size
        return mass * a * a / 6 * np.eye(3) if a == b else box_inertia(mass, size)

    def inverse_shortcut(R, Ib):
        return np.array(Ib, dtype=float) if np.allclose(R, np.eye(3)) else R @ Ib @ R.T
    assert not check("box_inertia", box_square).passed
    assert not check("inverse_inertia", inverse_shortcut).passed


def test_thresholds_and_clamps_meet_the_ends_of_the_scales():
    """Inputs at the ends of their scales, all valid: a small L, small forces, a force given twice, a fast spin, a
    run as long as the notebook's, far away — a threshold, a set of forces, a clamp, recursion or an early stop shows,
    and is said by what shows it, not by a formula that vanishes there."""
    def omega_threshold(I_inv, L):
        return np.zeros(3) if np.linalg.norm(L) < 1e-6 else I_inv @ L

    def forces_threshold(x, forces):
        return resultants(x, [(r, F) for r, F in forces if np.linalg.norm(F) > 1e-6])

    def forces_as_set(x, forces):
        unique = {(tuple(r), tuple(F)) for r, F in forces}
        return resultants(x, [(np.array(r), np.array(F)) for r, F in unique])

    def step_clamped(M, Ib, X, forces, dt):
        x, R, P, L = X
        omega = R @ Ib @ R.T @ L
        speed = np.linalg.norm(omega)
        omega = omega * min(1.0, 50.0 / speed) if speed else omega
        v, _, F, tau = dxdt(M, Ib, X, forces)
        return x + dt * v, R + dt * star(omega) @ R, P + dt * F, L + dt * tau

    def simulate_recursive(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
        if n_steps == 0:
            return tuple(np.array([np.asarray(a, float)]) for a in X0)
        x, R, P, L = simulate_recursive(M, Ib, X0, forces_at, dt, n_steps - 1, step)
        X = (x[-1], R[-1], P[-1], L[-1])
        Y = step(M, Ib, X, forces_at((n_steps - 1) * dt, X), dt)
        return tuple(np.concatenate([a, np.asarray(y, float)[None]]) for a, y in zip((x, R, P, L), Y))

    def simulate_stops_far(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
        if np.linalg.norm(X0[0]) > 100:
            n_steps = 0
        return simulate(M, Ib, X0, forces_at, dt, n_steps, step)
    expected = [("angular_velocity", omega_threshold, "L is tiny"), ("resultants", forces_threshold, "small (1e-8 N)"),
                ("resultants", forces_as_set, None), ("euler_step", step_clamped, "spins fast"),
                ("simulate", simulate_recursive, "long"), ("simulate", simulate_stops_far, None)]
    for name, fn, words in expected:
        r = check(name, fn)
        assert not r.passed and r.mistake not in ("wrong_result", "error", "cross_for_product", "rounded"), r.message
        assert words is None or words in r.message.splitlines()[0], r.message


# =====================================================================================
# Issue 46: the checks' and the exercise helpers' own arguments; an endless loop in a check
# =====================================================================================

@pytest.mark.parametrize("kwargs, words", [({"seed": "a"}, "seed must be an integer"), ({"seed": -1}, "seed must be"),
                                           ({"seed": True}, "seed must be"), ({"verbose": "no"}, "verbose must be")])
def test_a_checks_own_arguments_are_checked(kwargs, words):
    for check_fn in (ex.check_velocity, ex.check_simulate):
        with pytest.raises(ValueError, match=words):
            check_fn(velocity, **kwargs)


@pytest.mark.parametrize("call, words", [
    (lambda: ex.pushed_box(t_push=-1), "t_push must be >= 0"),
    (lambda: ex.simulate_or_reference(simulate, euler_step, 1.0, 0.01, problem="box"), "problem must be a box"),
    (lambda: ex.simulate_or_reference(simulate, euler_step, 1.0, float("nan")), "dt must be finite"),
    (lambda: ex.simulate_or_reference(simulate, euler_step, -1.0, 0.01), "t_end must be > 0"),
    (lambda: ex.simulate_or_reference(simulate, euler_step, 1.0, 0), "dt must be > 0"),
    (lambda: ex.simulate_or_reference(simulate, euler_step, 1e9, 1e-6), "t_end / dt must be at most"),
    (lambda: ex.show_iterations(euler_step, iterations="2"), "iterations must be an integer"),
    (lambda: ex.show_iterations(euler_step, iterations=-3), "iterations must be an integer in"),
    (lambda: ex.show_iterations(euler_step, dt=-1), "dt must be > 0")])
def test_the_exercise_helpers_check_their_arguments(call, words):
    with pytest.raises((ValueError, TypeError), match=words):
        call()


def test_an_endless_loop_is_out_of_time(monkeypatch):
    from rbcourse.workbook.exercises import harness
    monkeypatch.setattr(harness, "LIMIT", 0.3)

    def endless(P, M):
        while True:
            pass

    def simulate_endless(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
        while True:
            pass
    for name, fn in (("velocity", endless), ("simulate", simulate_endless)):
        r = check(name, fn)
        assert (r.passed, r.mistake) == (False, "out_of_time"), r.message
