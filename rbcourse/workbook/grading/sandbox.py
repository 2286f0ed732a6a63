"""Where a hand-in's process runs: in a bubblewrap sandbox (Debian's `bubblewrap`, the `bwrap` command), or —
with `--no-sandbox` only — as a plain process of its own.

    missing() -> None, or why there is no sandbox here and how to install it (one line)
    start(mode, limits, scratch, sandboxed=True, cache=None) -> Process (its channel, stop(), the tail of stderr)

Inside the sandbox (every namespace of its own: no network, its own process ids, its own hostname and IPC):
- an unprivileged user: uid 65534, no capability, no new privileges (setuid files do nothing).  When the
  grader is root, bwrap builds the sandbox, then `setpriv` drops to uid 65534 and `unshare --user` gives it a
  user namespace of its own (so that its process limit counts its own processes only); otherwise bwrap's own
  user namespace does both (--uid 65534);
- what it sees of the machine (layout.py): read-only, /usr, /etc/fonts, and under /grading Python's installation and
  its packages (no host path is seen inside), the grading files the process runs (worker.py, wire.py, seccomp.py),
  and in mode "run" the package rbcourse (/grading/rbcourse); in mode "serve" the package is not there at all
  (standin.py is /grading/rbcourse instead, an installed copy is hidden); writable, a private tmpfs /tmp of
  layout.TMPFS bytes (HOME is /tmp/home, the working folder /tmp/handin);
- nothing else: not SUBMISSIONS, not the other hand-ins, not the solution, not the outputs, not the grader's
  environment (--clearenv: only ENVIRONMENT and a few RBCOURSE_* / NUMBA_* settings), not its processes;
- no file lock, file watch, key ring or page-cache probe (seccomp.py: the system calls that would let two sandboxes
  signal each other through a file they both see, read-only as it is), and no user namespace of its own;
- the worker's own limits (worker.set_limits): memory, CPU seconds, file size, processes, open files; and, where
  the grader is root and the kernel's control groups can be written, memory, processes and processor time of the
  whole sandbox (cgroups.py);
- when the grader ends, or is killed, so does the sandbox (--die-with-parent); when the sandbox's first
  process ends, every process left in it is killed by the kernel (it is the init of its PID namespace).
"""
from __future__ import annotations

import json
import os
import select
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from . import cgroups, layout, seccomp, wire

HERE = Path(__file__).resolve().parent
UID = 65534
ENVIRONMENT = {"HOME": "/tmp/home", "TMPDIR": "/tmp", "LANG": "C.UTF-8", "MPLBACKEND": "Agg",
               "MPLCONFIGDIR": "/tmp/home/.matplotlib", "IPYTHONDIR": "/tmp/home/.ipython", "PYTHONHASHSEED": "0",
               "PYTHONDONTWRITEBYTECODE": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
               "MKL_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1"}
PASSED = ("RBCOURSE_QUICK",)
INSTALL = ("install bubblewrap (Debian, Ubuntu: sudo apt-get install bubblewrap; Fedora: sudo dnf install "
           "bubblewrap), or grade unprotected with --no-sandbox")


def _root() -> bool:
    return os.geteuid() == 0


def missing() -> str | None:
    """None when a sandbox can be made here; else why not, and how to get one (one line)."""
    tools = ["bwrap"] + (["setpriv", "unshare"] if _root() else [])
    absent = [t for t in tools if shutil.which(t) is None]
    if absent:
        return f"the sandbox tool {'bubblewrap (bwrap)' if 'bwrap' in absent else ' and '.join(absent)} is not " \
               f"installed: {INSTALL if 'bwrap' in absent else 'install util-linux'}"
    try:
        probe = python("run", "", timeout=60)
    except (OSError, subprocess.TimeoutExpired) as err:
        return f"bwrap cannot start here ({type(err).__name__}: {err}): {INSTALL}"
    if probe.returncode != 0:
        why = " ".join(probe.stderr.split())[:200]
        return f"bwrap cannot make a sandbox here ({why or f'exit code {probe.returncode}'}): {INSTALL}"
    return None


def environment(home: str, tmp: str, python: Path | None = None) -> dict:
    """The hand-in's environment: ENVIRONMENT (with its own HOME and TMPDIR), PATH, and the few settings passed; in a
    sandbox (python: its interpreter there), Python's own libraries where the sandbox sees them."""
    env = {**ENVIRONMENT, "HOME": home, "TMPDIR": tmp, "MPLCONFIGDIR": f"{home}/.matplotlib",
           "IPYTHONDIR": f"{home}/.ipython",
           "PATH": f"{(python or Path(sys.executable)).parent}:/usr/bin:/bin"}
    if python is not None and not layout.inside(python, [Path("/usr")]):
        env["LD_LIBRARY_PATH"] = str(python.parent.parent / "lib")      # its libpython, moved with it
    env.update({k: v for k, v in os.environ.items()
                if k in PASSED or (k.startswith("NUMBA_") and k not in ("NUMBA_CACHE_DIR", "NUMBA_NUM_THREADS"))})
    return env


def worker_command(mode: str, worker_args: list[str], sandboxed: bool, grading: Path | None = None) -> list[str]:
    """The worker's command line: in a sandbox, its Python as the sandbox sees it, without site (-S: the worker adds
    the grader's package folders itself, as the sandbox sees them: -I would add the base Python's instead)."""
    if not sandboxed:
        return [sys.executable, "-I", str(grading / "worker.py"), *worker_args, "[]"]
    where = layout.places()
    sites = layout.sites(where)
    return [str(layout.interpreter(where)), "-I", "-S", str(layout.GRADING / "worker.py"), *worker_args, json.dumps(sites)]


def _bwrap(mode: str, cache, info_fd, command: list[str]) -> tuple[list[str], list[int]]:
    """The bwrap command line that runs `command` (staged: layout.Stage); and the file descriptors it reads (the
    seccomp filter, files' contents), to pass to it and close once it started."""
    filter_code, fds, staged = seccomp.program(), [], layout.stage(_root())
    if filter_code is not None:
        fds.append(layout.pipe(filter_code))
    env = []
    for k, v in environment("/tmp/home", "/tmp", layout.interpreter(layout.places())).items():
        env += ["--setenv", k, v]
    common = ["--die-with-parent", "--new-session", "--clearenv", *env, *layout.filesystem(mode, cache, fds, staged),
              "--chdir", "/tmp/handin"] + (["--info-fd", str(info_fd)] if info_fd is not None else []) \
        + (["--seccomp", str(fds[0])] if filter_code is not None else [])
    if _root():
        return staged.wrap(["bwrap", "--unshare-ipc", "--unshare-pid", "--unshare-net", "--unshare-uts", "--unshare-cgroup-try",
                *common, "--cap-add", "CAP_SETUID", "--cap-add", "CAP_SETGID", "--cap-add", "CAP_SETPCAP", "--",
                "setpriv", f"--reuid={UID}", f"--regid={UID}", "--clear-groups", "--nnp", "--inh-caps=-all",
                "--bounding-set=-all", "--", "unshare", "--user", "--map-current-user", "--"] + command), fds
    return staged.wrap(["bwrap", "--unshare-all", "--unshare-user", "--disable-userns", "--uid", str(UID), "--gid",
                        str(UID), *common, "--"] + command), fds


def python(mode: str, code: str, timeout: float | None = None, wait: bool = True):
    """`python -c code` in a sandbox of `mode` ("run": with the package; "serve": without), as a hand-in's process
    runs (its Python and packages, its filter; no limits): its CompletedProcess (output captured, text), or with
    wait=False the Popen (stdout and stderr piped).  For a probe of the sandbox (missing(), the tests)."""
    where = layout.places()
    sites = layout.sites(where)
    setup = f"import site, sys; sys.path.insert(0, {str(layout.GRADING)!r}); [site.addsitedir(f) for f in {sites!r}]\n"
    command, fds = _bwrap(mode, None, None, [str(layout.interpreter(where)), "-I", "-S", "-c", setup + code])
    try:
        if not wait:
            return subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                    pass_fds=fds, text=True)
        return subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, timeout=timeout, pass_fds=fds,
                              text=True)
    finally:
        for fd in fds:
            os.close(fd)


@dataclass
class Process:
    """A hand-in's process: its channel, what bwrap said of it (info), where its stderr goes."""
    popen: subprocess.Popen
    channel: wire.Channel
    stderr: Path
    sandboxed: bool
    info: dict
    fds: tuple
    groups: list = field(default_factory=list)     # its control groups (cgroups.py), removed once it is gone
    stopped: bool | None = None       # None: running; False: killed, some of it maybe still there; True: gone
    cpu_seconds: float | None = None  # once gone: the processor time its processes used (None: not counted here)

    def stop(self, wait: float = 5.0) -> bool:
        """Kill it and everything it started; True once none of its processes is left (waited up to `wait` s).
        Only bwrap, this process's own child, is killed by its id (an id that cannot have been reused); the
        sandbox's first process dies with it (--die-with-parent), and with that one every process of the
        sandbox; any still found in its PID namespace is killed there.  Again: nothing more is done."""
        if self.stopped is None:
            self.kill()
            self.popen.wait()
            for fd in self.fds:
                os.close(fd)
            self.stopped = False
        end = time.monotonic() + wait
        while not self.stopped:
            left = self.alive()
            if not left:
                self.stopped = True
                self.cpu_seconds = cgroups.cpu_seconds(self.groups)
                cgroups.remove(self.groups)
            elif time.monotonic() > end:
                break
            else:
                for pid in left if self.sandboxed else ():
                    try:
                        os.kill(pid, signal.SIGKILL)
                    except (ProcessLookupError, PermissionError):
                        pass
                time.sleep(0.01)
        return self.stopped

    def kill(self) -> None:
        """Kill it (bwrap, and with it the sandbox), its channel left open: what it sent can still be read."""
        try:
            os.kill(self.popen.pid, signal.SIGKILL) if self.sandboxed else os.killpg(self.popen.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass

    def alive(self) -> list[int]:
        """The processes of this hand-in still there: in its PID namespace (sandboxed), else its process group."""
        ns = self.info.get("pid-namespace")
        if self.sandboxed:
            return processes_in(ns) if isinstance(ns, int) else []
        try:
            os.killpg(self.popen.pid, 0)
            return [self.popen.pid]
        except (ProcessLookupError, PermissionError):
            return []

    def tail(self, n: int = 600) -> str:
        try:
            with open(self.stderr, "rb") as f:
                f.seek(max(0, f.seek(0, 2) - n))
                return f.read().decode("utf-8", errors="replace")
        except OSError:
            return ""


def processes_in(namespace: int) -> list[int]:
    """The live processes whose PID namespace is `namespace` (its inode number); not the zombies (dead, their
    exit status not yet collected: the namespace's first process, reparented to the system's init)."""
    found = []
    for entry in os.scandir("/proc"):
        if entry.name.isdigit():
            try:
                if os.readlink(f"/proc/{entry.name}/ns/pid") == f"pid:[{namespace}]":
                    with open(f"/proc/{entry.name}/stat", "rb") as f:
                        if f.read().rpartition(b")")[2].split()[0] != b"Z":
                            found.append(int(entry.name))
            except (OSError, IndexError):
                pass
    return found


def start(mode: str, limits: dict, scratch: Path, sandboxed: bool = True, cache: Path | None = None) -> Process:
    """The worker in `mode` ("run" or "serve"), its stderr in scratch/MODE.stderr; its channel is ready."""
    to_child, from_parent = os.pipe()
    to_parent, from_child = os.pipe()
    info_read, info_write = os.pipe() if sandboxed else (None, None)
    stderr = scratch / f"{mode}.stderr"
    worker_args = [mode, str(to_child), str(from_child), json.dumps(limits)]
    fds = []
    groups = cgroups.made(limits.get("total_memory", 0), limits.get("processes", 0)) if sandboxed else []
    if sandboxed:
        command, fds = _bwrap(mode, cache, info_write, worker_command(mode, worker_args, True))
        command = cgroups.entering(groups, command)
        cwd, env = "/", {"PATH": os.environ.get("PATH", os.defpath)}
    else:
        grading, home = _unprotected_folders(mode, scratch)
        command = worker_command(mode, worker_args, False, grading)
        cwd, env = str(scratch / "handin"), environment(str(home), str(home))
    passed = tuple(fd for fd in (to_child, from_child, info_write, *fds) if fd is not None)
    try:
        with open(stderr, "wb") as err:
            popen = subprocess.Popen(command, cwd=cwd, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                     stderr=err, pass_fds=passed, start_new_session=True)
    except BaseException:
        cgroups.remove(groups, wait=0)           # nothing was started in them
        for fd in (to_parent, from_parent, info_read):
            if fd is not None:
                os.close(fd)
        raise
    finally:
        for fd in passed:
            os.close(fd)
    kept = (to_parent, from_parent) + ((info_read,) if info_read is not None else ())
    channel = wire.Channel(to_parent, from_parent, blocking=False, sends=wire.MAX_NOTEBOOK)
    process = Process(popen, channel, stderr, sandboxed, {}, kept, groups)
    if sandboxed:
        process.info = _info(info_read)
    return process


def _info(fd: int, seconds: float = 30.0) -> dict:
    """bwrap's JSON about the sandbox it made (child-pid, pid-namespace); {} if it said nothing."""
    data, end = b"", time.monotonic() + seconds
    while time.monotonic() < end and select.select([fd], [], [], max(0.0, end - time.monotonic()))[0]:
        chunk = os.read(fd, 4096)
        if not chunk:
            break
        data += chunk
        try:
            return json.loads(data.decode())
        except ValueError:
            continue
    return {}


def _unprotected_folders(mode: str, scratch: Path) -> tuple[Path, Path]:
    """--no-sandbox: the worker's files (and the stand-in) copied into scratch, its HOME and working folder."""
    grading = scratch / f"grading-{mode}"
    grading.mkdir()
    for name in ("worker.py", "wire.py", "seccomp.py"):
        shutil.copyfile(HERE / name, grading / name)
    if mode == "serve":
        (grading / "rbcourse").mkdir()
        shutil.copyfile(HERE / "standin.py", grading / "rbcourse" / "__init__.py")
    home = scratch / f"home-{mode}"
    home.mkdir()
    (scratch / "handin").mkdir(exist_ok=True)
    return grading, home
