"""Running one hand-in: in a process of its own, in its own temporary folder, within its limit.

    grade_one(handin, …)     -> Graded: status, the checks' outcomes, cell errors, changes outside, seconds

A hand-in's process (worker.py) starts its own session, so that its process group — the worker and
anything it started — is killed whole (SIGKILL) at the time limit, and after it ends in any case (no
stray children).  Its environment is reduced to what Python needs (PATH, the locale, RBCOURSE_*,
NUMBA_*, MPLBACKEND=Agg, PYTHONPATH to this package) with HOME, TMPDIR and cwd its own folder.  The
watched places (SUBMISSIONS and the outputs) are snapshotted before and after: a hand-in that
changed them is "wrote-outside", its changes listed.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import rbcourse

from ..language import LANGUAGES

GRACE = 5.0            # s after its limit: a hand-in that ignored its interrupt is killed then
KEPT_VARIABLES = ("PATH", "LANG", "LC_ALL", "LC_CTYPE", "SYSTEMROOT")
KEPT_PREFIXES = ("RBCOURSE_", "NUMBA_")


@dataclass
class Handin:
    name: str          # the student: the notebook's stem, or the folder's name
    source: Path       # where it was found (relative to SUBMISSIONS in messages)
    text: str          # the notebook, as read before any hand-in ran


@dataclass
class Graded:
    name: str
    status: str                                   # ok / error / timeout / wrote-outside
    checks: dict = field(default_factory=dict)    # check name -> outcome dict (see grading.outcome), final
    cell_errors: list = field(default_factory=list)
    changed: list = field(default_factory=list)   # paths outside its folder that it changed
    seconds: float = 0.0
    note: str = ""                                # what went wrong, in a line (empty when ok)
    language: str = "en"
    timed_out: bool = False                       # killed at its limit (it ignored the interrupt)
    interrupted: dict | None = None               # the cell that was still running at its limit
    finished: bool = False                        # the final checks ran
    timeout: float = 0.0                          # its limit (s)
    returncode: int | None = None                 # its process's exit code (negative: killed by that signal)


def snapshot(places) -> dict:
    """{path: (size, mtime_ns, kind)} of each watched place: a folder (recursive, or its listing only with
    shallow=True) or a file.  places: [(path, recursive)]."""
    state = {}
    for place, recursive in places:
        place = Path(place)
        if not place.exists():
            continue
        items = [place]
        if place.is_dir():
            items += list(place.rglob("*")) if recursive else list(place.iterdir())
        for p in items:
            try:
                st = p.lstat()
            except OSError:
                continue
            state[str(p)] = (st.st_size, st.st_mtime_ns, "dir" if p.is_dir() else "file")
    return state


def differences(before: dict, after: dict) -> list[str]:
    """'deleted P', 'created P', 'modified P' for each path that changed (folders: created/deleted only)."""
    out = []
    for p in sorted(set(before) | set(after)):
        if p not in after:
            out.append(f"deleted {p}")
        elif p not in before:
            out.append(f"created {p}")
        elif before[p] != after[p] and after[p][2] == "file":
            out.append(f"modified {p}")
    return out


def environment(home: Path, log: Path) -> dict:
    """The hand-in's environment: the kept variables, its folder as HOME and TMPDIR, this package on the path."""
    env = {k: v for k, v in os.environ.items() if k in KEPT_VARIABLES or k.startswith(KEPT_PREFIXES)}
    env.pop("RBCOURSE_GRADE_LOG", None)
    package_root = str(Path(rbcourse.__file__).resolve().parent.parent)
    env.update(HOME=str(home), TMPDIR=str(home), TMP=str(home), TEMP=str(home), MPLBACKEND="Agg",
               PYTHONPATH=package_root, PYTHONDONTWRITEBYTECODE="1", IPYTHONDIR=str(home / ".ipython"),
               MPLCONFIGDIR=str(home / ".matplotlib"), PYTHONHASHSEED="0")
    env.setdefault("PATH", os.defpath)
    return env


def _kill_group(pgid: int, wait: float = 5.0) -> None:
    """SIGKILL the process group, then wait (up to `wait` s) until none of it is left, so that nothing of the
    hand-in still writes into its folder when the folder is removed."""
    try:
        os.killpg(pgid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        return
    end = time.monotonic() + wait
    while time.monotonic() < end:
        try:
            os.killpg(pgid, 0)
        except (ProcessLookupError, PermissionError):
            return
        time.sleep(0.02)


def _remove(root: Path, tries: int = 5) -> None:
    """Remove the hand-in's temporary folder, again if something was still being written into it."""
    for _ in range(tries):
        shutil.rmtree(root, ignore_errors=True)
        if not root.exists():
            return
        time.sleep(0.1)


LANGUAGE_CALL = re.compile(r"""\b(?:langue|language)\(\s*(?:code\s*=\s*)?["']([A-Za-z]+)["']\s*\)""")
"""A call that sets the checks' language in a code cell: ex.langue("fr"), language('en'), langue(code="fr")."""


def notebook_language(text: str) -> str:
    """The hand-in's language, one of LANGUAGES: the last ex.langue("…") / ex.language("…") call in its code cells
    (what its checks print in), else its metadata rbcourse.language, else English.  The worker starts in this
    language (so a notebook that only declares it in its metadata is graded in it too)."""
    from ..language import LANGUAGES
    from .worker import code_cells
    try:
        notebook = json.loads(text)
        meta = notebook.get("metadata", {}) or {}
        sources = code_cells(notebook)
    except (ValueError, AttributeError, TypeError):
        return "en"
    calls = [m.group(1).lower() for source in sources for m in LANGUAGE_CALL.finditer(source)]
    calls = [c for c in calls if c in LANGUAGES]
    if calls:
        return calls[-1]
    declared = (meta.get("rbcourse") or {}).get("language") if isinstance(meta.get("rbcourse"), dict) else None
    declared = str(declared).lower() if declared else ""
    return declared if declared in LANGUAGES else "en"


def budgets(timeout: float) -> tuple[float, float]:
    """(the cells' seconds, the final checks' seconds) within a hand-in's limit: the checks get a third of it,
    at most 60 s."""
    checks = min(timeout / 3, 60.0)
    return timeout - checks, checks


def grade_one(handin: Handin, timeout: float, watched, check_names, clock=time.monotonic) -> Graded:
    """Run one hand-in and say what it did.  watched: [(path, recursive)] snapshotted before and after.
    Its cells and then its final checks get budgets(timeout) (the worker interrupts them); a hand-in still
    running GRACE s after its limit is killed with its process group."""
    root = Path(tempfile.mkdtemp(prefix="rbcourse-grade-"))
    try:
        home = root / "handin"
        home.mkdir()
        notebook = home / (handin.name + ".ipynb")
        notebook.write_text(handin.text, encoding="utf-8")
        log, errors = root / "events.jsonl", root / "stderr.txt"
        before = snapshot(watched)
        start = clock()
        with open(errors, "wb") as err:
            cells, checks = budgets(timeout)
            proc = subprocess.Popen([sys.executable, "-m", "rbcourse.workbook.grading.worker", notebook.name, str(log),
                                     repr(cells), repr(checks), notebook_language(handin.text)],
                                    cwd=home, env=environment(home, log), stdin=subprocess.DEVNULL,
                                    stdout=subprocess.DEVNULL, stderr=err, start_new_session=True)
            try:
                proc.wait(timeout=timeout + GRACE)
                timed_out = False
            except subprocess.TimeoutExpired:
                timed_out = True
            finally:
                _kill_group(proc.pid, wait=0)    # the worker at its limit, and whatever it left running
                proc.wait()
                _kill_group(proc.pid)            # again, waiting until none of its group is left
        seconds = clock() - start
        changed = differences(before, snapshot(watched))
        events = _events(log)
        tail = errors.read_text(encoding="utf-8", errors="replace")[-600:]
        return _graded(handin, events, check_names, timed_out, timeout, changed, seconds, proc.returncode, tail)
    finally:
        _remove(root)


def _events(log: Path) -> list[dict]:
    out = []
    if not log.exists():
        return out
    for line in log.read_text(encoding="utf-8", errors="replace").splitlines():
        try:
            event = json.loads(line)
        except ValueError:
            continue                          # a line cut by the kill
        if isinstance(event, dict):
            out.append(event)
    return out


def _graded(handin, events, check_names, timed_out, timeout, changed, seconds, returncode, tail) -> Graded:
    """The outcome of a run from its events: the final checks when they ran, else the last result the notebook
    got for each check; status by gravity: wrote-outside, timeout, error, ok."""
    g = Graded(handin.name, "ok", seconds=seconds, changed=changed, language=notebook_language(handin.text),
               timed_out=timed_out, timeout=timeout, returncode=returncode)
    seen = {}
    final = {}
    for e in events:
        if e.get("event") == "check" and e.get("name") in check_names:
            (final if e.get("phase") == "final" else seen)[e["name"]] = e
        elif e.get("event") == "cell_error":
            g.cell_errors.append(e)
        elif e.get("event") == "interrupted":
            g.interrupted = e
        elif e.get("event") == "language" and e.get("code") in LANGUAGES:
            g.language = e["code"]            # the language its checks really printed in
    g.finished = any(e.get("event") == "done" for e in events)
    g.checks = {**seen, **final}            # the final checks when they ran, else what the notebook got
    notes = []
    if changed:
        g.status = "wrote-outside"
        notes.append(f"changed {len(changed)} path(s) outside its folder: " + "; ".join(changed[:3])
                     + (" …" if len(changed) > 3 else ""))
    if timed_out:
        g.status = g.status if g.status != "ok" else "timeout"
        notes.append(f"killed at {timeout + GRACE:g} s: it ignored the interrupt at its time limit ({timeout:g} s)")
    elif g.interrupted:
        g.status = g.status if g.status != "ok" else "timeout"
        i = g.interrupted
        notes.append(f"stopped at its time limit: code cell {i.get('cell')} ({i.get('first_line', '')}) was still "
                     f"running after {budgets(timeout)[0]:g} s; the cells after it did not run")
    elif not g.finished:
        g.status = g.status if g.status != "ok" else "error"
        last = " ".join(tail.split()[-30:])
        notes.append(f"its process ended before the checks ran (exit code {returncode}){': ' + last if last else ''}")
    if g.cell_errors:
        g.status = g.status if g.status != "ok" else "error"
        first = g.cell_errors[0]
        notes.append(f"{len(g.cell_errors)} cell(s) raised; first: code cell {first.get('cell')} "
                     f"({first.get('first_line', '')}): {first.get('error', '')}")
    g.note = " | ".join(notes)
    return g
