"""A hand-in's process, in its sandbox: ``python -I -S /grading/worker.py MODE READ_FD WRITE_FD LIMITS SITES``.

Nothing here is trusted by the grader: this file runs in the same process as the student's code, which may
change any of it.  What it sends (wire.py: plain data only) is what the student's code made; the verdicts
are the checker's, in another process (checker.py).

SITES (JSON) are the package folders it adds to its path, as its sandbox sees them (it runs without site: -S).
It first lowers its own limits (LIMITS, JSON: memory, CPU seconds, file size, processes, open files), then
receives {"cells": [...], "language": …, "seconds": S, "names": [...], "cache": …} and runs the code cells
one after the other in an IPython shell, as "Run All" does, going on after a cell that raises; a cell still
running S seconds after the first one started is interrupted (OutOfTime, raised in it, as Jupyter's
"Interrupt" does) and the cells after it are not run.  Then it sends

    {"op": "cells", "errors": [{"cell", "cells", "first_line", "error"}], "interrupted": {…} or None,
     "language": …, "functions": {name: {"callable", "type", "repr", "params"}}}

MODE "run" (the notebook with the library, for its status) stops there.  MODE "serve" (the notebook where
``import rbcourse`` finds standin.py) then answers the checker's calls, one at a time:

    → {"op": "call", "id": k, "name": …, "args": [...], "kwargs": {...}, "seconds": s}
    ← {"op": "callback", "id": k, "fn": j, "args": [...], "kwargs": {...}}   (the student's code calls forces_at)
    → {"op": "return", "id": k, "value": …} or {"op": "raise", "id": k, "type": …, "message": …}
    ← {"op": "result", "id": k, "value": …, "args": [the arguments as the call left them]}
      or {"op": "raised", "id": k, "type", "builtin", "message", "frames", "library"} or {"op": "timed_out", "id": k}
    → {"op": "quit"}
"""
from __future__ import annotations

import gc
import inspect
import json
import os
import resource
import shutil
import signal
import sys
import sysconfig
import traceback
import warnings

if __name__ == "__main__":                  # run as /grading/worker.py: wire.py (and the stand-in) beside it
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    SITES = json.loads(sys.argv[5]) if len(sys.argv) > 5 else []   # python -S: the grader's package folders
    import site
    for _folder in SITES:
        site.addsitedir(_folder)
else:
    SITES = []
try:
    from . import seccomp, wire
except ImportError:
    import seccomp
    import wire

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
NOT_STUDENT = tuple({HERE, os.path.dirname(np.__file__), os.path.dirname(os.__file__)}
                    | {sysconfig.get_paths()[k] for k in ("stdlib", "platstdlib", "purelib", "platlib")}
                    | set(SITES))
"""Folders whose frames are not the student's code (for where an exception was raised)."""
MAX_ERRORS = 50


class OutOfTime(BaseException):
    """Raised in the hand-in's code when its time is up (a BaseException: `except Exception` does not stop it)."""


def _out_of_time(signum, frame):
    raise OutOfTime("the time limit was reached")


def alarm(seconds: float) -> None:
    """OutOfTime in `seconds` (0: no alarm)."""
    signal.setitimer(signal.ITIMER_REAL, max(seconds, 1e-3) if seconds else 0.0)


LIMITED = {"memory": resource.RLIMIT_AS, "cpu": resource.RLIMIT_CPU, "file_size": resource.RLIMIT_FSIZE,
           "processes": resource.RLIMIT_NPROC, "open_files": resource.RLIMIT_NOFILE}


def set_limits(limits: dict) -> None:
    """This process's limits (and its children's), lowered for good: they cannot be raised again."""
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)          # a write past the file size limit fails (EFBIG)
    for key, value in limits.items():
        if key in LIMITED and value:
            resource.setrlimit(LIMITED[key], (int(value), int(value) + (1 if key == "cpu" else 0)))


def code_cells(notebook: dict) -> list[str]:
    """The source of each code cell, in order."""
    out = []
    for cell in notebook.get("cells", []) if isinstance(notebook, dict) else []:
        if isinstance(cell, dict) and cell.get("cell_type") == "code":
            source = cell.get("source", "")
            out.append("".join(str(s) for s in source) if isinstance(source, list) else str(source))
    return out


def first_line(source: str, look: int = 65536) -> str:
    """The cell's first line that is neither blank nor a comment, within its first `look` characters (a cell of
    20 MB is not split whole: its process may be short of memory), cut to 80."""
    for line in source[:look].splitlines():
        if line.strip() and not line.lstrip().startswith("#"):
            return line.strip()[:80]
    return ""


def _text(exc: BaseException) -> str:
    try:
        text = " ".join(str(exc).split())
    except BaseException:       # noqa: BLE001 — a str() that raises
        text = ""
    return f"{wire.type_name(exc)}: {text}"[:300] if text else wire.type_name(exc)


RESERVE = 32 << 20      # bytes held back while a cell runs: given back when it ran out of memory, to say so
MAX_CELL = 4 << 20      # characters of code (comment lines aside) of a cell that is run: a bigger one is an error
                        # (its parse tree alone would take its process's memory, and minutes)


def code_size(source: str) -> int:
    """The characters of a cell's lines that are not comments (what its parse tree grows with: a comment, or a
    string's line that starts with #, is no node of it)."""
    return sum(len(line) for line in source.splitlines() if not line.lstrip().startswith("#"))


def run_cells(shell, sources, seconds: float) -> tuple[list, dict | None]:
    """Run the cells within `seconds` in all: (the errors, the interrupted cell or None).  A cell that ran out of
    memory (its process is limited) is an error as any other: the memory held back (RESERVE) is given back first,
    for the rest of the notebook to be run and said."""
    errors, k = [], 0
    try:
        alarm(seconds)
        reserve = bytearray(RESERVE)
        for k, source in enumerate(sources, 1):
            size = code_size(source) if len(source) > MAX_CELL else 0
            if size > MAX_CELL:
                if len(errors) < MAX_ERRORS:
                    errors.append({"cell": k, "cells": len(sources), "first_line": first_line(source),
                                   "error": f"not run: {size:,} characters of code (a code cell of at most "
                                            f"{MAX_CELL:,}, comments aside, is run)"})
                continue
            result = shell.run_cell(source, store_history=True)
            error = result.error_before_exec or result.error_in_exec
            if isinstance(error, OutOfTime):
                raise error
            if isinstance(error, MemoryError):
                error.__traceback__ = None          # its frames, and what kept them alive (the cell's parse tree)
                result = reserve = shell.last_execution_result = sys.last_value = sys.last_traceback = None
                sys.last_exc = None
                gc.collect()
                try:
                    reserve = bytearray(RESERVE)
                except MemoryError:
                    pass
            if error is not None and len(errors) < MAX_ERRORS:
                errors.append({"cell": k, "cells": len(sources), "first_line": first_line(source),
                               "error": _text(error)})
        alarm(0)
        del reserve
        return errors, None
    except OutOfTime:
        alarm(0)
        return errors, {"cell": k, "cells": len(sources), "seconds": seconds,
                        "first_line": first_line(sources[k - 1]) if k else ""}


def describe(obj) -> dict:
    """What the checker is told of a graded function: callable or not, its type, repr and parameters."""
    params = None
    try:
        if callable(obj):
            params = [str(p)[:40] for p in inspect.signature(obj).parameters][:20]
    except BaseException:       # noqa: BLE001 — no signature (a builtin, a strange object)
        params = None
    return {"callable": bool(callable(obj)), "type": wire.type_name(obj), "repr": wire.short_repr(obj),
            "params": params}


def student_frames(exc: BaseException) -> list:
    """[(function, line number, line)] of the student's own frames in the exception's traceback."""
    try:
        frames = traceback.extract_tb(exc.__traceback__)
    except BaseException:       # noqa: BLE001
        return []
    return [[str(f.name)[:60], int(f.lineno or 0), str(f.line or "")[:120]] for f in frames
            if not str(f.filename).startswith(NOT_STUDENT)][-10:]


def raised(call_id, exc: BaseException) -> dict:
    builtin = next((c.__name__ for c in type(exc).__mro__ if c.__module__ == "builtins"), "Exception")
    library = getattr(exc, "path", None) if type(exc).__name__ == "LibraryUnavailable" else None
    try:
        message = str(exc)[:300]
    except BaseException:       # noqa: BLE001
        message = ""
    return {"op": "raised", "id": call_id, "type": wire.type_name(exc), "builtin": builtin, "message": message,
            "frames": student_frames(exc), "library": str(library)[:120] if library else None}


def _unavailable(value) -> str | None:
    """The rbcourse name a value is, when it is one of the stand-in's (returned instead of computed)."""
    return type(value).__name__ == "Standin" and getattr(value, "__name__", None) or None


def callback(channel, call_id, item: dict):
    """The checker's function number item["id"] (forces_at, step), as the student's code calls it."""
    def proxy(*args, **kwargs):
        channel.send({"op": "callback", "id": call_id, "fn": item.get("id"), "args": [wire.encode(a) for a in args],
                      "kwargs": {str(k): wire.encode(v) for k, v in kwargs.items()}})
        while True:
            message = channel.receive()
            if message.get("id") == call_id and message.get("op") == "return":
                return wire.decode(message.get("value"))
            if message.get("id") == call_id and message.get("op") == "raise":
                error = _builtin_exception(message.get("type"))
                raise error(str(message.get("message", "")))
    proxy.__name__ = str(item.get("name", "callback"))
    try:
        proxy.__signature__ = inspect.Signature([inspect.Parameter(str(p), inspect.Parameter.POSITIONAL_OR_KEYWORD)
                                                 for p in item.get("params") or []])
    except (TypeError, ValueError):
        pass
    return proxy


def _builtin_exception(name):
    import builtins
    found = getattr(builtins, str(name), None)
    return found if isinstance(found, type) and issubclass(found, Exception) else RuntimeError


def answer(channel, message: dict, functions: dict) -> dict:
    """One call of a graded function, as the checker asked it: its result (and its arguments as it left them),
    what it raised, or that it ran out of time."""
    call_id = message.get("id")
    fn = functions.get(message.get("name"))
    try:
        alarm(float(message.get("seconds", 1.0)))
        args = [wire.decode(a, lambda item: callback(channel, call_id, item)) for a in message.get("args", [])]
        kwargs = {str(k): wire.decode(v, lambda item: callback(channel, call_id, item))
                  for k, v in (message.get("kwargs") or {}).items()}
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            out = fn(*args, **kwargs)
        library = _unavailable(out)
        if library:
            reply = {"op": "raised", "id": call_id, "type": "LibraryUnavailable", "builtin": "Exception",
                     "message": "", "frames": [], "library": str(library)[:120]}
        else:
            reply = {"op": "result", "id": call_id, "value": wire.encode(out), "args": [wire.encode(a) for a in args]}
    except OutOfTime:
        reply = {"op": "timed_out", "id": call_id}
    except BaseException as exc:    # noqa: BLE001 — whatever the student's code raised is an answer too
        try:
            reply = raised(call_id, exc)        # (its text is the student's code too: still within the time)
        except OutOfTime:
            reply = {"op": "timed_out", "id": call_id}
    alarm(0)
    return reply


def serve(channel, functions: dict) -> None:
    """Answer the checker's calls until it says quit (or goes)."""
    while True:
        try:
            message = channel.receive()
        except wire.Broken:
            return
        if message.get("op") == "quit":
            return
        if message.get("op") == "call":         # (a late reply to a callback of a call that ran out of time: skipped)
            reply = answer(channel, message, functions)
            try:
                channel.send(reply)
            except wire.Broken:
                return


def refuse_new_users() -> None:
    """No user namespace of its own for the hand-in (seccomp.no_new_users), installed before any of its code runs;
    where the kernel refuses the filter, the sandbox's other walls still stand."""
    code = seccomp.no_new_users()
    try:
        if code is not None:
            seccomp.install(code)
    except OSError:
        pass


def copy_cache(source: str) -> None:
    """The grader's compiled engine (numba's cache, bound read-only at `source`) copied where numba looks here."""
    try:
        from rbcourse.engine import jit
        target = jit.cache_folder()
        if target is None or not os.path.isdir(source):
            return
        for name in os.listdir(source):
            if name.endswith((".nbi", ".nbc", ".sha256")):
                shutil.copyfile(os.path.join(source, name), os.path.join(target, name))
    except Exception:       # noqa: BLE001 — without it the engine compiles, as anywhere
        pass


def _language(mode: str, default: str) -> str:
    """The language the notebook left the checks in: the library's (mode "run"), or the one the stand-in noted."""
    module = sys.modules.get("rbcourse.workbook.language" if mode == "run" else "rbcourse")
    try:
        return str(module.current())[:8]
    except BaseException:   # noqa: BLE001 — no such module loaded, or replaced by the notebook: its declared one
        return default


def main(argv=None) -> int:
    mode, read_fd, write_fd, limits = (argv or sys.argv[1:])[:4]
    set_limits(json.loads(limits))
    refuse_new_users()
    channel = wire.Channel(int(read_fd), int(write_fd), receives=wire.MAX_NOTEBOOK)   # its notebook: a big frame
    start = channel.receive()
    if start.get("cache"):
        copy_cache(start["cache"])
    try:
        import importlib
        importlib.import_module("rbcourse.workbook.language").langue(start.get("language", "en"))
    except BaseException:       # noqa: BLE001 — no rbcourse at all: the checks speak the checker's guess
        pass

    from traitlets.config import Config
    from IPython.core.interactiveshell import InteractiveShell
    config = Config()
    config.HistoryManager.enabled = False
    shell = InteractiveShell.instance(config=config)
    signal.signal(signal.SIGALRM, _out_of_time)
    errors, interrupted = run_cells(shell, [str(s) for s in start.get("cells", [])], float(start.get("seconds", 60)))

    functions = {}
    called = getattr(sys.modules.get("rbcourse"), "CALLED", None) if mode == "serve" else None
    for name in start.get("names", []):
        obj = shell.user_ns.get(name)
        if obj is None and isinstance(called, dict):
            obj = called.get(name)
        if obj is not None:
            functions[name] = obj
    channel.send({"op": "cells", "errors": errors, "interrupted": interrupted,
                  "language": _language(mode, start.get("language", "en")),
                  "functions": {name: describe(obj) for name, obj in functions.items()}})
    if mode == "serve":
        serve(channel, functions)
    return 0


if __name__ == "__main__":
    os._exit(main())
