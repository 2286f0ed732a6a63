"""Forces at points and their resultants (slide "Les Formules — les résultantes").

Forces Fᵢ act at world points rᵢ(t).  Their resultants on the body are

    F = Σ Fᵢ                     (total force: changes P)
    τ = Σ (rᵢ − x(t)) ∧ Fᵢ       (total torque about the centre of mass: changes L)

``resultants`` sums a list of forces at points, with the engine's own torque (engine/motion.py:
torque, which the engine's effects use too), for the course and the exercise.
"""
from __future__ import annotations

import numpy as np

from .support import checks


def resultants(x, forces):
    """F = Σ Fᵢ and τ = Σ (rᵢ − x) × Fᵢ for a list of (rᵢ, Fᵢ) pairs (world points, world forces).

    x: (3,) the centre of mass (or the point torques are taken about).
    forces: sequence of (r_i, F_i), each a 3-vector; an empty list gives zeros.
    Returns (F, tau), two (3,) arrays.  Each torque is the engine's (engine/motion.py: torque).
    """
    x = checks.vector3("x", x)
    r, F_i = force_arrays(forces)
    from .engine import interpreted
    algebra, motion = interpreted.module("algebra"), interpreted.module("motion")
    F = tau = (0.0, 0.0, 0.0)
    for ri, fi in zip(r, F_i):
        F = algebra.add(F, fi)                       # F = Σ Fᵢ
        tau = algebra.add(tau, motion.torque(x, ri, fi))   # τ = Σ (rᵢ − x) ∧ Fᵢ
    return np.array(F, dtype=float), np.array(tau, dtype=float)


def force_arrays(forces):
    """Check a list of (r_i, F_i) pairs -> r (k, 3), F (k, 3)."""
    if isinstance(forces, (str, bytes, dict, np.ndarray)) and not (isinstance(forces, np.ndarray) and forces.ndim == 3):
        raise ValueError(f"forces must be a list of (r_i, F_i) pairs, got {forces!r}")
    try:
        pairs = list(forces)
    except TypeError:
        raise ValueError(f"forces must be a list of (r_i, F_i) pairs, got {forces!r}") from None
    r = np.zeros((len(pairs), 3))
    F = np.zeros((len(pairs), 3))
    for i, pair in enumerate(pairs):
        try:
            ri, fi = pair
        except (TypeError, ValueError):
            raise ValueError(f"forces[{i}] must be a pair (r_i, F_i) of 3-vectors, got {pair!r}") from None
        r[i] = checks.vector3(f"forces[{i}] point r_i", ri)
        F[i] = checks.vector3(f"forces[{i}] force F_i", fi)
    return r, F
