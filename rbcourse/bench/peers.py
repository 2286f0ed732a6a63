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


# ------------------------------------------------------------------ many boxes, and boxes on the ground


def _mujoco_memory(n: int, ground: bool) -> str:
    """A <size memory=…/> large enough for n boxes (MuJoCo's default arena holds ~1000 boxes on a plane: 10⁴
    of them fail with 'Could not allocate memory'), or '' for MuJoCo's default."""
    if n <= 1000:
        return ""
    return f'<size memory="{(n * (100 if ground else 20)) // 1000 + 16}M"/>'


def mujoco_boxes_model(masses, sizes, integrator: str, dt: float, gravity: float = 0.0, friction: float | None = None,
                       positions=None):
    """N free boxes as one MuJoCo model: body i a free joint with mass masses[i] and the inertia of a solid box of
    full sides sizes[i] (the same numbers as RigidBody.box: I = m/12 · diag(b²+c², a²+c², a²+b²), given as
    <inertial>), and a box geom of those half sides.  friction None: no geom collides (free boxes, no contacts);
    a number μ: a plane z = 0 under them, box–plane contacts only (no box–box pairs, as our Ground), condim 3,
    sliding friction μ (MuJoCo's default solref / solimp: soft contacts).  positions (N, 3): where the bodies'
    frames start (only the model's qpos0; a runner sets the state it times).  Gravity (0, 0, −gravity)."""
    import mujoco
    m = np.asarray(masses, dtype=float).reshape(-1)
    a = np.asarray(sizes, dtype=float).reshape(m.size, 3)
    pos = np.zeros((m.size, 3)) if positions is None else np.asarray(positions, dtype=float).reshape(m.size, 3)
    f = lambda v: f"{v:.17g}"      # noqa: E731
    if friction is None:
        collide = 'contype="0" conaffinity="0"'
        plane = ""
    else:
        mu = f"{f(friction)} 0.005 0.0001"
        collide = f'contype="1" conaffinity="0" condim="3" friction="{mu}"'
        plane = (f'<geom name="ground" type="plane" size="0 0 1" contype="0" conaffinity="1" condim="3" '
                 f'friction="{mu}"/>')
    bodies = []
    for i in range(m.size):
        A, B, C = a[i]
        I = (m[i] / 12 * (B * B + C * C), m[i] / 12 * (A * A + C * C), m[i] / 12 * (A * A + B * B))
        bodies.append(f'<body pos="{f(pos[i, 0])} {f(pos[i, 1])} {f(pos[i, 2])}"><freejoint/>'
                      f'<inertial pos="0 0 0" mass="{f(m[i])}" diaginertia="{f(I[0])} {f(I[1])} {f(I[2])}"/>'
                      f'<geom type="box" size="{f(A / 2)} {f(B / 2)} {f(C / 2)}" {collide}/></body>')
    xml = (f'<mujoco>{_mujoco_memory(m.size, friction is not None)}'
           f'<option gravity="0 0 {f(-gravity)}" integrator="{integrator}" timestep="{f(dt)}"/>'
           f'<worldbody>{plane}{"".join(bodies)}</worldbody></mujoco>')
    return mujoco.MjModel.from_xml_string(xml)


def mujoco_ground_model(masses, sizes, integrator: str = "RK4", dt: float = 1e-3, friction: float = 0.5,
                        gravity: float = 9.81, positions=None):
    """N boxes over the ground plane z = 0, under gravity (mujoco_boxes_model with a plane): the peer of a
    Scene(boxes, [Gravity(), Ground(height=0, friction=μ)]).  Its contacts are MuJoCo's soft ones, ours
    impulses: the scenes match in bodies, start and step, not in contact model."""
    return mujoco_boxes_model(masses, sizes, integrator, dt, gravity=gravity, friction=friction, positions=positions)


def mujoco_state(bodies, X) -> tuple[np.ndarray, np.ndarray]:
    """Our State X of the bodies (a RigidBody, or a sequence of N) as MuJoCo's free joints' (qpos, qvel), flattened
    N × 7 and N × 6: qpos = (x, quaternion w x y z: rotation.quat_from_matrix's order), qvel = (v = P / M in world
    axes, ω in body axes: I_body⁻¹ Rᵀ L)."""
    bodies = (bodies,) if hasattr(bodies, "I_body_inv") else tuple(bodies)
    x = np.asarray(X.x, dtype=float).reshape(-1, 3)
    R = np.asarray(X.R, dtype=float).reshape(-1, 3, 3)
    P = np.asarray(X.P, dtype=float).reshape(-1, 3)
    L = np.asarray(X.L, dtype=float).reshape(-1, 3)
    if len(bodies) == 1 and x.shape[0] > 1:
        bodies = bodies * x.shape[0]
    if len(bodies) != x.shape[0]:
        raise ValueError(f"{len(bodies)} bodies for a State of {x.shape[0]}")
    mass = np.array([b.mass for b in bodies], dtype=float)
    I_inv = np.stack([np.asarray(b.I_body_inv, dtype=float) for b in bodies])
    w_body = np.einsum("nij,nj->ni", I_inv, np.einsum("nji,nj->ni", R, L))      # I_body⁻¹ Rᵀ L
    qpos = np.concatenate([x, quat_from_matrix(R).reshape(-1, 4)], axis=1)
    qvel = np.concatenate([P / mass[:, None], w_body], axis=1)
    return qpos.reshape(-1), qvel.reshape(-1)


def mujoco_stepper(model, bodies, X):
    """go(n): MuJoCo's data reset to our State X of the bodies (mujoco_state), then n steps of mj_step; returns
    the data."""
    import mujoco
    mujoco.set_mju_user_warning(lambda message: None)      # a blow-up is measured, not printed
    data = mujoco.MjData(model)
    qpos, qvel = mujoco_state(bodies, X)

    def go(n: int):
        mujoco.mj_resetData(model, data)
        data.qpos[:], data.qvel[:] = qpos, qvel
        mujoco.mj_step(model, data, nstep=int(n))
        return data
    return go


def run_mujoco_steps(model, bodies, X, steps: int, repeats: int, min_total: float = 0.0):
    """(median seconds of a run of `steps` steps from our State X of the bodies, (qpos, qvel) after it):
    mujoco_stepper timed as the other runners are (runs.timed)."""
    go = mujoco_stepper(model, bodies, X)
    with np.errstate(all="ignore"):
        seconds, data = timed(lambda: go(steps), repeats, min_total)
    return seconds, (data.qpos.copy(), data.qvel.copy())
