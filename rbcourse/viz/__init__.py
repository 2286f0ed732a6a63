"""Drawing: matplotlib plots of trajectories (plots) and the meshcat 3-D viewer (viewer; imports meshcat).
They read trajectories and never step physics; the engine never imports them.

explore(scene, X0, methods=[...], dts=[...], t_end=...): the accuracy explorer (explorer/), a grid of runs on
one self-contained page; loaded at its first use (importing rbcourse.viz loads neither it, nor the engine,
nor meshcat)."""


def __getattr__(name):
    if name in ("explore", "Explorer"):
        from . import explorer
        value = getattr(explorer, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | {"explore", "Explorer"})
