"""What every integrator is: a step function plus what it promises, in the METHODS registry.

A method steps a state of N bodies:  step(scene, t, Y, h) -> Y(t + h).
Y is the method's own representation of the state: the slides' State (x, R, P, L)
for matrix methods, or a flat array [x, q, P, L] (N, 13) for quaternion methods;
`encode` / `decode` convert from / to State (identity for State methods).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable


def _same(scene, X):
    return X


@dataclass(frozen=True)
class Method:
    """An integrator: its step function and what it promises.

    order: the global order of accuracy (error ~ dt^order).
    keeps: what it conserves exactly (to rounding) for a free body, among
           "SO(3)" (R stays a rotation), "L" (world angular momentum), "|L|", "energy".
    stable: what it promises on the hard cases, in words.
    claims: the same promises, checkable (stability.broken_claims; tests/test_stability.py asserts them on every hard case):
        finite: bool — finishes every case;  diverges_on: cases where it must blow up (clear error);
        so3: max ‖RᵀR − I‖ on every finished run;  free_L, free_norm_L, free_energy: relative
        tolerances on world L, |L| and the energy of a free body (these four are "kept to rounding":
        tolerances for 10⁴ steps, growing in proportion beyond, as rounding adds up — stability.py);  energy_bounded: over the long free
        runs the energy error does not drift (last half <= 3 × first half, or below 1e-10);  dissipative: a free
        body's energy never increases.
    cost: work per step (force evaluations, solves).
    options, settings: the options step takes and their values; check_options(options) -> options
        checks the values given to configured (e.g. adaptive: rtol and atol within their ranges).
    """
    name: str
    step: Callable = field(repr=False)
    order: int
    keeps: frozenset
    cost: str
    reference: str
    summary: str
    stable: str = ""
    claims: dict = field(default_factory=dict, repr=False)
    uses_exact_flow: bool = False
    encode: Callable = field(default=_same, repr=False)
    decode: Callable = field(default=_same, repr=False)
    options: tuple = ()                 # names of the options step accepts (e.g. rtol, atol)
    settings: dict = field(default_factory=dict, repr=False)
    check_options: Callable | None = field(default=None, repr=False)   # options dict -> checked (ValueError)

    def __call__(self, scene, t, Y, dt):
        return self.step(scene, t, Y, dt, **self.settings)

    def configured(self, **options) -> "Method":
        """This method with options set (e.g. adaptive: rtol, atol); unknown options are an error."""
        options = {k: v for k, v in options.items() if v is not None}
        unknown = set(options) - set(self.options)
        if unknown:
            allowed = f"takes {', '.join(self.options)}" if self.options else "takes no options"
            raise ValueError(f"method {self.name!r} {allowed}; got {', '.join(sorted(unknown))}")
        if options and self.check_options is not None:
            options = self.check_options(options)
        return replace(self, settings={**self.settings, **options}) if options else self


METHODS: dict[str, Method] = {}


def register(method: Method) -> Method:
    """Add a method to METHODS (name -> Method)."""
    METHODS[method.name] = method
    return method


def get_method(method) -> Method:
    """A Method from its name (or a Method itself)."""
    if isinstance(method, Method):
        return method
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"method must be one of {sorted(METHODS)}, got {method!r}")
    return METHODS[method]
