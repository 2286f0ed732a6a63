"""What every integrator is: a step function plus its own properties; and what a run prepares.

A method steps a state of N bodies:  step(scene, t, Y, h, prep) -> Y(t + h).
Y is the method's own representation of the state: the slides' State (x, R, P, L)
for matrix methods, or a flat array [x, q, P, L] (13, N) for quaternion methods;
`encode` / `decode` convert from / to State (identity for State methods).
prep is the run's Prepared (prepare(scene), built once per simulate call): the inertia
in the layouts the steps use, and the exact free flow for exact_splitting.  Called by
hand, a step may be given prep=None and prepares what it needs itself.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np


def _same(scene, X):
    return X


@dataclass(frozen=True)
class Method:
    """An integrator: its step function and its own properties.

    order: the global order of accuracy (error ~ dt^order).
    keeps: what it conserves exactly (to rounding) for a free body, among
           "SO(3)" (R stays a rotation), "L" (world angular momentum), "|L|", "energy".
    cost: work per step (force evaluations, solves).  reference, summary: where it comes from, in one line.
    uses_exact_flow: it steps with the exact torque-free flow (prepare builds it).
    options, settings: the options step takes and their values; check_options(options) -> options
        checks the values given to configured (e.g. adaptive: rtol and atol within their ranges).
    (What it promises on the named hard cases is the bench's: rbcourse.bench.claims.)
    """
    name: str
    step: Callable = field(repr=False)
    order: int
    keeps: frozenset
    cost: str
    reference: str
    summary: str
    uses_exact_flow: bool = False
    encode: Callable = field(default=_same, repr=False)
    decode: Callable = field(default=_same, repr=False)
    options: tuple = ()                 # names of the options step accepts (e.g. rtol, atol)
    settings: dict = field(default_factory=dict, repr=False)
    check_options: Callable | None = field(default=None, repr=False)   # options dict -> checked (ValueError)

    def __call__(self, scene, t, Y, dt, prep=None):
        return self.step(scene, t, Y, dt, prep, **self.settings)

    def prepare(self, scene) -> "Prepared":
        """What this method precomputes for a run of `scene` (see prepare)."""
        return prepare(scene, exact_flow=self.uses_exact_flow)

    def configured(self, **options) -> "Method":
        """This method with options set (e.g. adaptive: rtol, atol); unknown options are an error."""
        options = {k: v for k, v in options.items() if v is not None}
        unknown = set(options) - set(self.options)
        if unknown:
            allowed = f"takes {', '.join(self.options)}" if self.options else "takes no options"
            raise ValueError(f"method {self.name!r} {allowed}; got {', '.join(sorted(unknown))}")
        if options and self.check_options is not None:
            options = self.check_options(options)
        return replace(self, settings={**self.settings, **options}) if options else self


@dataclass(frozen=True)
class Prepared:
    """What the methods precompute for one run of a scene, from its inertia about the rotation
    centre I_rot (N, 3, 3) — constants of the run, not of the scene:

    I_rot_moments (N, 3), I_rot_axes (N, 3, 3): I_rot = A diag(I₁, I₂, I₃) Aᵀ, the principal axes
        as the columns of A, det A = +1 (the splitting's axis flows, the float kernels' R_p = R A);
    diagonal_inertia: every I_rot is diagonal; Iinv_rows: I⁻¹_rot laid out over the bodies for
        ω_b = I⁻¹ L_b on rows: its diagonal (3, N), or the 6 entries (00, 01, 02, 11, 12, 22) (6, N);
    free_rotation_flow: rbcourse.exact's FreeRotationFlow(I_rot) for exact_splitting, else None.
    """
    I_rot_moments: np.ndarray
    I_rot_axes: np.ndarray
    diagonal_inertia: bool
    Iinv_rows: np.ndarray
    free_rotation_flow: object = field(default=None, repr=False)


def prepare(scene, exact_flow: bool = False) -> Prepared:
    """The run's Prepared for `scene` (its I_rot and I_rot_inv); exact_flow: build the exact free flow too."""
    I_rot, J = scene.I_rot, scene.I_rot_inv
    moments, axes = np.linalg.eigh(I_rot)                 # principal moments and axes (columns)
    axes[np.linalg.det(axes) < 0, :, 2] *= -1.0
    offdiag = I_rot - np.einsum("nii->ni", I_rot)[:, :, None] * np.eye(3)
    diagonal = bool(np.all(offdiag == 0.0))
    rows = (np.einsum("nii->in", J).copy() if diagonal else
            np.stack([J[:, 0, 0], J[:, 0, 1], J[:, 0, 2], J[:, 1, 1], J[:, 1, 2], J[:, 2, 2]]))
    for arr in (moments, axes, rows):
        arr.setflags(write=False)
    flow = None
    if exact_flow:
        from ..exact import FreeRotationFlow
        flow = FreeRotationFlow(I_rot)
    return Prepared(moments, axes, diagonal, rows, flow)
