"""The catalogue of mistakes, grown (issue 15, item 1): each wrong implementation below — the cases the issue
found, then more that students write — is fed to its check, which must give exactly its diagnosis (the
mistake's id and its text), from the function's behaviour alone.  The solution and the first catalogue are
in test_exercises.py (loaded here by path)."""
import importlib.util
import pathlib

import numpy as np
import pytest
from scipy.linalg import expm

from rbcourse.workbook import exercises as ex

_spec = importlib.util.spec_from_file_location("_exercise_tests", pathlib.Path(__file__).with_name("test_exercises.py"))
base = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(base)

check, star, resultants, dxdt, euler_step = base.check, base.star, base.resultants, base.dxdt, base.euler_step
inverse_inertia, velocity, project_so3 = base.inverse_inertia, base.velocity, base.project_so3
_dxdt_with, _euler_with, _resultants_with, _svd, _box = (base._dxdt_with, base._euler_with, base._resultants_with,
                                                          base._svd, base._box)


# =====================================================================================
# Wrong implementations, written as a student would (a function body, not a formula table)
# =====================================================================================

def inverse_inertia_with_inv(R, I_body_inv):
    return R @ I_body_inv @ np.linalg.inv(R)             # R⁻¹ for Rᵀ: right only when R is a rotation


def dxdt_with_inv(M, I_body_inv, X, forces):
    x, R, P, L = X
    I_inv = R @ I_body_inv @ np.linalg.inv(R)
    F, tau = resultants(x, forces)
    return P / M, star(I_inv @ L) @ R, F, tau


def project_no_fix(R):
    U, S, Vt = np.linalg.svd(R)
    return U @ Vt


def project_negated(R):
    U, S, Vt = np.linalg.svd(R)
    Q = U @ Vt
    return -Q if np.linalg.det(Q) < 0 else Q


def project_first_column(R):
    U, S, Vt = np.linalg.svd(R)
    if np.linalg.det(U @ Vt) < 0:
        U[:, 0] *= -1
    return U @ Vt


def project_always_flipped(R):
    U, S, Vt = np.linalg.svd(R)
    U[:, 2] *= -1
    return U @ Vt


def velocity_list(P, M):
    return [p / M for p in P]


def velocity_int(P, M):
    v = np.array([0, 0, 0])
    for i in range(3):
        v[i] = P[i] / M
    return v


def velocity_swapped(M, P):
    return P / M


def resultants_missing_last(x, forces):
    F, tau = np.zeros(3), np.zeros(3)
    for i in range(len(forces) - 1):
        r, F_i = forces[i]
        F = F + F_i
        tau = tau + np.cross(r - x, F_i)
    return F, tau


def resultants_return_in_loop(x, forces):
    F, tau = np.zeros(3), np.zeros(3)
    for r, F_i in forces:
        F = F + F_i
        tau = tau + np.cross(r - x, F_i)
        return F, tau
    return F, tau


def resultants_dot(x, forces):
    F, tau = np.zeros(3), np.zeros(3)
    for r, F_i in forces:
        F = F + F_i
        tau = tau + np.dot(r - x, F_i)
    return F, tau


def resultants_int(x, forces):
    F, tau = np.zeros(3, dtype=int), np.zeros(3)
    for r, F_i in forces:
        F[:] = F + F_i
        tau = tau + np.cross(r - x, F_i)
    return F, tau


def resultants_swapped(forces, x):
    return resultants(x, forces)


def _euler_parts(M, Ib, X, forces, dt):
    x, R, P, L = X
    v, R_dot, F, tau = dxdt(M, Ib, X, forces)
    return x, R, P, L, v, R_dot, F, tau


def euler_L_with_F(M, Ib, X, forces, dt):
    x, R, P, L, v, R_dot, F, tau = _euler_parts(M, Ib, X, forces, dt)
    return x + dt * v, R + dt * R_dot, P + dt * F, L + dt * F


def euler_dt_twice(M, Ib, X, forces, dt):
    x, R, P, L, v, R_dot, F, tau = _euler_parts(M, Ib, X, forces, dt)
    d = [dt * a for a in (v, R_dot, F, tau)]               # "dX = dt * dX/dt", then X + dt * dX
    return x + dt * d[0], R + dt * d[1], P + dt * d[2], L + dt * d[3]


def euler_expm(M, Ib, X, forces, dt):
    x, R, P, L, v, R_dot, F, tau = _euler_parts(M, Ib, X, forces, dt)
    omega = R @ Ib @ R.T @ L
    return x + dt * v, expm(dt * star(omega)) @ R, P + dt * F, L + dt * tau


def euler_projected(M, Ib, X, forces, dt):
    x, R, P, L = euler_step(M, Ib, X, forces, dt)
    return x, project_so3(R), P, L


def euler_R_dot_R(M, Ib, X, forces, dt):
    x, R, P, L, v, R_dot, F, tau = _euler_parts(M, Ib, X, forces, dt)
    return x + dt * v, R + dt * R_dot @ R, P + dt * F, L + dt * tau


def euler_swapped(M, Ib, X, dt, forces):
    return euler_step(M, Ib, X, forces, dt)


def euler_list(M, Ib, X, forces, dt):
    x, R, P, L = euler_step(M, Ib, X, forces, dt)
    return list(x), R, P, L


def star_bad_sign(w):                  # one sign wrong in the last row
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [w[1], w[0], 0.0]])


def star_misplaced(w):                 # ω_x and ω_z exchanged
    return np.array([[0.0, -w[0], w[1]], [w[0], 0.0, -w[2]], [-w[1], w[2], 0.0]])


def dxdt_star(s):
    def wrong(M, Ib, X, forces):
        x, R, P, L = X
        F, tau = resultants(x, forces)
        return P / M, s(R @ Ib @ R.T @ L) @ R, F, tau
    return wrong


def euler_with_dxdt(d):
    def wrong(M, Ib, X, forces, dt):
        return tuple(a + dt * b for a, b in zip(X, d(M, Ib, X, forces)))
    return wrong


def box_loop_int(mass, size):
    a, b, c = size
    I = np.zeros((3, 3), dtype=int)
    I[0, 0], I[1, 1], I[2, 2] = mass / 12 * (b**2 + c**2), mass / 12 * (a**2 + c**2), mass / 12 * (a**2 + b**2)
    return I


def angular_velocity_matrix(I_inv, L):
    return np.matrix(I_inv) * np.matrix(L).T


def inverse_inertia_complex(R, Ib):
    w, V = np.linalg.eig(R)                               # Rᵀ from R's eigen-decomposition: complex numbers
    return R @ Ib @ (V @ np.diag(w.conj()) @ np.linalg.inv(V))


def project_qr(R):
    Q, _ = np.linalg.qr(R)
    return Q


ISSUE = [
    # R⁻¹ for Rᵀ: caught where R is off SO(3), as Euler leaves it
    ("inverse_inertia", inverse_inertia_with_inv, "R_inverse_not_transpose", ["R⁻¹ instead of Rᵀ", "Euler's R is not one"]),
    ("dxdt", dxdt_with_inv, "R_inverse_not_transpose", ["I⁻¹(t): R⁻¹ instead of Rᵀ"]),
    ("euler_step", euler_with_dxdt(dxdt_with_inv), "R_inverse_not_transpose", ["dX/dt: I⁻¹(t): R⁻¹ instead of Rᵀ"]),
    # det(U Vᵀ) = −1
    ("project_so3", project_no_fix, "svd_no_det_fix", ["det(U Vᵀ) = −1", "reflection"]),
    ("project_so3", project_negated, "svd_negated", ["−U Vᵀ"]),
    ("project_so3", project_first_column, "svd_wrong_column", ["the last one (U[:, 2])"]),
    ("project_so3", project_always_flipped, "svd_flip_always", ["only when det(U Vᵀ) < 0"]),
    # what a function returns
    ("velocity", velocity_list, "returned_list", ["Python list", "TypeError"]),
    ("velocity", velocity_int, "integer_array", ["truncates", "dtype int64"]),
    ("resultants", resultants_int, "integer_array", ["in F: dtype"]),
    ("euler_step", euler_list, "returned_list", ["in x(t+Δt): "]),
    ("box_inertia", box_loop_int, "integer_array", ["truncates"]),
    ("angular_velocity", angular_velocity_matrix, "returned_matrix", ["np.matrix"]),
    ("inverse_inertia", inverse_inertia_complex, "complex_array", ["complex"]),
    # vague before
    ("resultants", resultants_missing_last, "force_skipped", ["left out", "range(len(forces) - 1)"]),
    ("resultants", resultants_return_in_loop, "first_force_only", ["first force"]),
    ("velocity", lambda P, M: P, "velocity_no_mass", ["P itself"]),
    ("dxdt", _dxdt_with(R_dot=lambda S, R: S * R), "R_dot_elementwise", ["element by element", "star(omega) @ R"]),
    ("euler_step", euler_dt_twice, "dt_twice", ["Δt²"]),
    ("resultants", resultants_dot, "dot_for_cross", ["np.cross", "np.dot"]),
    ("dxdt", _dxdt_with(tau=lambda x, fs: sum(np.dot(r - x, F) for r, F in fs)), "dot_for_cross", ["F, τ: ", "np.cross"]),
    ("inverse_inertia", lambda R, Ib: R @ Ib @ R, "missing_transpose", ["R · I⁻¹_body · R"]),
    ("dxdt", dxdt_star(star_bad_sign), "star_wrong", ["cross-product matrix", "ω ∧ a"]),
    ("dxdt", dxdt_star(star_misplaced), "star_wrong", ["cross-product matrix"]),
    ("dxdt", dxdt_star(lambda w: star(w).T), "omega_star_sign", ["wrong sign"]),
    ("euler_step", euler_with_dxdt(dxdt_star(star_bad_sign)), "star_wrong", ["cross-product matrix"]),
    ("euler_step", euler_expm, "R_exact_rotation", ["expm", "R(t) + Δt · ω* R(t)"]),
    ("project_so3", _svd(lambda R, U, S, Vt: Vt @ U), "svd_factors_swapped", ["Vt @ U"]),
    ("velocity", velocity_swapped, "args_swapped", ["wrong order", "velocity(M, P)", "velocity(P, M)"]),
    ("resultants", resultants_swapped, "args_swapped", ["wrong order", "resultants(x, forces)"]),
    ("euler_step", euler_swapped, "args_swapped", ["wrong order", "euler_step(M, I_body_inv, X, forces, dt)"]),
    # misleading before
    ("euler_step", euler_L_with_F, "L_step_uses_F", ["L(t) + Δt · τ(t)", "Δt · F"]),
]

MORE = [
    # box_inertia
    ("box_inertia", _box(lambda m, a, b, c: np.linalg.inv(m / 12 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2]))),
     "box_inverted", ["inverse"]),
    ("box_inertia", _box(lambda m, a, b, c: m / 12 * (a**2 + b**2 + c**2) * np.eye(3)), "box_sum_all", ["two sides"]),
    ("box_inertia", _box(lambda m, a, b, c: [[m / 12 * (b**2 + c**2), 0, 0], [0, m / 12 * (a**2 + c**2), 0],
                                             [0, 0, m / 12 * (a**2 + b**2)]]), "returned_list", ["Python list"]),
    ("box_inertia", lambda mass, size: mass / 12 * np.diag([size[1]**2 + size[2]**2, size[0]**2 + size[2]**2,
                                                            size[0]**2 + size[1]**2])[::-1, ::-1],
     "box_wrong_pairing", ["paired"]),
    # velocity
    ("velocity", lambda P, M: P // M, "floor_division", ["//"]),
    ("velocity", lambda P, M: (P / M).tolist(), "returned_list", ["np.array"]),
    ("velocity", lambda P, M: np.array(P / M, dtype=complex), "complex_array", ["complex"]),
    ("velocity", lambda P, M: np.matrix(P / M), "returned_matrix", ["np.matrix"]),
    # inverse_inertia
    ("inverse_inertia", lambda R, Ib: Ib @ R.T, "missing_R_left", ["R is missing on the left"]),
    ("inverse_inertia", lambda R, Ib: R.T @ Ib, "missing_R_left", ["R is missing on the left"]),
    ("inverse_inertia", lambda R, Ib: np.linalg.inv(R) @ Ib @ R, "R_inverse_I_R", ["wrong side"]),
    ("inverse_inertia", lambda Ib, R: R @ Ib @ R.T, "args_swapped", ["inverse_inertia(Ib, R)"]),
    ("inverse_inertia", lambda R, Ib: (R @ Ib @ R.T).tolist(), "returned_list", ["Python list"]),
    # angular_velocity
    ("angular_velocity", lambda I_inv, L: (I_inv @ L).reshape(3, 1), "column_vector", ["shape (3, 1)", "(3, 1) column"]),
    ("angular_velocity", lambda I_inv, L: list(I_inv @ L), "returned_list", ["Python list"]),
    # resultants
    ("resultants", lambda x, fs: (sum(F for _, F in fs[1:]) + np.zeros(3),
                                  sum(np.cross(r - x, F) for r, F in fs[1:]) + np.zeros(3)), "force_skipped", ["left out"]),
    ("resultants", _resultants_with(tau=lambda t, r, x, F: t + np.cross(x - r, F)), "tau_sign", ["(x − rᵢ) ∧ Fᵢ"]),
    ("resultants", lambda x, fs: (sum((F for _, F in fs), np.zeros(3)),
                                  np.cross(sum((r for r, _ in fs), np.zeros(3)) - x, sum((F for _, F in fs), np.zeros(3)))),
     "tau_of_sums", ["sum of the torques"]),
    ("resultants", lambda x, fs: (np.mean([F for _, F in fs], axis=0) if fs else np.zeros(3),
                                  np.mean([np.cross(r - x, F) for r, F in fs], axis=0) if fs else np.zeros(3)),
     "forces_averaged", ["not averages"]),
    ("resultants", lambda x, fs: resultants(x, [(F, r) for r, F in fs]), "force_pair_order", ["the point first"]),
    ("resultants", lambda x, fs: [list(a) for a in resultants(x, fs)], "returned_list", ["in F: "]),
    # dxdt
    ("dxdt", lambda M, Ib, X, fs: (dxdt(M, Ib, X, fs)[0], Ib @ X[3], *dxdt(M, Ib, X, fs)[2:]), "wrong_shape",
     ["dR/dt has shape"]),
    ("dxdt", lambda M, Ib, X, fs: (dxdt(M, Ib, X, fs)[0], X[1] @ Ib @ X[1].T @ X[3], *dxdt(M, Ib, X, fs)[2:]),
     "R_dot_is_omega", ["the vector ω"]),
    ("dxdt", lambda M, Ib, X, fs: (*dxdt(M, Ib, X, fs)[:2], X[2], dxdt(M, Ib, X, fs)[3]), "dP_is_P", ["P itself"]),
    ("dxdt", lambda M, Ib, X, fs: (*dxdt(M, Ib, X, fs)[:3], X[3]), "dL_is_L", ["L itself"]),
    ("dxdt", _dxdt_with(I_inv=lambda R, Ib: R @ Ib @ R), "missing_transpose", ["I⁻¹(t): "]),
    ("dxdt", _dxdt_with(I_inv=lambda R, Ib: np.linalg.inv(R @ Ib @ R.T)), "inverse_inertia_not_inverted", ["I⁻¹(t): "]),
    ("dxdt", lambda M, Ib, X, fs: (*dxdt(M, Ib, X, fs)[:2], *resultants_missing_last(X[0], fs)), "force_skipped",
     ["F, τ: "]),
    ("dxdt", lambda Ib, M, X, fs: dxdt(M, Ib, X, fs), "args_swapped", ["dxdt(Ib, M, X, fs)"]),
    ("dxdt", lambda M, Ib, X, fs: tuple(np.array(a, dtype=int) for a in dxdt(M, Ib, X, fs)), "integer_array",
     ["in dx/dt: "]),
    # euler_step
    ("euler_step", lambda M, Ib, X, fs, dt: (lambda x, R, P, L, v, Rd, F, t: (x + dt * v, R + dt * Rd, P + dt * t,
                                                                             L + dt * t))(*_euler_parts(M, Ib, X, fs, dt)),
     "P_step_uses_tau", ["Δt · τ"]),
    ("euler_step", euler_projected, "projected_in_euler_step", ["inside euler_step"]),
    ("euler_step", euler_R_dot_R, "R_dot_times_R", ["Ṙ · R"]),
    ("euler_step", lambda M, Ib, X, fs, dt: dxdt(M, Ib, X, fs), "returned_rates", ["the rates"]),
    ("euler_step", lambda M, Ib, X, fs, dt: tuple(dt * d for d in dxdt(M, Ib, X, fs)), "returned_increment",
     ["the change only"]),
    ("euler_step", lambda M, Ib, X, fs, dt: tuple(a - dt * d for a, d in zip(X, dxdt(M, Ib, X, fs))), "euler_minus",
     ["subtracted"]),
    ("euler_step", euler_with_dxdt(_dxdt_with(R_dot=lambda S, R: S * R)), "R_dot_elementwise", ["dX/dt: "]),
    ("euler_step", euler_with_dxdt(lambda M, Ib, X, fs: (*dxdt(M, Ib, X, fs)[:2], *resultants_return_in_loop(X[0], fs))),
     "first_force_only", ["dX/dt: F, τ: "]),
    ("euler_step", euler_with_dxdt(_dxdt_with(I_inv=lambda R, Ib: R @ Ib @ R)), "missing_transpose", ["dX/dt: I⁻¹(t): "]),
    ("euler_step", lambda M, Ib, X, fs, dt: (lambda x, R, P, L, v, Rd, F, t: (x + dt * P, R + dt * Rd, P + dt * F,
                                                                             L + dt * t))(*_euler_parts(M, Ib, X, fs, dt)),
     "dx_is_P", ["dX/dt: dx/dt = v = P / M"]),
    # project_so3
    ("project_so3", _svd(lambda R, U, S, Vt: U), "svd_U_only", ["U alone"]),
    ("project_so3", lambda R: R / np.cbrt(np.linalg.det(R)), "scaled_by_det", ["det(R)^(1/3)"]),
    ("project_so3", lambda R: project_so3(R).tolist(), "returned_list", ["Python list"]),
    ("project_so3", _svd(lambda R, U, S, Vt: Vt.T @ U.T), "projection_transposed", ["transpose"]),
    # euler_step_projected
    ("euler_step_projected", lambda M, Ib, X, fs, dt: (lambda x, R, P, L: (x, project_so3(R), P, L))(
        *euler_L_with_F(M, Ib, X, fs, dt)), "L_step_uses_F", ["the Euler step: "]),
]

def _rates(M, Ib, X, fs):
    x, R, P, L = X
    omega = R @ Ib @ R.T @ L
    return P / M, omega, *resultants(x, fs)


MORE += [
    ("box_inertia", _box(lambda m, a, b, c: m / 3 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])), "box_third", ["M/3"]),
    ("box_inertia", _box(lambda m, a, b, c: m / 12 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + c**2])), "box_one_moment",
     ["I_zz is wrong", "I_zz = M/12 (a² + b²)"]),
    ("velocity", lambda P, M: P / M**2, "velocity_mass_squared", ["twice"]),
    ("velocity", lambda P, M: np.round(P / M, 2), "rounded", ["to 2 decimals", "Evolution temporelle"]),
    ("inverse_inertia", lambda R, Ib: R.T @ Ib @ R.T, "transpose_both", ["Rᵀ · I⁻¹_body · Rᵀ"]),
    ("angular_velocity", lambda I_inv, L: I_inv @ L / 2, "scaled", ["0.5 ×"]),
    ("resultants", lambda x, fs: (sum((F for _, F in fs), np.zeros(3)), np.zeros(3)), "tau_missing", ["τ is zero"]),
    ("resultants", _resultants_with(tau=lambda t, r, x, F: t + np.cross(r + x, F)), "lever_arm_plus", ["rᵢ + x(t)"]),
    ("dxdt", lambda M, Ib, X, fs: (X[2] / M, X[1] @ star(Ib @ X[1].T @ X[3]), *resultants(X[0], fs)), "R_dot_body_frame",
     ["exact rotation"]),
    ("dxdt", lambda M, Ib, X, fs: (lambda v, w, F, t: (v, np.cross(w, X[1]), F, t))(*_rates(M, Ib, X, fs)), "cross_rows",
     ["each row of R"]),
    ("dxdt", lambda M, Ib, X, fs: (lambda d: (d[0], d[1].T, d[2], d[3]))(dxdt(M, Ib, X, fs)), "R_dot_transposed",
     ["(ω* R)ᵀ"]),
    ("dxdt", lambda M, Ib, X, fs: (lambda d: (d[0], d[1], M * d[2], d[3]))(dxdt(M, Ib, X, fs)), "dP_times_mass",
     ["multiplied F by M"]),
    ("dxdt", lambda M, Ib, X, fs: (lambda d: (d[0], d[1], d[3], d[2]))(dxdt(M, Ib, X, fs)), "rates_order",
     ["τ before F"]),
    ("euler_step", lambda M, Ib, X, fs, dt: tuple(a + dt / 2 * d for a, d in zip(X, dxdt(M, Ib, X, fs))), "half_step",
     ["Δt/2"]),
    ("euler_step", lambda M, Ib, X, fs, dt: (lambda s: (s[0], s[2], s[1], s[3]))(euler_step(M, Ib, X, fs, dt)),
     "state_order", ["(x, R, P, L)"]),
    ("euler_step", lambda M, Ib, X, fs, dt: (lambda d: (X[0] + dt * d[0], X[1] + dt * dt * d[1], X[2] + dt * d[2],
                                                        X[3] + dt * d[3]))(dxdt(M, Ib, X, fs)), "dt_twice", ["Δt²"]),
    ("euler_step", lambda M, Ib, X, fs, dt: (lambda s: (s[0], s[1], s[2], np.round(s[3], 3)))(euler_step(M, Ib, X, fs, dt)),
     "rounded", ["in L(t+Δt): ", "to 3 decimals"]),
    ("euler_step_projected", lambda M, Ib, X, fs, dt: euler_step(M, Ib, (X[0], project_so3(X[1]), X[2], X[3]), fs, dt),
     "projected_before", ["not before"]),
]

def euler_moves_x_first(M, Ib, X, forces, dt):
    x, R, P, L = X
    x = x + dt * P / M
    F, tau = resultants(x, forces)                         # the torque about the new x
    return x, R + dt * star(R @ Ib @ R.T @ L) @ R, P + dt * F, L + dt * tau


MORE.append(("euler_step", euler_moves_x_first, "rates_after_update", ["about the new x(t+Δt)", "Itération 1"]))

# --- simulate: the loop's mistakes (issue 15, item 1: forces computed once, one state returned, …)

def _arrays(states):
    return tuple(np.array([s[i] for s in states]) for i in range(4))

def simulate_ok(M, Ib, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(M, Ib, X, forces_at(k * dt, X), dt)
        states.append(X)
    return _arrays(states)

def simulate_forces_once(M, Ib, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    forces = forces_at(0.0, X0)
    for k in range(n_steps):
        X = step(M, Ib, X, forces, dt)
        states.append(X)
    return _arrays(states)

def simulate_last_state(M, Ib, X0, forces_at, dt, n_steps, step=None):
    X = X0
    for k in range(n_steps):
        X = step(M, Ib, X, forces_at(k * dt, X), dt)
    return X

def simulate_extra_step(M, Ib, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    for k in range(n_steps + 1):
        X = step(M, Ib, X, forces_at(k * dt, X), dt)
        states.append(X)
    return _arrays(states)

def simulate_fixed_dt(M, Ib, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(M, Ib, X, forces_at(k * dt, X), 0.01)
        states.append(X)
    return _arrays(states)

def simulate_no_initial(M, Ib, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, []
    for k in range(n_steps):
        X = step(M, Ib, X, forces_at(k * dt, X), dt)
        states.append(X)
    return _arrays(states)

def simulate_same_object(M, Ib, X0, forces_at, dt, n_steps, step=None):
    x, R, P, L = (np.array(a, float) for a in X0)
    xs, Rs, Ps, Ls = [x], [R], [P], [L]
    for k in range(n_steps):
        x1, R1, P1, L1 = step(M, Ib, (x, R, P, L), forces_at(k * dt, (x, R, P, L)), dt)
        x[:], R[:], P[:], L[:] = x1, R1, P1, L1
        xs.append(x); Rs.append(R); Ps.append(P); Ls.append(L)
    return np.array(xs), np.array(Rs), np.array(Ps), np.array(Ls)

def simulate_time_late(M, Ib, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(M, Ib, X, forces_at((k + 1) * dt, X), dt)
        states.append(X)
    return _arrays(states)

def simulate_stale(M, Ib, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(M, Ib, X, forces_at(k * dt, X0), dt)
        states.append(X)
    return _arrays(states)

def simulate_one_short(M, Ib, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    for k in range(n_steps - 1):
        X = step(M, Ib, X, forces_at(k * dt, X), dt)
        states.append(X)
    return _arrays(states)


SIMULATE = [
    ("simulate", simulate_forces_once, "forces_once", ["only once, before the loop", "inside the loop"]),
    ("simulate", simulate_last_state, "returned_one_state", ["returned one state, not the list of states"]),
    ("simulate", simulate_extra_step, "extra_step", ["one step too many"]),
    ("simulate", simulate_fixed_dt, "ignores_dt", ["time step dt", "step got dt = 0.01"]),
    ("simulate", simulate_no_initial, "missing_initial", ["start with X₀"]),
    ("simulate", simulate_one_short, "missing_final", ["X_n is missing"]),
    ("simulate", simulate_same_object, "aliasing", ["the same (the last one)"]),
    ("simulate", simulate_time_late, "wrong_time", ["wrong times", "your times: [0.0"]),
    ("simulate", simulate_stale, "stale_state", ["current state X_k"]),
]
MORE += SIMULATE


def _sim_forces_kept(M, Ib, X0, forces_at, dt, n_steps, step=None):
    """forces += forces_at(…): the forces of past steps keep acting."""
    X, states, forces = X0, [X0], []
    for k in range(n_steps):
        forces = forces + forces_at(k * dt, X)
        X = step(M, Ib, X, forces, dt)
        states.append(X)
    return tuple(np.array([np.asarray(s[i], float) for s in states]) for i in range(4))


_CACHE = {}


def _velocity_cached(P, M):
    """A cache keyed by the array's id: P changed in place gets the old velocity."""
    return _CACHE.setdefault((id(P), M), P / M)


MORE += [   # issue 45: one rule of precision (float32 refused in every check); the parts of a result in another order
    ("angular_velocity", lambda I_inv, L: (I_inv @ L).astype(np.float32), "float32", ["float64"]),
    ("velocity", lambda P, M: np.float32(1.0) * (P / M).astype(np.float32), "float32", ["float64"]),
    ("simulate", lambda *a, **k: (lambda x, R, P, L: (x, R, L, P))(*simulate_ok(*a, **k)), "parts_order",
     ["(x, R, L, P)"]),
    ("simulate", _sim_forces_kept, "forces_changed", ["forces_at returned"]),
    ("velocity", _velocity_cached, "stateful", ["earlier call"]),
]

_slips_spec = importlib.util.spec_from_file_location("_slips", pathlib.Path(__file__).with_name("slips.py"))
slips = importlib.util.module_from_spec(_slips_spec)
_slips_spec.loader.exec_module(slips)
ISSUE_30 = [(name, fn, mistake, []) for name, fn, mistake in slips.SLIPS]
"""Issue 30's families of slips (slips.py), each written three ways unlike the ones above."""
MORE += ISSUE_30

CASES = ISSUE + MORE


@pytest.mark.parametrize("name, fn, mistake, words", CASES, ids=[f"{c[0]}-{c[2]}-{i}" for i, c in enumerate(CASES)])
def test_each_mistake_gets_exactly_its_diagnosis(name, fn, mistake, words):
    r = check(name, fn)
    assert not r.passed
    assert r.mistake == mistake, r.message
    for w in words:
        assert w in r.message, (w, r.message)
    assert r.message.startswith(f"✗ {name}: ")
    m = ex.MISTAKES.get(mistake)
    if m is not None:
        assert m.text.split(":")[0].split("{")[0] in r.message
        assert m.slide in r.message


def test_the_catalogue_is_large_and_specific():
    """At least 40 wrong implementations beyond the issue's, none of them a bare "wrong result"."""
    assert len(MORE) >= 40
    assert all(c[2] != "wrong_result" for c in CASES)


def test_every_known_mistake_is_exercised():
    assert {c[2] for c in base.WRONG + CASES} >= set(ex.MISTAKES)


# =====================================================================================
# What each new diagnosis rests on: the inputs that tell the mistakes apart
# =====================================================================================

def test_R_inverse_passes_on_exact_rotations_only():
    """On an exact rotation R⁻¹ = Rᵀ: the check finds R⁻¹ only because some of its R are off SO(3)."""
    from rbcourse.rotation import exp_so3
    R = exp_so3(np.array([0.3, -1.0, 0.5]))
    Ib = np.diag([1.0, 2.0, 3.0])
    assert np.allclose(inverse_inertia_with_inv(R, Ib), inverse_inertia(R, Ib))
    r = check("inverse_inertia", inverse_inertia_with_inv)
    assert r.mistake == "R_inverse_not_transpose"


def test_project_so3_meets_a_negative_determinant():
    """The solution passes although some inputs have det(U Vᵀ) = −1; there U Vᵀ is a reflection."""
    assert check("project_so3", project_so3).passed
    r = check("project_so3", project_no_fix)
    assert r.mistake == "svd_no_det_fix"


def test_the_reference_is_never_shown_as_the_students():
    """A wrong result shows the student's own numbers after "got", never the reference's."""
    def velocity_plus(P, M):
        return P / M + 0.25
    r = check("velocity", velocity_plus)
    assert r.mistake == "probed" and "even on the simplest input" in r.message      # issue 45: probed
    want, got = r.message.split("expected ")[1].split(", got ")
    assert want.split("]")[0] != got.split("]")[0]


def test_an_exception_in_the_returned_object_is_the_students_error():
    class Weird:
        def __array__(self, *a, **k):
            raise RuntimeError("boom")

        def __len__(self):
            raise RuntimeError("boom")
    r = check("velocity", lambda P, M: Weird())
    assert not r.passed and r.mistake in ("not_numbers", "error") and "itself failed" not in r.message


def test_swapped_arguments_need_the_swapped_names():
    """lambda P, M: M / P (declared in the exercise's order) is the formula's mistake, not the order's."""
    assert check("velocity", lambda P, M: M / P).mistake == "velocity_mass_over_P"
    assert check("velocity", velocity_swapped).mistake == "args_swapped"
    assert check("velocity", lambda a, b: b / a).mistake == "velocity_mass_over_P"


def test_the_student_notebook_stubs_stay_not_done():
    def stub(*a, **k):
        raise NotImplementedError
    for name in ("box_inertia", "velocity", "inverse_inertia", "angular_velocity", "resultants", "dxdt",
                 "euler_step", "project_so3", "euler_step_projected"):
        r = check(name, stub)
        assert r.mistake == "not_done", r.message


def test_messages_are_in_one_table():
    from rbcourse.workbook.exercises import mistakes
    for code in ex.LANGUAGES:
        for key in ("pass", "fail", "not_done", "error", "wrong_result", "wrong_part", "not_a_function"):
            assert key in mistakes.TEXTS[code]
    assert all(m.text for m in ex.MISTAKES.values())


def test_the_simulate_check_shows_different_numbers_for_a_wrong_loop():
    """Forces computed once used to print identical "expected" and "got": now named; a loop wrong otherwise
    shows values that read differently."""
    def simulate_kick(M, Ib, X0, forces_at, dt, n_steps, step=None):
        x, R, P, L = simulate_ok(M, Ib, X0, forces_at, dt, n_steps, step)
        return x, R, P + 1e-6, L
    r = check("simulate", simulate_kick)
    assert r.mistake == "probed" and "P differs first at state 0" in r.message, r.message
    want, got = r.message.split("expected ")[1].split(" — ")[0].split(", got ")
    assert want != got
    assert check("simulate", simulate_ok).passed


def test_two_different_values_never_read_alike():
    """A result off by 1e-6 shows enough digits for "expected" and "got" to differ."""
    def off(P, M):
        return P / M + 1e-6
    r = check("velocity", off)
    assert r.mistake == "probed" and "digits only" in r.message, r.message        # issue 45: said in digits
    ex.langue("en")
    from rbcourse.workbook.exercises.verdict import Case, Spec, diagnose
    P, M = np.array([0.1, 0.2, 0.3]), 2.0
    r = diagnose(Spec("velocity", "v = P/M", "x"), Case((P, M), ("P", "M"), P / M), off(P, M))
    want, got = r.message.split("expected ")[1].split(" — ")[0].split(", got ")
    assert want != got


def test_integer_zeros_for_no_force_are_right():
    """An integer array holding the exact answer (no force: zeros) is not a truncation."""
    def resultants_int_start(x, forces):
        F, tau = np.array([0, 0, 0]), np.array([0, 0, 0])
        for r, F_i in forces:
            F = F + F_i
            tau = tau + np.cross(r - x, F_i)
        return F, tau
    assert check("resultants", resultants_int_start).passed


# =====================================================================================
# The French edition: every diagnosis in French, the same ids, the same placeholders
# =====================================================================================

import string

from rbcourse.workbook.exercises import mistakes as _m

SAME_IN_BOTH = {"complex_detail", "X0_changed", "float_detail"}
"""The only texts legitimately the same in French: '{where}{real} + i·{imag}' (a formula) and the name X0."""




def _fields(template):
    return sorted(f for _, f, _, _ in string.Formatter().parse(template) if f is not None)


@pytest.mark.parametrize("table", ["TEXTS", "MISTAKE_TEXTS"])
def test_every_text_has_a_french_edition_with_the_same_placeholders(table):
    texts = getattr(_m, table)
    assert set(texts["fr"]) == set(texts["en"])
    for key, english in texts["en"].items():
        french_text = texts["fr"][key]
        assert _fields(french_text) == _fields(english), (key, english, french_text)
        assert (french_text == english) == (key in SAME_IN_BOTH), (key, french_text)


@pytest.mark.parametrize("name, fn, mistake, words", CASES, ids=[f"fr-{c[0]}-{c[2]}-{i}" for i, c in enumerate(CASES)])
def test_each_mistake_gets_its_french_diagnosis(french, name, fn, mistake, words):
    """The same id as in English; the message is the French text of that id, and the slide to reread in French."""
    r = check(name, fn)
    assert not r.passed and r.mistake == mistake, r.message
    assert r.message.startswith(f"✗ {name} : "), r.message
    m = ex.MISTAKES.get(mistake)
    if m is not None:
        assert m.text == _m.MISTAKE_TEXTS["fr"][mistake]
        assert m.text.split("{")[0] in r.message, (m.text, r.message)
        assert f"→ relisez {_m.slide_text(m.slide)}" in r.message, r.message
    assert "reread" not in r.message and "wrong result" not in r.message
    # the parts a nested mistake is found in are named in French too ("le pas d'Euler : dX/dt : v : …")
    assert "the Euler step" not in r.message and not any(f"{p}: " in r.message for p in ("dX/dt", "v", "ω", "I⁻¹(t)", "F, τ"))


def test_the_french_pass_and_not_done_lines(french):
    assert check("velocity", velocity).message == "✓ velocity : v = P/M — juste sur 20 entrées aléatoires"
    assert check("simulate", simulate_ok).message.endswith("— juste sur 6 simulations aléatoires")

    def stub(P, M):
        raise NotImplementedError
    assert check("velocity", stub).message == "○ velocity : pas encore écrite (elle lève NotImplementedError)"
    r = check("project_so3", lambda R: R)
    assert "relisez la partie 8 du notebook" in r.message


def test_the_language_is_read_when_the_message_is_made():
    """Switching the language changes the next message, not the ones already made."""
    english = check("velocity", lambda P, M: P * M)
    ex.langue("fr")
    try:
        french_result = check("velocity", lambda P, M: P * M)
    finally:
        ex.langue("en")
    assert "you multiplied P by M" in english.message
    assert "vous avez multiplié P par M" in french_result.message
    assert english.mistake == french_result.mistake == "velocity_times_mass"
