"""Rotations: the cross-product matrix ω*, the exponential map, SO(3) projection, quaternions.

Every function accepts a single object or a batch (leading dimensions, broadcast against each other),
so the same code serves one body or N bodies.

Quaternions are stored as (w, x, y, z) with w the scalar part (Baraff 2001, notes G, §4).

The formulas the engine's step uses are written once, in engine/algebra.py, for one body; here they are
applied row by row (engine/rows.py, through rowwise.py): star, cross, exp_so3, retract, quat_multiply,
quat_normalize, matrix_from_quat, and orthonormalize (engine/orthonormalize.py: orthonormalize_rows).  What the
engine does not have lives here only, in numpy: log_so3, project_so3 (by the SVD), orthogonality_error,
is_rotation, rotation_angle, quat_rotate, quat_from_matrix (its candidate then normalised by quat_normalize).
Importing this module loads no numba: the engine loads at the first call that needs it.
"""
from __future__ import annotations

import numpy as np

from .support import checks
from .rowwise import as_rows, engine_rows, matrix_parts, matrix_rows


def _vectors(name: str, a, trailing: tuple) -> np.ndarray:
    """a as a float64 array of the given trailing shape: a float64 ndarray passes at no cost (the engine's
    own calls); anything else is checked (numbers only, the shape) with a ValueError naming it."""
    if isinstance(a, np.ndarray) and a.dtype == np.float64 and a.shape[a.ndim - len(trailing):] == trailing:
        return a
    arr = checks.numbers(name, a, f"an array of numbers of shape (..., {', '.join(map(str, trailing))})")
    if arr.shape[arr.ndim - len(trailing):] != trailing or arr.ndim < len(trailing):
        raise ValueError(f"{name} must have shape (..., {', '.join(map(str, trailing))}), got shape {arr.shape}")
    return arr


def _shown(a: np.ndarray) -> str:
    """a, for a message: its numbers if few, else its shape and its first non-finite number."""
    if a.size <= 12:
        return str(a.tolist())
    bad = a[~np.isfinite(a)]
    return f"an array of shape {a.shape}" + (f" holding {bad[0]}" if bad.size else "")


def _quiet():
    """No floating-point warnings: a non-finite result is NaN, the signal (np.errstate, entered once each)."""
    return np.errstate(over="ignore", invalid="ignore", divide="ignore")


def _rows(names: tuple, arrays: tuple, tails: tuple):
    """as_rows(*arrays, tails=tails), with a ValueError naming the arrays if their leading axes do not broadcast."""
    try:
        return as_rows(*arrays, tails=tails)
    except ValueError:
        shapes = ", ".join(f"{n} {np.shape(a)}" for n, a in zip(names, arrays))
        raise ValueError(f"{' and '.join(names)} must broadcast against each other over their leading axes, "
                         f"got shapes {shapes}") from None


def star(omega: np.ndarray) -> np.ndarray:
    """ω* : the matrix with  ω* a = ω × a  (the slides' "ω*", Baraff eq. 2-5).

        ω* = [[ 0,  -ω_z,  ω_y],
              [ ω_z,  0,  -ω_x],
              [-ω_y, ω_x,   0 ]]

    omega: (..., 3) of finite numbers (else a ValueError naming it) -> (..., 3, 3).  (engine/algebra.py: star, row
    by row.)
    """
    omega = _vectors("omega", omega, (3,))
    if not np.all(np.isfinite(omega)):
        raise ValueError(f"omega must contain only finite numbers (no NaN or inf), got {_shown(omega)}")
    lead, (w,) = as_rows(omega, tails=((3,),))
    W = np.empty((len(w), 3, 3))
    engine_rows().star_rows(w, W)
    return W.reshape(lead + (3, 3))


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b = (a_y b_z − a_z b_y, a_z b_x − a_x b_z, a_x b_y − a_y b_x) on the last axis; a (..., 3) and
    b (..., 3) broadcast.  (engine/algebra.py: cross, row by row.)"""
    lead, (a, b) = _rows(("a", "b"), (_vectors("a", a, (3,)), _vectors("b", b, (3,))), ((3,), (3,)))
    c = np.empty_like(a)
    engine_rows().cross_rows(a, b, c)
    return c.reshape(lead + (3,))


def matvec(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """A b for stacks of matrices and vectors: (..., 3, 3), (..., 3) -> (..., 3)."""
    return np.einsum("...ij,...j->...i", A, b)


def transpose(A: np.ndarray) -> np.ndarray:
    """Aᵀ on the last two axes."""
    return np.swapaxes(A, -1, -2)


def exp_so3(phi: np.ndarray) -> np.ndarray:
    """Rotation by the angle |φ| about the axis φ/|φ| (Rodrigues' formula).

        exp(φ*) = I + sin|φ|/|φ| φ* + (1 − cos|φ|)/|φ|² φ*²

    Small angles (|φ|² < 1e-8) use the Taylor series, so the result is accurate to machine
    precision for every |φ|.  A φ that is not finite (or whose |φ|² overflows) gives NaN.
    phi: (..., 3) -> (..., 3, 3).  (engine/algebra.py: exp_so3, row by row.)
    """
    lead, (phi,) = as_rows(_vectors("phi", phi, (3,)), tails=((3,),))
    if phi.size and not np.abs(phi).max() < 1e150:      # NaN, inf, or |φ|² that may overflow: checked per row
        with np.errstate(over="ignore", invalid="ignore"):
            phi[~np.isfinite(np.sum(phi * phi, axis=-1))] = np.nan   # NaN in, NaN out (math.sin(inf) would raise)
    R = np.empty((len(phi), 3, 3))
    engine_rows().exp_so3_rows(phi, R)
    return R.reshape(lead + (3, 3))


def log_so3(R: np.ndarray) -> np.ndarray:
    """The rotation vector φ with exp_so3(φ) = R, |φ| in [0, π]: from R's quaternion (s, v),
    φ = 2 atan2(|v|, s) v / |v|.  (..., 3, 3) -> (..., 3)"""
    q = quat_from_matrix(_vectors("R", R, (3, 3)))
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


def nearest_rotation(R: np.ndarray, name: str = "R") -> np.ndarray:
    """project_so3's rotation U Vᵀ, each R of the stack (finite) on its own: where det R > 0 it is R's polar factor
    (Vᵀ's rotation and U's agree, no sign to flip), found by orthonormalize — 0.05-0.2 µs a matrix, the SVD 2 µs —
    and by the SVD (project_so3) where det R <= 0.  The two agree to rounding (~1e-15); an R already on SO(3) to
    rounding (max |RᵀR − I| < 1e-15) is its own nearest rotation, as it is."""
    R = _vectors(name, R, (3, 3))
    if not np.all(np.isfinite(R)):
        raise ValueError(f"{name} must hold finite numbers only (no NaN or inf) to be projected onto SO(3)")
    out = orthonormalize(R)
    flipped = ~(np.linalg.det(R) > 0.0)
    if flipped.any():
        out[flipped] = project_so3(R[flipped])
    return out


def orthonormalize(R: np.ndarray, tol: float = 1e-15, max_iter: int = 20) -> np.ndarray:
    """The nearest rotation to an almost-orthogonal R (polar factor), each R of the stack on its own, by
    Björck's iteration R ← R − ½ R (RᵀR − I) = R (3 I − RᵀR) / 2, which converges quadratically, until
    max |RᵀR − I| < tol (at most max_iter steps); if R is far from SO(3) (max |RᵀR − I| > 0.5), its polar
    factor by Newton's iteration R ← ½ (R + R⁻ᵀ), R⁻ᵀ = cof(R) / det R.  Both need det R > 0 to give a
    rotation (as every R of the Euler step has): with det R < 0 Björck converges to an orthogonal matrix of
    det −1, and Newton leaves an R with det R <= 0 as it is.  A blown-up R is left as it is, for the
    divergence check to see.  R (..., 3, 3) -> a new array (..., 3, 3).
    (engine/orthonormalize.py: orthonormalize_rows, the euler_project method's finish, on each R.)"""
    R = _vectors("R", R, (3, 3))
    tol = checks.real("tol", tol, low=0.0)
    max_iter = checks.integer("max_iter", max_iter, low=0)
    from .engine import orthonormalize as kernel    # numba loads at the first call, not at import
    lead, (R,) = as_rows(R, tails=((3, 3),))
    S = matrix_rows(np.zeros((len(R), 3)), R)      # the engine's state rows (x, R, P, L): only R is read and written
    with _quiet():                           # run as Python (NUMBA_DISABLE_JIT), a blown-up R's inf − inf would warn
        kernel.orthonormalize_rows(S, tol, max_iter)
    return matrix_parts(S)[1].reshape(lead + (3, 3))


def retract(R: np.ndarray) -> np.ndarray:
    """One Björck step, R ← R − ½ R (RᵀR − I): removes the rounding drift of a product of
    rotations (an error ε off SO(3) becomes ~ε²), so geometric methods stay on SO(3) to
    rounding over millions of steps.  (engine/algebra.py: retract, row by row.)"""
    lead, (R,) = as_rows(_vectors("R", R, (3, 3)), tails=((3, 3),))
    out = np.empty_like(R)
    engine_rows().retract_rows(R, out)
    return out.reshape(lead + (3, 3))


def orthogonality_error(R: np.ndarray) -> np.ndarray:
    """‖RᵀR − I‖ (Frobenius): 0 for a rotation; how far Euler's R has left SO(3)."""
    R = _vectors("R", R, (3, 3))
    return np.linalg.norm(transpose(R) @ R - np.eye(3), axis=(-2, -1))


def is_rotation(R: np.ndarray, tol: float = 1e-6) -> bool:
    """True if every R in the stack has ‖RᵀR − I‖ <= tol and det R > 0."""
    R = _vectors("R", R, (3, 3))
    return bool(np.all(orthogonality_error(R) <= tol) and np.all(np.linalg.det(R) > 0))


def rotation_angle(R_ref: np.ndarray, R: np.ndarray) -> np.ndarray:
    """Angle (rad) of R_refᵀ R, both first brought to their nearest rotation (nearest_rotation): the benchmarks'
    rotation error."""
    R_ref, R = _vectors("R_ref", R_ref, (3, 3)), _vectors("R", R, (3, 3))
    D = transpose(nearest_rotation(R_ref, "R_ref")) @ nearest_rotation(R, "R")
    q = quat_from_matrix(D)
    return 2.0 * np.arctan2(np.linalg.norm(q[..., 1:], axis=-1), np.abs(q[..., 0]))


def rotation_about(axis, angle: float) -> np.ndarray:
    """Rotation by `angle` (rad) about a (not necessarily unit) axis: exp_so3(angle · axis / |axis|)."""
    axis = checks.vector3("axis", axis)
    angle = checks.real("angle", angle)
    n = np.linalg.norm(axis)
    if not n > 0.0:
        raise ValueError(f"axis must be a nonzero vector, got {axis.tolist()}")
    return exp_so3(axis / n * angle)


# --- quaternions (w, x, y, z) -------------------------------------------------

def quat_multiply(q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Hamilton product q1 q2 = (s1 s2 − v1·v2, s1 v2 + s2 v1 + v1 × v2); q1 (..., 4) and q2 (..., 4)
    broadcast.  (engine/algebra.py: quat_multiply, row by row.)"""
    lead, (p, q) = _rows(("q1", "q2"), (_vectors("q1", q1, (4,)), _vectors("q2", q2, (4,))), ((4,), (4,)))
    out = np.empty_like(p)
    engine_rows().quat_multiply_rows(p, q, out)
    return out.reshape(lead + (4,))


def quat_times_vector(q: np.ndarray, w: np.ndarray) -> np.ndarray:
    """q ⊗ (0, w): the Hamilton product with a pure vector (used in q̇ = ½ q ⊗ (0, ω_body))."""
    q, w = _vectors("q", q, (4,)), _vectors("w", w, (3,))
    pure = np.zeros(w.shape[:-1] + (4,))
    pure[..., 1:] = w
    return quat_multiply(q, pure)


def quat_rotate(q: np.ndarray, v: np.ndarray, inverse: bool = False) -> np.ndarray:
    """R(q) v (or R(q)ᵀ v if inverse) for a unit quaternion, without forming R:
    t = 2 u × v,  v' = v + s t + u × t   (u the vector part, s the scalar part; u → −u for Rᵀ)."""
    q, v = _vectors("q", q, (4,)), _vectors("v", v, (3,))
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
    finite-looking 0: the divergence check must see it.  (engine/algebra.py: quat_normalize, row by row.)"""
    lead, (q,) = as_rows(_vectors("q", q, (4,)), tails=((4,),))
    out = np.empty_like(q)
    with _quiet():                           # run as Python, |q|² overflowing would warn: NaN is the signal
        engine_rows().quat_normalize_rows(q, out)
    return out.reshape(lead + (4,))


def matrix_from_quat(q: np.ndarray) -> np.ndarray:
    """R(q) for a quaternion q = (s, vx, vy, vz), normalised first (Baraff 2001, eq. 4-3):

        R = [[1 − 2(y² + z²), 2(xy − sz),     2(xz + sy)    ],
             [2(xy + sz),     1 − 2(x² + z²), 2(yz − sx)    ],
             [2(xz − sy),     2(yz + sx),     1 − 2(x² + y²)]]

    q (..., 4) -> (..., 3, 3).  (engine/algebra.py: matrix_from_quat, row by row.)"""
    lead, (q,) = as_rows(_vectors("q", q, (4,)), tails=((4,),))
    R = np.empty((len(q), 3, 3))
    with _quiet():                           # as quat_normalize
        engine_rows().matrix_from_quat_rows(q, R)
    return R.reshape(lead + (3, 3))


def quat_from_matrix(R: np.ndarray) -> np.ndarray:
    """A unit quaternion (w >= 0) for the rotation R (Shepperd's method, stable for all angles)."""
    R = _vectors("R", R, (3, 3))
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
