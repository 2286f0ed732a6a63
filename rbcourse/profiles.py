"""Forces over time as data: rb.PointForce(..., force=rb.Pulse((0, 0, 10), 0.0, 0.1)).

A force given as a Python function f(t) is called by the driver at every stage time of every step (a Python
call each: ~4 µs per stage).  The common time profiles are small immutable objects the kernel evaluates
itself (engine/profiles.py: profile_value, compiled with the step), at the same stage times:

    Constant(f)                    F = f
    Pulse(f, t_start, t_stop)      F = f on t_start <= t < t_stop, 0 outside
    Ramp(f, t_start, t_stop)       F = 0 before t_start, f (t − t_start)/(t_stop − t_start) on [t_start, t_stop),
                                   f after
    Sine(amplitude, frequency, phase=0, offset=0)    F = offset + amplitude sin(2π frequency t + phase)
    Steps(times, forces)           F = forces[j] on times[j] <= t < times[j+1] (the last after times[-1],
                                   0 before times[0])

Each is also a function of t (profile(t) -> (3,) array, the same compiled formula run as Python), so it
works wherever f(t) does (the adaptive method, which picks its own stage times, calls it so).

Every profile's force is finite at every time it is asked for, or refused: its parameters are finite numbers
(not booleans: the rule of every number of the package, support/checks.py), a Sine's |offset| + |amplitude| is
finite in each component, its 2π frequency finite, and its phase 2π frequency t + phase at the time asked
(profile(t), or a run's t_end: Scene.check_start calls check_time).  A Ramp is exact over any span, even one
whose duration t_stop − t_start overflows (from −1e308 to 1e308: engine/profiles.py divides the halves then).
Every time a profile's method is given (profile(t), acts_after(t0), Pulse.on(t), check_time) is a finite real
number, or a ValueError names it.
"""
from __future__ import annotations

import math
import sys

import numpy as np

from .support import checks
from .engine import system as kernel_profiles      # the kinds (numpy only: numba loads at the first run)
from .engine.system import TimeRow
from .support.language import say

LARGEST = sys.float_info.max        # 1.8e308
MAX_FREQUENCY = 1e307               # 2π frequency stays finite (2π × 2.9e307 = 1.8e308)
PHASE_MAX = checks.ANGLE_MAX         # 2³² = 4.29e9 rad: float64 resolves a phase up to it to 1e-6 rad or better


def _formula():
    """The kernel's profile_value: compiled when this process has loaded the compiled kernel already (a run
    did), else run as Python (engine/interpreted.py; numba is not loaded for it) — one formula, either way."""
    jit, compiled = sys.modules.get("rbcourse.engine.jit"), sys.modules.get("rbcourse.engine.profiles")
    if compiled is not None and getattr(jit, "COMPILED", False):
        return compiled.profile_value
    from .engine import interpreted
    return interpreted.module("profiles").profile_value


class Profile:
    """A force over time given as data (see the module docstring).  Immutable: its arrays are read-only."""

    kind: int = -1

    def __init__(self, params, table=()):
        row = np.zeros(kernel_profiles.PROFILE_COLUMNS)
        row[1] = self.kind
        params = (0, len(table)) if len(table) else params     # a step table: its rows (the System's hold where)
        row[2:2 + len(params)] = params
        object.__setattr__(self, "_row", checks.frozen(row))
        object.__setattr__(self, "_table", checks.frozen(np.asarray(table, dtype=float).reshape(-1, 4)))

    def __setattr__(self, name, value):
        raise AttributeError(f"{type(self).__name__} is immutable: build a new one instead of setting {name!r}")

    def __call__(self, t) -> np.ndarray:
        """F(t), a (3,) array (the kernel's formula, run as Python); t a finite real number (check_time)."""
        t = self.check_time("t", t)
        return np.array(_formula()(self._row, self._table, t), dtype=float)

    def check_time(self, name: str, t) -> float:
        """t, a finite real number at which the force is finite (every t, but for a Sine: its phase), or a
        ValueError naming it.  A run checks its t_end so (Scene.check_start): its stage times lie in [0, t_end]."""
        return checks.real(name, t)

    def acts_after(self, t0) -> bool:
        """Is F(t) nonzero at some t >= t₀ (a finite real number)?  Exact, from the profile's data (no sampling)."""
        return self._acts_after(checks.real("t0", t0))

    def _acts_after(self, t0: float) -> bool:
        raise NotImplementedError

    def time_row(self, slot: int) -> TimeRow:
        """Its row in the kernel's System (engine/system.py: TimeRow), its force in values[:, :, slot] (an index
        >= 0)."""
        slot = checks.integer("slot", slot, low=0)
        table = tuple(tuple(r) for r in self._table.tolist())
        return TimeRow(slot, self.kind, tuple(self._row[2:].tolist()), table)


def _times(name, t0, t1):
    t0, t1 = checks.real(f"{name} t_start", t0), checks.real(f"{name} t_stop", t1)
    if not t1 >= t0:
        raise ValueError(f"{name} t_stop must be >= t_start = {t0:g}, got {t1:g}")
    return t0, t1


class Constant(Profile):
    """F = force, at every t (the same as giving the 3-vector itself)."""
    kind = kernel_profiles.CONSTANT

    def __init__(self, force):
        f = checks.vector3("force", force)
        super().__init__(tuple(f))
        object.__setattr__(self, "force", checks.frozen(f))

    def _acts_after(self, t0: float) -> bool:
        return bool(np.any(self.force != 0))

    def __repr__(self) -> str:
        return f"Constant({self.force.tolist()} N)"


class _Interval(Profile):
    """A force over an interval [t_start, t_stop) (Pulse, Ramp): its force, t_start and t_stop."""

    def __init__(self, force, t_start: float, t_stop: float):
        f = checks.vector3("force", force)
        t0, t1 = _times(type(self).__name__, t_start, t_stop)
        super().__init__((*f, t0, t1))
        for name, v in (("force", checks.frozen(f)), ("t_start", t0), ("t_stop", t1)):
            object.__setattr__(self, name, v)


class Pulse(_Interval):
    """F = force for t_start <= t < t_stop, 0 outside (a push)."""
    kind = kernel_profiles.PULSE

    def on(self, t) -> bool:
        """Whether the force acts at time t (a finite real number): t_start <= t < t_stop."""
        t = checks.real("t", t)
        return self.t_start <= t < self.t_stop

    def _acts_after(self, t0: float) -> bool:
        """[max(t₀, t_start), t_stop) is not empty, and the force is not zero."""
        return bool(np.any(self.force != 0)) and self.t_stop > max(t0, self.t_start)

    def __repr__(self) -> str:
        return say(f"Pulse({self.force.tolist()} N for {self.t_start:g} <= t < {self.t_stop:g} s)",
                   f"Pulse({self.force.tolist()} N pendant {self.t_start:g} <= t < {self.t_stop:g} s)")


class Ramp(_Interval):
    """F = 0 before t_start, rising linearly to `force` at t_stop, then `force`:  F = force (t − t_start) /
    (t_stop − t_start) on [t_start, t_stop), for any finite times (over (−1e308, 1e308), whose duration overflows,
    F(0) = force / 2: engine/profiles.py)."""
    kind = kernel_profiles.RAMP

    def _acts_after(self, t0: float) -> bool:
        """F = force for every t >= t_stop, so from any t₀ on: whether the force is not zero."""
        return bool(np.any(self.force != 0))

    def __repr__(self) -> str:
        return say(f"Ramp(0 → {self.force.tolist()} N over {self.t_start:g} <= t < {self.t_stop:g} s)",
                   f"Ramp(0 → {self.force.tolist()} N sur {self.t_start:g} <= t < {self.t_stop:g} s)")


class Sine(Profile):
    """F = offset + amplitude sin(2π frequency t + phase)  (frequency in Hz, phase in rad, |phase| <= PHASE_MAX)."""
    kind = kernel_profiles.SINE

    def __init__(self, amplitude, frequency: float, phase: float = 0.0, offset=(0.0, 0.0, 0.0)):
        a, c = checks.vector3("amplitude", amplitude), checks.vector3("offset", offset)
        with np.errstate(over="ignore"):                  # an overflow to inf is the answer looked for
            bound = np.abs(a) + np.abs(c)
        if not np.all(np.isfinite(bound)):
            raise ValueError(f"Sine offset and amplitude must keep |offset| + |amplitude| <= {LARGEST:.4g} in each "
                             f"component (F finite), got offset = {c.tolist()}, amplitude = {a.tolist()}")
        nu = checks.real("frequency", frequency, low=0.0, high=MAX_FREQUENCY)
        phi = checks.real("phase", phase)
        if not abs(phi) <= PHASE_MAX:           # beyond it, 2π frequency t + phase no longer resolves t (nor the sine)
            raise ValueError(f"phase must be within ±{PHASE_MAX:.4g} rad (2³², where float64 still resolves the phase "
                             f"to 1e-6 rad; reduce it modulo 2π), got {phi!r}")
        super().__init__((*a, nu, phi, *c))
        for name, v in (("amplitude", checks.frozen(a)), ("frequency", nu), ("phase", phi), ("offset", checks.frozen(c))):
            object.__setattr__(self, name, v)

    def check_time(self, name: str, t) -> float:
        """t, if the phase 2π frequency t + phase is finite there (sin(inf) would be NaN)."""
        t = checks.real(name, t)
        if not math.isfinite(2.0 * math.pi * self.frequency * t + self.phase):     # the kernel's formula's order
            most = (LARGEST - abs(self.phase)) / (2.0 * math.pi * self.frequency)
            raise ValueError(f"{name} must keep the Sine's phase 2π frequency t + phase finite: |{name}| <= "
                             f"{most:.3g} s at frequency = {self.frequency:g} Hz, got {t!r}")
        return t

    def _acts_after(self, t0: float) -> bool:
        """At frequency 0, F is the constant offset + amplitude sin(phase); otherwise F is zero on no interval
        unless offset and amplitude are both zero."""
        if self.frequency == 0:
            return bool(np.any(self.offset + self.amplitude * np.sin(self.phase) != 0))
        return bool(np.any(self.amplitude != 0) or np.any(self.offset != 0))

    def __repr__(self) -> str:
        return (f"Sine({self.offset.tolist()} + {self.amplitude.tolist()} sin(2π {self.frequency:g} t + "
                f"{self.phase:g}) N)")


class Steps(Profile):
    """F = forces[j] for times[j] <= t < times[j+1]; forces[-1] after times[-1]; 0 before times[0]
    (a piecewise-constant table: times strictly increasing)."""
    kind = kernel_profiles.STEPS

    def __init__(self, times, forces):
        t = checks.finite("times", checks.numbers("times", times, "a non-empty 1-D sequence of real numbers"))
        if t.ndim != 1 or len(t) == 0:
            raise ValueError(f"times must be a non-empty 1-D sequence of real numbers, got shape {t.shape}")
        if len(t) > 1 and not np.all(np.diff(t) > 0):
            raise ValueError(f"times must be strictly increasing, got {t.tolist()}")
        f = checks.finite("forces", checks.numbers("forces", forces, "one 3-vector of real numbers per time"))
        if f.shape != (len(t), 3):
            raise ValueError(f"forces must hold one 3-vector per time: shape ({len(t)}, 3), got {f.shape}")
        super().__init__((), np.concatenate([t[:, None], f], axis=1))
        object.__setattr__(self, "times", checks.frozen(t))
        object.__setattr__(self, "forces", checks.frozen(f))

    def _acts_after(self, t0: float) -> bool:
        """One of the steps that hold on [t₀, ∞) (the one in force at t₀, or the first, and those after) is not
        zero."""
        first = max(int(np.searchsorted(self.times, t0, side="right")) - 1, 0)
        return bool(np.any(self.forces[first:] != 0))

    def __repr__(self) -> str:
        return say(f"Steps({len(self.times)} steps from t = {self.times[0]:g} s)",
                   f"Steps({len(self.times)} paliers à partir de t = {self.times[0]:g} s)")

