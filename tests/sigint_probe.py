"""Run `python -m rbcourse ARGS…` and send it SIGINT at one chosen moment, from inside, so that the moment is exact
(tests/test_cli_interrupt.py): the command is the real one, run as `python -m rbcourse` runs it (runpy's
_run_module_as_main, sys.argv[0] "-m" while the package is imported), the signal the one Ctrl-C sends (os.kill of
the process, SIGINT), its handling the process's own.

    python tests/sigint_probe.py MOMENT [ARGS…]

MOMENT, when the signal is sent:
    import:NAME     as the module NAME starts being imported (e.g. rbcourse.bench.commands, imported before main())
    notify          inside LLVM's object-cache notify callback, called from C through ctypes while numba compiles
                    (a cold cache: NUMBA_CACHE_DIR an empty folder)
    getbuffer       inside LLVM's object-cache getbuffer callback (likewise)
    compile         as numba starts compiling a function (numba's "numba:compile" event)
    write:NAME      as the command writes a file whose name ends with NAME (pathlib and open)
    exit            at the end, in the first exit handler run (after the command has returned its code)

With NUMBA_CACHE_DIR empty, `notify` and `getbuffer` land in the first compile's callbacks.
"""
import atexit
import importlib.abc
import os
import runpy
import signal
import sys

sent = False


def interrupt(*_):
    """SIGINT to this process, once: as Ctrl-C sends it (the handler runs at the next bytecode of the main thread)."""
    global sent
    if not sent:
        sent = True
        os.kill(os.getpid(), signal.SIGINT)


class OnImport(importlib.abc.MetaPathFinder):
    def __init__(self, name):
        self.name = name

    def find_spec(self, name, path=None, target=None):
        if name == self.name:
            interrupt()
        return None                   # the normal finders import it


def on_callback(which: str):
    """Wrap numba's object-cache hook that LLVM's ctypes callback calls (llvmlite's _raw_object_cache_*), before numba
    hands the hooks to LLVM (at the codegen's creation, the first compile)."""
    from numba.core import codegen
    name = {"notify": "_object_compiled_hook", "getbuffer": "_object_getbuffer_hook"}[which]
    for cls in (codegen.JITCodeLibrary, codegen.CPUCodeLibrary):
        hook = cls.__dict__.get(name)
        if hook is None:
            continue
        original = hook.__func__

        def wrapped(klass, *args, _original=original):
            interrupt()
            return _original(klass, *args)
        setattr(cls, name, classmethod(wrapped))


def on_compile():
    from numba.core import event

    class Listener(event.Listener):
        def on_start(self, ev):
            interrupt()

        def on_end(self, ev):
            pass
    event.register("numba:compile", Listener())


def on_write(suffix: str):
    import builtins
    import io
    real_open = builtins.open

    def opening(file, mode="r", *args, **kwargs):
        if any(m in mode for m in "wax") and str(file).endswith(suffix):
            interrupt()
        return real_open(file, mode, *args, **kwargs)
    builtins.open = io.open = opening


def on_exit():
    """As the command ends (interrupts.leave: its code is known, its output written), in the first exit handler run."""
    from rbcourse.support import interrupts     # (the package is imported here, not by runpy: installed by __main__)
    closing = interrupts.closing

    def closing_then_interrupt():
        closing()
        atexit.register(interrupt)              # the last registered: the first run
    interrupts.closing = closing_then_interrupt


def main():
    moment, args = sys.argv[1], sys.argv[2:]
    kind, _, value = moment.partition(":")
    if kind == "import":
        sys.meta_path.insert(0, OnImport(value))
    elif kind in ("notify", "getbuffer"):
        on_callback(kind)
    elif kind == "compile":
        on_compile()
    elif kind == "write":
        on_write(value)
    elif kind == "exit":
        on_exit()
    else:
        raise SystemExit(f"unknown moment {moment!r}")
    sys.argv = ["-m", *args]          # as `python -m rbcourse ARGS…` starts: runpy's own entry point for -m
    runpy._run_module_as_main("rbcourse")


if __name__ == "__main__":
    main()
