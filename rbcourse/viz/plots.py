"""Matplotlib plots of trajectories (they return Axes; never plt.show()), and of the benchmark's saved
results (the work-precision diagram).  Plots read results; they never compute them: nothing here imports bench.

Titles, axis labels and legends are in the workbook's language (rbcourse.workbook.langue("fr"): in
French; English by default): one table per language, TEXTS, keyed by the same ids and placeholders (made from
_WORDS, where each id is written once with its text in every language)."""
from __future__ import annotations

import numpy as np

from ..language import LANGUAGES
from ..workbook.language import text

_WORDS = {
    "run": ("run {i}", "calcul {i}"), "diverged": ("diverged", "divergé"),
    "diverged_at": ("{label} (diverged at t = {t} s)", "{label} (divergé à t = {t} s)"),
    "drift_energy": ("|E − E₀| / |E₀|  (energy drift)", "|E − E₀| / |E₀|  (dérive de l'énergie)"),
    "drift_L": ("‖L − L₀‖ / ‖L₀‖  (angular momentum, world)",
                "‖L − L₀‖ / ‖L₀‖  (moment cinétique, repère monde)"),
    "drift_R": ("‖RᵀR − I‖  (distance from SO(3))", "‖RᵀR − I‖  (écart à SO(3))"),
    "time": ("t (s)", "t (s)"),
    "kinetic": ("kinetic T", "cinétique T"), "potential": ("potential U", "potentielle U"),
    "total": ("total E", "totale E"), "energy": ("energy (J)", "énergie (J)"),
    "L_norm": ("|L| about the origin (kg m²/s)", "|L| par rapport à l'origine (kg m²/s)"),
    "wp_title": ("problem {p}: error at T vs time", "problème {p} : erreur à T selon le temps de calcul"),
    "wall": ("wall time (s)", "temps de calcul (s)"), "rot_error": ("rotation error (rad)", "erreur de rotation (rad)"),
    "least": ("least inertia", "plus petite inertie"), "intermediate": ("intermediate", "intermédiaire"),
    "largest": ("largest inertia", "plus grande inertie"),
}
"""The plots' words: each id once, with its text in every language, in LANGUAGES' order (English, French)."""

TEXTS = {language: {key: texts[k] for key, texts in _WORDS.items()} for k, language in enumerate(LANGUAGES)}
"""The plots' words, per language (rbcourse.workbook.language): the same ids and placeholders."""


def drift(traj, t_from: float = 0.0) -> dict:
    """Drift diagnostics of one trajectory over time, from t_from on (default: the start):
    relative energy error (E − E0)/|E0|, relative angular-momentum error ‖L − L0‖/‖L0‖
    (world, about the origin) and ‖RᵀR − I‖, with E0, L0 taken at t_from."""
    keep = traj.t >= t_from
    if not keep.any():
        raise ValueError(f"t_from must be within the trajectory's times [{traj.t[0]:g}, {traj.t[-1]:g}], got {t_from:g}")
    E = traj.total_energy()[keep]
    L = traj.angular_momentum()[keep]
    if E.ndim > 1:
        E, L = E.sum(-1), L.sum(-2)
    E0, L0 = E[0], L[0]
    scale_E = abs(E0) if E0 != 0 else 1.0
    scale_L = np.linalg.norm(L0) if np.linalg.norm(L0) > 0 else 1.0
    orth = traj.orthogonality_error()[keep]
    return {
        "t": traj.t[keep],
        "energy": (E - E0) / scale_E,
        "angular_momentum": np.linalg.norm(L - L0, axis=-1) / scale_L,
        "orthogonality": orth if orth.ndim == 1 else orth.max(-1),
    }


def plot_drift(trajs, labels=None, axes=None, t_from: float = 0.0, floor: float = 1e-17, ceiling: float = 1e3):
    """|energy drift|, |angular-momentum drift| and ‖RᵀR − I‖ over time on log axes, one line per trajectory.

    trajs: a Trajectory or a list of them (e.g. several methods on one scene).
    Values are clipped to [floor, ceiling] so that an exact zero and a blow-up both stay on the plot.
    Returns the array of 3 Axes.
    """
    import matplotlib.pyplot as plt

    if not isinstance(trajs, (list, tuple)):
        trajs = [trajs]
    labels = labels or [t.method or text(TEXTS, "run").format(i=i) for i, t in enumerate(trajs)]
    if axes is None:
        _, axes = plt.subplots(1, 3, figsize=(13, 3.6), constrained_layout=True)
    titles = [text(TEXTS, k) for k in ("drift_energy", "drift_L", "drift_R")]
    keys = ["energy", "angular_momentum", "orthogonality"]
    for traj, label in zip(trajs, labels):
        d = drift(traj, t_from)
        if traj.diverged and text(TEXTS, "diverged") not in label:
            label = text(TEXTS, "diverged_at").format(label=label, t=f"{traj.divergence.t:.3g}")
        for ax, key in zip(axes, keys):
            line, = ax.plot(d["t"], np.clip(np.abs(d[key]), floor, ceiling), label=label)
            if traj.diverged:
                mark_divergence(ax, traj, line)
    for ax, title in zip(axes, titles):
        ax.set_title(title, fontsize=10)
        ax.set_xlabel(text(TEXTS, "time"))
        ax.set_yscale("log")
        ax.set_ylim(floor / 3, ceiling * 3)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    return axes


def mark_divergence(ax, traj, line=None):
    """A diverged run's end on a time axis: a dotted line at the time of the blow-up and, given the
    run's curve (a Line2D), a cross where it stops (what would come after is overflow, not physics)."""
    if not traj.diverged:
        return
    color = line.get_color() if line is not None else "k"
    ax.axvline(traj.divergence.t, color=color, linestyle=":", linewidth=1.2)
    if line is not None and len(line.get_xdata()):
        ax.plot(line.get_xdata()[-1:], line.get_ydata()[-1:], marker="x", color=color, markersize=7)


def plot_energy_momentum(traj, axes=None):
    """Kinetic, potential and total energy, and |L| about the origin, over time."""
    import matplotlib.pyplot as plt

    if axes is None:
        _, axes = plt.subplots(1, 2, figsize=(10, 3.4), constrained_layout=True)
    T, U = traj.kinetic_energy(), traj.potential_energy()
    if T.ndim > 1:
        T, U = T.sum(-1), U.sum(-1)
    axes[0].plot(traj.t, T, label=text(TEXTS, "kinetic"))
    if np.any(U):
        axes[0].plot(traj.t, U, label=text(TEXTS, "potential"))
        axes[0].plot(traj.t, T + U, label=text(TEXTS, "total"), color="k")
    axes[0].set_title(text(TEXTS, "energy") + (f" — {traj.outcome}" if traj.diverged else ""), fontsize=10)
    L = traj.angular_momentum()
    if L.ndim > 2:
        L = L.sum(-2)
    axes[1].plot(traj.t, np.linalg.norm(L, axis=-1))
    for ax in axes:
        mark_divergence(ax, traj)
        if traj.diverged:         # its last values are 10⁵⁰… times the first: a linear axis shows one spike
            ax.set_yscale("symlog", linthresh=max(abs(float(T[0])), 1e-12))
    axes[1].set_title(text(TEXTS, "L_norm"), fontsize=10)
    for ax in axes:
        ax.set_xlabel(text(TEXTS, "time"))
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    return axes


WORK_PRECISION_LEVELS = (1e-3, 1e-6, 1e-9)     # rotation errors (rad) the diagram marks, and the bench tabulates


def plot_work_precision(runs, path, note: str = ""):
    """The work-precision diagram (rotation error at T against wall time, log-log, one panel per
    problem), saved to `path` (a Figure of its own: no pyplot, any backend).  runs: bench Run
    records (problem, label, tool, seconds, error), as a sweep returns them or bench.read_results
    reads them back.  One colour per method in every panel (ours solid with dots, peers dashed with
    squares), grey lines at WORK_PRECISION_LEVELS, one legend for the whole figure below the panels;
    `note` (e.g. "partial: …") as a title in red.  A diverged run (error inf) is left out."""
    from matplotlib import colormaps
    from matplotlib.figure import Figure
    problems = list(dict.fromkeys(r.problem for r in runs))
    labels = list(dict.fromkeys(r.label for r in runs))
    palette = colormaps["tab20"]
    colour = {label: palette(i % 20) for i, label in enumerate(labels)}
    fig = Figure(figsize=(6 * len(problems), 6), constrained_layout=True)
    axes = fig.subplots(1, len(problems), squeeze=False)
    lines = {}
    for ax, p in zip(axes[0], problems):
        for label in labels:
            rs = sorted((r for r in runs if r.problem == p and r.label == label and np.isfinite(r.error)),
                        key=lambda r: r.seconds)
            if not rs:
                continue
            ours = rs[0].tool == "rbcourse"
            (lines[label],) = ax.loglog([r.seconds for r in rs], [max(r.error, 1e-16) for r in rs],
                                        "-" if ours else "--", marker="o" if ours else "s", ms=3,
                                        color=colour[label], label=label)
        for thr in WORK_PRECISION_LEVELS:
            ax.axhline(thr, color="grey", lw=0.5)
        ax.set_title(text(TEXTS, "wp_title").format(p=p))
        ax.set_xlabel(text(TEXTS, "wall"))
        ax.set_ylabel(text(TEXTS, "rot_error"))
        ax.grid(True, which="both", alpha=0.2)
    shown = [label for label in labels if label in lines]
    if shown:
        fig.legend([lines[label] for label in shown], shown, loc="outside lower center", ncol=min(6, len(shown)),
                   fontsize=8)
    if note:
        fig.suptitle(note, color="firebrick")
    fig.savefig(path, dpi=110)


def work_precision_png(runs, note: str = "") -> bytes:
    """The benchmark's work-precision diagram — the very figure `python -m rbcourse bench` saves as
    work_precision.png (plot_work_precision) — as PNG bytes, for a notebook:
    IPython.display.Image(plots.work_precision_png(runs)).  runs: bench Run records (a sweep's, or
    bench.read_results' for a saved one); note: a line in red over the panels (e.g. "partial: …")."""
    import io

    if not runs:
        raise ValueError("runs must hold at least one bench.Run, got none")
    buffer = io.BytesIO()
    plot_work_precision(list(runs), buffer, note=note)
    return buffer.getvalue()


def momentum_sphere(ax, inertia, L_norm: float, energy: float | None = None, title: str = ""):
    """The sphere |L_b| = L_norm on which a free body's angular momentum in body axes, L_b = Rᵀ L,
    must stay — with the body axes drawn through it, each named by its moment (least, intermediate,
    largest inertia) — and, given the kinetic energy, the energy ellipsoid
    2E = L₁²/I₁ + L₂²/I₂ + L₃²/I₃ (semi-axes √(2E Iᵢ)) in green: a polhode is where the two meet.

    ax: a 3-D Axes (projection="3d"); inertia: the principal moments (3,) or I_body (3, 3), body axes.
    Draw polhodes over it with ax.plot(*L_b.T).  Returns ax."""
    inertia = np.asarray(inertia, dtype=float)
    moments = np.diag(inertia) if inertia.shape == (3, 3) else inertia
    if moments.shape != (3,) or not np.all(moments > 0):
        raise ValueError(f"inertia must be 3 positive principal moments or a 3×3 I_body, got {inertia!r}")
    if not (np.isfinite(L_norm) and L_norm > 0):
        raise ValueError(f"L_norm must be a positive number, got {L_norm!r}")
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 25), np.linspace(0, np.pi, 13))
    unit = np.array([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)])
    ax.plot_wireframe(*(L_norm * unit), color="grey", alpha=0.2, lw=0.5)
    if energy is not None:
        ax.plot_wireframe(*(np.sqrt(2 * energy * moments)[:, None, None] * unit), color="tab:green", alpha=0.35, lw=0.5)
    roles = {0: text(TEXTS, "least"), 1: text(TEXTS, "intermediate"), 2: text(TEXTS, "largest")}
    rank = np.argsort(np.argsort(moments, kind="stable"), kind="stable")
    for k, name in enumerate("xyz"):
        end = np.zeros(3)
        end[k] = 1.35 * L_norm
        ax.plot(*np.array([-end, end]).T, color="k", lw=0.8)
        ax.text(*(1.05 * end), f"{name} ({roles[int(rank[k])]})", fontsize=8)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=20, azim=25)
    lim = 1.1 * L_norm
    ax.set(xlim=(-lim, lim), ylim=(-lim, lim), zlim=(-lim, lim))
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize=10)
    return ax
