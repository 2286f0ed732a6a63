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


if COMPILED:
    from numba.core import types as _types
    from numba.core.registry import CPUDispatcher

    class KernelFunction(CPUDispatcher):
        """A kernel function as numba compiles it for the kernel's own callers: machine code only, with none of the
        wrappers that let Python call it (numba makes two per function: a CPython one, and a C one for first-class
        function pointers) — they were a fifth of a cold compile, for functions Python never calls.  Called from
        Python (the driver's loops, a test), it is its twin: the same function, compiled with its Python wrapper at
        its first call from Python, cached on disk apart (cache.EngineCache(python=True))."""

        def __call__(self, *args, **kwargs):
            return self.from_python(*args, **kwargs)

        def get_call_template(self, args, kws):
            """Typing a call from a kernel function: compiled for its arguments' types, not for the values of the
            constants among them (numba's literal types): spin_entry(I_inv, at, 0, 1) would be compiled once for
            each pair of indices — nine times.  (An index LLVM still sees constant, once the function is inlined.)"""
            return super().get_call_template(tuple(_types.unliteral(a) for a in args),
                                             {k: _types.unliteral(v) for k, v in kws.items()})

        @property
        def from_python(self):
            """The same function, compiled to be called from Python (once per process)."""
            twin = self.__dict__.get("_from_python")
            if twin is None:
                from .cache import EngineCache
                options = {k: v for k, v in self.targetoptions.items() if k != "no_cpython_wrapper"}
                twin = CPUDispatcher(py_func=self.py_func, locals={}, targetoptions=options)
                twin._cache = EngineCache(self.py_func, python=True)
                self.__dict__["_from_python"] = twin
            return twin


if COMPILED:
    from llvmlite import binding as _ll
    from numba.core import compiler as _compiler
    from numba.core.codegen import JITCodeLibrary

    class KernelLibrary(JITCodeLibrary):
        """A kernel function's code as numba keeps it: LLVM IR, linked into each compiled caller and made into machine
        code there, with its caller — never machine code of its own, since only kernel functions call it (Python calls
        its twin, KernelFunction.from_python).  numba would translate it to machine code at every level of calls, and
        optimise it again at each level: a loop's compile held the contact solve's machine code six times over.

        Nor is it optimised on its own (numba's function passes only): the loop Python calls optimises it, inside
        itself, once — unless its code holds the address of a Python object (a function passed as an argument: numba's
        dynamic globals), which only optimisation takes away and numba's disk cache refuses.  Kept on disk as LLVM
        bitcode (kind "kernel", rebuilt)."""

        def _optimize_final_module(self):
            if any(gv.name.startswith("numba.dynamic.globals") for gv in self._final_module.global_variables):
                super()._optimize_final_module()

        def _finalize_final_module(self):
            self._finalize_dynamic_globals()
            self._verify_declare_only_symbols()
            self._finalized = True               # and no machine code (numba: _add_module, _finalize_specific)

        def get_pointer_to_function(self, name):
            self._ensure_finalized()
            return 0                             # no machine code: numba asks for the Python wrapper it has not

        @property
        def codegen(self):
            return _NoEnvironment(self._codegen)

        def serialize_using_object_code(self):
            self._ensure_finalized()
            return (self.name, "kernel", self._get_module_for_linking().as_bitcode())

        @classmethod
        def rebuilt(cls, codegen, state):
            """The library serialize_using_object_code kept on disk: its bitcode, ready to link."""
            name, _, bitcode = state
            self = cls(codegen, name)
            self._final_module = self._shared_module = _ll.parse_bitcode(bitcode)
            self._finalized = True
            return self

    class _NoEnvironment:
        """numba's codegen, as a KernelLibrary's: it sets no environment (a global of the machine code that points at
        its Python objects), since there is no machine code — and a kernel function takes no Python object."""

        def __init__(self, codegen):
            self._codegen = codegen

        def __getattr__(self, name):
            return getattr(self._codegen, name)

        def set_env(self, env_name, env):
            pass

    _numba_unserialize = JITCodeLibrary._unserialize.__func__

    def _unserialize(cls, codegen, state):
        """numba's reading of a cached library, which also reads a KernelLibrary's (kind "kernel": only the engine's
        cache files hold one)."""
        if state[1] == "kernel":
            return KernelLibrary.rebuilt(codegen, state)
        return _numba_unserialize(cls, codegen, state)

    class KernelCompiler(_compiler.Compiler):
        """numba's compiler, with a kernel function's code kept as a KernelLibrary."""

        def compile_extra(self, func):
            if self.state.library is None:
                self.state.library = KernelLibrary(self.state.targetctx.codegen(), func.__qualname__)
            return super().compile_extra(func)

    # numba's own code library, as KernelLibrary builds on it (numba 0.68): with another numba that lacks a part of
    # it, kernel functions are compiled numba's own way — slower to compile, the same machine code
    KERNEL_LIBRARY = all(hasattr(JITCodeLibrary, name) for name in (
        "_optimize_final_module", "_finalize_final_module", "_finalize_dynamic_globals", "_verify_declare_only_symbols",
        "_get_module_for_linking", "_ensure_finalized", "_unserialize"))
    if KERNEL_LIBRARY:
        JITCodeLibrary._unserialize = classmethod(_unserialize)
    PIPELINE = KernelCompiler if KERNEL_LIBRARY else _compiler.Compiler


def kernel_function(fn, **options):
    """fn compiled by numba for the kernel (KernelFunction: nopython, its disk cache: cache.EngineCache) — or fn
    itself when the engine runs as Python (no numba, NUMBA_DISABLE_JIT=1, engine/interpreted.py's copy)."""
    if not COMPILED:
        return fn
    from .cache import EngineCache
    options = {"_nrt": False, "error_model": ERRORS, "no_cpython_wrapper": True, "no_cfunc_wrapper": True, **options}
    dispatcher = KernelFunction(py_func=fn, locals={}, targetoptions=options, pipeline_class=PIPELINE)
    dispatcher._cache = EngineCache(fn)
    return dispatcher


def njit(fn):
    """A kernel function, compiled on its own and called (kernel_function)."""
    return kernel_function(fn, nogil=True)


def hot(fn):
    """A kernel function of the inner loop (rates, forces, the stage loop, a body's contact solve): always inlined
    by LLVM into its callers (forceinline), so the arrays it takes are not passed call by call (a Work or a System
    is some 200 numbers: passed on the stack at every call)."""
    return kernel_function(fn, forceinline=True)


def unrolled(fn):
    """A piece of rk4's lane loop (stages.py): inlined by numba itself into its caller before the caller is
    compiled (inline="always"), so that LLVM sees one loop it can run in vector instructions, several bodies at
    once (inlined by LLVM instead, as hot is, the loop stays scalar: twice the time per body-step)."""
    return kernel_function(fn, inline="always")


def inline(fn):
    """A small helper (the algebra on tuples, the symmetric solve's 3×3 pieces): always inlined by LLVM into its
    callers (forceinline), so that a call passes nothing — an array argument alone is some 8 numbers, and LLVM
    left a helper of a few lines that takes two of them as a call."""
    return kernel_function(fn, forceinline=True)


def describe() -> str:
    """One line: which implementation of the engine runs in this process, and why."""
    return f"{IMPLEMENTATION}: {WHY}"

