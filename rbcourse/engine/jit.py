"""The one switch between compiled and interpreted physics: numba's njit, or nothing.

The engine's functions are written once (engine/*.py), in plain Python on 3-vectors and 3×3
matrices held as tuples of floats, and decorated with ``njit``.  With numba installed they are
compiled (to machine code, cached on disk: cache.py); without numba, or with
NUMBA_DISABLE_JIT=1, the very same functions run as Python (slow, but the same numbers to
rounding).  ``IMPLEMENTATION`` says which, and why.

Compiled, a division is IEEE's (numba's error_model="numpy"): x / 0 is ±inf or NaN, as in NumPy, with no test
for zero before it — so a loop of divisions can run several bodies at once in vector instructions.  The
engine divides only by what cannot be 0 (a mass, checked positive) or what it tests itself first (a norm,
quaternion.quat_normalize); a blown-up run's inf or NaN is what the step's check (run.first_bad) stops at.
"""
from __future__ import annotations

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
ERRORS = "numpy"            # a division by 0 gives ±inf or NaN (module docstring), no ZeroDivisionError
COMPILED = IMPLEMENTATION == "compiled"


def cache_folder(folder: Path = Path(__file__).parent) -> Path | None:
    """The folder numba keeps the engine's compiled code in, as numba itself chooses it (its cache locators, in
    its order): under NUMBA_CACHE_DIR when that is set; else engine/__pycache__, beside the sources, when it
    can be written; else the user's own cache folder, ~/.cache/numba/engine_<hash of the engine's path> (a
    read-only install: a shared JupyterHub environment, a system-wide pip install).  The folder is created if
    need be.  None when nothing is cached (the engine runs interpreted, or numba finds no writable folder)."""
    if not COMPILED:
        return None
    from numba.core import caching
    sources = sorted(folder.glob("*.py"))
    locators = getattr(caching.CacheImpl, "_locator_classes", None) or [
        caching.UserProvidedCacheLocator, caching.InTreeCacheLocator, caching.UserWideCacheLocator]
    for locator in locators if sources else ():
        try:
            found = locator.from_function(cache_folder, str(sources[0]))   # any engine function: same folder
        except Exception:        # a locator numba may add, that expects another kind of function: not the engine's
            found = None
        if found is not None:
            return Path(found.get_cache_path())
    return None


def _drop_stale_cache(folder: Path = Path(__file__).parent):
    """numba's disk cache checks a function's own file only: a compiled caller would keep running the old
    code of a function it calls from another file that was edited.  So the engine's cache (*.nbi, *.nbc in
    cache_folder(): engine/__pycache__, or the user's folder for a read-only install, or NUMBA_CACHE_DIR's)
    is kept only while every engine source is the one it was compiled from (a hash of them all, in
    engine_sources.sha256 beside it); otherwise it is removed, and recompiled."""
    from .cache import sources_digest
    digest = sources_digest(folder)
    cache = cache_folder(folder)
    if cache is None:
        return
    stamp = cache / "engine_sources.sha256"
    try:
        if stamp.exists() and stamp.read_text() == digest:
            return
        for old in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
            old.unlink()
        stamp.write_text(digest)
    except OSError:          # a folder numba could write a moment ago, and no longer can: nothing to keep in step
        pass


if COMPILED:
    _drop_stale_cache()


def _cached(dispatcher):
    """The dispatcher with its disk cache (cache.py: EngineCache, numba's own loaded without its refresh).  With NUMBA_DISABLE_JIT=1 numba gives back the plain function: nothing to cache."""
    if not hasattr(dispatcher, "py_func"):
        return dispatcher
    from .cache import EngineCache
    dispatcher._cache = EngineCache(dispatcher.py_func)
    return dispatcher


def njit(fn):
    """Compile fn with numba (nopython, on-disk cache) — or return fn itself when numba is absent.

    Small helpers (the 3-vector algebra) are inlined where they are called."""
    if numba is None:
        return fn
    return _cached(numba.njit(nogil=True, _nrt=False, error_model=ERRORS, forceinline=False)(fn))


def hot(fn):
    """njit for the functions of the inner loop (rates, forces, the stage loop, a body's contact solve): inlined
    into their callers by numba itself, so the arrays they take are not passed call by call (a Work or a
    System is some 200 numbers: passed on the stack at every call)."""
    if numba is None:
        return fn
    return _cached(numba.njit(_nrt=False, inline="always", error_model=ERRORS, forceinline=False)(fn))


def inline(fn):
    """njit for the small helpers (the algebra on tuples, the symmetric solve's 3×3 pieces): always inlined
    by LLVM into their callers (forceinline), so that a call passes nothing — an array argument alone is
    some 8 numbers, and LLVM left a helper of a few lines that takes two of them as a call."""
    if numba is None:
        return fn
    return _cached(numba.njit(_nrt=False, error_model=ERRORS, forceinline=True)(fn))


def describe() -> str:
    """One line: which implementation of the engine runs in this process, and why."""
    return f"{IMPLEMENTATION}: {WHY}"

