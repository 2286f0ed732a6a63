"""Ctrl-C at any moment of a command ends with its one line, `python -m rbcourse COMMAND: interrupted`, and exit
code 130 (rbcourse/support/interrupts.py) — never a traceback.  Once in about 30 tries a Ctrl-C landing in a numba
compile printed llvmlite's: "Exception ignored on calling ctypes callback function: <function
ExecutionEngine._raw_object_cache_notify …>", the KeyboardInterrupt dropped there, and the command ran on to exit
code 0.

Each moment is exact: tests/sigint_probe.py runs the command as `python -m rbcourse` does and sends the process
SIGINT from inside at that moment (while Python imports the package or a module, inside LLVM's callbacks into
Python during a cold compile — NUMBA_CACHE_DIR an empty folder —, as numba starts a compile, as a file is written,
in the exit handlers); one more is sent from outside, as Ctrl-C is, once the command says it compiles.  The
commands are quick ones (notebooks: no engine; compile and explore: interrupted at their first compile)."""
import os
import selectors
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from rbcourse.compiling import NOTICE

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")

PROBE = Path(__file__).with_name("sigint_probe.py")
EXPLORE = ["explore", "tennis_racket", "--methods", "rk4", "euler", "--dts", "0.05", "--t-end", "1"]
COMPILE = ["compile", "--methods", "euler"]


def environment(tmp_path: Path) -> dict:
    """An empty numba cache (every compile cold), no progress bars (stderr holds what the command says)."""
    cache = tmp_path / "numba_cache"
    cache.mkdir(exist_ok=True)
    return dict(os.environ, NUMBA_CACHE_DIR=str(cache), TQDM_DISABLE="1", PYTHONUNBUFFERED="1")


def default_sigint():
    signal.signal(signal.SIGINT, signal.SIG_DFL)     # a shell may start background jobs with SIGINT ignored


def said_interrupted(command: str, code: int, err: str):
    """Exit code 130 and, on stderr, the command's one line, after nothing but its notices of a compile."""
    lines = err.splitlines()
    assert code == 130, err
    assert lines and lines[-1] == f"python -m rbcourse {command}: interrupted", err
    notice = NOTICE["en"].split("(")[0]
    assert all(line.startswith(notice) for line in lines[:-1]), err          # no traceback, no "Exception ignored"


MOMENTS = [
    ("import:numpy", ["notebooks", "--to", "{tmp}/copies"]),                 # the package's own imports
    ("import:rbcourse.bench.commands", ["notebooks", "--to", "{tmp}/copies"]),   # __main__.py's, before main()
    ("import:rbcourse.workbook.copies", ["notebooks", "--to", "{tmp}/copies"]),  # the command's, in main()
    ("write:.ipynb", ["notebooks", "--to", "{tmp}/copies"]),
    ("exit", ["notebooks", "--to", "{tmp}/copies"]),                        # done: in the exit handlers
    ("notify", COMPILE),                                                    # LLVM's callbacks, a cold compile
    ("getbuffer", COMPILE),
    ("compile", COMPILE),                                                   # numba starts compiling
    ("notify", EXPLORE + ["--out", "{tmp}/out"]),
    ("compile", EXPLORE + ["--out", "{tmp}/out"]),
]


@pytest.mark.parametrize("moment, argv", MOMENTS, ids=[f"{m} {a[0]}" for m, a in MOMENTS])
def test_ctrl_c_at_this_moment_is_the_commands_one_line_and_exit_code_130(moment, argv, tmp_path):
    argv = [a.format(tmp=tmp_path) for a in argv]
    run = subprocess.run([sys.executable, str(PROBE), moment, *argv], capture_output=True, text=True, timeout=600,
                         env=environment(tmp_path), cwd=tmp_path, stdin=subprocess.DEVNULL, preexec_fn=default_sigint)
    said_interrupted(argv[0], run.returncode, run.stderr)
    if moment == "exit":                                                    # the command had done its work
        assert "14 copied" in run.stdout and len(list((tmp_path / "copies").rglob("*.ipynb"))) == 14


def test_ctrl_c_from_outside_during_a_cold_compile(tmp_path):
    """Ctrl-C as a terminal sends it, once the explorer says it compiles (the compile takes seconds then)."""
    proc = subprocess.Popen([sys.executable, "-m", "rbcourse", *EXPLORE, "--out", str(tmp_path / "out")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                            env=environment(tmp_path), cwd=tmp_path, preexec_fn=default_sigint)
    err = b""
    try:
        with selectors.DefaultSelector() as wait:
            wait.register(proc.stderr, selectors.EVENT_READ)
            deadline = time.monotonic() + 300
            while NOTICE["en"].split("(")[0].encode() not in err and time.monotonic() < deadline:
                if wait.select(timeout=1.0):
                    chunk = os.read(proc.stderr.fileno(), 4096)
                    if not chunk:
                        break
                    err += chunk
        assert proc.poll() is None, "the command ended before it compiled"
        proc.send_signal(signal.SIGINT)
        _, rest = proc.communicate(timeout=300)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    said_interrupted("explore", proc.returncode, (err + rest).decode())


def test_importing_the_package_leaves_ctrl_c_to_python():
    """Only `python -m rbcourse` handles Ctrl-C itself: a notebook, a script or a test importing the package (its
    command line's main too) keeps Python's own handler."""
    code = ("import signal, rbcourse, rbcourse.__main__; "
            "print(signal.getsignal(signal.SIGINT) is signal.default_int_handler)")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.stdout.strip() == "True", run.stderr
