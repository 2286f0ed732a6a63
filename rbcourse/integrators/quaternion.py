"""The state as one flat array per body, for quaternion methods:  Y = [x, q, P, L]  (N, 13).

q is the unit quaternion of R; L the world angular momentum (about the rotation
centre: the centre of mass, or the pivot).  One array keeps each RK stage to a
couple of numpy operations, however many bodies there are.

    d/dt [x, q, P, L] = [v, ½ q ⊗ (0, ω_body), F, τ],   ω_body = I⁻¹_body Rᵀ L
"""
from __future__ import annotations

import numpy as np

from ..dynamics import forces
from ..rotation import matrix_from_quat, quat_from_matrix, quat_normalize, quat_rotate, quat_times_vector
from ..state import State

X_, Q_, P_, L_ = slice(0, 3), slice(3, 7), slice(7, 10), slice(10, 13)


def encode(scene, X: State) -> np.ndarray:
    """State (engine coordinates) -> Y = [x, q, P, L]."""
    return np.concatenate([X.x, quat_from_matrix(X.R), X.P, X.L], axis=-1)


def decode(scene, Y: np.ndarray) -> State:
    """Y -> State; q is normalised, pivoted bodies get x and P from R and L."""
    return scene.constrain(State._raw(Y[:, X_], matrix_from_quat(Y[:, Q_]), Y[:, P_], Y[:, L_]))


def body_omega(scene, q: np.ndarray, L: np.ndarray) -> np.ndarray:
    """ω_body = I⁻¹_body (Rᵀ L), with Rᵀ L computed from q."""
    L_body = quat_rotate(q, L, inverse=True)
    if scene.diagonal_inertia:
        return L_body * scene.I_rot_inv_diag
    return np.einsum("nij,nj->ni", scene.I_rot_inv, L_body)


def rates(scene, t: float, Y: np.ndarray) -> np.ndarray:
    """dY/dt = [v, ½ q ⊗ (0, ω_body), F, τ]; forces are evaluated only if the scene has some."""
    q, L = Y[:, Q_], Y[:, L_]
    q = q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))
    omega_b = body_omega(scene, q, L)
    dY = np.empty_like(Y)
    dY[:, Q_] = 0.5 * quat_times_vector(q, omega_b)
    if scene.has_forces or scene.has_pivots:
        X = scene.constrain(State._raw(Y[:, X_], matrix_from_quat(q), Y[:, P_], L))
        v = X.P / scene.mass[:, None]
        F, tau = forces(scene, t, X, v, quat_rotate(q, omega_b))
        dY[:, X_], dY[:, P_], dY[:, L_] = v, F, tau
    else:
        dY[:, X_] = Y[:, P_] / scene.mass[:, None]       # a free body: v = P/M, F = 0, τ = 0
        dY[:, 7:] = 0.0
    return dY


def normalized(Y: np.ndarray) -> np.ndarray:
    """Y with its quaternion normalised (so R(q) is a rotation)."""
    Y[:, Q_] = quat_normalize(Y[:, Q_])
    return Y
