"""3-vectors, 3×3 matrices and quaternions as tuples of floats: the engine's algebra.

A vector is (a0, a1, a2); a matrix is its three rows ((A00, A01, A02), (A10, ...), ...); a quaternion
is (s, vx, vy, vz).  Tuples are values: compiled, they live in registers, where a small numpy array
would be allocated on the heap at every operation (23× slower for a step of one body).  Each
function is one line of the slides' algebra, named as it is read: matvec(R, b) is R b,
matmul(matmul(R, I_body_inv), transpose(R)) is R I⁻¹_body Rᵀ, cross(r - x, F) is (r − x) × F.
"""
from __future__ import annotations

import math

from .jit import inline


@inline
def add(a, b):
    """a + b"""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@inline
def sub(a, b):
    """a − b"""
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@inline
def scale(s, a):
    """s a (a number times a vector)"""
    return (s * a[0], s * a[1], s * a[2])


@inline
def axpy(a, s, b):
    """a + s b"""
    return (a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2])


@inline
def dot(a, b):
    """a · b"""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@inline
def norm(a):
    """|a|"""
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@inline
def cross(a, b):
    """a × b"""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@inline
def matvec(A, b):
    """A b"""
    return (dot(A[0], b), dot(A[1], b), dot(A[2], b))


@inline
def transpose(A):
    """Aᵀ"""
    return ((A[0][0], A[1][0], A[2][0]), (A[0][1], A[1][1], A[2][1]), (A[0][2], A[1][2], A[2][2]))


@inline
def matmul(A, B):
    """A B (row i of A B is Bᵀ applied to row i of A)"""
    Bt = transpose(B)
    return (matvec(Bt, A[0]), matvec(Bt, A[1]), matvec(Bt, A[2]))


@inline
def mat_axpy(A, s, B):
    """A + s B (matrices)"""
    return (axpy(A[0], s, B[0]), axpy(A[1], s, B[1]), axpy(A[2], s, B[2]))


@inline
def star(w):
    """ω* : the matrix with ω* r = ω × r (slide "Les Formules")."""
    return ((0.0, -w[2], w[1]), (w[2], 0.0, -w[0]), (-w[1], w[0], 0.0))


@inline
def quat_multiply(p, q):
    """Hamilton product p q = (s₁s₂ − v₁·v₂, s₁v₂ + s₂v₁ + v₁ × v₂)."""
    return (p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
            p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
            p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
            p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0])


@inline
def quat_normalize(q):
    """q / |q|; a quaternion whose norm is 0, inf or NaN (a run that blew up) gives NaN, never a
    finite-looking 0: the divergence check must see it."""
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    if not (n > 0.0 and n < math.inf):
        return (math.nan, math.nan, math.nan, math.nan)
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


@inline
def quat_of_rotation(phi):
    """The unit quaternion of exp(φ*), the turn by |φ| about φ/|φ|:  (cos |φ|/2, sin(|φ|/2) φ/|φ|)
    (small angles by the Taylor series of sin(|φ|/2)/|φ|)."""
    theta2 = dot(phi, phi)
    if theta2 < 1e-8:
        c, s = 1.0 - theta2 / 8.0 + theta2 * theta2 / 384.0, 0.5 - theta2 / 48.0 + theta2 * theta2 / 3840.0
    else:
        theta = math.sqrt(theta2)
        c, s = math.cos(0.5 * theta), math.sin(0.5 * theta) / theta
    return (c, s * phi[0], s * phi[1], s * phi[2])


@inline
def matrix_from_quat(q):
    """R(q) for a quaternion q = (s, vx, vy, vz), normalised first (Baraff 2001, eq. 4-3)."""
    s, x, y, z = quat_normalize(q)
    xx, yy, zz, xy, xz, yz, sx, sy, sz = x * x, y * y, z * z, x * y, x * z, y * z, s * x, s * y, s * z
    return ((1 - 2 * (yy + zz), 2 * (xy - sz), 2 * (xz + sy)),
            (2 * (xy + sz), 1 - 2 * (xx + zz), 2 * (yz - sx)),
            (2 * (xz - sy), 2 * (yz + sx), 1 - 2 * (xx + yy)))


@inline
def quat_from_matrix(R):
    """A unit quaternion q = (s, x, y, z), s >= 0, with R(q) = R, by Shepperd's method (stable at every angle):
    the four diagonal terms

        1 + tr R = 4 s²,   1 + R00 − R11 − R22 = 4 x²,   1 − R00 + R11 − R22 = 4 y²,   1 − R00 − R11 + R22 = 4 z²

    the largest (largest_of_four) picks one of the candidates 4 s q, 4 x q, 4 y q, 4 z q (each that term and
    sums and differences of R's off-diagonal entries), normalised, then negated if s < 0.  The same numbers as
    rbcourse.rotation.quat_from_matrix, which lays out a State for the quaternion methods."""
    m00, m11, m22 = R[0][0], R[1][1], R[2][2]
    trace = m00 + m11 + m22
    d = (1 + trace, 1 + m00 - m11 - m22, 1 - m00 + m11 - m22, 1 - m00 - m11 + m22)
    k = largest_of_four(d)
    if k == 0:
        q = (d[0], R[2][1] - R[1][2], R[0][2] - R[2][0], R[1][0] - R[0][1])
    elif k == 1:
        q = (R[2][1] - R[1][2], d[1], R[0][1] + R[1][0], R[0][2] + R[2][0])
    elif k == 2:
        q = (R[0][2] - R[2][0], R[0][1] + R[1][0], d[2], R[1][2] + R[2][1])
    else:
        q = (R[1][0] - R[0][1], R[0][2] + R[2][0], R[1][2] + R[2][1], d[3])
    q = quat_normalize(q)
    return (q[0] * -1.0, q[1] * -1.0, q[2] * -1.0, q[3] * -1.0) if q[0] < 0 else q


@inline
def largest_of_four(d):
    """The index of the largest of d's four numbers: the first on a tie, the first NaN if one is (numpy's argmax)."""
    k = 0
    for j in range(1, 4):
        if d[k] != d[k]:
            return k
        if not d[j] <= d[k]:
            k = j
    return k


@inline
def quat_rotate_inverse(q, v):
    """R(q)ᵀ v for a unit quaternion q = (s, u), without forming R:  t = 2 u' × v,  Rᵀ v = v + s t + u' × t,
    u' = −u.  The same numbers as rbcourse.rotation.quat_rotate(q, v, inverse=True)."""
    s, x, y, z = q[0], -q[1], -q[2], -q[3]
    a, b, c = v[0], v[1], v[2]
    t0, t1, t2 = 2 * (y * c - z * b), 2 * (z * a - x * c), 2 * (x * b - y * a)
    return (a + s * t0 + (y * t2 - z * t1), b + s * t1 + (z * t0 - x * t2), c + s * t2 + (x * t1 - y * t0))


@inline
def quat_axpy(q, s, p):
    """q + s p (quaternions)"""
    return (q[0] + s * p[0], q[1] + s * p[1], q[2] + s * p[2], q[3] + s * p[3])


@inline
def identity():
    """I, the 3×3 identity"""
    return ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


@inline
def exp_so3(phi):
    """Rotation by the angle |φ| about the axis φ/|φ| (Rodrigues' formula):

        exp(φ*) = I + sin|φ|/|φ| φ* + (1 − cos|φ|)/|φ|² φ*²

    small angles by the Taylor series, so it is accurate to rounding for every |φ|."""
    theta2 = dot(phi, phi)
    if not theta2 < math.inf:             # NaN or inf (a run that blew up): NaN, as the compiled sin would give
        n = math.nan
        return ((n, n, n), (n, n, n), (n, n, n))
    if theta2 < 1e-8:
        a = 1.0 - theta2 / 6.0 + theta2 * theta2 / 120.0
        b = 0.5 - theta2 / 24.0 + theta2 * theta2 / 720.0
    else:
        theta = math.sqrt(theta2)
        a = math.sin(theta) / theta
        b = (1.0 - math.cos(theta)) / theta2
    K = star(phi)
    K2 = matmul(K, K)
    I = identity()
    return (axpy(axpy(I[0], a, K[0]), b, K2[0]), axpy(axpy(I[1], a, K[1]), b, K2[1]),
            axpy(axpy(I[2], a, K[2]), b, K2[2]))


@inline
def gram_defect(R):
    """E = RᵀR − I: zero for a rotation (how far R has left SO(3))."""
    E = matmul(transpose(R), R)
    return ((E[0][0] - 1.0, E[0][1], E[0][2]), (E[1][0], E[1][1] - 1.0, E[1][2]), (E[2][0], E[2][1], E[2][2] - 1.0))


@inline
def bjorck_step(R, E):
    """R − ½ R E, with E = RᵀR − I (gram_defect): one step of Björck's iteration towards the polar factor."""
    return mat_axpy(R, -0.5, matmul(R, E))


@inline
def retract(R):
    """One Björck step, R ← R − ½ R (RᵀR − I): removes the rounding drift of a product of rotations
    (an error ε off SO(3) becomes ~ε²)."""
    return bjorck_step(R, gram_defect(R))


@inline
def solve3(A, b):
    """x with A x = b (Cramer's rule through the cofactors: x = cof(A)ᵀ b / det A)."""
    c0, c1, c2 = cross(A[1], A[2]), cross(A[2], A[0]), cross(A[0], A[1])   # columns of A⁻¹ times det A
    det = dot(A[0], c0)
    return scale(1.0 / det, (c0[0] * b[0] + c1[0] * b[1] + c2[0] * b[2],
                             c0[1] * b[0] + c1[1] * b[1] + c2[1] * b[2],
                             c0[2] * b[0] + c1[2] * b[1] + c2[2] * b[2]))


@inline
def positive_definite3(A):
    """A (3×3, symmetric) positive definite: its leading principal minors A00, A00 A11 − A01 A10 and det A
    are all > 0 (Sylvester's criterion: the three pivots of its Cholesky factor, Δ1, Δ2/Δ1, Δ3/Δ2, all > 0)."""
    return A[0][0] > 0.0 and A[0][0] * A[1][1] - A[0][1] * A[1][0] > 0.0 and dot(A[0], cross(A[1], A[2])) > 0.0
