"""What a raw exception in a student's function means, for a numpy beginner: the classic slips that raise rather
than give a wrong number, told by the exception's message (the same text in a grading sandbox, where the exception
is rebuilt from its type name and message):

    `^` for a power (XOR)                          TypeError … for ^ / ufunc 'bitwise_xor'
    arithmetic on the tuple X                      can't multiply sequence by non-int / inhomogeneous shape / …
    a float added in place to an int array         Cannot cast ufunc 'add' output from dtype('float64') to int
    X.x on the plain tuple a step returns          'tuple' object has no attribute 'x'
    scipy's Rotation.from_matrix on det R < 0      Non-positive determinant
    np.vstack / np.stack of no force               need at least one array to concatenate / stack

explain(exc) -> the id of the mistake in MISTAKES (mistakes.py), or None; its line in the student's code is
harness.where(exc).
"""
from __future__ import annotations

import re

CRASHES = (
    ("xor_power", re.compile(r"for \^:|'bitwise_xor'")),
    ("tuple_arithmetic", re.compile(r"can't multiply sequence by non-int|can only concatenate tuple|"
                                    r"inhomogeneous (part|shape)|setting an array element with a sequence|"
                                    r"unsupported operand type\(s\) for [-+*/@]: ('tuple' and|\S+ and 'tuple')")),
    ("int_in_place", re.compile(r"Cannot cast ufunc '\w+' output from dtype\('(float|complex)\d*'\) to "
                                r"dtype\('u?int\d*'\)")),
    ("state_attributes", re.compile(r"'tuple' object has no attribute '(x|R|P|L|_asdict|_fields|_replace)'")),
    ("scipy_negative_det", re.compile(r"Non-positive determinant")),
    ("empty_forces", re.compile(r"need at least one array to (concatenate|stack)")),
)
"""(mistake id, the pattern of its exception's message), the first that matches names the crash."""


def explain(exc: BaseException) -> str | None:
    """The mistake a raw exception shows (an id of MISTAKES), or None when its message is none of CRASHES'."""
    try:
        text = str(exc)
    except Exception:       # noqa: BLE001 — a student's exception whose str raises
        return None
    for mistake, pattern in CRASHES:
        if pattern.search(text):
            return mistake
    return None
