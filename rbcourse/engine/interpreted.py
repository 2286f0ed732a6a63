"""The engine's own functions, run as Python: the same files (engine/*.py), loaded a second time as the
package ``rbcourse.engine_python`` whose ``njit`` is the identity (jit.py reads the package's name).

simulate(..., fast=False), dxdt, the walkthrough and the exercise's reference run this: the code a
student reads, step by step, and the code the compiled run compiles are one text.  Loading it takes
no numba and no compile: it is plain Python, so every call is slow (about 1000× the compiled one),
and it can be stepped through in a debugger.
"""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

NAME = "rbcourse.engine_python"


def package():
    """The engine package, loaded as Python (once per process)."""
    mod = sys.modules.get(NAME)
    if mod is None:
        folder = Path(__file__).parent
        spec = importlib.util.spec_from_file_location(NAME, folder / "__init__.py",
                                                      submodule_search_locations=[str(folder)])
        mod = importlib.util.module_from_spec(spec)
        sys.modules[NAME] = mod
        try:
            spec.loader.exec_module(mod)
        except BaseException:
            del sys.modules[NAME]
            raise
    return mod


def module(name: str):
    """One module of the interpreted engine, e.g. module("run") or module("motion")."""
    package()
    return importlib.import_module(f"{NAME}.{name}")
