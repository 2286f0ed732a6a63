"""From the student's output to a verdict: compare it with the reference on each case; on the first
difference, name the mistake (the first known wrong formula that gives the same output), else say
what differs and on which input.  A check never raises: an exception is a message too.
"""
from __future__ import annotations

import copy
import inspect

import numpy as np

from .crashes import explain
from .harness import (BadOutput, TimeUp, as_array, as_tuple, call, close, exc_text, fmt_pair, not_done, quiet, same,
                      short, where)
from .probed import answers_again, probed, probed_instead, remembers
from .result import CheckResult
from .spec import (Case, Spec, fail, library_answer, parts, parts_order, read,  # noqa: F401 (the checks'
                   shape_problem, shown)                                                   # names, from here too)
from .texts import tr
from ...support import checks


def scaled_or_rounded(got, want):
    """("scaled", "0.5") when got = c · want (c ≠ 1), ("rounded", "to 2 decimals") when got is want rounded;
    else None — two mistakes told by the numbers alone, whatever the formula."""
    if not isinstance(got, np.ndarray) or got.shape != want.shape or not np.all(np.isfinite(got)) or not want.size:
        return None
    for k in range(7):
        if np.array_equal(got, np.round(want, k)) and np.any(np.round(want, k)):    # (a tiny value rounds to 0)
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
    return [(mistake, prefix) for mistake, wrong, prefix in case.candidates()
            if close(got, wrong) and not _vanishing(wrong, case.expected)]


def _vanishing(wrong, want) -> bool:
    """A wrong formula whose value is not zero but vanishes beside the right one (on tiny inputs, np.cross(ω, L) is
    1e-16 where ω is 1e-8): matching it there says nothing about the formula."""
    def biggest(a):
        return max((float(np.abs(np.asarray(v, float)).max()) for v in (a if isinstance(a, tuple) else (a,))
                    if np.size(v)), default=0.0)
    w = biggest(wrong)
    return 0.0 < w < 1e-6 * biggest(want)


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
            other = read(spec, quiet(fn, copy.deepcopy(case.args), case.kwargs))
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
                    got = read(spec, quiet(fn, tuple(args), c.kwargs))
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
            if isinstance(e, TimeUp):
                return CheckResult(spec.name, False, "out_of_time", tr("out_of_time").format(name=spec.name))
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
        if answers_again(spec, fn, case.args, got, case.kwargs):
            return fail(spec, "stateful", tr("stale_twice"))
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
            return probed_instead(spec, fn, case, result)
        return result
    stale = remembers(spec, fn, cases)
    if stale:
        return stale
    extra = f" ({notes[0]})" if notes else ""
    return CheckResult(spec.name, True, None, tr("pass").format(name=spec.name, formula=spec.formula_text(),
                                                                count=spec.counted(), note=extra))


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


def check_options(seed, verbose) -> tuple:
    """(seed, verbose) as a check takes them: an integer in [0, 2⁶³ − 1], and True or False."""
    return checks.integer("seed", seed, low=0, high=2**63 - 1), checks.boolean("verbose", verbose)


def at_the_ends(spec: Spec, cases: list) -> list:
    """The check's cases, then its first one altered to each end of its scales (Spec.scales: a tiny body, a huge one,
    far away), expected from the reference: valid inputs where a threshold or a clamp shows."""
    if not spec.scales or spec.reference is None or not cases:
        return cases
    base = cases[0]
    extra = []
    for _, alter in spec.scales:
        args = alter(copy.deepcopy(base.args))
        want = spec.reference(*copy.deepcopy(args))
        want = tuple(np.asarray(w, float) for w in want) if isinstance(want, tuple) else np.asarray(want, float)
        extra.append(Case(args, base.names, want, kwargs=base.kwargs))
    return list(cases) + extra


def run(spec: Spec, fn, make_cases, verbose: bool, seed, accept=None, last_resort=None) -> CheckResult:
    """judge() on make_cases(rng) with the check's seed; a bug in the check is a result too; printed if verbose.
    (seed and verbose are the check's own arguments: a wrong one is an error naming it, not a verdict.)"""
    spec.seed, verbose = check_options(seed, verbose)
    try:
        result = judge(spec, fn, at_the_ends(spec, make_cases(np.random.default_rng(seed))), accept, last_resort)
    except Exception as e:      # noqa: BLE001 — a bug in the check must not stop the notebook
        result = CheckResult(spec.name, False, "check_failed", tr("check_failed").format(name=spec.name,
                                                                                           exc=exc_text(e)))
    return result.printed(verbose)
