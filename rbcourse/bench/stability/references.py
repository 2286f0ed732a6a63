"""What a cell is measured against: the case's reference at its end (the exact free rotation, a DOP853
solution, rest, or a fine adaptive run), and the rotation and position errors of a trajectory's last state."""
from __future__ import annotations

import math

import numpy as np

from ...rotation import rotation_angle
from ...simulate import simulate
from ..hardcases import HardCase


def reference_end(case: HardCase, T: float):
    """The case's reference at T: (R, x) with R (3,3) or (N,3,3) and x (3,), (N,3) or None; None if it has none."""
    if case.reference == "exact":
        from ...exact.free_body import exact_free_body
        return exact_free_body(case.scene.bodies[0], case.X0, np.array([T])).R[-1], None
    if case.reference == "dop853":
        from ..problems import problem_C
        p = problem_C()
        p.T = T
        return p.reference_R(), None
    if case.reference == "rest":
        return np.array(case.X0.R), np.array(case.X0.x)
    if case.reference == "fine":
        traj = simulate(case.scene, case.X0, T, case.dt, "adaptive", rtol=1e-12, atol=1e-12, record_every=10**9)
        return traj.R[-1], traj.x[-1]
    return None


def reference_R(case: HardCase, T: float) -> np.ndarray | None:
    """R(T) of the case's reference solution (None if it has none)."""
    ref = reference_end(case, T)
    return None if ref is None else ref[0]


def end_errors(traj, ref) -> tuple[float, float]:
    """(rotation error, position error) of the last state against the reference (nan where none)."""
    if ref is None:
        return math.nan, math.nan
    R_ref, x_ref = ref
    R, Rr = traj.R[-1].reshape(-1, 3, 3), np.asarray(R_ref).reshape(-1, 3, 3)
    rot = max(float(rotation_angle(a, b)) for a, b in zip(Rr, R))
    pos = math.nan if x_ref is None else float(np.max(np.linalg.norm(traj.x[-1] - x_ref, axis=-1)))
    return rot, pos
