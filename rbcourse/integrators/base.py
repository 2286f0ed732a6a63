"""What every integrator is, as data: its name and properties (order, what it keeps exactly, cost,
reference) and the options it takes; and what a run prepares from the scene's inertia.

The steps themselves are the engine's (rbcourse/engine: steps.py and the family files), written
once, compiled by numba or run as Python: a Method here is what the engine runs, by name.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class Method:
    """An integrator: its name and its own properties.

    order: the global order of accuracy (error ~ dt^order).
    keeps: what it conserves exactly (to rounding) for a free body, among
           "SO(3)" (R stays a rotation), "L" (world angular momentum), "|L|", "energy".
    cost: work per step (force evaluations, solves).  reference, summary: where it comes from, in one line.
    step: where its step is written (the engine's function, by name).
    uses_exact_flow: it steps with the exact torque-free flow (so a free body's step is exact at any size).
    options, settings: the options it takes and their values; check_options(options) -> options
        checks the values given to configured (e.g. adaptive: rtol and atol within their ranges).
    (What it promises on the named hard cases is the bench's: rbcourse.bench.claims.)
    """
    name: str
    step: str
    order: int
    keeps: frozenset
    cost: str
    reference: str
    summary: str
    uses_exact_flow: bool = False
    options: tuple = ()                 # names of the options it accepts (e.g. rtol, atol)
    settings: dict = field(default_factory=dict, repr=False)
    check_options: Callable | None = field(default=None, repr=False)   # options dict -> checked (ValueError)

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
    """What a run computes once from the scene's inertia about the rotation centre I_rot (N, 3, 3):

    I_rot_moments (N, 3), I_rot_axes (N, 3, 3): I_rot = A diag(I₁, I₂, I₃) Aᵀ, ascending moments, the
        principal axes as the columns of A, det A = +1 (the splitting's axis flows, the exact free flow).
    """
    I_rot_moments: np.ndarray
    I_rot_axes: np.ndarray


def prepare(scene) -> Prepared:
    """The run's Prepared for `scene` (the eigen-decomposition of its I_rot)."""
    moments, axes = np.linalg.eigh(scene.I_rot)           # principal moments and axes (columns)
    axes[np.linalg.det(axes) < 0, :, 2] *= -1.0
    for arr in (moments, axes):
        arr.setflags(write=False)
    return Prepared(moments, axes)
