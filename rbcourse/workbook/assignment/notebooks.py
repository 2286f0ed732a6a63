"""Reading, writing and finding notebooks: the AssignmentError every step raises, the student notebook a solution
generates (student_path), a notebook read (read_notebook) and written as nbformat writes it (writes), a cell's
source, and the solution notebooks found by default (solution_notebooks)."""
from __future__ import annotations

import json
from pathlib import Path


class AssignmentError(ValueError):
    """A solution notebook that cannot generate its student version (the message names the file and cell)."""


def student_path(solution) -> Path:
    """The student notebook a solution notebook generates: solutions/X.ipynb -> X.ipynb beside solutions/."""
    solution = Path(solution)
    if solution.suffix != ".ipynb":
        raise AssignmentError(f"{solution}: not a notebook (expected a .ipynb file)")
    if solution.parent.name != "solutions":
        raise AssignmentError(f"{solution}: a solution notebook must be in a folder named solutions/ "
                              f"(it generates the notebook of the same name in the folder above)")
    return solution.parent.parent / solution.name


def read_notebook(path) -> dict:
    """The notebook at path as a dict (nbformat 4), or an AssignmentError naming the file."""
    path = Path(path)
    if not path.is_file():
        raise AssignmentError(f"{path}: no such file")
    try:
        nb = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise AssignmentError(f"{path}: not a readable notebook ({err})") from None
    if not isinstance(nb, dict) or nb.get("nbformat") != 4 or not isinstance(nb.get("cells"), list):
        raise AssignmentError(f"{path}: not a notebook in nbformat 4")
    return nb


def writes(nb: dict) -> str:
    """The notebook's JSON text, exactly as nbformat.write writes it (sorted keys, indent 1, a final newline)."""
    import nbformat
    return nbformat.writes(nbformat.from_dict(nb)) + "\n"


def source(cell: dict) -> str:
    """A cell's source as one string (nbformat stores a list of lines or a string)."""
    text = cell.get("source", "")
    return "".join(text) if isinstance(text, list) else text


def is_solution_cell(cell: dict) -> bool:
    """nbgrader's rule: a cell whose metadata nbgrader.solution is true."""
    return bool(cell.get("metadata", {}).get("nbgrader", {}).get("solution", False))


def notebooks_folders() -> list[Path]:
    """Where the solution notebooks are looked for by default: notebooks/ of the checkout holding this
    package (a checkout or an editable install), then notebooks/ of the current folder.  A wheel ships no
    notebooks: `assignment build` is a tool for a checkout."""
    here = Path(__file__).resolve().parents[3] / "notebooks"
    cwd = Path.cwd() / "notebooks"
    return [here] if here.resolve() == cwd.resolve() else [here, cwd]


def _shorter(path: Path) -> Path:
    """path relative to the current folder when it is inside it (as the messages show it)."""
    try:
        return path.resolve().relative_to(Path.cwd().resolve())
    except ValueError:
        return path


def solution_notebooks(folders=None) -> list[Path]:
    """Every notebook in notebooks/**/solutions/*.ipynb of the first folder that has any (sorted)."""
    folders = notebooks_folders() if folders is None else [Path(f) for f in folders]
    for folder in folders:
        found = sorted(p for p in folder.glob("**/solutions/*.ipynb") if ".ipynb_checkpoints" not in p.parts)
        if found:
            return [_shorter(p) for p in found]
    raise AssignmentError(f"no solution notebook (notebooks/**/solutions/*.ipynb) in "
                          f"{' or '.join(str(f) for f in folders)}: run it from a checkout of rbcourse, "
                          f"or name the solution notebooks")
