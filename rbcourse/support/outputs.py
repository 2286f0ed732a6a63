"""Output folders of the commands: checked before any computation, written so that a folder never
mixes the files of two runs, and kept when a long run is interrupted.

- ``writable_folder(out)``: a folder that exists (created if missing) and takes a file, or a
  ``ValueError`` naming `out` (an empty name, a file, a path under a file, ``/proc/x``, …).
- ``write_text`` / ``write_with``: a file written whole or not at all (a temporary file in the
  same folder, then ``os.replace``).
- ``RowLog``: a CSV that grows one complete, flushed row per finished run.
- ``Interrupted``: the ``KeyboardInterrupt`` of a long run whose finished part was written.
"""
from __future__ import annotations

import os
import secrets
import signal
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path

from . import checks


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during a long run, after what was finished had been written (marked partial).
    done, total: runs finished and planned; paths: the files written."""

    def __init__(self, done: int, total: int, paths: list[Path]):
        super().__init__(f"interrupted after {done} of {total} runs")
        self.done, self.total, self.paths = done, total, list(paths)


def writable_folder(out, name: str = "out", files=()) -> Path:
    """`out` as a Path: created if missing (with its parents), probed with a temporary file.
    files: the names the command will write there (none may be a folder)."""
    if not isinstance(out, (str, os.PathLike)) or str(out) == "":
        raise ValueError(f"{name} must name a folder, got {str(out)!r}")
    if "\0" in str(out):
        raise ValueError(f"{name} must name a folder (no NUL byte), got {str(out)!r}")
    out = checks.path_length(name, Path(out))
    if out.exists() and not out.is_dir():
        raise ValueError(f"{name} must be a folder, but {out} is a file")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise ValueError(f"{name}: cannot create the folder {out} ({err.strerror or err})") from None
    try:
        fd, probe = tempfile.mkstemp(dir=out, prefix=".probe-")
        os.close(fd)
        os.unlink(probe)
    except OSError as err:
        raise ValueError(f"{name}: cannot write into the folder {out} ({err.strerror or err})") from None
    for f in files:
        if (out / f).is_dir():
            raise ValueError(f"{name}: {out / f} is a folder, where a file of this command goes")
    return out


def write_with(path: Path, write) -> Path:
    """write(tmp_path) writes the file's content to a temporary path beside `path` (with the same
    suffix, so that e.g. savefig knows the format); then it replaces `path` at once: a reader sees
    the old file or the new one, never half of one."""
    path = Path(path)
    # a fresh name rather than mkstemp, whose files are private (0600): the file gets the umask's mode; short,
    # whatever the file's own name (a name near the file system's 255 bytes leaves no room for more)
    tmp = path.parent / f".rbcourse-{os.getpid()}-{secrets.token_hex(4)}.tmp{path.suffix[:16]}"
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        if tmp.exists():
            tmp.unlink()
        raise
    return path


def write_text(path: Path, text: str) -> Path:
    """`path` holds `text` (UTF-8), written whole or not at all."""
    return write_with(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


def remove(out: Path, names) -> None:
    """Remove the outputs a new run replaces (only these names: `out` may hold other files)."""
    for name in names:
        try:
            (Path(out) / name).unlink()
        except FileNotFoundError:
            pass


class RowLog:
    """A CSV written as the runs finish: the header, then one row per run, each flushed at once."""

    def __init__(self, path: Path, header: str):
        self.path = Path(path)
        self._file = open(self.path, "w", encoding="utf-8", newline="")
        self._file.write(header + "\n")
        self._file.flush()

    def add(self, row: str) -> None:
        self._file.write(row + "\n")
        self._file.flush()

    def close(self) -> None:
        self._file.close()


@contextmanager
def shielded():
    """Ctrl-C is ignored inside (while the final files are written, a few seconds at most);
    outside the main thread, where signals cannot be set, nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


class _NoBar:
    def update(self, n: int = 1):
        pass


BAR_WORDS = {"step": "pas", "run": "simulation", "simulate": "simulation", "explore": "exploration", "bench": "banc",
             "errors": "erreurs", "stability": "stabilité"}
"""A progress bar's unit or description (English) -> its French word."""


@contextmanager
def progress(total: int, unit: str, desc: str, on: bool):
    """A progress bar (tqdm) while a long run goes on, or nothing at all when `on` is False: tqdm is not
    even imported then (in a notebook without ipywidgets, importing tqdm.auto writes a warning to stderr).
    Its unit and description in the active language (BAR_WORDS)."""
    if not on:
        yield _NoBar()
        return
    from tqdm.auto import tqdm
    from .language import say
    unit, desc = (say(word, BAR_WORDS.get(word, word)) for word in (unit, desc))
    with tqdm(total=total, unit=unit, desc=desc) as bar:
        yield bar
