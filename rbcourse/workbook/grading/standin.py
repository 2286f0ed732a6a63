"""What ``import rbcourse`` finds in the process whose functions are checked: not the library — a stand-in.

The grader runs each hand-in twice, in two sandboxes (runner.py): once as written, with the library, for its
status; and once to be checked, where this file is bound read-only as ``/grading/rbcourse/__init__.py`` and the
package itself is not there at all.  So a graded function cannot take its answer from rbcourse, however it
reaches it (an import, a name built at run time, a patched grading loop): every name under rbcourse — rb.simulate,
rbcourse.state.inverse_inertia, ex.reference, … — is a stand-in that raises LibraryUnavailable when called, and
the checker reports the function as using the library (the mistake "library_call").

Kept, because they compute nothing of the exercise: StateTuple (the tuple X = (x, R, P, L) the checks pass),
langue / language / current (the notebook's language, noted: the checks speak it), quick_mode, and every
check_* — which notes the function the notebook gave it (the one checked when the notebook has no function
of the check's name) and prints nothing.

It imports nothing but the standard library and wire.py (bound beside it, in /grading).
"""
from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import os
import sys
import types

try:
    from . import wire          # imported as rbcourse.workbook.grading.standin (its tests): nothing is replaced
except ImportError:
    import wire                 # bound as /grading/rbcourse/__init__.py, wire.py in /grading

CALLED: dict = {}                # the check's name -> the function the notebook passed to ex.check_<name>
LANGUAGE = ["en"]                # the language the notebook chose (ex.langue("fr"))
LANGUAGES = ("en", "fr")


class LibraryUnavailable(Exception):
    """A name of rbcourse was used where the checks run: the library is not there."""

    def __init__(self, path: str):
        super().__init__(f"{path} is not available while your functions are checked: write it with numpy")
        self.path = path


def _langue(code="en", *args, **kwargs):
    code = str(code).lower()
    if code in LANGUAGES:
        LANGUAGE[0] = code
    return code


def _current():
    return LANGUAGE[0]


def _quick_mode():
    return os.environ.get("RBCOURSE_QUICK", "") not in ("", "0")


KEPT = {"StateTuple": wire.StateTuple, "langue": _langue, "language": _langue, "current": _current,
        "quick_mode": _quick_mode, "LANGUAGES": LANGUAGES}


def _recorder(name: str):
    def check(fn=None, *args, **kwargs):
        CALLED[name] = fn
    check.__name__ = f"check_{name}"
    return check


def _attribute(module_name: str, name: str):
    if name.startswith("__"):
        raise AttributeError(name)
    if name in KEPT:
        return KEPT[name]
    if name.startswith("check_"):
        return _recorder(name[len("check_"):])
    return importlib.import_module(f"{module_name}.{name}")


class Standin(types.ModuleType):
    """A name under rbcourse (a module, a class, a function: all alike): its attributes are stand-ins too;
    calling it raises LibraryUnavailable."""

    def __getattr__(self, name):
        return _attribute(self.__name__, name)

    def __call__(self, *args, **kwargs):
        raise LibraryUnavailable(self.__name__)

    def __repr__(self):
        return f"<{self.__name__}: not available while your functions are checked>"


class _Finder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Any rbcourse.X import: a Standin."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname.startswith("rbcourse."):
            return importlib.machinery.ModuleSpec(fullname, self, is_package=True)
        return None

    def create_module(self, spec):
        module = Standin(spec.name)
        module.__path__ = []
        return module

    def exec_module(self, module):
        pass


if __name__ == "rbcourse":          # the package's stand-in: rbcourse.X is a Standin, and so is rbcourse.x.y
    def __getattr__(name):
        return _attribute(__name__, name)

    sys.meta_path.insert(0, _Finder())
