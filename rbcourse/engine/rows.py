"""The derived quantities over many rows — a State's bodies, a trajectory's recorded states — for the
diagnostics (rbcourse.state: velocity, inverse_inertia, angular_velocity; the trajectory's energy): the
step's own functions (motion.py), applied row by row, so each formula is written once.

    v = P / M,    I⁻¹(t) = R I⁻¹_body Rᵀ,    ω = I⁻¹(t) L,    T = ½ P·v + ½ L·ω,    U (gravity, springs)

Rows are the flattened leading axes: P (n, 3), M (n,), R (n, 3, 3), I_body_inv (n, 3, 3), L (n, 3);
for U, the scene's states S (n, N, 18) (motion.py's layout: x, R row by row, P, L) and its System.

The rotation helpers (rbcourse.rotation: star, cross, exp_so3, retract, quat_multiply, quat_normalize,
matrix_from_quat) are algebra.py's functions applied the same way, row by row.
"""
from __future__ import annotations

from .algebra import cross, exp_so3, matrix_from_quat, quat_multiply, quat_normalize, retract, star
from .jit import inline, njit
from .motion import angular_velocity, inverse_inertia, kinetic_energy, mat, potential, put, put_mat, vec, velocity


@njit
def velocity_rows(P, M, v):
    """v = P / M for every row, into v (n, 3)."""
    for i in range(P.shape[0]):
        put(v, i, velocity(vec(P, i), M[i]))


@njit
def inverse_inertia_rows(R, I_body_inv, I_inv):
    """I⁻¹(t) = R I⁻¹_body Rᵀ for every row, into I_inv (n, 3, 3)."""
    for i in range(R.shape[0]):
        put_mat(I_inv, i, inverse_inertia(mat(R, i), mat(I_body_inv, i)))


@njit
def angular_velocity_rows(I_inv, L, omega):
    """ω = I⁻¹(t) L for every row, into omega (n, 3)."""
    for i in range(L.shape[0]):
        put(omega, i, angular_velocity(mat(I_inv, i), vec(L, i)))


@njit
def kinetic_energy_rows(R, P, L, M, I_body_inv, T):
    """T = ½ P·v + ½ L·ω for every row, into T (n,)."""
    for i in range(P.shape[0]):
        T[i] = kinetic_energy(mat(R, i), vec(P, i), vec(L, i), M[i], mat(I_body_inv, i))


@njit
def potential_rows(sys, S, U):
    """U of every body in every state: S (n, N, 18) -> U (n, N)."""
    for k in range(S.shape[0]):
        for i in range(S.shape[1]):
            U[k, i] = potential(sys, S[k], i)


# --- the rotation helpers (rbcourse.rotation): algebra.py's functions, row by row --------------------
# ω (n, 3), a and b (n, 3), φ (n, 3), R (n, 3, 3), quaternions (n, 4) as (s, vx, vy, vz).

@inline
def quat(a, i):
    """Row i of an (n, 4) array, as a quaternion."""
    return (a[i, 0], a[i, 1], a[i, 2], a[i, 3])


@inline
def put_quat(a, i, q):
    """Row i of an (n, 4) array := q."""
    a[i, 0], a[i, 1], a[i, 2], a[i, 3] = q[0], q[1], q[2], q[3]


@njit
def star_rows(omega, W):
    """W = ω* for every row, into W (n, 3, 3): the matrix with ω* a = ω × a,
    ω* = ((0, −ω_z, ω_y), (ω_z, 0, −ω_x), (−ω_y, ω_x, 0))."""
    for i in range(omega.shape[0]):
        put_mat(W, i, star(vec(omega, i)))


@njit
def cross_rows(a, b, c):
    """c = a × b for every row, into c (n, 3):
    a × b = (a_y b_z − a_z b_y, a_z b_x − a_x b_z, a_x b_y − a_y b_x)."""
    for i in range(a.shape[0]):
        put(c, i, cross(vec(a, i), vec(b, i)))


@njit
def exp_so3_rows(phi, R):
    """R = exp(φ*) for every row, into R (n, 3, 3), by Rodrigues' formula (its Taylor series for small |φ|):
    exp(φ*) = I + sin|φ|/|φ| φ* + (1 − cos|φ|)/|φ|² φ*²."""
    for i in range(phi.shape[0]):
        put_mat(R, i, exp_so3(vec(phi, i)))


@njit
def retract_rows(R, out):
    """One Björck step for every row, into out (n, 3, 3) (an error ε off SO(3) becomes ~ε²):
    out = R − ½ R (RᵀR − I)."""
    for i in range(R.shape[0]):
        put_mat(out, i, retract(mat(R, i)))


@njit
def quat_multiply_rows(p, q, out):
    """The Hamilton product p q for every row, into out (n, 4): with p = (s₁, v₁), q = (s₂, v₂),
    p q = (s₁s₂ − v₁·v₂, s₁v₂ + s₂v₁ + v₁ × v₂)."""
    for i in range(p.shape[0]):
        put_quat(out, i, quat_multiply(quat(p, i), quat(q, i)))


@njit
def quat_normalize_rows(q, out):
    """q / |q| for every row, into out (n, 4): |q| = sqrt(s² + vx² + vy² + vz²) for q = (s, vx, vy, vz);
    NaN where |q| is 0, inf or NaN (a run that blew up), never a finite-looking 0."""
    for i in range(q.shape[0]):
        put_quat(out, i, quat_normalize(quat(q, i)))


@njit
def matrix_from_quat_rows(q, R):
    """R(q) for every row, into R (n, 3, 3): with (s, v) = q / |q| (q normalised first),
    R(q) = I + 2 s v* + 2 v*²."""
    for i in range(q.shape[0]):
        put_mat(R, i, matrix_from_quat(quat(q, i)))
