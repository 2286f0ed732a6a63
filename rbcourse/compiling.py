"""The one-line notice said when the engine compiles: numba compiles a method's loop at its first use, a few
seconds on a cold cache (more with a ground: the contact solve), once per machine (cached on disk afterwards) —
and says nothing while it does.

    with compiling.announced(loop, args, "explicit_quat", forces=True, ground=False):
        loop(*args)

says, before the call, "compiling the engine for this machine, once (~6 s)…" (in the workbook's language,
rbcourse.support.language), its estimate from what the call compiles (estimate), when that call will compile, once per
such compile per process; nothing otherwise:

- on the command line and in scripts: one line on stderr;
- in a notebook (an IPython kernel): a visible note that is not stderr, taken back once the compile is done.
  It is a display whose first message carries no data at all, then updated to the note, then updated to
  nothing again: nbval reads only the first message of a display (an empty one, which compares as nothing)
  and ignores its updates, so a checked cell passes whether the cache was cold (the note shown) or warm (no
  note); nbclient keeps the last update (again empty); JupyterLab and Notebook show the note meanwhile.

will_compile(dispatcher, args) says whether a call will compile: no overload for the arguments' types in this
process, and none in numba's disk cache (its index for the function read, not its machine code).
"""
from __future__ import annotations

import contextlib
import html
import sys

from .support import language

SECONDS = {"euler": 3, "explicit_quat": 5, "explicit_quat_world": 3, "symplectic_euler": 3, "splitting": 4,
           "rkmk4": 4, "variational": 4, "implicit_gyro": 3, "implicit_midpoint": 4, "adaptive": 5, "exact": 6}
"""What a run compiles on a cold cache, in seconds, by its loop (run.LOOPS: one per method, or two methods that
share a step), for a free body: the loop, its step and decode, nothing else.  A scene that evaluates forces adds
FORCES (the effects' code), a scene with a ground adds GROUND (the contact solve).  Measured on the development
machine (2 cores, idle; numba 0.68.1) as `python -m rbcourse throughput --compile` measures: each alone, in a
fresh process on an empty cache, the first rb.simulate of a free box, of a box under gravity, of a box on
rb.Ground.  Rounded: the same compile varies by ±20 % with the machine's load, and less when another run has
cached some of its pieces already (the same forces, the same contact solve)."""

FORCES = 1
"""Seconds a scene that evaluates forces (an effect, a pivot) adds to its loop's compile."""

GROUND = 10
"""Seconds a scene with a ground adds to its loop's compile: the contact solve."""

KICKS = 3
"""Seconds a scene with impulses adds to its loop's compile: the kicks' table walked in the loop (engine/kicks.py)."""

DEFAULT_SECONDS = 8
"""The estimate for a loop not in SECONDS."""

NOTICE = {"en": "compiling the engine for this machine, once (~{seconds} s)…",
          "fr": "compilation du moteur pour cette machine, une seule fois (~{seconds} s)…"}
"""The notice, per language (rbcourse.support.language.LANGUAGES)."""

_announced: set[str] = set()
_checked: set = set()          # the dispatchers whose first call in this process was checked
_quiet = [0]


def will_compile(dispatcher, args) -> bool:
    """Will calling this numba dispatcher with these arguments compile?  True when neither this process
    (dispatcher.overloads, keyed by the arguments' numba types) nor numba's disk cache (the function's
    index, whose entries are keyed by those types, the machine, and the function's code) holds it.  False
    when the engine runs interpreted (no numba, NUMBA_DISABLE_JIT=1), for a plain Python function, and for
    arguments numba cannot type (the call fails at once: nothing to wait for)."""
    dispatcher = getattr(dispatcher, "from_python", dispatcher)     # a kernel function called from Python: its twin
    if not hasattr(dispatcher, "overloads") or not hasattr(dispatcher, "typeof_pyval"):
        return False                                     # a plain Python function: the kernel run as Python
    from .engine import jit                              # (numba is loaded already: dispatcher is numba's)
    if not jit.COMPILED:
        return False
    if not getattr(dispatcher, "_can_compile", True):     # signatures given up front: it never compiles on a call
        return False
    try:
        from numba.core import types
        sig = tuple(dispatcher.typeof_pyval(a) for a in args)
    except Exception:
        return False
    if any(t == types.pyobject for t in sig):
        return False
    if sig in dispatcher.overloads:
        return False
    return not _in_disk_cache(dispatcher, sig)


def _in_disk_cache(dispatcher, sig) -> bool:
    """Is sig in the dispatcher's disk cache index (numba.core.caching: Cache._index_key, IndexDataCacheFile's
    index, which is empty when stale: another numba, or the function's file changed)?  Read, not loaded."""
    cache = getattr(dispatcher, "_cache", None)
    index = getattr(cache, "_cache_file", None)
    if index is None:                                  # NullCache: caching off, a call compiles
        return False
    try:
        codegen = dispatcher.targetctx.codegen()        # no refresh (0.3-0.5 s of registries): the key needs none
        if hasattr(cache, "holds"):                    # the engine's (engine/cache.py)
            return cache.holds(sig, codegen)
        return cache._index_key(sig, codegen) in index._load_index()
    except Exception:                                   # an unreadable index: numba will compile
        return False


def estimate(family: str, forces: bool = False, ground: bool = False, kicks: bool = False) -> int:
    """The seconds a cold compile of this loop takes (SECONDS; DEFAULT_SECONDS for another), with the forces of a
    scene that evaluates some (FORCES), the contact solve of a scene with a ground (GROUND) and the kicks of a
    scene with impulses (KICKS)."""
    return SECONDS.get(family, DEFAULT_SECONDS) + FORCES * bool(forces) + GROUND * bool(ground) + KICKS * bool(kicks)


def notice(family: str, forces: bool = False, ground: bool = False, kicks: bool = False) -> str:
    """The notice for this compile, in the active language."""
    return NOTICE[language.current()].format(seconds=estimate(family, forces, ground, kicks))


@contextlib.contextmanager
def announced(dispatcher, args, family: str, forces: bool = False, ground: bool = False, kicks: bool = False):
    """Around the call dispatcher(*args): says the notice first when the call will compile (will_compile),
    once per compile (a loop, with forces or not, with a ground or not, with kicks or not: estimate) in this
    process; does nothing otherwise.  In a notebook the note goes away when the
    block ends.  Checked at the first call of each dispatcher in the process only: typing the arguments costs
    about a millisecond, and the driver calls a family's loop with arguments of the same types every time."""
    what = (family, bool(forces), bool(ground), bool(kicks))
    if _quiet[0] or what in _announced or (dispatcher, what) in _checked:
        yield
        return
    _checked.add((dispatcher, what))
    if not will_compile(dispatcher, args):
        yield
        return
    _announced.add(what)
    line = notice(family, forces, ground, kicks)
    handle = _notebook_note(line) if _in_kernel() else None
    if handle is None:
        with contextlib.suppress(OSError, ValueError):     # a stderr that cannot be written (full, closed): no notice
            sys.stderr.write(line + "\n")                  # one write: a Ctrl-C never leaves the line open
            sys.stderr.flush()
    try:
        yield
    finally:
        if handle is not None:
            with contextlib.suppress(Exception):
                handle.update({}, raw=True)


@contextlib.contextmanager
def quiet():
    """No notice inside this block (a caller with its own progress display: `python -m rbcourse compile`)."""
    _quiet[0] += 1
    try:
        yield
    finally:
        _quiet[0] -= 1


def _in_kernel() -> bool:
    """Is this process an IPython kernel (a notebook)?  Never imports IPython itself."""
    ipython = sys.modules.get("IPython")
    if ipython is None:
        return False
    try:
        shell = ipython.get_ipython()
    except Exception:
        return False
    return shell is not None and getattr(shell, "kernel", None) is not None


def _notebook_note(line: str):
    """The note shown in the cell's output, not on stderr: a display with no data at first (all nbval
    records), updated to the note.  None when IPython cannot display (the caller then uses stderr)."""
    try:
        from IPython.display import display
        handle = display({}, raw=True, display_id=True)
        handle.update({"text/plain": line, "text/html": f"<pre>{html.escape(line)}</pre>"}, raw=True)
        return handle
    except Exception:
        return None
