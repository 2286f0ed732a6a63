"""The contact points of a body against the ground, compiled: ρ = r − x in world axes, from the body's shape,
its rotation R and its shape data (engine/contact.py, the ground contact solver, reads them).

* BOX: its 8 corners, ρ = R (σ ∘ half), σ = (±1, ±1, ±1);
* CYLINDER (axis = body z; half = (radius, radius, half height)): 4 points on each rim, the lowest one and
  those at 90°, 180°, 270° from it, on the bottom rim (k < 4) and the top one (k >= 4);
* ELLIPSOID (semi-axes half along the principal axes; a sphere too): its lowest point, one only.

lowest_gap: how far the lowest of them is above the ground (a start below it is refused: rbcourse/contact.py).

The shape codes are rbcourse/contact.py's SHAPE_CODES; K_MAX bounds the points of a body (the solver's scratch).
"""
from __future__ import annotations

from .algebra import add, cross, dot, matmul, matvec, norm, scale, sub
from .jit import inline

BOX, CYLINDER, ELLIPSOID = 0, 1, 2     # shapes: 8 corners; 4 points on each rim; the lowest point
K_MAX = 8                              # contact points per body, at most


@inline
def box_corner(R, half, k):
    """Corner k of a box, ρ = R (σ ∘ half), σ = (±1, ±1, ±1) in the order (−−−, −−+, −+−, ..., +++)."""
    sx = 1.0 if k & 4 else -1.0
    sy = 1.0 if k & 2 else -1.0
    sz = 1.0 if k & 1 else -1.0
    return matvec(R, (sx * half[0], sy * half[1], sz * half[2]))


@inline
def cylinder_point(R, radius, half_height, k):
    """Point k of a cylinder (axis a = body z): 4 points on each rim, the lowest one u and those at 90°,
    180°, 270° from it, u ∝ −(n − (n·a) a) (standing upright: the body x axis ⟂ a); rim k % 4, bottom
    (−a half_height) for k < 4, top for k >= 4."""
    a0 = (R[0][2], R[1][2], R[2][2])
    a = scale(1.0 / norm(a0), a0)
    down = sub(scale(a[2], a), (0.0, 0.0, 1.0))
    size = norm(down)
    if size > 1e-9:
        u = (down[0] / size, down[1] / size, down[2] / size)
    else:
        x0 = (R[0][0], R[1][0], R[2][0])
        side = sub(x0, scale(dot(x0, a), a))
        ns = norm(side)
        u = (side[0] / ns, side[1] / ns, side[2] / ns)
    au = cross(a, u)
    r = k % 4
    if r == 0:
        rim = scale(radius, u)
    elif r == 1:
        rim = scale(radius, au)
    elif r == 2:
        rim = scale(radius, (-u[0], -u[1], -u[2]))
    else:
        rim = scale(radius, (-au[0], -au[1], -au[2]))
    cap = scale(half_height, a)
    return sub(rim, cap) if k < 4 else add(rim, cap)


@inline
def ellipsoid_point(R, axes, half):
    """The lowest point of the ellipsoid of semi-axes half along the principal axes Q = R axes:
    ρ = −Q A² Qᵀ n / |A Qᵀ n|, A = diag(half)."""
    Q = matmul(R, axes)
    a_n = (half[0] * Q[2][0], half[1] * Q[2][1], half[2] * Q[2][2])
    w = matvec(Q, (half[0] * a_n[0], half[1] * a_n[1], half[2] * a_n[2]))
    d = max(norm(a_n), 1e-300)
    return (-w[0] / d, -w[1] / d, -w[2] / d)


@inline
def contact_point(shape, R, half, axes, k):
    """ρ of the body's contact point k (world axes)."""
    if shape == BOX:
        return box_corner(R, half, k)
    if shape == CYLINDER:
        return cylinder_point(R, half[0], half[2], k)
    return ellipsoid_point(R, axes, half)


@inline
def n_points(shape):
    """How many contact points a shape has."""
    return 1 if shape == ELLIPSOID else K_MAX


@inline
def lowest_gap(shape, R, half, axes, x_z, height):
    """How far the body's lowest contact point is above the plane z = height, min over k of x_z + ρ_k,z − height
    (negative: below it), with x_z the centre of mass's height.  (rbcourse/contact.py: Ground.check_start
    refuses a start below the ground with it.)"""
    gap = x_z + contact_point(shape, R, half, axes, 0)[2] - height
    for k in range(1, n_points(shape)):
        gap = min(gap, x_z + contact_point(shape, R, half, axes, k)[2] - height)
    return gap
