"""The benchmark's peers, run in the same process as our methods: scipy's solve_ivp (RK45, DOP853)
on the problem's quaternion right-hand side, and MuJoCo (Euler, implicit, implicitfast, RK4) on the
problem as an MJCF model, when it is installed (requirements-peers.txt).  Each runner returns a Run
(runs.py), its error measured against the same reference R(T) as ours."""
from __future__ import annotations

import numpy as np

from ..rotation import matrix_from_quat, quat_from_matrix, rotation_angle
from .problems import Problem
from .runs import DIVERGED, Run, timed

SCIPY_SOLVERS = ("RK45", "DOP853")
MUJOCO_INTEGRATORS = ("Euler", "implicit", "implicitfast", "RK4")


def mujoco_installed() -> bool:
    try:
        import mujoco  # noqa: F401
    except ImportError:
        return False
    return True


def run_scipy(problem: Problem, solver: str, rtol: float, repeats: int, min_total: float = 0.0) -> Run:
    """scipy.integrate.solve_ivp(method=solver, rtol=atol=rtol) on problem.rhs(): y = (ω_b, q)."""
    from scipy.integrate import solve_ivp
    f, y0 = problem.rhs(), problem.y0()
    seconds, sol = timed(lambda: solve_ivp(f, (0.0, problem.T), y0, method=solver, rtol=rtol, atol=rtol), repeats,
                         min_total)
    error = float(rotation_angle(problem.reference_R(), matrix_from_quat(sol.y[3:, -1]))) if sol.success else DIVERGED
    return Run(problem.name, "scipy", solver, rtol, int(sol.t.size - 1), seconds, error)


def mujoco_model(problem: Problem, integrator: str, dt: float):
    """The problem as a MuJoCo model: a free box (A, B) or a disc on a ball joint at the origin (C)."""
    import mujoco
    I = np.diag(problem.body.I_body)
    inertia = " ".join(f"{v:.17g}" for v in I)
    if problem.pivot_com:
        joint = '<joint type="ball"/>'
        pos = f"0 0 {problem.pivot_com:.17g}"
    else:
        joint, pos = "<freejoint/>", "0 0 0"
    xml = f"""<mujoco><option gravity="0 0 {-problem.gravity:.17g}" integrator="{integrator}" timestep="{dt:.17g}"/>
      <worldbody><body name="b">{joint}<inertial pos="{pos}" mass="{problem.body.mass:.17g}" diaginertia="{inertia}"/>
      </body></worldbody></mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def run_mujoco(problem: Problem, integrator: str, dt: float, repeats: int, min_total: float = 0.0) -> Run:
    """MuJoCo's integrator at the fixed step dt; a blow-up (non-finite or collapsed quaternion) is DIVERGED."""
    import mujoco
    mujoco.set_mju_user_warning(lambda message: None)      # a blow-up is measured, not printed
    model = mujoco_model(problem, integrator, dt)
    data = mujoco.MjData(model)
    n = round(problem.T / dt)
    q0 = quat_from_matrix(problem.X0.R)

    def go():
        mujoco.mj_resetData(model, data)
        if problem.pivot_com:
            data.qpos[:4], data.qvel[:3] = q0, problem.omega0_body
        else:
            data.qpos[3:7], data.qvel[3:6] = q0, problem.omega0_body
        mujoco.mj_step(model, data, nstep=n)
        return data.xquat[1].copy()
    with np.errstate(all="ignore"):
        seconds, q = timed(go, repeats, min_total)
    ok = np.all(np.isfinite(q)) and np.linalg.norm(q) > 0.5
    error = float(rotation_angle(problem.reference_R(), matrix_from_quat(q))) if ok else DIVERGED
    return Run(problem.name, "mujoco", integrator, dt, n, seconds, error)


RUNNERS = {"scipy": run_scipy, "mujoco": run_mujoco}
