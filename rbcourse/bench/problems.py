"""The benchmark problems A, B, C of ../shared/benchmarks.md, with their reference solutions.

A — tennis racket: box 1 kg, 0.3 × 0.2 × 0.05 m, ω0 = (0.01, 5, 0.01) body, T = 20 s.
B — fast spin about the major axis: same box, ω0 = (0.1, 0.1, 50) body, T = 10 s.
C — fast heavy top: disc r = 0.04, h = 0.01, m = 1 kg on a massless stem, pivot at the
    origin, centre of mass 5 cm up the symmetry axis, tilted 30° about x, spin 200 rad/s, T = 5 s.
References: the exact torque-free solution for A and B; scipy's DOP853 at rtol = atol = 1e-13
on Euler's equations about the pivot for C.

The scenes are the named set-ups of examples.py (tennis_racket, fast_spin, heavy_top); a
problem adds its own data: the duration T, a title, and what the peers need (ω0 in body axes, g and
the pivot's distance to the centre of mass).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..examples import Example, fast_spin, heavy_top, tennis_racket
from ..scene import Scene
from ..state import State


@dataclass
class Problem:
    """A benchmark problem: scene, initial state, duration, and the data peers need."""
    name: str
    title: str
    scene: Scene
    X0: State
    T: float
    omega0_body: np.ndarray          # initial angular velocity, body axes (as MuJoCo's)
    gravity: float
    pivot_com: float = 0.0           # distance pivot -> centre of mass along body z (C)
    _ref: np.ndarray | None = field(default=None, repr=False)

    @property
    def body(self):
        return self.scene.bodies[0]

    def reference_R(self) -> np.ndarray:
        """R(T) of the reference solution (computed once)."""
        if self._ref is None:
            if self.pivot_com:
                self._ref = _rotation_with_gravity(self, rtol=1e-13)
            else:
                from ..exact.free_body import exact_free_body
                self._ref = exact_free_body(self.body, self.X0, np.array([self.T])).R[-1]
        return self._ref

    def inertia_about_rotation_centre(self) -> np.ndarray:
        """Principal moments about the pivot (C) or the centre of mass (A, B)."""
        return np.diag(self.scene.I_rot[0]).copy()

    def rhs(self):
        """f(t, y) for y = (ω_b, q): Euler's equations with gravity's torque about the pivot — the peers'
        form, written in plain floats so that scipy is measured at its best (a call costs a few µs)."""
        I1, I2, I3 = (float(v) for v in self.inertia_about_rotation_centre())
        mgl = self.body.mass * self.gravity * self.pivot_com

        def f(t, y):
            w0, w1, w2, q0, q1, q2, q3 = y.tolist()
            # gravity's torque c × Rᵀ(0, 0, −m g), c = (0, 0, l): (m g l R₂₁, −m g l R₂₀, 0)
            t0 = mgl * 2 * (q2 * q3 + q0 * q1)
            t1 = -mgl * 2 * (q1 * q3 - q0 * q2)
            return [((I2 - I3) * w1 * w2 + t0) / I1, ((I3 - I1) * w2 * w0 + t1) / I2, (I1 - I2) * w0 * w1 / I3,
                    0.5 * (-q1 * w0 - q2 * w1 - q3 * w2), 0.5 * (q0 * w0 + q2 * w2 - q3 * w1),
                    0.5 * (q0 * w1 - q1 * w2 + q3 * w0), 0.5 * (q0 * w2 + q1 * w1 - q2 * w0)]
        return f

    def y0(self) -> np.ndarray:
        from ..rotation import quat_from_matrix
        return np.concatenate([self.omega0_body, quat_from_matrix(self.X0.R)])


def _rotation_with_gravity(problem: Problem, rtol: float) -> np.ndarray:
    """Reference for C: Euler's equations about the pivot with gravity's torque, and q̇ = ½ q ⊗ (0, ω_b),
    by scipy's DOP853 at rtol = atol = 1e-13."""
    from scipy.integrate import solve_ivp
    from ..rotation import matrix_from_quat
    sol = solve_ivp(problem.rhs(), (0.0, problem.T), problem.y0(), method="DOP853", rtol=rtol, atol=rtol)
    return matrix_from_quat(sol.y[3:, -1])


def from_example(name: str, title: str, ex: Example, T: float) -> Problem:
    """The problem `name` on the set-up ex (its scene, X0 and ω0 in body axes), run for T seconds; for a
    pivoted scene under gravity (C), g and the pivot's distance l to the centre of mass along body z."""
    from ..effects import Gravity
    from ..pivot import Pivot
    g = float(sum(e.g for e in ex.scene.effects if isinstance(e, Gravity)))
    l = float(sum(-e.body_point[2] for e in ex.scene.effects if isinstance(e, Pivot)))
    return Problem(name, title, ex.scene, ex.X0, T, ex.omega_body, g, pivot_com=l)


def problem_A() -> Problem:
    """A: the tennis racket, T = 20 s."""
    return from_example("A", "tennis racket (Dzhanibekov flip)", tennis_racket(), 20.0)


def problem_B() -> Problem:
    """B: the fast spin about the major axis, T = 10 s."""
    return from_example("B", "fast spin about the major axis", fast_spin(), 10.0)


def problem_C() -> Problem:
    """C: the fast heavy top, T = 5 s."""
    return from_example("C", "fast heavy top", heavy_top(), 5.0)


PROBLEMS = {"A": problem_A, "B": problem_B, "C": problem_C}
