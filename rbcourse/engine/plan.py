"""How the kernel steps a method, as data (numpy only: methods.METHODS reads it at import, no numba loads).

Each row of methods.METHODS holds a Stepping: the compiled loop it runs (run.py: LOOPS, one loop per step, so
a run compiles only its own method's step), the kind of step inside it, the state it steps (a layout),
its Butcher table (tableaus.py), how it finishes a step, the times its forces are evaluated at, and what its
step needs beyond that.  What a family of methods reads of a run beyond its table (its options, whether it can
run a scene) is the family's, in the kernel (run.py: LOOPS, a Family each), found there by the driver in the
kernel that runs (compiled, or engine/interpreted.py's copy run as Python).

The layouts, and the columns of a body's row in each (rbcourse/rowwise.py encodes and decodes them):

    MATRIX      S (N, 18) = [x, R row by row, P, L]            the slides' state
    QUAT        Y (N, 13) = [x, q, P, L_b],  L_b = Rᵀ L         the body-frame quaternion state (rk4, adaptive)
    QUAT_WORLD  Y (N, 13) = [x, q, P, L],  L world              Baraff's quaternion state (notes G, eq. 4-2)
    KICK        S, with the momenta's rates only, (0, 0, F, τ) at fixed positions (the splittings' kicks)
"""
from __future__ import annotations

from typing import NamedTuple

MATRIX, QUAT, KICK, QUAT_WORLD = 0, 1, 2, 3
LAYOUTS = {"matrix": MATRIX, "quat": QUAT, "quat_world": QUAT_WORLD}
COLUMNS = {"matrix": (("x", 0, 3), ("R", 3, 12), ("P", 12, 15), ("L", 15, 18)),
           "quat": (("x", 0, 3), ("q", 3, 7), ("P", 7, 10), ("L", 10, 13)),
           "quat_world": (("x", 0, 3), ("q", 3, 7), ("P", 7, 10), ("L", 10, 13))}

# how a method finishes its step
NO_FINISH, PROJECT_R, NORMALIZE_Q = 0, 1, 2
# the kinds of step, within their family
EULER, EXPLICIT_RK, ADAPTIVE, IMPLICIT_GYRO, IMPLICIT_MIDPOINT, SYMPLECTIC_EULER, SPLITTING, RKMK4, EXACT_SPLITTING, \
    VARIATIONAL = range(10)
# work slots a step needs that depend on the number of bodies (a Stepping's scratch; steps.work_slots)
LANES, NEWTON = -1, -2


class Stepping(NamedTuple):
    """What the kernel needs to step a method (see the module docstring).

    family: its compiled loop and step, and what the family reads of a run beyond its table (run.py:
        LOOPS[family], a Family: the named loop run_<family>, its step, configure and supported);
    kind: its step within the family; layout: "matrix", "quat" or "quat_world";
    table: its Butcher table (tableaus.py), or a function giving it (built at first use);
    finish: NO_FINISH, PROJECT_R or NORMALIZE_Q;
    nodes: the c_i of the times t + c_i h its forces are evaluated at, if not its table's;
    scratch: work slots it needs beyond its table's stages: a number, or LANES (rk4's lane block) or NEWTON (the
        implicit midpoint's Newton system), which depend on the number of bodies (steps.work_slots);
    time_forces: are its stage times known before its step (forces f(t) evaluated ahead; else per attempt,
        between compiled calls: the adaptive substeps).
    """
    family: str
    kind: int
    layout: str
    table: object
    finish: int = NO_FINISH
    nodes: tuple = ()
    scratch: int = 0
    time_forces: bool = True
