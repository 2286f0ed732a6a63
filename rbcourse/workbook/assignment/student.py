"""Generating the student version of a solution notebook (generate): each ### BEGIN/END SOLUTION region replaced by
the stub of the notebook's language (STUBS), each <!-- SOLUTION ONLY --> span of markdown removed, every
nbgrader solution cell checked (a region, a grade_id of its own)."""
from __future__ import annotations

import copy
import re
from pathlib import Path

from .notebooks import AssignmentError, is_solution_cell, read_notebook, source, student_path

BEGIN = "### BEGIN SOLUTION"
END = "### END SOLUTION"
ONLY = "<!-- SOLUTION ONLY -->"
ONLY_END = "<!-- /SOLUTION ONLY -->"
STUBS = {"en": ("# YOUR CODE HERE", "raise NotImplementedError()"),
         "fr": ("# VOTRE CODE ICI", "raise NotImplementedError()")}
_ONLY_SPAN = re.compile(re.escape(ONLY) + r".*?" + re.escape(ONLY_END), re.S)


def language(nb: dict, path) -> str:
    """The notebook's language: metadata rbcourse.language, "en" by default."""
    lang = nb.get("metadata", {}).get("rbcourse", {}).get("language", "en")
    if lang not in STUBS:
        raise AssignmentError(f"{path}: notebook metadata rbcourse.language must be one of "
                              f"{', '.join(sorted(STUBS))}, got {lang!r}")
    return lang


def clear_regions(text: str, stub: tuple[str, str], where: str) -> tuple[str, int]:
    """The code with each ### BEGIN/END SOLUTION region replaced by the stub at the region's indentation;
    and the number of regions.  where: "FILE, cell N" for the errors."""
    out, begun, count = [], None, 0
    for number, line in enumerate(text.split("\n"), start=1):
        mark = line.strip()
        if mark not in (BEGIN, END) and ("BEGIN SOLUTION" in line or "END SOLUTION" in line):
            raise AssignmentError(f"{where}, line {number}: write {BEGIN!r} and {END!r} alone on their line, "
                                  f"got {mark!r}")
        if mark == BEGIN:
            if begun is not None:
                raise AssignmentError(f"{where}, line {number}: {BEGIN} inside the region begun line {begun} "
                                      f"(regions do not nest)")
            begun, count = number, count + 1
            indent = line[:len(line) - len(line.lstrip())]
            out.extend(indent + s for s in stub)
        elif mark == END:
            if begun is None:
                raise AssignmentError(f"{where}, line {number}: {END} with no {BEGIN} before it")
            begun = None
        elif begun is None:
            out.append(line)
    if begun is not None:
        raise AssignmentError(f"{where}, line {begun}: {BEGIN} with no {END} after it")
    return "\n".join(out), count


def clear_solution_only(text: str, where: str) -> str:
    """The markdown with each <!-- SOLUTION ONLY --> … <!-- /SOLUTION ONLY --> span removed."""
    if "BEGIN SOLUTION" in text or "END SOLUTION" in text:
        raise AssignmentError(f"{where}: a markdown cell holds {BEGIN}/{END}: in markdown, mark the words "
                              f"the student must not see with {ONLY} … {ONLY_END}")
    kept = _ONLY_SPAN.sub("", text)
    for marker in (ONLY, ONLY_END):
        if marker in kept:
            raise AssignmentError(f"{where}: {marker} with no matching "
                                  f"{ONLY_END if marker == ONLY else ONLY} (they go in pairs, "
                                  f"{ONLY} first)")
    return kept


def _check_solution_cell(cell: dict, where: str, regions: int, ids: dict):
    """A cell with regions must be an nbgrader solution cell, with a grade_id of its own."""
    if not regions:
        raise AssignmentError(f"{where}: an nbgrader solution cell with no {BEGIN} … {END} region (nbgrader "
                              f"would replace the whole cell): put the solution between the markers")
    grade_id = cell["metadata"]["nbgrader"].get("grade_id")
    if not isinstance(grade_id, str) or not grade_id:
        raise AssignmentError(f"{where}: nbgrader metadata without a grade_id (the name of the function)")
    if grade_id in ids:
        raise AssignmentError(f"{where}: grade_id {grade_id!r} is already the grade_id of {ids[grade_id]}")
    ids[grade_id] = where


def generate(solution) -> dict:
    """The student notebook generated from the solution notebook at `solution` (no outputs)."""
    solution = Path(solution)
    student_path(solution)
    nb = copy.deepcopy(read_notebook(solution))
    stub = STUBS[language(nb, solution)]
    ids: dict[str, str] = {}
    for index, cell in enumerate(nb["cells"]):
        where = f"{solution}, cell {index}"
        text = source(cell)
        if cell.get("cell_type") == "code":
            text, regions = clear_regions(text, stub, where)
            if is_solution_cell(cell):
                _check_solution_cell(cell, where, regions, ids)
            elif regions:
                raise AssignmentError(f"{where}: a {BEGIN} region in a cell without nbgrader solution metadata "
                                      f"(add {{\"nbgrader\": {{\"solution\": true, \"grade\": false, "
                                      f"\"locked\": false, \"grade_id\": \"<function name>\", "
                                      f"\"schema_version\": 3}}}} to the cell's metadata)")
            cell["outputs"], cell["execution_count"] = [], None
        elif cell.get("cell_type") == "markdown":
            text = clear_solution_only(text, where)
        cell["source"] = text
    if not ids:
        raise AssignmentError(f"{solution}: no nbgrader solution cell (nothing for the student to write)")
    return nb
