"""simulate(scene, X0, t_end, dt, method) -> Trajectory: the run.

The run is N = round(t_end/dt) steps of size h = t_end/N, made by the kernel (rbcourse/engine: the
slides' physics written once, compiled by numba — or, with fast=False, the same functions run as
Python; driver.py resolves the method in it).  Each step is:
    1. an impulse in [t, t + h] kicks the momenta at its own time (the step split there, inside the compiled
       loop, which walks a table of the run's kicks: engine/kicks.py; only if the scene has Impulse effects);
    2. the method advances the smooth dynamics (the scene's forces and torques) by h — forces given as
       functions f(t) evaluated here, a chunk of steps at a time, at the times the method needs;
    3. contacts are resolved: collisions and resting contact (only if the scene has a Ground,
       and only on a state that passed the check), inside the kernel's compiled loop;
    4. the state is checked, every component on its own (trajectory.blow_up): a NaN, an inf or a
       component beyond 1e100 stops the run with SimulationDiverged, which keeps the trajectory
       computed so far (all finite) — or, with on_divergence="stop", returns it, marked diverged.
Steps 1–4 of a chunk of steps are the family's loop, engine/run.py (run_euler: loop(euler_family_step, …) for
the slides' Euler, engine/euler.py), called by simulate_compiled below.
"""
from __future__ import annotations

import math

import numpy as np

from .support import checks
from . import compiling
from .driver import Kernel, Outcome, contact_failed, decoder, encode, kernel, new_record, plan, reason, supports
from .engine.plan import ADAPTIVE
from .engine.system import evaluates_forces
from .forcing import SubstepForces, deferred_interrupt, forces_at
from .impulse import kick
from .support.outputs import progress as progress_bar
from .methods import get_method
from .support.language import say
from .scene import as_scene
from .state import State, from_matrix
from .trajectory import OVERFLOW, Divergence, SimulationDiverged, Trajectory, blow_up, first_blow_up

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
    """The run through the kernel (compiled or run as Python: driver.kernel) by simulate_compiled below: the phases
    of the module docstring, a blow-up stopping it with the steps before it kept."""
    with progress_bar(n, "step", "simulate", progress and n >= 1000) as bar:
        out = simulate_compiled(kernel, scene, data, method, X, n, h, every, bar)
    rows, bad_step, why = out.rows, out.bad_step, out.why
    t, x, R, P, L = (a[:rows] for a in out.record)
    if scene.has_pivots:
        with np.errstate(over="ignore", invalid="ignore"):     # an overflow here is found just below
            _to_state_L(scene, x, R, P, L)
        good, why_L = first_blow_up([("L", L)])      # L about the centre of mass may overflow where L_p did not
        if good < rows:
            rows, bad_step, why = good, int(round(t[good] / h)), why_L
            t, x, R, P, L = (a[:rows] for a in (t, x, R, P, L))
    if scene.single:
        x, R, P, L = (a[:, 0] for a in (x, R, P, L))
    traj = Trajectory(t, x, R, P, L, scene=scene, method=method.name, dt=h, implementation=implementation)
    if bad_step:
        raise _diverged(traj, method, n, h, bad_step, why)
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


CHUNK = 1 << 14          # steps per call when forces are functions of t (their values are evaluated per chunk)
WORK = 1 << 22           # body-steps per call at most (about a second): Ctrl-C is honoured between calls


class Run:
    """One run's arrays and state: the method's plan, its arrays Y, out, K, U, w, the contact solver's work cw,
    the record, and its impulses: the table of kicks the loop walks (engine/kicks.py), or — for a step made here,
    _python_step — the steps that hold them (kicks)."""

    kicks_in_loop = True    # False: each step with kicks made here (_python_step), the path the loop's is tested on

    def __init__(self, kernel: Kernel, scene, data, method, X: State, n: int, h: float, every: int):
        self.kernel, self.scene, self.sys, self.functions = kernel, scene, data.system, data.functions
        self.n, self.h, self.every = n, h, every
        self.Y = encode(method.kernel.layout, X)
        N = self.Y.shape[0]
        self.plan = p = plan(kernel, method, self.sys, N)
        self.decode = decoder(kernel, p.layout)
        self.out, self.U = np.empty_like(self.Y), np.empty_like(self.Y)
        self.K = np.empty((max(p.stages, len(p.stage_times)) + p.scratch,) + self.Y.shape)
        self.w = kernel.motion.work(N)
        self.cw = kernel.contact.work(N) if scene.has_contacts else None    # None: no contact code compiled
        self.rec = new_record(X, n, every)
        self.substeps = (SubstepForces(self.functions, p.stage_times, p.args, kernel.adaptive)
                         if self.functions and not p.time_forces else None)
        self.fill = (None if not len(self.sys.profiles)
                     else lambda times, values: kernel.profiles.fill_profiles(self.sys, times, values))
        self.forces = evaluates_forces(self.sys)      # else no force code is compiled (values None: motion.stage)
        in_loop = scene._impulses and n and self.substeps is None and self.kicks_in_loop
        e = scene._kicks
        self.table = kernel.kicks.table(e.time, e.owner, e.body, e.point, e.impulse, self.Y) if in_loop else None
        self.kicks = {} if in_loop else kick_plan(kernel, scene._impulses, n, h)

    def chunk(self) -> int:
        """Steps per compiled call: as many as fit (a chunk of forces f(t) at a time; 1 with substep forces)."""
        most = max(1, WORK // self.Y.shape[0])
        return 1 if self.substeps is not None else min(CHUNK if self.functions else max(self.n, 1), most)

    def values(self, starts, h):
        """The forces over time at the stage times of steps of size h (a number, or one per step) from `starts`
        (zeros: no slot); None for a scene that evaluates no force (a free body: engine/motion.stage — no force
        code is compiled for it)."""
        if not self.forces:
            return None
        if not self.functions or self.substeps is not None:
            return np.zeros((len(starts), len(self.plan.stage_times), 0, 3))
        return forces_at(self.functions, self.plan.stage_times, starts, h, self.fill)

    def loop_values(self, k0: int, k1: int):
        """The values the loop reads for steps k0 … k1 − 1: each step's, then each piece's of the steps it splits
        at their kicks (kicks.pieces, in the loop's order)."""
        starts, sizes = np.arange(k0, k1) * self.h, self.h
        if self.forces and self.table is not None:
            times, pieces = self.kernel.kicks.pieces(self.table, k0, k1, self.n, self.h)
            if len(times):
                starts, sizes = np.r_[starts, times], np.r_[np.full(k1 - k0, self.h), pieces]
        return self.values(starts, sizes)


def kick_plan(kernel: Kernel, impulses, n: int, h: float) -> dict:
    """{step k: {time t: [(Impulse, rows), ...]}}: each impulse in the step that holds its time, at its time
    (engine/kicks.py: kick_step, the loop's own rule, its code run as Python: a time on a step boundary, to
    rounding, is the boundary k h itself, applied before step k — or, at t_end = n h, after the last step, before
    its state is recorded).  A run of no step (t_end = 0) has none here: simulate_compiled applies its impulses to
    the one state it records."""
    plan: dict = {}
    if n == 0:
        return plan
    step_of = getattr(kernel.kicks.kick_step, "py_func", kernel.kicks.kick_step)
    for e, idx in impulses:
        k, t = step_of(e.time, n, h)
        plan.setdefault(int(k), {}).setdefault(float(t), []).append((e, idx))
    return plan


def simulate_compiled(kernel: Kernel, scene, data, method, X: State, n: int, h: float, every: int, bar) -> Outcome:
    """n steps of the method from X (engine coordinates) in `kernel`; data: scene.compile(); `bar` a progress bar
    (update(k)).  Chunks of steps run in the compiled loop (engine/run.py: contacts and impulses included); a step
    whose forces f(t) are evaluated per attempt (adaptive) is made here (_python_step)."""
    r = Run(kernel, scene, data, method, X, n, h, every)
    p, rec = r.plan, r.rec
    chunk = r.chunk()
    row, k = 1, 0
    if n == 0 and scene._impulses:          # t_end = 0: its impulses (all at t = 0) are in the one state recorded
        r.Y = _kick(r, r.Y, scene._impulses)
        r.decode(r.sys, r.Y, 0, *rec[1:])
    with deferred_interrupt(kernel.fast) as held:     # Ctrl-C: honoured between calls, never inside numba
        while k < n:
            held.check()
            if k in r.kicks or r.substeps is not None:
                Y_good = r.Y
                why = _python_step(r, k)
                if why:
                    return _stopped(r, row, k + 1, why, Y_good, k)
                k += 1
                bar.update(1)
                if k % every == 0 or k == n:
                    r.decode(r.sys, r.Y, row, *rec[1:])
                    why = blow_up([(name, getattr(rec, name)[row]) for name in "xRPL"])
                    if why:
                        return _stopped(r, row, k, why, Y_good, k - 1)
                    rec.t[row] = k * h
                    row += 1
                continue
            k1 = min([n, k + chunk] + [j for j in r.kicks if j > k])
            values = r.loop_values(k, k1)
            args = (p.args, r.sys, values, r.Y, r.out, h, k, k1, n, every, row, tuple(rec), r.K, r.U, r.w, r.cw,
                    r.table)
            with compiling.announced(p.loop, args, p.family, r.forces, r.cw is not None, r.table is not None):
                k_done, row, bad = p.loop(*args)
            bar.update(k_done - k)
            if bad:
                why = (reason(p.layout, r.out) or blow_up([(name, getattr(rec, name)[row]) for name in "xRPL"])
                       or contact_failed())
                return _stopped(r, row, k_done + 1, why, r.Y, k_done)
            k = k_done
    return Outcome(rec, row, 0, "")


def _stopped(r: Run, row, step, why, Y_good, k_good) -> Outcome:
    """A blow-up at `step`: the last good state (after k_good steps) recorded if it is not yet."""
    rec = r.rec
    if rec.t[row - 1] != k_good * r.h:
        rec.t[row] = k_good * r.h
        r.decode(r.sys, Y_good, row, *rec[1:])
        row += 1
    return Outcome(rec, row, step, why)


def _python_step(r: Run, k: int) -> str:
    """Step k made here, between compiled calls (forces f(t) evaluated per attempt: adaptive; or Run.kicks_in_loop
    False): split at the times of its impulses (each kick applied at its
    own time: the method steps to it, kicks, steps on), the contacts after each piece.  r.Y := the new state
    (a copy; r.Y is left as it was if a piece blew up).  Returns why it blew up, or ''."""
    h = r.h
    t0, t1 = k * h, (k + 1) * h
    Y, t = r.Y, t0
    kicks = sorted(r.kicks.get(k, {}).items())
    for t_kick, impulses in kicks + [(t1, None)]:
        if t_kick > t:
            whole = (t, t_kick) == (t0, t1)
            why = _piece(r, Y, t, h if whole else t_kick - t, k if whole else None)
            if why:
                return why
            Y, t = np.ascontiguousarray(r.out).copy(), t_kick
        if impulses:
            Y = _kick(r, Y, impulses)
            why = reason(r.plan.layout, Y)
            if why:
                return why
    if r.plan.args[0] == ADAPTIVE:
        r.plan.args[-1][r.kernel.adaptive.STEPS] = k + 1     # its output steps: t = STEPS h
    r.Y = Y if Y is not r.Y else Y.copy()
    return ""


def _piece(r: Run, Y, t: float, h: float, k=None) -> str:
    """One step of the method from Y at time t, of size h, into r.out, then the contacts: why it blew up, or ''.
    k: the step's number when the piece is the whole step k (t = k h)."""
    p = r.plan
    if p.args[0] == ADAPTIVE:                  # its forces f(t) are at t = STEPS h
        adaptive = r.kernel.adaptive
        if k is None or r.kicks:                   # the state, or the step, changed: the substep is chosen again
            adaptive.forget_substep(p.args[-1])
        p.args[-1][adaptive.STEPS] = k if k is not None else t / h
    if r.substeps is not None:
        r.substeps(r.sys, Y, r.out, h, r.K, r.U, r.w)
    else:
        values = r.values(np.array([t]), h)
        args = (*p.args, r.sys, None if values is None else values[0], Y, r.out, h, r.K, r.U, r.w)
        with compiling.announced(p.step, args, p.family, r.forces):    # checked at the step's first call only
            p.step(*args)
    why = reason(p.layout, r.out)
    if not why and r.scene.has_contacts:
        if r.kernel.grounds.contacts(p.args[1], r.sys, r.out, h, r.cw) < 0:
            return contact_failed()
        why = reason(p.layout, r.out)
    return why


def _kick(r: Run, Y, impulses):
    """The kicks of `impulses` [(Impulse, rows)] on the method's state Y (a new array): engine/motion.py's kick
    on the slides' state (impulse.kick), laid out back as the method's."""
    S = encode("matrix", _state(r, Y))
    kick(impulses, r.sys, S, r.kernel.motion)
    return S if r.plan.layout == "matrix" else encode(r.plan.layout, from_matrix(S))


def _state(r: Run, Y) -> State:
    """The engine's State of the method's arrays Y."""
    N = Y.shape[0]
    x, R, P, L = np.zeros((1, N, 3)), np.zeros((1, N, 3, 3)), np.zeros((1, N, 3)), np.zeros((1, N, 3))
    r.decode(r.sys, Y, 0, x, R, P, L)
    return State.unchecked(x[0], R[0], P[0], L[0])
