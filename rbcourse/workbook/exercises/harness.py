"""Calling a student's function safely: its random inputs (seeded), the call (warnings silenced, any
exception caught by the caller), reading its output as arrays, comparing with the reference, and
the one-line texts of messages (numbers, exceptions, where in the student's code).

    close(got, want):  same shapes, finite, |got − want| <= RTOL |want| + ATOL · max |want|   (relative at every scale)
"""
from __future__ import annotations

import contextlib
import io
import os
import signal
import sys
import threading
import sysconfig
import traceback
import warnings

import numpy as np

from ...rotation import exp_so3, star
from .texts import tr
from .reference import StateTuple

def random_rotation(rng):
    """A random rotation exp(θ*), θ ~ N(0, 1.2²) per component."""
    return exp_so3(rng.normal(size=3) * 1.2)


def random_spd(rng):
    """A symmetric positive-definite 3×3 matrix (an inverse inertia in some axes)."""
    Q = random_rotation(rng)
    return Q @ np.diag(rng.uniform(0.5, 4.0, 3)) @ Q.T


def random_forces(rng, x, k):
    """k forces (rᵢ, Fᵢ): points near x, forces of a few newtons."""
    return [(x + rng.normal(0.0, 0.6, 3), rng.normal(0.0, 2.0, 3)) for _ in range(k)]


def drifted_rotation(rng, steps: int = 3, h: float = 0.25):
    """A rotation after a few of Euler's steps R ← R + Δt ω* R (|Δt ω| = h): off SO(3) as Euler makes it
    (det R > 1, Rᵀ ≠ R⁻¹), so that R⁻¹ and Rᵀ, or R and its projection, differ."""
    R = random_rotation(rng)
    for _ in range(steps):
        w = rng.normal(size=3)
        R = R + star(h * w / np.linalg.norm(w)) @ R
    return R


def random_state(rng, off_so3: float = 0.0, drift: bool = False):
    """A random X = (x, R, P, L); R a rotation, off SO(3) by about off_so3, or drifted as Euler does
    (drift, see drifted_rotation)."""
    R = drifted_rotation(rng) if drift else random_rotation(rng)
    R = R + off_so3 * rng.normal(size=(3, 3))
    return StateTuple(rng.normal(0.0, 1.0, 3), R, rng.normal(0.0, 1.5, 3), rng.normal(0.0, 1.5, 3))


# =====================================================================================
# Calling the student's function, reading what it returns, comparing
# =====================================================================================

N = 20                     # random inputs per check
RTOL, ATOL = 1e-7, 1e-9    # close(): |got − want| <= RTOL |want| + ATOL · max |want| (no absolute floor: a body of
                           # 1e-12 kg m² is checked as closely as one of 1 kg m²)


class BadOutput(Exception):
    """What the student's function returned cannot be read as the expected arrays (mistake, text)."""

    def __init__(self, mistake: str, text: str):
        super().__init__(text)
        self.mistake = mistake
        self.text = text


MAX_SHOWN = 48     # values shown of an answer at most (a state is 18); beyond: its first ones, and its shape


def fmt(a, digits: int = 4) -> str:
    """A number, vector, matrix, tuple or list of them on one line (4 significant digits); an answer of more than
    MAX_SHOWN values shows its first ones and its size (what a student's function returns may be huge)."""
    if isinstance(a, (tuple, list)) and (isinstance(a, tuple) or any(isinstance(v, (tuple, list, np.ndarray))
                                                                     for v in a[:MAX_SHOWN])):
        inner = ", ".join(fmt(v, digits) for v in a[:MAX_SHOWN])
        more = f", … ({len(a):,} in all)" if len(a) > MAX_SHOWN else ""
        return ("(" + inner + more + ")") if isinstance(a, tuple) else ("[" + inner + more + "]")
    try:
        arr = np.asarray(a, dtype=float)
    except (TypeError, ValueError, OverflowError):
        text = repr(a)[:81] if not isinstance(a, (list, tuple)) else f"a {type(a).__name__} of {len(a):,} items"
        return text if len(text) <= 80 else text[:77] + "…"
    if arr.ndim == 0:
        return f"{float(arr) + 0.0:.{digits}g}"
    if arr.size > MAX_SHOWN:
        first = ", ".join(f"{float(v) + 0.0:.{digits}g}" for v in arr.reshape(-1)[:6])
        return f"[{first}, … ({arr.size:,} values, shape {arr.shape})]"
    return "[" + ", ".join(fmt(v, digits) for v in arr) + "]"




def fmt_pair(want, got) -> tuple:
    """(expected, got) as text, with as many digits (4 to 17) as it takes for them to read differently:
    two different values are never printed alike."""
    for digits in (4, 6, 8, 12, 17):
        a, b = fmt(want, digits), fmt(got, digits)
        if a != b:
            return a, b
    return a, b


def close(got, want) -> bool:
    """got matches want (arrays or tuples of them): same shapes, finite, within RTOL and ATOL."""
    if isinstance(want, tuple):
        return isinstance(got, tuple) and len(got) == len(want) and all(close(g, w) for g, w in zip(got, want))
    if isinstance(got, tuple) or got.shape != want.shape or not np.all(np.isfinite(got)):
        return False
    scale = float(np.abs(want).max()) if want.size else 0.0
    return bool(np.allclose(got, want, rtol=RTOL, atol=ATOL * scale))


def same(a, b) -> bool:
    """Exactly the same content (to detect in-place changes of an input)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        try:
            return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)
        except (TypeError, ValueError):
            return False
    if isinstance(a, (list, tuple)):
        return isinstance(b, (list, tuple)) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    try:
        return bool(a == b)
    except Exception:       # noqa: BLE001
        return False


PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
"""rbcourse itself: a frame there is the check's or the engine's, never the student's."""
LIBRARY_DIRS = tuple({PACKAGE_DIR + os.sep, os.path.dirname(os.__file__)} |
                     {sysconfig.get_paths()[k] for k in ("stdlib", "platstdlib", "purelib", "platlib")})
"""Folders whose frames are not the student's code: rbcourse (the checks, the engine), the standard library,
site-packages."""


def student_frames(exc: BaseException) -> list:
    """The frames of the student's own code in the exception's traceback — or, for an exception raised in the
    student's process while grading (grading/checker.py), the frames that process sent (exc.frames)."""
    sent = getattr(exc, "frames", None)
    if isinstance(sent, list):
        return sent
    return [f for f in traceback.extract_tb(exc.__traceback__) if not f.filename.startswith(LIBRARY_DIRS)
            and not (os.sep in f.filename and not os.path.isabs(f.filename))]     # a compiled library's (scipy/….pyx)


def where(exc: BaseException) -> str:
    """ ' (in velocity, line 3: return P @ M)' — the last frame of the student's own code, in the active language
    (' (dans velocity, ligne 3 : return P @ M)')."""
    frames = student_frames(exc)
    if not frames:
        return ""
    f = frames[-1]
    name = next((g.name for g in reversed(frames) if not g.name.startswith("<")), f.name)   # a <listcomp>'s function
    if f.line:
        return tr("where").format(name=name, line=f.lineno, code=f.line.strip())
    return tr("where_no_code").format(name=name, line=f.lineno)


def exc_text(exc: BaseException) -> str:
    """ 'ValueError: its message' on one line (at most 200 characters)."""
    text = str(exc).strip().splitlines()
    text = text[0] if text else ""
    text = text if len(text) <= 200 else text[:197] + "…"
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def not_done(name: str, exc: NotImplementedError) -> str:
    """One line: the function is a stub (or calls one, named)."""
    frames = student_frames(exc)
    if len(frames) > 1 and frames[-1].name != frames[0].name:
        return tr("not_done_calls").format(name=name, callee=frames[-1].name)
    return tr("not_done").format(name=name)


class LibraryUsed(Exception):
    """The student's function called rbcourse for its answer: .library names what it called (the checks then say
    "library_call", as the grader does)."""

    def __init__(self, name: str):
        super().__init__(name)
        self.library = name


GRADING_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "grading") + os.sep
"""The grader's stand-ins for a student's function live here: calling them is not the student calling rbcourse."""
GRADING_MODULE = __name__.rsplit(".", 2)[0] + ".grading"
"""rbcourse.workbook.grading: a function of this package is the grader's stand-in (grading/checker.py), whose source
the grader reads for rbcourse (grading/library.py); the student's code runs in its sandbox, not here."""


def _students(filename: str) -> bool:
    """A frame of the student's own code (a notebook cell, a file of theirs): not rbcourse, the standard library or
    site-packages (as student_frames reads them)."""
    return not filename.startswith(LIBRARY_DIRS) and not (os.sep in filename and not os.path.isabs(filename))


def _passed_in(values) -> set:
    """The code of the functions a check hands the student's function to call (check_simulate's forces_at and step,
    the pushed box's forces_at): calling them is not taking an answer from the library."""
    codes = set()
    for value in values:
        code = getattr(getattr(value, "__func__", value), "__code__", None)
        if code is not None:
            codes.add(code)
    return codes


def _library_name(frame, allowed) -> str | None:
    """'rbcourse.state.inverse_inertia' when this call enters rbcourse straight from the student's code (not one of
    the functions it was handed, allowed), else None."""
    code = frame.f_code
    if (not code.co_filename.startswith(PACKAGE_DIR + os.sep) or code.co_filename.startswith(GRADING_DIR)
            or code in allowed):
        return None
    caller = frame.f_back
    if caller is None or not _students(caller.f_code.co_filename):
        return None
    qualname = getattr(code, "co_qualname", code.co_name)
    return f"{frame.f_globals.get('__name__', 'rbcourse')}.{qualname}"


LIMIT = 60.0
"""Seconds one call of the student's function may take in a check (in the notebook; the grader has its own limits):
an endless loop is then "out_of_time", not a cell that never ends."""


class TimeUp(Exception):
    """The student's function was still running after LIMIT seconds."""


def _time_up(signum, frame):
    raise TimeUp(f"still running after {LIMIT:g} s")


@contextlib.contextmanager
def time_limit():
    """LIMIT seconds for what runs inside, by SIGALRM — where Python can use it (POSIX, the main thread, no timer
    already set); elsewhere no limit."""
    usable = (hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
              and signal.getitimer(signal.ITIMER_REAL)[0] == 0)
    if not usable:
        yield
        return
    before = signal.signal(signal.SIGALRM, _time_up)
    signal.setitimer(signal.ITIMER_REAL, LIMIT)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, before)


def call(fn, args, kwargs=None):
    """fn(*args, **kwargs) with NumPy's warnings silenced (an overflow is judged by its result), within LIMIT seconds
    (TimeUp), watching what it calls: a call from the student's code into rbcourse (its answer taken from the
    library) raises LibraryUsed."""
    if type(fn).__module__.startswith(GRADING_MODULE):      # a stand-in: the grader reads the source instead
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            return fn(*args, **(kwargs or {}))
    seen, allowed = [], _passed_in(list(args) + list((kwargs or {}).values()) + [_time_up])

    def watch(frame, event, arg):
        if event == "call" and not seen:
            name = _library_name(frame, allowed)
            if name:
                seen.append(name)

    before = sys.getprofile()
    sys.setprofile(watch)
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"), time_limit():
            warnings.simplefilter("ignore")
            out = fn(*args, **(kwargs or {}))
    except BaseException as e:
        sys.setprofile(before)
        if seen:
            raise LibraryUsed(seen[0]) from e
        raise
    sys.setprofile(before)
    if seen:
        raise LibraryUsed(seen[0])
    return out


def as_array(out, strict: bool = False, label: str | None = None) -> np.ndarray:
    """The student's output as a float array, or BadOutput (None, not numbers).  strict: the output must
    already be a real float NumPy array — a list, an np.matrix, integers or complex numbers are named
    (label: which part of a tuple it is)."""
    where_ = tr("in_label").format(label=label) if label else ""
    if out is None:
        raise BadOutput("returned_none", where_ + tr("returned_none"))
    if strict:
        if isinstance(out, np.matrix):
            raise BadOutput("returned_matrix", "")
        if isinstance(out, (list, tuple)):
            raise BadOutput("returned_list", tr("list_detail").format(where=where_, got=short(out)))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            raw = np.asarray(out)
            arr = np.asarray(out, dtype=float)
    except Exception:       # noqa: BLE001 — whatever the object does, it is not numbers
        raise BadOutput("not_numbers", where_ + tr("not_numbers").format(got=short(out))) from None
    if strict and raw.dtype.kind in "iu":
        raise BadOutput("integer_array", tr("int_detail").format(where=where_, dtype=raw.dtype, values=fmt(raw)))
    if strict and raw.dtype.kind == "c":
        raise BadOutput("complex_array", tr("complex_detail").format(where=where_, real=fmt(raw.real),
                                                                        imag=fmt(raw.imag)))
    if strict and raw.dtype.kind == "f" and raw.dtype.itemsize < 8:
        raise BadOutput("float32", tr("float_detail").format(where=where_, dtype=raw.dtype))
    if strict and raw.dtype.kind == "b":
        raise BadOutput("not_numbers", where_ + tr("not_numbers").format(got=short(out)))
    return arr


def as_tuple(out, labels, strict: bool = False, want: str | None = None) -> tuple:
    """The student's output as a tuple of float arrays, one per label, or BadOutput (strict: each part must
    be a float NumPy array, see as_array; want: what was expected, in words, default "a tuple (labels)")."""
    if out is None:
        raise BadOutput("returned_none", tr("returned_none"))
    want = want or tr("tuple_want").format(labels=", ".join(labels))
    if isinstance(out, np.ndarray) and out.ndim == 1 and out.dtype != object:
        raise BadOutput("wrong_return", tr("one_array").format(shape=out.shape, want=want))
    if len(labels) == 4 and all(hasattr(out, k) for k in "xRPL"):
        items = [out.x, out.R, out.P, out.L]
    elif isinstance(out, (tuple, list)) or (isinstance(out, np.ndarray) and out.ndim >= 1):
        items = list(out)
    else:
        raise BadOutput("wrong_return", tr("wrong_return").format(got=short(out), want=want))
    if len(items) != len(labels):
        raise BadOutput("wrong_return", tr("wrong_count").format(n=len(items), k=len(labels), want=want))
    return tuple(as_array(v, strict, label) for v, label in zip(items, labels))


def short(obj) -> str:
    """An object's type and repr, cut to 80 characters."""
    try:
        text = repr(obj)
    except Exception:       # noqa: BLE001 — a student's object whose repr raises
        text = f"<{type(obj).__name__}>"
    text = text if len(text) <= 80 else text[:77] + "…"
    return f"{type(obj).__name__} {text}" if not isinstance(obj, (list, tuple)) else text


def quiet(fn, args, kwargs=None):
    """fn(*args, **kwargs) with its prints swallowed (a probe of the check's, not the student's run): call()."""
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return call(fn, args, kwargs)
