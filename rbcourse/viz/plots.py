"""Matplotlib plots of trajectories (they return Axes; never plt.show()), and of the benchmark's saved
results (the work-precision diagram).  Plots read results; they never compute them: nothing here imports bench.

Titles, axis labels and legends are in the workbook's language (rbcourse.workbook.langue("fr"): in
French; English by default): one table per language, TEXTS, keyed by the same ids and placeholders (made from
_WORDS, where each id is written once with its text in every language)."""
from __future__ import annotations

import textwrap

import numpy as np

from ..support import checks
from ..support.language import LANGUAGES, text
from ..trajectory import shown
from . import figures, plot_inputs

figures.register()          # in a notebook: its figures as 256-colour PNGs (figures.py); elsewhere nothing

_WORDS = {
    "run": ("run {i}", "calcul {i}"), "diverged": ("diverged", "divergé"),
    "diverged_at": ("{label} (diverged at t = {t} s)", "{label} (divergé à t = {t} s)"),
    "drift_energy": ("|E − E₀| / |E₀|  (energy drift)", "|E − E₀| / |E₀|  (dérive de l'énergie)"),
    "drift_L": ("‖L − L₀‖ / ‖L₀‖  (angular momentum about the centre of mass)",
                "‖L − L₀‖ / ‖L₀‖  (moment cinétique au centre de masse)"),
    "drift_Lz": ("|L_z − L_z₀| / ‖L₀‖  (L_z about the {where} {p})", "|L_z − L_z₀| / ‖L₀‖  (L_z autour du {where} {p})"),
    "pivot": ("pivot", "pivot"), "anchor": ("spring's anchor", "point d'attache du ressort"),
    "not_kept": ("{what}: not conserved by this scene\n({why}): no drift to plot",
                 "{what} : non conservé dans cette scène\n({why}) : pas de dérive à tracer"),
    "kept": ("conserved", "quantité conservée"), "not_kept_short": ("not conserved here", "non conservée ici"),
    "exactly_0": ("exactly 0", "exactement 0"), "all_zero": ("exactly 0 throughout", "exactement 0 tout du long"),
    "Lz_about": ("L_z about the {where} {p} (kg m²/s)", "L_z autour du {where} {p} (kg m²/s)"),
    "L_com": ("|L| about the centre of mass (kg m²/s)", "|L| au centre de masse (kg m²/s)"),
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
"""The plots' words, per language (rbcourse.support.language.text): the same ids and placeholders."""


def conserved(traj, t_from: float = 0.0):
    """What the physics of the run's scene keeps from t_from on (quantities.plan: energy, L about the centres of
    mass or L_z about a pivot, or neither), read from its effects."""
    from . import quantities
    t = shown("traj", traj).t
    t_from = checks.real("t_from", t_from)
    if not t[0] - 1e-9 * (1 + abs(t[0])) <= t_from <= t[-1]:
        raise ValueError(f"t_from must be within the trajectory's times [{t[0]:g}, {t[-1]:g}], got {t_from:g}")
    step = (t[-1] - t[0]) / (len(t) - 1) if len(t) > 1 else 1.0
    return quantities.plan(traj.scene, float(t_from), float(t[-1]), step)


def drift(traj, t_from: float = 0.0) -> dict:
    """Drift diagnostics of one trajectory over time, from t_from on (default: the start), of what its scene
    conserves (conserved(traj, t_from)) — any change of it is the method's error:
    "energy" (E − E₀)/|E₀| when the scene keeps E; "angular_momentum" when it keeps L (‖L − L₀‖/‖L₀‖, L about
    the centre of mass, world axes) or L_z about a pivot (|L_z − L_z₀|/‖L₀‖); "orthogonality" ‖RᵀR − I‖, always;
    "t" the times; "plan" what was measured (quantities.Plan).  A quantity the scene does not keep has no key."""
    from . import quantities
    p = conserved(traj, t_from)
    k0 = quantities.first_at(traj.t, p.t0)
    d = quantities.drifts(p, traj)
    out = {"t": traj.t[k0:], "plan": p}
    for key, name in (("energy", "energy"), ("momentum", "angular_momentum"), ("orthogonality", "orthogonality")):
        if key in d:
            out[name] = d[key][k0:]
    return out


def _drift_titles(p) -> list:
    """The three panels' titles: energy, the momentum the scene keeps, ‖RᵀR − I‖ — or why it keeps none."""
    energy = text(TEXTS, "drift_energy") if p.energy_conserved else text(TEXTS, "not_kept").format(
        what="E", why=p["energy"].why)
    if p.momentum == "com":
        momentum = text(TEXTS, "drift_L")
    elif p.momentum == "vertical":
        momentum = text(TEXTS, "drift_Lz").format(where=_where(p), p=_point(p.point))
    else:
        momentum = text(TEXTS, "not_kept").format(what="L", why=p["momentum"].why)
    return [energy, momentum, text(TEXTS, "drift_R")]


def _where(p) -> str:
    """What p is (a pivot, a spring's anchor), in the workbook's language."""
    return text(TEXTS, "pivot" if "pivot" in p["momentum"].title else "anchor")


def _point(p) -> str:
    return "(" + ", ".join(f"{v:g}" for v in np.round(p, 6)) + ")"


def plot_drift(trajs, labels=None, axes=None, t_from: float = 0.0, floor: float = 1e-17, ceiling: float = 1e3):
    """The drift of what the scene conserves — |energy drift|, the momentum it keeps (L, or L_z about its pivot) —
    and ‖RᵀR − I‖ over time on log axes, one line per trajectory (drift); a quantity the scene does not keep
    gets no curve, its panel says why.

    trajs: a Trajectory or a list of them (e.g. several methods on one scene).
    labels: None (each run's method) or one string per trajectory; axes: None (a figure made here) or 3 Axes.
    Values are clipped to [floor, ceiling], 1e-300 <= floor < ceiling <= 1e300 (plot_inputs.FLOOR_RANGE: log axes, with room
    for the zeros' row at floor / 1000), so that a blow-up stays on the plot; an exact zero is drawn on
    its own row under the floor, labelled "exactly 0" (not as a tiny number).  The legend is under the
    panels (a figure made here: outside its axes; on given axes, at the figure's foot: leave room there).
    Returns the array of 3 Axes.
    """
    import matplotlib.pyplot as plt

    trajs = plot_inputs.trajectories(trajs)
    if labels is None:
        labels = [t.method or text(TEXTS, "run").format(i=i) for i, t in enumerate(trajs)]
    labels = plot_inputs.labels(labels, len(trajs))
    floor, ceiling = plot_inputs.bounds(floor, ceiling)
    axes = plot_inputs.axes("axes", axes, 3)
    made = axes is None
    if made:
        _, axes = plt.subplots(1, 3, figsize=(13, 3.9), constrained_layout=True)
    keys = ["energy", "angular_momentum", "orthogonality"]
    zero = floor / 100                  # the row of the exact zeros, under the floor
    for ax in axes:
        ax.set_yscale("log")
        ax.set_ylim(zero / 10, ceiling * 3)
    handles, names, zeros = [], [], {}
    for traj, label in zip(trajs, labels):
        d = drift(traj, t_from)
        if traj.diverged and text(TEXTS, "diverged") not in label:
            label = text(TEXTS, "diverged_at").format(label=label, t=f"{traj.divergence.t:.3g}")
        for ax, key in zip(axes, keys):
            if key not in d:
                continue
            v = np.abs(d[key])
            line, = ax.plot(d["t"], np.where(v == 0, zero, np.clip(v, floor, ceiling)), label=label)
            if traj.diverged:
                mark_divergence(ax, traj, line)
            if not np.any(v[np.isfinite(v)]):          # said in words too: a flat line on the zero row
                zeros.setdefault(key, []).append(label)
            if key == "orthogonality":
                handles.append(line)
                names.append(label)
    for ax, key in zip(axes, keys):
        if key in zeros:
            words = f"{text(TEXTS, 'all_zero')}: " + ", ".join(zeros[key])
            ax.text(0.98, zero * 30, textwrap.fill(words, 60), fontsize=8, ha="right", va="bottom", color="0.25",
                    transform=ax.get_yaxis_transform())
    for ax, title in zip(axes, _drift_titles(drift(trajs[0], t_from)["plan"])):
        if "\n" in title:                  # not conserved: no axes, the reason in their place
            ax.set_axis_off()
            ax.text(0.5, 0.5, "\n".join(textwrap.fill(part, 44) for part in title.split("\n")), ha="center",
                    va="center", transform=ax.transAxes, fontsize=9, color="0.3")
            continue
        ax.set_title(title, fontsize=10)
        ax.set_xlabel(text(TEXTS, "time"))
        ax.set_ylim(zero / 10, ceiling * 3)
        ax.axhspan(zero / 10, floor / 10, color="0.93", lw=0)          # the exact zeros' row
        ticks = [zero] + [10.0 ** k for k in range(-15, 4, 3)]
        ax.set_yticks(ticks, [text(TEXTS, "exactly_0")] + [f"$10^{{{k}}}$" for k in range(-15, 4, 3)])
        ax.minorticks_off()
        ax.grid(True, alpha=0.3)
    fig = axes[0].figure
    if made:
        fig.legend(handles, names, loc="outside lower center", ncol=min(3, len(names)), fontsize=8)
    else:
        fig.legend(handles, names, loc="lower center", ncol=min(3, len(names)), fontsize=8, frameon=False)
    return axes


def _at_least_percent(ax):
    """A linear axis spanning at least 2% of its curves' size: a value kept to 1e-9 shows flat, not as noise
    magnified under a tick offset (its drift is plot_drift's)."""
    ys = [line.get_ydata() for line in ax.get_lines()]
    ys = np.concatenate([y[np.isfinite(y)] for y in ys]) if ys else np.zeros(0)
    if ys.size == 0:
        return
    lo, hi = float(ys.min()), float(ys.max())
    half = max((hi - lo) * 0.55, 0.01 * max(abs(lo), abs(hi)), 1e-12)
    mid = (lo + hi) / 2
    ax.set_ylim(mid - half, mid + half)
    ax.ticklabel_format(axis="y", useOffset=False)


def mark_divergence(ax, traj, line=None):
    """A diverged run's end on a time axis: a dotted line at the time of the blow-up and, given the
    run's curve (a Line2D), a cross where it stops (what would come after is overflow, not physics)."""
    if not traj.diverged:
        return
    color = line.get_color() if line is not None else "k"
    ax.axvline(traj.divergence.t, color=color, linestyle=":", linewidth=1.2)
    if line is not None and len(line.get_xdata()):
        ax.plot(line.get_xdata()[-1:], line.get_ydata()[-1:], marker="x", color=color, markersize=7)


def plot_energy_momentum(traj, axes=None, t_from: float = 0.0):
    """Kinetic, potential and total energy, and the angular momentum the scene keeps from t_from on
    (conserved: |L| about the centre of mass, or L_z about its pivot; else |L| about the origin, said not
    conserved), over time."""
    import matplotlib.pyplot as plt

    p = conserved(traj, t_from)
    axes = plot_inputs.axes("axes", axes, 2)
    if axes is None:
        _, axes = plt.subplots(1, 2, figsize=(10, 3.4), constrained_layout=True)
    T, U = traj.kinetic_energy(), traj.potential_energy()
    if T.ndim > 1:
        T, U = T.sum(-1), U.sum(-1)
    axes[0].plot(traj.t, T, label=text(TEXTS, "kinetic"))
    if np.any(U):
        axes[0].plot(traj.t, U, label=text(TEXTS, "potential"))
        axes[0].plot(traj.t, T + U, label=text(TEXTS, "total"), color="k")
    kept = text(TEXTS, "kept") if p.energy_conserved else text(TEXTS, "not_kept_short")
    axes[0].set_title(text(TEXTS, "energy") + f" — {kept}" + (f" — {traj.outcome}" if traj.diverged else ""),
                      fontsize=10)
    if p.momentum == "vertical":
        axes[1].plot(traj.t, traj.angular_momentum(p.point)[:, 2])
        title = text(TEXTS, "Lz_about").format(where=_where(p), p=_point(p.point)) + " — " + text(TEXTS, "kept")
    else:
        L = traj.angular_momentum("com" if p.momentum == "com" else "origin")
        if L.ndim > 2:
            L = L.sum(-2)
        axes[1].plot(traj.t, np.linalg.norm(L, axis=-1))
        title = text(TEXTS, "L_com" if p.momentum == "com" else "L_norm") + " — " + \
            text(TEXTS, "kept" if p.momentum == "com" else "not_kept_short")
    axes[1].set_title(title, fontsize=10)
    for ax in axes:
        _at_least_percent(ax)
        mark_divergence(ax, traj)
        if traj.diverged:         # its last values are 10⁵⁰… times the first: a linear axis shows one spike
            ax.set_yscale("symlog", linthresh=max(abs(float(T[0])), 1e-12))
        if p.t0 > traj.t[0]:
            ax.axvspan(traj.t[0], p.t0, color="0.9", lw=0)         # before t_from: not kept (the push acts)
    for ax in axes:
        ax.set_xlabel(text(TEXTS, "time"))
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8, loc="best")          # where it covers the fewest points
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
    runs = plot_inputs.runs(runs)
    if not hasattr(path, "write"):               # a file object (work_precision_png's buffer) or a path
        path = checks.file_path("path", path)
    note = checks.text("note", note)
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
    energy: None or a positive kinetic energy (J), with √(2E Iᵢ) finite.
    Draw polhodes over it with ax.plot(*L_b.T).  Returns ax."""
    if getattr(ax, "name", None) != "3d" or not hasattr(ax, "plot_wireframe"):
        raise ValueError(f"ax must be a 3-D matplotlib Axes (fig.add_subplot(projection=\"3d\")), got {ax!r}")
    inertia = np.asarray(inertia, dtype=float)
    moments = np.diag(inertia) if inertia.shape == (3, 3) else inertia
    if moments.shape != (3,) or not np.all(moments > 0):
        raise ValueError(f"inertia must be 3 positive principal moments or a 3×3 I_body, got {inertia!r}")
    if not (np.isfinite(L_norm) and L_norm > 0):
        raise ValueError(f"L_norm must be a positive number, got {L_norm!r}")
    if energy is not None:
        energy = checks.positive("energy", energy)
        if not np.all(moments <= checks.HUGE / (2 * energy)):          # 2E Iᵢ finite, without overflowing
            raise ValueError(f"energy must be None or a positive number with 2·energy·Iᵢ finite (the ellipsoid's "
                             f"semi-axes √(2E Iᵢ)), got {energy!r} with inertia {moments.tolist()}")
    title = checks.text("title", title)
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
