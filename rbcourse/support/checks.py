"""Input validation shared by the whole package.

Every public entry point checks its arguments here, so that a bad input always
gives a ``ValueError`` that names the parameter and says what is allowed.

What counts as a number (the same rule everywhere):

* a real number is an ``int`` or a ``float`` (numpy's integer and floating scalars too,
  e.g. ``np.float32``); a bool, a string (even ``'1.0'``), a complex number or None is not;
* an array of numbers has an integer or floating dtype: lists of ints and floats and numpy
  arrays of any int/float dtype are accepted (converted to float64); strings, bools, complex
  numbers and other objects (None, Decimal, ...) in it are not;
* an index is an ``int`` (or a numpy integer), never a bool, a float or a string.
"""
from __future__ import annotations

import math
import os
from numbers import Real
from pathlib import Path

import numpy as np

TINY = float(np.finfo(float).tiny)     # 2.2e-308, the smallest normal float
HUGE = 1.0 / TINY                      # 4.5e307: its inverse is TINY, still a normal float

ANGLE_MAX = 2.0 ** 32                 # 4.29e9 rad: float64 resolves an angle up to it to 2⁻²⁰ ≈ 9.5e-7 rad or better
_REAL_KINDS = "iuf"                    # numpy dtype kinds that are real numbers (int, unsigned, float)


def is_real_scalar(value) -> bool:
    return (not isinstance(value, (bool, np.bool_))
            and isinstance(value, (Real, np.floating, np.integer)))


def real(name: str, value, *, low=None, high=None, low_open=False, high_open=False) -> float:
    """A finite real number (int or float, not bool or str), optionally within [low, high] (or open ends)."""
    if not is_real_scalar(value):
        raise ValueError(f"{name} must be a real number (an int or a float), got {value!r}")
    try:
        value = float(value)
    except OverflowError:                       # a huge Python int
        raise ValueError(f"{name} must be finite, got {value!r}") from None
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if low is not None and (value < low or (low_open and value == low)):
        bound = f"> {low:g}" if low_open else f">= {low:g}"
        raise ValueError(f"{name} must be {bound}, got {value!r}")
    if high is not None and (value > high or (high_open and value == high)):
        bound = f"< {high:g}" if high_open else f"<= {high:g}"
        raise ValueError(f"{name} must be {bound}, got {value!r}")
    return value


def positive(name: str, value) -> float:
    """A finite real number > 0."""
    return real(name, value, low=0.0, low_open=True)


def scale(name: str, value) -> float:
    """A positive real number usable as a mass or a moment of inertia, and so as a divisor:
    within [TINY, HUGE] = [2.2e-308, 4.5e307] (a normal float whose inverse is a normal float)."""
    value = positive(name, value)
    if not TINY <= value <= HUGE:
        raise ValueError(f"{name} must be in [{TINY:.3g}, {HUGE:.3g}] (a normal float, so that 1/{name} "
                         f"is finite and nonzero), got {value!r}")
    return value


def boolean(name: str, value) -> bool:
    """True or False (a bool or numpy bool; not 0/1, not a string)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def integer(name: str, value, *, low=None, high=None) -> int:
    """An int (not bool, not float) within [low, high]."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    value = int(value)
    if (low is not None and value < low) or (high is not None and value > high):
        raise ValueError(f"{name} must be an integer {_range(low, high)}, got {value}")
    return value


def index(name: str, value, length: int, what: str = "items") -> int:
    """An index into `length` items, as Python indexes a list: an int (not bool, not float) in [-length, length - 1],
    -1 the last; never wrapped or clipped beyond that.  `what` names the items, for the message."""
    if length == 0:
        integer(name, value)
        raise ValueError(f"{name} must be an index into the {what}, but there are none (0 {what}), got {value!r}")
    value = integer(name, value)
    if not -length <= value < length:
        raise ValueError(f"{name} must be an integer in [{-length}, {length - 1}] (an index into {length} {what}, "
                         f"-1 the last), got {value}")
    return value


def _range(low, high) -> str:
    if low is not None and high is not None:
        return f"in [{low}, {high}]"
    return f">= {low}" if low is not None else f"<= {high}"


def numbers(name: str, value, what: str = "an array of numbers", *, copy: bool = True) -> np.ndarray:
    """Any array of real numbers (int/float dtype, not str, bool, complex or object) -> a float64 array.

    `what` says what is wanted, for the message ("an array of numbers with shape (3,)").  copy=False: a float64
    array given is returned as it is, not copied (a run's record, which can be gigabytes: Trajectory)."""
    def bad():      # the message, written only when it is needed (repr of a large array is slow)
        return ValueError(f"{name} must be {what} (ints or floats; not strings, booleans or complex numbers), "
                          f"got {value!r}")
    if isinstance(value, (str, bytes, dict, set)) or value is None:
        raise bad()
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError, OverflowError):      # ragged nested lists, ...
        raise bad() from None
    if arr.dtype.kind not in _REAL_KINDS:
        raise bad()
    if not isinstance(value, np.ndarray) and _holds_bool(value):     # [True, 0, 0] is read as ints by numpy
        raise bad()
    try:
        return arr.astype(float, copy=copy)              # own copy (unless copy=False), float64
    except OverflowError:
        raise bad() from None


def _holds_bool(value) -> bool:
    """Does a (nested) sequence hold a bool among its numbers?"""
    if isinstance(value, (bool, np.bool_)):
        return True
    if isinstance(value, np.ndarray):
        return value.dtype.kind == "b"
    if isinstance(value, (list, tuple)):
        return any(_holds_bool(v) for v in value)
    return False


def array(name: str, value, shape: tuple, *, batch: bool = False) -> np.ndarray:
    """A finite float array of the given trailing shape (with one leading dim of N >= 1 if batch)."""
    want = f"{_fmt(shape)} or (N, {', '.join(str(s) for s in shape)})" if batch else _fmt(shape)
    arr = numbers(name, value, f"an array of numbers with shape {want}")
    ok = arr.shape[arr.ndim - len(shape):] == shape if batch else arr.shape == shape
    if not ok or (batch and arr.ndim > len(shape) + 1):
        raise ValueError(f"{name} must have shape {want}, got shape {arr.shape}")
    if batch and arr.ndim == len(shape) + 1 and arr.shape[0] == 0:
        raise ValueError(f"{name} must hold at least one body (N >= 1), got shape {arr.shape}")
    return finite(name, arr)


def finite(name: str, arr: np.ndarray) -> np.ndarray:
    """arr itself, if every number in it is finite (no NaN or inf); else a ValueError naming it."""
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite numbers (no NaN or inf), got {arr.tolist()}")
    return arr


def vector3(name: str, value, *, bound: float | None = None) -> np.ndarray:
    """A finite 3-vector; with a bound, each component within [-bound, bound]."""
    v = array(name, value, (3,))
    if bound is not None and not np.all(np.abs(v) <= bound):
        raise ValueError(f"{name} must have components within ±{bound:g}, got {v.tolist()}")
    return v


def text(name: str, value, optional: bool = False) -> str | None:
    """A string (str: not bytes) that can be written as UTF-8 (a page, a file name: no lone surrogate); or None where
    optional."""
    if value is None and optional:
        return None
    if not isinstance(value, str):
        raise ValueError(f"{name} must be a string{' or None' if optional else ''}, got {value!r}")
    try:
        value.encode("utf-8")
    except UnicodeEncodeError as err:
        raise ValueError(f"{name} must be text that can be written as UTF-8, got {value!r} (a lone surrogate at "
                         f"character {err.start})") from None
    return value


def choice(name: str, value, allowed) -> str:
    """One of a fixed set of strings."""
    if not isinstance(value, str) or value not in allowed:
        raise ValueError(f"{name} must be one of {sorted(allowed)}, got {value!r}")
    return value


def method_names(text: str | None, allowed) -> list[str]:
    """The methods of `--methods a,b` (all of `allowed` when text is None), checked, each once, in the order given:
    ValueError naming the flag and the allowed ones for an unknown or empty name."""
    allowed = list(allowed)
    if text is None:
        return allowed
    names = [n.strip() for n in text.split(",")]
    bad = [n for n in names if n not in allowed]
    if bad:
        raise ValueError(f"--methods: unknown method {', '.join(repr(n) for n in bad)}; "
                         f"choose among {', '.join(allowed)} (comma-separated)")
    return list(dict.fromkeys(names))


def indices(name: str, value) -> tuple:
    """A non-empty sequence of distinct ints (not bools, floats or strings) -> a tuple of ints.

    (A range check needs the number of bodies: Scene does it.)"""
    bad = (f"{name} must be None, an index, a RigidBody or a list of indices (an index is an int, not a "
           f"bool, a float or a string; a list is non-empty, of distinct ints), got {value!r}")
    if isinstance(value, (str, bytes, dict, set)) or value is None:
        raise ValueError(bad)
    try:
        items = list(value)
    except TypeError:
        raise ValueError(bad) from None
    if not items:
        raise ValueError(f"{name} must not be an empty list: name at least one body (or None: every body)")
    for i in items:
        if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)):
            raise ValueError(bad)
    items = tuple(int(i) for i in items)
    if len(set(items)) != len(items):
        raise ValueError(f"{name} must not repeat an index, got {list(items)}")
    return items


def frozen(value) -> np.ndarray:
    """A private, read-only copy of an array, on an immutable bytes buffer: writing into it (``a[0] = 9``) raises
    ValueError "assignment destination is read-only", and so does ``a.setflags(write=True)`` — unlike a copy merely
    flagged read-only, which setflags can make writable again.  The dtype and shape are kept (C order).
    Effects and States hold their arrays this way (effects.py, state.py): one copy (tobytes) per array — none for
    an array that is frozen already (or a view of one: a State's x[None], a body of a stacked State), returned as
    it is, since nobody can write it."""
    arr = np.asarray(value)
    if is_frozen(arr):
        return arr
    return np.frombuffer(arr.tobytes(), dtype=arr.dtype).reshape(arr.shape)     # tobytes: C order, any strides


def read_only(value) -> np.ndarray:
    """A read-only view of an array, with no copy: writing into it (``a[0] = 9``) raises numpy's ValueError
    "assignment destination is read-only".  For arrays too large to copy (a run's record: Trajectory); unlike
    frozen, whoever holds the array itself can still write it, and setflags(write=True) can undo the flag."""
    view = np.asarray(value).view()
    view.setflags(write=False)
    return view


def is_frozen(arr: np.ndarray) -> bool:
    """Is arr read-only memory, for good: a read-only array (or view) on an immutable bytes buffer (frozen)?"""
    if arr.flags.writeable:
        return False
    base = arr
    while isinstance(base, np.ndarray):
        base = base.base
    return isinstance(base, bytes)


def _fmt(shape: tuple) -> str:
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


NAME_MAX = 255
"""The longest name (a file's, a folder's: one part of a path) a file system takes, in bytes (UTF-8)."""
PATH_MAX = 4095
"""The longest path the system takes, in bytes (UTF-8): Linux's PATH_MAX, 4096 with the NUL that ends it."""


def _short(text: str, keep: int = 40) -> str:
    return repr(text) if len(text) <= keep else repr(text[:keep]) + f"… ({len(text)} characters)"


def path_length(name: str, path: Path) -> Path:
    """path itself, if each of its names is at most NAME_MAX bytes and the whole at most PATH_MAX bytes (in UTF-8,
    as the file system counts them); else a ValueError naming it (the system's "File name too long" otherwise)."""
    for part in path.parts:
        size = len(os.fsencode(part))
        if size > NAME_MAX:
            raise ValueError(f"{name}: a file or folder name must be at most {NAME_MAX} bytes long (the file system's "
                             f"limit), got a name of {size} bytes: {_short(part)}")
    size = len(os.fsencode(str(path)))
    if size > PATH_MAX:
        raise ValueError(f"{name} must be a path of at most {PATH_MAX} bytes (the system's limit), got {size} bytes: "
                         f"{_short(str(path))}")
    return path


def file_path(name: str, value) -> Path:
    """A path to write a file to: a str or os.PathLike, not empty, without a NUL byte, each name at most NAME_MAX
    bytes and the whole at most PATH_MAX (path_length), not a folder, in a folder that exists."""
    if not isinstance(value, (str, os.PathLike)) or str(value) == "" or "\0" in str(value):
        raise ValueError(f"{name} must be a file path (text, not empty, no NUL byte), got {value!r}")
    path = path_length(name, Path(value))
    if path.is_dir():
        raise ValueError(f"{name} must be a file path, but {path} is a folder")
    if not path.parent.is_dir():
        raise ValueError(f"{name}: the folder {path.parent} does not exist")
    return path

