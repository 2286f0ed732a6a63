"""What is drawn at each frame, read from the physics: the states at the drawn instants (Frames:
x, R, its projection onto SO(3), ω = I⁻¹(t) L, L), which part of a run can be drawn at all, which
recorded states become frames, and the arrows (ω and L from each centre of mass, each PointForce's
force F = R f (body axes) or f from its point r = x + R b)."""
from __future__ import annotations

import numpy as np

from ...support.language import say
from ...effects import PointForce
from ...rotation import matvec, project_so3
from ...state import unchecked_angular_velocity, unchecked_inverse_inertia      # unchecked: a run's own arrays
from ...trajectory import Trajectory, shown


class Frames:
    """States at the drawn instants, over N bodies: x (F, N, 3), R (F, N, 3, 3), ω, L (F, N, 3)."""

    def __init__(self, t, x, R, L, scene):
        self.t = np.asarray(t, dtype=float)
        self.x, self.R, self.L = x, R, L
        self.Rp = project_so3(R)
        self.omega = unchecked_angular_velocity(unchecked_inverse_inertia(R, scene.I_body_inv), L)
        self.scene = scene

    @classmethod
    def from_trajectory(cls, traj: Trajectory, index: np.ndarray) -> "Frames":
        x, R, L = traj.x[index], traj.R[index], traj.L[index]
        if x.ndim == 2:                                  # one body: add the body axis
            x, R, L = x[:, None], R[:, None], L[:, None]
        return cls(traj.t[index], x, R, L, traj.scene)


DRAWABLE = {"x": 1e6, "R": 1e15, "L": 1e30}   # beyond these (m, entries of R, kg m²/s) a run is not drawn on (float32 in three.js)

def drawable(traj: Trajectory) -> tuple[Trajectory, str]:
    """The part of a run that can be drawn, and a note if it was cut ('' if not).

    A run that blew up (the slides' Euler) keeps finite states up to 1e100, but a body 10⁸⁰ m away,
    or an R with entries of 10³⁰, cannot be framed or drawn (three.js computes NaN bounds): the
    drawing ends where the run stops being drawable, and says so.  A run that ended early
    (traj.diverged) says when it diverged."""
    m = len(traj.t)
    ok = np.ones(m, dtype=bool)
    for key, limit in DRAWABLE.items():
        ok &= (np.abs(getattr(traj, key)).reshape(m, -1) < limit).all(axis=1)
    k = m if ok.all() else int(np.argmin(ok))
    note = traj.outcome if traj.diverged else ""
    if k < m:
        last = traj.t[max(k - 1, 0)]
        note = note or say(f"not drawable after t = {last:.4g} s", f"plus dessinable après t = {last:.4g} s")
        traj = traj.head(max(k, 1))
    return traj, note


def checked_trajectory(name: str, traj) -> Trajectory:
    """traj, if it is a Trajectory of its scene's bodies with finite states at strictly increasing times."""
    traj = shown(name, traj)          # a Trajectory of at least one state
    n = traj.scene.n_bodies
    single = (len(traj.t),) + ((3,) if n == 1 else (n, 3))
    if traj.x.shape != single or traj.R.shape != single + (3,) or traj.L.shape != single:
        raise ValueError(f"{name} must hold states of its scene's {n} bod{'y' if n == 1 else 'ies'} "
                         f"(x of shape {single}), got x of shape {traj.x.shape}")
    for key in ("t", "x", "R", "L"):
        if not np.all(np.isfinite(getattr(traj, key))):
            raise ValueError(f"{name} must hold finite states only, but {name}.{key} has NaN or inf "
                             "(a diverged run: draw the steps before the blow-up)")
    if np.any(np.diff(traj.t) <= 0):
        raise ValueError(f"{name}.t must increase strictly")
    return traj


def frame_indices(t: np.ndarray, speed: float, fps: float, max_frames: int) -> np.ndarray:
    """Indices of the recorded states nearest to the frames t0 + speed·j/fps (the last state always kept)."""
    span = t[-1] - t[0]
    n = int(np.floor(span / speed * fps + 1e-9)) + 1
    if n > max_frames:
        raise ValueError(f"fps must give at most max_frames = {max_frames} frames: {span:g} s played at "
                         f"×{speed:g} and {fps:g} fps is {n} frames (lower fps or raise speed or max_frames)")
    wanted = t[0] + speed * np.arange(n) / fps
    k = np.clip(np.searchsorted(t, wanted), 1, max(len(t) - 1, 1))
    if len(t) > 1:
        k = np.where(wanted - t[k - 1] <= t[k] - wanted, k - 1, k)
    else:
        k = np.zeros(n, dtype=int)
    return np.unique(np.append(k, len(t) - 1))


class Arrow:
    """An arrow drawn from tail (F, 3) along vec (F, 3), physics units times scale (m per unit)."""

    def __init__(self, name, kind, tail, vec):
        self.name, self.kind, self.tail, self.vec = name, kind, tail, vec


def frame_arrows(fr: Frames, omega: bool, L: bool, forces: bool) -> list[Arrow]:
    """ω and L from each centre of mass, and each PointForce's force from its point."""
    out = []
    n = fr.scene.n_bodies
    for i in range(n):
        if omega:
            out.append(Arrow(f"omega_{i}", "omega", fr.x[:, i], fr.omega[:, i]))
        if L:
            out.append(Arrow(f"L_{i}", "L", fr.x[:, i], fr.L[:, i]))
    if forces:
        for e_index, e in enumerate(fr.scene.effects):
            if not isinstance(e, PointForce):
                continue
            for j in fr.scene.bodies_of(e):
                f = np.array([e.force_at(float(t)) for t in fr.t], dtype=float)
                F = matvec(fr.R[:, j], f) if e.frame == "body" else f            # F = R f in body axes
                r = fr.x[:, j] + matvec(fr.Rp[:, j], e.body_point)               # r = x + R b
                out.append(Arrow(f"force_{e_index}_{j}", "force", r, F))
    return out
