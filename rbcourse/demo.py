"""The demo: run a named scene, compare with the slides' Euler, write data, plots, a summary and a 3-D page."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .integrators import get_method
from .plots import drift, plot_drift, plot_energy_momentum
from .rotation import quat_from_matrix
from .scenes import get_scene
from .simulate import simulate
from .trajectory import SimulationDiverged


def run_demo(scene_name: str = "pushed_box", *, method=None, t_end=None, dt=None, out: Path = Path("demo_output"),
             live: bool = False):
    """Simulate a named scene; write trajectory.csv, drift.png, energy.png, summary.txt and SCENE.html into `out`.

    SCENE.html is the 3-D animation (meshcat), a standalone page: the run, with the slides'
    Euler beside it as a ghost.  live: also send it to this process's live meshcat server
    (rbcourse.viewer.live_server(); its .url is where to look; close_live_server() stops it).
    Returns the list of paths written.
    """
    if not isinstance(live, bool):
        raise ValueError(f"live must be True or False, got {live!r}")
    os.environ.setdefault("MPLBACKEND", "Agg")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ex = get_scene(scene_name)
    method = get_method(method or ex.method).name
    t_end = ex.t_end if t_end is None else t_end
    dt = ex.dt if dt is None else dt
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    traj = simulate(ex.scene, ex.X0, t_end, dt, method, progress=True)
    runs, labels = [traj], [method]
    if method != "euler":
        try:
            runs.append(simulate(ex.scene, ex.X0, t_end, dt, "euler"))
            labels.append("euler (the slides')")
        except SimulationDiverged as err:
            runs.append(err.trajectory)
            labels.append(f"euler (diverged at t = {err.t:.3g} s)")
    t_from = min(ex.drift_from, *(r.t[-1] for r in runs))
    written = []
    path = out / "trajectory.csv"
    _write_csv(path, traj)
    written.append(path)
    path = out / "energy.png"
    axes = plot_energy_momentum(traj)
    axes[0].figure.suptitle(f"{ex.name}: {method}, dt = {traj.dt:g} s", fontsize=11)
    axes[0].figure.savefig(path, dpi=110)
    plt.close(axes[0].figure)
    written.append(path)
    path = out / "drift.png"
    axes = plot_drift(runs, labels, t_from=t_from)
    axes[0].figure.suptitle(f"{ex.name}: drift of {' vs '.join(labels)}", fontsize=11)
    axes[0].figure.savefig(path, dpi=110)
    plt.close(axes[0].figure)
    written.append(path)
    path = out / "summary.txt"
    path.write_text(_summary(ex, runs, labels, t_from), encoding="utf-8")
    written.append(path)
    drawing = _drawing(ex, runs, labels)
    written.append(drawing.save(out / f"{ex.name}.html"))
    if live:
        drawing.show()
    return written


def _write_csv(path: Path, traj):
    q = quat_from_matrix(traj.R) if traj.x.ndim == 2 else None
    cols = [traj.t[:, None], traj.x, q, traj.P, traj.L, traj.kinetic_energy()[:, None], traj.total_energy()[:, None]]
    header = "t,x,y,z,qw,qx,qy,qz,Px,Py,Pz,Lx,Ly,Lz,kinetic_energy,total_energy"
    np.savetxt(path, np.hstack(cols), delimiter=",", header=header, comments="", fmt="%.10g")


def _summary(ex, runs, labels, t_from: float) -> str:
    lines = [ex.scene.describe(runs[0].method), "", f"{ex.description}.", ""]
    for traj, label in zip(runs, labels):
        d = drift(traj, t_from=t_from)
        lines.append(f"{label}: {len(traj.t) - 1} steps of dt = {traj.dt:g} s up to t = {traj.t[-1]:g} s; "
                     f"final energy error {d['energy'][-1]:+.3e}, |L| drift {d['angular_momentum'][-1]:.3e}, "
                     f"‖RᵀR − I‖ {d['orthogonality'][-1]:.3e}, det R {np.linalg.det(traj.R[-1]):.6g}")
    return "\n".join(lines) + "\n"


def _drawing(ex, runs, labels):
    """The 3-D animation: the run, and the slides' Euler beside it as a semi-transparent ghost."""
    from . import viewer  # meshcat is imported only here
    ghost = runs[1] if len(runs) > 1 else None
    size = max(2 * float(b.half_extents().max()) for b in ex.scene.bodies)
    return viewer.draw_trajectory(runs[0], ghost=ghost, ghost_offset=(0.0, 1.5 * size, 0.0),
                                  ghost_label=labels[1] if ghost is not None else "",
                                  title=f"{ex.scene.name or ex.name}: {labels[0]}, dt = {runs[0].dt:g} s")
