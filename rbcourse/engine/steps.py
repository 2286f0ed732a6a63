"""The methods' steps, by family: each family is one step function (one signature), so that a run compiles
only its own family's code (run.py: the one loop, bound to a family's step and its layout's decode by loop_for).

    step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w)

kind (plan.py) picks the method within its family; A, b, den its Butcher table (tableaus.py); opts the floats
its step reads (its settings); Y (N, m) the state of the N bodies in its layout, out (N, m) the result;
values (stages, slots, 3) the forces given as functions f(t) at the stage times t + c_i h (evaluated by the
driver); K (stages, N, m), U (N, m), w: work arrays.

    euler        euler.py: euler_step, the slides' X(t + Δt) = X(t) + Δt · dX/dt (euler, euler_project)
    explicit     an explicit Runge–Kutta table on a quaternion state, then q normalised (stages.py: rk_stages):
                 quaternion_euler (EULER on Baraff's (x, q, P, L)), quaternion_euler_body (EULER on
                 (x, q, P, L_b)), rk4 (RK4 on (x, q, P, L_b): Kutta 1901)
    geometric    symplectic_euler, splitting, rkmk4 (geometric.py), variational (variational.py)
    implicit     implicit_gyro, implicit_midpoint (implicit.py)
    adaptive     DOP853 substeps under error control (adaptive.py)
    exact        exact_splitting: kick / exact free flow / kick (exact_flow.py)
"""
from __future__ import annotations

from . import geometric, variational
from .adaptive import adaptive_step, forget_substep
from .euler import euler_family_step
from .exact_flow import exact_step
from .implicit import implicit_gyro_step, implicit_midpoint_step
from .jit import njit
from .plan import ADAPTIVE, IMPLICIT_GYRO, NORMALIZE_Q, SPLITTING, SYMPLECTIC_EULER, VARIATIONAL
from .stages import rk_stages


@njit
def explicit_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """quaternion_euler, quaternion_euler_body, rk4: an explicit Runge–Kutta table on its quaternion layout,
    then q normalised (R(q) ∈ SO(3))."""
    rk_stages(layout, sys, values, A, b, den, Y, out, h, K, U, w, 0, finish == NORMALIZE_Q)


@njit
def geometric_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """symplectic_euler, splitting, rkmk4 (geometric.py), variational (variational.py)."""
    if kind == SYMPLECTIC_EULER:
        geometric.symplectic_euler_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)
    elif kind == SPLITTING:
        geometric.splitting_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)
    elif kind == VARIATIONAL:
        variational.variational_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)
    else:
        geometric.rkmk4_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)


@njit
def implicit_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """implicit_gyro, implicit_midpoint (implicit.py)."""
    if kind == IMPLICIT_GYRO:
        implicit_gyro_step(sys, values, opts, Y, out, h, K, U, w)
    else:
        implicit_midpoint_step(sys, values, opts, Y, out, h, K, U, w)


@njit
def adaptive_family_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """adaptive: DOP853 substeps under error control over the output step h (adaptive.py)."""
    adaptive_step(A, b, den, opts, sys, values, Y, out, h, K, U, w)


@njit
def state_changed(kind, opts):
    """The state changed between two steps (a contact, an impulse): a method that carries something from
    step to step forgets it (adaptive: its substep is chosen again)."""
    if kind == ADAPTIVE:
        forget_substep(opts)


# each family's step, as the driver finds it (the loop of family f is run.py's run_f)
FAMILY_STEP = {"euler": euler_family_step, "explicit": explicit_step, "geometric": geometric_step,
               "implicit": implicit_step, "adaptive": adaptive_family_step, "exact": exact_step}
