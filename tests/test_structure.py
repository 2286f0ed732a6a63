"""The package's shape, read from the source: the kernel (rbcourse/engine/) at the bottom, importing nothing of
rbcourse outside it; no import cycle between files (imports inside functions counted); one concept a file, no
.py or .js file over 400 lines."""
import ast
from pathlib import Path

import pytest

from test_layers import PKG, dotted, imports, modules

MAX_LINES = 400
ENGINE = PKG / "engine"


def files_imported(path: Path, source: str | None = None, known=None) -> set[str]:
    """The rbcourse modules (files) a file imports, anywhere in it: `from . import x` names the module x when x
    is one, else the package; `from .m import name` names m."""
    known = known if known is not None else {dotted(p) for p in modules()}
    out = set()
    for mod, names in imports(path, source):
        subs = [f"{mod}.{n}" for n in names if f"{mod}.{n}" in known]
        out.update(subs)
        if mod in known and len(subs) < len(names) or (mod in known and not names):
            out.add(mod)
    out.discard(dotted(path))
    return {m for m in out if m in known}


def cycles(graph: dict) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_no_import_cycle_between_files():
    graph = {dotted(p): files_imported(p) for p in modules()}
    assert not cycles(graph), f"import cycles (lazy imports counted): {cycles(graph)}"


def test_the_cycle_finder_can_fail():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    lazy = "def f():\n    from .state import State\n"
    assert "rbcourse.state" in files_imported(PKG / "rotation.py", lazy)


@pytest.mark.parametrize("path", sorted(ENGINE.glob("*.py")), ids=lambda p: p.name)
def test_the_kernel_imports_nothing_of_rbcourse_outside_it(path):
    bad = [m for m in files_imported(path) | {mod for mod, _ in imports(path)}
           if m.startswith("rbcourse") and not m.startswith("rbcourse.engine")]
    assert not bad, f"engine/{path.name} imports {sorted(set(bad))}"


def test_the_kernel_check_can_fail():
    assert "rbcourse.state" in files_imported(ENGINE / "system.py", "from ..state import State\n")


@pytest.mark.parametrize("path", sorted(p for p in PKG.rglob("*") if p.suffix in (".py", ".js")
                                        and "__pycache__" not in p.parts), ids=lambda p: str(p.relative_to(PKG)))
def test_one_concept_a_file_at_most_400_lines(path):
    n = len(path.read_text(encoding="utf-8").splitlines())
    assert n <= MAX_LINES, f"{path.relative_to(PKG)} has {n} lines (at most {MAX_LINES}: split it by concept)"


def test_one_plotting_code_and_one_3d_renderer_in_the_pages_scripts():
    """The pages' scripts (rbcourse/**/*.js: the linked view's, the explorer's split by concept) draw on a 2-D canvas
    only through viewer/js/timeplots.js (besides the runtime's contact sheet of frames) (RbPlot: the linked view's plots and the explorer's drift panels; rbFit, the
    axis helpers the work-precision panel uses), and in 3-D only through meshcat's viewer (no WebGL of their own)."""
    js = {p.relative_to(PKG).as_posix(): p.read_text(encoding="utf-8") for p in PKG.rglob("*.js")}
    assert "viz/explorer/js/scene.js" in js and "viz/viewer/js/timeplots.js" in js
    assert sorted(k for k, s in js.items() if "getContext(" in s) == ["viz/viewer/js/runtime.js",
                                                                       "viz/viewer/js/timeplots.js"]
    runtime = js["viz/viewer/js/runtime.js"]      # there, only the contact sheet's canvas (#sheet=: frames of a GIF)
    assert runtime.count("getContext(") == 1 and runtime.index("getContext(") > runtime.index("function sheet(")
    assert not [k for k, s in js.items() if "webgl" in s.lower()]
    assert sorted(k for k, s in js.items() if "new RbPlot(" in s) == ["viz/explorer/js/panels.js",
                                                                      "viz/viewer/js/timeplots.js"]
    assert "new MeshCat.Viewer(" in js["viz/explorer/js/scene.js"]


MAX_TOP_MODULES = 18
FLOORS = {          # (importer's folder, folder it must not import from): each piece on its floor
    ("rbcourse.viz", "rbcourse.workbook"), ("rbcourse.workbook.grading", "rbcourse.bench"),
    ("rbcourse.support", "rbcourse"), ("rbcourse.examples", "rbcourse.viz"), ("rbcourse.examples", "rbcourse.bench"),
    ("rbcourse.examples", "rbcourse.workbook"), ("rbcourse.bench", "rbcourse.workbook"),
}


def floor_breaches(graph: dict) -> list[str]:
    """Every import (file → module) that looks up a floor: the importer under one folder of FLOORS and the module
    under the folder it must not import from (rbcourse.support may import rbcourse.support only)."""
    def under(m, folder):
        return m == folder or m.startswith(folder + ".")
    bad = []
    for src, targets in graph.items():
        for top, banned in FLOORS:
            if under(src, top):
                bad += [f"{src} → {t}" for t in targets if under(t, banned) and not under(t, top)]
    return sorted(set(bad))


def test_each_piece_on_its_floor():
    """The language, the checks, the parallel runner live in support/, under every layer; the scene catalogue
    (rbcourse.examples) under viz/, bench/ and workbook/, which take their scenes from it; no view imports the
    workbook, the grader no benchmark."""
    graph = {dotted(p): files_imported(p) | {m for m, _ in imports(p) if m.startswith("rbcourse")} for p in modules()}
    assert not floor_breaches(graph), f"imports that look up a floor: {floor_breaches(graph)}"


def test_the_floor_check_can_fail():
    assert floor_breaches({"rbcourse.viz.plots": {"rbcourse.workbook.language"},
                           "rbcourse.support.checks": {"rbcourse.support.language", "rbcourse.state"}}) == [
        "rbcourse.support.checks → rbcourse.state", "rbcourse.viz.plots → rbcourse.workbook.language"]


def test_at_most_18_modules_at_the_top_of_the_package():
    top = sorted(p.stem for p in PKG.glob("*.py") if p.name not in ("__init__.py", "__main__.py"))
    assert len(top) <= MAX_TOP_MODULES, f"{len(top)} modules at the top of rbcourse/ (at most {MAX_TOP_MODULES}): {top}"


def _defined_and_imported(path: Path) -> tuple[set, dict]:
    """The functions a file defines, and {name: module} of what it imports by name (relative imports resolved)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    defined = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    imported = {name: mod for mod, names in imports(path) for name in names}
    return defined, imported


def test_rb_simulate_reaches_the_slides_euler_in_three_files_and_every_formula_in_four():
    """simulate.py (simulate → simulate_compiled) → engine/run.py (run_euler: loop(euler_family_step, …)) →
    engine/euler.py (euler_step) → engine/motion.py (the slides' formulas), each named where docs/architecture.md
    and engine/__init__ say."""
    sim_defs, sim_imports = _defined_and_imported(PKG / "simulate.py")
    assert {"simulate", "simulate_compiled"} <= sim_defs
    run_defs, run_imports = _defined_and_imported(ENGINE / "run.py")
    assert "run_euler" in run_defs and "loop" in run_defs and run_imports["euler_family_step"] == "rbcourse.engine.euler"
    run_euler = next(n for n in ast.parse((ENGINE / "run.py").read_text("utf-8")).body
                     if isinstance(n, ast.FunctionDef) and n.name == "run_euler")
    calls = [c for c in ast.walk(run_euler) if isinstance(c, ast.Call) and getattr(c.func, "id", "") == "loop"]
    assert calls and getattr(calls[0].args[0], "id", "") == "euler_family_step"
    euler_defs, euler_imports = _defined_and_imported(ENGINE / "euler.py")
    assert {"euler_step", "euler_family_step"} <= euler_defs and euler_imports["dxdt"] == "rbcourse.engine.motion"
    motion_defs, _ = _defined_and_imported(ENGINE / "motion.py")
    assert {"dxdt", "velocity", "inverse_inertia", "angular_velocity", "rotation_rate", "body_point", "torque",
            "resultants"} <= motion_defs
    routes = [(ENGINE / "__init__.py").read_text("utf-8"), (PKG.parent / "docs" / "architecture.md").read_text("utf-8")]
    assert all("run_euler" in text and "simulate_compiled" in text for text in routes)


def test_a_new_force_effect_touches_four_files():
    """An effect's code is read only where its force is (engine/motion.py), defined beside the others
    (engine/system.py) and emitted by its class (effects.py) — stages.py reads GRAVITY alone, for its
    central-force shortcut, which any other code leaves off; what else depends on an effect is the effect's own
    data (velocity_dependent, has_potential): a new effect is those three files and its public name (__init__)."""
    codes = {"GRAVITY", "POINT_FORCE", "SPRING", "LINEAR_DRAG", "ANGULAR_DRAG"}
    readers = sorted(str(p.relative_to(PKG)) for p in modules()
                     if any(mod == "rbcourse.engine.system" and codes & set(names) for mod, names in imports(p)))
    assert readers == ["effects.py", "engine/motion.py", "engine/stages.py"], readers
    stages = {n for mod, names in imports(ENGINE / "stages.py") if mod == "rbcourse.engine.system" for n in names}
    assert stages & codes == {"GRAVITY"}
