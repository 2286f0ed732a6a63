"""A trajectory: the states over time as arrays, plus the diagnostics a student plots.

traj.t (n+1,), traj.x (n+1, 3), traj.R (n+1, 3, 3), traj.P (n+1, 3), traj.L (n+1, 3)
for one body; with N bodies a body axis follows the time axis: x (n+1, N, 3), ...
"""
from __future__ import annotations

import numpy as np

from .rotation import matvec, orthogonality_error, transpose
from .state import State, angular_velocity, inverse_inertia, velocity


class Trajectory:
    """States X(t_k) = (x, R, P, L) at times t_k, and what derives from them."""

    def __init__(self, t, x, R, P, L, scene, method: str = "", dt: float | None = None):
        self.t = np.asarray(t, dtype=float)
        self.x, self.R, self.P, self.L = (np.asarray(a, dtype=float) for a in (x, R, P, L))
        self.scene = scene
        self.method = method
        self.dt = dt

    # --- access --------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.t)

    def state(self, k: int) -> State:
        """X(t_k) as a State (not checked: R may have left SO(3) under Euler)."""
        return State._raw(self.x[k], self.R[k], self.P[k], self.L[k])

    @property
    def final(self) -> State:
        """The last state."""
        return self.state(-1)

    @property
    def body(self):
        """The body (single-body scenes)."""
        return self.scene.bodies[0]

    def _mass(self):
        return self.scene.mass[0] if self.x.ndim == 2 else self.scene.mass

    def _I_body_inv(self):
        return self.scene.I_body_inv[0] if self.x.ndim == 2 else self.scene.I_body_inv

    # --- derived quantities over time ----------------------------------------------
    def velocity(self) -> np.ndarray:
        """v = P / M."""
        return velocity(self.P, self._mass())

    def angular_velocity(self) -> np.ndarray:
        """ω = I⁻¹(t) L,  I⁻¹(t) = R I⁻¹_body Rᵀ  (world frame)."""
        return angular_velocity(inverse_inertia(self.R, self._I_body_inv()), self.L)

    def kinetic_energy(self) -> np.ndarray:
        """T = ½ P·v + ½ L·ω  (translation + rotation), shape (n+1,) (or (n+1, N))."""
        return 0.5 * np.sum(self.P * self.velocity(), -1) + 0.5 * np.sum(self.L * self.angular_velocity(), -1)

    def potential_energy(self) -> np.ndarray:
        """U of the scene's conservative effects (gravity M g z, springs ½ k s²); zeros if none."""
        u = self.scene.potential_energy(self._batched(self.x), self._batched(self.R))
        shape = self.t.shape if self.x.ndim == 2 else self.x.shape[:-1]
        return np.zeros(shape) if u is None else u.reshape(shape)

    def total_energy(self) -> np.ndarray:
        """E = T + U."""
        return self.kinetic_energy() + self.potential_energy()

    def linear_momentum(self) -> np.ndarray:
        """P (world)."""
        return self.P

    def angular_momentum(self, about="origin") -> np.ndarray:
        """Angular momentum in world axes about the origin (L + x × P), the centre of mass
        (about="com": the slides' L) or any fixed world point (a 3-vector)."""
        if isinstance(about, str):
            if about == "com":
                return self.L
            if about != "origin":
                raise ValueError(f"about must be 'origin', 'com' or a 3-vector, got {about!r}")
            point = np.zeros(3)
        else:
            point = np.asarray(about, dtype=float)
            if point.shape != (3,) or not np.all(np.isfinite(point)):
                raise ValueError(f"about must be 'origin', 'com' or a finite 3-vector, got {about!r}")
        return self.L + np.cross(self.x - point, self.P)

    def orthogonality_error(self) -> np.ndarray:
        """‖RᵀR − I‖ over time: 0 on SO(3)."""
        return orthogonality_error(self.R)

    def det_R(self) -> np.ndarray:
        """det R over time: 1 for a rotation."""
        return np.linalg.det(self.R)

    def body_point(self, b, body: int = 0) -> np.ndarray:
        """World path r(t) = x + R b of a body point b (body axes)."""
        b = np.asarray(b, dtype=float)
        if self.x.ndim == 2:
            return self.x + matvec(self.R, b)
        return self.x[:, body] + matvec(self.R[:, body], b)

    def body_angular_momentum(self) -> np.ndarray:
        """Rᵀ L: the angular momentum in body axes (the polhode lives here)."""
        return matvec(transpose(self.R), self.L)

    def _batched(self, a):
        return a[:, None] if self.x.ndim == 2 else a

    def __repr__(self) -> str:
        n = len(self.t) - 1
        return (f"Trajectory({n} steps, t = {self.t[0]:g} … {self.t[-1]:g} s, method {self.method!r}, "
                f"{self.scene.n_bodies} bod{'y' if self.scene.n_bodies == 1 else 'ies'})")


class SimulationDiverged(RuntimeError):
    """A run blew up (NaN, inf or overflow).  .trajectory holds the steps computed before."""

    def __init__(self, message: str, trajectory: Trajectory, t: float, step: int, reason: str):
        super().__init__(message)
        self.trajectory = trajectory
        self.t = t
        self.step = step
        self.reason = reason
