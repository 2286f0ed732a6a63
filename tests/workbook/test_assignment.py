"""One source, two versions (rbcourse.workbook.assignment, `python -m rbcourse assignment build`): every stored
student notebook is what its solution notebook generates; the build is deterministic; it holds no solution
line; a solution notebook that cannot generate is a clear error naming the file and the cell."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

from rbcourse.__main__ import main
from rbcourse.workbook import assignment as asg
from rbcourse.workbook.assignment import execute

ROOT = Path(__file__).resolve().parents[2]
SOLUTIONS = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "notebooks").glob("**/solutions/*.ipynb"))
ENGLISH = ROOT / "notebooks" / "solutions" / "01_exercise_euler.ipynb"
NBGRADER = {"solution": True, "grade": False, "locked": False, "schema_version": 3}


def code(text, grade_id=None):
    meta = {"nbgrader": dict(NBGRADER, grade_id=grade_id)} if grade_id else {}
    return {"cell_type": "code", "execution_count": None, "id": f"c{abs(hash(text)) % 10**8}", "metadata": meta,
            "outputs": [], "source": text}


def markdown(text):
    return {"cell_type": "markdown", "id": f"m{abs(hash(text)) % 10**8}", "metadata": {}, "source": text}


def notebook(cells, lang=None):
    meta = {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"}}
    if lang:
        meta["rbcourse"] = {"language": lang}
    return {"cells": cells, "metadata": meta, "nbformat": 4, "nbformat_minor": 5}


def write(path: Path, nb) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(nb), encoding="utf-8")
    return path


FRENCH = notebook([
    markdown("# Exercice<!-- SOLUTION ONLY --> — corrigé<!-- /SOLUTION ONLY -->\n\nÉcrivez v."),
    code("import numpy as np"),
    code('def vitesse(P, M):\n    """v = P / M"""\n    # Indice : divisez par la masse\n'
         '    ### BEGIN SOLUTION\n    return P / M\n    ### END SOLUTION', "vitesse"),
    code("try:\n    print(vitesse(np.ones(3), 2.0))\nexcept NotImplementedError:\n    print('pas encore')"),
], lang="fr")


# ---------------------------------------------------------------------------------------------------
# The stored notebooks
# ---------------------------------------------------------------------------------------------------

def test_the_solution_notebooks_are_found():
    assert "notebooks/solutions/01_exercise_euler.ipynb" in SOLUTIONS
    assert [p.resolve() for p in asg.solution_notebooks([ROOT / "notebooks"])] == [ROOT / p for p in SOLUTIONS]


@pytest.mark.parametrize("name", SOLUTIONS)
def test_the_stored_student_notebook_is_what_the_build_generates(name):
    solution = ROOT / name
    target = asg.student_path(solution)
    assert target == solution.parent.parent / solution.name
    assert target.is_file(), f"{target} is missing: run python -m rbcourse assignment build {name}"
    assert asg.check(solution) == [], f"run: python -m rbcourse assignment build {name}"
    stored = asg.read_notebook(target)
    ran = [c for c in stored["cells"] if c["cell_type"] == "code" and c.get("outputs")]
    assert ran, f"{target} stores no output: it was written without being run"


@pytest.mark.parametrize("name", SOLUTIONS)
def test_the_student_version_holds_no_solution_line(name):
    solution = asg.read_notebook(ROOT / name)
    if not asg.student_path(ROOT / name).is_file():
        pytest.fail(f"{asg.student_path(ROOT / name)} is missing: run python -m rbcourse assignment build {name}")
    student = asg.read_notebook(asg.student_path(ROOT / name))
    text = "\n".join(asg.source(c) for c in student["cells"])
    inside, outside, region = [], set(), False
    for cell in solution["cells"]:
        for line in asg.source(cell).split("\n"):
            if line.strip() in (asg.BEGIN, asg.END):
                region = line.strip() == asg.BEGIN
            elif region and asg.is_solution_cell(cell):
                inside.append(line)
            else:
                outside.add(line)
    regions = 0
    for line in inside:
        if line.strip() and not line.strip().startswith("#") and line not in outside:   # a line given elsewhere
            regions += 1
            assert line not in text.split("\n"), f"{name}: the solution line {line!r} is in the student version"
    assert regions >= 9
    assert asg.BEGIN not in text and asg.END not in text and asg.ONLY not in text and "solution" not in \
        asg.source(student["cells"][0]).split("\n")[0]


def test_the_english_student_version_keeps_the_hints_and_stubs():
    student = asg.read_notebook(asg.student_path(ENGLISH))
    text = "\n".join(asg.source(c) for c in student["cells"])
    for line in ("    return P / M", "    return R @ I_body_inv @ R.T", "        U[:, 2] *= -1",
                 "        tau = tau + np.cross(r_i - x, F_i)", "    return v, star(omega) @ R, F, tau"):
        assert line not in text.split("\n"), line
    assert text.count("    # YOUR CODE HERE\n    raise NotImplementedError()") == 9
    for hint in ("# Hint: v = P / M", "# Hint: U, S, Vt = np.linalg.svd(R); the nearest rotation is U @ Vt, unless det(U @ Vt) = -1",
                 "# Hint: X + Δt · dX/dt, every rate taken at t"):
        assert hint in text
    assert "    x, R, P, L = X\n    # Hint: v = P/M" in text                  # dxdt's given first line stays
    title = asg.source(student["cells"][0]).split("\n")[0]
    assert title == "# Exercise (2 h) — a rigid body, step by step: the slides' explicit Euler"
    checks = [c for c in student["cells"] if asg.source(c).startswith("ex.check_velocity")
              and "nbval-check-output" in c["metadata"].get("tags", [])]
    assert "○ velocity: not done yet" in json.dumps(checks[0]["outputs"], ensure_ascii=False)


def test_the_build_is_deterministic_and_written_as_nbformat_writes():
    import nbformat
    first = asg.writes(asg.generate(ENGLISH))
    assert first == asg.writes(asg.generate(ENGLISH))
    assert first == nbformat.writes(nbformat.reads(first, as_version=4)) + "\n"
    stored = (asg.student_path(ENGLISH)).read_text(encoding="utf-8")
    assert stored == asg.writes(json.loads(stored))                       # the stored file as the build writes it


def test_a_stale_student_notebook_is_named():
    stored = asg.read_notebook(asg.student_path(ENGLISH))
    generated = asg.generate(ENGLISH)
    assert asg.differences(stored, generated) == []
    stored["cells"][8]["source"] = asg.source(stored["cells"][8]).replace("# YOUR CODE HERE", "return P / M")
    assert asg.differences(stored, generated) == ["cell 8 (code): source differ"]
    stored["cells"].pop()
    assert asg.differences(stored, generated)[0] == f"{len(generated['cells']) - 1} cells stored, " \
                                                    f"{len(generated['cells'])} generated"


# ---------------------------------------------------------------------------------------------------
# The rules, on small notebooks (a French one included)
# ---------------------------------------------------------------------------------------------------

def test_a_french_notebook_gets_the_french_stub(tmp_path):
    solution = write(tmp_path / "fr" / "solutions" / "01_exercice.ipynb", FRENCH)
    nb = asg.generate(solution)
    assert asg.student_path(solution) == tmp_path / "fr" / "01_exercice.ipynb"
    assert asg.source(nb["cells"][0]) == "# Exercice\n\nÉcrivez v."
    assert asg.source(nb["cells"][2]) == ('def vitesse(P, M):\n    """v = P / M"""\n    # Indice : divisez par la masse\n'
                                          '    # VOTRE CODE ICI\n    raise NotImplementedError()')
    assert nb["cells"][2]["metadata"] == FRENCH["cells"][2]["metadata"]          # nbgrader's metadata kept
    assert [c["id"] for c in nb["cells"]] == [c["id"] for c in FRENCH["cells"]]


def test_the_region_keeps_its_indentation(tmp_path):
    nb = notebook([code("def f(x):\n    if x:\n        ### BEGIN SOLUTION\n        return 1\n        ### END SOLUTION\n"
                        "    return 0", "f")])
    out = asg.generate(write(tmp_path / "solutions" / "a.ipynb", nb))
    assert asg.source(out["cells"][0]) == ("def f(x):\n    if x:\n        # YOUR CODE HERE\n"
                                           "        raise NotImplementedError()\n    return 0")


def _error(tmp_path, cells, name="solutions/a.ipynb"):
    path = write(tmp_path / name, notebook(cells))
    with pytest.raises(asg.AssignmentError) as err:
        asg.generate(path)
    return str(err.value), path


REGION = "def f():\n    ### BEGIN SOLUTION\n    return 1\n    ### END SOLUTION"


@pytest.mark.parametrize("cells, words", [
    ([markdown("# t"), code("def f():\n    ### BEGIN SOLUTION\n    return 1", "f")],
     ["cell 1, line 2", "### BEGIN SOLUTION with no ### END SOLUTION"]),
    ([code("def f():\n    return 1\n    ### END SOLUTION", "f")], ["cell 0, line 3", "with no ### BEGIN SOLUTION"]),
    ([code("### BEGIN SOLUTION\n### BEGIN SOLUTION\n### END SOLUTION", "f")], ["cell 0, line 2", "do not nest"]),
    ([code("x = 1  ### BEGIN SOLUTION\n### END SOLUTION", "f")], ["cell 0, line 1", "alone on their line"]),
    ([markdown("t"), code(REGION)], ["cell 1", "without nbgrader solution metadata", '"grade_id"']),
    ([code("def f():\n    return 1", "f")], ["cell 0", "no ### BEGIN SOLUTION", "region"]),
    ([code(REGION, "f"), code(REGION.replace("f()", "g()"), "f")], ["cell 1", "grade_id 'f' is already"]),
    ([markdown("# t<!-- SOLUTION ONLY --> — solution")], ["cell 0", "<!-- SOLUTION ONLY --> with no matching"]),
    ([markdown("# t<!-- /SOLUTION ONLY -->"), code(REGION, "f")], ["cell 0", "<!-- /SOLUTION ONLY --> with no"]),
    ([markdown("### BEGIN SOLUTION\nx\n### END SOLUTION")], ["cell 0", "markdown cell"]),
    ([code("x = 1")], ["no nbgrader solution cell"]),
])
def test_a_bad_solution_notebook_is_a_clear_error(tmp_path, cells, words):
    message, path = _error(tmp_path, cells)
    assert message.startswith(str(path)), message
    for w in words:
        assert w in message, (w, message)


def test_a_notebook_outside_solutions_or_missing_is_a_clear_error(tmp_path):
    path = write(tmp_path / "answers" / "a.ipynb", notebook([code(REGION, "f")]))
    with pytest.raises(asg.AssignmentError, match=r"answers/a\.ipynb: a solution notebook must be in a folder "
                                                  r"named solutions/"):
        asg.generate(path)
    with pytest.raises(asg.AssignmentError, match=r"solutions/missing\.ipynb: no such file"):
        asg.generate(tmp_path / "solutions" / "missing.ipynb")
    (tmp_path / "solutions").mkdir()
    (tmp_path / "solutions" / "bad.ipynb").write_text("{not json", encoding="utf-8")
    with pytest.raises(asg.AssignmentError, match=r"bad\.ipynb: not a readable notebook"):
        asg.generate(tmp_path / "solutions" / "bad.ipynb")
    with pytest.raises(asg.AssignmentError, match=r"rbcourse\.language must be one of en, fr, got 'de'"):
        asg.generate(write(tmp_path / "solutions" / "de.ipynb", notebook([code(REGION, "f")], lang="de")))


# ---------------------------------------------------------------------------------------------------
# solution_functions
# ---------------------------------------------------------------------------------------------------

def test_solution_functions_are_the_notebooks_own():
    import inspect
    fns = asg.solution_functions(ENGLISH)
    assert {"box_inertia", "velocity", "inverse_inertia", "angular_velocity", "resultants", "star", "dxdt",
            "euler_step", "simulate", "project_so3", "euler_step_projected"} <= set(fns)
    import numpy as np
    assert np.allclose(fns["velocity"](np.array([2.0, 4.0, 6.0]), 2.0), [1, 2, 3])
    assert "### BEGIN SOLUTION" in inspect.getsource(fns["velocity"])       # the notebook's cell, markers and all
    assert inspect.signature(fns["simulate"]).parameters["step"].default is fns["euler_step"]


def test_solution_functions_run_nothing_else(tmp_path):
    nb = notebook([code("import math\nraise SystemExit('a check cell ran')"),
                   code("def helper(x):\n    return 2 * x\n\nhelper(undefined_name)"),
                   code("def f(x):\n    ### BEGIN SOLUTION\n    return helper(math.sqrt(x))\n    ### END SOLUTION", "f"),
                   code("%matplotlib inline\nimport os")])
    fns = asg.solution_functions(write(tmp_path / "solutions" / "a.ipynb", nb))
    assert set(fns) == {"helper", "f"} and fns["f"](9.0) == 6.0


def test_solution_functions_errors_name_the_cell(tmp_path):
    bad = write(tmp_path / "solutions" / "b.ipynb", notebook([code("def f(:\n    pass", "f")]))
    with pytest.raises(asg.AssignmentError, match=r"b\.ipynb, cell 0, line 1: not valid Python"):
        asg.solution_functions(bad)
    wrong_id = write(tmp_path / "solutions" / "c.ipynb", notebook([code(REGION, "g")]))
    with pytest.raises(asg.AssignmentError, match=r"c\.ipynb, cell 0: its grade_id 'g' names no function"):
        asg.solution_functions(wrong_id)
    raises = write(tmp_path / "solutions" / "d.ipynb", notebook([code("import no_such_module_here")]))
    with pytest.raises(asg.AssignmentError, match=r"d\.ipynb, cell 0: defining its functions raised "
                                                  r"ModuleNotFoundError"):
        asg.solution_functions(raises)


# ---------------------------------------------------------------------------------------------------
# The command line
# ---------------------------------------------------------------------------------------------------

def test_cli_check_exit_codes(tmp_path, capsys):
    assert main(["assignment", "build", "--check", str(ENGLISH)]) == 0
    assert capsys.readouterr().out == f"up to date: {asg.student_path(ENGLISH)}\n"
    solution = write(tmp_path / "fr" / "solutions" / "01_exercice.ipynb", FRENCH)
    target = asg.student_path(solution)
    assert main(["assignment", "build", "--check", str(solution), str(ENGLISH)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[0] == f"differs: {target} (from {solution}): {target} is missing"
    assert out[1].startswith("up to date: ") and out[2].startswith("1 of 2 student notebooks differ")
    assert not target.exists()                                             # --check writes nothing
    target.write_text(asg.writes(asg.generate(solution)), encoding="utf-8")
    assert main(["assignment", "build", "--check", str(solution)]) == 0
    capsys.readouterr()
    stale = asg.generate(solution)
    stale["cells"][0]["source"] = "# Exercice — corrigé\n\nÉcrivez v."
    target.write_text(asg.writes(stale), encoding="utf-8")
    before = target.read_bytes()
    assert main(["assignment", "build", "--check", str(solution)]) == 1
    assert "cell 0 (markdown): source differ" in capsys.readouterr().out
    assert target.read_bytes() == before


@pytest.mark.parametrize("argv, words", [
    (["assignment"], ["python -m rbcourse assignment: error:", "required"]),
    (["assignment", "build", "--check", "nowhere/x.ipynb"], ["assignment build: error: nowhere/x.ipynb:",
                                                             "solutions/"]),
    (["assignment", "build", "--check", "solutions/none.ipynb"], ["solutions/none.ipynb: no such file"]),
    (["assignment", "build", "--nope"], ["unrecognized arguments: --nope"]),
])
def test_cli_errors_are_one_line_exit_2(argv, words, capsys):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.count("\n") == 1, err
    for w in words:
        assert w in err, (w, err)


def test_cli_build_runs_the_student_version(tmp_path):
    """The build writes the student version with its outputs (run in its folder under RBCOURSE_QUICK=1)."""
    solution = write(tmp_path / "fr" / "solutions" / "01_exercice.ipynb", FRENCH)
    done = subprocess.run([sys.executable, "-m", "rbcourse", "assignment", "build", str(solution)],
                          capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert done.returncode == 0, done.stderr
    target = asg.student_path(solution)
    assert done.stdout == f"wrote {target} (from {solution})\n" and done.stderr == ""
    nb = asg.read_notebook(target)
    assert asg.differences(nb, asg.generate(solution)) == []
    assert nb["cells"][1]["execution_count"] == 1 and nb["metadata"] == FRENCH["metadata"]
    assert nb["cells"][3]["outputs"] == [{"name": "stdout", "output_type": "stream", "text": ["pas encore\n"]}]
    raising = json.loads(json.dumps(FRENCH))
    raising["cells"][3]["source"] = "vitesse(np.ones(3), 2.0)"
    solution = write(tmp_path / "solutions" / "raises.ipynb", raising)
    done = subprocess.run([sys.executable, "-m", "rbcourse", "assignment", "build", str(solution)],
                          capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert done.returncode == 1 and not asg.student_path(solution).exists()
    assert done.stderr.startswith(f"python -m rbcourse assignment build: {asg.student_path(solution)}, cell 3: "
                                  "the generated student version raised when run: NotImplementedError"), done.stderr


def test_no_solution_notebook_found_says_where_it_looked(tmp_path):
    with pytest.raises(asg.AssignmentError, match=r"no solution notebook \(notebooks/\*\*/solutions/\*\.ipynb\) in "
                                                  r".+: run it from a checkout of rbcourse, or name the solution"):
        asg.solution_notebooks([tmp_path])


def test_a_cells_consecutive_prints_are_one_output():
    out = lambda name, text: {"name": name, "output_type": "stream", "text": text}           # noqa: E731
    figure = {"output_type": "display_data", "data": {"text/plain": "F"}, "metadata": {}}
    joined = execute._joined_streams([out("stdout", "a\n"), out("stdout", ["b\n", "c"]), out("stderr", "w\n"), figure,
                                  out("stdout", "d\n")])
    assert joined == [out("stdout", "a\nb\nc"), out("stderr", "w\n"), figure, out("stdout", "d\n")]
