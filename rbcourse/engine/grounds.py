"""The scene's grounds after a step, in the compiled loop (run.py): every ground's contacts (contact.py: resolve)
on the method's own state, whatever its layout.

    resolve_all(S, sys, dt, w)         every ground, ground after ground, on the slides' S (N, 18)
    contacts(layout, sys, Y, dt, w)    the same on the method's state Y: S itself, or a quaternion state
                                       read as S and written back for the bodies that changed
"""
from __future__ import annotations

from .algebra import matrix_from_quat, matvec, quat_multiply, quat_normalize, transpose
from .contact import resolve
from .jit import inline, njit, unrolled
from .motion import put_state, state_of
from .plan import MATRIX, QUAT
from .quaternion import put_quat_state, quat_state_of


@unrolled
def resolve_all(S, sys, dt, w):
    """The contacts of every ground of the System on S (N, 18), in place (resolve, ground after ground):
    how many body contacts there were, or −1 if a contact system is not finite.  w.changed[i] = 1 for a
    body whose state they changed, w.turn[i] the quaternion of what the lifts turned it by."""
    for i in range(S.shape[0]):
        w.changed[i] = 0
        w.turn[i, 0], w.turn[i, 1], w.turn[i, 2], w.turn[i, 3] = 1.0, 0.0, 0.0, 0.0
    total = 0
    for g in range(sys.grounds.shape[0]):
        n = resolve(S, w.S0, sys, g, dt, w)
        if n < 0:
            return -1
        total += n
    return total


@inline
def read_as_matrix(layout, Y, S):
    """S := the quaternion state Y (x, q, P, L_b) or (x, q, P, L) as the slides' state: R = R(q), L = R L_b."""
    for i in range(Y.shape[0]):
        x, q, P, L = quat_state_of(Y, i)
        R = matrix_from_quat(q)
        put_state(S, i, x, R, P, matvec(R, L) if layout == QUAT else L)


@inline
def write_changed(layout, S, Y, w):
    """The bodies the contacts changed (w.changed), written back from S to the quaternion state Y: q turned as
    the lift turned R (q ← q_turn q: no R → q conversion), L_b = R₁ᵀ L₁."""
    for i in range(Y.shape[0]):
        if w.changed[i]:
            x, q, P, L = quat_state_of(Y, i)
            x1, R1, P1, L1 = state_of(S, i)
            q1 = quat_normalize(quat_multiply((w.turn[i, 0], w.turn[i, 1], w.turn[i, 2], w.turn[i, 3]), q))
            put_quat_state(Y, i, x1, q1, P1, matvec(transpose(R1), L1) if layout == QUAT else L1)


@njit
def contacts(layout, sys, Y, dt, w):
    """The contacts after a step, in place on the method's state Y (N, m), in the kernel: the slides' state
    S is Y itself (layout MATRIX); a quaternion state is read as S into w.S, and only the bodies the contacts
    changed are written back.  Returns as resolve_all.  (One call of resolve_all for every layout: the
    contact solve is compiled once per loop, not once per layout.)"""
    S = Y if layout == MATRIX else w.S
    if layout != MATRIX:
        read_as_matrix(layout, Y, S)
    n = resolve_all(S, sys, dt, w)
    if n > 0 and layout != MATRIX:
        write_changed(layout, S, Y, w)
    return n
