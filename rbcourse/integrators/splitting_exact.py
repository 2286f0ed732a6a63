"""exact_splitting: kick / exact torque-free flow / kick, composed to order 4.

The motion splits into a part we can solve exactly, the free rigid body (torque-free
rotation about the rotation centre, and free translation), and the forces, which only
change the momenta ("kicks", positions fixed).  A composition is a table of fractions:

    K(b₀h) F(a₁h) K(b₁h) F(a₂h) … F(a_s h) K(b_s h)

K: P += bh F, L += bh τ (forces at the current positions);  F: the exact free flow.
Strang (b = ½, ½; a = 1) is order 2; the tables below are order 4.  With no force the
kicks vanish and a step is exact whatever its size.  The step is the engine's
(rbcourse/engine/exact_flow.py); here are its compositions.
"""
from __future__ import annotations

# Blanes & Moan, J. Comput. Appl. Math. 142 (2002), the 6-stage order-4 method S6 (symmetric):
_BM_A = (0.0792036964311957, 0.353172906049774, -0.0420650803577195)
_BM_B = (0.209515106613362, -0.143851773179818)
_BM_A4 = 1.0 - 2.0 * sum(_BM_A)
_BM_B3 = 0.5 - sum(_BM_B)
_Y1 = 1.0 / (2.0 - 2.0 ** (1.0 / 3.0))                       # Yoshida's triple jump
_Y2 = 1.0 - 2.0 * _Y1

COMPOSITIONS = {
    "strang": dict(order=2, kicks=(0.5, 0.5), flows=(1.0,)),
    "yoshida4": dict(order=4, kicks=(_Y1 / 2, (_Y1 + _Y2) / 2, (_Y1 + _Y2) / 2, _Y1 / 2), flows=(_Y1, _Y2, _Y1)),
    # BM S6 with its 7 "a" fractions on the kicks and its 6 "b" fractions on the flows
    "blanes_moan4": dict(order=4, kicks=_BM_A + (_BM_A4,) + _BM_A[::-1], flows=_BM_B + (_BM_B3, _BM_B3) + _BM_B[::-1]),
}
DEFAULT = "blanes_moan4"


def check_composition(options: dict) -> dict:
    """composition must name a table of COMPOSITIONS."""
    if "composition" in options and (not isinstance(options["composition"], str)
                                     or options["composition"] not in COMPOSITIONS):
        raise ValueError(f"composition must be one of {sorted(COMPOSITIONS)}, got {options['composition']!r}")
    return options
