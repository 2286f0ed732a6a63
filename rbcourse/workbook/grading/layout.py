"""What a hand-in's sandbox sees of the machine: its file system, as bwrap's arguments (sandbox.py runs them).

    places() -> {host folder: where the sandbox sees it}   Python's installation and packages, under /grading
    seen(path, places) -> Path | None                      a host path as the sandbox sees it
    interpreter(places) -> Path                            the Python the sandbox runs
    filesystem(mode, cache, fds) -> [bwrap's arguments]    the whole view (see sandbox.py's docstring)
    site_folders() -> [str]                                the grader's package folders, in its order
"""
from __future__ import annotations

import os
import site
import sys
from pathlib import Path

import rbcourse

HERE = Path(__file__).resolve().parent
GRADING = Path("/grading")     # where the sandbox sees what the grader gives it
PACKAGE = Path(rbcourse.__file__).resolve().parent
TMPFS = 256 << 20


def _read_only_trees() -> list[Path]:
    """Python's installation and its packages: what the hand-in's process needs to run, read-only."""
    paths = {Path(sys.base_prefix), Path(sys.prefix), Path(sys.base_exec_prefix), Path(sys.exec_prefix)}
    paths |= {Path(p) for p in site_folders()}
    paths = {p.resolve() for p in paths if p.is_dir()}
    return sorted(p for p in paths if not any(q != p and q in p.parents for q in paths))


def site_folders() -> list[str]:
    """The grader's package folders (its venv's site-packages, the user's when Python reads it), in its order."""
    folders = list(site.getsitepackages())
    if site.ENABLE_USER_SITE and site.getusersitepackages() in sys.path:
        folders.append(site.getusersitepackages())
    return [f for f in folders if Path(f).is_dir()]


def inside(path: Path, trees) -> bool:
    return any(path == t or t in path.parents for t in trees)


def places() -> dict[Path, Path]:
    """{host folder: where the sandbox sees it} for the trees of _read_only_trees(): the system's (under /usr) where
    they are; Python's installation at /grading/python, the environment's (a venv) at /grading/env, any other at
    /grading/site-N — the host's folders (a checkout, a home, the grader's TMPDIR) are no business of the hand-in."""
    base, prefix = Path(sys.base_prefix).resolve(), Path(sys.prefix).resolve()
    out = {}
    for n, tree in enumerate(_read_only_trees()):
        if inside(tree, [Path("/usr")]):
            out[tree] = tree
        else:
            out[tree] = GRADING / ("python" if tree == base else "env" if tree == prefix else f"site-{n}")
    return out


def seen(path: Path, where: dict[Path, Path]) -> Path | None:
    """Where the sandbox sees the host's `path` (None: not at all)."""
    path = Path(path).resolve()
    for tree, place in where.items():
        if path == tree or tree in path.parents:
            return place / path.relative_to(tree)
    return None


def interpreter(where: dict[Path, Path]) -> Path:
    """The Python the sandbox runs: the grader's own interpreter (a venv's base one), as the sandbox sees it."""
    found = seen(Path(getattr(sys, "_base_executable", None) or sys.executable), where)
    return found if found is not None else Path(sys.executable)


def filesystem(mode: str, cache: Path | None, fds: list) -> list[str]:
    """bwrap's arguments for the sandbox's file system (see the module's docstring); the file descriptors they name
    are appended to fds (the caller passes them to bwrap, then closes them)."""
    # /proc, /dev and the private /tmp first: what is bound below lands on top of them
    args = ["--proc", "/proc", "--dev", "/dev", "--perms", "01777", "--size", str(TMPFS), "--tmpfs", "/tmp",
            "--perms", "0777", "--dir", "/tmp/home", "--perms", "0777", "--dir", "/tmp/handin"]
    made = {Path("/"), Path("/tmp"), Path("/tmp/home"), Path("/tmp/handin")}

    def folders(dest: Path):            # every folder above a mount point, readable by uid 65534
        for parent in reversed(dest.parents):
            if parent not in made:
                made.add(parent)
                args.extend(["--perms", "0755", "--dir", str(parent)])

    def bind(source, dest, how="--ro-bind"):
        folders(Path(dest))
        args.extend([how, str(source), str(dest)])

    for top in ("bin", "lib", "lib32", "lib64", "sbin"):
        p = Path("/") / top
        if p.is_symlink():
            args.extend(["--symlink", os.readlink(p), str(p)])
        elif p.is_dir():
            bind(p, p)
    bind("/usr", "/usr")
    if Path("/etc/fonts").is_dir():
        bind("/etc/fonts", "/etc/fonts")
    where = places()
    for tree, place in where.items():
        if place != tree:
            bind(tree, place)
    installed = seen(PACKAGE, where)
    if installed is not None and mode == "serve":
        args.extend(["--tmpfs", str(installed)])          # an installed copy of the package: hidden
    for folder in site_folders():                        # an editable install's hook (it names the checkout): empty
        for hook in Path(folder).glob("__editable__*rbcourse*"):
            if hook.is_file() and seen(hook, where) is not None:
                fds.append(pipe(b""))
                args.extend(["--perms", "0644", "--ro-bind-data", str(fds[-1]), str(seen(hook, where))])
    bind(HERE / "worker.py", GRADING / "worker.py")
    bind(HERE / "wire.py", GRADING / "wire.py")
    bind(HERE / "seccomp.py", GRADING / "seccomp.py")
    bind(HERE / "standin.py" if mode == "serve" else PACKAGE,
         GRADING / "rbcourse" / "__init__.py" if mode == "serve" else GRADING / "rbcourse")
    if cache is not None:
        bind(cache, GRADING / "numba-cache")
    return args


def pipe(data: bytes) -> int:
    """A pipe's read end holding `data` (a few hundred bytes at most: within the pipe's buffer), for bwrap to read."""
    read, write = os.pipe()
    os.write(write, data)
    os.close(write)
    return read
