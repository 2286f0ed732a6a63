"""The hand-ins of SUBMISSIONS/, read once, before anything runs — one per entry, whatever the entry is — and
SUBMISSIONS' fingerprint, to tell whether anything changed it while the class was graded.

    read(folder)          -> [Handin]: each with its notebook's text, or the reason it is invalid
    fingerprint(folder)   -> {relative path: (kind, size, sha256 of a file's bytes, or a link's target)}
    changes(before, after) -> ["modified ann.ipynb", "created x", …]

An entry is a hand-in: ``STUDENT.ipynb`` (the extension in any case: ``Upper.IPYNB`` is Upper's), or a folder
``STUDENT/`` holding exactly one notebook (at any depth; its hidden entries, such as .ipynb_checkpoints, and its
other files are left aside).  Every file is opened without following a symbolic link (O_NOFOLLOW, each folder
by its descriptor), without waiting on a FIFO (O_NONBLOCK), checked to be a regular file after it is open, and
read up to MAX_BYTES.  Anything else is a row with the status "invalid" and the reason: a hidden entry, a link,
a FIFO, a socket or a device, a file that is not a notebook, a folder with no notebook or several, a file too
large, not UTF-8, not JSON, not a notebook.  Names are Unicode NFC (é typed as one character or as e + ´ is the
same student): two entries with the same name are both invalid, each naming the other.
"""
from __future__ import annotations

import errno
import hashlib
import json
import os
import stat
import unicodedata
from dataclasses import dataclass

MAX_BYTES = 32 << 20          # a notebook's size
MAX_ENTRIES = 20_000          # entries looked at in SUBMISSIONS in all (folders walked, fingerprint)
MAX_DEPTH = 8                 # folders within a hand-in's folder
NOTEBOOK = ".ipynb"
OPEN = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC
FOLDER = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC


@dataclass
class Handin:
    name: str                 # the student: the notebook's stem or the folder's name (NFC)
    source: str               # where it is in SUBMISSIONS (for messages)
    text: str | None = None   # the notebook, as read before anything ran (None: invalid)
    problem: str = ""         # why it is invalid


def _printable(raw: str, nfc: bool = True) -> tuple[str, bool]:
    """(the name as text, NFC unless nfc=False; whether it was valid UTF-8)."""
    try:
        raw.encode("utf-8")
        return unicodedata.normalize("NFC", raw) if nfc else raw, True
    except UnicodeEncodeError:
        return raw.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace"), False


def _kind(mode: int) -> str:
    for test, word in ((stat.S_ISLNK, "a symbolic link"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISSOCK, "a socket"),
                       (stat.S_ISCHR, "a device"), (stat.S_ISBLK, "a device"), (stat.S_ISDIR, "a folder"),
                       (stat.S_ISREG, "a file")):
        if test(mode):
            return word
    return "a special file"


def read_notebook(name: str, dir_fd: int) -> tuple[str | None, str]:
    """(the notebook's text, "") or (None, why it cannot be one)."""
    try:
        fd = os.open(name, OPEN, dir_fd=dir_fd)
    except OSError as err:
        if err.errno == errno.ELOOP:        # O_NOFOLLOW met a symbolic link
            return None, "a symbolic link: not followed"
        return None, f"cannot be opened ({err.strerror or err})"
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            return None, f"{_kind(st.st_mode)}, not a regular file"
        if st.st_size > MAX_BYTES:
            return None, f"{st.st_size:,} bytes: a notebook may have at most {MAX_BYTES:,}"
        chunks, size = [], 0
        while size <= MAX_BYTES:
            chunk = os.read(fd, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        if size > MAX_BYTES:
            return None, f"more than {MAX_BYTES:,} bytes: a notebook may have at most that"
    except OSError as err:
        return None, f"cannot be read ({err.strerror or err})"
    finally:
        os.close(fd)
    try:
        text = b"".join(chunks).decode("utf-8")
    except UnicodeDecodeError as err:
        return None, f"not UTF-8 text (byte {err.start}): a notebook is UTF-8 JSON"
    try:
        notebook = json.loads(text)
    except (ValueError, RecursionError) as err:
        return None, f"not JSON ({' '.join(str(err).split())[:80]}): a notebook is UTF-8 JSON"
    if not isinstance(notebook, dict) or not isinstance(notebook.get("cells"), list):
        return None, "JSON, but not a notebook (it has no list of cells)"
    return text, ""


def _notebooks_in(dir_fd: int, prefix: str, depth: int, budget: list) -> list[tuple[int, str, str]]:
    """[(its folder's descriptor, its name, its path)] of every *.ipynb under the folder (hidden entries left
    aside, links not followed); the descriptors of the folders walked are in the result or closed."""
    found = []
    for raw in sorted(os.listdir(dir_fd)):
        budget[0] -= 1
        if budget[0] < 0 or raw.startswith("."):
            continue
        try:
            st = os.stat(raw, dir_fd=dir_fd, follow_symlinks=False)
        except OSError:
            continue
        if stat.S_ISDIR(st.st_mode) and depth < MAX_DEPTH:
            try:
                sub = os.open(raw, FOLDER, dir_fd=dir_fd)
            except OSError:
                continue
            inner = _notebooks_in(sub, f"{prefix}{raw}/", depth + 1, budget)
            if not any(d == sub for d, _, _ in inner):
                os.close(sub)
            found += inner
        elif raw.lower().endswith(NOTEBOOK):
            found.append((dir_fd, raw, prefix + raw))
    return found


def _entry(raw: str, dir_fd: int, budget: list) -> Handin:
    shown, utf8 = _printable(raw)
    source = _printable(raw, nfc=False)[0]          # as it is on disk (two names alike once NFC differ here)
    try:
        st = os.stat(raw, dir_fd=dir_fd, follow_symlinks=False)
    except OSError as err:
        return Handin(shown, source, problem=f"cannot be read ({err.strerror or err})")
    is_notebook = stat.S_ISREG(st.st_mode) and raw.lower().endswith(NOTEBOOK)
    name = shown[: -len(NOTEBOOK)] if shown.lower().endswith(NOTEBOOK) and not stat.S_ISDIR(st.st_mode) else shown
    if not utf8:
        return Handin(name, source, problem="its name is not UTF-8 text")
    if raw.startswith("."):
        return Handin(name, source, problem="a hidden entry (its name starts with a dot): hand in STUDENT.ipynb")
    if stat.S_ISDIR(st.st_mode):
        return _folder(raw, name, source, dir_fd, budget)
    if not stat.S_ISREG(st.st_mode):
        return Handin(name, source, problem=f"{_kind(st.st_mode)}, not a notebook file (not followed, not read)")
    if not is_notebook:
        return Handin(name, source, problem=f"not a notebook: its extension is {os.path.splitext(shown)[1] or 'none'}"
                                            f", a hand-in is STUDENT{NOTEBOOK} or a folder STUDENT/")
    text, problem = read_notebook(raw, dir_fd)
    return Handin(name, source, text, problem)


def _folder(raw: str, name: str, source: str, dir_fd: int, budget: list) -> Handin:
    try:
        sub = os.open(raw, FOLDER, dir_fd=dir_fd)
    except OSError as err:
        return Handin(name, source + "/", problem=f"a folder that cannot be read ({err.strerror or err})")
    try:
        notebooks = _notebooks_in(sub, f"{raw}/", 0, budget)
        try:
            if len(notebooks) != 1:
                listed = ", ".join(_printable(p, nfc=False)[0] for _, _, p in notebooks[:3]) \
                    + (" …" if len(notebooks) > 3 else "")
                return Handin(name, source + "/", problem=f"a folder must hold exactly one notebook ({NOTEBOOK}); it "
                                                        f"holds {len(notebooks)}" + (f": {listed}" if listed else ""))
            folder_fd, file_name, path = notebooks[0]
            text, problem = read_notebook(file_name, folder_fd)
            return Handin(name, _printable(path, nfc=False)[0], text, problem)
        finally:
            for fd in {d for d, _, _ in notebooks} - {sub}:
                os.close(fd)
    finally:
        os.close(sub)


def read(folder) -> list[Handin]:
    """One Handin per entry of SUBMISSIONS, sorted by name (ValueError: SUBMISSIONS cannot be read, or is empty)."""
    try:
        dir_fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError as err:
        raise ValueError(f"SUBMISSIONS: cannot read {folder} ({err.strerror or err})") from None
    try:
        budget = [MAX_ENTRIES]
        handins = [_entry(raw, dir_fd, budget) for raw in sorted(os.listdir(dir_fd))]
    finally:
        os.close(dir_fd)
    if budget[0] < 0:
        raise ValueError(f"SUBMISSIONS: more than {MAX_ENTRIES:,} entries in {folder}")
    if not handins:
        raise ValueError(f"SUBMISSIONS: no hand-in in {folder} (expected STUDENT.ipynb files or STUDENT/ folders "
                         f"each holding one notebook)")
    by_name: dict[str, list[Handin]] = {}
    for h in handins:
        by_name.setdefault(h.name, []).append(h)
    for same in (group for group in by_name.values() if len(group) > 1):
        for h in same:
            others = ", ".join(ascii(o.source) for o in same if o is not h)
            h.text, h.problem = None, f"its name is also that of {others} (the same once Unicode-normalised, NFC): " \
                                      f"rename one"
    return sorted(handins, key=lambda h: (h.name, h.source))


def fingerprint(folder) -> dict:
    """{path relative to folder: (kind, size, sha256 of a regular file's bytes / a link's target)}: every entry,
    hidden ones too, links not followed, FIFOs and devices not opened."""
    out: dict = {}
    try:
        top = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError:
        return out
    _walk(top, "", out, [MAX_ENTRIES], 0)
    return out


def _walk(dir_fd: int, prefix: str, out: dict, budget: list, depth: int) -> None:
    try:
        for raw in sorted(os.listdir(dir_fd)):
            budget[0] -= 1
            if budget[0] < 0:
                out["…"] = ("more entries than fingerprinted", 0, "")
                return
            path = prefix + raw
            try:
                st = os.stat(raw, dir_fd=dir_fd, follow_symlinks=False)
            except OSError:
                continue
            if stat.S_ISLNK(st.st_mode):
                out[path] = ("link", 0, os.readlink(raw, dir_fd=dir_fd))
            elif stat.S_ISREG(st.st_mode):
                out[path] = ("file", st.st_size, _digest(raw, dir_fd))
            elif stat.S_ISDIR(st.st_mode):
                out[path] = ("folder", 0, "")
                if depth < MAX_DEPTH + 2:
                    try:
                        sub = os.open(raw, FOLDER, dir_fd=dir_fd)
                    except OSError:
                        continue
                    _walk(sub, path + "/", out, budget, depth + 1)
            else:
                out[path] = (_kind(st.st_mode), 0, "")
    finally:
        os.close(dir_fd)


def _digest(name: str, dir_fd: int) -> str:
    h = hashlib.sha256()
    try:
        fd = os.open(name, OPEN, dir_fd=dir_fd)
    except OSError as err:
        return f"unreadable: {err.strerror}"
    try:
        while chunk := os.read(fd, 1 << 20):
            h.update(chunk)
    except OSError as err:
        return f"unreadable: {err.strerror}"
    finally:
        os.close(fd)
    return h.hexdigest()


def changes(before: dict, after: dict) -> list[str]:
    """'deleted P', 'created P', 'modified P' for each entry that changed."""
    out = []
    for p in sorted(set(before) | set(after)):
        shown = _printable(p)[0]
        if p not in after:
            out.append(f"deleted {shown}")
        elif p not in before:
            out.append(f"created {shown}")
        elif before[p] != after[p]:
            out.append(f"modified {shown}")
    return out
