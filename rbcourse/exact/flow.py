"""The exact torque-free flow of the orientation over one step, for the splitting methods
(kick – free flow – kick):  R(h) with Ṙ = ω* R, ω = R I⁻¹ Rᵀ L, L constant (world).

FreeRotationFlow(inertia) does the set-up that depends only on the inertia once; many bodies
go through free_body.Motion as arrays, one body through plain Python floats (the hot path):
with m = RᵀL in body axes,

    spherical:   R(h) = R exp(h m*/I)
    symmetric:   R(h) = R exp(h m*/I_eq) exp(h (1/I_s − 1/I_eq)(a·m) a*)     (a the symmetry axis)
    on an axis:  R(h) = R exp(h m*/I_k)
    asymmetric:  free_body's steps 1 and 2 at t = h (Jacobi's sn, cn, dn and Π: elliptic.py),

the exponentials as unit quaternions (cos ½θ, sin ½θ φ/θ), θ = |φ|.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import special

from .. import checks
from ..body import RigidBody, inertia_matrix
from ..rotation import transpose
from .elliptic import LANDEN_MC, SEPARATRIX_MC, jacobi_landen_float, pi_big_n, sech
from .free_body import RELABEL, SYMMETRY_TOL, ZERO_COMPONENT, Motion, is_identity

__all__ = ["FreeRotationFlow", "free_rotation_flow"]


class FreeRotationFlow:
    """The exact torque-free flow of the orientation, for splitting integrators.

    ``flow = FreeRotationFlow(inertia)`` does the set-up that depends only on the
    inertia (the principal axes) once; ``flow(R, L, h)`` then returns R(h), the
    orientation after a time h of torque-free motion with the constant world angular
    momentum L:  Ṙ = ω* R,  ω = R I⁻¹ Rᵀ L.  Use it as the "free rigid body" step of a
    kick–flow–kick method (L is unchanged by this step; the kicks change it).

    inertia: body-frame inertia about the rotation centre — 3 principal moments (3,),
    one 3×3 matrix, one matrix per body (N, 3, 3), or a RigidBody (its I_body).
    R: (3, 3) or (N, 3, 3); L: (3,) or (N, 3) (world); h: a real step (any sign).

    A single body (R (3, 3), or (1, 3, 3)) takes a plain-Python fast path; N bodies
    are computed as arrays.  R, L are not checked for finiteness here (it is a hot
    path); shapes and h are.
    """

    def __init__(self, inertia):
        if isinstance(inertia, RigidBody):
            inertia = inertia.I_body
        arr = checks.numbers("inertia", inertia, "3 principal moments, a 3x3 matrix or (N, 3, 3) matrices")
        if arr.shape in ((3,), (3, 3)):
            mats = inertia_matrix(arr)[None]
            self.n = None
        elif arr.ndim == 3 and arr.shape[1:] == (3, 3) and arr.shape[0] > 0:
            mats = np.stack([inertia_matrix(a) for a in arr])
            self.n = arr.shape[0]
        else:
            raise ValueError(f"inertia must have shape (3,), (3, 3) or (N, 3, 3), got shape {arr.shape}")
        moments, axes = np.linalg.eigh(mats)
        axes[np.linalg.det(axes) < 0, :, 2] *= -1.0
        self.inertia = mats if self.n is not None else mats[0]
        self.moments = moments                         # (N or 1, 3) ascending
        self.axes = axes                               # (N or 1, 3, 3), det +1
        self.identity_axes = bool(all(is_identity(a) for a in axes))
        # a single body (also given as (1, 3, 3)): plain-float constants for the fast path
        self._one = _OneBody(moments[0], axes[0]) if self.n in (None, 1) else None

    def __call__(self, R, L, h):
        """R(h) for the constant world angular momentum L (see the class docstring)."""
        h = checks.real("h", h)
        R = np.asarray(R, dtype=float)
        L = np.asarray(L, dtype=float)
        if R.ndim == 2:
            if R.shape != (3, 3) or L.shape != (3,):
                raise ValueError(f"R must have shape (3, 3) and L (3,) (or (N, 3, 3) and (N, 3)), "
                                 f"got R {R.shape} and L {L.shape}")
            if self.n is not None and self.n != 1:
                raise ValueError(f"the flow holds {self.n} bodies but R has shape (3, 3): pass R (N, 3, 3)")
            return self._one.flow(R, L, h)
        if R.ndim != 3 or R.shape[1:] != (3, 3) or L.shape != (R.shape[0], 3):
            raise ValueError(f"R must have shape (N, 3, 3) and L (N, 3) (or (3, 3) and (3,)), "
                             f"got R {R.shape} and L {L.shape}")
        if self.n is not None and self.n != R.shape[0]:
            raise ValueError(f"the flow holds {self.n} bodies but R holds {R.shape[0]}")
        if R.shape[0] == 1 and self._one is not None:
            return self._one.flow(R[0], L[0], h)[None]
        return self._many(R, L, h)

    def _many(self, R, L, h):
        if h == 0.0:
            return R.copy()
        N = R.shape[0]
        A = np.broadcast_to(self.axes, (N, 3, 3))
        moments = np.broadcast_to(self.moments, (N, 3))
        mb = np.einsum("nji,nj->ni", R, L)             # Rᵀ L
        mp = mb if self.identity_axes else np.einsum("nji,nj->ni", A, mb)
        D = Motion(moments, mp).increment(np.array([h]))[0]
        if not self.identity_axes:
            D = A @ D @ transpose(A)
        return R @ D


def free_rotation_flow(inertia, R, L, h):
    """R(h): the exact torque-free flow of the orientation (one call of FreeRotationFlow).

    inertia: body-frame inertia — 3 principal moments, a 3×3 matrix, or (N, 3, 3).
    R (3, 3) or (N, 3, 3) at the start, L (3,) or (N, 3) the constant world angular
    momentum, h the time step (any sign).  Returns R(h) with Ṙ = ω* R, ω = R I⁻¹ Rᵀ L.
    For repeated steps build ``FreeRotationFlow(inertia)`` once and call it (the
    eigen-decomposition of the inertia is then done once).
    """
    R_arr = checks.numbers("R", R, "an array of numbers of shape (3, 3) or (N, 3, 3)")
    L_arr = checks.numbers("L", L, "an array of numbers of shape (3,) or (N, 3)")
    for name, arr in (("R", R_arr), ("L", L_arr)):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must contain only finite numbers, got {arr.tolist()}")
    return FreeRotationFlow(inertia)(R_arr, L_arr, h)



class _OneBody:
    """Precomputed constants of one body; flow(R, L, h) with Python floats throughout.

    The closed forms are applied in body axes (no change of frame): with m = RᵀL,
    R(h) = R exp(h m*/I_eq) exp(h (1/I_s − 1/I_eq)(a·m) a*)  (a the body symmetry axis).
    """

    def __init__(self, moments, axes):
        I1, I2, I3 = (float(v) for v in moments)
        axes = np.asarray(axes, dtype=float)
        self.I = (I1, I2, I3)
        self.A = None if is_identity(axes) else axes.tolist()
        self.At = None if self.A is None else axes.T.tolist()
        sym12 = I2 - I1 <= SYMMETRY_TOL * I3
        sym23 = I3 - I2 <= SYMMETRY_TOL * I3
        self.a = None
        if sym12 and sym23:
            self.kind, self.I_eq = "spherical", (I1 + I2 + I3) / 3.0
        elif sym12 or sym23:
            s = 2 if sym12 else 0
            self.kind = "symmetric"
            self.I_eq = 0.5 * (I1 + I2) if sym12 else 0.5 * (I2 + I3)
            self.a = axes[:, s].tolist()                    # symmetry axis in body axes
            self.c_s = 1.0 / self.I[s] - 1.0 / self.I_eq
        else:
            self.kind, self.I_eq = "asymmetric", None

    def flow(self, R, L, h):
        if h == 0.0:
            return R.copy()
        Rl = R.tolist()
        L0, L1, L2 = L.tolist()
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = Rl
        m0, m1, m2 = r00 * L0 + r10 * L1 + r20 * L2, r01 * L0 + r11 * L1 + r21 * L2, r02 * L0 + r12 * L1 + r22 * L2
        kind = self.kind
        if kind == "spherical":
            k = h / self.I_eq
            D = _quat_matrix(_quat_rotvec((k * m0, k * m1, k * m2)))
        elif kind == "symmetric":
            k = h / self.I_eq
            a0, a1, a2 = self.a
            c = h * self.c_s * (a0 * m0 + a1 * m1 + a2 * m2)
            D = _quat_matrix(_quat_mul(_quat_rotvec((k * m0, k * m1, k * m2)), _quat_rotvec((c * a0, c * a1, c * a2))))
        else:
            A = self.A
            mp = [m0, m1, m2] if A is None else [A[0][i] * m0 + A[1][i] * m1 + A[2][i] * m2 for i in range(3)]
            Ln = math.hypot(mp[0], mp[1], mp[2])
            if Ln == 0.0:
                return R.copy()
            mu = [v / Ln if abs(v / Ln) >= ZERO_COMPONENT else 0.0 for v in mp]
            if (mu[0] != 0.0) + (mu[1] != 0.0) + (mu[2] != 0.0) <= 1:    # spin along a principal axis
                k = h / self.I[max(range(3), key=lambda i: abs(mu[i]))]
                D = _quat_matrix(_quat_rotvec((k * m0, k * m1, k * m2)))
            else:
                D = _elliptic_one(self.I, mu, Ln, h)
                if A is not None:
                    D = _mm(_mm(A, D), self.At)
        return np.array(_mm(Rl, D))


def _elliptic_one(I, mu, Ln, h):
    """D(h) in principal axes for one asymmetric body off its axes (free_body.Elliptic's formulas, in floats)."""
    I1, I2, I3 = I
    m1, m2, m3 = mu
    delta = m1 * m1 * ((I1 - I2) / I1) + m3 * m3 * ((I3 - I2) / I3)
    flip = delta < 0
    if flip:
        J1, J2, J3 = I3, I2, I1
        w1, w2, w3 = m3, -m2, m1
    else:
        J1, J2, J3 = I1, I2, I3
        w1, w2, w3 = m1, m2, m3
    d31, d32, d21 = J3 - J1, J3 - J2, J2 - J1
    beta = w2 * w2 * (d21 / J2) + w3 * w3 * (d31 / J3)
    mc = min(max((d31 * delta) / (d32 * beta), 0.0), 1.0)
    if mc < SEPARATRIX_MC:
        mc = 0.0
    a1 = math.sqrt(w1 * w1 + w2 * w2 * ((J1 * d32) / (J2 * d31)))
    a2 = math.sqrt(w2 * w2 + w1 * w1 * ((J2 * d31) / (J1 * d32)))
    a3 = math.sqrt(w3 * w3 + w2 * w2 * ((J3 * d21) / (J2 * d31)))
    s1 = -1.0 if w1 < 0 else 1.0
    s3 = -1.0 if w3 < 0 else 1.0
    lam = s1 * s3 * math.copysign(1.0, d31) * Ln * math.sqrt((d32 * beta) / (J1 * J2 * J3))
    n = -(J3 * d21) / (J1 * d32)
    C = Ln * d31 / (J1 * J3 * lam)
    sn0 = w2 / a2
    cn0 = abs(w1) / a1
    hyp = math.hypot(sn0, cn0)
    sn0, cn0 = sn0 / hyp, cn0 / hyp
    dn0 = abs(w3) / a3
    tau0 = sn0 * float(special.elliprf(cn0 * cn0, dn0 * dn0, 1.0))
    u = tau0 + lam * h
    big = abs(n) > 1.0
    if mc == 0.0:
        nu = -n
        r = math.sqrt(nu)
        sn, cn = math.tanh(u), sech(u, math.exp)
        dn = cn
        if big:
            P = (u + r * math.atan(r * sn)) / (1.0 + nu)
            P0 = (tau0 + r * math.atan(r * math.tanh(tau0))) / (1.0 + nu)
        else:
            P = (r * math.atan(r * sn) - nu * u) / (1.0 + nu)
            P0 = (r * math.atan(r * math.tanh(tau0)) - nu * tau0) / (1.0 + nu)
    else:
        if abs(u) <= max(abs(tau0), 1.5707963267948966):     # |u| <= K for sure (|τ0| <= K, π/2 <= K)
            j, ur = 0, u
        else:
            K = float(special.elliprf(0.0, mc, 1.0))
            j = round(u / (2.0 * K))
            ur = u - j * 2.0 * K
        if mc >= LANDEN_MC:
            sn, cn, dn, _ = special.ellipj(ur, 1.0 - mc)
            sn, cn, dn = float(sn), float(cn), float(dn)
        else:
            sn, cn, dn = jacobi_landen_float(ur, mc)
        if big:
            w = (1.0 - mc) / n
            P = float(pi_big_n(sn, cn, dn, n, w))
            P0 = float(pi_big_n(sn0, cn0, dn0, n, w))
            if j:
                P += 2.0 * j * float(special.elliprc(0.0, (1.0 - n) * (1.0 - w))
                                     - w / 3.0 * special.elliprj(0.0, mc, 1.0, 1.0 - w))
        else:
            n3 = n / 3.0
            P = n3 * sn ** 3 * float(special.elliprj(cn * cn, dn * dn, 1.0, 1.0 - n * sn * sn))
            P0 = n3 * sn0 ** 3 * float(special.elliprj(cn0 * cn0, dn0 * dn0, 1.0, 1.0 - n * sn0 * sn0))
            if j:
                P += n3 * 2.0 * j * float(special.elliprj(0.0, mc, 1.0, 1.0 - n))
        if j % 2:
            sn, cn = -sn, -cn
    psi = Ln / (J3 if big else J1) * h + C * (P - P0)
    B0 = _B1(w1, w2, w3)
    B = _B1(s1 * a1 * cn, a2 * sn, s3 * a3 * dn)
    c, s = math.cos(psi), math.sin(psi)
    r1, r2 = B[0], B[1]
    RzB = [[c * r1[i] - s * r2[i] for i in range(3)], [s * r1[i] + c * r2[i] for i in range(3)], B[2]]
    D = _mm(list(zip(*B0)), RzB)                     # B0ᵀ Rz B
    if flip:
        p = RELABEL
        sg = (1.0, -1.0, 1.0)
        D = [[sg[i] * sg[k] * D[p[i]][p[k]] for k in range(3)] for i in range(3)]
    return D


def _B1(w1, w2, w3):
    nrm = math.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
    w1, w2, w3 = w1 / nrm, w2 / nrm, w3 / nrm
    rho = math.hypot(w1, w2)
    c1, c2 = w1 / rho, w2 / rho
    return [[c2, -c1, 0.0], [w3 * c1, w3 * c2, -rho], [w1, w2, w3]]




def _quat_rotvec(phi):
    """Unit quaternion (w, x, y, z) of the rotation vector φ (plain floats)."""
    th = math.sqrt(phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2])
    if th < 1e-8:
        s = 0.5 - th * th / 48.0
        return (1.0 - th * th / 8.0, s * phi[0], s * phi[1], s * phi[2])
    s = math.sin(0.5 * th) / th
    return (math.cos(0.5 * th), s * phi[0], s * phi[1], s * phi[2])


def _quat_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def _quat_matrix(q):
    w, x, y, z = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def _mm(A, B):
    """A B for 3×3 nested lists (unrolled: this is the hot path)."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = A
    (b00, b01, b02), (b10, b11, b12), (b20, b21, b22) = B
    return [[a00 * b00 + a01 * b10 + a02 * b20, a00 * b01 + a01 * b11 + a02 * b21, a00 * b02 + a01 * b12 + a02 * b22],
            [a10 * b00 + a11 * b10 + a12 * b20, a10 * b01 + a11 * b11 + a12 * b21, a10 * b02 + a11 * b12 + a12 * b22],
            [a20 * b00 + a21 * b10 + a22 * b20, a20 * b01 + a21 * b11 + a22 * b21, a20 * b02 + a21 * b12 + a22 * b22]]
