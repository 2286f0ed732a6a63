"""exact_splitting's compositions, as data: the fractions of the step its kicks and exact free flows take.

    K(b₀h) F(a₁h) K(b₁h) F(a₂h) … F(a_s h) K(b_s h)        kicks = (b₀ … b_s), flows = (a₁ … a_s)

K: a kick, P += bh F, L += bh τ at fixed positions;  F: the exact torque-free flow (exact_flow.py).
Strang (b = ½, ½; a = 1) is order 2; yoshida4 and blanes_moan4 are order 4.  "order" also names the
order of the Runge–Kutta table the kicks use when a force depends on the velocities (exact_flow.kick_order).

Written once, here: the compiled step reads a composition through exact_flow.options (opts), and
rbcourse/methods/exact_splitting.py checks the method's `composition` option against these names.
This file imports nothing.
"""

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


def composition(settings: dict) -> dict:
    """The composition the settings name (settings["composition"], default DEFAULT)."""
    return COMPOSITIONS[settings.get("composition", DEFAULT)]
