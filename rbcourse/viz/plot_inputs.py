"""What the plots are given, checked (plots.py's arguments): a clear error naming the argument and what it must be,
in the API's words, never matplotlib's or numpy's own."""
from __future__ import annotations

import numpy as np

from ..support import checks
from ..trajectory import Trajectory, shown


FLOOR_RANGE = (1e-300, 1e300)
"""plot_drift's floor and ceiling: within these, floor / 1000 (the zeros' row) and ceiling × 3 are finite, positive."""


def trajectories(trajs) -> list:
    """plot_drift's trajs: a Trajectory or a non-empty list (or tuple) of them, each holding a state (shown)."""
    if isinstance(trajs, (list, tuple)):
        if not trajs:
            raise ValueError("trajs must be a Trajectory or a non-empty list of Trajectories, got an empty list")
        return [shown(f"trajs[{i}]", t) for i, t in enumerate(trajs)]
    if not isinstance(trajs, Trajectory):
        raise ValueError(f"trajs must be a Trajectory or a non-empty list of Trajectories, got {trajs!r}")
    return [shown("trajs", trajs)]


def labels(labels, n: int) -> list:
    """plot_drift's labels: one string per trajectory."""
    if isinstance(labels, str) or not isinstance(labels, (list, tuple)):
        raise ValueError(f"labels must be None or a list of {n} string{'s' if n > 1 else ''} (one per trajectory), "
                         f"got {labels!r}")
    if len(labels) != n:
        raise ValueError(f"labels must hold one string per trajectory ({n}), got {len(labels)}: {list(labels)!r}")
    return [checks.text(f"labels[{i}]", label) for i, label in enumerate(labels)]


def bounds(floor, ceiling) -> tuple:
    """plot_drift's floor and ceiling, checked: FLOOR_RANGE[0] <= floor < ceiling <= FLOOR_RANGE[1]."""
    lo, hi = FLOOR_RANGE
    floor = checks.real("floor", floor)
    ceiling = checks.real("ceiling", ceiling)
    if not lo <= floor <= hi:
        raise ValueError(f"floor must be in [{lo:g}, {hi:g}] (log axes: a positive number), got {floor!r}")
    if not lo <= ceiling <= hi:
        raise ValueError(f"ceiling must be in [{lo:g}, {hi:g}] (log axes: a positive number), got {ceiling!r}")
    if not floor < ceiling:
        raise ValueError(f"floor must be below ceiling, got floor = {floor:g} >= ceiling = {ceiling:g}")
    return floor, ceiling


def axes(name: str, axes, n: int):
    """None, or n matplotlib Axes (a list, tuple or array of them: what plt.subplots(1, n) returns)."""
    if axes is None:
        return None
    from matplotlib.axes import Axes
    items = list(np.ravel(np.asarray(axes, dtype=object))) if isinstance(axes, (list, tuple, np.ndarray)) else None
    if items is None or len(items) != n or not all(isinstance(ax, Axes) for ax in items):
        raise ValueError(f"{name} must be None or {n} matplotlib Axes (e.g. plt.subplots(1, {n})[1]), got {axes!r}")
    return axes


def runs(runs) -> list:
    """plot_work_precision's runs: a non-empty list (or tuple) of bench Run records (problem, label, tool, seconds,
    error)."""
    if isinstance(runs, (str, bytes, dict)) or not isinstance(runs, (list, tuple)):
        raise ValueError(f"runs must be a non-empty list of bench.Run records (as a sweep returns them or "
                         f"bench.read_results reads them back), got {runs!r}")
    if not runs:
        raise ValueError("runs must hold at least one bench.Run, got none")
    for i, r in enumerate(runs):
        if not all(hasattr(r, k) for k in ("problem", "label", "tool", "seconds", "error")):
            raise ValueError(f"runs[{i}] must be a bench.Run (problem, label, tool, seconds, error), got {r!r}")
    return list(runs)
