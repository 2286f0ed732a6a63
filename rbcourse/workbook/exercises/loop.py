"""check_simulate: the slides' iterations as a loop, checked by watching what it calls.

    X₀ given;  X_{k+1} = step(M, I_body_inv, X_k, forces_at(t_k, X_k), dt),  t_k = k · Δt

The check passes its own step and forces_at (a Recorder), so it sees the times, the states and the
number of steps, and can say which of them is wrong (missing X₀, stale state, wrong times, …).
"""
from __future__ import annotations

import copy

import numpy as np

from . import reference as ref
from .harness import (BadOutput, as_tuple, call, close, exc_text, fmt, not_done, random_spd, random_state, same,
                      short, where)
from .mistakes import ITERATION_2, CheckResult
from .reference import as_floats
from .verdict import Spec, fail, shape_problem


class _Recorder:
    """forces_at and step as the student's simulate sees them; they record how they are called."""

    def __init__(self, b, F0, G, step):
        self.b, self.F0, self.G, self._step = b, F0, G, step
        self.times, self.states, self.steps = [], [], 0

    def forces_at(self, t, X):
        """Forces attached to body points bᵢ: rᵢ = x + R bᵢ, Fᵢ(t) = F0ᵢ + t Gᵢ."""
        if isinstance(t, (tuple, list, np.ndarray)) and not np.ndim(t) == 0:
            raise TypeError("forces_at(t, X) takes the time t (a number) first, then the state X")
        x, R, P, L = as_floats(X)
        self.times.append(float(t))
        self.states.append((x.copy(), R.copy(), P.copy(), L.copy()))
        return [(x + R @ bi, F0 + float(t) * G) for bi, F0, G in zip(self.b, self.F0, self.G)]

    def step(self, M, I_body_inv, X, forces, dt):
        self.steps += 1
        return self._step(M, I_body_inv, X, forces, dt)


def check_simulate(simulate, *, verbose: bool = True, seed: int = 2010) -> CheckResult:
    """simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=euler_step) -> (x, R, P, L), the slides'
    iterations repeated:

        X₀ given;  X_{k+1} = step(M, I_body_inv, X_k, forces_at(t_k, X_k), dt),  t_k = k · Δt
        x, R, P, L: arrays of the n_steps + 1 states X₀ … X_n  ((n+1, 3), (n+1, 3, 3), (n+1, 3), (n+1, 3))

    The check passes its own step (the reference Euler step, or a projected one) and forces_at, and
    watches how they are called.
    """
    spec = Spec("simulate", "X_{k+1} = step(X_k), forces_at(k·Δt, X_k), n_steps + 1 states",
                ITERATION_2, labels=("x", "R", "P", "L"), count="6 random runs")
    try:
        result = _judge_simulate(spec, simulate, np.random.default_rng(seed))
    except Exception as e:      # noqa: BLE001
        result = CheckResult(spec.name, False, "check_failed",
                             f"✗ check_simulate itself failed ({exc_text(e)}): please tell your teacher")
    return result.printed(verbose)


def _judge_simulate(spec: Spec, simulate, rng) -> CheckResult:
    if not callable(simulate):
        return CheckResult(spec.name, False, "not_a_function",
                           f"✗ check_simulate takes your function itself: check_simulate(simulate), not its result"
                           f" — got {short(simulate)}")
    for run in range(6):
        M, Ib = float(rng.uniform(0.5, 5.0)), random_spd(rng)
        X0 = random_state(rng)
        k = int(rng.integers(1, 3))
        b, F0, G = rng.normal(0, 0.5, (k, 3)), rng.normal(0, 2.0, (k, 3)), rng.normal(0, 5.0, (k, 3))
        dt, n = float(rng.uniform(0.01, 0.05)), int(rng.integers(6, 12))
        ref_step = ref.euler_step if run % 2 == 0 else ref.euler_step_projected
        rec = _Recorder(b, F0, G, ref_step)
        expected = ref.simulate(M, Ib, X0, _Recorder(b, F0, G, ref_step).forces_at, dt, n, ref_step)
        args = (M, Ib, copy.deepcopy(X0), rec.forces_at, dt, n)
        shown = f"M = {fmt(M)}, X0 = {fmt(tuple(X0))}, dt = {fmt(dt)}, n_steps = {n}"
        try:
            out = call(simulate, args, {"step": rec.step})
        except NotImplementedError as e:
            return CheckResult(spec.name, False, "not_done", not_done(spec.name, e))
        except TypeError as e:
            if "step" in str(e) and "argument" in str(e):
                return fail(spec, "no_step_parameter", exc_text(e))
            return CheckResult(spec.name, False, "error", f"✗ simulate raised {exc_text(e)}{where(e)}\n   on {shown}")
        except (Exception, SystemExit) as e:        # noqa: BLE001
            return CheckResult(spec.name, False, "error", f"✗ simulate raised {exc_text(e)}{where(e)}\n   on {shown}")
        if not same(tuple(X0), tuple(args[2])):
            return fail(spec, "modified_input", "it changed X0")
        if isinstance(out, (list, tuple)) and len(out) in (n, n + 1) and all(
                isinstance(s, (list, tuple)) and len(s) == 4 for s in out):
            return fail(spec, "wrong_return", f"it returned a list of {len(out)} states: return four arrays "
                                               f"(x, R, P, L), e.g. x = np.array([X[0] for X in states])")
        try:
            got = as_tuple(out, spec.labels)
        except BadOutput as e:
            return fail(spec, e.mistake, e.text.replace("expected a tuple", "expected the arrays"))
        if rec.steps == 0:
            return fail(spec, "ignores_step")
        if close(got, expected):
            continue
        lengths = {len(g) if g.ndim else 0 for g in got}
        if lengths == {n}:
            if close(got, tuple(e[1:] for e in expected)):
                return fail(spec, "missing_initial")
            if close(got, tuple(e[:-1] for e in expected)):
                return fail(spec, "missing_final")
        if lengths != {n + 1}:
            got_n = " and ".join(str(v) for v in sorted(lengths))
            return fail(spec, "wrong_length", f"got {got_n} states for n_steps = {n}")
        shape = shape_problem(got, expected, spec.labels)
        if shape:
            return fail(spec, "wrong_shape", shape)
        if all(np.all(g == g[-1]) for g in got) and any(not np.allclose(e[0], e[-1]) for e in expected):
            return fail(spec, "aliasing")
        times = np.array(rec.times)
        want_t = dt * np.arange(len(times))
        if len(times) and not np.allclose(times, want_t, rtol=0, atol=1e-9):
            return fail(spec, "wrong_time", f"your times: {fmt(times[:4])}…, expected {fmt(want_t[:4])}…")
        for i, state in enumerate(rec.states[: n]):
            if not close(tuple(state), tuple(e[i] for e in expected)):
                return fail(spec, "stale_state", f"at step {i} it got a state other than X_{i}")
        if rec.steps != n:
            return fail(spec, "step_count", f"it was called {rec.steps} times for n_steps = {n}")
        for i, label in enumerate(spec.labels):
            if not close(got[i], expected[i]):
                k = int(np.argmax([not close(g, e) for g, e in zip(got[i], expected[i])]))
                return fail(spec, "wrong_result", f"wrong result: {label} differs first at state {k}: expected "
                                                   f"{fmt(expected[i][k])}, got {fmt(got[i][k])} — on {shown}")
    return CheckResult(spec.name, True, None, f"✓ simulate: {spec.formula} — correct on {spec.count}")
