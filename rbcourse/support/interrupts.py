"""Ctrl-C for the command line (python -m rbcourse): at any moment, the command's one line and exit code 130.

Python raises KeyboardInterrupt at the next bytecode its main thread runs after SIGINT.  Where that bytecode
runs decides what happens:

* in Python code of the command (its own, numpy's, numba's compiler passes): the exception unwinds, the command
  keeps what it finished (bench, stability) and __main__.main says its one line;
* inside a ctypes callback: numba's compiler gives LLVM two Python callbacks (llvmlite's object cache,
  ExecutionEngine._raw_object_cache_notify and _raw_object_cache_getbuffer, called from C while LLVM compiles a
  module).  An exception raised there cannot cross LLVM's C frames: ctypes prints it ("Exception ignored on
  calling ctypes callback function", then its traceback — the 16 lines seen during `explore`), drops it, and the
  command runs on to its end as if no Ctrl-C had come (or, a callback cut short, LLVM reads a buffer it did not
  finish: a crash);
* where Python prints an exception instead of raising it (a finaliser, an exit handler, the interpreter's
  teardown, any other callback): "Exception ignored in …" and a traceback;
* before the command's code runs (Python importing the package and its modules): a traceback of the import.

So a command's process handles SIGINT here (install_if_command from the package's import under `python -m`, or
install; then running(prog) once its arguments are read, said() once its line is written, closing() as main
returns and at leave):

    before running: the command's line at once ("python -m rbcourse COMMAND: interrupted"), exit code 130 —
                    nothing has been computed or written yet;
    running:        KeyboardInterrupt raised where Python can unwind it, not inside llvmlite (any frame of the main
                    thread's stack in the llvmlite package: a callback, or a call into LLVM: a compile is cut at
                    its next return into Python), nor while a KeyboardInterrupt is being handled (the command
                    stopping: the partial files of bench and stability, its line).  The Ctrl-C stays pending
                    until the command says it (said()), SIGINT sent again every RETRY s by a thread meanwhile: a
                    KeyboardInterrupt that code beneath drops (numba's dispatcher, typing a call's arguments in C,
                    clears the error it gets), or that lands where Python cannot raise it (sys.unraisablehook: not
                    printed), is raised again;
    closing:        held, then said after the exit handlers (the last of them): the command's line and code 130
                    (nothing more once the command has said it).

Outside the command line (a notebook, a script) nothing here is installed: Python's own handler, and simulate's
deferred_interrupt (forcing.py), apply.
"""
from __future__ import annotations

import atexit
import os
import signal
import sys
import threading
import time

PROG = "python -m rbcourse"
RETRY = 0.05            # s between two SIGINTs while one is pending (held inside llvmlite, or dropped)

BEFORE, RUNNING, CLOSING = "before", "running", "closing"


class _State:
    phase = BEFORE
    prog = PROG          # the command's name, for its one line
    pending = False      # a Ctrl-C came that the command has not said yet
    said = False         # the command said it was interrupted
    retrying = None      # the thread sending SIGINT again while one is pending
    previous_hook = None


state = _State()


def install(argv=None):
    """Handle SIGINT as the module docstring says, from now on (the phase: before running).  argv: the
    command line's arguments (default sys.argv[1:]), whose first word names the command in the early line."""
    argv = sys.argv[1:] if argv is None else argv
    word = next(iter(argv), "")
    if word.isidentifier():
        state.prog = f"{PROG} {word}"
    if threading.current_thread() is not threading.main_thread():
        return
    signal.signal(signal.SIGINT, _handler)
    if state.previous_hook is None:
        state.previous_hook = sys.unraisablehook
        sys.unraisablehook = _unraisable
        atexit.register(_at_exit)           # registered first: run last, after every other exit handler


def install_if_command():
    """install(), if this is `python -m rbcourse` importing the package (runpy's _run_module_as_main("rbcourse")
    is on the stack, sys.argv[0] still "-m"): Ctrl-C is the command line's from the package's first import on,
    before Python reaches __main__.py.  Any other import of the package (a notebook, a test) installs nothing."""
    if sys.argv[:1] != ["-m"]:
        return
    frame = sys._getframe(1)
    while frame is not None:
        if frame.f_code.co_name == "_run_module_as_main" and frame.f_locals.get("mod_name") == "rbcourse":
            install()
            return
        frame = frame.f_back


def running(prog: str):
    """The command runs (its arguments are read): a Ctrl-C is a KeyboardInterrupt from now on."""
    state.prog = prog
    state.phase = RUNNING
    if state.pending:                       # came while the arguments were read: raised now, where it can be
        _resend()


def said():
    """The command has said it was interrupted (its one line is written): a Ctrl-C from now on is held, unsaid."""
    state.said = True
    state.pending = False
    state.phase = CLOSING


def closing():
    """The command is done (main returns, leave): a Ctrl-C from now on is held, and said after the exit
    handlers."""
    state.phase = CLOSING


def _at_exit():
    """The last exit handler: a Ctrl-C held while closing, that the command has not said, is said now (its line,
    exit code 130)."""
    if state.phase == CLOSING and state.pending and not state.said:
        _say_and_exit()


def line() -> str:
    return f"{state.prog}: interrupted"


def _handler(signum, frame):
    if state.phase == BEFORE:
        _say_and_exit()
    state.pending = True                    # until the command says it (said), or its end does (_at_exit)
    if state.phase == CLOSING:
        return
    _retry_later()
    if _stopping() or _inside_llvmlite(frame):
        return
    raise KeyboardInterrupt


def _stopping() -> bool:
    """Is a KeyboardInterrupt being handled (an except or finally block, an exit function, under it)?"""
    return isinstance(sys.exc_info()[1], KeyboardInterrupt)


def _say_and_exit():
    """Before the command runs: nothing to keep, its line and code 130 at once."""
    try:
        sys.stdout.flush()
    except (OSError, ValueError):
        pass
    try:
        os.write(2, (line() + "\n").encode())
    finally:
        os._exit(130)


def _inside_llvmlite(frame) -> bool:
    """Is a frame of the main thread's stack in llvmlite (a callback from LLVM, or a call into it)?"""
    module = sys.modules.get("llvmlite")
    if module is None or frame is None:
        return False
    folder = os.path.dirname(module.__file__) + os.sep
    while frame is not None:
        if frame.f_code.co_filename.startswith(folder):
            return True
        frame = frame.f_back
    return False


def _retry_later():
    """While the command runs and has not said its Ctrl-C: SIGINT again every RETRY s (a thread)."""
    if state.phase != RUNNING:
        return
    if state.retrying is None or not state.retrying.is_alive():
        state.retrying = threading.Thread(target=_retry, name="rbcourse-sigint", daemon=True)
        state.retrying.start()


def _retry():
    while state.pending and state.phase == RUNNING:
        time.sleep(RETRY)
        if state.pending and state.phase == RUNNING:
            _resend()


def _resend():
    os.kill(os.getpid(), signal.SIGINT)


def _unraisable(info):
    """A KeyboardInterrupt where Python cannot raise it: pending, raised again (not printed).  Anything else: as
    the hook before."""
    if isinstance(info.exc_value, KeyboardInterrupt) or (info.exc_type is not None
                                                          and issubclass(info.exc_type, KeyboardInterrupt)):
        state.pending = True                # it did not unwind: raised again where it can be
        _retry_later()
        return
    state.previous_hook(info)


def leave(code: int):
    """End the process with exit code `code` once a command is done: its exit handlers run (atexit: the live server
    closed, temporary folders removed, multiprocessing's children joined), its output is flushed, and the process
    ends there, without the interpreter's teardown — which frees every object and numba's machine code one by one,
    0.15-0.35 s of the demo's wall time for nothing anyone sees.  With a thread still running that a normal exit
    would wait for (not a daemon: tqdm's monitor is one), the normal exit."""
    closing()
    waited = [t for t in threading.enumerate() if t is not threading.main_thread() and not t.daemon and t.is_alive()]
    if waited or not isinstance(code, int):
        sys.exit(code)
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):       # a closed or broken pipe: nothing more to say
            pass
    os._exit(code)
