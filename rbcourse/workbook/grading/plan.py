"""What `python -m rbcourse grade` will do, its arguments checked first; then doing it.

    handins(folder)            -> [Handin(name, source, text)]   (every notebook read into memory at once)
    check_arguments(…)         -> Plan: the hand-ins, the outputs (their folders created and probed), the limit
    grade(plan)                -> (graded, paths): each hand-in run in turn (runner.grade_one), the outputs written
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from . import runner
from .runner import Handin


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
        g = runner.grade_one(h, plan.timeout, plan.watched(), names)
        graded.append(g)
        if progress:
            passed = sum(1 for n in names if (g.checks.get(n) or {}).get("passed"))
            progress(f"{g.name}: {g.status}, {passed} of {len(names)} checks passed ({g.seconds:.1f} s)"
                     + (f" — {g.note}" if g.note else ""))
    return graded, write_all(graded, names, plan.out, plan.feedback, plan.gradescope)
