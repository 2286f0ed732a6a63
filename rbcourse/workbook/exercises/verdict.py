"""From the student's output to a verdict: compare it with the reference on each case; on the first
difference, name the mistake (the first known wrong formula that gives the same output), else say
what differs and on which input.  A check never raises: an exception is a message too.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .harness import (BadOutput, N, as_array, as_tuple, call, close, exc_text, fmt, not_done, same, short,
                      where)
from .mistakes import MISTAKES, SLIDES, CheckResult


@dataclass
class Case:
    """One input of a check: the arguments, the reference's output, and the wrong formulas' outputs."""
    args: tuple                          # passed to the student's function (as copies)
    names: tuple                         # the names of the arguments, for messages
    expected: object                     # np.ndarray, or a tuple of them
    candidates: Callable = lambda: ()    # -> iterable of (mistake id, wrong value, prefix)
    special: str | None = None           # a mistake id: any failure on this input is that mistake
    kwargs: dict | None = None


@dataclass
class Spec:
    """What a check checks: the student's function, its formula and slide, the parts of its result."""
    name: str                            # the student's function
    formula: str                         # shown in the pass line
    slide: str                           # to reread after a generic failure
    labels: tuple | None = None          # the components of a tuple result (None: one array)
    count: str = f"{N} random inputs"


def shown(case: Case) -> str:
    """The input of a case, for messages: 'P = [1, 2, 3], M = 2'."""
    return ", ".join(f"{n} = {fmt(v)}" for n, v in zip(case.names, case.args))


def shape_problem(got, want, labels) -> str | None:
    """What is wrong with the shapes, or None."""
    if isinstance(want, tuple):
        for g, w, label in zip(got, want, labels):
            if g.shape != w.shape:
                return f"{label} has shape {g.shape}; expected {w.shape}"
        return None
    return None if got.shape == want.shape else f"it returned shape {got.shape}; expected {want.shape}"


def fail(spec: Spec, mistake: str, detail: str = "", prefix: str = "") -> CheckResult:
    """✗ and the mistake's text (or the detail of a generic failure), then the slide to reread."""
    m = MISTAKES.get(mistake)
    if m is None:           # a generic failure
        text, slide = detail, spec.slide
    else:
        text = prefix + m.text + (f" ({detail})" if detail else "")
        slide = m.slide
    return CheckResult(spec.name, False, mistake, f"✗ {spec.name}: {text}\n   → reread {slide_text(slide)}")


def slide_text(slide: str) -> str:
    """'the slide “Les Formules”' for a slide's title; any other source as it is."""
    return f"the slide “{slide}”" if slide in SLIDES else slide


def diagnose(spec: Spec, case: Case, got, last_resort=None) -> CheckResult:
    """The student's output differs from the reference: name the mistake.  last_resort(got, case) -> a
    mistake id or None, tried before the generic "wrong result"."""
    if case.special:
        return fail(spec, case.special, f"on the input {shown(case)}")
    for mistake, wrong, prefix in case.candidates():
        if close(got, wrong) and not close(got, case.expected):
            return fail(spec, mistake, prefix=prefix)
    shape = shape_problem(got, case.expected, spec.labels)
    if shape:
        return fail(spec, "wrong_shape", f"{shape} (on the input {shown(case)})")
    late = last_resort(got, case) if last_resort else None
    if late:
        return fail(spec, late)
    nan = " (it contains NaN or inf)" if not all(np.all(np.isfinite(g)) for g in parts(got)) else ""
    if isinstance(case.expected, tuple):
        wrong = [i for i, (g, w) in enumerate(zip(got, case.expected)) if not close(g, w)]
        first = wrong[0]
        others = [spec.labels[i] for i in wrong[1:]]
        also = f"; {', '.join(others)} {'is' if len(others) == 1 else 'are'} wrong too" if others else ""
        for mistake, bad, prefix in case.candidates():       # a mistake that explains the first wrong part
            if close(got[first], bad[first]) and not close(bad[first], case.expected[first]):
                return fail(spec, mistake, f"seen in {spec.labels[first]}{also}", prefix=prefix)
        return fail(spec, "wrong_result",
                    f"wrong result: {spec.labels[first]} should be {fmt(case.expected[first])}, got "
                    f"{fmt(got[first])}{nan}{also} — on the input {shown(case)}")
    return fail(spec, "wrong_result", f"wrong result: expected {fmt(case.expected)}, got {fmt(got)}{nan} — "
                                       f"on the input {shown(case)}")


def parts(got):
    """A result as a tuple of its parts."""
    return got if isinstance(got, tuple) else (got,)


def judge(spec: Spec, fn, cases, accept=None, last_resort=None) -> CheckResult:
    """Run fn on every case; the first failure is diagnosed.  accept(got, case) -> a note: an
    output different from the reference that is right all the same (then the pass line adds the note)."""
    if not callable(fn):
        return CheckResult(spec.name, False, "not_a_function",
                           f"✗ check_{spec.name} takes your function itself: check_{spec.name}({spec.name}), "
                           f"not its result — got {short(fn)}")
    notes = []
    for case in cases:
        args = copy.deepcopy(case.args)
        try:
            out = call(fn, args, case.kwargs)
        except NotImplementedError as e:
            return CheckResult(spec.name, False, "not_done", not_done(spec.name, e))
        except (Exception, SystemExit) as e:        # noqa: BLE001 — a check never raises
            if case.special:
                return fail(spec, case.special, f"it raised {exc_text(e)}{where(e)}")
            return CheckResult(spec.name, False, "error",
                               f"✗ {spec.name} raised {exc_text(e)}{where(e)}\n   on the input {shown(case)}")
        changed = [n for n, a, b in zip(case.names, case.args, args) if not same(a, b)]
        if changed:
            return fail(spec, "modified_input", f"it changed {', '.join(changed)}")
        try:
            got = as_tuple(out, spec.labels) if spec.labels else as_array(out)
        except BadOutput as b:
            if case.special:
                return fail(spec, case.special, b.text)
            return fail(spec, b.mistake, b.text + f" (on the input {shown(case)})")
        if close(got, case.expected):
            continue
        note = accept(got, case) if accept else None
        if note:
            notes.append(note)
            continue
        return diagnose(spec, case, got, last_resort)
    extra = f" ({notes[0]})" if notes else ""
    return CheckResult(spec.name, True, None, f"✓ {spec.name}: {spec.formula} — correct on {spec.count}{extra}")


def run(spec: Spec, fn, make_cases, verbose: bool, seed, accept=None, last_resort=None) -> CheckResult:
    """judge() on make_cases(rng) with the check's seed; a bug in the check is a result too; printed if verbose."""
    try:
        result = judge(spec, fn, make_cases(np.random.default_rng(seed)), accept, last_resort)
    except Exception as e:      # noqa: BLE001 — a bug in the check must not stop the notebook
        result = CheckResult(spec.name, False, "check_failed",
                             f"✗ check_{spec.name} itself failed ({exc_text(e)}): please tell your teacher")
    return result.printed(verbose)
