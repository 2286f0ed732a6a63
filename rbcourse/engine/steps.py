"""The methods' steps, each in one signature, so that the loop (run.py) takes any of them and a run compiles only
its own method's step:

    step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w)

kind (plan.py) picks the method where one step serves two (euler, euler_project); A, b, den its Butcher table
(tableaus.py); opts the floats its step reads (its settings); Y (N, m) the state of the N bodies in its layout,
out (N, m) the result; values (stages, slots, 3) the forces given as functions f(t) at the stage times t + c_i h
(evaluated by the driver); K (stages, N, m), U (N, m), w: work arrays.

    euler_family_step          euler.py: euler_step, the slides' X(t + Δt) = X(t) + Δt · dX/dt (euler, euler_project)
    explicit_quat_step         an explicit Runge–Kutta table on (x, q, P, L_b), then q normalised (stages.py):
                               quaternion_euler_body (EULER), rk4 (RK4: Kutta 1901)
    explicit_quat_world_step   the same on Baraff's (x, q, P, L): quaternion_euler
    symplectic_euler, splitting, rkmk4 (geometric.py), variational (variational.py), implicit_gyro,
    implicit_midpoint (implicit.py), adaptive (adaptive.py: DOP853 substeps under error control),
    exact (exact_flow.py: kick / exact free flow / kick)
"""
from __future__ import annotations

from . import geometric, variational
from .adaptive import STEPS, adaptive_step, forget_substep
from .exact_flow import exact_splitting_step
from .implicit import implicit_gyro_step, implicit_midpoint_step, midpoint_scratch
from .jit import njit
from .plan import ADAPTIVE, LANES, NEWTON
from .quaternion import rates_quat, rates_quat_world
from .stages import lane_scratch, lanes_fit, rk_stages, rk_stages_lanes


@njit
def explicit_quat_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """quaternion_euler_body, rk4: an explicit Runge–Kutta table on (x, q, P, L_b) (quaternion.rates_quat), then
    q normalised (R(q) ∈ SO(3)); rk4 on bodies that do not act on one another, LANES bodies at a time."""
    if lanes_fit(sys, A, b, Y, K):
        rk_stages_lanes(sys, values, A, b, den, Y, out, h, K, True)
    else:
        rk_stages(rates_quat, sys, values, A, b, den, Y, out, h, K, U, w, 0, True)


@njit
def explicit_quat_world_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """quaternion_euler: an explicit Runge–Kutta table on Baraff's (x, q, P, L) (quaternion.rates_quat_world), then
    q normalised."""
    rk_stages(rates_quat_world, sys, values, A, b, den, Y, out, h, K, U, w, 0, True)


@njit
def symplectic_euler_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """symplectic_euler (geometric.py)."""
    geometric.symplectic_euler_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)


@njit
def splitting_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """splitting (geometric.py)."""
    geometric.splitting_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)


@njit
def rkmk4_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """rkmk4 (geometric.py)."""
    geometric.rkmk4_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)


@njit
def variational_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """variational (variational.py)."""
    variational.variational_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)


@njit
def implicit_gyro_family_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """implicit_gyro (implicit.py)."""
    implicit_gyro_step(sys, values, opts, Y, out, h, K, U, w)


@njit
def implicit_midpoint_family_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """implicit_midpoint (implicit.py)."""
    implicit_midpoint_step(sys, values, opts, Y, out, h, K, U, w)


@njit
def adaptive_family_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """adaptive: DOP853 substeps under error control over the output step h (adaptive.py)."""
    adaptive_step(A, b, den, opts, sys, values, Y, out, h, K, U, w)


@njit
def exact_step(kind, layout, finish, A, b, den, opts, sys, values, Y, out, h, K, U, w):
    """exact_splitting (exact_flow.py)."""
    exact_splitting_step(sys, values, opts, A, b, den, Y, out, h, K, U, w)


@njit
def state_changed(kind, opts):
    """The state changed between two steps (a contact, an impulse): a method that carries something from
    step to step forgets it (adaptive: its substep is chosen again)."""
    if kind == ADAPTIVE:
        forget_substep(opts)


@njit
def piece_begins(kind, opts, k, t, h, whole):
    """A piece of step k begins at t, of size h (a step split at its kicks' times: run.split_step): a method that
    carries something from step to step forgets it, as after a contact (state_changed), and the adaptive's
    forces are at t = STEPS h (STEPS = k for the whole step, t / h for a piece)."""
    if kind == ADAPTIVE:
        forget_substep(opts)
        opts[STEPS] = k if whole else t / h


@njit
def step_done(kind, opts, k):
    """Step k, split at its kicks' times, is done: the adaptive's output steps are k + 1 (t = STEPS h)."""
    if kind == ADAPTIVE:
        opts[STEPS] = k + 1


def work_slots(scratch: int, n: int) -> int:
    """The work slots a method's step adds to its table's stages, for n bodies: its Stepping's scratch, a number; or
    LANES, rk4's lane block (stages.lane_scratch), or NEWTON, the implicit midpoint's Newton system
    (implicit.midpoint_scratch)."""
    if scratch == LANES:
        return lane_scratch(n)
    if scratch == NEWTON:
        return midpoint_scratch(n)
    return scratch
