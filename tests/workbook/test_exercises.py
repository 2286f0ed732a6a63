"""The exercise checks (rbcourse.workbook.exercises): each deliberately wrong implementation gets exactly its
diagnosis; the solution passes; a stub is "not done yet"; an exception is a clean message; a check
never raises."""
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import rbcourse as rb
from rbcourse.workbook import exercises as ex
from rbcourse.workbook.exercises import mistakes
from rbcourse.rotation import rotation_about
from rbcourse.workbook.assignment import solution_functions


# =====================================================================================
# The solution: the functions of notebooks/solutions/01_exercise_euler.ipynb, from the notebook itself
# =====================================================================================

NOTEBOOK = Path(__file__).resolve().parents[2] / "notebooks" / "solutions" / "01_exercise_euler.ipynb"
FUNCTIONS = solution_functions(NOTEBOOK)
SOLUTION = {name: FUNCTIONS[name] for name in ("box_inertia", "velocity", "inverse_inertia", "angular_velocity",
                                               "resultants", "dxdt", "euler_step", "simulate", "project_so3",
                                               "euler_step_projected")}
# the names the wrong implementations below (and test_mistakes.py) are built from
(box_inertia, velocity, inverse_inertia, angular_velocity, resultants, star, dxdt, euler_step, simulate, project_so3,
 euler_step_projected) = (FUNCTIONS[name] for name in (
    "box_inertia", "velocity", "inverse_inertia", "angular_velocity", "resultants", "star", "dxdt", "euler_step",
    "simulate", "project_so3", "euler_step_projected"))


def check(name, fn, **kw):
    return getattr(ex, f"check_{name}")(fn, verbose=False, **kw)


# =====================================================================================
# Wrong implementations: (check, function, the mistake it must be diagnosed as, words in the message)
# =====================================================================================

def _box(f):
    def box(mass, size):
        a, b, c = size
        return f(mass, a, b, c)
    return box


def _dxdt_with(v=None, w=None, R_dot=None, F=None, tau=None, dP=None, dL=None, I_inv=None):
    """dX/dt with one piece replaced: each option is a function of the pieces."""
    def wrong(M, I_body_inv, X, forces):
        x, R, P, L = X
        J = I_inv(R, I_body_inv) if I_inv else R @ I_body_inv @ R.T
        omega = w(J, P, L) if w else J @ L
        Fr, tr = resultants(x, forces)
        if F or tau:
            Fr, tr = (F or (lambda x, fs: resultants(x, fs)[0]))(x, forces), (tau or (lambda x, fs: tr))(x, forces)
        S = star(omega)
        return ((v(P, L, M) if v else P / M), (R_dot(S, R) if R_dot else S @ R),
                (dP(Fr, M) if dP else Fr), (dL(J, tr) if dL else tr))
    return wrong


def _euler_with(dxdt_fn=dxdt, update=None):
    """An Euler step built on dxdt_fn; update(X, d, dt, M, Ib) -> the new state replaces the slides' one."""
    def wrong(M, I_body_inv, X, forces, dt):
        d = dxdt_fn(M, I_body_inv, X, forces)
        if update:
            return update(X, d, dt, M, I_body_inv)
        return tuple(a + dt * b for a, b in zip(X, d))
    return wrong


def _semi_implicit_P(M, Ib, X, forces, dt):
    x, R, P, L = X
    v, R_dot, F, tau = dxdt(M, Ib, X, forces)
    P_new = P + dt * F
    return x + dt * P_new / M, R + dt * R_dot, P_new, L + dt * tau


def _semi_implicit_L(M, Ib, X, forces, dt):
    x, R, P, L = X
    v, R_dot, F, tau = dxdt(M, Ib, X, forces)
    L_new = L + dt * tau
    omega_new = (R @ Ib @ R.T) @ L_new
    return x + dt * v, R + dt * star(omega_new) @ R, P + dt * F, L_new


def _in_place_euler(M, Ib, X, forces, dt):
    x, R, P, L = X
    v, R_dot, F, tau = dxdt(M, Ib, X, forces)
    x += dt * v                                          # changes the caller's x
    return x, R + dt * R_dot, P + dt * F, L + dt * tau


def _sim(record_from=0, record_to=None, time=lambda k, dt: k * dt, state_for_forces=None, use_step=True,
         n_calls=None):
    """A simulate loop with one thing changed."""
    def wrong(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
        X = X0
        states = [X0]
        for k in range(n_steps if n_calls is None else n_calls(n_steps)):
            forces = forces_at(time(k, dt), state_for_forces(X0, X) if state_for_forces else X)
            X = (step if use_step else euler_step)(M, Ib, X, forces, dt)
            states.append(X)
        while len(states) < n_steps + 1:
            states.append(X)
        states = states[record_from:record_to]
        return tuple(np.array([s[i] for s in states]) for i in range(4))
    return wrong


def _sim_aliasing(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
    x, R, P, L = (np.array(a, dtype=float) for a in X0)
    xs, Rs, Ps, Ls = [x], [R], [P], [L]
    for k in range(n_steps):
        nx, nR, nP, nL = step(M, Ib, (x, R, P, L), forces_at(k * dt, (x, R, P, L)), dt)
        x[:], R[:], P[:], L[:] = nx, nR, nP, nL             # in place: every entry is the same array
        xs.append(x), Rs.append(R), Ps.append(P), Ls.append(L)
    return np.array(xs), np.array(Rs), np.array(Ps), np.array(Ls)


def _sim_modifies_X0(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
    X0[0][:] = X0[0] + 0.0 * dt
    X0[2][0] += 1.0                                          # changes the caller's P
    return simulate(M, Ib, X0, forces_at, dt, n_steps, step)


def _sim_no_step(M, Ib, X0, forces_at, dt, n_steps):
    return simulate(M, Ib, X0, forces_at, dt, n_steps)


def _gram_schmidt(R):
    a, b = R[:, 0], R[:, 1]
    e1 = a / np.linalg.norm(a)
    b = b - (e1 @ b) * e1
    e2 = b / np.linalg.norm(b)
    return np.column_stack([e1, e2, np.cross(e1, e2)])


def _svd(f):
    def wrong(R):
        U, S, Vt = np.linalg.svd(R)
        return f(R, U, S, Vt)
    return wrong


def _projected_with(step, project=project_so3, before=False):
    def wrong(M, Ib, X, forces, dt):
        if before:
            x, R, P, L = X
            return step(M, Ib, (x, project(R), P, L), forces, dt)
        x, R, P, L = step(M, Ib, X, forces, dt)
        return x, project(R), P, L
    return wrong


def _resultants_with(F=None, tau=None):
    def wrong(x, forces):
        Fs, taus = np.zeros(3), np.zeros(3)
        for r, F_i in forces:
            Fs = F(Fs, F_i) if F else Fs + F_i
            taus = tau(taus, r, x, F_i) if tau else taus + np.cross(r - x, F_i)
        return Fs, taus
    return wrong


WRONG = [
    # box_inertia
    ("box_inertia", _box(lambda m, a, b, c: m / 12 * np.diag([b + c, a + c, a + b])), "box_not_squared", ["squared"]),
    ("box_inertia", _box(lambda m, a, b, c: m / 12 * np.diag([a**2 + b**2, a**2 + c**2, b**2 + c**2])),
     "box_wrong_pairing", ["paired", "perpendicular"]),
    ("box_inertia", _box(lambda m, a, b, c: m / 12 * np.diag([a**2, b**2, c**2])), "box_wrong_pairing", ["paired"]),
    ("box_inertia", _box(lambda m, a, b, c: m * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])),
     "box_missing_twelfth", ["1/12"]),
    ("box_inertia", _box(lambda m, a, b, c: m / 12 * np.diag([(b / 2)**2 + (c / 2)**2, (a / 2)**2 + (c / 2)**2,
                                                              (a / 2)**2 + (b / 2)**2])), "box_half_sizes", ["half"]),
    ("box_inertia", _box(lambda m, a, b, c: np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2]) / 12),
     "box_missing_mass", ["mass"]),
    ("box_inertia", _box(lambda m, a, b, c: m / 12 * np.array([b**2 + c**2, a**2 + c**2, a**2 + b**2])),
     "box_moments_not_matrix", ["3×3", "np.diag"]),
    # velocity
    ("velocity", lambda P, M: P * M, "velocity_times_mass", ["P / M", "multiplied"]),
    ("velocity", lambda P, M: M / P, "velocity_mass_over_P", ["M / P"]),
    # inverse_inertia
    ("inverse_inertia", lambda R, Ib: Ib, "I_body_as_world", ["world inertia", "R(t) · I⁻¹_body · R(t)ᵀ"]),
    ("inverse_inertia", lambda R, Ib: np.linalg.inv(R) @ Ib @ R, "R_inverse_I_R", ["R⁻¹", "wrong side"]),
    ("inverse_inertia", lambda R, Ib: R.T @ Ib @ R, "R_inverse_I_R", ["Rᵀ · I⁻¹_body · R"]),
    ("inverse_inertia", lambda R, Ib: R @ Ib, "missing_RT", ["Rᵀ is missing"]),
    ("inverse_inertia", lambda R, Ib: np.linalg.inv(R @ Ib @ R.T), "inverse_inertia_not_inverted", ["I(t)", "inverse"]),
    ("inverse_inertia", lambda R, Ib: R * Ib * R.T, "elementwise", ["element by element", "@"]),
    # angular_velocity
    ("angular_velocity", lambda I_inv, L: I_inv * L, "elementwise", ["element by element"]),
    ("angular_velocity", lambda I_inv, L: np.linalg.inv(I_inv) @ L, "omega_uses_inertia", ["I(t)"]),
    # resultants
    ("resultants", _resultants_with(tau=lambda t, r, x, F: t + np.cross(F, r - x)), "tau_sign",
     ["wrong sign", "(rᵢ − x) ∧ Fᵢ", "Les Formules"]),
    ("resultants", _resultants_with(tau=lambda t, r, x, F: t + np.cross(r, F)), "lever_arm", ["rᵢ − x(t)", "origin"]),
    ("resultants", _resultants_with(tau=lambda t, r, x, F: t + np.cross(F, r)), "tau_sign_and_lever_arm",
     ["two mistakes"]),
    ("resultants", _resultants_with(F=lambda Fs, F: F, tau=lambda t, r, x, F: np.cross(r - x, F)), "last_force_only",
     ["last force", "F += Fᵢ"]),
    ("resultants", lambda x, forces: resultants(x, forces)[::-1], "F_tau_swapped", ["(F, τ)"]),
    ("resultants", lambda x, forces: (sum(F for _, F in forces), sum(np.cross(r - x, F) for r, F in forces)),
     "empty_forces", ["forces = []", "np.zeros(3)"]),
    ("resultants", lambda x, forces: (np.stack([F for _, F in forces]).sum(0),
                                      np.cross(np.stack([r for r, _ in forces]) - x, np.stack([F for _, F in forces])).sum(0)),
     "empty_forces", ["ValueError"]),
    # dxdt
    ("dxdt", _dxdt_with(R_dot=lambda S, R: R @ S), "R_dot_order", ["ω* · R", "R · ω*", "Les Formules"]),
    ("dxdt", _dxdt_with(R_dot=lambda S, R: S), "R_dot_missing_R", ["ω* alone"]),
    ("dxdt", _dxdt_with(R_dot=lambda S, R: S.T @ R), "omega_star_sign", ["wrong sign", "ω ∧ a"]),
    ("dxdt", _dxdt_with(w=lambda J, P, L: J @ P), "omega_from_P", ["from P", "moment cinétique", "Vecteur d'état"]),
    ("dxdt", _dxdt_with(v=lambda P, L, M: L / M), "v_from_L", ["from L", "quantité de mouvement"]),
    ("dxdt", _dxdt_with(v=lambda P, L, M: L / M, w=lambda J, P, L: J @ P), "P_L_swapped", ["swapped"]),
    ("dxdt", _dxdt_with(v=lambda P, L, M: P), "dx_is_P", ["dx/dt = v = P / M"]),
    ("dxdt", _dxdt_with(dP=lambda F, M: F / M), "dP_is_acceleration", ["dP/dt = F"]),
    ("dxdt", _dxdt_with(dL=lambda J, tau: J @ tau), "dL_is_angular_acceleration", ["dL/dt = τ"]),
    ("dxdt", _dxdt_with(I_inv=lambda R, Ib: Ib), "I_body_as_world", ["I⁻¹(t): ", "world inertia"]),
    ("dxdt", _dxdt_with(I_inv=lambda R, Ib: R.T @ Ib @ R), "R_inverse_I_R", ["I⁻¹(t): "]),
    ("dxdt", _dxdt_with(tau=lambda x, fs: sum(np.cross(F, r - x) for r, F in fs)), "tau_sign", ["F, τ: ", "wrong sign"]),
    ("dxdt", _dxdt_with(tau=lambda x, fs: sum(np.cross(r, F) for r, F in fs)), "lever_arm", ["rᵢ − x(t)"]),
    ("dxdt", _dxdt_with(v=lambda P, L, M: P * M), "velocity_times_mass", ["v: "]),
    # euler_step
    ("euler_step", _euler_with(update=lambda X, d, dt, M, Ib: (X[0] + dt * d[0], X[1], X[2] + dt * d[2], X[3] + dt * d[3])),
     "R_not_updated", ["R is not updated", "Evolution temporelle (Euler)"]),
    ("euler_step", _euler_with(update=lambda X, d, dt, M, Ib: (X[0], X[1] + dt * d[1], X[2] + dt * d[2], X[3] + dt * d[3])),
     "x_not_updated", ["x is not updated"]),
    ("euler_step", _euler_with(update=lambda X, d, dt, M, Ib: (X[0] + dt * d[0], X[1] + dt * d[1], X[2], X[3] + dt * d[3])),
     "P_not_updated", ["P is not updated"]),
    ("euler_step", _euler_with(update=lambda X, d, dt, M, Ib: (X[0] + dt * d[0], X[1] + dt * d[1], X[2] + dt * d[2], X[3])),
     "L_not_updated", ["L is not updated"]),
    ("euler_step", _semi_implicit_P, "semi_implicit", ["semi-implicit", "X(t)", "Itération 1"]),
    ("euler_step", _semi_implicit_L, "semi_implicit", ["semi-implicit"]),
    ("euler_step", _euler_with(update=lambda X, d, dt, M, Ib: tuple(a + b for a, b in zip(X, d))), "no_dt", ["Δt"]),
    ("euler_step", _in_place_euler, "modified_input", ["in place", "X"]),
    ("euler_step", _euler_with(_dxdt_with(R_dot=lambda S, R: R @ S)), "R_dot_order", ["dX/dt: ", "R · ω*"]),
    ("euler_step", _euler_with(_dxdt_with(w=lambda J, P, L: J @ P)), "omega_from_P", ["dX/dt: "]),
    ("euler_step", _euler_with(_dxdt_with(tau=lambda x, fs: sum(np.cross(F, r - x) for r, F in fs))), "tau_sign",
     ["dX/dt: F, τ: "]),
    # simulate
    ("simulate", _sim(record_from=1), "missing_initial", ["X₀"]),
    ("simulate", _sim(record_to=-1), "missing_final", ["X_n"]),
    ("simulate", _sim(record_from=0, record_to=-2), "wrong_length", ["n_steps + 1"]),
    ("simulate", _sim_aliasing, "aliasing", ["in place"]),
    ("simulate", _sim(time=lambda k, dt: (k + 1) * dt), "wrong_time", ["k · Δt"]),
    ("simulate", _sim(time=lambda k, dt: 0.0), "wrong_time", ["k · Δt"]),
    ("simulate", _sim(time=lambda k, dt: k), "wrong_time", ["k · Δt"]),
    ("simulate", _sim(state_for_forces=lambda X0, X: X0), "stale_state", ["current state"]),
    ("simulate", _sim(use_step=False), "ignores_step", ["never called the step"]),
    ("simulate", _sim(n_calls=lambda n: n - 1), "step_count", ["n_steps times"]),
    ("simulate", _sim_no_step, "no_step_parameter", ["step=euler_step"]),
    ("simulate", _sim_modifies_X0, "modified_input", ["X0"]),
    # project_so3
    ("project_so3", _svd(lambda R, U, S, Vt: U @ Vt.T), "svd_V_transposed", ["U @ Vt"]),
    ("project_so3", _svd(lambda R, U, S, Vt: U @ np.diag(S) @ Vt), "svd_not_projected", ["unchanged"]),
    ("project_so3", lambda R: R / np.linalg.norm(R, axis=0), "columns_normalized", ["perpendicular"]),
    ("project_so3", lambda R: project_so3(R).T, "projection_transposed", ["transpose"]),
    ("project_so3", lambda R: project_so3(R) @ rotation_about([0, 0, 1], np.pi / 2), "not_nearest", ["far from R"]),
    ("project_so3", lambda R: 1.5 * R, "not_a_rotation", ["not a rotation"]),
    # euler_step_projected
    ("euler_step_projected", euler_step, "step_not_projected", ["not projected"]),
    ("euler_step_projected", _projected_with(euler_step, before=True), "projected_before", ["after the Euler step"]),
    ("euler_step_projected",
     _projected_with(_euler_with(update=lambda X, d, dt, M, Ib: (X[0] + dt * d[0], X[1], X[2] + dt * d[2], X[3] + dt * d[3]))),
     "R_not_updated", ["the Euler step: ", "R is not updated"]),
]


@pytest.mark.parametrize("name, fn, mistake, words", WRONG, ids=[f"{w[0]}-{w[2]}-{i}" for i, w in enumerate(WRONG)])
def test_each_mistake_gets_its_own_diagnosis(name, fn, mistake, words):
    r = check(name, fn)
    assert not r.passed
    assert r.mistake == mistake, r.message
    for w in words:
        assert w in r.message, (w, r.message)
    assert r.message.startswith(f"✗ {name}: ")
    m = ex.MISTAKES[mistake]
    assert m.text.split(":")[0] in r.message
    assert f"→ reread the slide “{m.slide}”" in r.message or (m.slide not in ex.SLIDES and f"→ reread {m.slide}" in r.message)


def test_every_mistake_names_a_slide():
    """Each mistake points where its formula is: a slide, Baraff's notes (the box), or Part 8 (the projection);
    never the slide "Bibliographie", which holds only the reference line."""
    for m in ex.MISTAKES.values():
        assert m.slide in ex.SLIDES or "Baraff" in m.slide or m.slide.startswith("Part 8"), m
        assert m.slide != "Bibliographie", m
    assert set(ex.SLIDES) >= {"Les Formules", "Vecteur d'état du Rigidbody", "Evolution temporelle (Euler)",
                              "Itération 1", "Itération 2"}


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
    assert check("resultants", lambda x, fs: rb.resultants(x, fs)).passed
    assert check("resultants", lambda x, fs: np.array(rb.resultants(x, fs))).passed
    assert check("dxdt", lambda M, Ib, X, fs: rb.StateDerivative(*dxdt(M, Ib, X, fs))).passed
    assert check("euler_step", lambda *a: ex.StateTuple(*euler_step(*a))).passed
    assert check("simulate", lambda *a, **k: ex.StateTuple(*simulate(*a, **k))).passed
    assert check("box_inertia", lambda m, s: rb.RigidBody.box(m, s).I_body).passed


def test_simulate_with_accumulated_time_passes():
    def sim(M, Ib, X0, forces_at, dt, n_steps, step=euler_step):
        X, t, out = X0, 0.0, [X0]
        for _ in range(n_steps):
            X = step(M, Ib, X, forces_at(t, X), dt)
            t += dt
            out.append(X)
        return tuple(np.array([s[i] for s in out]) for i in range(4))
    assert check("simulate", sim).passed


def test_gram_schmidt_passes_with_a_note():
    r = check("project_so3", _gram_schmidt)
    assert r.passed and "Gram–Schmidt" in r.message


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
    assert (r.passed, r.mistake) == (False, "error")
    assert r.message.startswith("✗ velocity raised ValueError: ")
    assert "(in velocity, line " in r.message and "return P @ M" in r.message
    assert "on the input P = [" in r.message
    assert "Traceback" not in r.message and "File " not in r.message


def test_errors_inside_numpy_point_at_the_students_line():
    def inverse_inertia(R, Ib):
        R_T = np.transpose(R, (0, 1, 2))
        return R @ Ib @ R_T
    r = check("inverse_inertia", inverse_inertia)
    assert r.mistake == "error" and "in inverse_inertia, line" in r.message and "np.transpose" in r.message


@pytest.mark.parametrize("out, mistake", [
    (None, "returned_none"), ("hello", "not_numbers"), (object(), "not_numbers"), (np.zeros((3, 1)), "wrong_shape"),
    (np.zeros(4), "wrong_shape"), (np.full(3, np.nan), "wrong_result"), (np.ones(3), "wrong_result"),
])
def test_bad_outputs(out, mistake):
    r = check("velocity", lambda P, M: out)
    assert (r.passed, r.mistake) == (False, mistake), r.message
    assert "\n   → reread the slide “Evolution temporelle (Euler)”" in r.message


def test_wrong_result_shows_input_expected_and_got():
    r = check("velocity", lambda P, M: P / M + 1.0)
    assert r.mistake == "wrong_result"
    assert re.search(r"wrong result: expected \[.+\], got \[.+\] — on the input P = \[.+\], M = ", r.message)


def test_tuple_results_wrong_part_is_named():
    r = check("dxdt", lambda M, Ib, X, fs: (*dxdt(M, Ib, X, fs)[:3], np.ones(3)))
    assert r.mistake == "wrong_result" and "dL/dt should be" in r.message
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
    assert check("velocity", quits).mistake == "error"


def test_the_checks_are_deterministic():
    wrong = lambda P, M: P / M + 0.5  # noqa: E731
    assert check("velocity", wrong).message == check("velocity", wrong).message
    assert check("simulate", _sim(record_to=-1)).message == check("simulate", _sim(record_to=-1)).message


def test_the_check_prints_once_in_a_notebook(capsys, monkeypatch):
    cell = [7]
    monkeypatch.setattr(mistakes, "execution_count", lambda: cell[0])
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
    assert (r.passed, r.mistake) == (False, "error") or r.mistake in ("empty_forces", "no_step_parameter")
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
