"""Issue 30: the checks name slips by family, whatever their spelling.  slips.py holds, per family, at least three
implementations written unlike the catalogue's (loops, comprehensions, einsum, scipy) and the equivalent forms that
must pass; here every one is fed to its check in both languages: each slip rejected and named with its family's
mistake, each message wholly in the active language, a crash shown at the student's own line, the notebook's own
inputs (forces = [], a plain tuple X, n_steps = 0) tried and named."""
import collections
import importlib.util
import pathlib
import time

import numpy as np
import pytest

from rbcourse.workbook import exercises as ex
from rbcourse.workbook.exercises.crashes import CRASHES

_spec = importlib.util.spec_from_file_location("_slips", pathlib.Path(__file__).with_name("slips.py"))
slips = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(slips)

ENGLISH_FRAMING = ("(in ", ", line ", "it raised", "on the input", "reread", "wrong result", "expected")
"""The English words of a check's framing: none may show in a French message."""


def check(name, fn):
    return getattr(ex, f"check_{name}")(fn, verbose=False)


@pytest.mark.parametrize("name, fn, family", slips.SLIPS,
                         ids=[f"{n}-{m}-{getattr(f, '__name__', 'lambda')}-{i}" for i, (n, f, m) in enumerate(slips.SLIPS)])
def test_each_slip_is_named_as_its_family(name, fn, family, language):
    r = check(name, fn)
    assert not r.passed and r.mistake == family, r.message
    mistake = ex.MISTAKES[family]
    assert mistake.text.split("{")[0].split(":")[0] in r.message
    assert r.message.startswith(f"✗ {name}")
    if language == "fr":
        for english in ENGLISH_FRAMING:
            assert english not in r.message, (english, r.message)
        assert "→ relisez " in r.message


@pytest.mark.parametrize("name, fn", slips.CORRECT, ids=[f"{n}-{i}" for i, (n, _) in enumerate(slips.CORRECT)])
def test_equivalent_forms_pass(name, fn, language):
    r = check(name, fn)
    assert r.passed, r.message


def test_three_spellings_per_family_at_least():
    count = collections.Counter((name, family) for name, _, family in slips.SLIPS)
    assert min(count.values()) >= 3, [k for k, v in count.items() if v < 3]
    assert len({family for _, family in count}) >= 20


CRASHING = [(n, f, m) for n, f, m in slips.SLIPS if m in {c for c, _ in CRASHES} - {"empty_forces", "state_attributes"}
            and f is not slips.euler_tuple_concat]          # (X + (…) returns 8 values: no crash)


@pytest.mark.parametrize("name, fn, family", CRASHING, ids=[f.__name__ for _, f, _ in CRASHING])
def test_a_crash_is_shown_at_the_students_line(name, fn, family, language):
    """The raw exception is explained (its family's text) and framed at the line of the student's own function,
    never one inside rbcourse, scipy or numpy, in the active language."""
    r = check(name, fn)
    assert r.mistake == family, r.message
    frame = {"en": f"(in {fn.__name__}, line ", "fr": f"(dans {fn.__name__}, ligne "}[language]
    assert frame in r.message, r.message
    assert "rbcourse" not in r.message.split(frame)[1].split(")")[0]


def test_the_notebooks_later_inputs_are_tried_and_said():
    """forces = [] (the box after its push), a plain tuple X (what a step returns), n_steps = 0: a function that fails
    only there fails its check, saying which case."""
    def euler_no_force_fails(M, Ib, X, forces, dt):
        if not forces:
            raise ValueError("no forces")
        return slips._step(M, Ib, X, forces, dt)
    r = check("euler_step", euler_no_force_fails)
    assert r.mistake == "empty_forces" and "forces = []" in r.message and "Part 7" in r.message

    def euler_named_tuple_only(M, Ib, X, forces, dt):
        return slips._step(M, Ib, (X.x, X.R, X.P, X.L), forces, dt)
    r = check("euler_step", euler_named_tuple_only)
    assert r.mistake == "state_attributes" and "plain tuple" in r.message

    def simulate_needs_one_step(M, Ib, X0, forces_at, dt, n_steps, step=None):
        X, states = X0, [X0]
        for k in range(n_steps):
            X = step(M, Ib, X, forces_at(k * dt, X), dt)
            states.append(X)
        states[1]                                        # noqa: B018 — fails on n_steps = 0
        return tuple(np.array([s[i] for s in states]) for i in range(4))
    r = check("simulate", simulate_needs_one_step)
    assert r.mistake == "crashes_when" and "n_steps = 0" in r.message.splitlines()[0] \
        and "simulate_needs_one_step" in r.message


def test_a_simulate_never_sees_a_line_of_rbcourse():
    """The step's arguments in another order raised inside the check's step: named as the call's order, with no
    frame of rbcourse's and no engine message."""
    r = check("simulate", slips.simulate_step_args)
    assert r.mistake == "call_order" and "step(float, ndarray (3, 3), tuple, float, list)" in r.message
    assert "forces must be" not in r.message and ".py" not in r.message


def test_harmless_types_pass_and_harmful_ones_are_named():
    """As the notebook's conventions cell says: a state returned as a list or a StateTuple, and integer zeros for
    no force, pass; a list for an array, integers that truncate, a (3, 1) column are named."""
    assert check("euler_step", lambda *a: list(slips._step(*a))).passed
    assert check("euler_step", lambda *a: ex.StateTuple(*slips._step(*a))).passed
    assert check("resultants", lambda x, fs: slips._res(x, fs) if fs else (np.zeros(3, int), np.zeros(3, int))).passed
    assert check("velocity", lambda P, M: list(P / M)).mistake == "returned_list"
    assert check("velocity", lambda P, M: (P / M).astype(int)).mistake == "integer_array"
    assert check("velocity", lambda P, M: (P / M)[:, None]).mistake == "column_vector"


def test_the_whole_check_set_stays_fast():
    functions = {name: fn for name, fn in slips.CORRECT[::-1]}       # one correct form per check
    functions["velocity"] = lambda P, M: P / M
    start = time.perf_counter()
    for name, fn in functions.items():
        assert check(name, fn).passed
    assert time.perf_counter() - start < 5.0
