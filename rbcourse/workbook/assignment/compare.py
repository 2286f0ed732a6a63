"""Comparing the stored student notebook with the one its solution generates, outputs and execution counts aside
(differences; check: the command's --check and the tests)."""
from __future__ import annotations

from .notebooks import read_notebook, source, student_path
from .student import generate


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
