"""The compile notice (rbcourse.compiling): will_compile reads the process's overloads and numba's disk cache;
announced says one line on stderr, once per family, in the workbook's language; in a notebook a note that
nbval never compares, cold cache or warm.  Tested on a small numba function of a module written here (numba
caches only functions of real files), not on the engine."""
import importlib.util
import itertools
import os
import subprocess
import sys

import pytest

from rbcourse import compiling
from rbcourse.support import language
from rbcourse.engine import jit

pytestmark = pytest.mark.skipif(not jit.COMPILED, reason=f"the engine is not compiled here ({jit.WHY})")

PROBE = "import numba\n\n\n@numba.njit(cache=True)\ndef plus_one(x):\n    return x + {k}\n"
_names = itertools.count()


def load(path):
    """The module at path, imported afresh (a new dispatcher: nothing compiled in this process yet)."""
    spec = importlib.util.spec_from_file_location(f"compile_probe_{next(_names)}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def probe(tmp_path, monkeypatch):
    from numba.core import config
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setattr(config, "CACHE_DIR", "")      # numba read NUMBA_CACHE_DIR at its import: its cache beside
    path = tmp_path / "probe.py"                      # the probe's file, where the test looks
    path.write_text(PROBE.format(k="1.0"))
    return path


@pytest.fixture(autouse=True)
def fresh_notices(monkeypatch):
    monkeypatch.setattr(compiling, "_announced", set())
    yield
    language.choose("en")


def test_will_compile_until_compiled_then_read_from_the_disk_cache(probe):
    f = load(probe).plus_one
    assert compiling.will_compile(f, (1.0,))
    assert f(1.0) == 2.0
    assert not compiling.will_compile(f, (2.0,))                 # float64: compiled in this process
    assert compiling.will_compile(f, (1,))                       # int64: another overload
    g = load(probe).plus_one                                     # a new dispatcher, the same file
    assert not g.overloads and not compiling.will_compile(g, (1.0,))     # on disk
    g(1.0)
    assert g.stats.cache_hits and not g.stats.cache_misses       # ...and indeed read, not compiled
    probe.write_text(PROBE.format(k="2.0"))                      # the source edited: the index is stale
    assert compiling.will_compile(load(probe).plus_one, (1.0,))


def test_nothing_compiles_when_interpreted(probe, monkeypatch):
    assert not compiling.will_compile(lambda x: x, (1.0,))       # a plain Python function
    assert not compiling.will_compile(load(probe).plus_one.py_func, (1.0,))
    monkeypatch.setattr(jit, "COMPILED", False)                  # no numba, or NUMBA_DISABLE_JIT=1
    assert not compiling.will_compile(load(probe).plus_one, (1.0,))


def test_announced_says_one_line_on_stderr_once_per_compile(probe, capsys):
    f = load(probe).plus_one
    seconds = compiling.SECONDS["explicit_quat"]
    with compiling.announced(f, (1.0,), "explicit_quat"):
        f(1.0)
    assert capsys.readouterr().err == f"compiling the engine for this machine, once (~{seconds} s)…\n"
    with compiling.announced(f, (1,), "explicit_quat"):          # compiles, but this compile was announced
        f(1)
    g = load(probe).plus_one
    with compiling.announced(g, (1.0,), "splitting"):            # from the disk cache: no compile, no notice
        g(1.0)
    out = capsys.readouterr()
    assert out.err == "" and out.out == ""


def test_the_estimate_is_what_the_run_compiles(probe, capsys):
    """A loop's estimate, with the forces of a scene that evaluates some and the contact solve of a ground; a run
    that compiles the same loop again for a ground is announced again, with the ground's estimate."""
    assert compiling.estimate("euler") == compiling.SECONDS["euler"]
    assert compiling.estimate("euler", forces=True) == compiling.SECONDS["euler"] + compiling.FORCES
    assert compiling.estimate("euler", True, True) == compiling.SECONDS["euler"] + compiling.FORCES + compiling.GROUND
    f = load(probe).plus_one
    with compiling.announced(f, (1.0,), "euler"):
        f(1.0)
    with compiling.announced(f, (1,), "euler", forces=True, ground=True):
        f(1)
    assert capsys.readouterr().err.splitlines() == [compiling.notice("euler"), compiling.notice("euler", True, True)]


def test_the_notice_is_in_the_workbooks_language_with_a_default_estimate(probe, capsys):
    from rbcourse.workbook import langue
    langue("fr")
    f = load(probe).plus_one
    with compiling.announced(f, (1.0,), "a family of tomorrow"):
        f(1.0)
    assert capsys.readouterr().err == (f"compilation du moteur pour cette machine, une seule fois "
                                       f"(~{compiling.DEFAULT_SECONDS} s)…\n")
    assert set(compiling.NOTICE) == set(language.LANGUAGES)
    from rbcourse.engine import run
    assert set(compiling.SECONDS) == set(run.LOOPS)


def test_quiet_says_nothing(probe, capsys):
    f = load(probe).plus_one
    with compiling.quiet(), compiling.announced(f, (1.0,), "euler"):
        f(1.0)
    assert capsys.readouterr().err == "" and not compiling._announced


def test_in_a_notebook_the_note_never_makes_nbval_fail_cold_or_warm(tmp_path, probe):
    """A # NBVAL_CHECK_OUTPUT cell that compiles: its outputs stored on a warm cache (no note), then checked by
    nbval on an empty cache (the note shown, then taken back) and on the warm one."""
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("nbval")
    source = (f"# NBVAL_CHECK_OUTPUT\nimport sys\nsys.path.insert(0, {str(tmp_path)!r})\n"
              "from rbcourse import compiling\nimport probe\nprint('before')\n"
              "with compiling.announced(probe.plus_one, (1.0,), 'euler'):\n    y = probe.plus_one(1.0)\nprint('after', y)")
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(source)])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    warm, cold = tmp_path / "warm", tmp_path / "cold"
    env = {**os.environ, "NUMBA_CACHE_DIR": str(warm)}
    seen = []

    class Client(nbclient.NotebookClient):
        def process_message(self, msg, cell, cell_index):
            seen.append((msg["msg_type"], msg["content"].get("data")))
            return super().process_message(msg, cell, cell_index)

    os.environ["NUMBA_CACHE_DIR"], saved = str(warm), os.environ.get("NUMBA_CACHE_DIR")
    try:
        Client(nb, kernel_name="python3").execute()              # cold: compiles, the note shown then cleared
        notes = [data for kind, data in seen if kind == "update_display_data"]
        assert notes[0]["text/plain"] == compiling.NOTICE["en"].format(seconds=compiling.SECONDS["euler"])
        assert notes[-1] == {}
        assert not any(o.get("name") == "stderr" for o in nb.cells[0].outputs)
        nbclient.NotebookClient(nb, kernel_name="python3").execute()     # warm: the outputs stored
    finally:
        os.environ.pop("NUMBA_CACHE_DIR") if saved is None else os.environ.update(NUMBA_CACHE_DIR=saved)
    outputs = nb.cells[0].outputs                                # warm: no note at all
    assert {o.output_type for o in outputs} == {"stream"} and "".join(o.text for o in outputs) == "before\nafter 2.0\n"
    nbformat.write(nb, tmp_path / "probe.ipynb")
    for cache in (cold, warm):
        run = subprocess.run([sys.executable, "-m", "pytest", "--nbval-lax", "-p", "no:cacheprovider", "-q",
                              str(tmp_path / "probe.ipynb")], capture_output=True, text=True, cwd=tmp_path,
                             env={**env, "NUMBA_CACHE_DIR": str(cache)}, timeout=300)
        assert run.returncode == 0, run.stdout[-2000:]
    assert (cold / next(p.name for p in warm.iterdir())).exists()     # the cold run did compile (and cache)


def test_a_notice_that_cannot_be_written_stops_nothing(probe, monkeypatch):
    """A stderr past its file size limit (a grader's sandbox after a flood) or closed: the compile goes on, silent."""
    class Full:
        def write(self, text):
            raise OSError(27, "File too large")

        def flush(self):
            raise OSError(27, "File too large")
    monkeypatch.setattr(sys, "stderr", Full())
    f = load(probe).plus_one
    with compiling.announced(f, (1.0,), "euler"):
        assert f(1.0) == 2.0
