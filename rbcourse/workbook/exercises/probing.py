"""Diagnosis by probing: where no known mistake matches, the student's function is run on inputs of growing
generality, and the first feature that breaks it is named, then the kind of difference it makes there.

    ladder = (Rung("R_rotated", make), …)     simplest input first; each rung adds one feature to the ones before
    probe(fn, ladder, reference, read)        -> the first rung where fn's result differs from the reference (or
                                                 it raises), with that input and what fn gave: a Found, or None
    kind_of(found, label, …)                  -> what the difference is, in words: a sign, a constant factor (only
                                                 when it is the same on every probe), a transpose, an order swap,
                                                 Δt missing or twice, degrees for radians, float32 rounding, the
                                                 input returned unchanged, which components, …

The first line of a check's message then says both:  « ✗ resultants : τ est faux dès que la force n'est pas au
barycentre — son signe est inversé (sur l'entrée …) ».  The ladders of the checks are in ladders.py.
"""
from __future__ import annotations

import copy
import itertools
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .harness import BadOutput, close, fmt, quiet
from .texts import tr

DRAWS = 3           # inputs tried per rung


@dataclass(frozen=True)
class Rung:
    """One step of a ladder: the feature it adds (an id in TEXTS, "feature_<id>"), make(rng) -> the arguments, and
    alts: (id in TEXTS, alter(args) -> args) — the input as a function that misses this feature reads it (M taken as
    1, only the first force, R as the rotation nearest it, …): a result that is the reference's on the altered input
    is named by that id."""
    feature: str
    make: Callable
    alts: tuple = ()


@dataclass
class Found:
    """The first rung that breaks the function: the rung, its input, the expected result, what fn gave (an
    array or a tuple of them; None when it raised: exc), and the results of the other failing probes (got, want,
    args) from that rung on, to tell a constant factor from one that changes."""
    rung: Rung
    args: tuple
    expected: object
    got: object = None
    exc: BaseException | None = None
    others: list | None = None


def _outcome(fn, args, reference, read):
    """(expected, got, exc): fn's result on args read as the check reads it (read: raw -> arrays, or BadOutput)."""
    expected = reference(*copy.deepcopy(args))
    try:
        got = read(quiet(fn, copy.deepcopy(args)))
    except BadOutput:
        return expected, None, None
    except (Exception, SystemExit) as e:        # noqa: BLE001 — a probe: the exception is what it found
        return expected, None, e
    return expected, got, None


def misread(found: Found, reference) -> str | None:
    """The id of the first alt of the found rung whose altered input the reference turns into fn's result (the
    function read the input that way), on every failing probe of that rung; else None."""
    for key, alter in found.rung.alts:
        try:
            if close(found.got, reference(*alter(copy.deepcopy(found.args)))) and all(
                    close(g, reference(*alter(copy.deepcopy(a)))) for g, _, a in found.others[: DRAWS - 1]):
                return key
        except (Exception, SystemExit):      # noqa: BLE001 — an alteration that does not apply
            continue
    return None


def probe(fn, ladder, reference, read, seed: int) -> Found | None:
    """Climb the ladder (DRAWS inputs a rung, drawn from the check's seed: a grading's secret seed draws others): the
    first input whose result is not the reference's, or raises, is the Found; the failing probes of its rung and of
    the rungs above are gathered with it (others).  None when fn is right on every rung, or gives what cannot be read
    (the check says that itself)."""
    rng = np.random.default_rng([seed, 45])
    found = None
    for rung in ladder:
        for _ in range(DRAWS):
            args = rung.make(rng)
            expected, got, exc = _outcome(fn, args, reference, read)
            if found is None:
                if exc is not None:
                    return Found(rung, args, expected, exc=exc)
                if got is not None and not close(got, expected):
                    found = Found(rung, args, expected, got, others=[])
            elif got is not None and not close(got, expected):
                found.others.append((got, expected, args))
    return found


# =====================================================================================
# The kind of difference, told from the numbers
# =====================================================================================

DEGREES = 180.0 / np.pi


def _factor(got, want) -> float | None:
    """c when got = c · want (c ≠ 0, to 1e-9 relative), else None."""
    if got.shape != want.shape or not np.all(np.isfinite(got)):
        return None
    ww = float(np.sum(want * want))
    if ww == 0.0:
        return None
    c = float(np.sum(got * want)) / ww
    return c if abs(c) > 1e-12 and close(got, c * want) else None


def constant_factor(pairs) -> float | None:
    """The factor c with got = c · want on every (got, want) pair, the same on all of them (1e-6), or None."""
    cs = [_factor(g, w) for g, w in pairs]
    if not cs or any(c is None for c in cs):
        return None
    return cs[0] if all(abs(c - cs[0]) <= 1e-6 * abs(cs[0]) for c in cs) else None


def factor_text(c: float) -> str:
    """A constant factor in words: the sign, twice, half, degrees for radians, or 'c × the right value'."""
    for value, key in ((-1.0, "kind_sign"), (2.0, "kind_twice"), (0.5, "kind_half"), (-2.0, "kind_minus_twice"),
                       (-0.5, "kind_minus_half"), (DEGREES, "kind_degrees"), (1 / DEGREES, "kind_radians")):
        if abs(c - value) <= 1e-6 * abs(value):
            return tr(key)
    return tr("kind_factor").format(c=f"{c:.6g}")


def _permutation(got, want) -> str | None:
    """'y, z, x' when got holds want's components in another order (a vector), or its rows or columns (a matrix)."""
    if got.shape != want.shape or got.ndim not in (1, 2) or got.shape[0] != 3:
        return None
    axes = "xyz"
    for perm in itertools.permutations(range(3)):
        if perm == (0, 1, 2):
            continue
        names = ", ".join(axes[i] for i in perm)
        if close(got, want[list(perm)]):
            return tr("kind_order" if got.ndim == 1 else "kind_rows").format(order=names)
        if got.ndim == 2 and close(got, want[:, list(perm)]):
            return tr("kind_columns").format(order=names)
    return None


def _components(got, want) -> str | None:
    """Which entries differ, when only some do: 'only its z component', 'only its off-diagonal entries', …"""
    bad = ~np.isclose(got, want, rtol=1e-7, atol=1e-9 * max(1.0, float(np.abs(want).max())))
    if got.shape != want.shape or bad.all() or not bad.any():
        return None
    if got.ndim == 1 and got.size == 3:
        names = [c for c, b in zip("xyz", bad) if b]
        return tr("kind_component" if len(names) == 1 else "kind_components").format(names=", ".join(names))
    if got.shape == (3, 3):
        rows, cols = np.nonzero(bad.any(1))[0], np.nonzero(bad.any(0))[0]
        if len(rows) == 1:
            return tr("kind_row").format(i=int(rows[0]) + 1)
        if len(cols) == 1:
            return tr("kind_column").format(j=int(cols[0]) + 1)
        diagonal = np.eye(3, dtype=bool)
        if np.any(want[~diagonal]) and np.any(want[diagonal]):     # (of a diagonal matrix, it tells nothing)
            if bad[diagonal].all() and not bad[~diagonal].any():
                return tr("kind_diagonal")
            if bad[~diagonal].any() and not bad[diagonal].any():
                return tr("kind_off_diagonal")
        if bad.sum() <= 3:
            return tr("kind_entries").format(entries=", ".join(f"({i + 1}, {j + 1})" for i, j in zip(*np.nonzero(bad))))
    return None


def _digits(got, want) -> int:
    """How many significant digits got and want share (the largest relative difference)."""
    scale = max(1e-300, float(np.abs(want).max()))
    rel = float(np.abs(got - want).max()) / scale
    return max(0, int(np.floor(-np.log10(rel)))) if rel > 0 else 16


def scalar_factor(factors, scalars) -> str | None:
    """'12/M' when the factors of the probes are c/v (or c·v) for one scalar input v (M, dt, …): a factor v too many
    or missing.  factors: got/want of each probe; scalars: [(name, value), …] of each probe."""
    if len(factors) < 2 or any(f is None for f in factors) or not scalars or not scalars[0]:
        return None
    for k, (name, _) in enumerate(scalars[0]):
        values = [float(row[k][1]) for row in scalars]
        if len(set(values)) < 2 or any(v == 0 for v in values):
            continue
        for text, combine in (("{c}/{name}", lambda f, v: f * v), ("{c}·{name}", lambda f, v: f / v)):
            cs = [combine(f, v) for f, v in zip(factors, values)]
            if all(abs(c - cs[0]) <= 1e-6 * abs(cs[0]) for c in cs):
                return text.format(c=f"{cs[0]:.6g}", name=name)
    return None


def _approximate_factor(got, want) -> str | None:
    """The degrees-for-radians factors (57.3, 1/57.3) to 2 %, as after a rotation made with the wrong unit."""
    for value, key in ((DEGREES, "kind_degrees"), (1 / DEGREES, "kind_radians")):
        if np.allclose(got, value * want, rtol=0.02, atol=0.02 * value * float(np.abs(want).max())):
            return tr(key)
    return None


WEAK = "weak"
"""array_kind's mark of a kind that says little (which entries differ, the digits, the numbers): an input the
function ignores, if there is one, says more."""


def array_kind(got, want, pairs, inputs, scalars=None) -> tuple:
    """(text, strength) of the difference between one wrong part got and the expected want, in words; strength is
    WEAK for a kind that says little.  pairs: (got, want) of the same part on the other failing probes (a factor is
    constant only if it is on all of them); inputs: (name, value) of the arguments, to tell an input returned
    unchanged; scalars: the scalar inputs of each probe (the found one first), to tell a factor 12/M."""
    strong = _strong_kind(got, want, pairs, inputs, scalars or [])
    if strong:
        return strong, ""
    digits = _digits(got, want)
    if digits >= 3:
        return tr("kind_digits").format(digits=digits), WEAK
    which = _components(got, want)
    return which or tr("kind_other").format(want=fmt(want), got=fmt(got)), WEAK


def _strong_kind(got, want, pairs, inputs, scalars) -> str | None:
    """The kinds of difference that name the mistake (array_kind), or None."""
    if got.shape != want.shape:
        return tr("shape").format(got=got.shape, want=want.shape)
    if not np.all(np.isfinite(got)):
        return tr("kind_nan")
    for name, value in inputs:
        if np.shape(value) == got.shape and np.any(value) and np.array_equal(got, np.asarray(value, float)):
            return tr("kind_input").format(name=name)
    if not np.any(got) and np.any(want):
        return tr("kind_zero")
    if pairs and all(np.array_equal(g, got) for g, _ in pairs) and any(not close(w, want) for _, w in pairs):
        return tr("kind_constant")
    if got.ndim == 1 and abs(np.linalg.norm(got) - 1.0) < 1e-9 and abs(np.linalg.norm(want) - 1.0) > 1e-6:
        return tr("kind_unit")
    if any(np.array_equal(got, f(want)) for f in (np.trunc, np.floor, np.round)) and not np.array_equal(got, want):
        return tr("kind_whole")
    c = constant_factor([(got, want)] + pairs)
    if c is not None:
        return factor_text(c)
    if _factor(got, want) is not None:
        by_input = scalar_factor([_factor(g, w) for g, w in [(got, want)] + pairs], scalars)
        if by_input:
            return tr("kind_factor_of").format(factor=by_input)
        return tr("kind_varying").format(c=f"{_factor(got, want):.4g}")
    if got.ndim == 2 and got.shape[0] == got.shape[1] and close(got, want.T):
        return tr("kind_transposed")
    order = _permutation(got, want)
    if order:
        return order
    if got.size > 1 and close(np.abs(got), np.abs(want)):
        signs = _components(got, want)
        return tr("kind_signs") + (f" ({signs})" if signs else "")
    return _approximate_factor(got, want)


def increment_kind(probes) -> str | None:
    """A next state's part from its start X(t): its increment got − start against the right one want − start —
    not updated, Δt missing (the rate itself), Δt twice (Δt² · rate), or the same factor on the increment.
    probes: (got, want, start, dt) of every failing probe, the found one first.  None: none of these."""
    steps = [(g - s, w - s, dt) for g, w, s, dt in probes
             if np.abs(w - s).max(initial=0.0) > 1e-4 * np.abs(s).max(initial=0.0)]   # (far away, a step is lost)
    if not steps:
        return None
    step, right, _ = steps[0]
    if not np.any(right):
        return None
    if not np.any(step):
        return tr("kind_not_updated")
    for key, scale in (("kind_no_dt", lambda dt: 1 / dt), ("kind_dt_twice", lambda dt: dt)):
        if all(close(g, scale(dt) * w) for g, w, dt in steps if np.any(w)):
            return tr(key)
    c = constant_factor([(g, w) for g, w, _ in steps if np.any(w)])
    if c is not None:
        return tr("kind_increment").format(text=factor_text(c))
    about = _approximate_factor(step, right)
    return tr("kind_increment").format(text=about) if about else None


def _swapped_in(args, names, other, j):
    """args with the input j taken from `other` (a part of X, 'X.0' … 'X.3', when j is such a name)."""
    if isinstance(j, int):
        return args[:j] + (copy.deepcopy(other[j]),) + args[j + 1:]
    k, part = names.index("X"), int(j[2])
    X = list(args[k])
    X[part] = copy.deepcopy(list(other[k])[part])
    return args[:k] + (type(args[k])(X) if isinstance(args[k], list) else tuple(X),) + args[k + 1:]


def ignores(fn, found: Found, reference, names, read) -> str | None:
    """The name of an input fn ignores: given another value of it alone (from another failing probe), fn returns the
    same result while the reference's changes — a global of the notebook used instead of the argument.  None."""
    if found.got is None or not found.others or not any(np.any(g) for g in
                                                        (found.got if isinstance(found.got, tuple) else (found.got,))):
        return None
    others = [a for _, _, a in found.others if len(a) == len(found.args)][:6]
    inputs = [(j, n) for j, n in enumerate(names) if n != "X"] + (
        [(f"X.{p}", n) for p, n in enumerate("xRPL")] if "X" in names else [])
    for j, name in inputs:
        for other in others:
            try:
                args = _swapped_in(found.args, names, other, j)
                want = reference(*copy.deepcopy(args))
                if close(want, found.expected):
                    continue
                got = read(quiet(fn, copy.deepcopy(args)))
            except (Exception, SystemExit):      # noqa: BLE001 — a probe
                break
            if close(got, found.got):
                return name
            break
    return None
