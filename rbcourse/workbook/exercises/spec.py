"""What a check checks and how it says a verdict: a Case (one input, the reference's output, the known wrong
formulas), a Spec (the student's function, its formula, slide, the parts of its result, its probing ladder), and
fail(): ✗, the mistake's text, the slide to reread — with the few readings every verdict shares (read, parts,
parts_order, a crash with the input that triggers it, an answer taken from rbcourse)."""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Callable

from .crashes import explain
from .harness import N, as_array, as_tuple, close, exc_text, fmt, where
from ..language import current
from .mistakes import MISTAKES
from .result import CheckResult
from .slides import slide_text
from .texts import TEXTS, tr


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
    count: str = "random_inputs"         # an id in TEXTS ({n}: N), or a text
    n: int = N                           # how many inputs (the count's {n})
    ladder: tuple = ()                   # the probing ladder (ladders.py), where no known mistake matches
    reference: Callable | None = None    # the right function, on the ladder's inputs
    formulas: Callable | None = None     # (args) -> (text, value) of other formulas a probe may find (ladders.py)
    scales: tuple = ()                   # (feature, alter(args) -> args): the ends of the scales (ladders.SCALES)
    seed: int = 0                        # the check's seed (run() sets it): the probes' inputs come from it too

    def counted(self) -> str:
        """'20 random inputs', in the active language."""
        return local(self.count).format(n=self.n)

    def formula_text(self) -> str:
        """The formula of the pass line, in the active language (an id in TEXTS, or the formula itself)."""
        return local(self.formula)

def local(key: str) -> str:
    """The text of id `key` in the active language when TEXTS has it, else `key` itself (a formula)."""
    return TEXTS[current()].get(key, key)

def shown(case: Case) -> str:
    """The input of a case, for messages: 'P = [1, 2, 3], M = 2'."""
    return ", ".join(f"{n} = {fmt(v)}" for n, v in zip(case.names, case.args))

def shape_problem(got, want, labels) -> str | None:
    """What is wrong with the shapes, or None."""
    if isinstance(want, tuple):
        for g, w, label in zip(got, want, labels):
            if g.shape != w.shape:
                return tr("part_shape").format(label=label, got=g.shape, want=w.shape)
        return None
    return None if got.shape == want.shape else tr("shape").format(got=got.shape, want=want.shape)

def fail(spec: Spec, mistake: str, detail: str = "", prefix: str = "", **fields) -> CheckResult:
    """✗ and the mistake's text (or the detail of a generic failure), then the slide to reread.  A
    mistake's text may hold {fields} (e.g. args_swapped's {signature}); detail then fills {detail}."""
    m = MISTAKES.get(mistake)
    if m is None:           # a generic failure
        text, slide = detail, spec.slide
    elif "{" in m.text:
        text, slide = prefix + m.text.format(detail=detail, **fields), m.slide
    else:
        text = prefix + m.text + (f" ({detail})" if detail else "")
        slide = m.slide
    if mistake in OWN_SLIDE:
        slide = spec.slide
    return CheckResult(spec.name, False, mistake, tr("fail").format(name=spec.name, text=text,
                                                                       slide=slide_text(slide)))

OWN_SLIDE = ("scaled", "rounded", "stateful")
"""Mistakes any check may find: they send to the check's own slide."""

def crashed(spec: Spec, e: BaseException, given: str, feature: str = "") -> CheckResult:
    """A crash's verdict: the slip it shows (crashes.py) or the exception and the student's line, with the input
    that shows it — the simplest one of the probing ladder (feature), said in the first line."""
    raised = tr("raised").format(exc=exc_text(e), where=where(e))
    crash = explain(e)
    if feature:
        if crash:
            return fail(spec, crash, tr("crash_probed").format(exc=exc_text(e), where=where(e), feature=feature,
                                                               input=given))
        return CheckResult(spec.name, False, "crashes_when", tr("error_probed").format(
            name=spec.name, exc=exc_text(e), where=where(e), feature=feature, input=given))
    if crash:
        return fail(spec, crash, tr("detail_on_input").format(text=raised, input=given))
    return CheckResult(spec.name, False, "error", tr("error").format(name=spec.name, exc=exc_text(e), where=where(e),
                                                                    input=given))

def parts_order(spec: Spec, got, want) -> str | None:
    """'it returned (dx/dt, dP/dt, dR/dt, dL/dt); expected (dx/dt, dR/dt, dP/dt, dL/dt)' when the parts of a tuple
    result are the right ones in another order, else None."""
    if not isinstance(want, tuple) or len(got) != len(want):
        return None
    for perm in itertools.permutations(range(len(want))):
        if perm != tuple(range(len(want))) and all(close(got[k], want[p]) for k, p in enumerate(perm)):
            return tr("parts_found").format(got=", ".join(spec.labels[p] for p in perm), want=", ".join(spec.labels))
    return None

def parts(got):
    """A result as a tuple of its parts."""
    return got if isinstance(got, tuple) else (got,)

def read(spec: Spec, out):
    """The student's output as the check's arrays (strict: lists, integers, … are mistakes), or BadOutput."""
    return as_tuple(out, spec.labels, strict=True) if spec.labels else as_array(out, strict=True)

def library_answer(spec: Spec, fn, error: BaseException | None = None) -> CheckResult | None:
    """The "library_call" verdict when the function's answer comes from rbcourse itself, else None.  Grading tells
    it (grading/checker.py): the function stands for the student's, with .library = what its source takes from
    rbcourse, or the exception it raised has .library = the rbcourse name it called (absent where it is graded)."""
    try:
        found = getattr(fn if error is None else error, "library", None)
    except Exception:       # noqa: BLE001 — a student's object whose attributes raise
        found = None
    if not isinstance(found, str) or not found:
        return None
    return CheckResult(spec.name, False, "library_call", tr("library_call").format(name=spec.name, detail=found))
