"""The explorer page's data: one JSON object that the page's script reads (page_data), the runs' arrays beside it
as float32 in one buffer (Arrays: in the JSON each is {"f32": [start, count]}); the colours of the methods and the
bodies, and the ranges of the log plots."""
from __future__ import annotations

import math

import numpy as np

from ...support.language import current
from ..words import script_words
from .text import dt_text

METHOD_COLORS = ("#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2")
FLOOR = 1e-17                                     # the log plots' lowest value
CEILING = 1e3                                     # and their highest (a relative drift of 10³: the run has blown up)


class Arrays:
    """The page's float32 arrays, one buffer: add(a) keeps a and returns its reference {"f32": [start, count]} (in
    floats); packed() is the buffer with its bytes regrouped by place (every float's first byte, then every second
    byte, ...): the exponents' bytes side by side, which LZMA packs ~10 % smaller (js/data.js undoes it)."""

    def __init__(self):
        self.parts, self.count = [], 0

    def add(self, a) -> dict:
        a = np.ascontiguousarray(a, dtype="<f4").ravel()
        self.parts.append(a)
        self.count += len(a)
        return {"f32": [self.count - len(a), len(a)]}

    def packed(self) -> bytes:
        floats = np.concatenate(self.parts) if self.parts else np.zeros(0, "<f4")
        return floats.view(np.uint8).reshape(-1, 4).T.tobytes()


def _num(x):
    """A float for JSON, or None if it is not finite (JSON has no inf)."""
    x = float(x)
    return x if math.isfinite(x) else None


def _track(tr, arrays: Arrays) -> dict:
    return {"n": int(len(tr.t)), "t": arrays.add(tr.t), "x": arrays.add(tr.x), "q": arrays.add(tr.q)}


def _decades(values, low=FLOOR, high=1e30, pad_low=0.3, pad_high=0.3):
    """[lo, hi] (log10, integers) holding the positive finite values (lo >= log10(low)); a value exactly 0 is
    drawn on its own row under the axis ("exactly 0": viewer/js/timeplots.js), so it does not widen it."""
    v = np.concatenate([np.ravel(a) for a in values]) if values else np.array([])
    v = v[np.isfinite(v) & (v > 0)]
    if v.size == 0:
        return [round(math.log10(low)), 0]
    lo = max(math.floor(math.log10(max(v.min(), low)) - pad_low), round(math.log10(low)))
    hi = min(math.ceil(math.log10(min(v.max(), high)) + pad_high), math.ceil(math.log10(high) - 1e-9))
    return [int(lo), int(max(hi, lo + 1))]


def _after_start(v: np.ndarray) -> np.ndarray:
    """A curve without its first defined point (0 by construction: a drift from itself, R(0) = R_ref(0))."""
    v = v.astype(float)
    first = np.flatnonzero(~np.isnan(v))
    if first.size:
        v[first[0]] = np.nan
    return v


def page_data(grid, arrays: Arrays) -> dict:
    """Everything the page's script reads (one JSON object; its arrays kept in `arrays`, referred to by place)."""
    s, plan, ref = grid.settings, grid.plan, grid.reference
    panels = []
    for q in plan.quantities:
        v = [_after_start(r.curves[q.key]) for r in grid.runs]
        rotation = q.key == "rotation"              # at most π; the others are cut at CEILING (off the chart above)
        panels.append({"key": q.key, "title": q.title, "unit": q.unit, "note": q.note, "mode": q.mode,
                       "ylim": _decades(v, high=math.pi if rotation else CEILING, pad_high=0.0 if rotation else 0.3)})
    errors = [r.error for r in grid.runs if math.isfinite(r.error)]
    if ref.accuracy is not None and math.isfinite(ref.accuracy):
        errors.append(ref.accuracy)
    seconds = [r.seconds for r in grid.runs]
    runs = []
    for r in grid.runs:
        runs.append({
            "method": r.method, "dt": r.dt, "dt_index": s.dts.index(r.dt), "h": r.h, "steps": r.steps,
            "seconds": r.seconds, "error": _num(r.error), "position_error": _num(r.position_error),
            "diverged": r.diverged, "reason": r.reason, "t_last": r.t_last, "t_diverged": _num(r.t_diverged),
            "implementation": r.implementation,
            "drawn_note": r.drawn_note, "drawn_until": float(r.track.t[-1]),
            "curve_t": arrays.add(r.curve_t), "curves": {k: arrays.add(v) for k, v in r.curves.items()},
            "track": _track(r.track, arrays)})
    from ...methods import METHODS
    from ..viewer.parts import BODY_PALETTE, COLORS
    from .view import view_setup                  # meshcat: loaded when a page is made, not with the package
    methods = [{"name": m, "color": METHOD_COLORS[i % len(METHOD_COLORS)], "order": METHODS[m].order,
                "summary": METHODS[m].summary} for i, m in enumerate(s.methods)]
    bodies = [{"color": f"#{COLORS['body'] if s.scene.single else BODY_PALETTE[i % len(BODY_PALETTE)]:06x}"}
              for i in range(s.scene.n_bodies)]
    show_ghost = s.scene.n_bodies <= 3
    return {
        "version": 1, "name": s.name, "description": s.description, "t_end": s.t_end, "t0": s.drift_from,
        "methods": methods, "dts": list(s.dts), "dt_labels": [dt_text(d) for d in s.dts], "steps": list(s.steps),
        "default": {"method": s.methods.index(s.default[0]), "dt": s.dts.index(s.default[1])},
        "panels": panels,
        "reference": {"exact": ref.exact, "label": ref.label, "detail": ref.detail,
                      "accuracy": None if ref.accuracy is None else _num(ref.accuracy)},
        "wp": {"xlim": _decades([np.array(seconds)], low=1e-9, pad_low=0.1, pad_high=0.1),
               "ylim": _decades([np.array(errors)], high=10.0, pad_high=0.0)},
        "bodies": bodies, "ghost_color": f"#{COLORS['ghost']:06x}",
        "view": view_setup(s.scene, grid.ghost, show_ghost=show_ghost), "show_ghost": show_ghost,
        "ghost": _track(grid.ghost, arrays), "runs": runs, "lang": current(), "words": script_words(),
    }
