"""Runge–Kutta methods as data: Butcher tables (the kernel's one stage loop, stages.py, runs them).

A table (A, b, c) of s stages advances y' = f(t, y) by h:

    k_i = f(t + c_i h, y + h Σ_{j<i} a_ij k_j)   (i = 1 … s),    y(t + h) = y + h Σ_i b_i k_i

The same loop runs classic RK4 on (x, q, P, L_b), RK–Munthe-Kaas in the Lie algebra (rkmk4:
the algebra element u_i, and R_i = exp(u_i) R), the kicks at fixed positions of the splittings,
and DOP853's stages (adaptive).

DOP853's table is scipy's (the public `scipy.integrate.DOP853` class attributes), read at
the first use of the adaptive method: `import rbcourse` does not import scipy.integrate.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np


@dataclass(frozen=True, eq=False)
class Tableau:
    """A Butcher table: A (s, s) strictly lower triangular, b / den (s,) the weights, c (s,) the nodes;
    E5, E3 (s + 1,): the weights of an embedded error estimate (DOP853), or None.
    den: a common denominator of the weights, as they are written by hand (RK4: b = (1, 2, 2, 1),
    den = 6, so y + h/6 (k1 + 2 k2 + 2 k3 + k4) is computed, and rounded, as written).
    (Compared and hashed by identity: a table is one object.)"""
    name: str
    A: np.ndarray
    b: np.ndarray
    c: np.ndarray
    order: int
    den: float = 1.0
    E5: np.ndarray | None = None
    E3: np.ndarray | None = None

    @property
    def stages(self) -> int:
        return len(self.b)


def _table(name, A, b, c, order, den=1.0, **errors) -> Tableau:
    arrays = [np.array(a, dtype=float) for a in (A, b, c)]
    errors = {k: np.array(e, dtype=float) for k, e in errors.items()}
    for a in arrays + list(errors.values()):
        a.setflags(write=False)
    return Tableau(name, *arrays, order, float(den), **errors)


# Kutta 1901: the classic RK4 (written once: rk4, rkmk4, and the order-4 kick use it)
RK4 = _table("rk4", [[0, 0, 0, 0], [0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 1.0, 0]],
             [1, 2, 2, 1], [0, 0.5, 0.5, 1.0], order=4, den=6)
# the explicit midpoint rule (Runge 1895), order 2;  Euler, order 1
MIDPOINT = _table("midpoint", [[0, 0], [0.5, 0]], [0.0, 1.0], [0, 0.5], order=2)
EULER = _table("euler", [[0.0]], [1.0], [0.0], order=1)


@lru_cache(maxsize=None)
def dop853() -> Tableau:
    """Dormand–Prince 8(5,3) (Hairer, Nørsett & Wanner, Solving ODEs I, §II.10): 12 stages, and the
    error weights E5, E3 over the 12 stages and f at the new point.  From scipy.integrate.DOP853
    (imported here, at first use)."""
    from scipy.integrate import DOP853
    s = DOP853.n_stages
    return _table("dop853", DOP853.A[:s, :s], DOP853.B, DOP853.C[:s], order=DOP853.order, E5=DOP853.E5, E3=DOP853.E3)
