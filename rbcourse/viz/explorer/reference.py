"""The reference motion every run of the grid is measured against, at the run's own step times.

* A scene with no effect at all (free bodies): the exact torque-free motion, rb.exact_free_body (the
  closed form: Jacobi's elliptic functions), body by body — no step, rounding only.
* Any other scene: rk4 with steps REFINE times finer than the finest step of the grid.  A run of step
  h = t_end / n is compared with rk4 of step h / m (m = ⌈h / h*⌉, h* = h_min / REFINE) recorded every
  m steps, so at exactly the run's times; its own accuracy is measured as the rotation angle at t_end
  between rk4 at h* and rk4 at 2 h* (for an order-4 method that is about 15 times its own error).
"""
from __future__ import annotations

import math

import numpy as np

from ...rotation import rotation_angle
from ...simulate import simulate
from ...trajectory import SimulationDiverged, Trajectory
from .text import page_text

REFINE = 8                  # the fine reference's step: the grid's finest step / REFINE
REFERENCE_METHOD = "rk4"
CHUNK = 1 << 16             # times evaluated at once by the exact reference


class ExactReference:
    """The exact torque-free motion of each body of a scene with no effect."""
    exact = True

    def __init__(self, scene, X0):
        self.scene, self.X0 = scene, X0
        self.label = page_text("exact_label")
        self.detail = page_text("exact_detail")
        self.accuracy = None

    def at(self, t: np.ndarray) -> Trajectory:
        """The exact motion at the times t (n,): a Trajectory of the scene."""
        from ...exact import exact_free_body
        parts = [[] for _ in range(4)]
        for s in range(0, len(t), CHUNK):
            tt = t[s:s + CHUNK]
            bodies = [exact_free_body(b, self.X0.body(i), tt) for i, b in enumerate(self.scene.bodies)]
            for j, key in enumerate("xRPL"):
                a = [getattr(tr, key) for tr in bodies]
                parts[j].append(a[0] if self.scene.single else np.stack(a, axis=1))
        x, R, P, L = (np.concatenate(p) for p in parts)
        return Trajectory(t, x, R, P, L, scene=self.scene, method="exact")

    def for_run(self, h: float, n: int) -> Trajectory:
        """At the times k h, k = 0 … n (a run's steps)."""
        return self.at(np.arange(n + 1) * h)


class FineReference:
    """rk4 with steps REFINE times finer than the finest step of the grid (module docstring)."""
    exact = False

    def __init__(self, scene, X0, t_end: float, steps_max: int):
        self.scene, self.X0, self.t_end = scene, X0, t_end
        self.fine_steps = steps_max * REFINE                 # rk4's step h* = h_min / REFINE = t_end / fine_steps
        self.h_star = t_end / self.fine_steps
        self._cache = (None, None)
        self._fine = (1, None)               # (g, the run at h* recorded every g steps), after prepare()
        self.label = page_text("fine_label", method=REFERENCE_METHOD, h=self.h_star)
        self.accuracy = None
        self.detail = ""

    def prepare(self, steps) -> None:
        """Run rk4 at h* once for every step count n of the grid that divides fine_steps (then m n = fine_steps:
        the same run for each), recorded every g steps, g the greatest common divisor of their m; for_run then
        reads each such n's reference off it (the same states, not a run per step) — when that recording holds
        at most twice the states of the grid's finest run."""
        ms = [self.fine_steps // n for n in steps if self.fine_steps % n == 0]
        if len(ms) > 1 and self.fine_steps // math.gcd(*ms) <= 2 * max(steps):
            g = math.gcd(*ms)
            self._fine = (g, self._run(self.fine_steps // g, g))

    def for_run(self, h: float, n: int) -> Trajectory:
        """rk4 of step h/m recorded every m steps: at the times k h, k = 0 … n (m = ⌈h / h*⌉)."""
        if self._cache[0] == n:
            return self._cache[1]
        m = max(1, math.ceil(self.fine_steps / n - 1e-9))
        g, fine = self._fine
        ref = fine.every(m // g) if fine is not None and m * n == self.fine_steps and m % g == 0 else self._run(n, m)
        self._cache = (n, ref)
        return ref

    def _run(self, n: int, m: int) -> Trajectory:
        """rk4 of step t_end / (m n), recorded every m steps."""
        try:
            ref = simulate(self.scene, self.X0, self.t_end, self.t_end / (m * n), REFERENCE_METHOD, record_every=m)
        except SimulationDiverged as err:
            raise ValueError(f"dts: the reference ({REFERENCE_METHOD} at dt = {self.t_end / (m * n):.3g} s) diverged "
                             f"at t = {err.t:.4g} s ({err.reason}): choose smaller dts") from None
        self._cache = (n, ref)
        return ref

    def measure_accuracy(self, finest: Trajectory) -> float:
        """The rotation angle at t_end between rk4 at h* (finest: the reference of the finest run) and rk4
        at 2 h*; sets self.accuracy and self.detail."""
        steps = max(1, self.fine_steps // 2)
        coarse = simulate(self.scene, self.X0, self.t_end, self.t_end / steps, REFERENCE_METHOD, record_every=steps,
                          on_divergence="stop")
        if coarse.diverged or abs(coarse.t[-1] - self.t_end) > 1e-9 * self.t_end:
            self.accuracy = math.inf
        else:
            self.accuracy = float(np.max(rotation_angle(finest.R[-1], coarse.R[-1])))
        self.detail = page_text("fine_detail", method=REFERENCE_METHOD, refine=REFINE, h=self.h_star,
                                accuracy=self.accuracy, t_end=self.t_end)
        return self.accuracy


def reference_for(scene, X0, t_end: float, steps_max: int):
    """The exact reference for a scene with no effect, else the fine rk4 reference (steps_max: the step count
    of the grid's finest step)."""
    return ExactReference(scene, X0) if not scene.effects else FineReference(scene, X0, t_end, steps_max)
