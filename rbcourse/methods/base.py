"""What every integrator is, as data: its name and properties (order, what it keeps exactly, cost,
reference), the options it takes, and how the kernel steps it (engine/plan.py: Stepping).

The steps themselves are the kernel's (rbcourse/engine: euler.py, steps.py and the family files), written
once, compiled by numba or run as Python: a Method's row says which, and the driver runs it.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

from ..engine.plan import Stepping
from ..support.language import say


@dataclass(frozen=True)
class Method:
    """An integrator: its name and its own properties.

    order: the global order of accuracy (error ~ dt^order).
    keeps: what it conserves exactly (to rounding) for a free body, among
           "SO(3)" (R stays a rotation), "L" (world angular momentum), "|L|", "energy".
    cost: work per step (force evaluations, solves).  reference: where it comes from.  summary: what it is, in
           one line, in the active language (said: the line in English and in French).
    step: where its step is written (the kernel's function, by name); kernel: what the kernel needs to step it.
    uses_exact_flow: it steps with the exact torque-free flow (so a free body's step is exact at any size).
    options, settings: the options it takes and their values; check_options(options) -> options
        checks the values given to configured (e.g. adaptive: rtol and atol within their ranges).
    (What it promises on the named hard cases is the bench's: rbcourse.bench.claims.)
    """
    name: str
    step: str
    order: int
    keeps: frozenset
    cost: str
    reference: str
    said: tuple                         # (English, French): its summary, in each language
    uses_exact_flow: bool = False
    options: tuple = ()                 # names of the options it accepts (e.g. rtol, atol)
    settings: dict = field(default_factory=dict, repr=False)
    check_options: Callable | None = field(default=None, repr=False)   # options dict -> checked (ValueError)
    kernel: Stepping | None = field(default=None, repr=False)         # how the kernel steps it (engine/plan.py)

    @property
    def summary(self) -> str:
        """What it is, in one line, in the active language."""
        return say(*self.said)

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
