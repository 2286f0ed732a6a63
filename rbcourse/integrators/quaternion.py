"""The state as one flat array, for quaternion methods:  Y = [x, q, P, L_b]  of shape (13, N).

q is the unit quaternion of R; L_b = Rᵀ L the angular momentum in body axes (about the
rotation centre: the centre of mass, or the pivot), which follows Euler's equations:

    d/dt [x, q, P, L_b] = [v, ½ q ⊗ (0, ω_b), F, L_b × ω_b + Rᵀ τ],   ω_b = I⁻¹_body L_b

Components come first (row k of Y is one number for all N bodies), so each line of
arithmetic below is one fast numpy operation over all bodies.  Integrating L_b rather
than the world L keeps the energy, ½ L_b·ω_b, far better: the attitude's error no
longer feeds into it.
"""
from __future__ import annotations

import numpy as np

from ..dynamics import forces
from ..rotation import matrix_from_quat, matvec, quat_from_matrix, quat_normalize, quat_rotate, quat_times_vector, transpose
from ..state import State
from .base import Prepared, prepare

X_, Q_, P_, L_ = slice(0, 3), slice(3, 7), slice(7, 10), slice(10, 13)


def encode(scene, X: State) -> np.ndarray:
    """State (engine coordinates) -> Y = [x, q, P, L_b = Rᵀ L], shape (13, N)."""
    q = quat_from_matrix(X.R)
    return np.ascontiguousarray(np.concatenate([X.x, q, X.P, quat_rotate(q, X.L, inverse=True)], axis=-1).T)


def decode(scene, Y: np.ndarray) -> State:
    """Y -> State (L = R L_b); q is normalised, pivoted bodies get x and P from R and L."""
    R = matrix_from_quat(Y[Q_].T)
    return scene.constrain(State.unchecked(Y[X_].T, R, Y[P_].T, np.einsum("nij,nj->ni", R, Y[L_].T)))


def rates(scene, t: float, Y: np.ndarray, prep: Prepared | None = None) -> np.ndarray:
    """dY/dt = [v, ½ q ⊗ (0, ω_b), F, L_b × ω_b + Rᵀ τ]; forces only if the scene has some.
    prep: the run's Prepared (its I⁻¹ rows); None prepares it here."""
    if prep is None:
        prep = prepare(scene)
    L0, L1, L2 = Y[10], Y[11], Y[12]
    J = prep.Iinv_rows
    if prep.diagonal_inertia:                        # ω_b = I⁻¹_body L_b
        w0, w1, w2 = L0 * J[0], L1 * J[1], L2 * J[2]
    else:
        w0 = J[0] * L0 + J[1] * L1 + J[2] * L2
        w1 = J[1] * L0 + J[3] * L1 + J[4] * L2
        w2 = J[2] * L0 + J[4] * L1 + J[5] * L2
    dY = np.empty_like(Y)
    dY[Q_] = 0.5 * quat_times_vector(Y[Q_].T, np.stack([w0, w1, w2], -1)).T     # q̇ = ½ q ⊗ (0, ω_b)
    dY[10] = L1 * w2 - L2 * w1                       # Euler's equations: dL_b/dt = L_b × ω_b
    dY[11] = L2 * w0 - L0 * w2
    dY[12] = L0 * w1 - L1 * w0
    if scene.has_forces or scene.has_pivots:
        R = matrix_from_quat(Y[Q_].T)                    # (normalises q)
        X = scene.constrain(State.unchecked(Y[X_].T, R, Y[P_].T, matvec(R, Y[L_].T)))
        v = X.P / scene.mass[:, None]
        F, tau = forces(scene, t, X, v, matvec(R, np.stack([w0, w1, w2], -1)))
        dY[X_], dY[P_] = v.T, F.T
        dY[L_] += matvec(transpose(R), tau).T              # + τ_b = Rᵀ τ
    else:
        np.divide(Y[P_], scene.mass, out=dY[X_])         # a free body: v = P/M, F = 0
        dY[P_] = 0.0
    return dY


def normalized(Y: np.ndarray) -> np.ndarray:
    """Y with its quaternion normalised (rotation.quat_normalize), so R(q) is a rotation."""
    Y[Q_] = quat_normalize(Y[Q_].T).T
    return Y
