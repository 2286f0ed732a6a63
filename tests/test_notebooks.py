"""The workbook's notebooks as files: present, listed, small, and with stored outputs nbval can trust.

Running them is nbval's job (pyproject.toml: `python -m pytest` collects notebooks/ with --nbval-lax):
every cell must run, and a cell tagged `nbval-check-output` (its metadata: the student reads code only, no
test-harness line) must reproduce its stored output.  These checks keep those stored outputs meaningful: they exist, they hold nothing that changes
from run to run or machine to machine (addresses, URLs, times, temporary paths), and the notebooks stay
small enough to commit (the 3-D pages, about 1 MB each, are not stored).
"""
import ast
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
EXPECTED = ["00_course_walkthrough.ipynb", "01_exercise_euler.ipynb", "02_drift.ipynb", "03_accuracy_vs_time.ipynb",
            "04_hard_cases.ipynb", "05_scenes.ipynb", "demo_instructor.ipynb", "solutions/01_exercise_euler.ipynb",
            "fr/00_parcours_du_cours.ipynb", "fr/01_exercice_euler.ipynb", "fr/solutions/01_exercice_euler.ipynb",
            "fr/02_derive.ipynb", "fr/03_precision_et_temps.ipynb", "fr/04_cas_difficiles.ipynb", "fr/05_scenes.ipynb",
            "fr/demo_enseignant.ipynb"]
ALL = sorted(p.relative_to(NOTEBOOKS).as_posix() for p in NOTEBOOKS.rglob("*.ipynb") if ".ipynb_checkpoints" not in p.parts)
FRENCH = [n for n in ALL if n.startswith("fr/")]     # the French edition: notebooks/fr/ (solutions in fr/solutions/)
MAX_BYTES = 1_000_000
CHECK = "nbval-check-output"        # the tag of a cell whose output nbval compares (nbval reads cell tags)

# what must never be in a checked output: it differs between runs or machines
UNSTABLE = {
    "a URL": re.compile(r"\b(?:https?|tcp|ws)://|127\.0\.0\.1|localhost", re.I),
    "a memory address": re.compile(r"\b0x[0-9a-f]{6,}\b", re.I),
    "a timestamp": re.compile(r"\b\d{4}-\d{2}-\d{2}[T ]\d{2}:\d{2}"),
    "a temporary or absolute path": re.compile(r"/tmp/|/home/|/root/|/work/|\b[A-Z]:\\"),
}


def load(name: str) -> dict:
    return json.loads((NOTEBOOKS / name).read_text(encoding="utf-8"))


def code_cells(nb: dict):
    return [c for c in nb["cells"] if c["cell_type"] == "code"]


def source(cell) -> str:
    return "".join(cell["source"]) if isinstance(cell["source"], list) else cell["source"]


def output_text(output) -> str:
    if output["output_type"] == "stream":
        text = output["text"]
    elif output["output_type"] == "error":
        text = "\n".join(output.get("traceback", []))
    else:
        text = json.dumps(output.get("data", {}), ensure_ascii=False)
    return "".join(text) if isinstance(text, list) else text


def test_every_expected_notebook_exists():
    missing = [n for n in EXPECTED if not (NOTEBOOKS / n).is_file()]
    assert not missing, f"notebooks missing from notebooks/: {missing}"


@pytest.mark.parametrize("name", ALL)
def test_listed_in_the_readme_and_the_workbook_page(name):
    """Each notebook is told in docs/workbook.md (its path), and the README's table names each one a student opens
    (its name without .ipynb; the solutions by their folders)."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    page = (ROOT / "docs" / "workbook.md").read_text(encoding="utf-8")
    assert name in page, f"{name} is not told in docs/workbook.md (section 'Your own copies')"
    shown = name.rsplit("/", 1)[0] + "/" if "solutions/" in name else name.removesuffix(".ipynb")
    assert shown in readme, f"{shown} is not listed in README.md (section 'The workbook')"


@pytest.mark.parametrize("name", ALL)
def test_small_enough_to_commit(name):
    size = (NOTEBOOKS / name).stat().st_size
    assert size < MAX_BYTES, (f"{name} is {size / 1e6:.2f} MB (limit 1 MB): clear the outputs of its meshcat cells "
                              "(each embedded page is about 1 MB) or shrink its figures")


@pytest.mark.parametrize("name", ALL)
def test_python_kernel(name):
    assert load(name)["metadata"].get("kernelspec", {}).get("name") == "python3"


@pytest.mark.parametrize("name", ALL)
def test_no_stored_error(name):
    errors = [source(c).splitlines()[:2] for c in code_cells(load(name))
              if any(o["output_type"] == "error" for o in c.get("outputs", []))]
    assert not errors, f"{name} stores cells that raised: {errors} (re-run it, or fix them)"


@pytest.mark.parametrize("name", ALL)
def test_no_stored_3d_page(name):
    pages = [source(c).splitlines()[:2] for c in code_cells(load(name))
             if any("srcdoc" in output_text(o) or "MeshCat" in output_text(o) for o in c.get("outputs", []))]
    assert not pages, f"{name} stores meshcat pages (about 1 MB each) in cells {pages}: clear those outputs"


@pytest.mark.parametrize("name", ALL)
def test_checked_cells_hold_stable_outputs(name):
    checked = [c for c in code_cells(load(name)) if CHECK in c.get("metadata", {}).get("tags", [])]
    assert checked, f"{name}: no cell tagged {CHECK}: nbval would compare nothing"
    for cell in checked:
        head = source(cell).splitlines()[:1]
        assert cell.get("outputs"), f"{name}: a checked cell has no stored output to compare with: {head}"
        for output in cell["outputs"]:
            text = output_text(output)
            assert output["output_type"] != "error", f"{name}: a checked cell stores an error: {head}"
            assert "image/png" not in output.get("data", {}), f"{name}: a checked cell stores a figure: {head}"
            for what, pattern in UNSTABLE.items():
                hit = pattern.search(text)
                assert hit is None, f"{name}: a checked cell's output holds {what} ({hit.group(0)!r}): {head}"


@pytest.mark.parametrize("name", ALL)
def test_no_cell_starts_with_a_test_harness_line(name):
    """nbval's markers are cell tags (nbval-check-output, nbval-ignore-output): no code cell shows the student a
    `# NBVAL_…` line."""
    marked = [source(c).splitlines()[:1] for c in code_cells(load(name)) if "NBVAL_" in source(c)]
    assert not marked, f"{name}: cells with an nbval comment (make it a tag): {marked}"


@pytest.mark.parametrize("name", ALL)
def test_a_live_server_is_closed_by_the_last_cell(name):
    cells = code_cells(load(name))
    starts = any(re.search(r"(?<!plt)\.show\(|(?<!close_)live_server\(", line) and not line.lstrip().startswith("#")
                 for c in cells for line in source(c).splitlines())
    if starts:
        assert "close_live_server()" in source(cells[-1]), (
            f"{name} starts a live meshcat server: its last code cell must call viewer.close_live_server()")



# English a French notebook must not hold in its prose (outside tables, code and formulas), nor in its check lines
ENGLISH = re.compile(r"\b(?:the|and|this|that|with|which|your|you|is|are|of|to|from|when|here|now|has|have|not)\b",
                     re.I)
ENGLISH_SENTENCES = ["The slides", "This notebook", "Check the", "What next", "Here is", "YOUR CODE HERE",
                     "Your code", "Run the", "at rest", "x and R move now", "walkthrough and simulate agree"]


def prose(markdown: str) -> str:
    """A markdown cell's sentences: without its tables, code (inline and fenced) and formulas."""
    text = re.sub(r"```.*?```|\$\$.*?\$\$|\$[^$\n]*\$|`[^`\n]*`", " ", markdown, flags=re.S)
    return "\n".join(line for line in text.splitlines() if not line.lstrip().startswith("|"))


def test_the_french_edition_exists():
    assert {"fr/00_parcours_du_cours.ipynb", "fr/01_exercice_euler.ipynb", "fr/solutions/01_exercice_euler.ipynb"} <= set(FRENCH)


@pytest.mark.parametrize("name", FRENCH)
def test_french_notebooks_are_french(name):
    nb = load(name)
    assert nb["metadata"].get("rbcourse", {}).get("language") == "fr", f"{name}: metadata rbcourse.language is not 'fr'"
    first_code = source(code_cells(nb)[0])
    assert re.search(r"""\blangue\(["']fr["']\)""", first_code), f"{name}: its first code cell does not call langue('fr')"
    for cell in nb["cells"]:
        text = source(cell)
        found = [s for s in ENGLISH_SENTENCES if s in text]
        assert not found, f"{name}: English in a cell: {found} in {text.splitlines()[:1]}"
        if cell["cell_type"] == "markdown":
            words = ENGLISH.findall(prose(text))
            assert not words, f"{name}: English words {sorted(set(words))} in the markdown {text.splitlines()[:1]}"
    outputs = "\n".join(output_text(o) for c in code_cells(nb) for o in c.get("outputs", []))
    found = [s for s in ENGLISH_SENTENCES if s in outputs]
    assert not found, f"{name}: English in the stored outputs: {found}"
    printed = "\n".join(output_text(o) for c in code_cells(nb) for o in c.get("outputs", []) if o["output_type"] == "stream")
    english = [line for line in printed.splitlines() if ENGLISH.search(line)]
    assert not english, f"{name}: printed lines in English: {english[:3]}"
    verdicts = [line for line in outputs.splitlines() if line.lstrip().startswith(("✓", "✗", "○"))]
    english = [line for line in verdicts if ENGLISH.search(re.sub(r"`[^`]*`|'[^']*'", " ", line))]
    assert not english, f"{name}: check lines in English: {english[:3]}"
    if "x(t) connu" in outputs:                                   # the walkthrough's lines (rb.walkthrough)
        assert "au repos" in outputs and "(état actuel de l'itération 2)" in outputs


# --- one source for both languages: an edition's code cells do what the English ones do ----------------------

EDITIONS = {"fr/00_parcours_du_cours.ipynb": "00_course_walkthrough.ipynb", "fr/01_exercice_euler.ipynb": "01_exercise_euler.ipynb",
            "fr/solutions/01_exercice_euler.ipynb": "solutions/01_exercise_euler.ipynb",
            "fr/02_derive.ipynb": "02_drift.ipynb", "fr/03_precision_et_temps.ipynb": "03_accuracy_vs_time.ipynb",
            "fr/04_cas_difficiles.ipynb": "04_hard_cases.ipynb", "fr/05_scenes.ipynb": "05_scenes.ipynb",
            "fr/demo_enseignant.ipynb": "demo_instructor.ipynb"}
"""Each French notebook and the English one it translates."""
SAYING = {"print", "join", "format", "replace", "split", "get", "items", "append", "langue", "outcome_said", "named",
          "startswith", "strip", "keys", "values", "count", "summary", "describe", "tolist", "len", "display", "Markdown",
          "repr", "str"}
"""Calls that only say things (print, format, the library's sentences): an edition may say them its own way."""


def code_shape(src: str):
    """What a code cell does, whatever language it speaks: its asserts (their conditions, every string blanked)
    and the functions it calls (but SAYING's)."""
    class Blank(ast.NodeTransformer):
        def visit_Constant(self, node):
            return ast.Constant(value="" if isinstance(node.value, str) else node.value)

        def visit_JoinedStr(self, node):
            return ast.Constant(value="")
    tree = ast.parse("\n".join(line for line in src.splitlines() if not line.lstrip().startswith(("%", "!"))))
    asserts = [ast.dump(Blank().visit(node.test)) for node in ast.walk(tree) if isinstance(node, ast.Assert)]
    calls = {node.func.id if isinstance(node.func, ast.Name) else getattr(node.func, "attr", None)
             for node in ast.walk(tree) if isinstance(node, ast.Call)}
    return asserts, sorted(calls - SAYING - {None})


@pytest.mark.parametrize("edition", sorted(EDITIONS))
def test_an_edition_has_the_cells_and_checks_of_the_english_notebook(edition):
    """The same cells (types, ids, tags) and, cell by cell, the same checks and the same calls: the editions
    cannot drift apart (README: one notebook per language, translated cell by cell)."""
    fr, en = load(edition), load(EDITIONS[edition])
    assert [(c["cell_type"], c.get("id")) for c in fr["cells"]] == [(c["cell_type"], c.get("id")) for c in en["cells"]], \
        f"{edition}: its cells (types, ids) are not those of {EDITIONS[edition]}"
    for a, b in zip(code_cells(fr), code_cells(en)):
        tags = lambda c: sorted(t for t in c.get("metadata", {}).get("tags", []) if t.startswith("nbval"))   # noqa: E731
        assert tags(a) == tags(b), f"{edition}, cell {a.get('id')}: nbval tags {tags(a)} vs {tags(b)}"
        shape_fr, shape_en = code_shape(source(a)), code_shape(source(b))
        assert shape_fr[0] == shape_en[0], f"{edition}, cell {a.get('id')}: its checks differ from the English cell's"
        extra, missing = set(shape_fr[1]) - set(shape_en[1]), set(shape_en[1]) - set(shape_fr[1])
        assert not missing and extra <= {"langue"}, \
            f"{edition}, cell {a.get('id')}: calls {sorted(extra)} more, {sorted(missing)} fewer than the English cell"


SHORT_RUNS = {"en": "*Stored outputs: they come from the short runs the tests make (`RBCOURSE_QUICK=1`).",
              "fr": "*Sorties enregistrées : elles viennent des runs courts que font les tests (`RBCOURSE_QUICK=1`)."}


@pytest.mark.parametrize("name", ALL)
def test_a_notebook_with_short_runs_says_so_at_the_top(name):
    """A notebook whose runs the tests shorten (it reads quick_mode) says, in its first text cell and in its own
    language, that its stored outputs come from the short runs — a student's Run All gives the full ones."""
    nb = load(name)
    if not any("quick_mode" in source(c) or "QUICK" in source(c) for c in code_cells(nb)):
        return
    first = next(source(c) for c in nb["cells"] if c["cell_type"] == "markdown")
    said = SHORT_RUNS[nb["metadata"].get("rbcourse", {}).get("language", "en")]
    assert said in first, f"{name}: its first text cell does not say its outputs come from the short runs"
