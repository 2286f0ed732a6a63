"""A sandbox's processes limited together: `memory` bytes (what they hold, and what they write in their /tmp),
`processes` processes in all, and one processor's time at most, whatever each one's own limits (worker.set_limits:
memory and processes each) — and their processor time counted.

Done with the kernel's control groups (version 1: the memory, pids, cpu and cpuacct controllers), when the grader is
root and they can be written, as on this project's machines and CI; elsewhere only each process is limited, which
bounds a sandbox's memory by its processes' count times each one's.  The cpu controller shares the processors between
the sandboxes' groups, not between their processes: a sandbox of 60 busy processes gets no more of them than one of a
single process (a neighbour cannot slow a hand-in down by forking), and none gets more than CPUS processors.

    made(memory, processes) -> [folders]        a control group of each controller for one sandbox ([]: none here)
    entering(folders, command) -> command       the command, run from inside them (sh joins them, then execs it)
    cpu_seconds(folders) -> float | None        the processor time its processes used, in all (None: not counted)
    remove(folders)                             once every process in them is gone
"""
from __future__ import annotations

import itertools
import os
import time
from pathlib import Path

MOUNTS = Path("/sys/fs/cgroup")
LIMITS = {"memory": ("memory.limit_in_bytes", "memory.memsw.limit_in_bytes"), "pids": ("pids.max",),
          "cpu": ("cpu.cfs_period_us", "cpu.cfs_quota_us"), "cpuacct": ()}
OPTIONAL = ("cpu", "cpuacct")       # a kernel without them: the sandbox is still limited in memory and processes
PERIOD = 100_000                    # µs: the cpu controller's period, of which a sandbox gets CPUS periods' time
CPUS = 1
_made = itertools.count()


def _own(controller: str) -> Path | None:
    """The control group this process is in, for `controller` (version 1), as a folder; None if there is none."""
    try:
        lines = Path("/proc/self/cgroup").read_text().splitlines()
    except OSError:
        return None
    for line in lines:
        _, controllers, path = (line.split(":", 2) + ["", ""])[:3]
        if controller in controllers.split(","):
            folder = MOUNTS / controller / path.lstrip("/")
            return folder if (folder / "cgroup.procs").exists() else None
    return None


def made(memory: int, processes: int) -> list[Path]:
    """A control group of its own under this process's, for each controller, limited to `memory` bytes, `processes`
    processes and CPUS processors' time; [] when they cannot be made here (not root, no memory or pids controller,
    read-only)."""
    if os.geteuid() != 0:
        return []
    folders, values = [], {"memory.limit_in_bytes": memory, "memory.memsw.limit_in_bytes": memory,
                           "pids.max": processes, "cpu.cfs_period_us": PERIOD, "cpu.cfs_quota_us": CPUS * PERIOD}
    try:
        for controller, files in LIMITS.items():
            parent = _own(controller)
            if parent is None:
                if controller in OPTIONAL:
                    continue
                raise OSError(f"no {controller} control group")
            folder = parent / f"rbcourse-grade-{os.getpid()}-{next(_made)}"
            folder.mkdir()
            folders.append(folder)
            for name in files:
                if (folder / name).exists():
                    (folder / name).write_text(str(values[name]))
    except OSError:
        remove(folders, wait=0)
        return []
    return folders


def cpu_seconds(folders: list[Path]) -> float | None:
    """The processor time (s) the processes of these control groups used, in all; None where it is not counted."""
    for folder in folders:
        try:
            return int((folder / "cpuacct.usage").read_text()) / 1e9
        except (OSError, ValueError):
            continue
    return None


def entering(folders: list[Path], command: list[str]) -> list[str]:
    """`command`, run by sh after it joins the control groups (every process it starts is in them from its start)."""
    if not folders:
        return command
    return ["sh", "-c", 'while [ "$1" != -- ]; do echo $$ > "$1/cgroup.procs"; shift; done; shift; exec "$@"', "sh",
            *map(str, folders), "--", *command]


def remove(folders: list[Path], wait: float = 1.0) -> None:
    """Remove the control groups (empty once their processes are gone; a last one may linger a moment)."""
    end = time.monotonic() + wait
    for folder in folders:
        while True:
            try:
                folder.rmdir()
                break
            except FileNotFoundError:
                break
            except OSError:
                if time.monotonic() > end:
                    break
                time.sleep(0.01)
