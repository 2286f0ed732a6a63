"""The compiled step loop: n steps of a method, each checked, the recorded ones decoded to (x, R, P, L).

    for each step k:  out = step(Y);  if a component of out is NaN, inf or beyond 1e100: stop (k);
                      the scene's grounds, if any: contacts on out (contact.py), checked again;
                      if k is recorded: (x, R, P, L) of out into the record's row (checked too);  Y = out

The record's arrays are the trajectory's (the driver allocates them once): nothing is copied.
"""
from __future__ import annotations

import types
from functools import lru_cache

from .algebra import matvec
from .grounds import contacts
from .jit import njit
from .motion import copy_into, motion, put, put_mat, state_of
from .quaternion import quat_motion, quat_state_of, quat_world_motion
from .steps import FAMILY_STEP, state_changed

OVERFLOW = 1e100    # trajectory.OVERFLOW: the one blow-up limit
GOOD, BLEW_UP, CONTACT_FAILED = 0, 1, 2     # how a loop ended


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


def loop(method, sys, values, Y, out, h, k0, k1, n, every, row, rec, K, U, w, cw):
    """Steps k0 … k1−1 of n of a method, each checked, the contacts with the scene's grounds after each
    (contact.contacts, cw its work: contact.work), the recorded ones decoded to (x, R, P, L) and checked as
    recorded: the loop of every family of methods, with its own step (family_step: steps.FAMILY_STEP) and its
    layout's decode (decode_state: DECODE), bound by loop_for.

    method = (kind, layout, finish, A, b, den, opts); values (k1 − k0, stages, slots, 3) the forces f(t) at the
    steps' stage times; rec = (t, x, R, P, L) the record.  Returns the steps done, the next record row, and
    GOOD, or BLEW_UP / CONTACT_FAILED at step k (then Y holds the last good state and out the bad one)."""
    rec_t, rec_x, rec_R, rec_P, rec_L = rec
    grounds = sys.grounds.shape[0] > 0
    for k in range(k0, k1):
        family_step(*method, sys, values[k - k0], Y, out, h, K, U, w)
        if first_bad(out)[0] >= 0:
            return k, row, BLEW_UP
        if grounds:
            touched = contacts(method[1], sys, out, h, cw)
            if touched < 0:
                return k, row, CONTACT_FAILED
            if touched > 0:
                state_changed(method[0], method[6])
                if first_bad(out)[0] >= 0:
                    return k, row, BLEW_UP
        if (k + 1) % every == 0 or k + 1 == n:
            decode_state(sys, out, row, rec_x, rec_R, rec_P, rec_L)
            if row_bad(rec_x[row], rec_R[row], rec_P[row], rec_L[row]):
                return k, row, BLEW_UP
            rec_t[row] = (k + 1) * h
            row += 1
        copy_into(Y, out)
    return k1, row, GOOD


@lru_cache(maxsize=None)
def loop_for(family: str, layout: str):
    """The loop of one family of methods on one layout, compiled on its own (a run compiles only its family's
    step and its layout's decode): `loop`'s code with family_step = steps.FAMILY_STEP[family] and
    decode_state = DECODE[layout], named run_<family>_<layout> (numba caches each under its name)."""
    bound = {**loop.__globals__, "family_step": FAMILY_STEP[family], "decode_state": DECODE[layout]}
    fn = types.FunctionType(loop.__code__, bound, f"run_{family}_{layout}", loop.__defaults__)
    fn.__qualname__ = fn.__name__
    fn.__doc__ = f"loop, with steps.FAMILY_STEP[{family!r}] and DECODE[{layout!r}]."
    return njit(fn)


@njit
def row_bad(x, R, P, L):
    """Is a recorded row (x, R, P, L of the N bodies) NaN, inf or beyond ±1e100 anywhere?"""
    return (first_bad(x)[0] >= 0 or first_bad(R.reshape(-1, 9))[0] >= 0 or first_bad(P)[0] >= 0
            or first_bad(L)[0] >= 0)
