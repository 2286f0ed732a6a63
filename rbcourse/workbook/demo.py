"""The demo: run a named scene, compare with the slides' Euler, write data, plots, a summary and a 3-D page."""
from __future__ import annotations

import contextlib
import os
import threading
from pathlib import Path

import numpy as np

from .. import compiling
from ..support import checks
from ..support.language import say
from ..support.outputs import writable_folder
from ..methods import get_method
from ..viz.plots import drift, plot_drift, plot_energy_momentum
from ..viz.quantities import name as quantity_name
from ..rotation import quat_from_matrix
from ..examples import get_scene
from ..simulate import simulate
from ..trajectory import Trajectory


MAX_STATES = 10**6     # steps × bodies: the demo keeps every state of both runs, and writes each as a CSV row


def output_names(scene_name: str) -> list[str]:
    """The files `run_demo(scene_name)` writes: each named after its scene, so that the demos
    of two scenes written into one folder keep their own."""
    return [f"{scene_name}_{name}" for name in ("trajectory.csv", "energy.png", "drift.png", "summary.txt")] \
        + [f"{scene_name}.html", f"{scene_name}_explorer.html"]


def check_arguments(scene_name: str = "pushed_box", *, method=None, t_end=None, dt=None, live: bool = False):
    """The demo's arguments, checked before anything is computed or written: (example, method, t_end, dt).
    method, t_end, dt: None takes the scene's.  A ValueError names the first bad one.  At most
    MAX_STATES states (t_end / dt steps × bodies): the demo records every step of its run and of
    the slides' Euler beside it, and writes each as a CSV row (10⁶ rows: over 100 MB)."""
    if not isinstance(live, bool):
        raise ValueError(f"live must be True or False, got {live!r}")
    ex = get_scene(scene_name)
    method = get_method(ex.method if method is None else method).name
    t_end = ex.t_end if t_end is None else checks.positive("t_end", t_end)
    dt = ex.dt if dt is None else checks.positive("dt", dt)
    if dt > t_end:
        raise ValueError(f"dt must be <= t_end = {t_end:g} s, got dt = {dt:g} s")
    steps, bodies = t_end / dt, len(ex.scene.bodies)          # inf when it overflows (t_end = 1e308, dt = 1e-3)
    if not (steps <= MAX_STATES and round(steps) * bodies <= MAX_STATES):
        raise ValueError(f"too many recorded states: t_end / dt × bodies must be at most {MAX_STATES:,}, got "
                         f"{steps:,.0f} steps × {bodies} bod{'y' if bodies == 1 else 'ies'} (t_end = {t_end:g} s, "
                         f"dt = {dt:g} s)")
    return ex, method, t_end, dt


def run_demo(scene_name: str = "pushed_box", *, method=None, t_end=None, dt=None, out: Path = Path("demo_output"),
             live: bool = False):
    """Simulate a named scene; write SCENE_trajectory.csv, SCENE_energy.png, SCENE_drift.png,
    SCENE_summary.txt, SCENE.html and SCENE_explorer.html into `out` (see output_names).

    SCENE.html is the linked view (meshcat), a standalone page: the run in 3-D, with the slides'
    Euler beside it as a ghost, and under them the drift of both with one time cursor.  SCENE_explorer.html is the accuracy explorer (rbcourse.viz.explore):
    four methods × four steps of the scene, pick one and watch the body and its drift together, what
    each run cost in time beside its error (for many bodies: two methods × two steps, to stay quick).  live: also send it to this process's live meshcat server
    (rbcourse.viewer.live_server(); its .url is where to look; close_live_server() stops it).
    Every argument is checked (check_arguments), and `out` created and probed, before anything
    is computed.  Returns the list of paths written.
    """
    ex, method, t_end, dt = check_arguments(scene_name, method=method, t_end=t_end, dt=dt, live=live)
    out = writable_folder(out, "out", output_names(ex.name))
    theirs, ours = _compiles(ex, method)
    # the data files and plots, on the other core: meanwhile it loads them, and compiles its share of the runs
    plots = Beside(_matplotlib, _plots, first=lambda: _compile(ex, theirs, quiet=True))

    # a run that blows up (the slides' Euler, often) is part of the lesson: kept up to its blow-up, and said
    traj = simulate(ex.scene, ex.X0, t_end, dt, method, progress=True, on_divergence="stop")
    runs, labels = [traj], [_label(traj, method)]
    if method != "euler":
        runs.append(simulate(ex.scene, ex.X0, t_end, dt, "euler", on_divergence="stop"))
        labels.append(_label(runs[-1], say("euler (the slides')", "euler (celle des slides)")))
    t_from = min(ex.drift_from, *(r.t[-1] for r in runs))
    plots.give(out, ex, method, [Computed(r) for r in runs], labels, t_from)
    euler = runs[1] if method != "euler" else traj
    _compile(ex, ours)
    plots.warmed()                                    # its share compiled too: the explorer's runs compile nothing
    explorer = _explorer(ex, method, dt, euler, t_end).save(out / f"{ex.name}_explorer.html")
    drawing = _drawing(ex, runs, labels, t_from)      # here: meshcat and the compiled rows are loaded in this process
    linked = drawing.save(out / f"{ex.name}.html")
    written = [*plots.result(), linked, explorer]
    if live:
        drawing.show()
    return written


def _plots(out: Path, ex, method: str, runs, labels, t_from: float) -> list[Path]:
    """SCENE_trajectory.csv, SCENE_energy.png (the run's energy and |L|), SCENE_drift.png (the drifts of the
    runs beside each other) and SCENE_summary.txt: what the trajectories give, written beside the explorer and the
    linked view (SCENE.html), which the demo's own process makes."""
    _matplotlib()
    import matplotlib.pyplot as plt
    traj = runs[0]
    csv, energy, drift_png, summary = (out / f"{ex.name}_{name}" for name in
                                       ("trajectory.csv", "energy.png", "drift.png", "summary.txt"))
    write_csv(csv, traj, traj.quaternions)
    axes = plot_energy_momentum(traj, axes=_panels(plt, 2, (10, 3.4)), t_from=t_from)
    axes[0].figure.suptitle(f"{ex.name}{say(': ', ' : ')}{method}, dt = {traj.dt:g} s", fontsize=11)
    axes[0].figure.savefig(energy, dpi=110)
    plt.close(axes[0].figure)
    axes = plot_drift(runs, labels, t_from=t_from, axes=_panels(plt, 3, (13, 4.2), bottom=0.26))
    axes[0].figure.suptitle(say(f"{ex.name}: drift of {' vs '.join(labels)}",
                                f"{ex.name} : dérive de {' contre '.join(labels)}"), fontsize=11)
    axes[0].figure.savefig(drift_png, dpi=110)
    plt.close(axes[0].figure)
    summary.write_text(_summary(ex, runs, labels, t_from), encoding="utf-8")
    return [csv, energy, drift_png, summary]


class Beside:
    """fn(*args) run in a process forked now, beside this one (the machine's other core), where fork is the
    way processes start (Linux) and this process runs one thread (the command line; not a notebook's kernel):
    it runs first() at once (what this process will wait for: warmed()), then warm() (its imports), then waits for
    its arguments (give: sent through a pipe).
    Elsewhere it all runs here, in give().  result(): fn's value — a list of paths, sent
    back as text — once it is done; its error, if it failed, raised here as a RuntimeError with its message."""

    def __init__(self, warm, fn, first=None):
        import multiprocessing
        self.fn, self.value, self.process, self.early = fn, None, None, None
        if "fork" not in multiprocessing.get_all_start_methods() or os.name != "posix" or threading.active_count() > 1:
            return                                  # no fork, or threads that a fork could catch holding a lock
        ctx = multiprocessing.get_context("fork")
        self.receive, send = ctx.Pipe(duplex=False)
        self.inbox, self.post = ctx.Pipe(duplex=False)

        def child():
            try:
                if first is not None:
                    first()
                send.send(("warmed", None))
                warm()
                args = self.inbox.recv()
                send.send(("ok", [str(p) for p in fn(*args)]))
            except BaseException as err:                     # sent back, said by the parent
                send.send(("failed", f"{type(err).__name__}: {err}"))
        self.process = ctx.Process(target=child, daemon=True)
        self.process.start()
        send.close()
        self.inbox.close()          # only the process beside reads it: if it ends, a send here fails, not hangs

    def give(self, *args) -> None:
        """fn's arguments (pickled to the process beside, without waiting for it; or fn run here)."""
        if self.process is None:
            self.value = self.fn(*args)
        else:                       # sent by a thread: the pipe blocks until the process beside reads, done warming
            def send():
                try:
                    self.post.send(args)
                except OSError:             # the process beside ended first (it failed): result() says why
                    pass
            self.sender = threading.Thread(target=send, daemon=True)
            self.sender.start()

    def _next(self) -> tuple[str, object]:
        """The next word of the process beside: ("warmed", None), ("ok", paths) or ("failed", why)."""
        try:
            return self.receive.recv()
        except EOFError:
            return "failed", "it ended without a word"

    def warmed(self) -> None:
        """Returns once first() is done beside (at once where nothing runs beside); a failure is kept for result()."""
        if self.process is not None and self.early is None:
            self.early = self._next()

    def result(self) -> list[Path]:
        if self.process is None:
            return self.value
        kind, value = self.early if self.early is not None else self._next()
        if kind == "warmed":
            kind, value = self._next()
        self.process.join()
        self.sender.join()
        if kind != "ok" or self.process.exitcode != 0:
            raise RuntimeError(f"the demo's plots failed: {value if kind != 'ok' else f'exit code {self.process.exitcode}'}")
        return [Path(p) for p in value]


def _compiles(ex, method: str) -> tuple[list[str], list[str]]:
    """The methods whose loops the demo compiles beyond its own method's (the slides' Euler, the explorer's), shared
    between the process beside (theirs) and this one (ours), so that the two cores compile at once: theirs the
    slides' Euler (which this one runs next, while it runs its own method) and the second half of the others."""
    others = [m for m in _explorer_methods(ex, method) if m not in (method, "euler")]
    half = len(others) // 2
    return (["euler"] if method != "euler" else []) + others[half:], others[:half]


def _compile(ex, methods, quiet: bool = False) -> None:
    """Each method's loop for the scene compiled (numba keeps it in its disk cache): two steps of the scene.
    quiet: without the compile notice (the process beside: the demo's own process says what it compiles)."""
    with compiling.quiet() if quiet else contextlib.nullcontext():
        for m in methods:
            simulate(ex.scene, ex.X0, 2 * ex.dt, ex.dt, m, on_divergence="stop")


class Computed(Trajectory):
    """A run with what its files need of the compiled engine computed already, in the demo's own process (which
    has it loaded): its kinetic and potential energy at every step and the quaternions of its R.  The process
    beside, which writes the data files and plots of it, then never loads numba (0.2-0.3 s)."""

    def __init__(self, traj: Trajectory):
        super().__init__(traj.t, traj.x, traj.R, traj.P, traj.L, traj.scene, traj.method, traj.dt, traj.divergence,
                         traj.implementation)
        self._T, self._U = traj.kinetic_energy(), traj.potential_energy()
        self.quaternions = quat_from_matrix(traj.R)

    def kinetic_energy(self) -> np.ndarray:
        return self._T.copy()

    def potential_energy(self) -> np.ndarray:
        return self._U.copy()


def _matplotlib():
    """matplotlib, drawing to files (Agg), imported."""
    os.environ.setdefault("MPLBACKEND", "Agg")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot  # noqa: F401


def _panels(plt, n: int, size, bottom: float = 0.15):
    """n panels side by side on a figure of `size` inches, with fixed margins (room for the titles, the
    suptitle, log tick labels, the time axis and, with a larger bottom, a legend under the panels): a layout
    engine would measure every text twice per save."""
    fig, axes = plt.subplots(1, n, figsize=size)
    fig.subplots_adjust(left=0.07 if n == 2 else 0.065, right=0.985, bottom=bottom, top=0.78, wspace=0.25)
    return axes


def write_csv(path: Path, traj, q=None):
    """One row per recorded step; with N bodies, one row per step and body (a `body` column, 0 … N−1).
    q: the quaternions of traj.R, if known (else computed)."""
    q = quat_from_matrix(traj.R) if q is None else q
    if traj.x.ndim == 2:
        cols = [traj.t[:, None], traj.x, q, traj.P, traj.L, traj.kinetic_energy()[:, None],
                traj.total_energy()[:, None]]
        header = "t,x,y,z,qw,qx,qy,qz,Px,Py,Pz,Lx,Ly,Lz,kinetic_energy,total_energy"
    else:
        steps, n = traj.x.shape[:2]
        flat = lambda a: a.reshape(steps * n, -1)                                     # noqa: E731
        cols = [np.repeat(traj.t, n)[:, None], np.tile(np.arange(n), steps)[:, None], flat(traj.x), flat(q),
                flat(traj.P), flat(traj.L), flat(traj.kinetic_energy()), flat(traj.total_energy())]
        header = "t,body,x,y,z,qw,qx,qy,qz,Px,Py,Pz,Lx,Ly,Lz,kinetic_energy,total_energy"
    np.savetxt(path, np.hstack(cols), delimiter=",", header=header, comments="", fmt="%.10g")


def _label(traj, name: str) -> str:
    """The run's name, and when it diverged if it did."""
    if not traj.diverged:
        return name
    t = f"{traj.divergence.t:.3g}"
    return say(f"{name.split(' (')[0]} (diverged at t = {t} s)", f"{name.split(' (')[0]} (divergé à t = {t} s)")


def _summary(ex, runs, labels, t_from: float) -> str:
    lines = [ex.scene.describe(runs[0].method), "", f"{ex.description}.", ""]
    for traj, label in zip(runs, labels):
        if traj.diverged:             # its last numbers are overflow, not physics: say when it ended instead
            name, steps = label.split(' (')[0], len(traj.t) - 1
            lines.append(say(f"{name}: {traj.outcome}; {steps} steps of dt = {traj.dt:g} s kept, up to "
                             f"t = {traj.t[-1]:.4g} s",
                             f"{name} : {traj.outcome} ; {steps} pas de dt = {traj.dt:g} s gardés, jusqu'à "
                             f"t = {traj.t[-1]:.4g} s"))
            continue
        d = drift(traj, t_from=t_from)
        det = np.atleast_1d(np.linalg.det(traj.R[-1]))          # one per body
        det_R = f"{det[0]:.6g}" if det.size == 1 else f"{det.min():.6g} … {det.max():.6g}" + say(
            f" over the {det.size} bodies", f" sur les {det.size} corps")
        steps = len(traj.t) - 1
        lines.append(say(f"{label}: {steps} steps of dt = {traj.dt:g} s up to t = {traj.t[-1]:g} s; ",
                         f"{label} : {steps} pas de dt = {traj.dt:g} s jusqu'à t = {traj.t[-1]:g} s ; ")
                     + ", ".join(kept_drifts(d)) + f", ‖RᵀR − I‖ {d['orthogonality'][-1]:.3e}, det R {det_R}")
    plan = drift(runs[0], t_from=t_from)["plan"]
    lines += ["", say(f"Drifts from t = {plan.t0:g} s of what this scene conserves (any change is the method's error):",
                      f"Dérives à partir de t = {plan.t0:g} s de ce que cette scène conserve (toute variation est "
                      "l'erreur de la méthode) :")]
    lines += [f"  {q.title}{say(': ', ' : ')}{q.note}" for q in plan.quantities[:2] if q.mode == "drift"]
    lines += [say(f"  not conserved here, so not a drift: {q.key} ({q.why})",
                  f"  pas conservé ici, donc pas une dérive : {quantity_name(q.key)} ({q.why})")
              for q in plan.quantities[:2] if q.mode != "drift"]
    return "\n".join(lines) + "\n"


def kept_drifts(d: dict) -> list[str]:
    """The summary's words for the final drift of each quantity the scene conserves (d: plots.drift)."""
    p, out = d["plan"], []
    if "energy" in d:
        out.append(say("final energy drift (E − E₀)/|E₀| ", "dérive finale de l'énergie (E − E₀)/|E₀| ")
                   + _value(d['energy'][-1], '+.3e'))
    if p.momentum == "com" and "angular_momentum" in d:
        out.append(say("L drift ‖L − L₀‖/‖L₀‖ (about the centre of mass) ",
                       "dérive de L ‖L − L₀‖/‖L₀‖ (au centre de masse) ") + _value(d['angular_momentum'][-1], '.3e'))
    elif p.momentum == "vertical" and "angular_momentum" in d:
        point = np.round(p.point, 6).tolist()
        out.append(say(f"L_z drift |L_z − L_z₀|/‖L₀‖ (about p = {point}) ",
                       f"dérive de L_z |L_z − L_z₀|/‖L₀‖ (autour de p = {point}) ")
                   + _value(d['angular_momentum'][-1], '.3e'))
    return out or [say("neither energy nor angular momentum is conserved in this scene",
                       "ni l'énergie ni le moment cinétique ne sont conservés dans cette scène")]


def _value(v: float, fmt: str) -> str:
    """A drift in the summary: "exactly 0" when it is (not 0.000e+00, which could be a rounded 1e-300)."""
    return say("exactly 0", "exactement 0") if v == 0 else format(v, fmt)


def _explorer_methods(ex, method: str) -> list[str]:
    """The explorer's methods (_explorer): the default ones, the demo's method in place of the last."""
    from ..viz.explorer import DEFAULT_METHODS
    if len(ex.scene.bodies) > 1:
        return list(dict.fromkeys(["euler", method]))
    methods = list(dict.fromkeys([*DEFAULT_METHODS, method]))
    return methods[:3] + [method] if len(methods) > 4 else methods


def _explorer(ex, method: str, dt: float, euler, t_end: float):
    """The explorer page of the scene, opened at the demo's own run (method at dt): the default grid (euler,
    splitting, rk4, exact_splitting × the scene's dt × 20, 10, 5, 2.5), with the demo's method and dt added, and
    the largest step at which the slides' Euler survives the run (euler_survives); a scene of many bodies gets
    euler and the demo's method at its dt × 10 and × 5, and its dt."""
    from ..viz import explore
    methods = _explorer_methods(ex, method)
    factors = (10.0, 5.0) if len(ex.scene.bodies) > 1 else (20.0, 10.0, 5.0, 2.5)
    dts = [ex.dt * f for f in factors]
    survives = euler_survives(ex, euler, t_end)
    dts = sorted({*dts, dt, *([survives] if survives else [])}, reverse=True)
    return explore(ex, methods=methods, dts=dts, t_end=t_end, default=(method, dt))


def euler_survives(ex, euler, t_end: float, max_steps: int = 400_000) -> float | None:
    """The largest step dt / 2^k (k >= 0) at which the slides' Euler runs the scene to t_end without blowing up,
    at most max_steps steps (euler: its run at the demo's dt); None if it blows up at every such step."""
    h = euler.dt
    while euler.diverged:
        h /= 2
        if t_end / h > max_steps:
            return None
        euler = simulate(ex.scene, ex.X0, t_end, h, "euler", on_divergence="stop")
    return h


def _drawing(ex, runs, labels, t_from: float):
    """The linked view: the run in 3-D, the slides' Euler beside it as a semi-transparent ghost, and under them the
    drift of both over time (what the scene conserves, from t_from on; ‖RᵀR − I‖), one time cursor for all."""
    from ..viz import viewer  # meshcat is imported only here
    ghost = runs[1] if len(runs) > 1 else None
    size = max(2 * float(b.half_extents().max()) for b in ex.scene.bodies)
    return viewer.draw_trajectory(runs, ghost=ghost, ghost_offset=(0.0, 1.5 * size, 0.0),
                                  ghost_label=labels[1] if ghost is not None else "", plots=True,
                                  labels=[label.split(" (")[0] for label in labels], drift_from=t_from,
                                  ghost_is_reference=False,
                                  title=f"{ex.scene.name or ex.name}{say(': ', ' : ')}{labels[0]}, dt = {runs[0].dt:g} s")
