"""The diagnoses by probing, as verdicts (probing.py finds, this says): the first feature of the check's ladder that
breaks the student's function and the kind of difference there, the input that makes it raise, and a function that
answers from an earlier call (state kept between calls)."""
from __future__ import annotations

import copy

import numpy as np

from .harness import close, fmt, quiet, same
from .probing import array_kind, constant_factor, ignores, increment_kind, misread, probe
from .result import CheckResult
from .spec import Case, Spec, crashed, fail, parts, read
from .texts import tr


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
    if answers_again(spec, fn, found.args, found.got):
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


def answers_again(spec: Spec, fn, args, got, kwargs=None) -> bool:
    """Does fn, called again on a fresh copy of args (the first copy still alive: no id() of it can come back),
    give another answer than `got`?  Then it answers from an earlier call (a cache keyed by id(), a total kept
    between calls): which input it fails, and how, is chance — no other diagnosis holds.  A crash now: no."""
    try:
        again = read(spec, quiet(fn, copy.deepcopy(args), kwargs))
    except (Exception, SystemExit):      # noqa: BLE001 — a probe: a crash is judged where it happens
        return False
    return not (same(again, got) or close(again, got))


def _formula(spec: Spec, found, got) -> str | None:
    """The first of the check's other formulas (Spec.formulas) that gives fn's result on the found input and on the
    other failing probes (I⁻¹_body · I⁻¹_body and I⁻¹_body · R · I⁻¹_body agree while R = I), else None."""
    probes = [(got, found.args)] + [(g, a) for g, _, a in found.others]
    for text, value in spec.formulas(*found.args):
        if close(got, value) and all(close(g, dict(spec.formulas(*a)).get(text)) for g, a in probes[1:]):
            return text
    return None

def _refill(old, new):
    """old's arrays (in tuples and lists too) given new's values in place, the same objects; new's other values."""
    if (isinstance(old, np.ndarray) and isinstance(new, np.ndarray) and old.shape == new.shape
            and old.dtype == new.dtype):
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
        quiet(fn, args, A.kwargs)
        same_objects = _scalars_from(A.args, tuple(_refill(a, b) for a, b in zip(args, B.args)))
        tries = [(same_objects, None, "stale_in_place"),
                 (_scalars_from(A.args, copy.deepcopy(B.args)), None, "stale_numbers"),
                 (copy.deepcopy(B.args), B.expected, "stale_twice")]
        for given, want, key in tries:
            want = want if want is not None else spec.reference(*copy.deepcopy(given))
            want = tuple(np.asarray(w, float) for w in want) if isinstance(want, tuple) else np.asarray(want, float)
            got = read(spec, quiet(fn, given, B.kwargs))
            if not close(got, want):
                return fail(spec, "stateful", tr(key))
        for name, given in _one_changed(A, B):     # a cache keyed on some of the inputs only
            quiet(fn, copy.deepcopy(A.args), A.kwargs)
            want = spec.reference(*copy.deepcopy(given))
            want = tuple(np.asarray(w, float) for w in want) if isinstance(want, tuple) else np.asarray(want, float)
            if not close(read(spec, quiet(fn, given, A.kwargs)), want):
                return fail(spec, "stateful", tr("stale_one_input").format(name=name))
    except (Exception, SystemExit):      # noqa: BLE001 — a probe: the cases above judged what fn raises
        return None
    return None


def _one_changed(A: Case, B: Case):
    """(name, A's arguments with that one input from B): each argument, and each part of a state X, in turn."""
    for j, name in enumerate(A.names):
        if name == "X":
            for p, part in enumerate("xRPL"):
                X = list(copy.deepcopy(A.args[j]))
                X[p] = copy.deepcopy(list(B.args[j])[p])
                yield part, A.args[:j] + (tuple(X),) + A.args[j + 1:]
        else:
            yield name, copy.deepcopy(A.args[:j] + (B.args[j],) + A.args[j + 1:])

def probed_instead(spec: Spec, fn, case: Case, result: CheckResult) -> CheckResult:
    """A "wrong result" named by probing where it can be; a "scaled" kept only when probing finds the same factor
    on every input (a factor that changes with the input is no constant factor)."""
    return probed(spec, fn, case.names, result if result.mistake == "scaled" else None) or result
