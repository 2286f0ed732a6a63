"""The system calls a hand-in's sandbox refuses: those that let two sandboxes signal each other through something the
kernel shares between them, whatever the files they see (a read-only file of /usr is the same file in every sandbox).

    program() -> bytes | None      the filter, as the compiled BPF program bubblewrap loads (bwrap --seccomp FD);
                                   None on a processor it is not written for (then there is no filter: grading.md)

Refused (the call fails, as it would where the feature is missing; everything else is allowed):

- file locks, on any file, even one opened read-only: flock, and fcntl's F_GETLK/F_SETLK/F_SETLKW, the OFD locks
  (F_OFD_*), leases (F_SETLEASE, F_GETLEASE), directory notifications (F_NOTIFY) — ENOLCK;
- watches on files: inotify, fanotify — ENOSYS (a library that watches files falls back to reading them);
- the kernel's key rings (add_key, request_key, keyctl: a user's key ring is shared by all its processes), the page
  cache's state (cachestat, and preadv2/pwritev2, whose RWF_NOWAIT tells whether a file's page is cached),
  io_uring, perf_event_open, userfaultfd, bpf — ENOSYS;
- any call through another system-call table than the machine's own (x86-64's 32-bit and x32 tables) — ENOSYS.

A timing channel (how busy the processors are) is not closed by this: the grader never runs a process that has
the library while a checked one runs (runner.py).
"""
from __future__ import annotations

import errno
import platform
import struct

# classic BPF, as seccomp reads it (linux/filter.h, linux/seccomp.h)
LD_W_ABS, JEQ_K, JGE_K, RET_K = 0x20, 0x15, 0x35, 0x06
ALLOW, ERRNO = 0x7FFF0000, 0x00050000
NR, ARCH, ARG1 = 0, 4, 24          # offsets in struct seccomp_data: nr, arch, args[1] (its low 32 bits)

LOCKS = {"F_GETLK": 5, "F_SETLK": 6, "F_SETLKW": 7, "F_OFD_GETLK": 36, "F_OFD_SETLK": 37, "F_OFD_SETLKW": 38,
         "F_SETLEASE": 1024, "F_GETLEASE": 1025, "F_NOTIFY": 1026}
"""fcntl's commands that lock, lease or watch a file."""

TABLES = {
    "x86_64": {"arch": 0xC000003E, "x32": 0x40000000, "fcntl": 72, "flock": 73,
               "refused": {"inotify_init": 253, "inotify_init1": 294, "fanotify_init": 300, "add_key": 248,
                           "request_key": 249, "keyctl": 250, "cachestat": 451, "preadv2": 327, "pwritev2": 328,
                           "io_uring_setup": 425, "io_uring_enter": 426, "io_uring_register": 427,
                           "perf_event_open": 298, "userfaultfd": 323, "bpf": 321}},
    "aarch64": {"arch": 0xC00000B7, "x32": None, "fcntl": 25, "flock": 32,
                "refused": {"inotify_init1": 26, "fanotify_init": 262, "add_key": 217, "request_key": 218,
                            "keyctl": 219, "cachestat": 451, "preadv2": 286, "pwritev2": 287, "io_uring_setup": 425,
                            "io_uring_enter": 426, "io_uring_register": 427, "perf_event_open": 241,
                            "userfaultfd": 282, "bpf": 280}},
}
"""Each processor's system-call numbers (its own table: Linux's unistd headers)."""


def _op(code: int, k: int, jt: int = 0, jf: int = 0) -> bytes:
    return struct.pack("=HBBI", code, jt, jf, k)


def program(machine: str | None = None) -> bytes | None:
    """The filter for `machine` (platform.machine()'s name; default this one), or None if it has no table here."""
    table = TABLES.get({"amd64": "x86_64", "arm64": "aarch64"}.get(m := (machine or platform.machine()).lower(), m))
    if table is None:
        return None
    refuse = lambda code: _op(RET_K, ERRNO | code)                  # noqa: E731
    ops = [_op(LD_W_ABS, ARCH), _op(JEQ_K, table["arch"], 1, 0), refuse(errno.ENOSYS), _op(LD_W_ABS, NR)]
    if table["x32"] is not None:
        ops += [_op(JGE_K, table["x32"], 0, 1), refuse(errno.ENOSYS)]
    ops += [_op(JEQ_K, table["flock"], 0, 1), refuse(errno.ENOLCK)]
    for number in table["refused"].values():
        ops += [_op(JEQ_K, number, 0, 1), refuse(errno.ENOSYS)]
    ops += [_op(JEQ_K, table["fcntl"], 1, 0), _op(RET_K, ALLOW), _op(LD_W_ABS, ARG1)]
    for command in LOCKS.values():
        ops += [_op(JEQ_K, command, 0, 1), refuse(errno.ENOLCK)]
    ops.append(_op(RET_K, ALLOW))
    return b"".join(ops)
