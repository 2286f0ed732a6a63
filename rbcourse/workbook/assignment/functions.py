"""The functions of a solution notebook, made without running the notebook (solution_functions): the tests check
the solution from the notebook itself, not from a copy."""
from __future__ import annotations

import ast
import linecache
from pathlib import Path

from .notebooks import AssignmentError, is_solution_cell, read_notebook, source


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
