"""Two sandboxes share nothing they can write, lock, watch or signal (issue 44, item 1): a channel of each kind is
planted between two sandboxes running at the same time — a sender that has the library, a receiver that has not —
and carries nothing; host paths are not seen inside; and a class is graded so that no process with the library runs
while a checked one does (the timing of a shared resource carries nothing either)."""
import json
import os
import sys
import shutil
import tempfile
import threading
import time
from pathlib import Path

import pytest

from rbcourse.workbook.grading import plan, sandbox

pytestmark = pytest.mark.skipif(shutil.which("bwrap") is None, reason="bubblewrap (bwrap) is not installed: the "
                                "grader refuses to run without its sandbox (CI installs it)")
ROOT = Path(__file__).resolve().parents[2]
SOLUTION = ROOT / "notebooks" / "solutions" / "01_exercise_euler.ipynb"
SHARED = "/usr/bin/env"                 # a read-only file every sandbox sees


def pair(send: str, receive: str, settle: float = 1.5) -> dict:
    """Run `send` in a "run" sandbox (it has rbcourse) and, while it still runs, `receive` in a "serve" sandbox;
    the receiver's last line of output, as JSON."""
    sender = sandbox.python("run", "import time\n" + send + "\nprint('sent', flush=True)\ntime.sleep(30)", wait=False)
    try:
        lines = iter(sender.stdout.readline, "")
        assert "sent" in (line.strip() for line in lines), sender.stderr.read()
        time.sleep(settle)
        got = sandbox.python("serve", receive, timeout=60)
        assert got.returncode == 0, got.stderr[-2000:]
        return json.loads(got.stdout.strip().splitlines()[-1])
    finally:
        sender.kill()
        sender.wait()


def test_a_file_lock_on_a_shared_read_only_file_carries_nothing():
    send = ("import fcntl, errno, json\nf = open(%r, 'rb')\nout = {}\n"
            "for name, call in [('flock', lambda: fcntl.flock(f, fcntl.LOCK_EX)),"
            " ('posix', lambda: fcntl.lockf(f, fcntl.LOCK_SH, 1, 7)),"
            " ('ofd', lambda: fcntl.fcntl(f, 37, b'\\0' * 32))]:\n"
            "    try:\n        call(); out[name] = 'locked'\n"
            "    except OSError as e:\n        out[name] = errno.errorcode[e.errno]\n"
            "print(json.dumps(out))" % SHARED)
    receive = ("import fcntl, errno, json\nf = open(%r, 'rb')\nout = {}\n"
               "try:\n    fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB); out['flock'] = 'free'\n"
               "except OSError as e:\n    out['flock'] = errno.errorcode[e.errno]\n"
               "try:\n    out['getlk'] = repr(fcntl.fcntl(f, fcntl.F_GETLK, b'\\1\\0' + b'\\0' * 30))\n"
               "except OSError as e:\n    out['getlk'] = errno.errorcode[e.errno]\n"
               "print(json.dumps(out))" % SHARED)
    sent = sandbox.python("run", send, timeout=60)
    assert json.loads(sent.stdout.strip().splitlines()[-1]) == {"flock": "ENOLCK", "posix": "ENOLCK", "ofd": "ENOLCK"}
    got = pair(send, receive)
    assert got == {"flock": "ENOLCK", "getlk": "ENOLCK"}     # no lock is taken, none can be seen


def test_file_watches_key_rings_and_the_page_cache_are_refused():
    probe = ("import ctypes, errno, json, os\nlibc = ctypes.CDLL(None, use_errno=True)\nout = {}\n"
             "def call(name, *args):\n    r = getattr(libc, name)(*args)\n"
             "    out[name] = 'ok' if r >= 0 else errno.errorcode[ctypes.get_errno()]\n"
             "call('inotify_init1', 0)\n"
             "call('syscall', 248, b'user', b'k', b'v', 1, -3)\n"                    # add_key on x86-64
             "fd = os.open(%r, os.O_RDONLY)\n"
             "try:\n    os.preadv(fd, [bytearray(16)], 0, os.RWF_NOWAIT); out['preadv2'] = 'ok'\n"
             "except OSError as e:\n    out['preadv2'] = errno.errorcode[e.errno]\n"
             "print(json.dumps(out))" % SHARED)
    got = sandbox.python("serve", probe, timeout=60)
    out = json.loads(got.stdout.strip().splitlines()[-1])
    assert out["inotify_init1"] == "ENOSYS"
    assert out["preadv2"] in ("ENOSYS", "ENOTSUP", "EOPNOTSUPP")       # (glibc's word for it) not ok, not EAGAIN
    if os.uname().machine == "x86_64":
        assert out["syscall"] == "ENOSYS"


def test_shared_memory_files_sockets_and_signals_carry_nothing():
    send = ("import os, signal, socket, ctypes, json\n"
            "libc = ctypes.CDLL(None, use_errno=True)\n"
            "shm = libc.shmget(4242, 4096, 0o1666)\n"                                # SysV, key 4242, created
            "for path in ('/dev/shm/rbcourse-channel', '/tmp/rbcourse-channel'):\n"   # POSIX shared memory, a file
            "    try:\n        open(path, 'w').write('answer')\n    except OSError:\n        pass\n"
            "s = socket.socket(socket.AF_UNIX); s.bind('\\0rbcourse-channel'); s.listen()\n"
            "for folder in ('/grading', '/usr', '/grading/env', '/'):\n"
            "    try:\n        open(folder + '/rbcourse-channel', 'w')\n    except OSError:\n        pass\n"
            "assert shm >= 0\n"
            "try:\n    os.kill(-1, signal.SIGKILL)\nexcept OSError:\n    pass\n")
    receive = ("import os, socket, ctypes, json\nlibc = ctypes.CDLL(None, use_errno=True)\nout = {}\n"
               "out['shm'] = libc.shmget(4242, 0, 0) >= 0\n"
               "out['files'] = [p for p in ('/dev/shm/rbcourse-channel', '/tmp/rbcourse-channel', "
               "'/grading/rbcourse-channel', '/rbcourse-channel') if os.path.exists(p)]\n"
               "s = socket.socket(socket.AF_UNIX)\n"
               "try:\n    s.connect('\\0rbcourse-channel'); out['socket'] = True\n"
               "except OSError:\n    out['socket'] = False\n"
               "print(json.dumps(out))")
    # the sender's kill(-1) reached nothing outside its sandbox: the receiver runs and answers after it
    assert pair(send, receive, settle=2.0) == {"shm": False, "files": [], "socket": False}


def test_host_paths_are_not_seen_inside():
    scratch = tempfile.mkdtemp(prefix="rbcourse-grade-")
    hosts = [str(ROOT), str(Path(tempfile.gettempdir()) / Path(scratch).name), str(Path.home()),
             str(Path(os.__file__).resolve().parent), str(Path(sys.prefix).resolve())]
    try:
        probe = ("import json, os, sys, numpy, rbcourse\n"
                 "places = [sys.executable, sys.prefix, numpy.__file__, rbcourse.__file__, os.getcwd()] + sys.path\n"
                 "hooks = [open(os.path.join(f, n)).read() for f in sys.path if os.path.isdir(f) for n in os.listdir(f)"
                 " if n.startswith('__editable__')]\n"
                 "assert not any(%r in h for h in hooks), hooks\n"
                 "table = open('/proc/self/mountinfo').read()\n"
                 "print(json.dumps({'places': places, 'seen': [p for p in %r if os.path.exists(p)],\n"
                 "                  'named': [p for p in %r if p in table]}))"
                  % (str(ROOT), hosts, hosts))
        got = sandbox.python("run", probe, timeout=60)
        assert got.returncode == 0, got.stderr[-2000:]
        out = json.loads(got.stdout.strip().splitlines()[-1])
    finally:
        os.rmdir(scratch)
    assert out["seen"] == []
    if os.geteuid() == 0:                     # staged (layout.Stage): not even the mount table names a host folder
        assert out["named"] == [], out["named"]
    assert all(p.startswith(("/grading", "/usr", "/tmp")) for p in out["places"] if "/" in p), out["places"]


def _parent(pid: str) -> str:
    try:
        return Path(f"/proc/{pid}/stat").read_bytes().rpartition(b")")[2].split()[1].decode()
    except (OSError, IndexError):
        return "0"


def _modes_alive(ancestor: int) -> set:
    """The modes ("run", "serve") of the hand-in workers alive now that descend from the process `ancestor`."""
    modes = set()
    for entry in os.scandir("/proc"):
        if entry.name.isdigit():
            try:
                argv = Path(f"/proc/{entry.name}/cmdline").read_bytes().split(b"\0")
            except OSError:
                continue
            if b"/grading/worker.py" not in argv:
                continue
            pid = entry.name
            while pid not in ("0", "1", str(ancestor)):
                pid = _parent(pid)
            if pid == str(ancestor):                # (the last one: bwrap's command line binds it first)
                at = len(argv) - 1 - argv[::-1].index(b"/grading/worker.py")
                modes.add(argv[at + 1].decode() if len(argv) > at + 1 else "?")
    return modes


def test_no_process_with_the_library_runs_while_a_checked_one_does(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    for name in ("ann", "bob", "cy"):
        shutil.copyfile(SOLUTION, subs / f"{name}.ipynb")
    the_plan = plan.check_arguments(subs, tmp_path / "out" / "grades.csv", timeout=120,
                                    feedback=tmp_path / "out" / "feedback", workers=2)
    seen, done = [], threading.Event()

    def watch():
        while not done.is_set():
            seen.append(frozenset(_modes_alive(os.getpid())))
            time.sleep(0.02)
    watcher = threading.Thread(target=watch)
    watcher.start()
    try:
        graded, _ = plan.grade(the_plan, progress=None)
    finally:
        done.set()
        watcher.join()
    assert [g.status for g in graded] == ["ok"] * 3
    assert {"serve"} in seen and {"run"} in seen, set(seen)      # both were watched
    assert not [s for s in seen if {"run", "serve"} <= s]       # never at the same time


def test_the_filter_is_written_for_x86_64_and_aarch64_only():
    from rbcourse.workbook.grading import seccomp
    for machine in ("x86_64", "aarch64", "arm64", "AMD64"):
        code = seccomp.program(machine)
        assert code is not None and len(code) % 8 == 0 and len(code) // 8 < 4096     # BPF_MAXINSNS
    assert seccomp.program("mips") is None and seccomp.program("riscv64") is None


def test_a_hand_in_cannot_make_a_user_namespace_of_its_own():
    """Inside one it would have every capability over what it makes there (mounts, …): the worker refuses it to itself
    before any cell runs (seccomp.no_new_users)."""
    from rbcourse.workbook.grading import runner, submissions
    cell = ("import ctypes, errno, subprocess\nlibc = ctypes.CDLL(None, use_errno=True)\n"
            "r = libc.unshare(0x10000000)\nwhy = errno.errorcode.get(ctypes.get_errno())\n"
            "tool = subprocess.run(['unshare', '--user', '--map-root-user', 'true'], capture_output=True).returncode\n"
            "raise RuntimeError(f'unshare {r} {why}, the tool {tool}')")
    nb = {"cells": [{"cell_type": "code", "source": cell, "metadata": {}, "outputs": [], "execution_count": None}],
          "metadata": {}, "nbformat": 4, "nbformat_minor": 5}
    g = runner.grade_one(submissions.Handin("ann", "ann.ipynb", json.dumps(nb)), runner.Settings(plan.MIN_TIMEOUT * 4))
    assert [e["error"] for e in g.cell_errors] == ["RuntimeError: unshare -1 EPERM, the tool 1"], g.note


def test_no_copy_of_the_package_is_left_in_the_checked_run(tmp_path, monkeypatch):
    """A `pip install .` outside a venv puts a whole copy of rbcourse in the base Python's packages, which the sandbox
    mounts: the checked run ("serve") finds none, not even by its path (layout.package_copies)."""
    from rbcourse.workbook.grading import layout
    folder = tmp_path / "site-packages"
    (folder / "rbcourse").mkdir(parents=True)
    (folder / "rbcourse" / "__init__.py").write_text("REAL = True\n")
    (folder / "rbcourse-0.1.0.dist-info").mkdir()
    grader_s = layout.site_folders
    monkeypatch.setattr(layout, "site_folders", lambda: [*grader_s(), str(folder)])
    probe = ("import glob, json\n"
             "print(json.dumps(sorted(glob.glob('/grading/*/rbcourse*/*'))))")        # (a hidden folder is empty)
    served = json.loads(sandbox.python("serve", probe, timeout=60).stdout.strip().splitlines()[-1])
    assert not [p for p in served if not p.startswith("/grading/rbcourse")], served      # (the stand-in's own)
    ran = json.loads(sandbox.python("run", probe, timeout=60).stdout.strip().splitlines()[-1])
    assert any(p.endswith("rbcourse/__init__.py") and not p.startswith("/grading/rbcourse") for p in ran), ran
