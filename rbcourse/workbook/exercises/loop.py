"""check_simulate: the slides' iterations as a loop, checked by watching what it calls.

    X₀ given;  X_{k+1} = step(M, I_body_inv, X_k, forces_at(t_k, X_k), dt),  t_k = k · Δt

The check passes its own step and forces_at (a Recorder), so it sees the times, the states and the
number of steps, and can say which of them is wrong (missing X₀, stale state, wrong times, …).
"""
from __future__ import annotations

import copy
import dataclasses
import inspect
from dataclasses import dataclass
from typing import Callable

import numpy as np

from . import reference as ref
from .harness import (BadOutput, TimeUp, as_tuple, call, close, exc_text, fmt, fmt_pair, not_done, quiet, random_spd,
                      random_state, same, short)
from .result import CheckResult
from .slides import ITERATION_2
from .texts import tr
from .reference import StateTuple, as_floats
from .spec import Spec, crashed, fail, library_answer, parts_order, shape_problem
from .verdict import check_options


class _Recorder:
    """forces_at and step as the student's simulate sees them; they record how they are called (misuse: the first
    call with its arguments in another order, "forces_at(…)" or "step(…)", the kinds of what it got)."""

    def __init__(self, b, F0, G, step, t_stop=np.inf, kind: str = "state", t_start: float = 0.0):
        self.b, self.F0, self.G, self._step, self.t_stop, self.kind = b, F0, G, step, t_stop, kind
        self.t_start = t_start
        self.times, self.states, self.steps, self.dts = [], [], 0, []
        self.misuse = None
        self.stepped = []           # the states step was given
        self.returned = []          # the forces forces_at returned, call by call
        self.given = []             # the forces step was given, call by call

    def forces_at(self, t, X):
        """Forces attached to body points bᵢ: rᵢ = x + R bᵢ, Fᵢ(t) = F0ᵢ + t Gᵢ, from t_start while t < t_stop; else
        none, [] (as the notebook's box after its push)."""
        if not _number(t) or _number(X):
            self.misuse = self.misuse or ("forces_at", _kinds((t, X)))
            raise TypeError(tr("bad_forces_at_call"))
        x, R, P, L = as_floats(X)
        self.times.append(float(t))
        self.states.append((x.copy(), R.copy(), P.copy(), L.copy()))
        forces = [] if float(t) >= self.t_stop - 1e-9 or float(t) < self.t_start - 1e-9 else [
            (x + R @ bi, F0 + float(t) * G) for bi, F0, G in zip(self.b, self.F0, self.G)]
        self.returned.append([(r.copy(), F.copy()) for r, F in forces])
        return forces

    def step(self, M, I_body_inv, X, forces, dt):
        if not (_number(M) and _number(dt) and _forces(forces) and np.shape(I_body_inv) == (3, 3)
                and not _number(X)):
            self.misuse = self.misuse or ("step", _kinds((M, I_body_inv, X, forces, dt)))
            raise TypeError(tr("bad_step_call"))
        self.steps += 1
        self.dts.append(dt)
        self.given.append([tuple(np.array(a, dtype=float) for a in pair) for pair in forces])
        self.stepped.append(tuple(a.copy() for a in as_floats(X)))
        return as_kind(self._step(M, I_body_inv, X, forces, dt), self.kind)


KINDS = ("tuple", "list", "state")
"""What a step may return, all accepted: a plain tuple (x, R, P, L), a list, a StateTuple."""


def as_kind(X, kind: str):
    """The state X as a step of this kind returns it."""
    return tuple(X) if kind == "tuple" else list(X) if kind == "list" else StateTuple(*X)


def own_kind(simulate) -> str:
    """What the student's own step returns — the default of their simulate's `step`, tried on a state at rest — so
    that the check's step returns the same (a plain tuple when unknown: what most steps return)."""
    try:
        step = inspect.signature(simulate).parameters["step"].default
        X = quiet(step, (1.0, np.eye(3), StateTuple(np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3)), [], 0.01))
    except (Exception, SystemExit):      # noqa: BLE001 — no default, or one that fails: the plain tuple
        return "tuple"
    return "state" if isinstance(X, StateTuple) else "list" if isinstance(X, list) else "tuple"


def _number(a) -> bool:
    """A real number (a 0-d array of one too): what t, M and dt are."""
    if isinstance(a, np.ndarray):
        return a.ndim == 0 and a.dtype.kind in "iuf"
    return isinstance(a, (int, float, np.integer, np.floating)) and not isinstance(a, bool)


def _forces(forces) -> bool:
    """A list (or tuple) of pairs (rᵢ, Fᵢ) of 3-vectors (what forces_at returns)."""
    try:
        return isinstance(forces, (list, tuple)) and all(np.shape(np.asarray(p, dtype=float)) == (2, 3)
                                                          for p in forces)
    except (TypeError, ValueError):
        return False


def _kinds(args) -> str:
    """What a call got, in Python's words: 'float, ndarray (3, 3), StateTuple, float, list'."""
    def kind(a):
        shape = np.shape(a) if isinstance(a, np.ndarray) else None
        return f"{type(a).__name__} {shape}" if shape else type(a).__name__
    return ", ".join(kind(a) for a in args)


def check_simulate(simulate, *, verbose: bool = True, seed: int = 2010) -> CheckResult:
    """simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=euler_step) -> (x, R, P, L), the slides'
    iterations repeated:

        X₀ given;  X_{k+1} = step(M, I_body_inv, X_k, forces_at(t_k, X_k), dt),  t_k = k · Δt
        x, R, P, L: arrays of the n_steps + 1 states X₀ … X_n  ((n+1, 3), (n+1, 3, 3), (n+1, 3), (n+1, 3))

    The check passes its own step (the reference Euler step, or a projected one) and forces_at, and
    watches how they are called: the mistakes of the loop are named from what it called (forces_at once
    before the loop, a dt other than its own, one step too many, …) and what it returned (one state, the
    states without X₀, every entry the same object, …).
    """
    seed, verbose = check_options(seed, verbose)
    spec = Spec("simulate", "formula_simulate", ITERATION_2, labels=("x", "R", "P", "L"), count="random_runs", n=6,
                seed=seed)
    try:
        result = _judge_simulate(spec, simulate, np.random.default_rng(seed))
    except Exception as e:      # noqa: BLE001
        result = CheckResult(spec.name, False, "check_failed", tr("check_failed").format(name=spec.name,
                                                                                        exc=exc_text(e)))
    return result.printed(verbose)


LONG = 1200
SPIN = -1                                   # the edge run of a fast spin: |L| of 1e9, Δt of 1e-10 s, 5 steps
EDGE_STEPS = (0, 1, LONG, SPIN)
"""The n_steps of the edge runs, tried after the random ones (their pass line counts the random ones): none, one, and
a run as long as the notebook's (more than Python's 1000 nested calls), 10 000 km away and fast, and a fast spin."""


def _misused(spec: Spec, rec: _Recorder) -> CheckResult:
    """call_order: the student's simulate called forces_at or step with its arguments in another order."""
    fn, got = rec.misuse
    return fail(spec, "call_order", tr("called").format(fn=fn, got=got))


ONE_STATE = [(3,), (3, 3), (3,), (3,)]
"""The shapes of one state (x, R, P, L): what a simulate that returns only its last state gives."""


def _judge_simulate(spec: Spec, simulate, rng) -> CheckResult:
    if not callable(simulate):
        return CheckResult(spec.name, False, "not_a_function", tr("not_a_function").format(name=spec.name,
                                                                                          got=short(simulate)))
    if library_answer(spec, simulate):
        return library_answer(spec, simulate)
    own, runs = own_kind(simulate), []
    for run in range(spec.n + len(EDGE_STEPS)):
        M, Ib = float(rng.uniform(0.5, 5.0)), random_spd(rng)
        X0 = random_state(rng)
        k = int(rng.integers(1, 3))
        b, F0, G = rng.normal(0, 0.5, (k, 3)), rng.normal(0, 2.0, (k, 3)), rng.normal(0, 5.0, (k, 3))
        dt, n = float(rng.uniform(0.01, 0.05)), int(rng.integers(6, 12))
        if run >= spec.n:                       # the edge runs, after the random ones: n_steps = 0, 1, 1200
            n = EDGE_STEPS[run - spec.n]
        if n >= LONG:                           # as long as the notebook's runs, and far (10 000 km) and fast: no
            X0 = StateTuple(X0.x + 1e7, X0.R, 30.0 * X0.P, X0.L)     # recursion, no early stop, no clamp
            dt = 1e-3
        if n == SPIN:                           # a spin of |L| = 1e9: no guard against a "blow-up"
            X0, dt, n = StateTuple(X0.x, X0.R, X0.P, 1e9 * X0.L), 1e-10, 5
        ref_step = ref.euler_step if run % 2 == 0 else ref.euler_step_projected
        t_stop = dt * (n // 2) if run % 3 == 1 else np.inf     # the push stops: forces = [] from then on
        t_start = dt * 2 if run % 3 == 2 else 0.0                # the push starts late: forces = [] until then
        kind = own if run == 0 else KINDS[run % 3]             # the student's own kind of step first, then each
        runs.append(Run(M, Ib, X0, b, F0, G, dt, n, ref_step, t_stop, kind, stepped_before=run > 0, t_start=t_start))
        verdict = _one_run(spec, simulate, runs[-1])
        if verdict is not None:
            return verdict
    stale = _remembers(spec, simulate, runs[0], runs[1])
    if stale:
        return stale
    return CheckResult(spec.name, True, None, tr("pass").format(name=spec.name, formula=spec.formula_text(),
                                                                count=spec.counted(), note=""))


@dataclass
class Run:
    """One run of the student's simulate: the body, X₀, the forces Fᵢ(t) = F0ᵢ + t Gᵢ at body points bᵢ until
    t_stop, Δt, n_steps, the check's step (the reference Euler step, or the projected one) and what it returns."""
    M: float
    Ib: np.ndarray
    X0: tuple
    b: np.ndarray
    F0: np.ndarray
    G: np.ndarray
    dt: float
    n: int
    step: Callable
    t_stop: float = np.inf
    kind: str = "state"
    stepped_before: bool = False         # an earlier run called step: none called here is no "ignores_step"
    t_start: float = 0.0                 # the forces start then (forces = [] before)

    def recorder(self) -> "_Recorder":
        return _Recorder(self.b, self.F0, self.G, self.step, self.t_stop, self.kind, self.t_start)

    def expected(self):
        return ref.simulate(self.M, self.Ib, self.X0, self.recorder().forces_at, self.dt, self.n, self.step)

    def shown(self) -> str:
        return f"M = {fmt(self.M)}, X0 = {fmt(tuple(self.X0))}, dt = {fmt(self.dt)}, n_steps = {self.n}"


def _remembers(spec: Spec, simulate, first: Run, second: Run) -> CheckResult | None:
    """"stateful" when simulate, run again with the same X₀ arrays changed in place to another state (the same
    forces_at, step, Δt and n_steps), gives the first run's states (a cache keyed by id(X0), a list kept between
    calls)."""
    X0 = tuple(np.array(a, dtype=float) for a in first.X0)
    rec = first.recorder()
    forces_at, step = rec.forces_at, rec.step           # the same objects in both calls, as in a notebook
    again = dataclasses.replace(first, X0=tuple(np.array(a, dtype=float) for a in second.X0))
    try:
        quiet(simulate, (first.M, first.Ib, X0, forces_at, first.dt, first.n), {"step": step})
        for a, b in zip(X0, again.X0):
            np.copyto(a, b)
        got = as_tuple(quiet(simulate, (first.M, first.Ib, X0, forces_at, first.dt, first.n), {"step": step}),
                       spec.labels)
    except (Exception, SystemExit):      # noqa: BLE001 — a probe: the runs above judged what it raises
        return None
    return None if close(got, again.expected()) else fail(spec, "stateful", tr("stale_in_place"))


def _attempt(spec: Spec, simulate, r: Run) -> tuple:
    """One run: ("ok", None), ("named", a CheckResult), ("crash", the exception no slip explains) or ("wrong", the
    text of the first difference no loop mistake explains)."""
    rec, expected = r.recorder(), r.expected()
    args = (r.M, r.Ib, as_kind(copy.deepcopy(tuple(r.X0)), r.kind), rec.forces_at, r.dt, r.n)   # X₀ of its kind too
    try:
        out = call(simulate, args, {"step": rec.step})
    except NotImplementedError as e:
        return "named", CheckResult(spec.name, False, "not_done", not_done(spec.name, e))
    except (Exception, SystemExit) as e:        # noqa: BLE001
        if isinstance(e, TimeUp):
            return "named", CheckResult(spec.name, False, "out_of_time", tr("out_of_time").format(name=spec.name))
        if library_answer(spec, simulate, e):
            return "named", library_answer(spec, simulate, e)
        if rec.misuse:
            return "named", _misused(spec, rec)
        if isinstance(e, TypeError) and "step" in str(e) and "argument" in str(e):
            return "named", fail(spec, "no_step_parameter", exc_text(e))
        return "crash", e
    if rec.misuse:
        return "named", _misused(spec, rec)
    if not same(tuple(r.X0), tuple(args[2])):
        return "named", fail(spec, "modified_input", tr("changed").format(names=tr("X0_changed")))
    if isinstance(out, (list, tuple)) and len(out) in (r.n, r.n + 1) and all(
            isinstance(s, (list, tuple)) and len(s) == 4 for s in out):
        return "named", fail(spec, "wrong_return", tr("list_of_states").format(n=len(out)))
    try:
        got = as_tuple(out, spec.labels, strict=True, want=tr("arrays_want").format(labels=", ".join(spec.labels)))
    except BadOutput as e:
        return "named", fail(spec, e.mistake, tr("detail_on_input").format(text=e.text, input=r.shown())
                             if e.text else "")
    if rec.steps == 0 and r.n > 0 and not r.stepped_before:
        return "named", fail(spec, "ignores_step")
    if close(got, expected):
        return "ok", None
    mistake = _loop_mistake(spec, got, expected, rec, r.dt, r.n)
    if mistake:
        return "named", mistake
    order = parts_order(spec, got, expected)
    if order:
        return "named", fail(spec, "parts_order", order)
    i = next(i for i in range(4) if not close(got[i], expected[i]))
    holds = next((j for j in range(4) if j != i and np.any(expected[j]) and close(got[i], expected[j])), None)
    if holds is not None:
        return "wrong", tr("kind_holds_array").format(label=spec.labels[i], other=spec.labels[holds])
    k = int(np.argmax([not close(g, e) for g, e in zip(got[i], expected[i])]))
    want_text, got_text = fmt_pair(expected[i][k], got[i][k])
    return "wrong", tr("state_differs").format(label=spec.labels[i], k=k, want=want_text, got=got_text)


def _one_run(spec: Spec, simulate, r: Run) -> CheckResult | None:
    """The verdict of one run (None: right).  A crash, or a wrong result no loop mistake explains, is probed
    (_trigger): its first line then says the simplest run that shows it."""
    kind, value = _attempt(spec, simulate, r)
    if kind in ("ok", "named"):
        return value
    trigger = _trigger(spec, simulate)
    if trigger is not None:
        return trigger
    if kind == "crash":
        return crashed(spec, value, r.shown())
    return fail(spec, "wrong_result", tr("wrong_state").format(detail=value, input=r.shown()))


LADDER = (("sim_one_step", dict(n=1)), ("sim_steps", dict(n=4)), ("sim_forces_vary", dict(n=4, vary=True)),
          ("sim_step_tuple", dict(n=4, vary=True, kind="tuple")), ("sim_step_list", dict(n=4, vary=True, kind="list")),
          ("sim_forces_stop", dict(n=6, vary=True, kind="tuple", stop=3)),
          ("sim_forces_start", dict(n=6, vary=True, kind="tuple", start=2)), ("sim_dt", dict(n=4, vary=True, dt=0.037)),
          ("sim_no_step", dict(n=0, kind="tuple")), ("sim_long", dict(n=LONG, vary=True, kind="tuple", dt=1e-3)),
          ("sim_far", dict(n=4, vary=True, kind="tuple", far=True)))
"""check_simulate's probing ladder (probing.py): one step of a StateTuple step under constant forces → several →
forces that change with t → a step that returns a plain tuple → a list → forces that stop (forces = []) →
another Δt → n_steps = 0."""


def _trigger(spec: Spec, simulate) -> CheckResult | None:
    """The simplest run of LADDER on which simulate fails, its verdict said with that run's feature first:
    « ✗ simulate raised … as soon as n_steps = 0 — on the input … ».  None when it fails on none of them."""
    rng = np.random.default_rng([spec.seed, 45])
    for feature, setting in LADDER:
        Ib, X0 = random_spd(rng), random_state(rng)
        b, F0 = rng.normal(0, 0.5, (2, 3)), rng.normal(0, 2.0, (2, 3))
        G = rng.normal(0, 5.0, (2, 3)) if setting.get("vary") else np.zeros((2, 3))
        dt = setting.get("dt", 0.01)
        if setting.get("far"):
            X0 = StateTuple(X0.x + 1e3, X0.R, 30.0 * X0.P, X0.L)
        r = Run(float(rng.uniform(1.5, 5.0)), Ib, X0, b, F0, G, dt, setting["n"], ref.euler_step,
                dt * setting["stop"] if "stop" in setting else np.inf, setting.get("kind", "state"),
                stepped_before=feature != LADDER[0][0], t_start=dt * setting.get("start", 0))
        kind, value = _attempt(spec, simulate, r)
        if kind == "named":
            return value
        if kind == "crash":
            return crashed(spec, value, r.shown(), tr("feature_" + feature))
        if kind == "wrong":
            return fail(spec, "probed", tr("sim_probed").format(feature=tr("feature_" + feature), detail=value,
                                                                input=r.shown()))
    return None


def _loop_mistake(spec: Spec, got, expected, rec: _Recorder, dt: float, n: int):
    """The loop's mistake, told by what it returned and what it called (a CheckResult), or None."""
    if [g.shape for g in got] == ONE_STATE:
        return fail(spec, "returned_one_state")
    if any(g.shape != e.shape for g, e in zip(got, expected)) and all(
            g.shape == e.shape or close(np.moveaxis(g, -1, 0), e) or close(g.T, e) for g, e in zip(got, expected)):
        return fail(spec, "states_transposed", shape_problem(got, expected, spec.labels))
    lengths = {len(g) if g.ndim else 0 for g in got}
    if lengths == {n}:
        if close(got, tuple(e[1:] for e in expected)):
            return fail(spec, "missing_initial")
        if close(got, tuple(e[:-1] for e in expected)):
            return fail(spec, "missing_final")
    if rec.steps == n + 1 or lengths == {n + 2}:
        return fail(spec, "extra_step")
    if lengths != {n + 1}:
        got_n = tr("and").join(str(v) for v in sorted(lengths))
        return fail(spec, "wrong_length", tr("got_states").format(got=got_n, n=n))
    shape = shape_problem(got, expected, spec.labels)
    if shape:
        return fail(spec, "wrong_shape", shape)
    if n >= 2 and all(np.all(g[1:] == g[-1]) for g in got) and any(not np.allclose(e[1], e[-1]) for e in expected):
        return fail(spec, "aliasing")          # every stored state (X₀ apart, perhaps) the same array, changed in place
    if n >= 2 and len(rec.stepped) >= 2 and all(close(s, tuple(e[0] for e in expected)) for s in rec.stepped):
        return fail(spec, "state_not_advanced")    # every step from X₀: X never reassigned
    wrong_dt = [d for d in rec.dts if not isinstance(d, (int, float, np.floating)) or abs(float(d) - dt) > 1e-12]
    if wrong_dt:
        return fail(spec, "ignores_dt", tr("dt_given").format(got=fmt(wrong_dt[0]), want=fmt(dt)))
    if len(rec.times) == 1 and rec.steps > 1:
        return fail(spec, "forces_once")
    times = np.array(rec.times)
    want_t = dt * np.arange(len(times))
    if len(times) and not np.allclose(times, want_t, rtol=0, atol=1e-9):
        return fail(spec, "wrong_time", tr("times").format(got=fmt(times[:4]), want=fmt(want_t[:4])))
    for k, (given, returned) in enumerate(zip(rec.given, rec.returned)):
        if len(given) != len(returned) or not all(close(tuple(g), tuple(r)) for g, r in zip(given, returned)):
            return fail(spec, "forces_changed", tr("forces_given").format(k=k, got=len(given), want=len(returned)))
    for i, state in enumerate(rec.states[: n]):
        own = tuple(g[i] for g in got) if all(g.ndim and len(g) > i for g in got) else None
        if not close(tuple(state), tuple(e[i] for e in expected)) and (own is None or not close(tuple(state), own)):
            return fail(spec, "stale_state", tr("stale_at").format(i=i))
    if rec.steps != n:
        return fail(spec, "step_count", tr("called_times").format(k=rec.steps, n=n))
    return None
