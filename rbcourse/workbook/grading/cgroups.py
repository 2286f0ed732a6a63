"""A sandbox's processes limited together: `memory` bytes (what they hold, and what they write in their /tmp) and
`processes` processes in all, whatever each one's own limits (worker.set_limits: memory and processes each).

Done with the kernel's control groups (version 1: the memory and pids controllers), when the grader is root and
they can be written, as on this project's machines and CI; elsewhere only each process is limited, which bounds a
sandbox's memory by its processes' count times each one's.

    made(memory, processes) -> [folders]        a control group of each controller for one sandbox ([]: none here)
    entering(folders, command) -> command       the command, run from inside them (sh joins them, then execs it)
    remove(folders)                             once every process in them is gone
"""
from __future__ import annotations

import itertools
import os
import time
from pathlib import Path

MOUNTS = Path("/sys/fs/cgroup")
LIMITS = {"memory": ("memory.limit_in_bytes", "memory.memsw.limit_in_bytes"), "pids": ("pids.max",)}
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
    """A control group of its own under this process's, for each controller, limited to `memory` bytes and
    `processes` processes; [] when they cannot be made here (not root, no such controller, read-only)."""
    if os.geteuid() != 0:
        return []
    folders, values = [], {"memory": memory, "pids": processes}
    try:
        for controller, files in LIMITS.items():
            parent = _own(controller)
            if parent is None:
                raise OSError(f"no {controller} control group")
            folder = parent / f"rbcourse-grade-{os.getpid()}-{next(_made)}"
            folder.mkdir()
            folders.append(folder)
            for name in files:
                if (folder / name).exists():
                    (folder / name).write_text(str(values[controller]))
    except OSError:
        remove(folders, wait=0)
        return []
    return folders


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
