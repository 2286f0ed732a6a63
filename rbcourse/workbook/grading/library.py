"""Does a graded function take its answer from rbcourse?  Read from the notebook's source — the grader's own copy,
never from the student's process.

    from_rbcourse(notebook, names) -> {name: what it refers to}      e.g. {"box_inertia": "rb.RigidBody.box"}

A function is reported when its definition (its body, default values and decorators) refers to a name bound by
an import from rbcourse (``import rbcourse as rb``, ``from rbcourse.state import inverse_inertia``), imports
rbcourse itself, or names it as a module in a string: a string that is a module's name ("rbcourse.state"), or
one handed to what loads or runs code (``__import__("rbcourse")``, ``exec("import rbcourse")``,
``sys.modules["rbcourse"]``) — never a word in a message ("not rbcourse's answer").  It is followed through the
notebook's own functions and names it uses (a helper, ``table = {…: rb.simulate(…)}``) to the end, but not
into another graded function: that one is reported on its own, and a graded function that calls it computes
the rest itself (it is checked on what it does).  Each name is
taken as the notebook leaves it: its last definition or assignment in the order of the cells.  KEPT names
compute nothing of the exercise (the tuple X = (x, R, P, L) the checks pass): using them is fine.

What the source cannot show (a name built at run time and run with exec) the second run shows instead: there
rbcourse is not installed at all (standin.py), and a function that reaches it raises.
"""
from __future__ import annotations

import ast
import json
import re

from .worker import MAX_CELL, code_size

KEPT = {"StateTuple"}
LOADERS = {"__import__", "import_module", "exec", "eval", "compile", "run_module", "run_path", "find_spec",
           "reload", "getattr"}
"""What loads a module or runs code from a string: a string handed to one of them that names rbcourse uses it."""
MODULE_NAME = re.compile(r"\s*rbcourse(\.[A-Za-z_]\w*)*\s*$")


MAGIC = re.compile(r"^(\s*)(?:([A-Za-z_]\w*(?:\s*,\s*[A-Za-z_]\w*)*)\s*=\s*)?[!%]")
"""A line of IPython's shell or magic syntax (!ls, %time x = f(), files = !ls), with its indentation and the names
it assigns."""


def python_of(source: str) -> str | None:
    """A code cell's Python, its magic lines read in one pass: a shell or line magic is `pass` (names it assigns
    are None); a cell magic (%%bash, %%time: its body is a string to IPython) is no Python (None).  Linear in the
    cell's size: IPython's own transformer re-reads a cell once per magic line (and gives up after 500)."""
    if source.lstrip().startswith("%%"):
        return None
    lines = []
    for line in source.split("\n"):
        m = MAGIC.match(line)
        if m is None:
            lines.append(line)
        elif m.group(2):
            lines.append(f"{m.group(1)}{m.group(2)} = None")
        else:
            lines.append(f"{m.group(1)}pass")
    return "\n".join(lines)


def _cells(notebook: str) -> list[ast.Module]:
    """Each code cell as Python (python_of: its magic lines read as such); a cell that does not parse is left out
    (it raises when it runs, too), and so is one that is not run (worker.MAX_CELL: its parse tree alone would
    take the grader's memory)."""
    try:
        cells = json.loads(notebook).get("cells", [])
    except (ValueError, AttributeError):
        return []
    out = []
    for cell in cells if isinstance(cells, list) else []:
        if not isinstance(cell, dict) or cell.get("cell_type") != "code":
            continue
        source = cell.get("source", "")
        source = "".join(map(str, source)) if isinstance(source, list) else str(source)
        source = python_of(source) if len(source) <= MAX_CELL or code_size(source) <= MAX_CELL else None
        if source is None:
            continue
        try:
            out.append(ast.parse(source))
        except (SyntaxError, ValueError, RecursionError, MemoryError):
            continue
    return out


def _from_rbcourse(node) -> dict:
    """The names an import binds, each with what it is ("rb: import rbcourse as rb"), when it imports rbcourse."""
    if isinstance(node, ast.Import):
        return {(a.asname or a.name.split(".")[0]): a.name for a in node.names
                if a.name == "rbcourse" or a.name.startswith("rbcourse.")}
    if isinstance(node, ast.ImportFrom) and not node.level and node.module and (
            node.module == "rbcourse" or node.module.startswith("rbcourse.")):
        return {(a.asname or a.name): f"{node.module}.{a.name}" for a in node.names if a.name not in KEPT}
    return {}


def _direct(tree) -> str | None:
    """rbcourse imported or named in a string (not a docstring) anywhere inside `tree` (a function's definition)."""
    docstrings = {id(body[0].value) for node in ast.walk(tree)
                  if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))
                  for body in [node.body] if body and isinstance(body[0], ast.Expr)}
    loading = set()                      # the strings inside what loads a module or runs code (LOADERS, x.modules[…])
    for node in ast.walk(tree):
        func = node.func if isinstance(node, ast.Call) else None
        name = getattr(func, "id", None) or getattr(func, "attr", None)
        if name in LOADERS or (isinstance(node, ast.Subscript) and getattr(node.value, "attr", "") == "modules"):
            loading |= {id(n) for n in ast.walk(node)}
    for node in ast.walk(tree):
        if id(node) in docstrings:
            continue
        found = _from_rbcourse(node)
        if found:
            return f"import {next(iter(found.values()))}"
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and "rbcourse" in node.value and (
                MODULE_NAME.match(node.value) or id(node) in loading):
            return repr(node.value[:60])
    return None


def _globals_read(tree) -> set[str]:
    """The names `tree` (a statement at the notebook's top level) reads from the notebook's namespace, by Python's
    own scoping (symtable): not a function's parameters or local variables, nor a comprehension's."""
    import symtable

    def walk(table, top):
        names = set()
        for symbol in table.get_symbols():
            if (symbol.is_referenced() and top) or (not top and symbol.is_global()):
                names.add(symbol.get_name())
        for child in table.get_children():
            names |= walk(child, False)
        return names
    try:
        return walk(symtable.symtable(ast.unparse(tree), "<cell>", "exec"), True)
    except (SyntaxError, ValueError, RecursionError):
        return set()


def _loads(tree) -> list[tuple[str, str]]:
    """The notebook's names `tree` reads, each with the longest expression reading it (rb.RigidBody.box for rb)."""
    read = _globals_read(tree)
    longest: dict[str, str] = {}
    order = []
    for node in ast.walk(tree):
        root = node
        while isinstance(root, ast.Attribute):
            root = root.value
        if isinstance(root, ast.Name) and root.id in read and isinstance(node, (ast.Attribute, ast.Name)):
            text = ast.unparse(node) if node is not root else root.id
            if root.id not in longest:
                order.append(root.id)
            if len(text) > len(longest.get(root.id, "")):
                longest[root.id] = text
    return [(name, longest[name]) for name in order]


def _targets(target) -> list[str]:
    return [n.id for n in ast.walk(target) if isinstance(n, ast.Name)]


class _Notebook:
    """Every top-level name of the notebook: what its last binding depends on (a definition, an assignment, an
    import), and what each rbcourse name is."""

    def __init__(self, cells):
        self.bindings: dict[str, ast.AST | None] = {}      # name -> the tree its value comes from (None: clean)
        self.rbcourse: dict[str, str] = {}                 # name -> the rbcourse name it is bound to
        for cell in cells:
            for stmt in cell.body:
                self._statement(stmt)

    def _bind(self, names, tree, rbcourse=None):
        for name in names:
            self.bindings[name] = tree
            if rbcourse is not None and name in rbcourse:
                self.rbcourse[name] = rbcourse[name]
            else:
                self.rbcourse.pop(name, None)

    def _statement(self, stmt):
        if isinstance(stmt, (ast.Import, ast.ImportFrom)):
            found = _from_rbcourse(stmt)
            names = [(a.asname or (a.name.split(".")[0] if isinstance(stmt, ast.Import) else a.name))
                     for a in stmt.names]
            self._bind(names, None, found)
        elif isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            self._bind([stmt.name], stmt)
            self._globals(stmt)
        elif isinstance(stmt, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = stmt.targets if isinstance(stmt, ast.Assign) else [stmt.target]
            self._bind([n for t in targets for n in _targets(t)], stmt)
        elif isinstance(stmt, (ast.For, ast.AsyncFor)):
            self._bind(_targets(stmt.target), stmt)
        elif isinstance(stmt, (ast.With, ast.AsyncWith)):
            self._bind([n for item in stmt.items if item.optional_vars for n in _targets(item.optional_vars)], stmt)
        for field in ("body", "orelse", "finalbody", "handlers"):
            if not isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                for inner in getattr(stmt, field, []) or []:
                    self._statement(inner)
        for node in ast.walk(stmt):                       # x := …, anywhere at the top level
            if isinstance(node, ast.NamedExpr) and not isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef)):
                self._bind([node.target.id], node)

    def _globals(self, definition):
        """A function that sets a global (global name; name = …): that name depends on the function."""
        declared = {n for node in ast.walk(definition) if isinstance(node, ast.Global) for n in node.names}
        for node in ast.walk(definition):
            if isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                for name in (n for t in targets for n in _targets(t) if n in declared):
                    self.bindings[name] = definition
                    self.rbcourse.pop(name, None)

    def finding(self, name: str, seen=None, graded=frozenset()) -> str | None:
        """What `name` takes from rbcourse, following the notebook's names it reads (not into the `graded` ones,
        reported on their own); None if nothing."""
        seen = set() if seen is None else seen
        if name in seen:
            return None
        seen.add(name)
        if name in self.rbcourse:
            return self.rbcourse[name]
        tree = self.bindings.get(name)
        if tree is None:
            return None
        direct = _direct(tree)
        if direct:
            return direct
        for read, text in _loads(tree):
            if read in self.rbcourse:
                return self.rbcourse[read] if text == read else text
            if read != name and read in self.bindings and read not in graded:
                found = self.finding(read, seen, graded)
                if found:
                    return f"{read} → {found}"
        return None


def from_rbcourse(notebook: str, names) -> dict[str, str]:
    """{name: what it takes from rbcourse} for each of `names` (the notebook's graded functions) that does."""
    book = _Notebook(_cells(notebook))
    names = list(names)
    out = {}
    for name in names:
        found = book.finding(name, graded=frozenset(names) - {name})
        if found:
            out[name] = found[:120]
    return out
