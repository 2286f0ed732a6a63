"""Forces at points and their resultants (slide "Les Formules — les résultantes").

Forces Fᵢ act at world points rᵢ(t).  Their resultants on the body are

    F = Σ Fᵢ                     (total force: changes P)
    τ = Σ (rᵢ − x(t)) ∧ Fᵢ       (total torque about the centre of mass: changes L)

This is the one place where the engine sums forces and torques: the walkthrough's forces on
one body (``resultants``), and a scene's effects on its N bodies (``scene_resultants``: the
scene asks each effect for its forces at points and its pure torques, and hands them here).
"""
from __future__ import annotations

import numpy as np

from . import checks
from .rotation import cross


def resultants(x, forces):
    """F = Σ Fᵢ and τ = Σ (rᵢ − x) × Fᵢ for a list of (rᵢ, Fᵢ) pairs (world points, world forces).

    x: (3,) the centre of mass (or the point torques are taken about).
    forces: sequence of (r_i, F_i), each a 3-vector; an empty list gives zeros.
    Returns (F, tau), two (3,) arrays.
    """
    x = checks.vector3("x", x)
    r, Fi = force_arrays(forces)
    return resultants_arrays(x, r, Fi)


def resultants_arrays(x: np.ndarray, r: np.ndarray, F_i: np.ndarray):
    """The same with arrays, summed over the forces' axis (the last but one):
    x (..., 3), r (..., k, 3), F_i (..., k, 3) -> F (..., 3), τ (..., 3)."""
    F = F_i.sum(axis=-2)
    tau = cross(r - x[..., None, :], F_i).sum(axis=-2)
    return F, tau


def scene_resultants(c: np.ndarray, applied, torques=()):
    """F = Σ Fᵢ and τ = Σ (rᵢ − c) × Fᵢ + Σ τⱼ on each of N bodies, effect after effect.

    c: (N, 3) the point each body's torques are taken about (its centre of mass x, or its pivot p).
    applied: (j, r (n, 3), F (n, 3)) triples, one force at a point on each body j (a slice or n
    distinct indices); torques: (j, τ (n, 3)) pairs, pure torques.  Returns (F, tau), each (N, 3).
    """
    F = np.zeros_like(c)
    tau = np.zeros_like(c)
    for j, r, F_j in applied:
        dF, dtau = resultants_arrays(c[j], r[:, None], F_j[:, None])   # one force per body
        F[j] += dF
        tau[j] += dtau
    for j, tau_j in torques:
        tau[j] += tau_j
    return F, tau


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
