"""Machine code shipped with the package, so that nobody waits for numba on a machine like the one it was
built on — and numba's own cache for the rest.

numba compiles a family of methods at its first use (10–25 s, cold) and keeps the result on disk
(jit.cache_folder()).  `python -m rbcourse compile --ship` compiles every method ahead of time for the
x86-64-v3 processor level (NUMBA_CPU_NAME=x86-64-v3: AVX2 — every Intel processor since Haswell, 2013, and
AMD since 2015; vector instructions four numbers wide, where a generic x86-64 has two) into engine/compiled/,
which the repository and the wheel carry.  EngineCache, the cache of every kernel function (jit.py), looks in
that folder after the machine's own cache, and uses what it finds there when:

    the engine's sources are the ones it was built from     (compiled/engine_sources.sha256: sources_digest)
    this processor runs x86-64-v3 code                      (its features: host_runs_level)
    and the same numba, CPython and platform run            (numba's own index checks: version, file names
                                                             .pyXY, the target triple in the key)

Anything else (another platform or Python, an older processor, an edited engine) compiles as before, into the
machine's own cache; so does everything when RBCOURSE_SHIPPED_CODE=0 is set (to see what a machine without it
waits for).  The keys of the shipped entries name the target triple and "portable x86-64-v3" instead of this
processor's name and features.  The numbers are the same as a generic build's: numba fuses no multiply and add
(no fastmath), and a vector instruction does each body's arithmetic exactly as the scalar one.
"""
from __future__ import annotations

import hashlib
import os
import pickle
import zlib
from functools import lru_cache
from pathlib import Path

from numba.core import config
from numba.core.caching import FunctionCache, IndexDataCacheFile

ENGINE = Path(__file__).parent
SHIPPED = ENGINE / "compiled"
STAMP = "engine_sources.sha256"
LEVEL = "x86-64-v3"                        # the processor level the shipped code is built for (NUMBA_CPU_NAME)
LEVEL_FEATURES = frozenset({                # … and what a processor needs to run it (LLVM's names of x86-64-v3's)
    "cx16", "sahf", "popcnt", "sse3", "ssse3", "sse4.1", "sse4.2",                     # x86-64-v2
    "avx", "avx2", "bmi", "bmi2", "f16c", "fma", "lzcnt", "movbe", "xsave"})           # x86-64-v3
PORTABLE = f"portable {LEVEL}"
BUILD = "RBCOURSE_BUILD_MACHINE_CODE"      # set (to 1) by `compile --ship` in the process that builds SHIPPED
USE = "RBCOURSE_SHIPPED_CODE"              # set to 0: the shipped code is not used (all compiled, as elsewhere)


def sources_digest(folder: Path = ENGINE) -> str:
    """A hash of every engine source (*.py of engine/): compiled code is valid only for these."""
    return hashlib.sha256(b"".join(p.read_bytes() for p in sorted(folder.glob("*.py")))).hexdigest()


def host_runs_level(features=None) -> bool:
    """Does this processor run LEVEL's code: has it every feature of LEVEL_FEATURES?  features: the names of a
    processor's features (default: this one's, as LLVM reads them, which counts AVX only where the system
    saves its registers)."""
    if features is None:
        from llvmlite import binding
        features = {name for name, on in binding.get_host_cpu_features().items() if on}
    return LEVEL_FEATURES <= set(features)


@lru_cache(maxsize=None)
def shipped_is_current() -> bool:
    """Was SHIPPED built from the engine's sources as they are now, can this processor run it, and is it not
    turned off (USE=0)?"""
    if os.environ.get(USE) == "0":
        return False
    try:
        current = (SHIPPED / STAMP).read_text().strip() == sources_digest()
    except OSError:
        return False
    try:
        return current and host_runs_level()
    except Exception:                   # a platform whose features LLVM cannot read: compiled here instead
        return False


def building() -> bool:
    """Is this the process that builds SHIPPED (compile --ship: LEVEL's code, saved there)?"""
    return os.environ.get(BUILD) == "1"


class ShippedFile(IndexDataCacheFile):
    """numba's index and data files, the data compressed (zlib at level 9: the shipped folder is 38 % of its size;
    LZMA made it 33 %, but took 6× as long to read back: 0.08 s of the demo's 4 MB, zlib 0.015 s)."""

    def _save_data(self, name, data):
        with self._open_for_write(self._data_path(name)) as f:
            f.write(zlib.compress(self._dump(data), 9))

    def _load_data(self, name):
        with open(self._data_path(name), "rb") as f:
            return pickle.loads(zlib.decompress(f.read()))


class EngineCache(FunctionCache):
    """numba's cache of one kernel function (its own folder: jit.cache_folder()), then the shipped one."""

    def __init__(self, py_func):
        super().__init__(py_func)
        self._shipped = ShippedFile(cache_path=str(SHIPPED), filename_base=self._impl.filename_base,
                                    source_stamp=self._impl.locator.get_source_stamp())

    def _portable_key(self, sig, codegen):
        sig, magic, hashes = self._index_key(sig, codegen)
        return sig, (magic[0], PORTABLE), hashes

    def load_overload(self, sig, target_context):
        """numba's load_overload without the refresh of the target context it runs first (which imports and
        installs every registry of numba's lowering, scipy.linalg included: 0.3-0.5 s, the most of a fresh
        process's first run).  Machine code that is loaded, not compiled, is lowered already: it needs none of
        them (a compilation still refreshes, in numba's compiler).  Should a load fail without them, it is run
        again numba's own way, refresh first."""
        try:
            with self._guard_against_spurious_io_errors():
                return self._load_overload(sig, target_context)
        except Exception:
            return super().load_overload(sig, target_context)

    def _load_overload(self, sig, target_context):
        if building():
            return None                                   # everything compiled afresh, for SHIPPED
        data = super()._load_overload(sig, target_context)
        if data is None and self._enabled and shipped_is_current():
            data = self._shipped.load(self._portable_key(sig, target_context.codegen()))
            if data is not None:
                data = self._impl.rebuild(target_context, data)
        return data

    def _save_overload(self, sig, data):
        if not building():
            return super()._save_overload(sig, data)
        if config.CPU_NAME != LEVEL or config.CPU_FEATURES:
            raise RuntimeError(f"{BUILD}=1 needs NUMBA_CPU_NAME={LEVEL} and NUMBA_CPU_FEATURES empty (portable "
                               "machine code)")
        if self._enabled and self._impl.check_cachable(data):
            SHIPPED.mkdir(exist_ok=True)
            self._shipped.save(self._portable_key(sig, data.codegen), self._impl.reduce(data))

    def holds(self, sig, codegen) -> bool:
        """Is sig in this machine's cache index, or in the shipped one (current)?  Read, not loaded."""
        if sig_in(self._cache_file, self._index_key(sig, codegen)):
            return True
        return shipped_is_current() and sig_in(self._shipped, self._portable_key(sig, codegen))


def sig_in(index: IndexDataCacheFile, key) -> bool:
    """Is key in this cache index (empty when stale: another numba, or the function's file changed)?"""
    try:
        return key in index._load_index()
    except Exception:                                     # an unreadable index: numba compiles
        return False
