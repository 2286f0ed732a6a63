"""The derived quantities over many rows — a State's bodies, a trajectory's recorded states — for the
diagnostics (rbcourse.state: velocity, inverse_inertia, angular_velocity; the trajectory's energy): the
step's own functions (motion.py), applied row by row, so each formula is written once.

    v = P / M,    I⁻¹(t) = R I⁻¹_body Rᵀ,    ω = I⁻¹(t) L,    T = ½ P·v + ½ L·ω,    U (gravity, springs)

Rows are the flattened leading axes: P (n, 3), M (n,), R (n, 3, 3), I_body_inv (n, 3, 3), L (n, 3);
for U, the scene's states S (n, N, 18) (motion.py's layout: x, R row by row, P, L) and its System.
"""
from __future__ import annotations

from .jit import njit
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
