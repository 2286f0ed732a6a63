"""The plots of a linked view (draw_trajectory(..., plots=True)): the drift of what the scene conserves (energy,
L or L_z about a pivot: quantities.drifts, the one rule the matplotlib plots and the explorer follow), ‖RᵀR − I‖,
and the rotation error against the reference when there is one (the ghost), over time, for one run or several.

They become data for the page (js/timeplots.js draws them under meshcat's scene, with one time cursor shared with
the animation): each curve reduced to at most POINTS points, each the largest value of its stretch of steps (the
envelope: a spike between two samples is never lost), an exact zero kept as 0 (drawn on the "exactly 0" row), a
NaN (before t₀, after a run's end) as a gap, an overflow as inf (drawn at the top)."""
from __future__ import annotations

import numpy as np

from ...support.language import say
from ...rotation import rotation_angle
from .. import quantities
from ..plots import conserved

POINTS = 500                      # at most this many points per curve
PALETTE = ("#e15759", "#4e79a7", "#59a14f", "#b07aa1", "#f28e2b", "#76b7b2")
LOG_RANGE = (-17.0, 3.0)          # the plots' log10 range: the floor (under it: the "exactly 0" row) and the ceiling


def envelope(t: np.ndarray, v: np.ndarray, points: int = POINTS) -> tuple[np.ndarray, np.ndarray]:
    """(t, v) reduced to at most `points` points: each the largest |v| of its stretch of consecutive steps (NaN
    if the stretch is all NaN), at the stretch's last time."""
    n = len(t)
    if n <= points:
        return t, np.abs(v)
    starts = np.linspace(0, n, points + 1).astype(int)[:-1]
    a = np.abs(v)
    with np.errstate(invalid="ignore"):
        filled = np.where(np.isnan(a), -np.inf, a)
        top = np.maximum.reduceat(filled, starts)
    ends = np.append(starts[1:], n) - 1
    return t[ends], np.where(top == -np.inf, np.nan, top)


def _matched(ref, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The reference's recorded states at the times t: (indices into ref, those of t it has within 1e-9 of a step)."""
    k = np.clip(np.searchsorted(ref.t, t), 0, len(ref.t) - 1)
    prev = np.clip(k - 1, 0, None)
    k = np.where(np.abs(ref.t[prev] - t) <= np.abs(ref.t[k] - t), prev, k)
    step = np.min(np.diff(ref.t)) if len(ref.t) > 1 else 1.0
    return k, np.abs(ref.t[k] - t) <= 1e-9 * step + 1e-12 * np.abs(t)


def run_values(traj, plan, ref) -> dict:
    """One run's curves, by panel key: quantities.drifts (what the scene keeps, ‖RᵀR − I‖) and, given the
    reference ref (a Trajectory of the same scene), the rotation error angle(R_refᵀ R) (rad; the largest over
    the bodies) where ref has the run's times."""
    out = dict(quantities.drifts(plan, traj))
    if ref is not None:
        rows = quantities.rotation_rows(len(traj.t), traj.scene.n_bodies)
        k, ok = _matched(ref, traj.t[rows])
        err = np.full(len(traj.t), np.nan)
        angle = rotation_angle(ref.R[k[ok]], traj.R[rows[ok]])
        err[rows[ok]] = angle if angle.ndim == 1 else angle.max(-1)
        out["rotation"] = err
    return out


def panels(runs, labels, ref=None, ref_label: str | None = None, t_from: float = 0.0) -> dict:
    """The page's plot data: {"t0": drifts' start, "series": [{label, color}], "panels": [{key, title, note, unit,
    "curves": [{"s": series index, "t": [...], "v": [...]}]}]}.  runs: Trajectories of one scene (labels: their
    names); ref: the reference (the ghost), or None."""
    ref_label = say("reference", "référence") if ref_label is None else ref_label
    plan = conserved(runs[0], t_from)
    keys = [k for k in ("energy", "momentum") if plan[k].mode == "drift"] + ["orthogonality"] + \
        (["rotation"] if ref is not None else [])
    values = [run_values(traj, plan, ref) for traj in runs]
    out = []
    for key in keys:
        q = plan[key]
        title = q.title if key != "rotation" else say(f"rotation error vs {ref_label} (rad)",
                                                      f"écart de rotation à « {ref_label} » (rad)")
        curves = []
        for i, (traj, vals) in enumerate(zip(runs, values)):
            t, v = envelope(traj.t, vals[key])
            curves.append({"s": i, "t": _numbers(t), "v": _numbers(v)})
        out.append({"key": key, "title": title, "note": q.note, "unit": q.unit, "curves": curves})
    series = [{"label": label, "color": PALETTE[i % len(PALETTE)],
               "end": float(traj.divergence.t) if traj.diverged else None}
              for i, (traj, label) in enumerate(zip(runs, labels))]
    not_kept = [say(f"{plan[k].key}: not conserved here ({plan[k].why}), so not a drift",
                    f"{quantities.name(k)} : pas une quantité conservée ici ({plan[k].why}), donc pas une dérive")
                for k in ("energy", "momentum") if plan[k].mode != "drift"]
    return {"t0": plan.t0, "log": list(LOG_RANGE), "series": series, "panels": out, "notes": not_kept}


def _numbers(a: np.ndarray) -> list:
    """Floats with 4 significant digits for the page's JSON; NaN as None, an overflow as 1e308 (off the top)."""
    return [None if np.isnan(x) else (1e308 if np.isinf(x) else float(f"{x:.4g}")) for x in a.tolist()]
