"""`python -m rbcourse compile`: every method's compiled code made ahead of time (numba's disk cache), with a
progress bar; it says where the cache is and how long it took; a bad --methods is one line, exit code 2."""
import subprocess
import sys

import pytest

from rbcourse.workbook import warmup
from rbcourse.__main__ import main
from rbcourse.engine import jit
from rbcourse.methods import METHODS

PROG = "python -m rbcourse"


@pytest.mark.parametrize("methods, bad", [("nope", "'nope'"), ("euler,rk5", "'rk5'"), ("", "''"), ("euler,", "''")])
def test_a_bad_method_is_one_line_naming_the_allowed_ones_and_exit_code_2(methods, bad, capsys, monkeypatch):
    ran = []
    monkeypatch.setattr(warmup, "warm", lambda *a, **k: ran.append(a) or [])
    with pytest.raises(SystemExit) as e:
        main(["compile", "--methods", methods])
    assert e.value.code == 2 and not ran
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"{PROG} compile: error: --methods: unknown method {bad}")
    assert all(name in err for name in METHODS)


def test_the_methods_default_to_all_and_keep_their_order():
    assert warmup.check_methods(None) == sorted(METHODS)
    assert warmup.check_methods("rk4, euler,rk4") == ["rk4", "euler"]


def test_every_scene_is_a_valid_run():
    names = [name for name, _, _ in warmup.scenes()]
    assert names == ["free body", "forces", "pivoted top", "box on the ground", "two bodies"]


@pytest.mark.skipif(not jit.COMPILED, reason=f"the engine is not compiled here ({jit.WHY})")
def test_compile_warms_a_method_and_says_where_the_cache_is(capfd):
    """In a fresh process, then again: the second finds everything on disk (no compile, a second or so)."""
    runs = [subprocess.run([sys.executable, "-m", "rbcourse", "compile", "--methods", "euler"], capture_output=True,
                           text=True, timeout=300) for _ in range(2)]
    for run in runs:
        assert run.returncode == 0, run.stderr[-2000:]
        last = run.stdout.strip().splitlines()[-1]
        assert last.startswith("compiled 1 method and the helpers in ") and f"the cache: {jit.cache_folder()}" in last
        assert "6/6" in run.stderr                         # the progress bar: 5 scenes, then the helpers
        assert "compiling the engine" not in run.stderr    # the bar says it: no notice as well
    assert "not run" not in runs[0].stdout
    seconds = float(runs[1].stdout.split(" in ")[1].split(" s;")[0])
    assert seconds < 5, runs[1].stdout                   # warm: read from the cache
