"""One source, two versions: the student notebook is generated from the solution notebook.

The solution notebook is the single source.  A notebook in a ``solutions/`` folder generates the notebook
of the same name in the parent folder (``notebooks/solutions/01_exercise_euler.ipynb`` →
``notebooks/01_exercise_euler.ipynb``; ``notebooks/fr/solutions/X.ipynb`` → ``notebooks/fr/X.ipynb``),
by ``python -m rbcourse assignment build``.  The markers are nbgrader's, so an instructor can also use
nbgrader as is:

* **Code cells.**  A cell holding a solution has nbgrader's cell metadata
  ``{"nbgrader": {"solution": true, "grade": false, "locked": false, "grade_id": "<function name>",
  "schema_version": 3}}``, and its solution between the lines ``### BEGIN SOLUTION`` and
  ``### END SOLUTION``.  The student version has, instead of each region, at the region's indentation::

      # YOUR CODE HERE                (French, notebook metadata rbcourse.language == "fr": # VOTRE CODE ICI)
      raise NotImplementedError()

  Everything outside the regions stays: the signature, the docstring, a line such as ``x, R, P, L = X``,
  and the hint comments written just above ``### BEGIN SOLUTION``.  The checks say "not done yet" for
  a function that raises NotImplementedError, so the student version runs clean as shipped.
* **Markdown cells.**  Text between ``<!-- SOLUTION ONLY -->`` and ``<!-- /SOLUTION ONLY -->`` (inline or
  over several lines, the markers included) is removed from the student version: the title's
  "— solution", the sentence saying this is the solution notebook.  (nbgrader knows no such marker: a
  notebook released by nbgrader keeps these words.)
* **Everything else** — cells, cell ids, cell and notebook metadata — is copied unchanged.

Outputs.  The student notebook's stored outputs are made by running it (nbclient, this Python's kernel,
RBCOURSE_QUICK=1, its folder as the working directory), as nbval compares the cells marked
``# NBVAL_CHECK_OUTPUT`` with them; the outputs of cells tagged ``meshcat`` (a 3-D page, about 1 MB)
are not stored, and a cell's consecutive prints are one output (how they are cut depends on the kernel's
flushes).  The comparison with the stored student notebook (``--check``, and the tests) ignores outputs
and execution counts: it compares the cells' types, ids, sources and metadata, and the notebook's
metadata.  The JSON is written as nbformat writes it (sorted keys, indent 1): the same solution gives
the same bytes (two builds of notebook 01 gave identical files, figures included).

``solution_functions(path)`` runs the functions of a solution notebook without running the notebook: the
tests check the solution from the notebook itself, not from a copy.
"""
from __future__ import annotations

import ast
import copy
import json
import linecache
import os
import re
import subprocess
import sys
from pathlib import Path

BEGIN = "### BEGIN SOLUTION"
END = "### END SOLUTION"
ONLY = "<!-- SOLUTION ONLY -->"
ONLY_END = "<!-- /SOLUTION ONLY -->"
STUBS = {"en": ("# YOUR CODE HERE", "raise NotImplementedError()"),
         "fr": ("# VOTRE CODE ICI", "raise NotImplementedError()")}
MESHCAT_TAG = "meshcat"
CELL_TIMEOUT = 600          # s, per cell, when the student version is run
_ONLY_SPAN = re.compile(re.escape(ONLY) + r".*?" + re.escape(ONLY_END), re.S)


class AssignmentError(ValueError):
    """A solution notebook that cannot generate its student version (the message names the file and cell)."""


# ---------------------------------------------------------------------------------------------------
# Reading and writing notebooks
# ---------------------------------------------------------------------------------------------------

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


def language(nb: dict, path) -> str:
    """The notebook's language: metadata rbcourse.language, "en" by default."""
    lang = nb.get("metadata", {}).get("rbcourse", {}).get("language", "en")
    if lang not in STUBS:
        raise AssignmentError(f"{path}: notebook metadata rbcourse.language must be one of "
                              f"{', '.join(sorted(STUBS))}, got {lang!r}")
    return lang


def is_solution_cell(cell: dict) -> bool:
    """nbgrader's rule: a cell whose metadata nbgrader.solution is true."""
    return bool(cell.get("metadata", {}).get("nbgrader", {}).get("solution", False))


# ---------------------------------------------------------------------------------------------------
# Generating the student version
# ---------------------------------------------------------------------------------------------------

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


def _this_python_kernel():
    """A kernel manager that starts this Python (as nbval's --nbval-current-env)."""
    from jupyter_client.kernelspec import KernelSpec, KernelSpecManager
    from jupyter_client.manager import KernelManager

    class ThisPython(KernelSpecManager):
        def get_kernel_spec(self, kernel_name):
            return KernelSpec(argv=[sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
                              display_name="Python 3", language="python")
    return KernelManager(kernel_spec_manager=ThisPython(), kernel_name="python3")


def _joined_streams(outputs: list) -> list:
    """Consecutive stdout (or stderr) outputs as one: how a cell's printing is cut into outputs depends on
    when the kernel flushes, not on what it printed."""
    joined = []
    for out in outputs:
        last = joined[-1] if joined else None
        if (out.get("output_type") == "stream" and last is not None and last.get("output_type") == "stream"
                and last.get("name") == out.get("name")):
            last["text"] = source({"source": last["text"]}) + source({"source": out["text"]})
        else:
            joined.append(copy.deepcopy(out))
    return joined


def run(nb: dict, folder, label: str) -> dict:
    """The notebook with its outputs, run top to bottom under RBCOURSE_QUICK=1 in `folder`; the cells
    tagged meshcat keep no output; cell and notebook metadata unchanged.  A cell that raises is an
    AssignmentError naming it (label: the notebook's name)."""
    import nbformat
    from nbclient import NotebookClient
    from nbclient.exceptions import CellExecutionError
    node = nbformat.from_dict(copy.deepcopy(nb))
    client = NotebookClient(node, km=_this_python_kernel(), timeout=CELL_TIMEOUT, record_timing=False,
                            resources={"metadata": {"path": str(folder)}})
    saved = {key: os.environ.get(key) for key in ("RBCOURSE_QUICK", "MPLBACKEND")}
    os.environ["RBCOURSE_QUICK"] = "1"
    os.environ.pop("MPLBACKEND", None)
    try:
        client.execute(stderr=subprocess.DEVNULL)     # the kernel's own log (a cell's stderr is an output)
    except CellExecutionError as err:
        failed = next((i for i, c in enumerate(node.cells) if any(o.get("output_type") == "error"
                                                                  for o in c.get("outputs", []))), "?")
        ename, evalue = getattr(err, "ename", ""), getattr(err, "evalue", "")
        last = re.sub(r"\x1b\[[0-9;]*m", "", f"{ename}: {evalue}" if ename else str(err).strip().splitlines()[-1])
        last = " ".join(last.split())[:300]
        raise AssignmentError(f"{label}, cell {failed}: the generated student version raised when run: {last}") \
            from None
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value
    done = json.loads(json.dumps(node))
    for ran, cell in zip(done["cells"], nb["cells"]):
        ran["metadata"] = copy.deepcopy(cell.get("metadata", {}))
        if ran["cell_type"] == "code":
            ran["outputs"] = _joined_streams(ran["outputs"])
        if cell["cell_type"] == "code" and MESHCAT_TAG in cell.get("metadata", {}).get("tags", []):
            ran["outputs"], ran["execution_count"] = [], None
    done["metadata"] = copy.deepcopy(nb["metadata"])
    return done


def build(solution, *, execute: bool = True) -> tuple[Path, str]:
    """(the student notebook's path, its JSON text) generated from `solution`; execute: with its outputs
    (run as `run` says), else with none."""
    solution = Path(solution)
    target = student_path(solution)
    nb = generate(solution)
    if execute:
        nb = run(nb, target.parent, str(target))
    return target, writes(nb)


# ---------------------------------------------------------------------------------------------------
# Comparing with the stored student notebook
# ---------------------------------------------------------------------------------------------------

def _comparable(nb: dict) -> dict:
    """What the comparison looks at: cells' types, ids, sources, metadata; the notebook's metadata."""
    cells = [{"cell_type": c.get("cell_type"), "id": c.get("id"), "source": source(c),
              "metadata": c.get("metadata", {}), "attachments": c.get("attachments")} for c in nb["cells"]]
    return {"cells": cells, "metadata": nb.get("metadata", {}), "nbformat": (nb.get("nbformat"),
                                                                             nb.get("nbformat_minor"))}


def differences(stored: dict, generated: dict) -> list[str]:
    """How the stored student notebook differs from the generated one (outputs and execution counts
    aside): one line per difference, at most 5 cells named; [] when they agree."""
    a, b = _comparable(stored), _comparable(generated)
    found = []
    if len(a["cells"]) != len(b["cells"]):
        found.append(f"{len(a['cells'])} cells stored, {len(b['cells'])} generated")
    cells = [f"cell {index} ({y['cell_type']}): {', '.join(k for k in x if x[k] != y[k])} differ"
             for index, (x, y) in enumerate(zip(a["cells"], b["cells"])) if x != y]
    found += cells[:5] + ([f"and {len(cells) - 5} more cells"] if len(cells) > 5 else [])
    for key in ("metadata", "nbformat"):
        if a[key] != b[key]:
            found.append(f"the notebook's {key} differs")
    return found


def check(solution) -> list[str]:
    """[] if the stored student notebook is what `solution` generates (outputs aside), else its differences."""
    target = student_path(solution)
    generated = generate(solution)
    if not target.is_file():
        return [f"{target} is missing"]
    return differences(read_notebook(target), generated)


# ---------------------------------------------------------------------------------------------------
# Which solution notebooks
# ---------------------------------------------------------------------------------------------------

def notebooks_folders() -> list[Path]:
    """Where the solution notebooks are looked for by default: notebooks/ of the checkout holding this
    package (a checkout or an editable install), then notebooks/ of the current folder.  A wheel ships no
    notebooks: `assignment build` is a tool for a checkout."""
    here = Path(__file__).resolve().parents[2] / "notebooks"
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


# ---------------------------------------------------------------------------------------------------
# The solution's functions, from the notebook
# ---------------------------------------------------------------------------------------------------

def _parse(text: str, where: str) -> ast.Module:
    """A code cell's Python (IPython's %magic and !shell lines left out)."""
    lines = ["" if line.lstrip().startswith(("%", "!")) else line for line in text.split("\n")]
    try:
        return ast.parse("\n".join(lines), filename=where)
    except SyntaxError as err:
        raise AssignmentError(f"{where}, line {err.lineno}: not valid Python ({err.msg})") from None


def solution_functions(path) -> dict:
    """{name: function} for the functions a solution notebook defines, made without running the notebook.

    In one namespace, in the notebook's order: every top-level import of every code cell; every nbgrader
    solution cell in full; the top-level function definitions (``def``) of the other code cells (the
    functions the notebook gives, such as star).  Nothing else runs (no check, simulation or plot).
    Returns every function so defined; each solution cell must define the function its grade_id names.
    Tracebacks and inspect.getsource name the notebook and the cell.
    """
    path = Path(path)
    nb = read_notebook(path)
    namespace = {"__name__": f"rbcourse_solution_{path.stem}", "__builtins__": __builtins__}
    names, graded = [], []
    for index, cell in enumerate(nb["cells"]):
        if cell.get("cell_type") != "code":
            continue
        where = f"{path}, cell {index}"
        tree = _parse(source(cell), where)
        keep = [node for node in tree.body if isinstance(node, (ast.Import, ast.ImportFrom))
                or (isinstance(node, ast.FunctionDef) and not is_solution_cell(cell))]
        if is_solution_cell(cell):
            keep = tree.body
            graded.append((cell["metadata"]["nbgrader"].get("grade_id"), where))
        if not keep:
            continue
        filename = f"<{where}>"
        linecache.cache[filename] = (len(source(cell)), None, source(cell).splitlines(True), filename)
        try:
            exec(compile(ast.Module(body=keep, type_ignores=[]), filename, "exec"), namespace)
        except Exception as err:        # noqa: BLE001 — reported with the cell it came from
            raise AssignmentError(f"{where}: defining its functions raised {type(err).__name__}: {err}") from err
        names += [node.name for node in keep if isinstance(node, ast.FunctionDef)]
    for grade_id, where in graded:
        if grade_id not in names:
            raise AssignmentError(f"{where}: its grade_id {grade_id!r} names no function it defines")
    return {name: namespace[name] for name in dict.fromkeys(names)}
