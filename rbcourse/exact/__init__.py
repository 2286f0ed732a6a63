"""The exact torque-free motion of a rigid body: the motion in closed form (free_body: Jacobi's
solution, closed forms for symmetric bodies and principal-axis spins), the elliptic functions it
needs near the separatrix (elliptic), and its flow over a step for the splitting methods (flow).

The submodules (and scipy.special, which they use) are loaded at the first use of a name
(`rbcourse.exact.exact_free_body`, ...), not when rbcourse is imported."""
import importlib

_HOME = {"exact_free_body": "free_body", "FreeRotationFlow": "flow", "free_rotation_flow": "flow"}

__all__ = ["exact_free_body", "FreeRotationFlow", "free_rotation_flow"]


def __getattr__(name):
    """A public name, from its submodule (imported on first access, then kept here)."""
    if name not in _HOME:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_HOME[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
