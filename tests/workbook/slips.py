"""Student-like implementations of the exercise's functions, written for issue 30 before its fixes, from the
notebook alone and unlike the ones in test_exercises.py / test_mistakes.py (loops, comprehensions, einsum, scipy):

    SLIPS:   (check, function, the family's mistake id) — each must be rejected and named with that id
    CORRECT: (check, function) — equivalent forms that must pass

Run it to measure the checks on them (both languages):

    PYTHONPATH=. python tests/workbook/slips.py          # named / other name / vague / accepted, per family
"""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation


# =====================================================================================
# Correct pieces the slips are built from (as a student would write them)
# =====================================================================================

def _star(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def _res(x, forces):
    F, tau = np.zeros(3), np.zeros(3)
    for r, f in forces:
        F = F + f
        tau = tau + np.cross(r - x, f)
    return F, tau


def _rates(M, Ib, X, forces):
    x, R, P, L = X
    omega = R @ Ib @ R.T @ L
    F, tau = _res(x, forces)
    return P / M, _star(omega) @ R, F, tau


def _step(M, Ib, X, forces, dt):
    x, R, P, L = X
    v, Rd, F, tau = _rates(M, Ib, X, forces)
    return x + dt * v, R + dt * Rd, P + dt * F, L + dt * tau


def _svd_project(R):
    U, S, Vt = np.linalg.svd(R)
    if np.linalg.det(U @ Vt) < 0:
        U[:, 2] *= -1
    return U @ Vt


# =====================================================================================
# box_inertia
# =====================================================================================

def box_floor_div(mass, size):                          # integer arithmetic
    a, b, c = size
    return mass // 12 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])


def box_floor_div_loop(mass, size):
    a, b, c = size
    I = np.zeros((3, 3))
    for i, (p, q) in enumerate([(b, c), (a, c), (a, b)]):
        I[i, i] = np.floor_divide(mass, 12) * (p * p + q * q)
    return I


def box_int_mass(mass, size):
    a, b, c = size
    m = int(mass)
    return np.diag([m / 12 * (b * b + c * c), m / 12 * (a * a + c * c), m / 12 * (a * a + b * b)])


def box_precedence(mass, size):                         # M/12*b**2 + c**2
    a, b, c = size
    return np.diag([mass / 12 * b**2 + c**2, mass / 12 * a**2 + c**2, mass / 12 * a**2 + b**2])


def box_precedence_comprehension(mass, size):
    a, b, c = size
    return np.diag([mass / 12 * p * p + q * q for p, q in ((b, c), (a, c), (a, b))])


def box_precedence_divide(mass, size):
    a, b, c = size
    return np.diag([mass / (12 * (b**2 + c**2)), mass / (12 * (a**2 + c**2)), mass / (12 * (a**2 + b**2))])


def box_square_of_sum(mass, size):                      # (b + c)**2
    a, b, c = size
    return mass / 12 * np.diag([(b + c)**2, (a + c)**2, (a + b)**2])


def box_square_of_sum_np(mass, size):
    s = np.asarray(size, float)
    pairs = [s[[1, 2]], s[[0, 2]], s[[0, 1]]]
    return mass / 12 * np.diag([np.square(p.sum()) for p in pairs])


def box_square_of_sum_loop(mass, size):
    a, b, c = size
    I = np.zeros((3, 3))
    for i, (p, q) in enumerate([(b, c), (a, c), (a, b)]):
        I[i, i] = mass * (p + q) * (p + q) / 12
    return I


def box_xor(mass, size):                                # b^2: XOR
    a, b, c = size
    return mass / 12 * np.diag([b ^ 2 + c ^ 2, a ^ 2 + c ^ 2, a ^ 2 + b ^ 2])


def box_xor_array(mass, size):
    s = np.array(size)
    sq = s ^ 2
    return mass / 12 * np.diag([sq[1] + sq[2], sq[0] + sq[2], sq[0] + sq[1]])


def box_xor_comprehension(mass, size):
    a, b, c = size
    return np.diag([mass / 12 * (p ^ 2 + q ^ 2) for p, q in ((b, c), (a, c), (a, b))])


def box_full_matrix(mass, size):                        # the moments broadcast over the 3×3
    a, b, c = size
    return mass / 12 * np.array([b**2 + c**2, a**2 + c**2, a**2 + b**2]) * np.ones((3, 3))


def box_full_matrix_tile(mass, size):
    a, b, c = size
    m = mass / 12 * np.array([b**2 + c**2, a**2 + c**2, a**2 + b**2])
    return np.tile(m[:, None], (1, 3))


def box_full_matrix_outer(mass, size):
    a, b, c = size
    m = mass / 12 * np.array([b**2 + c**2, a**2 + c**2, a**2 + b**2])
    return np.outer(m, np.ones(3))


# =====================================================================================
# inverse_inertia, angular_velocity
# =====================================================================================

def inertia_order(R, I_body_inv):                       # I⁻¹_body R Rᵀ
    return I_body_inv @ R @ R.T


def inertia_order_einsum(R, I_body_inv):
    return np.einsum("ij,kj,kl->il", R, R, I_body_inv)  # R Rᵀ I⁻¹_body


def inertia_order_dot(R, I_body_inv):
    return np.dot(R.T, np.dot(R, I_body_inv))           # Rᵀ R I⁻¹_body


def inertia_elementwise_multiply(R, I_body_inv):
    return np.multiply(R, I_body_inv @ R.T)


def inertia_elementwise_einsum(R, I_body_inv):
    return np.einsum("ij,ij,ji->ij", R, I_body_inv, R)


def inertia_elementwise_loop(R, I_body_inv):
    out = np.zeros((3, 3))
    for i in range(3):
        for j in range(3):
            out[i, j] = R[i, j] * I_body_inv[i, j] * R.T[i, j]
    return out


def omega_cross(I_inv, L):                              # a cross product for the matrix product
    return np.cross(I_inv @ L, L)


def omega_cross_rows(I_inv, L):
    return np.cross(L, I_inv @ L)


def omega_cross_sum(I_inv, L):
    return np.cross(I_inv, L).sum(axis=1)


def omega_elementwise_einsum(I_inv, L):
    return np.einsum("ii,i->i", I_inv, L)


def omega_elementwise_multiply(I_inv, L):
    return np.multiply(I_inv, L).sum(axis=0)


def omega_elementwise_loop(I_inv, L):
    return np.array([I_inv[i, i] * L[i] for i in range(3)])


# =====================================================================================
# resultants
# =====================================================================================

def resultants_vstack(x, forces):                       # raises on forces = []
    r = np.vstack([p for p, _ in forces])
    f = np.vstack([q for _, q in forces])
    return f.sum(axis=0), np.cross(r - x, f).sum(axis=0)


def resultants_sum_builtin(x, forces):                  # sum() of nothing is the int 0
    F = sum(f for _, f in forces)
    tau = sum(np.cross(r - x, f) for r, f in forces)
    return F, tau


def resultants_stack(x, forces):
    r, f = np.stack([p for p, _ in forces]), np.stack([q for _, q in forces])
    return np.sum(f, 0), np.sum(np.cross(r - x, f), 0)


def resultants_tau_overwritten(x, forces):              # tau = … for tau += …
    F, tau = np.zeros(3), np.zeros(3)
    for r, f in forces:
        F += f
        tau = np.cross(r - x, f)
    return F, tau


def resultants_F_overwritten(x, forces):
    F, tau = np.zeros(3), np.zeros(3)
    for r, f in forces:
        F = np.array(f, float)
        tau = tau + np.cross(r - x, f)
    return F, tau


def resultants_both_overwritten_index(x, forces):
    F, tau = np.zeros(3), np.zeros(3)
    for i in range(len(forces)):
        F = forces[i][1] + 0.0
        tau = np.cross(forces[i][0] - x, forces[i][1])
    return F, tau


def resultants_elementwise(x, forces):                  # (rᵢ − x) * Fᵢ for ∧
    F, tau = np.zeros(3), np.zeros(3)
    for r, f in forces:
        F = F + f
        tau = tau + (r - x) * f
    return F, tau


def resultants_elementwise_comprehension(x, forces):
    F = np.zeros(3) + sum([f for _, f in forces], np.zeros(3))
    tau = sum([np.multiply(r - x, f) for r, f in forces], np.zeros(3))
    return F, tau


def resultants_elementwise_einsum(x, forces):
    if not forces:
        return np.zeros(3), np.zeros(3)
    r = np.array([p for p, _ in forces]) - x
    f = np.array([q for _, q in forces])
    return f.sum(0), np.einsum("ij,ij->j", r, f)


def resultants_int_accumulator(x, forces):              # an int array, then += a float
    F, tau = np.array([0, 0, 0]), np.array([0, 0, 0])
    for r, f in forces:
        F += f
        tau += np.cross(r - x, f)
    return F, tau


def resultants_int_zeros(x, forces):
    F = np.zeros(3, dtype=int)
    tau = np.zeros(3, dtype=int)
    for r, f in forces:
        np.add(F, f, out=F)
        np.add(tau, np.cross(r - x, f), out=tau)
    return F, tau


def resultants_int_list(x, forces):
    F, tau = np.array([0] * 3), np.array([0] * 3)
    for k in range(len(forces)):
        r, f = forces[k]
        F[:] += f
        tau[:] += np.cross(r - x, f)
    return F, tau


# =====================================================================================
# dxdt
# =====================================================================================

def dxdt_zero_int(M, I_body_inv, X, forces):            # no force: the int 0 for F and τ
    x, R, P, L = X
    if len(forces) == 0:
        F, tau = 0, 0
    else:
        F, tau = _res(x, forces)
    return P / M, _star(R @ I_body_inv @ R.T @ L) @ R, F, tau


def dxdt_sum_builtin(M, I_body_inv, X, forces):
    x, R, P, L = X
    F = sum(f for _, f in forces)
    tau = sum(np.cross(r - x, f) for r, f in forces)
    return P / M, _star(R @ I_body_inv @ R.T @ L) @ R, F, tau


def dxdt_vstack(M, I_body_inv, X, forces):
    x, R, P, L = X
    r, f = np.vstack([p for p, _ in forces]), np.vstack([q for _, q in forces])
    return P / M, _star(R @ I_body_inv @ R.T @ L) @ R, f.sum(0), np.cross(r - x, f).sum(0)


def dxdt_attributes(M, I_body_inv, X, forces):          # X.x: a plain tuple has no .x
    F, tau = _res(X.x, forces)
    return X.P / M, _star(X.R @ I_body_inv @ X.R.T @ X.L) @ X.R, F, tau


def dxdt_attributes_getattr(M, I_body_inv, X, forces):
    x, R, P, L = (getattr(X, k) for k in "xRPL")
    F, tau = _res(x, forces)
    return P / M, _star(R @ I_body_inv @ R.T @ L) @ R, F, tau


def dxdt_asdict(M, I_body_inv, X, forces):
    d = X._asdict()
    F, tau = _res(d["x"], forces)
    R = d["R"]
    return d["P"] / M, _star(R @ I_body_inv @ R.T @ d["L"]) @ R, F, tau


# =====================================================================================
# euler_step
# =====================================================================================

def euler_no_dt_R(M, I_body_inv, X, forces, dt):        # Δt dropped on R alone
    x, R, P, L = X
    v, Rd, F, tau = _rates(M, I_body_inv, X, forces)
    return x + dt * v, R + Rd, P + dt * F, L + dt * tau


def euler_no_dt_x(M, I_body_inv, X, forces, dt):
    x, R, P, L = X
    v, Rd, F, tau = _rates(M, I_body_inv, X, forces)
    return x + v, R + dt * Rd, P + dt * F, L + dt * tau


def euler_no_dt_L_comprehension(M, I_body_inv, X, forces, dt):
    d = _rates(M, I_body_inv, X, forces)
    return tuple(X[i] + (d[i] if i == 3 else dt * d[i]) for i in range(4))


def euler_tuple_times(M, I_body_inv, X, forces, dt):    # tuple arithmetic
    return X + dt * _rates(M, I_body_inv, X, forces)


def euler_tuple_np_add(M, I_body_inv, X, forces, dt):
    return tuple(np.add(X, np.multiply(dt, _rates(M, I_body_inv, X, forces))))


def euler_tuple_concat(M, I_body_inv, X, forces, dt):
    return X + tuple(dt * d for d in _rates(M, I_body_inv, X, forces))


def euler_heun(M, I_body_inv, X, forces, dt):           # another method: Heun
    k1 = _rates(M, I_body_inv, X, forces)
    Y = tuple(a + dt * b for a, b in zip(X, k1))
    k2 = _rates(M, I_body_inv, Y, forces)
    return tuple(a + dt / 2 * (b + c) for a, b, c in zip(X, k1, k2))


def euler_midpoint(M, I_body_inv, X, forces, dt):
    k1 = _rates(M, I_body_inv, X, forces)
    Y = [a + dt / 2 * b for a, b in zip(X, k1)]
    k2 = _rates(M, I_body_inv, Y, forces)
    return tuple(a + dt * b for a, b in zip(X, k2))


def euler_heun_loop(M, I_body_inv, X, forces, dt):
    x, R, P, L = X
    a = _rates(M, I_body_inv, X, forces)
    pred = [x + dt * a[0], R + dt * a[1], P + dt * a[2], L + dt * a[3]]
    b = _rates(M, I_body_inv, pred, forces)
    out = []
    for i, s in enumerate((x, R, P, L)):
        out.append(s + 0.5 * dt * a[i] + 0.5 * dt * b[i])
    return tuple(out)


def euler_vstack(M, I_body_inv, X, forces, dt):         # raises on forces = []
    x, R, P, L = X
    f = np.vstack([q for _, q in forces])
    r = np.vstack([p for p, _ in forces])
    F, tau = f.sum(0), np.cross(r - x, f).sum(0)
    omega = R @ I_body_inv @ R.T @ L
    return x + dt * P / M, R + dt * _star(omega) @ R, P + dt * F, L + dt * tau


def euler_attributes(M, I_body_inv, X, forces, dt):     # X.x fails on the plain tuple a step returns
    v, Rd, F, tau = _rates(M, I_body_inv, (X.x, X.R, X.P, X.L), forces)
    return X.x + dt * v, X.R + dt * Rd, X.P + dt * F, X.L + dt * tau


def euler_attributes_getattr(M, I_body_inv, X, forces, dt):
    x, R, P, L = (getattr(X, name) for name in ("x", "R", "P", "L"))
    return _step(M, I_body_inv, (x, R, P, L), forces, dt)


def euler_asdict(M, I_body_inv, X, forces, dt):
    state = X._asdict()
    rates = dict(zip("xRPL", _rates(M, I_body_inv, tuple(state.values()), forces)))
    return tuple(state[k] + dt * rates[k] for k in "xRPL")


def euler_int_first_force(M, I_body_inv, X, forces, dt):
    x, R, P, L = X
    F = forces[0][1]                                    # raises on forces = []
    tau = sum(np.cross(r - x, f) for r, f in forces)
    omega = R @ I_body_inv @ R.T @ L
    return x + dt * P / M, R + dt * _star(omega) @ R, P + dt * sum(f for _, f in forces) + 0 * F, L + dt * tau


# =====================================================================================
# simulate
# =====================================================================================

def simulate_lists(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):      # four lists
    xs, Rs, Ps, Ls = [X0[0]], [X0[1]], [X0[2]], [X0[3]]
    X = X0
    for k in range(n_steps):
        X = step(M, I_body_inv, X, forces_at(k * dt, X), dt)
        xs.append(X[0]); Rs.append(X[1]); Ps.append(X[2]); Ls.append(X[3])
    return xs, Rs, Ps, Ls


def simulate_list_comprehension(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    states = [X0]
    for k in range(n_steps):
        states.append(step(M, I_body_inv, states[-1], forces_at(k * dt, states[-1]), dt))
    return tuple([s[i] for s in states] for i in range(4))


def simulate_tuple_of_lists(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    out = ([], [], [], [])
    X = X0
    for k in range(n_steps + 1):
        for i in range(4):
            out[i].append(np.asarray(X[i]))
        if k < n_steps:
            X = step(M, I_body_inv, X, forces_at(k * dt, X), dt)
    return out


def simulate_aliased(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):    # every stored state one array
    x, R, P, L = (np.array(a, float) for a in X0)
    xs, Rs, Ps, Ls = [x], [R], [P], [L]
    for k in range(n_steps):
        Y = step(M, I_body_inv, (x, R, P, L), forces_at(k * dt, (x, R, P, L)), dt)
        x[:], R[:], P[:], L[:] = Y
        xs.append(x); Rs.append(R); Ps.append(P); Ls.append(L)
    return np.array(xs), np.array(Rs), np.array(Ps), np.array(Ls)


def simulate_aliased_buffer(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    X = [np.array(a, float) for a in X0]
    states = [tuple(X)]
    for k in range(n_steps):
        Y = step(M, I_body_inv, tuple(X), forces_at(k * dt, tuple(X)), dt)
        for i in range(4):
            X[i][...] = Y[i]
        states.append(tuple(X))
    return tuple(np.array([s[i] for s in states]) for i in range(4))


def simulate_aliased_copyto(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    cur = tuple(np.array(a, float) for a in X0)
    hist = {i: [cur[i]] for i in range(4)}
    for k in range(n_steps):
        new = step(M, I_body_inv, cur, forces_at(k * dt, cur), dt)
        for i in range(4):
            np.copyto(cur[i], new[i])
            hist[i].append(cur[i])
    return tuple(np.stack(hist[i]) for i in range(4))


def simulate_step_args(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):   # step(…, dt, forces)
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(M, I_body_inv, X, dt, forces_at(k * dt, X))
        states.append(X)
    return tuple(np.array([s[i] for s in states]) for i in range(4))


def simulate_step_args_X_first(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(X, M, I_body_inv, forces_at(k * dt, X), dt)
        states.append(X)
    return tuple(np.array([s[i] for s in states]) for i in range(4))


def simulate_forces_at_swapped(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):   # forces_at(X, t)
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(M, I_body_inv, X, forces_at(X, k * dt), dt)
        states.append(X)
    return tuple(np.array([s[i] for s in states]) for i in range(4))


def simulate_transposed(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):  # (3, n+1)
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(M, I_body_inv, X, forces_at(k * dt, X), dt)
        states.append(X)
    return (np.column_stack([s[0] for s in states]), np.array([s[1] for s in states]),
            np.array([s[2] for s in states]).T, np.array([s[3] for s in states]).T)


def simulate_transposed_T(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(M, I_body_inv, X, forces_at(k * dt, X), dt)
        states.append(X)
    return tuple(np.array([s[i] for s in states]).T for i in range(4))


def simulate_transposed_stack(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    X, states = X0, [X0]
    for k in range(n_steps):
        X = step(M, I_body_inv, X, forces_at(k * dt, X), dt)
        states.append(X)
    return tuple(np.stack([s[i] for s in states], axis=-1) for i in range(4))


def simulate_X_not_reassigned(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):   # X never advances
    X, states = X0, [X0]
    for k in range(n_steps):
        Y = step(M, I_body_inv, X, forces_at(k * dt, X), dt)
        states.append(Y)
    return tuple(np.array([s[i] for s in states]) for i in range(4))


def simulate_X_not_reassigned_comprehension(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    states = [X0] + [step(M, I_body_inv, X0, forces_at(k * dt, X0), dt) for k in range(n_steps)]
    return tuple(np.array([s[i] for s in states]) for i in range(4))


def simulate_X_not_reassigned_prealloc(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    x = np.zeros((n_steps + 1, 3)); R = np.zeros((n_steps + 1, 3, 3)); P = np.zeros((n_steps + 1, 3))
    L = np.zeros((n_steps + 1, 3))
    x[0], R[0], P[0], L[0] = X0
    for k in range(n_steps):
        X = (x[0], R[0], P[0], L[0])
        x[k + 1], R[k + 1], P[k + 1], L[k + 1] = step(M, I_body_inv, X, forces_at(k * dt, X), dt)
    return x, R, P, L


# =====================================================================================
# project_so3, euler_step_projected
# =====================================================================================

def project_scipy(R):                                   # raises on det R < 0
    return Rotation.from_matrix(R).as_matrix()


def project_scipy_quat(R):
    return Rotation.from_quat(Rotation.from_matrix(R).as_quat()).as_matrix()


def project_scipy_rotvec(R):
    return Rotation.from_rotvec(Rotation.from_matrix(R).as_rotvec()).as_matrix()


def _projected_with(project):
    def euler_step_projected(M, I_body_inv, X, forces, dt):
        x, R, P, L = _step(M, I_body_inv, X, forces, dt)
        return x, project(R), P, L
    return euler_step_projected


def _project_transposed(R):                             # Vt.T @ U.T
    U, S, Vt = np.linalg.svd(R)
    return Vt.T @ U.T


def _project_transposed_einsum(R):
    U, S, Vt = np.linalg.svd(R)
    return np.einsum("ji,kj->ik", Vt, U)


def _project_transposed_T(R):
    U, S, Vt = np.linalg.svd(R)
    return (U @ Vt).T


def _project_columns(R):                                # columns normalised only
    return R / np.linalg.norm(R, axis=0)


def _project_columns_loop(R):
    Q = np.array(R, float)
    for j in range(3):
        Q[:, j] = Q[:, j] / np.sqrt(np.sum(Q[:, j] ** 2))
    return Q


def _project_rows(R):
    return np.array([row / np.linalg.norm(row) for row in R])


# =====================================================================================
# The list, by family
# =====================================================================================

SLIPS = [
    # box_inertia
    ("box_inertia", box_floor_div, "floor_division"), ("box_inertia", box_floor_div_loop, "floor_division"),
    ("box_inertia", box_int_mass, "floor_division"),
    ("box_inertia", box_precedence, "precedence"), ("box_inertia", box_precedence_comprehension, "precedence"),
    ("box_inertia", box_precedence_divide, "precedence"),
    ("box_inertia", box_square_of_sum, "square_of_sum"), ("box_inertia", box_square_of_sum_np, "square_of_sum"),
    ("box_inertia", box_square_of_sum_loop, "square_of_sum"),
    ("box_inertia", box_xor, "xor_power"), ("box_inertia", box_xor_array, "xor_power"),
    ("box_inertia", box_xor_comprehension, "xor_power"),
    ("box_inertia", box_full_matrix, "moments_full_matrix"), ("box_inertia", box_full_matrix_tile, "moments_full_matrix"),
    ("box_inertia", box_full_matrix_outer, "moments_full_matrix"),
    # inverse_inertia
    ("inverse_inertia", inertia_order, "factor_order"), ("inverse_inertia", inertia_order_einsum, "factor_order"),
    ("inverse_inertia", inertia_order_dot, "factor_order"),
    ("inverse_inertia", inertia_elementwise_multiply, "elementwise"),
    ("inverse_inertia", inertia_elementwise_einsum, "elementwise"),
    ("inverse_inertia", inertia_elementwise_loop, "elementwise"),
    # angular_velocity
    ("angular_velocity", omega_cross, "cross_for_product"), ("angular_velocity", omega_cross_rows, "cross_for_product"),
    ("angular_velocity", omega_cross_sum, "cross_for_product"),
    ("angular_velocity", omega_elementwise_einsum, "elementwise"),
    ("angular_velocity", omega_elementwise_multiply, "elementwise"),
    ("angular_velocity", omega_elementwise_loop, "elementwise"),
    # resultants
    ("resultants", resultants_vstack, "empty_forces"), ("resultants", resultants_sum_builtin, "empty_forces"),
    ("resultants", resultants_stack, "empty_forces"),
    ("resultants", resultants_tau_overwritten, "last_force_only"),
    ("resultants", resultants_F_overwritten, "last_force_only"),
    ("resultants", resultants_both_overwritten_index, "last_force_only"),
    ("resultants", resultants_elementwise, "elementwise_cross"),
    ("resultants", resultants_elementwise_comprehension, "elementwise_cross"),
    ("resultants", resultants_elementwise_einsum, "elementwise_cross"),
    ("resultants", resultants_int_accumulator, "int_in_place"), ("resultants", resultants_int_zeros, "int_in_place"),
    ("resultants", resultants_int_list, "int_in_place"),
    # dxdt
    ("dxdt", dxdt_zero_int, "empty_forces"), ("dxdt", dxdt_sum_builtin, "empty_forces"),
    ("dxdt", dxdt_vstack, "empty_forces"),
    ("dxdt", dxdt_attributes, "state_attributes"), ("dxdt", dxdt_attributes_getattr, "state_attributes"),
    ("dxdt", dxdt_asdict, "state_attributes"),
    # euler_step
    ("euler_step", euler_no_dt_R, "no_dt"), ("euler_step", euler_no_dt_x, "no_dt"),
    ("euler_step", euler_no_dt_L_comprehension, "no_dt"),
    ("euler_step", euler_tuple_times, "tuple_arithmetic"), ("euler_step", euler_tuple_np_add, "tuple_arithmetic"),
    ("euler_step", euler_tuple_concat, "tuple_arithmetic"),
    ("euler_step", euler_heun, "other_method"), ("euler_step", euler_midpoint, "other_method"),
    ("euler_step", euler_heun_loop, "other_method"),
    ("euler_step", euler_vstack, "empty_forces"), ("euler_step", euler_int_first_force, "empty_forces"),
    ("euler_step", lambda M, Ib, X, forces, dt: _step(M, Ib, X, forces, dt) if forces else None, "empty_forces"),
    ("euler_step", euler_attributes, "state_attributes"), ("euler_step", euler_attributes_getattr, "state_attributes"),
    ("euler_step", euler_asdict, "state_attributes"),
    # simulate
    ("simulate", simulate_lists, "returned_list"), ("simulate", simulate_list_comprehension, "returned_list"),
    ("simulate", simulate_tuple_of_lists, "returned_list"),
    ("simulate", simulate_aliased, "aliasing"), ("simulate", simulate_aliased_buffer, "aliasing"),
    ("simulate", simulate_aliased_copyto, "aliasing"),
    ("simulate", simulate_step_args, "call_order"), ("simulate", simulate_step_args_X_first, "call_order"),
    ("simulate", simulate_forces_at_swapped, "call_order"),
    ("simulate", simulate_transposed, "states_transposed"), ("simulate", simulate_transposed_T, "states_transposed"),
    ("simulate", simulate_transposed_stack, "states_transposed"),
    ("simulate", simulate_X_not_reassigned, "state_not_advanced"),
    ("simulate", simulate_X_not_reassigned_comprehension, "state_not_advanced"),
    ("simulate", simulate_X_not_reassigned_prealloc, "state_not_advanced"),
    # project_so3
    ("project_so3", project_scipy, "scipy_negative_det"), ("project_so3", project_scipy_quat, "scipy_negative_det"),
    ("project_so3", project_scipy_rotvec, "scipy_negative_det"),
    # euler_step_projected: project_so3's own mistakes, named as project_so3's
    ("euler_step_projected", _projected_with(_project_transposed), "projection_transposed"),
    ("euler_step_projected", _projected_with(_project_transposed_einsum), "projection_transposed"),
    ("euler_step_projected", _projected_with(_project_transposed_T), "projection_transposed"),
    ("euler_step_projected", _projected_with(_project_columns), "columns_normalized"),
    ("euler_step_projected", _projected_with(_project_columns_loop), "columns_normalized"),
    ("euler_step_projected", _projected_with(_project_rows), "columns_normalized"),
]


# =====================================================================================
# Equivalent forms that must pass
# =====================================================================================

def _gram_schmidt_columns(R):            # a rotation close to R, not the nearest one: refused (test_exercise_behaviour)
    a, b = R[:, 0], R[:, 1]
    e1 = a / np.linalg.norm(a)
    b = b - (e1 @ b) * e1
    e2 = b / np.linalg.norm(b)
    e3 = np.cross(e1, e2)
    Q = np.column_stack([e1, e2, e3])
    return Q if np.linalg.det(Q) > 0 else Q * np.array([1.0, 1.0, -1.0])


def _polar(R):
    w, V = np.linalg.eigh(R.T @ R)
    Q = R @ V @ np.diag(1 / np.sqrt(w)) @ V.T
    if np.linalg.det(Q) < 0:
        U, S, Vt = np.linalg.svd(R)
        U[:, 2] *= -1
        Q = U @ Vt
    return Q


def _simulate_prealloc(M, I_body_inv, X0, forces_at, dt, n_steps, step=None):
    x = np.empty((n_steps + 1, 3)); R = np.empty((n_steps + 1, 3, 3))
    P = np.empty((n_steps + 1, 3)); L = np.empty((n_steps + 1, 3))
    x[0], R[0], P[0], L[0] = X0
    X = X0
    for k in range(n_steps):
        X = step(M, I_body_inv, X, forces_at(k * dt, X), dt)
        x[k + 1], R[k + 1], P[k + 1], L[k + 1] = X
    return x, R, P, L


def _euler_list(M, I_body_inv, X, forces, dt):          # a list [x, R, P, L]: harmless
    return list(_step(M, I_body_inv, X, forces, dt))


def _dxdt_einsum(M, I_body_inv, X, forces):
    x, R, P, L = X
    I_inv = np.einsum("ij,jk,lk->il", R, I_body_inv, R)
    F = np.zeros(3) + np.sum([f for _, f in forces], axis=0) if forces else np.zeros(3)
    tau = np.sum([np.cross(r - x, f) for r, f in forces], axis=0) if forces else np.zeros(3)
    return P / M, _star(I_inv @ L) @ R, F, tau


CORRECT = [
    ("box_inertia", lambda mass, size: mass / 12 * np.diag([size[1]**2 + size[2]**2, size[0]**2 + size[2]**2,
                                                           size[0]**2 + size[1]**2])),
    ("box_inertia", lambda mass, size: np.eye(3) * (mass / 12) * np.array([size[1]**2 + size[2]**2,
                                                                         size[0]**2 + size[2]**2,
                                                                         size[0]**2 + size[1]**2])),
    ("inverse_inertia", lambda R, Ib: np.einsum("ij,jk,lk->il", R, Ib, R)),
    ("angular_velocity", lambda I_inv, L: L @ I_inv),
    ("angular_velocity", lambda I_inv, L: np.einsum("ij,j->i", I_inv, L)),
    ("resultants", lambda x, forces: (sum((f for _, f in forces), np.zeros(3)),
                                      sum((np.cross(r - x, f) for r, f in forces), np.zeros(3)))),
    ("resultants", lambda x, forces: _res(x, forces)),
    ("dxdt", _dxdt_einsum),
    ("euler_step", _step),
    ("euler_step", _euler_list),
    ("simulate", _simulate_prealloc),
    ("project_so3", _svd_project),
    ("project_so3", _polar),
    ("euler_step_projected", _projected_with(_polar)),
]


VAGUE = {"wrong_result", "error", "check_failed", "wrong_shape", "wrong_return", "wrong_count", "not_numbers"}


def measure(language: str = "en") -> dict:
    """{'named': …, 'other': …, 'vague': …, 'accepted': …, 'correct_refused': …} on SLIPS and CORRECT, with the
    lines of the slips not named as their family."""
    from rbcourse.workbook import exercises as ex
    before = ex.current()
    ex.langue(language)
    try:
        counts = dict(named=0, other=0, vague=0, accepted=0, correct_refused=0)
        lines = []
        for name, fn, family in SLIPS:
            r = getattr(ex, f"check_{name}")(fn, verbose=False)
            kind = ("accepted" if r.passed else "named" if r.mistake == family else
                    "vague" if r.mistake in VAGUE else "other")
            counts[kind] += 1
            if kind != "named":
                lines.append(f"  {kind:8s} {name}/{getattr(fn, '__name__', '?')} (want {family}): {r.mistake}")
        for name, fn in CORRECT:
            r = getattr(ex, f"check_{name}")(fn, verbose=False)
            if not r.passed:
                counts["correct_refused"] += 1
                lines.append(f"  refused  {name}/{getattr(fn, '__name__', '?')}: {r.message.splitlines()[0]}")
        counts["lines"] = lines
        return counts
    finally:
        ex.langue(before)


if __name__ == "__main__":
    for code in ("en", "fr"):
        c = measure(code)
        print(f"[{code}] {len(SLIPS)} slips: named {c['named']}, named otherwise {c['other']}, vague {c['vague']}, "
              f"accepted {c['accepted']};  {len(CORRECT)} correct forms: refused {c['correct_refused']}")
        print("\n".join(c["lines"]))
