"""Rotations: the cross-product matrix ω*, the exponential map, SO(3) projection, quaternions.

Every function accepts a single object or a batch (leading dimensions), so the
same code steps one body or N bodies.

Quaternions are stored as (w, x, y, z) with w the scalar part (Baraff 2001, notes G, §4).
"""
from __future__ import annotations

import numpy as np

from . import checks


def _vectors(name: str, a, trailing: tuple) -> np.ndarray:
    """a as float arrays of the given trailing shape: a float ndarray passes at no cost (the engine's
    own calls); anything else is checked (numbers only, the shape) with a ValueError naming it."""
    if isinstance(a, np.ndarray) and a.dtype.kind == "f" and a.shape[a.ndim - len(trailing):] == trailing:
        return a
    arr = checks.numbers(name, a, f"an array of numbers of shape (..., {', '.join(map(str, trailing))})")
    if arr.shape[arr.ndim - len(trailing):] != trailing or arr.ndim < len(trailing):
        raise ValueError(f"{name} must have shape (..., {', '.join(map(str, trailing))}), got shape {arr.shape}")
    return arr


def star(omega: np.ndarray) -> np.ndarray:
    """ω* : the matrix with  ω* a = ω × a  (the slides' "ω*", Baraff eq. 2-5).

        ω* = [[ 0,  -ω_z,  ω_y],
              [ ω_z,  0,  -ω_x],
              [-ω_y, ω_x,   0 ]]

    omega: (..., 3) -> (..., 3, 3)
    """
    omega = _vectors("omega", omega, (3,))
    W = np.zeros(omega.shape + (3,))
    W[..., 0, 1], W[..., 0, 2] = -omega[..., 2], omega[..., 1]
    W[..., 1, 0], W[..., 1, 2] = omega[..., 2], -omega[..., 0]
    W[..., 2, 0], W[..., 2, 1] = -omega[..., 1], omega[..., 0]
    return W


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b on the last axis (a faster np.cross for small stacks of 3-vectors)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def matvec(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """A b for stacks of matrices and vectors: (..., 3, 3), (..., 3) -> (..., 3)."""
    return np.einsum("...ij,...j->...i", A, b)


def transpose(A: np.ndarray) -> np.ndarray:
    """Aᵀ on the last two axes."""
    return np.swapaxes(A, -1, -2)


def exp_so3(phi: np.ndarray) -> np.ndarray:
    """Rotation by the angle |φ| about the axis φ/|φ| (Rodrigues' formula).

        exp(φ*) = I + sin|φ|/|φ| φ* + (1 − cos|φ|)/|φ|² φ*²

    Small angles use the Taylor series, so the result is accurate to machine
    precision for every |φ|.  phi: (..., 3) -> (..., 3, 3)
    """
    phi = _vectors("phi", phi, (3,))
    theta2 = np.sum(phi * phi, axis=-1)
    theta = np.sqrt(theta2)
    small = theta2 < 1e-8
    safe = np.where(small, 1.0, theta)
    a = np.where(small, 1.0 - theta2 / 6.0 + theta2**2 / 120.0, np.sin(safe) / safe)
    b = np.where(small, 0.5 - theta2 / 24.0 + theta2**2 / 720.0, (1.0 - np.cos(safe)) / safe**2)
    K = star(phi)
    return np.eye(3) + a[..., None, None] * K + b[..., None, None] * (K @ K)


def log_so3(R: np.ndarray) -> np.ndarray:
    """The rotation vector φ with exp_so3(φ) = R, |φ| in [0, π].  (..., 3, 3) -> (..., 3)"""
    q = quat_from_matrix(R)
    w = np.clip(q[..., 0], -1.0, 1.0)
    vec = q[..., 1:]
    s = np.linalg.norm(vec, axis=-1)
    angle = 2.0 * np.arctan2(s, w)
    scale = np.where(s < 1e-12, 2.0 / np.where(np.abs(w) < 1e-300, 1.0, w), angle / np.where(s < 1e-12, 1.0, s))
    return vec * scale[..., None]


def project_so3(R: np.ndarray) -> np.ndarray:
    """The rotation nearest to R (Frobenius norm): U Vᵀ from R = U Σ Vᵀ, with det = +1."""
    R = _vectors("R", R, (3, 3))
    if not np.all(np.isfinite(R)):
        raise ValueError("R must hold finite numbers only (no NaN or inf) to be projected onto SO(3)")
    U, _, Vt = np.linalg.svd(R)
    d = np.sign(np.linalg.det(U @ Vt))
    U = U.copy()
    U[..., :, 2] *= d[..., None]
    return U @ Vt


def orthonormalize(R: np.ndarray, tol: float = 1e-15, max_iter: int = 20) -> np.ndarray:
    """The nearest rotation to an almost-orthogonal R (polar factor), by Björck's iteration
    R ← R − ½ R (RᵀR − I) = R (3 I − RᵀR) / 2, which converges quadratically; project_so3 (SVD)
    if R is far from SO(3) (‖RᵀR − I‖ > 0.5).  A blown-up R is left as it is, for the divergence
    check to see."""
    for _ in range(max_iter):
        E = transpose(R) @ R - np.eye(3)
        err = np.abs(E).max()
        if err < tol:
            return R
        if not np.isfinite(err):
            return R
        if err > 0.5:
            return project_so3(R)
        R = retract(R)
    return R


def retract(R: np.ndarray) -> np.ndarray:
    """One Björck step, R ← R − ½ R (RᵀR − I): removes the rounding drift of a product of
    rotations (an error ε off SO(3) becomes ~ε²), so geometric methods stay on SO(3) to
    rounding over millions of steps."""
    return R - 0.5 * R @ (transpose(R) @ R - np.eye(3))


def orthogonality_error(R: np.ndarray) -> np.ndarray:
    """‖RᵀR − I‖ (Frobenius): 0 for a rotation; how far Euler's R has left SO(3)."""
    return np.linalg.norm(transpose(R) @ R - np.eye(3), axis=(-2, -1))


def is_rotation(R: np.ndarray, tol: float = 1e-6) -> bool:
    """True if every R in the stack has ‖RᵀR − I‖ <= tol and det R > 0."""
    return bool(np.all(orthogonality_error(R) <= tol) and np.all(np.linalg.det(R) > 0))


def rotation_angle(R_ref: np.ndarray, R: np.ndarray) -> np.ndarray:
    """Angle (rad) of R_refᵀ R, both first projected onto SO(3): the benchmarks' rotation error."""
    R_ref, R = _vectors("R_ref", R_ref, (3, 3)), _vectors("R", R, (3, 3))
    D = transpose(project_so3(R_ref)) @ project_so3(R)
    q = quat_from_matrix(D)
    return 2.0 * np.arctan2(np.linalg.norm(q[..., 1:], axis=-1), np.abs(q[..., 0]))


def rotation_about(axis, angle: float) -> np.ndarray:
    """Rotation by `angle` (rad) about a (not necessarily unit) axis."""
    axis = np.asarray(axis, dtype=float)
    return exp_so3(axis / np.linalg.norm(axis) * angle)


# --- quaternions (w, x, y, z) -------------------------------------------------

def quat_multiply(q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Hamilton product q1 q2 = (s1 s2 − v1·v2, s1 v2 + s2 v1 + v1 × v2)."""
    w1, x1, y1, z1 = q1[..., 0], q1[..., 1], q1[..., 2], q1[..., 3]
    w2, x2, y2, z2 = q2[..., 0], q2[..., 1], q2[..., 2], q2[..., 3]
    out = np.empty(np.broadcast_shapes(q1.shape, q2.shape))
    out[..., 0] = w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2
    out[..., 1] = w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2
    out[..., 2] = w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2
    out[..., 3] = w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2
    return out


def quat_times_vector(q: np.ndarray, w: np.ndarray) -> np.ndarray:
    """q ⊗ (0, w): the Hamilton product with a pure vector (used in q̇ = ½ q ⊗ (0, ω_body))."""
    pure = np.zeros(w.shape[:-1] + (4,))
    pure[..., 1:] = w
    return quat_multiply(q, pure)


def quat_rotate(q: np.ndarray, v: np.ndarray, inverse: bool = False) -> np.ndarray:
    """R(q) v (or R(q)ᵀ v if inverse) for a unit quaternion, without forming R:
    t = 2 u × v,  v' = v + s t + u × t   (u the vector part, s the scalar part; u → −u for Rᵀ)."""
    s, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    if inverse:
        x, y, z = -x, -y, -z
    a, b, c = v[..., 0], v[..., 1], v[..., 2]
    t0, t1, t2 = 2 * (y * c - z * b), 2 * (z * a - x * c), 2 * (x * b - y * a)
    out = np.empty(np.broadcast_shapes(q.shape[:-1], v.shape[:-1]) + (3,))
    out[..., 0] = a + s * t0 + (y * t2 - z * t1)
    out[..., 1] = b + s * t1 + (z * t0 - x * t2)
    out[..., 2] = c + s * t2 + (x * t1 - y * t0)
    return out


def quat_normalize(q: np.ndarray) -> np.ndarray:
    """q / |q|.  A quaternion whose norm is 0, inf or NaN (a run that blew up) gives NaN, never a
    finite-looking 0: the divergence check must see it."""
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        n = np.sqrt(np.sum(q * q, axis=-1, keepdims=True))
        return np.where(np.isfinite(n) & (n > 0.0), q / n, np.nan)


def matrix_from_quat(q: np.ndarray) -> np.ndarray:
    """R(q) for a quaternion q = (s, vx, vy, vz), normalised first (Baraff 2001, eq. 4-3)."""
    q = quat_normalize(np.asarray(q, dtype=float))
    s, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    xx, yy, zz, xy, xz, yz, sx, sy, sz = x * x, y * y, z * z, x * y, x * z, y * z, s * x, s * y, s * z
    R = np.empty(q.shape[:-1] + (3, 3))
    R[..., 0, 0], R[..., 0, 1], R[..., 0, 2] = 1 - 2 * (yy + zz), 2 * (xy - sz), 2 * (xz + sy)
    R[..., 1, 0], R[..., 1, 1], R[..., 1, 2] = 2 * (xy + sz), 1 - 2 * (xx + zz), 2 * (yz - sx)
    R[..., 2, 0], R[..., 2, 1], R[..., 2, 2] = 2 * (xz - sy), 2 * (yz + sx), 1 - 2 * (xx + yy)
    return R


def quat_from_matrix(R: np.ndarray) -> np.ndarray:
    """A unit quaternion (w >= 0) for the rotation R (Shepperd's method, stable for all angles)."""
    R = np.asarray(R, dtype=float)
    m00, m11, m22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    trace = m00 + m11 + m22
    cands = np.stack([
        np.stack([1 + trace, R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]], -1),
        np.stack([R[..., 2, 1] - R[..., 1, 2], 1 + m00 - m11 - m22, R[..., 0, 1] + R[..., 1, 0], R[..., 0, 2] + R[..., 2, 0]], -1),
        np.stack([R[..., 0, 2] - R[..., 2, 0], R[..., 0, 1] + R[..., 1, 0], 1 - m00 + m11 - m22, R[..., 1, 2] + R[..., 2, 1]], -1),
        np.stack([R[..., 1, 0] - R[..., 0, 1], R[..., 0, 2] + R[..., 2, 0], R[..., 1, 2] + R[..., 2, 1], 1 - m00 - m11 + m22], -1),
    ], -2)
    diag = np.stack([1 + trace, 1 + m00 - m11 - m22, 1 - m00 + m11 - m22, 1 - m00 - m11 + m22], -1)
    k = np.argmax(diag, axis=-1)
    q = np.take_along_axis(cands, k[..., None, None], axis=-2)[..., 0, :]
    q = quat_normalize(q)
    return q * np.where(q[..., :1] < 0, -1.0, 1.0)
