"""`python -m rbcourse notebooks [--to DIR] [--solutions]`: the student's own copies of the workbook.

A student works on copies, never on the repository's notebooks: a "Run All" and a save change a notebook (its
outputs), and a `git pull` would then conflict with the course's next edit.  The copies go to my_notebooks/
(git-ignored) by default, laid out as notebooks/ is (the English ones at the top, the French in fr/); the
solution notebooks (solutions/, fr/solutions/) only when asked (--solutions): the exercise is to write them.

A copy is never overwritten.  Each run compares every repository notebook with the one it last copied (the
SHA-256 of each source copied is kept in DIR/.rbcourse-copies.json): when the course changed that notebook since,
the new version is written beside the student's as NAME.updated.ipynb, to compare and take from; the student's copy
stays as it is.  A notebook the student deleted is copied again.
"""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

from ..support.outputs import writable_folder, write_text

DEFAULT = "my_notebooks"
RECORD = ".rbcourse-copies.json"


def workbook_folder() -> Path:
    """The repository's notebooks/ (a checkout: the wheel ships no notebooks)."""
    folder = Path(__file__).resolve().parents[2] / "notebooks"
    if not folder.is_dir():
        raise ValueError("the workbook's notebooks are not installed with the package (the wheel ships none): run "
                         "this from a clone of the repository")
    return folder


def sources(folder: Path, solutions: bool) -> list[str]:
    """The notebooks to copy, as paths relative to folder (sorted): every *.ipynb, solutions/ only if asked."""
    names = []
    for path in sorted(folder.rglob("*.ipynb")):
        rel = path.relative_to(folder)
        if ".ipynb_checkpoints" in rel.parts or (not solutions and "solutions" in rel.parts):
            continue
        names.append(rel.as_posix())
    return names


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def updated_name(rel: str) -> str:
    """Where a newer version of the notebook rel goes beside the student's copy: NAME.updated.ipynb."""
    return rel[: -len(".ipynb")] + ".updated.ipynb"


def copy_workbook(to=DEFAULT, *, solutions: bool = False, source: Path | None = None) -> list[tuple[str, str]]:
    """Copy the workbook into the folder `to` (created if missing); returns (what happened, path) per notebook:
    "copied" (a new copy), "kept" (the student's copy, the course's unchanged since), "updated" (the course changed
    it: NAME.updated.ipynb written beside the student's copy, which is kept).  A `to` that is a file or cannot be
    written raises ValueError naming --to; so does a `to` inside the repository's notebooks/."""
    if not isinstance(solutions, bool):
        raise ValueError(f"solutions must be True or False, got {solutions!r}")
    source = workbook_folder() if source is None else Path(source)
    to = writable_folder(to, "--to")
    if to.resolve() == source.resolve() or source.resolve() in to.resolve().parents:
        raise ValueError(f"--to must be a folder outside the workbook's notebooks ({source}), got {to}")
    record_path = to / RECORD
    try:
        record = json.loads(record_path.read_text(encoding="utf-8")) if record_path.exists() else {}
    except (OSError, ValueError):
        record = {}                     # an unreadable record: every existing copy is then compared as changed
    done = []
    for rel in sources(source, solutions):
        src, dest = source / rel, to / rel
        digest = _digest(src)
        if not dest.exists():
            dest.parent.mkdir(parents=True, exist_ok=True)
            write_text(dest, src.read_text(encoding="utf-8"))
            record[rel] = digest
            done.append(("copied", str(dest)))
        elif record.get(rel) == digest:
            done.append(("kept", str(dest)))
        else:
            newer = to / updated_name(rel)
            write_text(newer, src.read_text(encoding="utf-8"))
            done.append(("updated", str(newer)))
    write_text(record_path, json.dumps(record, indent=1, sort_keys=True) + "\n")
    return done


def report(done: list[tuple[str, str]], to) -> str:
    """The command's lines: each notebook copied or updated, then a count, and what to do with an updated one."""
    lines = [f"copied  {p}" for what, p in done if what == "copied"]
    lines += [f"updated {p}  (the course changed it since your copy: compare, take what you want; your copy is "
              f"unchanged)" for what, p in done if what == "updated"]
    n = {k: sum(1 for what, _ in done if what == k) for k in ("copied", "kept", "updated")}
    lines.append(f"{n['copied']} copied, {n['kept']} kept as they were, {n['updated']} with a newer version beside "
                 f"them, in {to}: open them with `jupyter lab {to}`")
    return "\n".join(lines)
