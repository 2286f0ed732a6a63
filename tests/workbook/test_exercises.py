"""The exercise checks (rbcourse.workbook.exercises): each deliberately wrong implementation gets exactly its
diagnosis, from the solution's functions (loaded from the solution notebook itself).  What every check does
alike (the solution passes, stubs, exceptions, a check never raises, the pushed box) is in
test_exercise_behaviour.py."""
from pathlib import Path

import numpy as np
import pytest

from rbcourse.workbook import exercises as ex
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
    ("project_so3", lambda R: project_so3(R) @ np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),
     "not_nearest", ["nearest R"]),
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
