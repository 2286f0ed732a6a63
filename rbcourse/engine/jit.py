"""The one switch between compiled and interpreted physics: numba's njit, or nothing.

The engine's functions are written once (engine/*.py), in plain Python on 3-vectors and 3×3
matrices held as tuples of floats, and decorated with ``njit``.  With numba installed they are
compiled (to machine code, cached on disk beside the module); without numba, or with
NUMBA_DISABLE_JIT=1, the very same functions run as Python (slow, but the same numbers to
rounding).  ``IMPLEMENTATION`` says which, and why.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

AS_PYTHON = __name__.startswith("rbcourse.engine_python")   # the copy interpreted.py loads: never compiled

if AS_PYTHON:
    numba = None
else:
    try:
        import numba
    except ImportError:          # numba is optional: the engine then runs interpreted
        numba = None


def _which() -> tuple[str, str]:
    if AS_PYTHON:
        return "interpreted", "the engine's functions run as Python (engine/interpreted.py)"
    if numba is None:
        return "interpreted", "numba is not installed (pip install numba compiles the engine)"
    if numba.config.DISABLE_JIT:
        return "interpreted", "NUMBA_DISABLE_JIT=1 is set: the engine's functions run as Python"
    return "compiled", f"numba {numba.__version__} compiles the engine's functions (cached on disk)"


IMPLEMENTATION, WHY = _which()
COMPILED = IMPLEMENTATION == "compiled"


def _drop_stale_cache(folder: Path = Path(__file__).parent):
    """numba's disk cache checks a function's own file only: a compiled caller would keep running the old
    code of a function it calls from another file that was edited.  So the cache beside the engine
    (__pycache__/*.nbi, *.nbc) is kept only while every engine source is the one it was compiled from
    (a hash of them all, in __pycache__/engine_sources.sha256); otherwise it is removed, and recompiled."""
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sorted(folder.glob("*.py")))).hexdigest()
    cache = folder / "__pycache__"
    stamp = cache / "engine_sources.sha256"
    try:
        if stamp.exists() and stamp.read_text() == digest:
            return
        for old in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
            old.unlink()
        cache.mkdir(exist_ok=True)
        stamp.write_text(digest)
    except OSError:          # a read-only install: numba then caches in the user's folder (see the README)
        pass


if COMPILED:
    _drop_stale_cache()


def njit(fn):
    """Compile fn with numba (nopython, on-disk cache) — or return fn itself when numba is absent.

    Small helpers (the 3-vector algebra) are inlined where they are called."""
    if numba is None:
        return fn
    return numba.njit(cache=True, nogil=True, _nrt=False)(fn)


def hot(fn):
    """njit for the functions of the inner loop (rates, forces, the stage loop): inlined into their callers
    by numba itself, so the arrays they take are not passed call by call."""
    if numba is None:
        return fn
    return numba.njit(cache=True, _nrt=False, inline="always")(fn)


def inline(fn):
    """njit for the small algebra helpers (on tuples only: LLVM inlines them into their callers)."""
    if numba is None:
        return fn
    return numba.njit(cache=True, _nrt=False)(fn)


def describe() -> str:
    """One line: which implementation of the engine runs in this process, and why."""
    return f"{IMPLEMENTATION}: {WHY}"

