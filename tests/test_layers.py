"""The package's layers, read from the source: data flows one way (body + state + effects → dynamics →
integrator → trajectory → plots, viewer, bench, workbook).

- The physics (the flat engine at the top, methods/, exact/) never imports viz/, bench/ or workbook/,
  nor meshcat or matplotlib.
- No module imports another module's private name (a leading underscore).
"""
import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "rbcourse"
UPPER = ("viz", "bench", "workbook")
FACADES = {"__init__.py", "__main__.py"}        # the public contract and the command line re-export everything


def modules():
    return sorted(p for p in PKG.rglob("*.py") if "__pycache__" not in p.parts)


def dotted(path: Path) -> str:
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(path: Path, source: str | None = None):
    """(module imported, names imported) for every import in the file (or in `source`, read as if it
    were that file), relative ones resolved."""
    tree = ast.parse(path.read_text(encoding="utf-8") if source is None else source)
    here = dotted(path).split(".")
    package = here if path.name == "__init__.py" else here[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, []
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            yield mod, [a.name for a in node.names]


def layer(path: Path) -> str:
    rel = path.relative_to(PKG).parts
    return rel[0] if len(rel) > 1 and rel[0] in UPPER else "physics"


PHYSICS = [p for p in modules() if layer(p) == "physics" and p.name not in FACADES
           and p.relative_to(PKG).parts[0] not in FACADES]


@pytest.mark.parametrize("path", PHYSICS, ids=lambda p: str(p.relative_to(PKG)))
def test_physics_never_imports_the_upper_layers(path):
    bad = []
    for mod, names in imports(path):
        targets = [mod] + [f"{mod}.{n}" for n in names]
        for t in targets:
            if any(t == f"rbcourse.{u}" or t.startswith(f"rbcourse.{u}.") for u in UPPER):
                bad.append(t)
            if t.split(".")[0] in ("meshcat", "matplotlib"):
                bad.append(t)
    assert not bad, f"{path.relative_to(PKG)} (physics) imports {sorted(set(bad))}"


@pytest.mark.parametrize("path", modules(), ids=lambda p: str(p.relative_to(PKG)))
def test_no_module_imports_a_private_name_of_another(path):
    me = dotted(path)
    bad = [f"{mod}.{n}" for mod, names in imports(path) for n in names
           if mod.startswith("rbcourse") and mod != me and n.startswith("_") and not n.startswith("__")]
    bad += [mod for mod, _ in imports(path) if mod.startswith("rbcourse")
            and any(part.startswith("_") and not part.startswith("__") for part in mod.split("."))]
    assert not bad, f"{path.relative_to(PKG)} imports private names {bad}"


def test_the_checker_can_fail():
    """A physics file importing the viewer, and a private name, are both seen."""
    seen = list(imports(PKG / "methods" / "probe.py", "from ..viz import viewer\nfrom .adaptive import _S\n"))
    assert ("rbcourse.viz", ["viewer"]) in seen and ("rbcourse.methods.adaptive", ["_S"]) in seen
