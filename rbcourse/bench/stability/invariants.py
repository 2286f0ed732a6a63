"""The invariants a hard case may declare (INVARIANTS), each defined once, on the engine's energy and
momenta: each gives the relative error of its quantity at every recorded state of a trajectory."""
from __future__ import annotations

import numpy as np

from ...support.language import say


def _summed(a: np.ndarray, tail: int) -> np.ndarray:
    """A per-body quantity summed over the bodies of a many-body trajectory: (n+1, N, …) -> (n+1, …)."""
    return a.sum(axis=1) if a.ndim == tail + 2 else a


def total_energy(traj) -> np.ndarray:
    """E = Σ_bodies (T + U), shape (n+1,)."""
    return _summed(traj.total_energy(), 0)


def _relative(a: np.ndarray, scale: float) -> np.ndarray:
    return np.abs(a) / (scale if scale > 0 else 1.0)


def relative_energy_error(traj, X0) -> np.ndarray:
    E = total_energy(traj)
    return _relative(E - E[0], abs(E[0]))


def _world_L(traj, X0) -> np.ndarray:
    L = _summed(traj.angular_momentum(), 1)
    return np.linalg.norm(L - L[0], axis=1) / np.linalg.norm(L[0])


def _norm_L(traj, X0) -> np.ndarray:
    n = np.linalg.norm(traj.L, axis=-1)
    return _relative(n - n[0], n[0])


def _L_z(traj, X0) -> np.ndarray:
    L = traj.angular_momentum(about=np.zeros(3))
    return np.abs(L[:, 2] - L[0, 2]) / np.linalg.norm(L[0])


def _L3(traj, X0) -> np.ndarray:
    L3 = np.einsum("nji,nj->ni", traj.R, traj.L)[:, 2]          # (Rᵀ L)₃ = I₃ ω₃
    return _relative(L3 - L3[0], abs(L3[0]))


def _P(traj, X0) -> np.ndarray:
    P = _summed(traj.linear_momentum(), 1)
    return np.linalg.norm(P - P[0], axis=1) / np.linalg.norm(P[0])


def _rest(traj, X0) -> np.ndarray:
    x = traj.x
    return np.linalg.norm(x - x[0], axis=-1) / abs(x[0, 2])


INVARIANTS = {
    # name: ((what it is, in English, in French), relative error over the run, shape (n+1,))
    "energy": (("E = T + U, summed over the bodies: |E − E0| / |E0|",
                "E = T + U, sommée sur les corps : |E − E0| / |E0|"), relative_energy_error),
    "L": (("world L about the origin, summed over the bodies (no external torque): ‖L − L0‖ / ‖L0‖",
           "L du monde par rapport à l'origine, sommé sur les corps (aucun moment extérieur) : ‖L − L0‖ / ‖L0‖"), _world_L),
    "norm_L": (("|L| about the centre of mass (free rotation): ||L| − |L0|| / |L0|",
                "|L| par rapport au centre de masse (rotation libre) : ||L| − |L0|| / |L0|"), _norm_L),
    "L_z": (("vertical L about the pivot (gravity's torque is horizontal): |L_z − L_z0| / ‖L0‖",
             "L vertical par rapport au pivot (le moment de la gravité est horizontal) : |L_z − L_z0| / ‖L0‖"), _L_z),
    "L3": (("the spin L₃ = (RᵀL)₃ = I₃ω₃ of a symmetric top: |L₃ − L₃0| / |L₃0|",
            "la rotation propre L₃ = (RᵀL)₃ = I₃ω₃ d'une toupie symétrique : |L₃ − L₃0| / |L₃0|"), _L3),
    "P": (("total linear momentum (no external force): ‖P − P0‖ / ‖P0‖",
           "quantité de mouvement totale (aucune force extérieure) : ‖P − P0‖ / ‖P0‖"), _P),
    "rest": (("a body at rest stays put: ‖x − x0‖ / (its centre's height x0_z)",
              "un corps au repos ne bouge pas : ‖x − x0‖ / (la hauteur de son centre x0_z)"), _rest),
}
"""Every invariant a hard case may declare (HardCase.invariants), each defined once, on the engine's
energy and momenta (Trajectory.total_energy, angular_momentum, linear_momentum)."""


NAMES_FR = {"energy": "énergie", "L": "L", "norm_L": "|L|", "L_z": "L_z", "L3": "L₃", "P": "P", "rest": "repos"}
"""The invariants' names as a French report shows them (the results keep the keys: they are data)."""


def named(name: str) -> str:
    """Invariant `name` as the active language's report shows it (English: its key)."""
    return say(name, NAMES_FR[name])


def described(name: str) -> str:
    """What invariant `name` is, in the active language."""
    return say(*INVARIANTS[name][0])
