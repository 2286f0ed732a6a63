"""The exact torque-free flow of the orientation over one step, for the splitting methods
(kick – free flow – kick):  R(h) with Ṙ = ω* R, ω = R I⁻¹ Rᵀ L, L constant (world).

FreeRotationFlow(inertia) does the set-up that depends only on the inertia once; then every call, one
body or many, is free_body.Motion over h (scipy.special, as arrays): with m = RᵀL in body axes,

    spherical:   R(h) = R exp(h m*/I)
    symmetric:   R(h) = R exp(h m*/I_eq) exp(h (1/I_s − 1/I_eq)(a·m) a*)     (a the symmetry axis)
    on an axis:  R(h) = R exp(h m*/I_k)
    asymmetric:  free_body's steps 1 and 2 at t = h (Jacobi's sn, cn, dn and Π: elliptic.py).

Part of the independent reference (rbcourse/exact/): the flow a splitting written against the public
API can use, checked like exact_free_body.  The method exact_splitting does not use it: its step is
the compiled engine's own exact flow (rbcourse/engine/exact_flow.py, allocation-free, no scipy), which
shares no code with this one; tests/test_two_exact_flows.py compares the two.
"""
from __future__ import annotations

import numpy as np

from ..support import checks
from ..body import RigidBody, inertia_matrix
from ..rotation import transpose
from .free_body import Motion, is_identity

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

    One body or N, the motion is free_body.Motion's (scipy.special, as arrays).  R, L are not checked
    for finiteness here (a splitting calls it every step); shapes and h are.
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
        self.moments = np.ascontiguousarray(moments)   # (N or 1, 3) ascending
        self.axes = np.ascontiguousarray(axes)         # (N or 1, 3, 3), det +1
        self.identity_axes = bool(all(is_identity(a) for a in axes))

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
            return self._many(R[None], L[None], h)[0]
        if R.ndim != 3 or R.shape[1:] != (3, 3) or L.shape != (R.shape[0], 3):
            raise ValueError(f"R must have shape (N, 3, 3) and L (N, 3) (or (3, 3) and (3,)), "
                             f"got R {R.shape} and L {L.shape}")
        if self.n is not None and self.n != R.shape[0]:
            raise ValueError(f"the flow holds {self.n} bodies but R holds {R.shape[0]}")
        return self._many(R, L, h)

    def _many(self, R, L, h):
        """R(h) (N, 3, 3) for R (N, 3, 3), L (N, 3): Motion's increment D(h) in principal axes, R A D Aᵀ."""
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


