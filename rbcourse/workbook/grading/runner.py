"""Running the hand-ins: each in a process of its own, in its own temporary folder, within its limit.

    handins(folder)          -> [Handin(name, source, notebook)]   (every notebook read into memory)
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
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import rbcourse

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


def handins(folder: Path) -> list[Handin]:
    """The hand-ins in folder: STUDENT.ipynb, or STUDENT/ holding exactly one .ipynb (hidden entries skipped).
    A ValueError names a folder with no notebook or several, a name handed in twice, an unreadable file."""
    folder = Path(folder)
    found: dict[str, Handin] = {}
    for entry in sorted(folder.iterdir()):
        if entry.name.startswith("."):
            continue
        if entry.is_dir():
            notebooks = sorted(p for p in entry.rglob("*.ipynb")
                               if not any(part.startswith(".") for part in p.relative_to(entry).parts))
            if len(notebooks) != 1:
                raise ValueError(f"SUBMISSIONS: the folder {entry.name}/ must hold exactly one notebook (.ipynb), "
                                 f"it holds {len(notebooks)}")
            path, name = notebooks[0], entry.name
        elif entry.suffix == ".ipynb":
            path, name = entry, entry.stem
        else:
            continue
        if name in found:
            raise ValueError(f"SUBMISSIONS: {name} handed in twice ({found[name].source.name} and {entry.name})")
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as err:
            raise ValueError(f"SUBMISSIONS: cannot read {path.relative_to(folder)} ({err})") from None
        found[name] = Handin(name, path.relative_to(folder), text)
    if not found:
        raise ValueError(f"SUBMISSIONS: no hand-in in {folder} (expected STUDENT.ipynb files or STUDENT/ folders "
                         f"each holding one notebook)")
    return list(found.values())


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


def _kill_group(pgid: int) -> None:
    try:
        os.killpg(pgid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _language(text: str) -> str:
    """The notebook's language: metadata rbcourse.language, else metadata language, else English."""
    try:
        meta = json.loads(text).get("metadata", {})
    except (ValueError, AttributeError):
        return "en"
    lang = (meta.get("rbcourse") or {}).get("language") or meta.get("language") or "en"
    return str(lang).lower()[:2]


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
                                     repr(cells), repr(checks)],
                                    cwd=home, env=environment(home, log), stdin=subprocess.DEVNULL,
                                    stdout=subprocess.DEVNULL, stderr=err, start_new_session=True)
            try:
                proc.wait(timeout=timeout + GRACE)
                timed_out = False
            except subprocess.TimeoutExpired:
                timed_out = True
            finally:
                _kill_group(proc.pid)      # the worker at its limit, and whatever it left running
                proc.wait()
        seconds = clock() - start
        changed = differences(before, snapshot(watched))
        events = _events(log)
        tail = errors.read_text(encoding="utf-8", errors="replace")[-600:]
        return _graded(handin, events, check_names, timed_out, timeout, changed, seconds, proc.returncode, tail)
    finally:
        shutil.rmtree(root, ignore_errors=True)


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
    g = Graded(handin.name, "ok", seconds=seconds, changed=changed, language=_language(handin.text),
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


MIN_TIMEOUT, MAX_TIMEOUT, DEFAULT_TIMEOUT = 5.0, 3600.0, 300.0


@dataclass
class Plan:
    """What `grade` will do, its arguments checked: the hand-ins (read), where each output goes."""
    submissions: Path
    handins: list
    out: Path
    feedback: Path
    gradescope: Path | None
    timeout: float

    def watched(self):
        """The places a hand-in must not change: [(path, recursive)]."""
        places = [(self.submissions, True), (self.out.parent, False), (self.feedback, True)]
        if self.gradescope is not None:
            places.append((self.gradescope.parent, False))
        return places


def _folder(path: Path, flag: str, files, created: list) -> Path:
    """writable_folder(path), noting in `created` the folders it made (the missing ones, outermost first)."""
    from ...outputs import writable_folder
    missing = []
    p = Path(path).absolute()
    while not p.exists() and p != p.parent:
        missing.append(p)
        p = p.parent
    created.extend(reversed(missing))
    return writable_folder(path, flag, files)


def _output_file(path: Path, flag: str, created: list) -> Path:
    """A file the command will write: its folder created and probed, the path itself not a folder."""
    if path.is_dir():
        raise ValueError(f"{flag}: {path} is a folder; name the file to write (e.g. {path / 'grades.csv'})")
    _folder(path.parent, flag, [path.name], created)
    return path


def _inside(path: Path, folder: Path) -> bool:
    try:
        path.resolve().relative_to(folder.resolve())
        return True
    except ValueError:
        return False


def check_arguments(submissions, out, timeout=DEFAULT_TIMEOUT, feedback=None, gradescope=None) -> Plan:
    """Every argument of `grade`, checked before anything runs (a ValueError names the argument); then the
    outputs' folders are created and probed (a folder created for a probe that failed is removed again)."""
    if not isinstance(timeout, (int, float)) or not (MIN_TIMEOUT <= timeout <= MAX_TIMEOUT):
        raise ValueError(f"--timeout must be from {MIN_TIMEOUT:g} to {MAX_TIMEOUT:g} seconds, got {timeout!r}")
    if not isinstance(submissions, (str, os.PathLike)) or str(submissions) == "":
        raise ValueError("SUBMISSIONS must name a folder, got ''")
    folder = Path(submissions)
    if not folder.is_dir():
        raise ValueError(f"SUBMISSIONS: {folder} is not a folder" + ("" if folder.exists() else " (it does not exist)"))
    found = handins(folder)
    for path, flag in ((out, "--out"), (gradescope, "--gradescope")):
        if path is not None and (not isinstance(path, (str, os.PathLike)) or str(path) == ""):
            raise ValueError(f"{flag} must name a file, got {str(path)!r}")
    out = Path(out)
    feedback = Path(feedback) if feedback is not None and str(feedback) != "" else (
        out.parent / "feedback" if feedback is None else None)
    if feedback is None:
        raise ValueError("--feedback must name a folder, got ''")
    gradescope = None if gradescope is None else Path(gradescope)
    if gradescope is not None and len(found) != 1:
        raise ValueError(f"--gradescope: results.json holds one submission (Gradescope grades one hand-in at a "
                         f"time), but SUBMISSIONS holds {len(found)}")
    for path, flag in ((out, "--out"), (feedback, "--feedback"), (gradescope, "--gradescope")):
        if path is not None and _inside(path, folder):
            raise ValueError(f"{flag}: {path} is inside SUBMISSIONS; write the grades elsewhere")
    created = []
    try:
        out = _output_file(out, "--out", created)
        feedback = _folder(feedback, "--feedback", [f"{h.name}.md" for h in found], created)
        if gradescope is not None:
            gradescope = _output_file(gradescope, "--gradescope", created)
    except ValueError:
        for path in reversed(created):
            try:
                path.rmdir()
            except OSError:
                pass
        raise
    return Plan(folder, found, out, feedback, gradescope, float(timeout))


def grade(plan: Plan, progress=print) -> tuple[list, list]:
    """Run every hand-in of the plan, one after the other, and write the outputs.  Returns (graded, paths)."""
    from .report import write_all
    from .worker import checks
    names = [name for name, _ in checks()]
    graded = []
    for h in plan.handins:
        g = grade_one(h, plan.timeout, plan.watched(), names)
        graded.append(g)
        if progress:
            passed = sum(1 for n in names if (g.checks.get(n) or {}).get("passed"))
            progress(f"{g.name}: {g.status}, {passed} of {len(names)} checks passed ({g.seconds:.1f} s)"
                     + (f" — {g.note}" if g.note else ""))
    return graded, write_all(graded, names, plan.out, plan.feedback, plan.gradescope)
