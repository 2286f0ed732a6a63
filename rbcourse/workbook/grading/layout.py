"""What a hand-in's sandbox sees of the machine: its file system, as bwrap's arguments (sandbox.py runs them).

    places() -> {host folder: where the sandbox sees it}   Python's installation and packages, under /grading
    seen(path, places) -> Path | None                      a host path as the sandbox sees it
    interpreter(places) -> Path                            the Python the sandbox runs
    filesystem(mode, cache, fds, staged) -> [bwrap's args]  the whole view (see sandbox.py's docstring)
    stage(root) -> Stage                                   where bwrap binds from (no host path in the mount table)
    site_folders() -> [str]                                the grader's package folders, in its order
    sites(places) -> [str]                                 the same, as the sandbox sees them
    package_copies() -> [Path]                             the package's installed copies (hidden from "serve")
"""
from __future__ import annotations

import os
import shutil
import site
import sys
import sysconfig
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


def package_copies() -> list[Path]:
    """Every installed copy of the package among Python's package folders, and what an install leaves beside it
    (rbcourse-*.dist-info, an editable install's hook): the grader's own venv's, and the base Python's (a `pip install .`
    outside a venv puts a whole copy there, which the sandbox's Python, its installation mounted, would find)."""
    paths = sysconfig.get_paths(vars={"base": sys.base_prefix, "platbase": sys.base_exec_prefix})
    folders = dict.fromkeys([*site_folders(), paths["purelib"], paths["platlib"]])
    return [copy for folder in folders for pattern in ("rbcourse", "rbcourse-*", "__editable__*rbcourse*")
            for copy in sorted(Path(folder).glob(pattern))]


def sites(where: dict[Path, Path]) -> list[str]:
    """The grader's package folders as the sandbox sees them (the worker adds them to its path: it runs without site)."""
    return [str(seen(Path(f), where) or f) for f in site_folders()]


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


STAGE = Path("/mnt")
STAGING = r"""set -e
mount -t tmpfs -o mode=0755 rbcourse-stage /mnt
mkdir -p /mnt/empty /mnt/files
while [ "$1" != -- ]; do
  if [ "$1" = d ]; then
    mkdir -p "/mnt/lower/$3" "/mnt/view/$3"
    mount --bind "$2" "/mnt/lower/$3"
    mount -t overlay overlay -o "ro,lowerdir=/mnt/lower/$3:/mnt/empty" "/mnt/view/$3" \
      || mount --bind "/mnt/lower/$3" "/mnt/view/$3"
  else
    cp "$2" "/mnt/files/$3"
    chmod 0644 "/mnt/files/$3"
  fi
  shift 3
done
shift
exec "$@"
"""


class Stage:
    """Where bwrap takes what it binds from.  A bind mount keeps its source's path in the mount table
    (/proc/self/mountinfo); so, where the grader is root, each folder is first seen, in a mount namespace of the
    sandbox's own, as a read-only overlay under /mnt/view/N (its table then says only lowerdir=/mnt/lower/N) and each
    file as a copy under /mnt/files/N: no host path is in the sandbox's mount table.  Elsewhere the host's paths are
    bound as they are (their names in the mount table: docs/grading.md)."""

    def __init__(self, on: bool):
        self.on, self.items = on, []

    def source(self, path) -> Path:
        """The path bwrap binds `path` from."""
        path = Path(path)
        if not self.on:
            return path
        kind, name = ("d" if path.is_dir() else "f"), str(len(self.items))
        self.items.append((kind, str(path), name))
        return STAGE / ("view" if kind == "d" else "files") / name

    def wrap(self, command: list[str]) -> list[str]:
        """bwrap's `command`, run in a mount namespace of its own where its sources are staged."""
        if not self.on or not self.items:
            return command
        return ["unshare", "--mount", "--propagation", "private", "--", "sh", "-c", STAGING, "sh",
                *[part for item in self.items for part in item], "--", *command]


def stage(root: bool) -> Stage:
    """A Stage, staging where the grader is root and can (unshare, /mnt to mount its own on)."""
    return Stage(root and STAGE.is_dir() and shutil.which("unshare") is not None and shutil.which("mount") is not None)


def filesystem(mode: str, cache: Path | None, fds: list, staged: Stage | None = None) -> list[str]:
    """bwrap's arguments for the sandbox's file system (see the module's docstring); the file descriptors they name
    are appended to fds (the caller passes them to bwrap, then closes them); the host's folders and files are bound
    from where `staged` puts them (default: as they are)."""
    staged = staged or Stage(False)
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
            bind(staged.source(tree), place)
    for copy in package_copies():       # mode "serve": no copy of the package anywhere; an editable hook names the
        inside = seen(copy, where)      # checkout: emptied in both modes
        if inside is None or (mode == "run" and not copy.name.startswith("__editable__")):
            continue
        if copy.is_dir():
            args.extend(["--tmpfs", str(inside)])
        else:
            fds.append(pipe(b""))
            args.extend(["--perms", "0644", "--ro-bind-data", str(fds[-1]), str(inside)])
    for name in ("worker.py", "wire.py", "seccomp.py"):
        bind(staged.source(HERE / name), GRADING / name)
    bind(staged.source(HERE / "standin.py" if mode == "serve" else PACKAGE),
         GRADING / "rbcourse" / "__init__.py" if mode == "serve" else GRADING / "rbcourse")
    if cache is not None:
        bind(staged.source(cache), GRADING / "numba-cache")
    return args


def pipe(data: bytes) -> int:
    """A pipe's read end holding `data` (a few hundred bytes at most: within the pipe's buffer), for bwrap to read."""
    read, write = os.pipe()
    os.write(write, data)
    os.close(write)
    return read
