"""The compiled step loop: n steps of a method, each checked, the recorded ones decoded to (x, R, P, L).

    for each step k:  out = step(Y);  if a component of out is NaN, inf or beyond 1e100: stop (k);
                      the scene's grounds, if it has any: contacts on out (contact.py), checked again;
                      if k is recorded: (x, R, P, L) of out into the record's row (checked too);  Y = out

A step that holds kicks (a scene with impulses: kicks.py) is split at their times (split_step): the method
steps to each time, the kicks are applied there, and it steps on — each piece with its contacts and checks.

The record's arrays are the trajectory's (the driver allocates them once): nothing is copied.
"""
from __future__ import annotations

from typing import NamedTuple

from . import adaptive, exact_flow
from .algebra import matvec, quat_from_matrix, quat_rotate_inverse
from .grounds import contacts
from .jit import inline, njit, unrolled
from .kicks import first_kick, kick_state, next_kick
from .motion import copy_into, motion, put, put_mat, stage, state_of
from .quaternion import put_quat_state, quat_motion, quat_state_of, quat_world_motion
from .euler import euler_family_step
from .steps import (adaptive_family_step, exact_step, explicit_quat_step, explicit_quat_world_step,
                    implicit_gyro_family_step, implicit_midpoint_family_step, piece_begins, rkmk4_step, splitting_step,
                    state_changed, step_done, symplectic_euler_step, variational_step)

OVERFLOW = 1e100    # trajectory.OVERFLOW: the one blow-up limit
GOOD, BLEW_UP, CONTACT_FAILED = 0, 1, 2     # how a loop ended
NOT_SPLIT = -1                              # a step without kicks: advanced whole


@njit
def first_bad(Y):
    """(body, column) of the first component of Y (N, m) that is NaN, inf or beyond ±1e100; (-1, -1) if none.
    (The components are counted first, with no branch — a loop the compiler runs in vector instructions —
    and searched only when one is bad.)"""
    flat = Y.reshape(-1)
    bad = 0
    for k in range(flat.size):
        bad += not abs(flat[k]) <= OVERFLOW
    if bad == 0:
        return -1, -1
    for k in range(flat.size):
        if not abs(flat[k]) <= OVERFLOW:
            return k // Y.shape[1], k % Y.shape[1]
    return -1, -1


@njit
def put_row(row, i, x, R, P, L, rec_x, rec_R, rec_P, rec_L):
    """Body i of record row `row` := (x, R, P, L)."""
    put(rec_x[row], i, x)
    put_mat(rec_R[row], i, R)
    put(rec_P[row], i, P)
    put(rec_L[row], i, L)


@njit
def decode_matrix(sys, S, row, rec_x, rec_R, rec_P, rec_L):
    """The slides' state S -> record row (pivoted bodies: x and P from R and L)."""
    for i in range(S.shape[0]):
        x, R, P, L = state_of(S, i)
        x, P, v, omega = motion(sys, i, x, R, P, L)
        put_row(row, i, x, R, P, L, rec_x, rec_R, rec_P, rec_L)


@njit
def decode_quat(sys, Y, row, rec_x, rec_R, rec_P, rec_L):
    """Y = [x, q, P, L_b] -> record row: R = R(q), L = R L_b (pivoted bodies: x and P from R and L)."""
    for i in range(Y.shape[0]):
        x, q, P, Lb = quat_state_of(Y, i)
        x, R, P, v, omega_b, omega = quat_motion(sys, i, x, q, P, Lb)
        put_row(row, i, x, R, P, matvec(R, Lb), rec_x, rec_R, rec_P, rec_L)


@njit
def decode_quat_world(sys, Y, row, rec_x, rec_R, rec_P, rec_L):
    """Baraff's Y = [x, q, P, L] -> record row: R = R(q), L as it is (pivoted bodies: x and P from R and L)."""
    for i in range(Y.shape[0]):
        x, q, P, L = quat_state_of(Y, i)
        x, R, P, v, omega = quat_world_motion(sys, i, x, q, P, L)
        put_row(row, i, x, R, P, L, rec_x, rec_R, rec_P, rec_L)


DECODE = {"matrix": decode_matrix, "quat": decode_quat, "quat_world": decode_quat_world}   # by layout (plan.py)


@njit
def encode_matrix(S, Y):
    """The slides' state S (N, 18) as the method's state Y (N, 18): S itself, copied."""
    copy_into(Y, S)


@njit
def encode_quat(S, Y):
    """S = [x, R, P, L] -> Y = [x, q, P, L_b]: q = quat_from_matrix(R), L_b = R(q)ᵀ L (the numbers driver.encode
    gives a State: a kick's state laid out back, kicks.kick_state)."""
    for i in range(S.shape[0]):
        x, R, P, L = state_of(S, i)
        q = quat_from_matrix(R)
        put_quat_state(Y, i, x, q, P, quat_rotate_inverse(q, L))


@njit
def encode_quat_world(S, Y):
    """S = [x, R, P, L] -> Baraff's Y = [x, q, P, L]: q = quat_from_matrix(R), L as it is."""
    for i in range(S.shape[0]):
        x, R, P, L = state_of(S, i)
        put_quat_state(Y, i, x, quat_from_matrix(R), P, L)


ENCODE = {"matrix": encode_matrix, "quat": encode_quat, "quat_world": encode_quat_world}   # decode's inverse


@inline
def loop(step, decode, encode, method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """Steps k0 … k1−1 of n of a method, each checked, the contacts with the scene's grounds after each, the
    recorded ones decoded to (x, R, P, L) and checked as recorded: the loop of every method, given its step
    (steps.py) and its layout's decode and encode (DECODE, ENCODE).  numba compiles it for each step it is given,
    and only those: a run compiles its own method's step.  (Inlined into each named loop below: a function given
    as an argument is a pointer to a Python object until then, and numba caches no code that holds one.)

    method = (kind, layout, finish, A, b, den, opts); values (k1 − k0 + pieces, stages, slots, 3) the forces f(t)
    at the steps' stage times, then at the pieces' of the steps split at kicks (None: the scene evaluates no
    force, and no force code is compiled, motion.stage); rec = (t, x, R, P, L) the record; cw the contact
    solver's work (contact.work) — or None for a scene without a ground: then the contacts are not compiled at
    all (numba prunes `cw is not None`); kicks the run's table of impulses (kicks.table) — or None for a scene
    without impulses: then no kick is compiled either.  Returns the steps done, the next record row, and GOOD,
    or BLEW_UP / CONTACT_FAILED at step k (then Y holds the last good state and out the bad one)."""
    rec_t, rec_x, rec_R, rec_P, rec_L = rec
    e, kicked, at, piece = 0, n, 0.0, k1 - k0   # the next kick: its entry, step and time; the next piece's values
    if kicks is not None:
        e = first_kick(kicks, k0, n, h)
        kicked, at = next_kick(kicks, e, n, h)
    for k in range(k0, k1):
        ended = NOT_SPLIT
        if kicks is not None:
            if k == kicked:
                ended, piece, e, kicked, at = split_step(step, decode, encode, method, sys, values, Y, out, h, k, k0,
                                                         n, piece, K, U, w, cw, kicks, e, at)
        if ended == NOT_SPLIT:
            ended, touched = advance(step, method, sys, stage(values, k - k0), Y, out, h, K, U, w, cw)
            if touched > 0:                   # the contacts changed the state: the method forgets what it carries
                state_changed(method[0], method[6])
        if ended != GOOD:
            return k, row, ended
        if (k + 1) % every == 0 or k + 1 == n:
            decode(sys, out, row, rec_x, rec_R, rec_P, rec_L)
            if row_bad(rec_x[row], rec_R[row], rec_P[row], rec_L[row]):
                return k, row, BLEW_UP
            rec_t[row] = (k + 1) * h
            row += 1
        copy_into(Y, out)
    return k1, row, GOOD


@unrolled
def advance(step, method, sys, values, Y, out, h, K, U, w, cw):
    """out := one step of size h from Y, checked; then the contacts with the scene's grounds (cw not None),
    checked again if they changed it.  Returns (GOOD, BLEW_UP or CONTACT_FAILED, how many body contacts there
    were)."""
    step(*method, sys, values, Y, out, h, K, U, w)
    if first_bad(out)[0] >= 0:
        return BLEW_UP, 0
    touched = 0
    if cw is not None:
        touched = contacts(method[1], sys, out, h, cw)
        if touched < 0:
            return CONTACT_FAILED, touched
        if touched > 0 and first_bad(out)[0] >= 0:
            return BLEW_UP, touched
    return GOOD, touched


@inline
def split_step(step, decode, encode, method, sys, values, Y, out, h, k, k0, n, piece, K, U, w, cw, kicks, e, at):
    """Step k from Y into out, split at the times of its kicks (kicks.py; the first: entry e, at time `at`): from
    t = k h, for each of their times t' in order, the method advances the state so far by t' − t if t' > t (a
    piece), then the kicks at t' are applied to it (kick_state); then the method advances to (k + 1) h.  Each
    checked.  The state so far is held in kicks.state and out by turns (held; Y is left as it is): a step split
    at one time inside it, or at its start, ends in out with no copy.  values: the whole step's forces are row
    k − k0, a piece's the next row from `piece`.  Returns (GOOD, BLEW_UP or CONTACT_FAILED — out then holds the
    bad state —, the next piece's row, and the next kick: its entry, step and time)."""
    V = kicks.state
    t0, t1 = k * h, (k + 1) * h
    t, kicked, held = t0, k, IN_Y
    while True:
        here = kicked == k
        to = at if here else t1
        if to > t:
            whole = t == t0 and to == t1
            size = h if whole else to - t
            piece_begins(method[0], method[6], k, t, size, whole)
            source = Y if held == IN_Y else (V if held == IN_WORK else out)
            held = IN_OUT if held == IN_WORK else IN_WORK
            ended, _ = advance(step, method, sys, stage(values, k - k0 if whole else piece), source,
                               V if held == IN_WORK else out, size, K, U, w, cw)
            if not whole:
                piece += 1
            if ended != GOOD:
                return moved_out(ended, held, out, V), piece, e, kicked, at
            t = to
        if not here:
            break
        first = e
        kicked, next_at = next_kick(kicks, e + 1, n, h)
        e += 1
        while kicked == k and next_at == at:              # the kicks of this time
            e += 1
            kicked, next_at = next_kick(kicks, e, n, h)
        at = next_at
        source = Y if held == IN_Y else (V if held == IN_WORK else out)
        held = IN_WORK if held == IN_Y else held
        kick_state(decode, encode, sys, source, V if held == IN_WORK else out, kicks, first, e)
        if first_bad(V if held == IN_WORK else out)[0] >= 0:
            return moved_out(BLEW_UP, held, out, V), piece, e, kicked, at
    step_done(method[0], method[6], k)
    return moved_out(GOOD, held, out, V), piece, e, kicked, at


IN_Y, IN_OUT, IN_WORK = 0, 1, 2     # where split_step holds the state so far: in Y (none made yet), out, kicks.state


@inline
def moved_out(ended, held, out, V):
    """How a split step ended (GOOD, BLEW_UP, CONTACT_FAILED), its state moved to out if V holds it."""
    if held == IN_WORK:
        copy_into(out, V)
    return ended


# The loop of each method, named: numba keeps each in its disk cache under its name (a run loads it in the next
# process), compiled for the arguments a run gives it: cw None (no ground) or a contact work, kicks None (no
# impulse) or a table of kicks, values None (no force) or the forces over time.  (Its arguments spelt out, not
# *args: on Python 3.13 numba would type the step, decode and encode passed beside a star-argument as
# first-class function pointers, called indirectly.)

@njit
def run_euler(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """euler, euler_project: the loop with euler.euler_family_step on the slides' state."""
    return loop(euler_family_step, decode_matrix, encode_matrix, method, sys, values, Y, out, h, k0, k1, n, every,
                row, rec, K, U, w, cw, kicks)


@njit
def run_explicit_quat(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """rk4, quaternion_euler_body: the loop with steps.explicit_quat_step on (x, q, P, L_b)."""
    return loop(explicit_quat_step, decode_quat, encode_quat, method, sys, values, Y, out, h, k0, k1, n, every, row,
                rec, K, U, w, cw, kicks)


@njit
def run_explicit_quat_world(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """quaternion_euler: the loop with steps.explicit_quat_world_step on Baraff's (x, q, P, L)."""
    return loop(explicit_quat_world_step, decode_quat_world, encode_quat_world, method, sys, values, Y, out, h, k0,
                k1, n, every, row, rec, K, U, w, cw, kicks)


@njit
def run_symplectic_euler(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """symplectic_euler: the loop with steps.symplectic_euler_step."""
    return loop(symplectic_euler_step, decode_matrix, encode_matrix, method, sys, values, Y, out, h, k0, k1, n,
                every, row, rec, K, U, w, cw, kicks)


@njit
def run_splitting(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """splitting: the loop with steps.splitting_step."""
    return loop(splitting_step, decode_matrix, encode_matrix, method, sys, values, Y, out, h, k0, k1, n, every, row,
                rec, K, U, w, cw, kicks)


@njit
def run_rkmk4(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """rkmk4: the loop with steps.rkmk4_step."""
    return loop(rkmk4_step, decode_matrix, encode_matrix, method, sys, values, Y, out, h, k0, k1, n, every, row,
                rec, K, U, w, cw, kicks)


@njit
def run_variational(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """variational: the loop with steps.variational_step."""
    return loop(variational_step, decode_matrix, encode_matrix, method, sys, values, Y, out, h, k0, k1, n, every,
                row, rec, K, U, w, cw, kicks)


@njit
def run_implicit_gyro(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """implicit_gyro: the loop with steps.implicit_gyro_family_step."""
    return loop(implicit_gyro_family_step, decode_matrix, encode_matrix, method, sys, values, Y, out, h, k0, k1, n,
                every, row, rec, K, U, w, cw, kicks)


@njit
def run_implicit_midpoint(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """implicit_midpoint: the loop with steps.implicit_midpoint_family_step."""
    return loop(implicit_midpoint_family_step, decode_matrix, encode_matrix, method, sys, values, Y, out, h, k0, k1,
                n, every, row, rec, K, U, w, cw, kicks)


@njit
def run_adaptive(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """adaptive: the loop with steps.adaptive_family_step on (x, q, P, L_b)."""
    return loop(adaptive_family_step, decode_quat, encode_quat, method, sys, values, Y, out, h, k0, k1, n, every,
                row, rec, K, U, w, cw, kicks)


@njit
def run_exact(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw, kicks):
    """exact_splitting: the loop with steps.exact_step."""
    return loop(exact_step, decode_matrix, encode_matrix, method, sys, values, Y, out, h, k0, k1, n, every, row,
                rec, K, U, w, cw, kicks)


class Family(NamedTuple):
    """A family of methods as the kernel runs it: its named loop and its step; and, for a family whose run reads
    more than its Stepping's table, configure(sys, settings) -> (table, nodes, opts), the table, the times of its
    forces and the floats its step reads, from the method's settings; supported(sys) -> '' or why it cannot run
    a scene (its System)."""
    loop: object
    step: object
    configure: object = None
    supported: object = None


# every family (a Stepping's `family`: plan.py), as the driver finds it
LOOPS = {"euler": Family(run_euler, euler_family_step),
         "explicit_quat": Family(run_explicit_quat, explicit_quat_step),
         "explicit_quat_world": Family(run_explicit_quat_world, explicit_quat_world_step),
         "symplectic_euler": Family(run_symplectic_euler, symplectic_euler_step),
         "splitting": Family(run_splitting, splitting_step),
         "rkmk4": Family(run_rkmk4, rkmk4_step),
         "variational": Family(run_variational, variational_step),
         "implicit_gyro": Family(run_implicit_gyro, implicit_gyro_family_step),
         "implicit_midpoint": Family(run_implicit_midpoint, implicit_midpoint_family_step),
         "adaptive": Family(run_adaptive, adaptive_family_step, adaptive.configure),
         "exact": Family(run_exact, exact_step, exact_flow.configure, exact_flow.exact_flow_supported)}


@njit
def row_bad(x, R, P, L):
    """Is a recorded row (x, R, P, L of the N bodies) NaN, inf or beyond ±1e100 anywhere?"""
    return (first_bad(x)[0] >= 0 or first_bad(R.reshape(-1, 9))[0] >= 0 or first_bad(P)[0] >= 0
            or first_bad(L)[0] >= 0)
