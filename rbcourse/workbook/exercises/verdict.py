"""From the student's output to a verdict: compare it with the reference on each case; on the first
difference, name the mistake (the first known wrong formula that gives the same output), else say
what differs and on which input.  A check never raises: an exception is a message too.
"""
from __future__ import annotations

import contextlib
import copy
import inspect
import io
import itertools
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .crashes import explain
from .harness import (BadOutput, N, as_array, as_tuple, call, close, exc_text, fmt, fmt_pair, not_done, same,
                      short, where)
from ..language import current
from .mistakes import MISTAKES
from .probing import array_kind, constant_factor, ignores, increment_kind, misread, probe
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


def scaled_or_rounded(got, want):
    """("scaled", "0.5") when got = c · want (c ≠ 1), ("rounded", "to 2 decimals") when got is want rounded;
    else None — two mistakes told by the numbers alone, whatever the formula."""
    if not isinstance(got, np.ndarray) or got.shape != want.shape or not np.all(np.isfinite(got)) or not want.size:
        return None
    for k in range(7):
        if np.array_equal(got, np.round(want, k)):
            return "rounded", tr("rounded_detail").format(k=k)
    ww = float(np.sum(want * want))
    if ww > 0:
        c = float(np.sum(got * want)) / ww
        if abs(c) > 1e-9 and abs(c - 1.0) > 1e-3 and close(got, c * want):
            return "scaled", f"{c:.4g}"
    return None


def _differs(bad, want) -> list:
    """The indices of the parts where a wrong tuple differs from the reference."""
    return [i for i, (b, w) in enumerate(zip(bad, want)) if not close(b, w)]


def matching(case: Case, got) -> list:
    """The known wrong formulas of this case that give the whole output got: [(mistake id, prefix)], in order."""
    if close(got, case.expected):
        return []
    return [(mistake, prefix) for mistake, wrong, prefix in case.candidates() if close(got, wrong)]


def confirmed(spec: Spec, fn, cases, index: int, got) -> tuple | None:
    """(mistake id, prefix) of the known wrong formula that gives fn's output on the failing case and on every other
    case where fn fails and some formula matches (up to 4 of them): one case may match two formulas by chance (P and
    P / int(M) when 1 <= M < 2), the others tell them apart.  None when no formula matches this case."""
    first = matching(cases[index], got)
    if len(first) < 2:
        return first[0] if first else None
    ids = [m for m, _ in first]
    for case in [c for k, c in enumerate(cases) if k != index][:8]:
        try:
            other = read(spec, _quiet_call(fn, copy.deepcopy(case.args), case.kwargs))
        except (Exception, SystemExit):      # noqa: BLE001 — a probe
            continue
        found = [m for m, _ in matching(case, other)]
        if found and set(ids) & set(found):
            ids = [m for m in ids if m in found]
        if len(ids) == 1:
            break
    return next((m, prefix) for m, prefix in first if m == ids[0])


def diagnose(spec: Spec, case: Case, got, last_resort=None, known=None) -> CheckResult:
    """The student's output differs from the reference: name the mistake.  In order: a known wrong formula
    that gives the whole output; a wrong shape; (tuples) the known mistakes fully present in the output, the
    one that explains the first wrong part named; last_resort(got, case) -> a mistake id or None (a mistake
    told by its behaviour, e.g. a matrix that is not a rotation); else "wrong result", with the input, the
    expected and the returned values."""
    if case.special:
        return fail(spec, case.special, tr("on_input").format(input=shown(case)))
    candidates = list(case.candidates())
    known = known if known is not None else next(iter(matching(case, got)), None)
    if known:
        return fail(spec, known[0], prefix=known[1])
    order = parts_order(spec, got, case.expected)
    if order:
        return fail(spec, "parts_order", order)
    shape = shape_problem(got, case.expected, spec.labels)
    if shape:
        if any(g.shape == w.shape + (1,) and w.ndim == 1 for g, w in zip(parts(got), parts(case.expected))):
            return fail(spec, "column_vector", tr("shape_on_input").format(shape=shape, input=shown(case)))
        return fail(spec, "wrong_shape", tr("shape_on_input").format(shape=shape, input=shown(case)))
    nan = tr("nan") if not all(np.all(np.isfinite(g)) for g in parts(got)) else ""
    if isinstance(case.expected, tuple):
        wrong = _differs(got, case.expected)
        first = wrong[0]
        best = None                 # a mistake fully present in the output (every part it changes is as it makes it)
        for mistake, bad, prefix in candidates:
            diff = _differs(bad, case.expected) if isinstance(bad, tuple) and len(bad) == len(got) else []
            if first in diff and all(close(got[i], bad[i]) for i in diff):
                if best is None or len(diff) > len(best[3]):
                    best = (mistake, bad, prefix, diff)
        if best:
            mistake, _, prefix, diff = best
            others = [spec.labels[i] for i in wrong if i not in diff]
            also = ("; " + tr("also_one" if len(others) == 1 else "also_many").format(labels=", ".join(others))
                    .lstrip("; ")) if others else ""
            return fail(spec, mistake, tr("seen_in").format(label=spec.labels[first]) + also, prefix=prefix)
        found = scaled_or_rounded(got[first], case.expected[first])
        if found:
            return fail(spec, found[0], found[1], prefix=tr("in_label").format(label=spec.labels[first]))
        late = last_resort(got, case) if last_resort else None
        if late:
            return fail(spec, *late) if isinstance(late, tuple) else fail(spec, late)
        others = [spec.labels[i] for i in wrong[1:]]
        also = tr("also_one" if len(others) == 1 else "also_many").format(labels=", ".join(others)) \
            if others else ""
        want_text, got_text = fmt_pair(case.expected[first], got[first])
        return fail(spec, "wrong_result", tr("wrong_part").format(
            label=spec.labels[first], want=want_text, got=got_text, nan=nan, also=also, input=shown(case)))
    found = scaled_or_rounded(got, case.expected)
    if found:
        return fail(spec, *found)
    late = last_resort(got, case) if last_resort else None
    if late:
        return fail(spec, *late) if isinstance(late, tuple) else fail(spec, late)
    want_text, got_text = fmt_pair(case.expected, got)
    return fail(spec, "wrong_result", tr("wrong_result").format(want=want_text, got=got_text, nan=nan,
                                                                   input=shown(case)))


def probed(spec: Spec, fn, names, scaled: CheckResult | None = None) -> CheckResult | None:
    """The diagnosis by probing (probing.py) on the check's ladder: the first feature that breaks fn and the kind
    of difference it makes there — « ✗ resultants: τ is wrong as soon as a force acts off the barycentre — its
    sign is reversed (on the input …) », or the input that makes it raise.  None without a ladder, or when fn is
    right on every rung.  scaled: the check's "scaled" verdict, kept when the factor is the same on every probe."""
    if not spec.ladder or spec.reference is None:
        return None
    found = probe(fn, spec.ladder, spec.reference, lambda out: read(spec, out), spec.seed)
    if found is None:
        return None
    feature = tr("feature_" + found.rung.feature)
    given = ", ".join(f"{n} = {fmt(v)}" for n, v in zip(names, found.args))
    if found.exc is not None:
        return crashed(spec, found.exc, given, feature)
    try:
        again = read(spec, _quiet_call(fn, copy.deepcopy(found.args)))
    except (Exception, SystemExit):      # noqa: BLE001 — a probe
        again = found.got
    if not (same(again, found.got) or close(again, found.got)):
        return fail(spec, "stateful", tr("stale_twice"))
    alt = misread(found, spec.reference)
    if alt:
        return fail(spec, "probed", tr("probed_misread").format(feature=feature, kind=tr(alt), input=given))
    got, want = parts(found.got), parts(found.expected)
    wrong = [i for i, (g, w) in enumerate(zip(got, want)) if not close(g, w)]
    i = wrong[0]
    label = spec.labels[i] if spec.labels else tr("the_result")
    others = [(parts(g)[i], parts(w)[i], args) for g, w, args in found.others]
    kind = None
    if spec.labels and "X" in names and "dt" in names:      # a next state: its increment from X(t)
        X, dt = found.args[names.index("X")], found.args[names.index("dt")]
        kind = increment_kind([(got[i], want[i], np.asarray(list(X)[i], float), dt)] + [
            (g, w, np.asarray(list(a[names.index("X")])[i], float), a[names.index("dt")]) for g, w, a in others])
    inputs = list(zip("xRPL", list(found.args[names.index("X")]))) if "X" in names else []
    inputs += [(n, v) for n, v in zip(names, found.args) if isinstance(v, np.ndarray)]
    scalars = [[(n, v) for n, v in zip(names, a) if isinstance(v, (int, float)) and not isinstance(v, bool)]
               for a in [found.args] + [a for _, _, a in others]]
    pairs = [(g, w) for g, w, _ in others]
    if spec.labels:
        holds = next((j for j, w in enumerate(want) if j != i and np.any(w) and close(got[i], w)), None)
        if holds is not None:
            return fail(spec, "probed", tr("probed").format(label=label, feature=feature, also="", input=given,
                                                            kind=tr("kind_holds").format(other=spec.labels[holds])))
    if scaled is not None and constant_factor([(got[i], want[i])] + pairs) is not None:
        return scaled
    formula = _formula(spec, found, got[i]) if spec.formulas and not spec.labels else None
    kind = kind or (tr("kind_formula").format(formula=formula) if formula else None)
    weak = False
    if not kind:
        kind, weak = array_kind(got[i], want[i], pairs, inputs, scalars)
    ignored = ignores(fn, found, spec.reference, names, lambda out: read(spec, out)) if weak else None
    if ignored:
        return fail(spec, "probed", tr("probed_misread").format(feature=feature, input=given,
                                                                kind=tr("kind_ignores").format(name=ignored)))
    rest = [spec.labels[j] for j in wrong[1:]] if spec.labels else []
    also = tr("also_one" if len(rest) == 1 else "also_many").format(labels=", ".join(rest)) if rest else ""
    return fail(spec, "probed", tr("probed").format(label=label, feature=feature, kind=kind, also=also,
                                                    input=given))


def _formula(spec: Spec, found, got) -> str | None:
    """The first of the check's other formulas (Spec.formulas) that gives fn's result on the found input and on the
    other failing probes (I⁻¹_body · I⁻¹_body and I⁻¹_body · R · I⁻¹_body agree while R = I), else None."""
    probes = [(got, found.args)] + [(g, a) for g, _, a in found.others]
    for text, value in spec.formulas(*found.args):
        if close(got, value) and all(close(g, dict(spec.formulas(*a)).get(text)) for g, a in probes[1:]):
            return text
    return None


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


def _quiet_call(fn, args, kwargs=None):
    """fn(*args) with its prints swallowed (a probe, not the student's run)."""
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return call(fn, args, kwargs)


def swapped_arguments(spec: Spec, fn, cases, failing: int):
    """The two arguments (i, j) whose swap makes fn right on the failing case and on the others tried
    (up to 4), or None: the student's parameters are in another order than the exercise's."""
    case = cases[failing]
    n = len(case.args)
    for i in range(n):
        for j in range(i + 1, n):
            ok = True
            for c in [case] + [c for k, c in enumerate(cases) if k != failing][:3]:
                args = list(copy.deepcopy(c.args))
                args[i], args[j] = args[j], args[i]
                try:
                    got = read(spec, _quiet_call(fn, tuple(args), c.kwargs))
                except (Exception, SystemExit):      # noqa: BLE001 — a probe: any failure means "not this swap"
                    ok = False
                    break
                if not close(got, c.expected):
                    ok = False
                    break
            if ok:
                return i, j
    return None


def signature_of(fn) -> str:
    """'(M, P)': the parameters of the student's function, as it declares them (for messages)."""
    try:
        return "(" + ", ".join(inspect.signature(fn).parameters) + ")"
    except (TypeError, ValueError):
        return "(…)"


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


def judge(spec: Spec, fn, cases, accept=None, last_resort=None) -> CheckResult:
    """Run fn on every case; the first failure is diagnosed.  accept(got, case) -> a note: an
    output different from the reference that is right all the same (then the pass line adds the note)."""
    if not callable(fn):
        return CheckResult(spec.name, False, "not_a_function",
                           tr("not_a_function").format(name=spec.name, got=short(fn)))
    library = library_answer(spec, fn)
    if library:
        return library
    cases = list(cases)
    notes = []
    for index, case in enumerate(cases):
        args = copy.deepcopy(case.args)
        try:
            out = call(fn, args, case.kwargs)
        except NotImplementedError as e:
            return CheckResult(spec.name, False, "not_done", not_done(spec.name, e))
        except (Exception, SystemExit) as e:        # noqa: BLE001 — a check never raises
            library = library_answer(spec, fn, e)
            if library:
                return library
            raised = tr("raised").format(exc=exc_text(e), where=where(e))
            if case.special:
                return fail(spec, case.special, raised)
            swap = swapped_arguments(spec, fn, cases, index)
            if swap and _declared_order(fn, case, swap) != "as_the_exercise":
                return _swapped(spec, fn, case, swap)
            crash = explain(e)
            if crash:
                return fail(spec, crash, tr("detail_on_input").format(text=raised, input=shown(case)))
            found = probed(spec, fn, case.names)
            if found:
                return found
            return CheckResult(spec.name, False, "error", tr("error").format(
                name=spec.name, exc=exc_text(e), where=where(e), input=shown(case)))
        try:
            changed = [n for n, a, b in zip(case.names, case.args, args) if not same(a, b)]
        except Exception:       # noqa: BLE001 — the student's objects may compare strangely
            changed = []
        if changed:
            return fail(spec, "modified_input", tr("changed").format(names=", ".join(changed)))
        try:
            got = read(spec, out)
        except BadOutput as b:
            loose = _loose(spec, out) if b.mistake == "integer_array" else None
            if loose is not None and close(loose, case.expected):
                continue        # integers that hold the exact answer (zeros for no force): nothing was truncated
            if case.special:
                return fail(spec, case.special, b.text)
            mistake = b.mistake
            if mistake == "wrong_return" and spec.labels and isinstance(out, tuple) and len(out) == 2 * len(spec.labels):
                mistake = "tuple_arithmetic"        # X + (…): `+` joined two tuples end to end
            return fail(spec, mistake, tr("detail_on_input").format(text=b.text, input=shown(case)) if b.text else "")
        except (Exception, SystemExit) as e:        # noqa: BLE001 — reading the output ran the student's code
            return CheckResult(spec.name, False, "error", tr("error_reading").format(
                name=spec.name, exc=exc_text(e), where=where(e), input=shown(case)))
        if close(got, case.expected):
            continue
        note = accept(got, case) if accept else None
        if note:
            notes.append(note)
            continue
        swap = None if case.special else swapped_arguments(spec, fn, cases, index)
        order = _declared_order(fn, case, swap) if swap else None
        if order == "swapped":
            return _swapped(spec, fn, case, swap)
        known = None if case.special else confirmed(spec, fn, cases, index, got)
        result = diagnose(spec, case, got, last_resort, known)
        if order == "unknown" and result.mistake == "wrong_result":
            return _swapped(spec, fn, case, swap)
        if result.mistake in ("wrong_result", "scaled"):
            return _probed_instead(spec, fn, case, result)
        return result
    stale = remembers(spec, fn, cases)
    if stale:
        return stale
    extra = f" ({notes[0]})" if notes else ""
    return CheckResult(spec.name, True, None, tr("pass").format(name=spec.name, formula=spec.formula_text(),
                                                                count=spec.counted(), note=extra))


def _refill(old, new):
    """old's arrays (in tuples and lists too) given new's values in place, the same objects; new's other values."""
    if isinstance(old, np.ndarray) and isinstance(new, np.ndarray) and old.shape == new.shape and old.dtype == new.dtype:
        np.copyto(old, new)
        return old
    if isinstance(old, (list, tuple)) and isinstance(new, (list, tuple)) and len(old) == len(new):
        parts = [_refill(a, b) for a, b in zip(old, new)]
        if isinstance(old, list):
            old[:] = parts
            return old
        return type(new)(*parts) if hasattr(new, "_fields") else tuple(parts)
    return copy.deepcopy(new)


def _scalars_from(first, second):
    """second's arguments with first's numbers (M, mass, dt): a cache keyed by the mass answers wrongly."""
    return tuple(a if isinstance(a, (int, float)) and not isinstance(a, bool) else b for a, b in zip(first, second))


def remembers(spec: Spec, fn, cases) -> CheckResult | None:
    """"stateful" when fn, right on every case, answers from an earlier call: called again with the same arrays
    changed in place to another case's values (a cache keyed by id()), with another case's arrays and the first
    one's numbers (a cache keyed by the mass), or twice on one input (a total kept between calls).  None if not."""
    if spec.reference is None or len(cases) < 2:
        return None
    A, B = cases[0], cases[1]
    try:
        args = copy.deepcopy(A.args)
        _quiet_call(fn, args, A.kwargs)
        same_objects = _scalars_from(A.args, tuple(_refill(a, b) for a, b in zip(args, B.args)))
        tries = [(same_objects, None, "stale_in_place"),
                 (_scalars_from(A.args, copy.deepcopy(B.args)), None, "stale_numbers"),
                 (copy.deepcopy(B.args), B.expected, "stale_twice")]
        for given, want, key in tries:
            want = want if want is not None else spec.reference(*copy.deepcopy(given))
            want = tuple(np.asarray(w, float) for w in want) if isinstance(want, tuple) else np.asarray(want, float)
            got = read(spec, _quiet_call(fn, given, B.kwargs))
            if not close(got, want):
                return fail(spec, "stateful", tr(key))
    except (Exception, SystemExit):      # noqa: BLE001 — a probe: the cases above judged what fn raises
        return None
    return None


def _probed_instead(spec: Spec, fn, case: Case, result: CheckResult) -> CheckResult:
    """A "wrong result" named by probing where it can be; a "scaled" kept only when probing finds the same factor
    on every input (a factor that changes with the input is no constant factor)."""
    return probed(spec, fn, case.names, result if result.mistake == "scaled" else None) or result


def _loose(spec: Spec, out):
    """The output read as floats whatever its type (None if it cannot be)."""
    try:
        return as_tuple(out, spec.labels) if spec.labels else as_array(out)
    except Exception:       # noqa: BLE001
        return None


def _declared_order(fn, case: Case, swap) -> str:
    """The student's fn is right with the arguments i, j swapped: are its parameters declared in the swapped
    order ("swapped": named as the exercise's j, i), in the exercise's ("as_the_exercise": then the formula
    itself swaps them, as M / P does), or named otherwise ("unknown")?"""
    i, j = swap
    try:
        declared = [p.lower() for p in inspect.signature(fn).parameters]
    except (TypeError, ValueError):
        return "unknown"
    want = [n.lower() for n in case.names]
    if len(declared) > j and (declared[i], declared[j]) == (want[j], want[i]):
        return "swapped"
    if len(declared) > j and (declared[i], declared[j]) == (want[i], want[j]):
        return "as_the_exercise"
    return "unknown"


def _swapped(spec: Spec, fn, case: Case, swap) -> CheckResult:
    i, j = swap
    call_text = f"{spec.name}({', '.join(case.names)})"
    detail = tr("swapped").format(call=call_text, name=spec.name, declared=signature_of(fn), a=case.names[i],
                                     b=case.names[j])
    return fail(spec, "args_swapped", detail, signature=call_text)


def run(spec: Spec, fn, make_cases, verbose: bool, seed, accept=None, last_resort=None) -> CheckResult:
    """judge() on make_cases(rng) with the check's seed; a bug in the check is a result too; printed if verbose."""
    spec.seed = seed
    try:
        result = judge(spec, fn, make_cases(np.random.default_rng(seed)), accept, last_resort)
    except Exception as e:      # noqa: BLE001 — a bug in the check must not stop the notebook
        result = CheckResult(spec.name, False, "check_failed", tr("check_failed").format(name=spec.name,
                                                                                           exc=exc_text(e)))
    return result.printed(verbose)
