"""numba's disk cache of the engine's functions, as the engine uses it (jit.py gives every kernel function one).

numba compiles a function at its first call on a machine and keeps it on disk (jit.cache_folder(): NUMBA_CACHE_DIR,
engine/__pycache__, or the user's own cache folder for a read-only install); every later process loads it from
there: the machine code of a function Python calls (a method's loop), the LLVM IR of a kernel function, which only
its compiled callers hold (jit.KernelLibrary).  Nothing compiled is shipped with the package: a new machine compiles
what its runs call for, once (compiling.py says so while it does).

EngineCache is numba's FunctionCache but for one thing: loading machine code skips numba's refresh of its target
context, which imports and installs every registry of numba's lowering (numba.np.arraymath, scipy.linalg among
them: 0.3–0.5 s of a fresh process).  Code that is loaded, not compiled, is lowered already and needs none of
them; a compilation still refreshes, in numba's compiler.  Should a load fail without them, it is run again
numba's own way, refresh first.  And a function given functions as arguments (run.loop its step, decode and
encode; stages.rk_stages its rate) is not kept on disk at all (takes_functions): only in the process, inside the
named loop that calls it — which is kept.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

from numba.core.caching import FunctionCache, IndexDataCacheFile

ENGINE = Path(__file__).parent
STAMP = "engine_sources.sha256"


def sources_digest(folder: Path = ENGINE) -> str:
    """A hash of every engine source (*.py of engine/): the cached code is valid only for these (jit.py)."""
    return hashlib.sha256(b"".join(p.read_bytes() for p in sorted(folder.glob("*.py")))).hexdigest()


class EngineCache(FunctionCache):
    """numba's cache of one kernel function, loaded without the refresh of the target context (module docstring).
    python=True: the cache of its twin compiled to be called from Python (jit.KernelFunction), in files of its own
    (the kernel's callers' code has no Python wrapper: the two are never mixed)."""

    def __init__(self, py_func, python: bool = False):
        super().__init__(py_func)
        if python:
            self._cache_file = IndexDataCacheFile(cache_path=self._cache_path,
                                                  filename_base=self._impl.filename_base + "-py",
                                                  source_stamp=self._impl.locator.get_source_stamp())

    def load_overload(self, sig, target_context):
        if takes_functions(sig):
            return None
        try:
            with self._guard_against_spurious_io_errors():
                return self._load_overload(sig, target_context)
        except Exception:
            return super().load_overload(sig, target_context)

    def save_overload(self, sig, data):
        """numba's save, but a cache that cannot be written (a read-only or full disk, a file size limit) loses only
        the cached copy: the run goes on with the code it compiled, and the next process compiles it again.  Nothing
        is saved for a function given functions (takes_functions)."""
        if takes_functions(sig):
            return
        try:
            super().save_overload(sig, data)
        except OSError:
            pass

    def holds(self, sig, codegen) -> bool:
        """Is sig in this function's cache index (read, not loaded; empty when stale: another numba, or the
        function's file changed)?"""
        try:
            return self._index_key(sig, codegen) in self._cache_file._load_index()
        except Exception:                                  # an unreadable index: numba compiles
            return False


def takes_functions(sig) -> bool:
    """Does sig type an argument as a function (a numba Dispatcher)?  Such an entry is never found by another
    process: a function argument's type is the very function object, which another process rebuilds anew when it
    reads the cache's index, and never equal to its own.  Kept, it would be pickled again at every save of its
    function's index, by then perhaps collected (numba: ReferenceError "underlying object has vanished", and the
    caller compiled in object mode instead)."""
    from numba.core import types
    return any(isinstance(a, types.Dispatcher) for a in sig)
