"""The last float kernel: exact_splitting on one asymmetric body that is free or pivoted, under uniform
gravity or nothing (benchmark problems A, B and C's asymmetric variants), in plain Python floats, with the
exact free flow of rbcourse.exact (Jacobi's elliptic functions, scipy.special: out of numba's reach).
Every other method, and exact_splitting on spherical and symmetric bodies, runs compiled (rbcourse/engine).
Tested against the readable numpy method it mirrors (tests/integrators/test_kernels.py).

The rotation is integrated in the principal axes of the inertia about the rotation centre
(R_p = R A, I = diag(I1, I2, I3)) as y = (q0, q1, q2, q3, L0, L1, L2): the unit quaternion of R_p and
the body angular momentum L_b = R_pᵀ L about the centre.  The translation is exact
(x = x0 + v0 t − ½ g t² ẑ for a free body) or follows the pivot.
"""
from __future__ import annotations

import math

import numpy as np

from ..effects import Gravity
from ..pivot import Pivot
from ..rotation import matrix_from_quat, quat_from_matrix
from ..trajectory import OVERFLOW, blow_up
from .base import Prepared, prepare


class Rotor:
    """One body turning about its rotation centre (centre of mass, or pivot), in floats."""

    def __init__(self, scene, prep: Prepared | None = None):
        prep = prepare(scene) if prep is None else prep
        self.scene = scene
        self.A = prep.I_rot_axes[0]
        self.I1, self.I2, self.I3 = (float(v) for v in prep.I_rot_moments[0])
        self.M = float(scene.mass[0])
        self.g = _gravity(scene)
        self.pivoted = bool(scene.pivoted[0])
        # centre of mass seen from the pivot, principal axes:  c = Aᵀ (−b)
        self.c = tuple(float(v) for v in self.A.T @ -scene.pivot_body_point[0]) if self.pivoted else (0.0, 0.0, 0.0)
        self.Mg = self.M * self.g
        self.torqued = self.pivoted and self.Mg != 0.0 and any(self.c)

        self._flow = None

    def free_flow(self, q0, q1, q2, q3, L0, L1, L2, h):
        """The exact torque-free flow over h of (q, L_b) of an asymmetric body, from rbcourse.exact (Jacobi's
        elliptic functions); spherical and symmetric bodies run compiled (engine/exact_flow.py)."""
        return self._elliptic_flow(q0, q1, q2, q3, L0, L1, L2, h)

    def _elliptic_flow(self, q0, q1, q2, q3, L0, L1, L2, h):
        """An asymmetric body: the exact flow from rbcourse.exact, on R_p = R(q) and L = R_p L_b."""
        if self._flow is None:
            from ..exact import FreeRotationFlow
            self._flow = FreeRotationFlow(np.diag([self.I1, self.I2, self.I3]))
        Rp = matrix_from_quat(np.array([q0, q1, q2, q3]))
        Lw = Rp @ np.array([L0, L1, L2])
        Rp = self._flow(Rp, Lw, h)
        q = quat_from_matrix(Rp)
        if q0 * q[0] + q1 * q[1] + q2 * q[2] + q3 * q[3] < 0:
            q = -q
        Lb = Rp.T @ Lw
        return (*q.tolist(), *Lb.tolist())

    # --- conversions -----------------------------------------------------------------
    def to_body(self, w, x, y, z, v):
        """R_pᵀ v for a unit quaternion (w, x, y, z):  t = 2 (−u) × v,  v_b = v + w t + (−u) × t."""
        v0, v1, v2 = v
        t0, t1, t2 = 2 * (z * v1 - y * v2), 2 * (x * v2 - z * v0), 2 * (y * v0 - x * v1)
        return (v0 + w * t0 - (y * t2 - z * t1), v1 + w * t1 - (z * t0 - x * t2), v2 + w * t2 - (x * t1 - y * t0))

    def encode(self, X) -> list:
        """Engine State (one body) -> [q of R_p = R A, L_b = R_pᵀ L]."""
        self.L_world = tuple(float(v) for v in X.L[0])
        Rp = X.R[0] @ self.A
        return [float(v) for v in quat_from_matrix(Rp)] + [float(v) for v in Rp.T @ X.L[0]]

    def decode_rotation(self, ys: np.ndarray):
        """Rows of y -> R (m, 3, 3) and world L = R_p L_b (m, 3)."""
        Rp = matrix_from_quat(ys[:, :4])
        return Rp @ self.A.T, np.einsum("mij,mj->mi", Rp, ys[:, 4:7])

    def body_torque(self, q0, q1, q2, q3):
        """τ_b = c × (−M g R_pᵀ ẑ): gravity's torque about the pivot, principal axes."""
        n = 1.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        g0 = -self.Mg * 2 * (q1 * q3 - q0 * q2) * n      # −M g × (third row of R_p)
        g1 = -self.Mg * 2 * (q2 * q3 + q0 * q1) * n
        g2 = -self.Mg * (1 - 2 * (q1 * q1 + q2 * q2) * n)
        c0, c1, c2 = self.c
        return c1 * g2 - c2 * g1, c2 * g0 - c0 * g2, c0 * g1 - c1 * g0

    def translation(self, X0, times: np.ndarray):
        """Free body: x = x0 + (P0/M) t − ½ g t² ẑ, P = P0 − M g t ẑ (None for a pivoted body)."""
        if self.pivoted:
            return None
        x = X0.x[0] + np.outer(times, X0.P[0] / self.M)
        x[:, 2] -= 0.5 * self.g * times**2
        P = np.repeat(X0.P[0][None], len(times), axis=0)
        P[:, 2] -= self.Mg * times
        return x, P


def _acts_on_the_body(scene, effect) -> bool:
    """Does the effect act on the scene's one body (its body= selection, as the numpy path reads it)?"""
    return 0 in scene.bodies_of(effect)


def _gravity(scene) -> float:
    """g summed over the Gravity effects that act on the body (0 if none does)."""
    return sum(e.g for e in scene.effects if isinstance(e, Gravity) and _acts_on_the_body(scene, e))


def supports(scene) -> bool:
    """Kernels handle one body, free or pivoted, under gravity or nothing, with no events or contacts."""
    return (scene.single and not scene.has_events and not scene.has_contacts
            and all(isinstance(e, (Gravity, Pivot)) for e in scene.effects))


# --- steppers on y = [q0..q3, L0..L2] ------------------------------------------------

def _normalized(y):
    """q / |q| (and L_b as it is); a quaternion whose norm is 0, inf or NaN gives NaN (a blow-up), as
    rotation.quat_normalize."""
    s = y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]
    n = 1.0 / math.sqrt(s) if 0.0 < s < math.inf else math.nan
    return [y[0] * n, y[1] * n, y[2] * n, y[3] * n, y[4], y[5], y[6]]




def exact_splitting(rotor: Rotor, t: float, y, h: float, composition: str = "blanes_moan4"):
    """Kick / exact free flow / kick composition (splitting_exact.py) on (q, L_b)."""
    from .splitting_exact import COMPOSITIONS
    table = COMPOSITIONS[composition]
    kicks, flows = table["kicks"], table["flows"]
    q0, q1, q2, q3, L0, L1, L2 = y
    flow = rotor.free_flow
    if not rotor.torqued:          # no kick: one exact flow over h, and L_b from the constant world L
        q0, q1, q2, q3, *_ = flow(q0, q1, q2, q3, L0, L1, L2, h)
        n = 1.0 / math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        q0, q1, q2, q3 = q0 * n, q1 * n, q2 * n, q3 * n
        return [q0, q1, q2, q3, *rotor.to_body(q0, q1, q2, q3, rotor.L_world)]
    if rotor.torqued:
        t0, t1, t2 = rotor.body_torque(q0, q1, q2, q3)
        b = kicks[0] * h
        L0, L1, L2 = L0 + b * t0, L1 + b * t1, L2 + b * t2
    for a, b in zip(flows, kicks[1:]):
        q0, q1, q2, q3, L0, L1, L2 = flow(q0, q1, q2, q3, L0, L1, L2, a * h)
        if rotor.torqued:
            t0, t1, t2 = rotor.body_torque(q0, q1, q2, q3)
            b *= h
            L0, L1, L2 = L0 + b * t0, L1 + b * t1, L2 + b * t2
    return _normalized([q0, q1, q2, q3, L0, L1, L2])


STEPPERS = {"exact_splitting": exact_splitting}


def _loop(step, y, n: int, h: float, every: int):
    """Step n times; record every `every` steps (and the last); stop at a NaN, an inf or an overflow,
    keeping the last good state.  Returns (times, rows, reason, step reached)."""
    rows, times = [y], [0.0]
    for k in range(1, n + 1):
        y_new = step(y, k)
        # a quick test on the sum of |components| (NaN propagates through it; no component can pass the
        # limit unless the sum does), then trajectory.blow_up decides, each component on its own
        if not sum(map(abs, y_new)) < OVERFLOW and (reason := blow_up(_named(y_new))):
            if times[-1] != (k - 1) * h:
                rows.append(y)
                times.append((k - 1) * h)
            return np.array(times), rows, reason, k
        y = y_new
        if k % every == 0 or k == n:
            rows.append(y)
            times.append(k * h)
    return np.array(times), rows, "", n


def _named(y) -> list:
    """A kernel's state by name, for the divergence message: (q, L_b) of a rotor, or the slides'
    18 floats (x, R, P, L)."""
    y = np.array(y, dtype=float)
    if len(y) == 7:
        return [("q", y[0:4]), ("L", y[4:7])]
    return [("x", y[0:3]), ("R", y[3:12]), ("P", y[12:15]), ("L", y[15:18])]


def available(method, scene) -> bool:
    """Is there a float kernel for this method (with its settings) and this scene?"""
    return method.name in STEPPERS and supports(scene)


def run(method, scene, X0, n: int, h: float, every: int, prep: Prepared | None = None):
    """Run a kernel for n steps of h, recording every `every` steps.

    Returns (times, x, R, P, L) in engine coordinates (pivoted bodies get x, P from the pivot),
    and the reason it stopped early ('' if it did not) with the step it reached.
    """
    rotor = Rotor(scene, prep)
    step = STEPPERS[method.name]
    if method.settings:
        step = _bind(step, method.settings)
    y = rotor.encode(X0)
    times, rows, reason, k_stop = _loop(lambda y, k: step(rotor, (k - 1) * h, y, h), y, n, h, every)
    return _arrays(rotor, scene, X0, times, np.array(rows)), reason, k_stop


def _bind(step, options):
    return lambda rotor, t, y, h: step(rotor, t, y, h, **options)


def _arrays(rotor, scene, X0, times, rows):
    from ..state import State
    R, L = rotor.decode_rotation(rows)
    m = len(times)
    moved = rotor.translation(X0, times)
    if moved is None:
        x, P = np.zeros((m, 3)), np.zeros((m, 3))
    else:
        x, P = moved
    X = scene.constrain(State.unchecked(x, R, P, L))
    return times, X.x, X.R, X.P, X.L
