"""The engine: the slides' physics written once, per body, compiled with numba (or run as Python).

jit.py the switch; algebra.py 3-vectors and 3×3 matrices as tuples; system.py a scene as data;
motion.py the derived quantities, the effects' forces, dX/dt; quaternion.py the quaternion state;
steps.py the methods' steps; run.py the checked, recorded step loop; driver.py the Python side;
interpreted.py the same files loaded as plain Python.

Importing this package loads nothing (numba loads with jit.py, at the first compiled run).
"""


def __getattr__(name):
    if name in ("COMPILED", "IMPLEMENTATION", "WHY"):
        from . import jit
        return getattr(jit, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["COMPILED", "IMPLEMENTATION", "WHY"]
