"""The pushed box of the exercise, run by the student's code when it is ready, else by the engine.

pushed_box():           the slides' box at rest, pushed at a corner by F = (0, 0, 10) N for 0.1 s
simulate_or_reference:  the student's simulate(..., step=…) when it and its step pass their checks,
                        else rbcourse.simulate(..., method="euler"); says which one ran
show_iterations:        the slides' "Itération 1" and "Itération 2", printed from rest
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...scene import Scene
from ...state import State
from ... import examples
from ...support import checks
from ...examples import Pulse
from . import reference as ref
from .harness import BadOutput, as_tuple, call, exc_text, fmt, where
from .loop import check_simulate
from .projection import check_euler_step_projected
from .reference import StateTuple, as_floats
from .stepping import check_euler_step
from .texts import tr

ROUNDING = 1e-9     # s: how far below the end of the push a student's time t may fall by rounding


@dataclass(frozen=True)
class PushedBox:
    """The slides' box (1 kg, 0.3 × 0.2 × 0.05 m), at rest, pushed at a corner by F = (0, 0, 10) N for
    0.1 s, then tumbling freely (no gravity).

    M, I_body, I_body_inv: the constants;  X0: the StateTuple at rest;  push: F(t);
    forces_at(t, X): [(rᵢ, Fᵢ)] with the corner rᵢ = x + R b (b in body axes) — the force stops at t = 0.1 s;
    scene, X0_state: the same problem for the reference engine (rbcourse.simulate).
    """
    M: float
    size: tuple
    I_body: np.ndarray
    I_body_inv: np.ndarray
    corner: np.ndarray
    push: Pulse
    X0: StateTuple
    scene: Scene
    X0_state: State

    def forces_at(self, t, X):
        """The forces at time t on the state X: the push at the corner r = x + R b while it lasts, then none.
        A t a hair (ROUNDING) below the push's end counts as its end: a loop that adds t += Δt gets
        there just below it, and the engine's t = k·Δt exactly at it."""
        if not self.push.on(t + ROUNDING):
            return []
        x, R = np.asarray(X[0], float), np.asarray(X[1], float)
        return [(x + R @ self.corner, self.push.force)]


def pushed_box(mass: float = 1.0, size=(0.3, 0.2, 0.05), push=(0.0, 0.0, 10.0), t_push: float = 0.1) -> PushedBox:
    """The box of the notebook, the named scene examples.pushed_box: pushed at its corner (a/2, b/2, c/2)
    by `push` (N, world) for t_push seconds."""
    ex = examples.pushed_box(mass, size, push, t_push)
    body, force = ex.scene.bodies[0], ex.scene.effects[0]
    X0 = StateTuple(np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3))
    return PushedBox(body.mass, tuple(size), np.array(body.I_body), np.array(body.I_body_inv), force.body_point,
                     force.force, X0, ex.scene, ex.X0)


def pushed(box: PushedBox) -> str:
    """The push a run uses, in words: "the box pushed by F = [0, 0, 10] N for 0.1 s"."""
    return tr("pushed").format(F=fmt(np.asarray(box.push.force), 6), T=f"{box.push.t_stop - box.push.t_start:g}")


def simulate_or_reference(simulate, step, t_end: float, dt: float, *, reference: str = "euler",
                          problem: PushedBox | None = None):
    """The pushed box over [0, t_end] with steps dt, as a rbcourse Trajectory (for viewer and plots).

    Your simulate(..., step=step) when both pass their checks (check_simulate, and check_euler_step —
    or check_euler_step_projected when reference = "euler_project"); otherwise the reference engine,
    rbcourse.simulate(scene, X0, t_end, dt, method=reference, on_divergence="stop").  Both run `problem`
    (default: the slides' box, pushed_box()) — pass the box you made, ex.pushed_box(push=…), and every run
    uses its push.  Prints which one ran, and the push.

    A run that blows up (the slides' Euler does, after about 3 s at dt = 1 ms) is part of the lesson,
    not an error: either way the trajectory ends at the last good state, is marked diverged
    (traj.diverged, traj.divergence, traj.outcome: "diverged at t = …"), and a line says so.
    """
    from ...simulate import simulate as engine_simulate
    from ...trajectory import Divergence, Trajectory, first_blow_up

    box, n = _problem(problem), _steps(t_end, dt)
    step_check = check_euler_step_projected if reference == "euler_project" else check_euler_step
    ready = [check_simulate(simulate, verbose=False), step_check(step, verbose=False)]
    step_name = getattr(step, "__name__", "step")
    waiting = [r for r in ready if not r.passed]
    if waiting:
        r = waiting[0]
        why = tr("run_not_done" if r.mistake == "not_done" else "run_not_passing").format(name=r.name)
    else:
        try:
            out = call(simulate, (box.M, box.I_body_inv, box.X0, box.forces_at, dt, n), {"step": step})
            x, R, P, L = as_tuple(out, ("x", "R", "P", "L"))
            t = dt * np.arange(len(x))
            last, reason = first_blow_up([("x", x), ("R", R), ("P", P), ("L", L)])   # as the engine checks
            if last == 0:
                raise BadOutput("not_finite", tr("first_state").format(reason=reason))
            divergence = Divergence(float(t[last]), last, reason) if last < len(t) else None
            traj = Trajectory(t[:last], x[:last], R[:last], P[:last], L[:last], scene=box.scene,
                              method=tr("your_code").format(method=reference), dt=dt, divergence=divergence)
            print(tr("run_yours").format(step=step_name, n=n, dt=f"{dt:g}", t_end=f"{n * dt:g}", pushed=pushed(box)))
            _diverged(traj)
            return traj
        except Exception as e:      # noqa: BLE001
            why = tr("run_raised").format(exc=exc_text(e) + where(e))
    print(tr("run_reference").format(why=why, t_end=f"{n * dt:g}", dt=f"{dt:g}", method=repr(reference),
                                     pushed=pushed(box)))
    traj = engine_simulate(box.scene, box.X0_state, n * dt, dt, method=reference, on_divergence="stop")
    _diverged(traj)
    return traj


MAX_STEPS = 10**7
"""The most steps a run of the pushed box takes (t_end / dt): a student's Python loop of 1e7 steps is hours."""


def _problem(problem) -> PushedBox:
    """The box a run uses: the one given (from ex.pushed_box(...)), or the slides' own."""
    if problem is None:
        return pushed_box()
    if not isinstance(problem, PushedBox):
        raise TypeError(f"problem must be a box made by ex.pushed_box(...) (or None: the slides' box), got {problem!r}")
    return problem


def _steps(t_end, dt) -> int:
    """round(t_end / dt), at least 1, for t_end > 0 and dt > 0 (s) with at most MAX_STEPS steps."""
    t_end, dt = checks.positive("t_end", t_end), checks.positive("dt", dt)
    if t_end / dt > MAX_STEPS:
        raise ValueError(f"t_end / dt must be at most {MAX_STEPS:.0e} steps, got t_end = {t_end:g} s and dt = {dt:g} s "
                         f"({t_end / dt:.3g} steps)")
    return max(1, round(t_end / dt))


def _diverged(traj) -> None:
    """'   diverged at t = 3.2 s (…); kept up to t = 3.199 s' when the run blew up (nothing otherwise)."""
    if traj.diverged:
        d = traj.divergence
        print(tr("run_diverged").format(t=f"{d.t:.4g}", reason=d.reason, kept=f"{traj.t[-1]:.4g}"))


NOT_WRITTEN = ("not_done", "not_a_function")     # check_euler_step's verdicts on a step that is not written yet


def show_iterations(euler_step, dt: float = 0.01, iterations: int = 2, problem: PushedBox | None = None) -> None:
    """The slides' "Itération 1" and "Itération 2" on the pushed box, from rest: prints X after each iteration.

    Your euler_step as soon as it is written, labelled as yours — and, if it does not pass its check yet,
    saying so next to it (its numbers are then not the slides'); the reference step only while yours is
    not written (a stub that raises NotImplementedError), and labelled as the reference.  Never raises for your step:
    if it raises or returns something that is not a state, the line says so and the iterations stop (dt > 0,
    iterations in [1, 1000] and problem are checked first, each named if wrong)."""
    dt, iterations = checks.positive("dt", dt), checks.integer("iterations", iterations, low=1, high=1000)
    box = _problem(problem)
    verdict = check_euler_step(euler_step, verbose=False)
    if verdict.mistake in NOT_WRITTEN:
        step = ref.euler_step
        print(tr("iter_reference"))
    else:
        step = euler_step
        if verdict.passed:
            print(tr("iter_yours"))
        else:
            first = verdict.message.splitlines()[0] if verdict.message else tr("iter_no_check")
            print(tr("iter_not_passing").format(first=first))
    X = box.X0
    num = lambda v: fmt(v, 6)                                      # noqa: E731
    vec = lambda a: fmt(np.asarray(a), 6)                          # noqa: E731
    for i in range(1, iterations + 1):
        forces = box.forces_at((i - 1) * dt, X)
        F, tau = ref.resultants(X[0], forces) if forces else (np.zeros(3), np.zeros(3))
        try:
            Y = as_floats(call(step, (box.M, box.I_body_inv, X, forces, dt)))
            if [np.shape(a) for a in Y] != [(3,), (3, 3), (3,), (3,)]:
                raise BadOutput("wrong_shape", tr("iter_shapes").format(shapes=", ".join(str(np.shape(a)) for a in Y)))
        except Exception as e:      # noqa: BLE001  (a student's step: say what it did, never raise)
            text = e.text if isinstance(e, BadOutput) else tr("iter_raised").format(exc=exc_text(e) + where(e))
            print(tr("iter_stopped").format(i=i, text=text))
            return
        x0, R0 = as_floats(X)[:2]
        print(tr("iter_head").format(i=i, t0=num((i - 1) * dt), t1=num(i * dt), F=vec(F), tau=vec(tau)))
        print(f"    x(t+Δt) = {vec(Y[0])}   " + tr("unchanged" if np.array_equal(Y[0], x0) else "moved"))
        print(f"    R(t+Δt) = {vec(Y[1])}   " + tr("unchanged" if np.array_equal(Y[1], R0) else "turned"))
        print(f"    P(t+Δt) = {vec(Y[2])}")
        print(f"    L(t+Δt) = {vec(Y[3])}")
        X = StateTuple(*Y)
