"""The hand-ins of SUBMISSIONS/, read once, before anything runs — one per entry, whatever the entry is — and
SUBMISSIONS' fingerprint, to tell whether anything changed it while the class was graded.

    read(folder)          -> [Handin]: each with its notebook's text, or the reason it is invalid
    fingerprint(folder)   -> {relative path: (kind, size, sha256 of a file's bytes, or a link's target)}
    changes(before, after) -> ["modified ann.ipynb", "created x", …]

An entry is a hand-in: ``STUDENT.ipynb`` (the extension in any case: ``Upper.IPYNB`` is Upper's), or a folder
``STUDENT/`` holding exactly one notebook (up to MAX_DEPTH folders deep; its hidden entries, such as
.ipynb_checkpoints, and its other files — a venv/, a data/ folder — are left aside, up to MAX_FOLDER_ENTRIES of
them looked at per hand-in).  Every file is opened without following a symbolic link (O_NOFOLLOW, each folder
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

from ...support.language import say

MAX_BYTES = 32 << 20          # a notebook's size
MAX_ENTRIES = 20_000          # hand-ins in SUBMISSIONS (its own entries), and entries fingerprinted in all
MAX_FOLDER_ENTRIES = 200_000  # entries looked at within one hand-in's folder (its notebook found among them)
MAX_DEPTH = 64                # folders within a hand-in's folder
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
    for test, word in ((stat.S_ISLNK, ("a symbolic link", "un lien symbolique")), (stat.S_ISFIFO, ("a FIFO", "une FIFO")),
                       (stat.S_ISSOCK, ("a socket", "un socket")), (stat.S_ISCHR, ("a device", "un périphérique")),
                       (stat.S_ISBLK, ("a device", "un périphérique")), (stat.S_ISDIR, ("a folder", "un dossier")),
                       (stat.S_ISREG, ("a file", "un fichier"))):
        if test(mode):
            return say(*word)
    return say("a special file", "un fichier spécial")


def read_notebook(name: str, dir_fd: int) -> tuple[str | None, str]:
    """(the notebook's text, "") or (None, why it cannot be one)."""
    try:
        fd = os.open(name, OPEN, dir_fd=dir_fd)
    except OSError as err:
        if err.errno == errno.ELOOP:        # O_NOFOLLOW met a symbolic link
            return None, say("a symbolic link: not followed", "un lien symbolique : non suivi")
        return None, say(f"cannot be opened ({err.strerror or err})", f"ne peut pas être ouvert ({err.strerror or err})")
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            return None, _kind(st.st_mode) + say(", not a regular file", ", pas un fichier ordinaire")
        if st.st_size > MAX_BYTES:
            return None, say(f"{st.st_size:,} bytes: a notebook may have at most {MAX_BYTES:,}",
                             f"{st.st_size:,} octets : un notebook en a au plus {MAX_BYTES:,}")
        chunks, size = [], 0
        while size <= MAX_BYTES:
            chunk = os.read(fd, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        if size > MAX_BYTES:
            return None, say(f"more than {MAX_BYTES:,} bytes: a notebook may have at most that",
                             f"plus de {MAX_BYTES:,} octets : un notebook en a au plus autant")
    except OSError as err:
        return None, say(f"cannot be read ({err.strerror or err})", f"ne peut pas être lu ({err.strerror or err})")
    finally:
        os.close(fd)
    try:
        text = b"".join(chunks).decode("utf-8")
    except UnicodeDecodeError as err:
        return None, say(f"not UTF-8 text (byte {err.start}): a notebook is UTF-8 JSON",
                         f"pas du texte UTF-8 (octet {err.start}) : un notebook est du JSON en UTF-8")
    try:
        notebook = json.loads(text)
    except (ValueError, RecursionError) as err:
        why = ' '.join(str(err).split())[:80]
        return None, say(f"not JSON ({why}): a notebook is UTF-8 JSON", f"pas du JSON ({why}) : un notebook est du JSON en UTF-8")
    if not isinstance(notebook, dict) or not isinstance(notebook.get("cells"), list):
        return None, say("JSON, but not a notebook (it has no list of cells)", "du JSON, mais pas un notebook (il n'a pas de "
                         "liste de cellules)")
    return text, ""


def _notebooks_in(dir_fd: int, prefix: str, depth: int, budget: list) -> list[tuple[int, str, str]]:
    """[(its folder's descriptor, its name, its path)] of every *.ipynb under the folder (hidden entries left
    aside, links not followed); the descriptors of the folders walked are in the result or closed."""
    found = []
    try:
        names = sorted(os.listdir(dir_fd))
    except OSError:
        return found
    for raw in names:
        budget[0] -= 1
        if budget[0] < 0:
            break
        if raw.startswith("."):
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


def _entry(raw: str, dir_fd: int) -> Handin:
    shown, utf8 = _printable(raw)
    source = _printable(raw, nfc=False)[0]          # as it is on disk (two names alike once NFC differ here)
    try:
        st = os.stat(raw, dir_fd=dir_fd, follow_symlinks=False)
    except OSError as err:
        return Handin(shown, source, problem=say(f"cannot be read ({err.strerror or err})",
                                                 f"ne peut pas être lu ({err.strerror or err})"))
    is_notebook = stat.S_ISREG(st.st_mode) and raw.lower().endswith(NOTEBOOK)
    name = shown[: -len(NOTEBOOK)] if shown.lower().endswith(NOTEBOOK) and not stat.S_ISDIR(st.st_mode) else shown
    if not utf8:
        return Handin(name, source, problem=say("its name is not UTF-8 text", "son nom n'est pas du texte UTF-8"))
    if raw.startswith("."):
        return Handin(name, source, problem=say("a hidden entry (its name starts with a dot): hand in STUDENT.ipynb",
                                                "une entrée cachée (son nom commence par un point) : rendez STUDENT.ipynb"))
    if stat.S_ISDIR(st.st_mode):
        return _folder(raw, name, source, dir_fd)
    if not stat.S_ISREG(st.st_mode):
        return Handin(name, source, problem=_kind(st.st_mode) + say(", not a notebook file (not followed, not read)",
                                                                    ", pas un fichier notebook (non suivi, non lu)"))
    if not is_notebook:
        ext = os.path.splitext(shown)[1] or say("none", "aucune")
        return Handin(name, source, problem=say(f"not a notebook: its extension is {ext}, a hand-in is STUDENT{NOTEBOOK} "
                                                "or a folder STUDENT/", f"pas un notebook : son extension est {ext}, un "
                                                f"rendu est STUDENT{NOTEBOOK} ou un dossier STUDENT/"))
    text, problem = read_notebook(raw, dir_fd)
    return Handin(name, source, text, problem)


def _folder(raw: str, name: str, source: str, dir_fd: int) -> Handin:
    try:
        sub = os.open(raw, FOLDER, dir_fd=dir_fd)
    except OSError as err:
        return Handin(name, source + "/", problem=say(f"a folder that cannot be read ({err.strerror or err})",
                                                      f"un dossier qui ne peut pas être lu ({err.strerror or err})"))
    try:
        budget = [MAX_FOLDER_ENTRIES]     # the hand-in's own: a folder of many files costs no one else anything
        notebooks = _notebooks_in(sub, f"{raw}/", 0, budget)
        try:
            if budget[0] < 0 and len(notebooks) != 1:
                return Handin(name, source + "/", problem=say(
                    f"a folder of more than {MAX_FOLDER_ENTRIES:,} entries, and no single notebook among the first: "
                    "hand in the notebook alone", f"un dossier de plus de {MAX_FOLDER_ENTRIES:,} entrées, sans notebook "
                    "unique parmi les premières : rendez le notebook seul"))
            if len(notebooks) != 1:
                listed = ", ".join(_printable(p, nfc=False)[0] for _, _, p in notebooks[:3]) \
                    + (" …" if len(notebooks) > 3 else "")
                return Handin(name, source + "/", problem=say(
                    f"a folder must hold exactly one notebook ({NOTEBOOK}); it holds {len(notebooks)}",
                    f"un dossier doit contenir exactement un notebook ({NOTEBOOK}) ; il en contient {len(notebooks)}")
                    + (say(": ", " : ") + listed if listed else ""))
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
        entries = sorted(os.listdir(dir_fd))
        if len(entries) > MAX_ENTRIES:
            raise ValueError(f"SUBMISSIONS: more than {MAX_ENTRIES:,} entries in {folder}")
        handins = [_entry(raw, dir_fd) for raw in entries]
    finally:
        os.close(dir_fd)
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
            h.name = f"{h.name} {ascii(h.source.split('/')[0])}"   # its entry's name on disk: its own row, its feedback
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
