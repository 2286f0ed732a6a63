"""The demo: run a named scene, compare with the slides' Euler, write data, plots and a summary."""
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


def run_demo(scene_name: str = "pushed_box", *, method=None, t_end=None, dt=None, out: Path = Path("demo_output")):
    """Simulate a named scene; write trajectory.csv, drift.png, energy.png and summary.txt into `out`.

    Returns the list of paths written.
    """
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
