"""library_call only for a real use of rbcourse (grading/library.py: from_rbcourse): a name of it imported and
used, a string naming it as a module or handed to what loads or runs code — never a word in a message, and not
passed on to a graded function that calls another one."""
import json

from rbcourse.workbook.grading.library import from_rbcourse

GRADED = ["velocity", "inverse_inertia", "euler_step", "simulate"]


def notebook(*cells: str) -> str:
    return json.dumps({"cells": [{"cell_type": "code", "source": c} for c in cells], "metadata": {}})


def test_a_word_in_a_message_is_no_library_call():
    text = notebook("def velocity(P, M):\n"
                    "    if M <= 0:\n        raise ValueError('M must be positive (as in rbcourse, not its copy)')\n"
                    "    return P / M\n",
                    "def simulate(P, M):\n    print('my own loop, not rbcourse.simulate')\n    return velocity(P, M)\n")
    assert from_rbcourse(text, GRADED) == {}


def test_a_graded_function_that_calls_one_that_uses_the_library_is_checked_on_its_own():
    text = notebook("import rbcourse as rb\n",
                    "def velocity(P, M):\n    return rb.velocity(P, M)\n",
                    "def helper(P, M):\n    return velocity(P, M)\n",
                    "def euler_step(P, M, dt):\n    return P + dt * helper(P, M)\n")
    found = from_rbcourse(text, GRADED)
    assert found == {"velocity": "rb.velocity"}


def test_real_uses_are_still_found():
    text = notebook("import importlib, sys\nimport rbcourse as rb\n",
                    "def helper(R):\n    return rb.inverse_inertia(R)\n",
                    "def inverse_inertia(R, I):\n    return helper(R)\n",
                    "def velocity(P, M):\n    return importlib.import_module('rbcourse.state').velocity(P, M)\n",
                    "def euler_step(X, dt):\n    exec('from rbcourse import simulate as s')\n    return X\n",
                    "def simulate(X):\n    return sys.modules['rbcourse'].simulate(X)\n")
    found = from_rbcourse(text, GRADED)
    assert set(found) == set(GRADED), found
    assert found["inverse_inertia"] == "helper → rb.inverse_inertia"
    assert found["euler_step"] == repr("from rbcourse import simulate as s")


def test_a_module_name_in_a_string_is_a_use_wherever_it_is():
    text = notebook("import importlib\nname = 'rbcourse.workbook.exercises.reference'\n",
                    "def velocity(P, M):\n    return importlib.import_module(name).velocity(P, M)\n")
    assert from_rbcourse(text, GRADED) == {"velocity": "name → 'rbcourse.workbook.exercises.reference'"}


def test_many_magic_lines_are_read_in_one_pass_and_what_follows_them_is_still_seen():
    """500 shell lines in a cell: IPython's transformer gives up on them (RuntimeError, which failed the row: "the
    grader failed"), and re-reads the cell once per magic line below that; here they are read in one pass."""
    magics = "\n".join(f"!echo {i}" for i in range(2000)) + "\nfiles = !ls\n%time t = 1\n"
    text = notebook(magics + "import rbcourse as rb\ndef velocity(P, M):\n    return rb.velocity(P, M)\n",
                    "%%bash\necho a cell magic's body is no Python\n")
    assert from_rbcourse(text, GRADED) == {"velocity": "rb.velocity"}      # IPython's transformer: RuntimeError
