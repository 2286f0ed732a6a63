"""The system calls a hand-in's sandbox refuses: those that let two sandboxes signal each other through something the
kernel shares between them, whatever the files they see (a read-only file of /usr is the same file in every sandbox).

    program() -> bytes | None        the filter, as the compiled BPF program bubblewrap loads (bwrap --seccomp FD);
                                     None on a processor it is not written for (then there is no filter: grading.md)
    no_new_users() -> bytes | None   the filter the hand-in's process installs itself (install(code)), first thing

Refused (the call fails, as it would where the feature is missing; everything else is allowed):

- file locks, on any file, even one opened read-only: flock, and fcntl's F_GETLK/F_SETLK/F_SETLKW, the OFD locks
  (F_OFD_*), leases (F_SETLEASE, F_GETLEASE), directory notifications (F_NOTIFY) — ENOLCK;
- watches on files: inotify, fanotify — ENOSYS (a library that watches files falls back to reading them);
- the kernel's key rings (add_key, request_key, keyctl: a user's key ring is shared by all its processes), the page
  cache's state (cachestat, and preadv2/pwritev2, whose RWF_NOWAIT tells whether a file's page is cached),
  io_uring, perf_event_open, userfaultfd, bpf — ENOSYS;
- a new user namespace (unshare or clone with CLONE_NEWUSER — EPERM; clone3, whose flags a filter cannot read — ENOSYS,
  and the C library falls back to clone): inside one, a process would have every capability over what it makes there,
  the kernel's largest surface;
- any call through another system-call table than the machine's own (x86-64's 32-bit and x32 tables) — ENOSYS.

A timing channel (how busy the processors are) is not closed by this: the grader never runs a process that has
the library while a checked one runs (runner.py).
"""
from __future__ import annotations

import errno
import platform
import struct

# classic BPF, as seccomp reads it (linux/filter.h, linux/seccomp.h)
LD_W_ABS, JEQ_K, JGE_K, JSET_K, RET_K = 0x20, 0x15, 0x35, 0x45, 0x06
ALLOW, ERRNO = 0x7FFF0000, 0x00050000
NR, ARCH, ARG0, ARG1 = 0, 4, 16, 24    # offsets in struct seccomp_data: nr, arch, args[0], args[1] (low 32 bits)
CLONE_NEWUSER = 0x10000000

LOCKS = {"F_GETLK": 5, "F_SETLK": 6, "F_SETLKW": 7, "F_OFD_GETLK": 36, "F_OFD_SETLK": 37, "F_OFD_SETLKW": 38,
         "F_SETLEASE": 1024, "F_GETLEASE": 1025, "F_NOTIFY": 1026}
"""fcntl's commands that lock, lease or watch a file."""

TABLES = {
    "x86_64": {"arch": 0xC000003E, "x32": 0x40000000, "fcntl": 72, "flock": 73, "new_user": (272, 56),
               "clone3": 435, "refused": {"inotify_init": 253, "inotify_init1": 294, "fanotify_init": 300, "add_key": 248,
                           "request_key": 249, "keyctl": 250, "cachestat": 451, "preadv2": 327, "pwritev2": 328,
                           "io_uring_setup": 425, "io_uring_enter": 426, "io_uring_register": 427,
                           "perf_event_open": 298, "userfaultfd": 323, "bpf": 321}},
    "aarch64": {"arch": 0xC00000B7, "x32": None, "fcntl": 25, "flock": 32, "new_user": (97, 220),
                "clone3": 435, "refused": {"inotify_init1": 26, "fanotify_init": 262, "add_key": 217, "request_key": 218,
                            "keyctl": 219, "cachestat": 451, "preadv2": 286, "pwritev2": 287, "io_uring_setup": 425,
                            "io_uring_enter": 426, "io_uring_register": 427, "perf_event_open": 241,
                            "userfaultfd": 282, "bpf": 280}},
}
"""Each processor's system-call numbers (its own table: Linux's unistd headers); new_user: unshare's and clone's,
whose first argument holds the flags."""


def _op(code: int, k: int, jt: int = 0, jf: int = 0) -> bytes:
    return struct.pack("=HBBI", code, jt, jf, k)


def _table(machine: str | None) -> dict | None:
    name = (machine or platform.machine()).lower()
    return TABLES.get({"amd64": "x86_64", "arm64": "aarch64"}.get(name, name))


def _start(table: dict) -> list[bytes]:
    """The filter's first instructions: another table than the machine's refused, then the call's number loaded."""
    ops = [_op(LD_W_ABS, ARCH), _op(JEQ_K, table["arch"], 1, 0), _refuse(errno.ENOSYS), _op(LD_W_ABS, NR)]
    if table["x32"] is not None:
        ops += [_op(JGE_K, table["x32"], 0, 1), _refuse(errno.ENOSYS)]
    return ops


def _refuse(code: int) -> bytes:
    return _op(RET_K, ERRNO | code)


def program(machine: str | None = None) -> bytes | None:
    """The filter bwrap installs (--seccomp), for `machine` (platform.machine()'s name; default this one): the channels
    (locks, watches, key rings, the page cache, …); None if the machine has no table here."""
    table = _table(machine)
    if table is None:
        return None
    ops = _start(table) + [_op(JEQ_K, table["flock"], 0, 1), _refuse(errno.ENOLCK)]
    for number in table["refused"].values():
        ops += [_op(JEQ_K, number, 0, 1), _refuse(errno.ENOSYS)]
    ops += [_op(JEQ_K, table["fcntl"], 1, 0), _op(RET_K, ALLOW), _op(LD_W_ABS, ARG1)]
    for command in LOCKS.values():
        ops += [_op(JEQ_K, command, 0, 1), _refuse(errno.ENOLCK)]
    ops.append(_op(RET_K, ALLOW))
    return b"".join(ops)


def no_new_users(machine: str | None = None) -> bytes | None:
    """The filter the hand-in's process installs itself, first thing (worker.py: once the sandbox's own user namespace
    is made, which needs the very call it refuses): no new user namespace (unshare, clone with CLONE_NEWUSER; clone3)."""
    table = _table(machine)
    if table is None:
        return None
    ops = _start(table) + [_op(JEQ_K, table["clone3"], 0, 1), _refuse(errno.ENOSYS)]
    for number in table["new_user"]:           # unshare / clone with CLONE_NEWUSER: EPERM
        ops += [_op(JEQ_K, number, 0, 4), _op(LD_W_ABS, ARG0), _op(JSET_K, CLONE_NEWUSER, 0, 1),
                _refuse(errno.EPERM), _op(RET_K, ALLOW)]
    ops.append(_op(RET_K, ALLOW))
    return b"".join(ops)


def install(code: bytes) -> None:
    """Install the filter `code` on this process and every process it starts, for good (no new privileges first:
    the kernel requires it).  OSError if the kernel refuses."""
    import ctypes
    libc = ctypes.CDLL(None, use_errno=True)
    buffer = ctypes.create_string_buffer(code, len(code))

    class Program(ctypes.Structure):
        _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.c_void_p)]
    fprog = Program(len(code) // 8, ctypes.addressof(buffer))
    for args in ((38, 1, 0, 0, 0), (22, 2, ctypes.addressof(fprog), 0, 0)):   # PR_SET_NO_NEW_PRIVS, PR_SET_SECCOMP
        if libc.prctl(*[ctypes.c_ulong(a) for a in args]) != 0:
            raise OSError(ctypes.get_errno(), "the seccomp filter cannot be installed")
