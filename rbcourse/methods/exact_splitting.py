"""exact_splitting: kick / exact torque-free flow / kick, composed to order 4.

The motion splits into a part we can solve exactly, the free rigid body (torque-free
rotation about the rotation centre, and free translation), and the forces, which only
change the momenta ("kicks", positions fixed).  A composition is a table of fractions:

    K(b₀h) F(a₁h) K(b₁h) F(a₂h) … F(a_s h) K(b_s h)

K: P += bh F, L += bh τ (forces at the current positions);  F: the exact free flow.
Strang (b = ½, ½; a = 1) is order 2; the others are order 4.  With no force the
kicks vanish and a step is exact whatever its size.  The step is the engine's
(rbcourse/engine/exact_flow.py); its compositions are data of the engine too
(rbcourse/engine/compositions.py: COMPOSITIONS, DEFAULT, written there once); here the
method's `composition` option is checked against them.
"""
from __future__ import annotations

from ..engine.compositions import COMPOSITIONS, DEFAULT

__all__ = ["COMPOSITIONS", "DEFAULT", "check_composition"]


def check_composition(options: dict) -> dict:
    """composition must name a table of COMPOSITIONS."""
    if "composition" in options and (not isinstance(options["composition"], str)
                                     or options["composition"] not in COMPOSITIONS):
        raise ValueError(f"composition must be one of {sorted(COMPOSITIONS)}, got {options['composition']!r}")
    return options
