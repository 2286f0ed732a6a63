"""Grading one hand-in: its notebook run twice, one run after the other, each in a sandbox of its own (sandbox.py),
its functions checked from here (checker.py).

    check_one(handin, settings) -> Graded     1. the checks: the notebook where rbcourse is not installed
    run_one(graded, handin, settings)         2. its status: the notebook as written, with the library
    grade_one(handin, settings) -> Graded     both, one after the other
    check_task, status_task, grade_task       the same, as a worker process or a Dask worker runs them

- "serve" (1.): the notebook where rbcourse is not installed (standin.py); its graded functions are then called by
  the checks, here.  The grade is only this.  Its cells get `budgets(timeout)[0]` seconds (the worker interrupts a
  cell still running then), the checks the rest.
- "run" (2.): the notebook as the student wrote it, with the library: its status (it ran to the end, a cell raised,
  it was still running at its limit) and its errors, for the feedback, within the hand-in's limit.  Nothing it says
  counts for the grade.
The run that has the library starts only once every process of the checked one is gone: it cannot pass it anything,
not even through the machine's load; and a class is graded in the same two phases (plan.grade: every hand-in's
checks, then every hand-in's run), so that no process with the library runs beside a checked one.  A sandbox is
stopped — its every process killed — as soon as it is done with, or GRACE s after its limit; the hand-in's temporary
folder (its stderr) is removed.
"""
from __future__ import annotations

import json
import math
import re
import shutil
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from ..language import LANGUAGES
from . import sandbox, wire
from .checker import check_all, checks
from .library import from_rbcourse
from .submissions import Handin
from .worker import code_cells

GRACE = 5.0                    # s after its limit: a hand-in that ignored its interrupt is killed then
MEMORY = 1536 << 20            # bytes of address space, per process
TOTAL_MEMORY = 2048 << 20      # bytes held by a sandbox's processes together, its /tmp included (cgroups.py)
FILE_SIZE = 64 << 20           # bytes, per file it writes
PROCESSES = 64                 # processes and threads at once (in its own sandbox)
OPEN_FILES = 256
REMARKS = {
    "en": {"failed": "the grader failed on this hand-in ({error}): grade it again",
           "alive": "some of its processes were still alive after its grading",
           "unsent": "its notebook could not be given to its sandbox ({error})",
           "not_protected": "not protected: graded without a sandbox (--no-sandbox)",
           "cell_running": "a cell was still running at its time limit when its functions were checked",
           "late": "still running at its time limit: {names} (timed-out)",
           "unchecked": "its functions could not all be checked: {problem}",
           "changed": "SUBMISSIONS changed while the class was graded (graded on the copies read before): {changes}"},
    "fr": {"failed": "le correcteur a échoué sur ce rendu ({error}) : notez-le à nouveau",
           "alive": "certains de ses processus étaient encore en vie après sa correction",
           "unsent": "son notebook n'a pas pu être donné à son bac à sable ({error})",
           "not_protected": "non protégé : noté sans bac à sable (--no-sandbox)",
           "cell_running": "une cellule tournait encore à sa limite de temps quand ses fonctions ont été vérifiées",
           "late": "encore en cours à sa limite de temps : {names} (temps dépassé)",
           "unchecked": "ses fonctions n'ont pas toutes pu être vérifiées : {problem}",
           "changed": "SUBMISSIONS a changé pendant la correction de la classe (noté sur les copies lues avant) : "
                      "{changes}"},
}
"""What the grader notes on a hand-in (Graded.remark: its feedback and the CSV's note), in the hand-in's language."""

NOTES = {
    "en": {"killed": "killed at {limit:g} s: it ignored the interrupt at its time limit ({timeout:g} s)",
           "stopped": "stopped at its time limit: code cell {cell} ({first_line}) was still running after {seconds:g} s;"
                      " the cells after it did not run",
           "ended": "its process ended before the end of its notebook (exit code {code})",
           "colon": ": ",
           "raised": "{n} cell(s) raised; first: code cell {cell} ({first_line}): {error}"},
    "fr": {"killed": "tué à {limit:g} s : il a ignoré l'interruption à sa limite de temps ({timeout:g} s)",
           "stopped": "arrêté à sa limite de temps : la cellule de code {cell} ({first_line}) tournait encore après "
                      "{seconds:g} s ; les cellules suivantes n'ont pas été exécutées",
           "ended": "son processus s'est terminé avant la fin de son notebook (code de sortie {code})",
           "colon": " : ",
           "raised": "{n} cellule(s) ont levé une exception ; la première : cellule de code {cell} ({first_line}) : "
                     "{error}"},
}
"""What the grader says of how a hand-in's notebook ran (the CSV's note), in the language of grade --lang."""


def remark(g, key: str, **values) -> None:
    """g.remark of REMARKS[key] in the hand-in's language (g.language), its {placeholders} filled from values."""
    g.remark(REMARKS.get(g.language, REMARKS["en"])[key].format(**values))


@dataclass
class Settings:
    """How every hand-in is graded: its limit (s), in a sandbox or not, the engine's compiled code to share."""
    timeout: float
    sandboxed: bool = True
    cache: Path | None = None      # the grader's numba cache of the engine, shared read-only
    language: str = "en"           # the language of the CSV's notes (grade --lang; NOTES)
    seed: int = 0                  # the check inputs' seed, kept in the grader's process (checker.check_all)


@dataclass
class Graded:
    name: str
    status: str                                   # ok / error / timeout / invalid
    checks: dict = field(default_factory=dict)    # check name -> outcome dict (see grading.outcome)
    cell_errors: list = field(default_factory=list)
    seconds: float = 0.0
    cpu_seconds: float | None = None              # the processor time of its sandboxes' processes (None: not counted)
    note: str = ""                                # what went wrong, in a line (empty when ok)
    language: str = "en"
    timed_out: bool = False                       # killed at its limit (it ignored the interrupt)
    interrupted: dict | None = None               # the cell that was still running at its limit
    finished: bool = False                        # every check ran
    timeout: float = 0.0                          # its limit (s)
    returncode: int | None = None                 # its notebook's process exit code, when it ended early
    source: str = ""                              # where it is in SUBMISSIONS
    protected: bool = True                        # graded in a sandbox
    ended: bool = False                           # its notebook's process ended before the end of its cells
    remarks: list = field(default_factory=list)   # what else the grader noted (timed-out functions, …)
    failed: bool = False                          # no phase 2 (run_one): invalid, or the grader failed on it
    left: bool = False                            # some of its processes outlived their sandbox's stop
    unsent: bool = False                          # its notebook could not be given to its process
    problem: str = ""                             # why its functions could not all be checked (phase 1)
    checked_while_running: bool = False           # a cell still ran at its limit when its functions were checked

    def remark(self, text: str) -> None:
        """Note `text` (in the feedback, and in the CSV's note)."""
        self.remarks.append(text)
        self.note = " | ".join(filter(None, [self.note, text]))


LANGUAGE_CALL = re.compile(r"""\b(?:langue|language)\(\s*(?:code\s*=\s*)?["']([A-Za-z]+)["']\s*\)""")
"""A call that sets the checks' language in a code cell: ex.langue("fr"), language('en'), langue(code="fr")."""


def notebook_language(text: str) -> str:
    """The hand-in's language, one of LANGUAGES: the last ex.langue("…") / ex.language("…") call in its code cells
    (what its checks print in), else its metadata rbcourse.language, else English."""
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
    """(the cells' seconds, the checks' seconds) within a hand-in's limit: the checks get a third, at most 60 s."""
    checks_seconds = min(timeout / 3, 60.0)
    return timeout - checks_seconds, checks_seconds


def limits(settings: Settings) -> dict:
    """The worker's limits (worker.set_limits); the process count only in a sandbox (elsewhere it counts every
    process of the user)."""
    out = {"memory": MEMORY, "cpu": int(settings.timeout + GRACE) + 1, "file_size": FILE_SIZE,
           "open_files": OPEN_FILES}
    if settings.sandboxed:
        out.update(processes=PROCESSES, total_memory=TOTAL_MEMORY)
    return out


def _report(process, deadline: float) -> dict | None:
    """The worker's report of its cells, or None if none came by the deadline: only its known fields, each of its
    type and cut to size (what the hand-in's process says of itself is its own word, and no more than a line)."""
    try:
        message = process.channel.receive(deadline)
    except wire.Broken:
        return None
    if message.get("op") != "cells" or not isinstance(message.get("functions", {}), dict):
        return None
    return {"errors": [_cell(e) for e in message.get("errors", []) if isinstance(e, dict)][:50]
            if isinstance(message.get("errors"), list) else [],
            "interrupted": _cell(message["interrupted"]) if isinstance(message.get("interrupted"), dict) else None,
            "language": message.get("language") if message.get("language") in LANGUAGES else None,
            "functions": {str(k): v for k, v in message["functions"].items() if isinstance(v, dict)}}


def _cell(event: dict) -> dict:
    """A cell's error (or interruption) as the worker reported it: its numbers written out ("?" for one that is
    missing or not a finite number: the frame is the hand-in's own, and may be forged), and texts of a line."""
    def number(v):
        ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
        return f"{v:g}" if ok else "?"
    return {"cell": number(event.get("cell")), "cells": number(event.get("cells")),
            "seconds": number(event.get("seconds")), "first_line": str(event.get("first_line", ""))[:80],
            "error": " ".join(str(event.get("error", "")).split())[:300]}


def check_task(task) -> Graded:
    """check_one(*task): phase 1 of a class; a failure of the grader itself on one hand-in (no sandbox could start, a
    full disk) is that hand-in's row, status "error": the class goes on."""
    handin, settings = task
    try:
        return check_one(handin, settings)
    except Exception as err:        # noqa: BLE001 — one row, not the class
        return failed(Graded(handin.name, "error", timeout=settings.timeout, source=handin.source,
                             protected=settings.sandboxed, language=notebook_language(handin.text or "")), err)


def status_task(task) -> Graded:
    """run_one on (handin, settings, graded by check_task): phase 2 of a class; a failure of the grader is the row's
    (status "error"), its checks kept."""
    handin, settings, g = task
    try:
        return run_one(g, handin, settings)
    except Exception as err:        # noqa: BLE001 — one row, not the class
        return failed(g, err)


def failed(g: Graded, err: Exception) -> Graded:
    """g, where the grader itself failed (err): status "error", said in its note; no phase 2."""
    g.status, g.failed = "error", True
    remark(g, "failed", error=f"{type(err).__name__}: {' '.join(str(err).split())[:200]}")
    return g


def grade_task(task) -> Graded:
    """grade_one(*task), guarded: both phases of one hand-in."""
    return status_task((*task, check_task(task)))


STOP_WAIT = 5.0     # s: a sandbox's processes are gone this long after their kill (then its control groups go)


def grade_one(handin: Handin, settings: Settings, clock=time.monotonic) -> Graded:
    """Grade one hand-in (see the module's docstring): its checks, then its status."""
    return run_one(check_one(handin, settings, clock), handin, settings, clock)


def _begin(handin: Handin, g: Graded, seconds: float) -> dict:
    """What a worker is sent first: the notebook's code cells, their language, their seconds, the graded names."""
    return {"cells": code_cells(json.loads(handin.text)), "language": g.language, "seconds": seconds,
            "names": [name for name, _ in checks()]}


def _sandboxed(mode: str, handin: Handin, g: Graded, settings: Settings, seconds: float, work, clock):
    """Start the hand-in's worker in `mode` (its own sandbox, its own scratch folder), send it the notebook, and
    return work(process); whatever happens, no process, control group or file of it is left (a process still alive
    after STOP_WAIT s is remarked)."""
    shared = settings.cache if settings.sandboxed and mode == "run" else None
    scratch = Path(tempfile.mkdtemp(prefix="rbcourse-grade-"))
    process = None
    try:
        process = sandbox.start(mode, limits(settings), scratch, settings.sandboxed, shared)
        try:
            process.channel.send({**_begin(handin, g, seconds), "cache": "/grading/numba-cache" if shared else None},
                                 clock() + 30)
        except wire.Broken as err:        # it would wait for its notebook until its limit: killed now, and said
            process.kill()
            if not g.unsent:
                g.unsent = True
                remark(g, "unsent", error=str(err))
        return work(process)
    finally:
        if process is not None and not process.stop(wait=STOP_WAIT) and not g.left:
            g.left = True
            remark(g, "alive")
        if process is not None and process.cpu_seconds is not None:
            g.cpu_seconds = (g.cpu_seconds or 0.0) + process.cpu_seconds
        shutil.rmtree(scratch, ignore_errors=True)


def check_one(handin: Handin, settings: Settings, clock=time.monotonic) -> Graded:
    """Phase 1: the notebook where rbcourse is not installed, its graded functions checked (the grade)."""
    g = Graded(handin.name, "ok", timeout=settings.timeout, source=handin.source, protected=settings.sandboxed,
               language=notebook_language(handin.text or ""))
    if handin.text is None:
        g.status, g.failed = "invalid", True
        g.remark(f"{handin.source}: {handin.problem}")
        return g
    start = clock()
    cells_seconds, checks_seconds = budgets(settings.timeout)
    names = [name for name, _ in checks()]

    def work(serve):
        served = _report(serve, start + cells_seconds + GRACE)
        g.problem = "its process ended before its functions could be checked"
        if served is None:
            return
        g.language = served["language"] or g.language
        g.checked_while_running = bool(served.get("interrupted"))
        g.checks, g.problem = check_all(serve.channel, served["functions"], checks_seconds, g.language,
                                        g.checked_while_running, from_rbcourse(handin.text, names), settings.seed)
        try:
            serve.channel.send({"op": "quit"}, clock() + 1)
        except wire.Broken:
            pass
        g.finished = not g.problem

    _sandboxed("serve", handin, g, settings, cells_seconds, work, clock)
    g.seconds = clock() - start
    return g


def run_one(g: Graded, handin: Handin, settings: Settings, clock=time.monotonic) -> Graded:
    """Phase 2: the notebook as written, with the library (its status and errors, for the feedback); then g's note."""
    if g.failed:
        return g
    start = clock()

    def work(run):
        ran = _report(run, start + settings.timeout + GRACE)
        g.returncode = run.popen.poll()
        return ran, run.tail()

    ran, tail = _sandboxed("run", handin, g, settings, budgets(settings.timeout)[0], work, clock)
    _notebook(g, ran, tail, start, clock, settings.language)
    if not settings.sandboxed:
        remark(g, "not_protected")
    g.seconds += clock() - start
    return g


def _notebook(g: Graded, ran: dict | None, tail: str, start: float, clock, language: str = "en") -> None:
    """The status and the note (in `language`: NOTES) from what the notebook did (run) and what the checks found
    (serve: g)."""
    notes, said = [], NOTES[language]
    problem = g.problem
    if ran is not None:
        g.cell_errors, g.interrupted = ran["errors"], ran["interrupted"]
        if not g.checks and g.problem and ran["language"]:   # (else the checks' language, which the feedback quotes)
            g.language = ran["language"]
    cells_seconds = budgets(g.timeout)[0]
    if ran is None and clock() - start >= g.timeout + GRACE:
        g.status, g.timed_out = "timeout", True
        notes.append(said["killed"].format(limit=g.timeout + GRACE, timeout=g.timeout))
    elif g.interrupted:
        g.status = "timeout"
        i = g.interrupted
        notes.append(said["stopped"].format(cell=i.get('cell'), first_line=i.get('first_line', ''), seconds=cells_seconds))
    elif ran is None:
        g.status, g.ended = "error", True
        last = " ".join(tail.split()[-30:])
        notes.append(said["ended"].format(code=g.returncode) + (said["colon"] + last if last else ""))
    if g.cell_errors:
        g.status = "error" if g.status == "ok" else g.status
        first = g.cell_errors[0]
        notes.append(said["raised"].format(n=len(g.cell_errors), cell=first.get('cell'),
                                           first_line=first.get('first_line', ''), error=first.get('error', '')))
    g.note = " | ".join(notes + ([g.note] if g.note else []))
    if g.checked_while_running and not g.interrupted:
        g.status = "timeout"
        remark(g, "cell_running")
    late = [n for n, o in g.checks.items() if (o or {}).get("mistake") == "out_of_time"]
    if late:
        g.status = "timeout" if g.status in ("ok", "error") else g.status
        remark(g, "late", names=", ".join(late))
    if problem:
        g.status = "error" if g.status == "ok" else g.status
        remark(g, "unchecked", problem=problem)
