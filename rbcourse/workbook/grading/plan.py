"""What `python -m rbcourse grade` will do, its arguments checked first; then doing it.

    check_arguments(…)   -> Plan: the hand-ins (read, submissions.py), the outputs (their folders created and
                            probed), the limit, who runs the hand-ins, the sandbox (there, or refused)
    grade(plan)          -> (graded, paths): every hand-in checked, then run (runner.py), then the outputs written

The hand-ins run on `workers` processes at once (support/parallel.py, as `stability` runs its cells), or on a
Dask cluster: each is graded alone and the same way wherever it runs, and the rows are sorted by student, so the
CSV is the same whatever ran them.  The outputs are written by this process only, each whole (a temporary
file, then renamed), once every hand-in is done.  SUBMISSIONS is fingerprinted (submissions.fingerprint) before
and after: a change is said on stderr and in every row's note.
"""
from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from pathlib import Path

from ...support import parallel
from ...support.language import current, say
from . import sandbox, submissions
from .runner import REMARKS, Settings, check_task, remark, status_task


MIN_TIMEOUT, MAX_TIMEOUT, DEFAULT_TIMEOUT = 5.0, 3600.0, 300.0


@dataclass
class Plan:
    """What `grade` will do, its arguments checked: the hand-ins (read), where each output goes, who grades."""
    submissions: Path
    handins: list
    out: Path
    feedback: Path
    gradescope: Path | None
    timeout: float
    workers: int = 1
    scheduler: object = None        # a Dask scheduler's address or Client (then workers is not used)
    sandboxed: bool = True
    seed: int = 0                   # the check inputs' seed (0: the notebook's own; draw_seed: a secret one)


MAX_SEED = (1 << 48) - 1


def draw_seed() -> int:
    """A seed no student can know in advance (1 … MAX_SEED), for the check inputs of one grading."""
    import secrets
    return 1 + secrets.randbelow(MAX_SEED)


def check_seed(seed) -> int:
    """--seed: an integer from 0 to MAX_SEED (0: the inputs the notebook's own checks use); ValueError otherwise."""
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise ValueError(f"--seed must be an integer from 0 to {MAX_SEED}, got {seed!r}")
    return seed


def _folder(path: Path, flag: str, files, created: list) -> Path:
    """writable_folder(path), noting in `created` the folders it made (the missing ones, outermost first)."""
    from ...support.outputs import writable_folder
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


def check_arguments(submissions_folder, out, timeout=DEFAULT_TIMEOUT, feedback=None, gradescope=None, workers=1,
                    scheduler=None, sandboxed: bool = True) -> Plan:
    """Every argument of `grade`, checked before anything runs (a ValueError names the argument and what it may
    be); then the outputs' folders are created and probed (a folder created for a probe that failed is removed)."""
    if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) \
            or not MIN_TIMEOUT <= timeout <= MAX_TIMEOUT:
        raise ValueError(f"--timeout must be from {MIN_TIMEOUT:g} to {MAX_TIMEOUT:g} seconds, got {timeout!r}")
    workers = parallel.check_workers(workers)
    if not isinstance(submissions_folder, (str, os.PathLike)) or str(submissions_folder) == "":
        raise ValueError("SUBMISSIONS must name a folder, got ''")
    folder = Path(submissions_folder)
    if not folder.is_dir():
        raise ValueError(f"SUBMISSIONS: {folder} is not a folder" + ("" if folder.exists() else " (it does not exist)"))
    found = submissions.read(folder)
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
    if sandboxed:
        why = sandbox.missing()
        if why:
            raise ValueError(f"no sandbox for the hand-ins: {why}")
    created = []
    try:
        out = _output_file(out, "--out", created)
        from .report import feedback_names
        feedback = _folder(feedback, "--feedback", list(feedback_names(found).values()), created)
        if gradescope is not None:
            gradescope = _output_file(gradescope, "--gradescope", created)
    except ValueError:
        for path in reversed(created):
            try:
                path.rmdir()
            except OSError:
                pass
        raise
    return Plan(folder, found, out, feedback, gradescope, float(timeout), workers, scheduler, bool(sandboxed))


EXERCISE_METHODS = ("euler", "euler_project", "quaternion_euler", "quaternion_euler_body", "rk4")
"""The methods the exercise notebook runs (notebooks/01_exercise_euler.ipynb; tests/workbook/test_grade.py keeps
them in step)."""


def engine_cache(progress=print) -> Path | None:
    """This machine's compiled engine (numba's cache), shared read-only with each sandbox: the exercise's methods
    are compiled into it first, here (`python -m rbcourse compile`: nothing to do where they are compiled already),
    so that no hand-in compiles them again.  (Both asked of another process: numba is not loaded in this one, which
    only waits for its workers — some 60 MB fewer.)"""
    import subprocess
    where = subprocess.run([sys.executable, "-c", "from rbcourse.engine import jit; print(jit.cache_folder() or '')"],
                           stdin=subprocess.DEVNULL, capture_output=True, text=True, check=False)
    if not where.stdout.strip():
        return None
    if progress:
        progress(say("compiling the exercise's methods into this machine's cache first (once), shared read-only with "
                     "every sandbox",
                     "les méthodes de l'exercice sont d'abord compilées dans le cache de cette machine (une fois), "
                     "partagé en lecture seule avec chaque bac à sable"))
    subprocess.run([sys.executable, "-m", "rbcourse", "compile", "--methods", ",".join(EXERCISE_METHODS)],
                   stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    folder = Path(where.stdout.strip().splitlines()[-1])
    return folder if folder.is_dir() else None


def grade(plan: Plan, progress=print, warn=None) -> tuple[list, list]:
    """Grade every hand-in of the plan, then write the outputs.  Returns (graded, paths).  warn(line): what the
    grader says on stderr (not protected; SUBMISSIONS changed)."""
    from .checker import checks
    from .report import texts, write_all
    warn = warn or (lambda line: print(line, file=sys.stderr))
    names = [name for name, _ in checks()]
    if not plan.sandboxed:
        warn(say("WARNING: the grades are not protected: every notebook runs without a sandbox (--no-sandbox), "
                 "with access to the grader's files, processes and network",
                 "ATTENTION : les notes ne sont pas protégées : chaque notebook tourne sans bac à sable "
                 "(--no-sandbox), avec accès aux fichiers, aux processus et au réseau du correcteur"))
    before = submissions.fingerprint(plan.submissions)
    if progress:                    # the grader's own log: the seed reproduces these inputs (grade --seed)
        progress(say(f"check inputs drawn from seed {plan.seed} (grade --seed {plan.seed} draws them again)",
                     f"entrées des vérifications tirées de la graine {plan.seed} (grade --seed {plan.seed} les "
                     "retire à l'identique)"))
    settings = Settings(plan.timeout, plan.sandboxed, engine_cache(progress) if plan.sandboxed else None, current(),
                        plan.seed)
    tasks = [(h, settings) for h in plan.handins]
    checked = [None] * len(tasks)         # 1. every hand-in's checks; 2. then every hand-in's run (runner.py)
    for i, g in parallel.run_tasks(check_task, tasks, plan.workers, plan.scheduler):
        checked[i] = g
    graded = [None] * len(tasks)
    for i, g in parallel.run_tasks(status_task, [(h, s, g) for (h, s), g in zip(tasks, checked)], plan.workers,
                                   plan.scheduler):
        graded[i] = g
        if progress:
            passed = sum(1 for n in names if (g.checks.get(n) or {}).get("passed"))
            status = texts(current())["status_word"].get(g.status, g.status)
            cpu = "" if g.cpu_seconds is None else say(f", {g.cpu_seconds:.1f} s of CPU", f", {g.cpu_seconds:.1f} s de CPU")
            progress(say(f"{g.name}: {status}, {passed} of {len(names)} checks passed ({g.seconds:.1f} s{cpu})",
                         f"{g.name} : {status}, {passed} vérifications réussies sur {len(names)} ({g.seconds:.1f} s{cpu})")
                     + (f" — {g.note}" if g.note else ""))
    changed = submissions.changes(before, submissions.fingerprint(plan.submissions))
    if changed:
        changes = "; ".join(changed[:5]) + (" …" if len(changed) > 5 else "")
        warn(REMARKS["en"]["changed"].format(changes=changes))
        for g in graded:
            remark(g, "changed", changes=changes)
    return graded, write_all(graded, names, plan.out, plan.feedback, plan.gradescope, warn)


def summary(graded, paths, plan: Plan) -> str:
    """What `grade` prints at the end: the hand-ins by status, and what it wrote."""
    counts = {s: sum(g.status == s for g in graded) for s in ("ok", "error", "timeout", "invalid")}
    files = len(paths) - 1 - bool(plan.gradescope)
    from .report import texts
    word = texts(current())["status_word"]
    s = "s" if len(graded) > 1 else ""                               # French plurals: 2 and more
    return (say(f"graded {len(graded)} hand-ins: ", f"{len(graded)} rendu{s} noté{s} : ")
            + ", ".join(f"{n} {word.get(s, s)}" for s, n in counts.items() if n) + "\n"
            + say(f"wrote {paths[0]} and {files} feedback files in {plan.feedback}",
                  f"écrit : {paths[0]} et {files} fichier{'s' if files > 1 else ''} de retour dans {plan.feedback}")
            + (say(f", and {paths[-1]}", f", et {paths[-1]}") if plan.gradescope else ""))
