"""The driver: simulate(scene, X0, t_end, dt, method) -> Trajectory.

The run is N = round(t_end/dt) steps of size h = t_end/N, made by the kernel (rbcourse/engine: the
slides' physics written once, compiled by numba — or, with fast=False, the same functions run as
Python), through the driver (driver.py).  Each step is:
    1. an impulse in [t, t + h] kicks the momenta at its own time (the step split there: only if the scene
       has Impulse effects);
    2. the method advances the smooth dynamics (the scene's forces and torques) by h;
    3. contacts are resolved: collisions and resting contact (only if the scene has a Ground,
       and only on a state that passed the check), inside the kernel's compiled loop;
    4. the state is checked, every component on its own (trajectory.blow_up): a NaN, an inf or a
       component beyond 1e100 stops the run with SimulationDiverged, which keeps the trajectory
       computed so far (all finite) — or, with on_divergence="stop", returns it, marked diverged.
"""
from __future__ import annotations

import math

import numpy as np

from .support import checks
from .driver import kernel, simulate_compiled, supports
from .support.outputs import progress as progress_bar
from .methods import get_method
from .support.language import say
from .scene import as_scene
from .state import State
from .trajectory import OVERFLOW, Divergence, SimulationDiverged, Trajectory, blow_up

MAX_RECORD_BYTES = 4e9   # a run whose recorded states would need more memory than this is refused


def simulate(scene, X0: State, t_end: float, dt: float, method="rk4", *,
             record_every: int = 1, progress: bool = False, rtol: float | None = None,
             atol: float | None = None, fast: bool = True, on_divergence: str = "raise") -> Trajectory:
    """Integrate the scene from X0 over [0, t_end] with steps of about dt.

    scene: a Scene, or a bare RigidBody (a free body).
    X0: the initial State (one body, or N bodies stacked).
    method: a name in METHODS (e.g. "euler", the slides' method) or a Method.
    record_every: keep every k-th state (long runs stay small); the last state is always kept.
    progress: show a progress bar (True or False).
    rtol, atol: tolerances of the error-controlled method "adaptive" (dt is then its output interval).
    fast: run the engine compiled (rbcourse/engine: the slides' physics written once per body, compiled
        by numba).  False: the same functions run as Python (engine/interpreted.py: slow, no compile,
        the code you read is the code that runs).  traj.implementation and traj.describe() say which
        ran, and why.  Forces given as functions f(t) are called in Python at the times the method
        needs (adaptive: before each attempt of a substep, between compiled calls); forces over time given
        as data (rb.Pulse, rb.Ramp, rb.Sine, rb.Steps, rb.Constant: profiles.py) are evaluated by the kernel.
    on_divergence: what a blow-up (NaN, inf, a component beyond 1e100) does —
        "raise": raise SimulationDiverged, whose .trajectory keeps the steps computed before;
        "stop": return that trajectory, with traj.diverged True and traj.divergence saying when and why
        (for runs that are expected to blow up, as the slides' Euler does: part of the lesson, not an error).
    """
    scene = as_scene(scene)
    if not isinstance(X0, State):
        raise ValueError(f"X0 must be a State, got {X0!r}")
    t_end = checks.real("t_end", t_end, low=0.0)
    dt = checks.positive("dt", dt)
    tolerances = {k: checks.positive(k, v) for k, v in (("rtol", rtol), ("atol", atol)) if v is not None}
    method = get_method(method).configured(**tolerances)
    record_every = checks.integer("record_every", record_every, low=1)
    progress = checks.boolean("progress", progress)
    fast = checks.boolean("fast", fast)
    on_divergence = checks.choice("on_divergence", on_divergence, ("raise", "stop"))
    X = scene.to_engine(X0)
    too_big = _blown_up(X)
    if too_big:
        raise ValueError(f"X0 must hold components within ±{OVERFLOW:g} (the blow-up limit), but its {too_big}")
    scene.check_start(X0, t_end)          # no body below a Ground, no Spring without a direction, no Impulse outside
    steps = t_end / dt                              # may be inf (t_end = 1e308, dt = 5e-324): check before round
    if not steps <= 10**9:
        raise ValueError(f"dt must give at most 1e9 steps over t_end = {t_end:g}, got dt = {dt:g} ({steps:.3g} steps)")
    n = 0 if t_end == 0 else max(1, round(steps))
    _check_memory(n, record_every, scene.n_bodies)
    h = t_end / n if n else dt
    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):   # a blow-up is detected below
            why_not, data = "fast=False", scene.compile()
            if fast:
                compiled = kernel(fast=True)    # numba loads at the first compiled run, not at `import rbcourse`
                why_not = supports(compiled, method, data.system)
                if not why_not:
                    return _run_engine(compiled, scene, data, X, n, h, method, record_every, progress,
                                       compiled.describe())
            python = kernel(fast=False)         # the same kernel, its functions run as Python
            why = supports(python, method, data.system)
            if why:
                raise ValueError(f"method {method.name!r} cannot run this scene: {why}")
            return _run_engine(python, scene, data, X, n, h, method, record_every, progress,
                               f"interpreted ({why_not}): the engine's functions run as Python (engine/interpreted.py)")
    except SimulationDiverged as err:
        if on_divergence == "stop":
            return err.trajectory
        raise


def _check_memory(n: int, every: int, n_bodies: int):
    """Refuse a run whose recorded states would not fit: (n/every + 2) states of 19 floats per body."""
    need = (n // every + 2) * (1 + 18 * n_bodies) * 8
    if need > MAX_RECORD_BYTES:
        k = int(math.ceil(need / MAX_RECORD_BYTES * every))
        raise ValueError(f"record_every = {every} would record {n // every + 1} states, about {need / 1e9:.3g} GB "
                         f"(the limit is {MAX_RECORD_BYTES / 1e9:g} GB): pass record_every >= {k}, or a shorter t_end")


def _diverged(traj: Trajectory, method, n: int, h: float, step: int, reason: str) -> SimulationDiverged:
    """The error for a blow-up at `step`; traj (the good part, all finite) learns when and why."""
    t = step * h
    traj.divergence = Divergence(t, step, reason)
    msg = say(f"simulation diverged at t = {t:.6g} s (step {step} of {n}, method {method.name!r}, dt = {h:g}): "
              f"{reason}; the trajectory up to t = {traj.t[-1]:.6g} s is kept in .trajectory",
              f"la simulation a divergé à t = {t:.6g} s (pas {step} sur {n}, méthode {method.name!r}, dt = {h:g}) : "
              f"{reason} ; la trajectoire jusqu'à t = {traj.t[-1]:.6g} s est gardée dans .trajectory")
    return SimulationDiverged(msg, traj, t, step, reason)


def _run_engine(kernel, scene, data, X, n, h, method, every, progress, implementation: str) -> Trajectory:
    """The run through the kernel (compiled or run as Python) by the driver (driver.py): the phases of the
    module docstring, a blow-up stopping it with the steps before it kept."""
    with progress_bar(n, "step", "simulate", progress and n >= 1000) as bar:
        out = simulate_compiled(kernel, scene, data, method, X, n, h, every, bar)
    rows = out.rows
    t, x, R, P, L = (a[:rows] for a in out.record)
    _to_state_L(scene, x, R, P, L)
    if scene.single:
        x, R, P, L = (a[:, 0] for a in (x, R, P, L))
    traj = Trajectory(t, x, R, P, L, scene=scene, method=method.name, dt=h, implementation=implementation)
    if out.bad_step:
        raise _diverged(traj, method, n, h, out.bad_step, out.why)
    return traj


def _blown_up(X: State) -> str:
    """'' if the State X is finite and not huge; else why not (trajectory.blow_up: every component tested
    on its own; the kernel checks each step's state the same way: engine/run.py: first_bad, driver.reason)."""
    return blow_up((name, getattr(X, name)) for name in State.__slots__)


_CHUNK = 1 << 16   # recorded rows converted at a time: the temporaries stay small


def _to_state_L(scene, x, R, P, L):
    """Engine L (about the rotation centre) -> L about the centre of mass (scene.to_state_arrays),
    written into L in place, _CHUNK rows at a time (arrays (m, N, ...))."""
    for s in range(0, len(L), _CHUNK):
        part = L[s:s + _CHUNK]
        out = scene.to_state_arrays(x[s:s + _CHUNK], R[s:s + _CHUNK], P[s:s + _CHUNK], part)
        if out is not part:
            part[...] = out
