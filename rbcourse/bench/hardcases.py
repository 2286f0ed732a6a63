"""The hard cases: named scenes on which easy methods go wrong (../shared/benchmarks.md).

Each case has its full length and a short one (`quick`, used under test with the
environment flag RBCOURSE_QUICK=1), a step size, and a reference where one exists.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..body import RigidBody
from .problems import problem_A, problem_B, problem_C
from ..scene import Scene
from ..state import State


@dataclass(frozen=True)
class HardCase:
    """A hard case: a scene, an initial state, how long and with what step, and what goes wrong."""
    name: str
    scene: Scene
    X0: State
    T: float
    dt: float
    T_quick: float
    reference: str               # "exact" (torque-free), "dop853" (benchmark C's), or "" (none)
    goes_wrong: str              # what goes wrong with naive methods

    @property
    def free(self) -> bool:
        """No force, no torque: the exact torque-free solution applies and L, |L|, E are invariants."""
        return not self.scene.effects

    def duration(self, quick: bool = False) -> float:
        """T, or the short T_quick (quick: passed down from rbcourse.config.quick_mode by the caller)."""
        return self.T_quick if quick else self.T


def _free(body, omega_body, R0=None) -> tuple:
    R0 = np.eye(3) if R0 is None else R0
    return Scene(body), State.from_velocities(body, np.zeros(3), R0, np.zeros(3), R0 @ np.asarray(omega_body, float))


def _case(name, scene_X0, T, dt, T_quick, reference, goes_wrong):
    scene, X0 = scene_X0
    return HardCase(name, scene, X0, T, dt, T_quick, reference, goes_wrong)


def catalogue() -> dict[str, HardCase]:
    """Every hard case, by name."""
    A, B, C = problem_A(), problem_B(), problem_C()
    box = A.body
    disk = RigidBody(1.0, [0.25, 0.25, 0.5], name="thin disk")
    rod = RigidBody(1.0, [1.72e-4, 1.72e-7, 1.7185e-4], name="slender rod")
    sphere = RigidBody.sphere(1.0, 0.1)
    top_like = RigidBody.cylinder(1.0, 0.1, 0.02)
    cases = [
        _case("racket_long", (A.scene, A.X0), 200.0, 1e-2, 40.0, "exact",
              "energy drift makes the flips come at the wrong times, or not at all"),
        _case("fast_spin_large_step", (B.scene, B.X0), 10.0, 1e-2, 10.0, "exact",
              "half a radian (29°) per step: the explicit gyroscopic term gains energy and blows up"),
        _case("fast_thin_disk", (Scene(disk), State(np.zeros(3), np.eye(3), np.zeros(3), [0.3, -0.2, 20.0])),
              10.0, 1e-2, 10.0, "exact", "energy gain when h|ω| is large (|ω| = 40 rad/s, h|ω| = 0.4)"),
        _case("slender_rod", _free(rod, [1.0, 300.0, 2.0]), 10.0, 1e-3, 2.0, "exact",
              "inertia ratio 1000:1:1000, spun about an oblique axis: stiff gyroscopic coupling (h ω = 0.3)"),
        _case("heavy_top_coarse", (C.scene, C.X0), 5.0, 1e-2, 1.0, "dop853",
              "2 rad of spin per step: Euler blows up; implicit damps the top and it falls"),
        _case("heavy_top_fine", (C.scene, C.X0), 5.0, 1e-3, 1.0, "dop853",
              "Euler still blows up; implicit still damps"),
        _case("near_separatrix", _free(box, [1e-6, 5.0, 1e-6]), 20.0, 1e-2, 20.0, "exact",
              "elliptic parameter → 1: the exact formulas lose digits; tiny errors decide the flip time"),
        _case("principal_axis_spin", _free(box, [0.0, 5.0, 0.0]), 20.0, 1e-2, 20.0, "exact",
              "spin exactly along the (unstable) intermediate axis: exact formulas divide by zero"),
        _case("long_run", _free(box, [1.0, 2.0, 3.0]), 1000.0, 1e-3, 10.0, "exact",
              "10⁶ steps: R leaves SO(3); |L| and the energy drift"),
        _case("sphere", _free(sphere, [1.0, -2.0, 3.0]), 10.0, 1e-2, 10.0, "exact",
              "a spherical body: every axis is principal (degenerate eigenvectors)"),
        _case("symmetric_body", _free(top_like, [1.0, 0.0, 30.0]), 10.0, 1e-2, 10.0, "exact",
              "two equal moments: steady precession; the elliptic formulas degenerate"),
        _case("light_body", _free(RigidBody.box(1e-6, (0.3, 0.2, 0.05)), [0.01, 5.0, 0.01]), 10.0, 1e-2, 10.0, "exact",
              "1 mg: tiny moments of inertia (3.5e-9 to 1.1e-8 kg m²), the same motion"),
        _case("heavy_body", _free(RigidBody.box(1e6, (0.3, 0.2, 0.05)), [0.01, 5.0, 0.01]), 10.0, 1e-2, 10.0, "exact",
              "1000 t: huge moments of inertia (3.5e3 to 1.1e4 kg m²), the same motion"),
    ]
    return {c.name: c for c in cases}
