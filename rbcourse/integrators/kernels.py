"""Fast kernels for the two methods the compiled engine (rbcourse/engine) does not run yet, adaptive
(DOP853) and exact_splitting: the same methods, in plain Python floats, for one body that is free or
pivoted, under uniform gravity or nothing — the benchmark problems A, B, C.  (A copy of the physics,
to be retired as these methods move into the compiled engine; euler and rk4 have moved.)

A numpy call on a 3-vector costs about 1 µs, so a single-body step written with many
small numpy calls costs 100+ µs; the same arithmetic on Python floats costs a few µs.
Each kernel is tested against the readable numpy method it mirrors (tests/integrators/test_kernels.py).

The rotation is integrated in the principal axes of the inertia about the rotation
centre (R_p = R A, I = diag(I1, I2, I3)) as y = (q0, q1, q2, q3, L0, L1, L2): the unit
quaternion of R_p and the body angular momentum L_b = R_pᵀ L about the centre
(Euler's equations, dL_b/dt = L_b × ω_b + τ_b).  The translation is
exact (x = x0 + v0 t − ½ g t² ẑ for a free body: every method here is exact on it) or
follows the pivot.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..effects import Gravity
from ..pivot import Pivot
from ..rotation import matrix_from_quat, quat_from_matrix
from ..trajectory import OVERFLOW, blow_up
from .adaptive import combined_error, controlled_substeps, first_substep
from .base import Prepared, prepare
from . import tableaus
from .tableaus import RK4, nonzero


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

        I = (self.I1, self.I2, self.I3)
        scale = max(I)
        self.axis = next((k for k in range(3) if abs(I[(k + 1) % 3] - I[(k + 2) % 3]) <= 1e-12 * scale), None)
        self._flow = None

    def free_flow(self, q0, q1, q2, q3, L0, L1, L2, h):
        """The exact torque-free flow over h of (q, L_b).  A symmetric body (two equal moments I_s,
        the third I_k about axis e_k) turns as two rotations, in closed form:

            q ← q ⊗ (cos θ₁/2, sin θ₁/2 L̂_b) ⊗ (cos θ₃/2, sin θ₃/2 e_k),   θ₁ = h |L|/I_s,
            θ₃ = h β,  β = (1/I_k − 1/I_s) L_k;   L_b turns about e_k by −θ₃.

        Other bodies use rbcourse.exact (Jacobi elliptic functions)."""
        k = self.axis
        if k is None:
            return self._elliptic_flow(q0, q1, q2, q3, L0, L1, L2, h)
        L = (L0, L1, L2)
        I = (self.I1, self.I2, self.I3)
        Is, Ik = I[(k + 1) % 3], I[k]
        norm = math.sqrt(L0 * L0 + L1 * L1 + L2 * L2)
        if norm == 0.0:
            return q0, q1, q2, q3, L0, L1, L2
        half1 = 0.5 * h * norm / Is
        s1 = math.sin(half1) / norm
        a0, a1, a2, a3 = math.cos(half1), s1 * L0, s1 * L1, s1 * L2
        # q ⊗ qa
        q0, q1, q2, q3 = (q0 * a0 - q1 * a1 - q2 * a2 - q3 * a3, q0 * a1 + q1 * a0 + q2 * a3 - q3 * a2,
                          q0 * a2 - q1 * a3 + q2 * a0 + q3 * a1, q0 * a3 + q1 * a2 - q2 * a1 + q3 * a0)
        theta3 = h * (1.0 / Ik - 1.0 / Is) * L[k]
        c, s = math.cos(0.5 * theta3), math.sin(0.5 * theta3)
        # q ⊗ (c, s e_k)
        v = [q1, q2, q3]
        i, j = (k + 1) % 3, (k + 2) % 3
        q0, vk, vi, vj = q0 * c - v[k] * s, v[k] * c + q0 * s, v[i] * c + v[j] * s, v[j] * c - v[i] * s
        v[k], v[i], v[j] = vk, vi, vj
        # L_b turns about e_k by −θ₃
        ct, st = math.cos(theta3), math.sin(theta3)
        Lo = [L0, L1, L2]
        Lo[i], Lo[j] = ct * L[i] + st * L[j], -st * L[i] + ct * L[j]
        return q0, v[0], v[1], v[2], Lo[0], Lo[1], Lo[2]

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

    def rates(self, q0, q1, q2, q3, L0, L1, L2):
        """d/dt (q, L_b) = (½ q ⊗ (0, ω_b), L_b × ω_b + τ_b),  ω_b = (L0/I1, L1/I2, L2/I3);
        τ_b = c × (R_pᵀ (0, 0, −M g)) for a pivoted body under gravity, 0 otherwise."""
        a, b, c = L0 / self.I1, L1 / self.I2, L2 / self.I3
        dL0, dL1, dL2 = L1 * c - L2 * b, L2 * a - L0 * c, L0 * b - L1 * a
        if self.torqued:
            t0, t1, t2 = self.body_torque(q0, q1, q2, q3)
            dL0, dL1, dL2 = dL0 + t0, dL1 + t1, dL2 + t2
        return (0.5 * (-q1 * a - q2 * b - q3 * c), 0.5 * (q0 * a + q2 * c - q3 * b),
                0.5 * (q0 * b - q1 * c + q3 * a), 0.5 * (q0 * c + q1 * b - q2 * a), dL0, dL1, dL2)

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


@lru_cache(maxsize=None)
def _terms(table):
    """A table's rows of A and its weights b as nonzero terms (j, c_j), for combination."""
    return table.rows(), nonzero(table.b)


@lru_cache(maxsize=None)
def _error_terms():
    """DOP853's error weights E5, E3 as nonzero terms (the table read at first use)."""
    table = tableaus.dop853()
    return nonzero(table.E5), nonzero(table.E3)


def combination(y, h: float, terms, K):
    """y + h Σ c_j k_j over the (j, c_j) in `terms`, for the 7 components of y = (q, L_b).

    Seven running sums of floats: the arithmetic of y + h np.tensordot(c, K), without
    numpy's call overhead (a stage of DOP853 sums up to 8 terms)."""
    s0 = s1 = s2 = s3 = s4 = s5 = s6 = 0.0
    for j, c in terms:
        k0, k1, k2, k3, k4, k5, k6 = K[j]
        s0 += c * k0
        s1 += c * k1
        s2 += c * k2
        s3 += c * k3
        s4 += c * k4
        s5 += c * k5
        s6 += c * k6
    y0, y1, y2, y3, y4, y5, y6 = y
    return y0 + h * s0, y1 + h * s1, y2 + h * s2, y3 + h * s3, y4 + h * s4, y5 + h * s5, y6 + h * s6


_ZERO = (0.0,) * 7


def dop853(rotor: Rotor, t: float, y, h: float, rtol: float = 1e-8, atol: float = 1e-10, state=None):
    """The adaptive method's DOP853 substeps over [t, t + h] on y = (q, L_b), in floats, under
    adaptive.controlled_substeps (adaptive.py is the readable numpy version, tested against this one):

        k_s = f(y + sub Σ_j a_sj k_j),  y_new = y + sub Σ_j b_j k_j,
        err = adaptive.combined_error of e = Σ_j E_j k_j / (atol + rtol size).

    `state` is a one-element list carrying the next substep to try from call to call."""
    table = tableaus.dop853()
    rows, weights = _terms(table)
    f = rotor.rates
    K = [None] * (table.stages + 1)
    K[0] = f(*y)
    now = [y, None]

    def attempt(t, sub):
        y_new = now[1] = rk_substep(f, now[0], K, sub, rows, weights)
        K[table.stages] = f(*y_new)
        return error_norm(now[0], y_new, K, sub, rtol, atol)

    def accept(more):
        now[0] = _normalized(now[1])
        K[0] = K[table.stages]

    sub = state[0] or first_substep(*_sizes(y, K[0], rtol, atol), h)
    try:
        state[0] = controlled_substeps(t, t + h, sub, attempt, accept)
    except FloatingPointError:
        return [math.nan] * 7
    return now[0]


def rk_substep(f, y, K, h: float, rows, weights, den: float = 1.0):
    """One substep of a Runge–Kutta table (its rows and weights as nonzero terms, tableaus.Tableau.rows)
    from y, K[0] = f(y) given: fills K[1 … s−1] and returns y_new.

        k_s = f(y + h Σ_j a_sj k_j)  (s = 1 … s−1),   y_new = y + h/den Σ_j b_j k_j."""
    for s in range(1, len(rows)):
        K[s] = f(*combination(y, h, rows[s], K))
    return combination(y, h / den, weights, K)


def error_norm(y, y_new, K, h: float, rtol: float, atol: float) -> float:
    """DOP853's error norm (adaptive.combined_error) over the 7 components of (q, L_b)."""
    q_scale, L_scale = error_scale(y, y_new, rtol, atol)
    err5, err3 = _error_terms()
    n5 = _scaled_square(combination(_ZERO, 1.0, err5, K), q_scale, L_scale)
    n3 = _scaled_square(combination(_ZERO, 1.0, err3, K), q_scale, L_scale)
    return combined_error(n5, n3, 7, h)


def _scaled_square(e, q_scale: float, L_scale: float) -> float:
    """‖e / scale‖²: the quaternion part over q_scale, the angular momentum part over L_scale."""
    return ((e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]) / (q_scale * q_scale)
            + (e[4] * e[4] + e[5] * e[5] + e[6] * e[6]) / (L_scale * L_scale))


def error_scale(y, y_new, rtol: float, atol: float) -> tuple[float, float]:
    """atol + rtol × size, the size of each block taken as a whole (rotation-invariant):
    |q| = 1 for the quaternion, max(|L_b|) over the substep for the angular momentum."""
    L = math.sqrt(max(y[4] * y[4] + y[5] * y[5] + y[6] * y[6],
                      y_new[4] * y_new[4] + y_new[5] * y_new[5] + y_new[6] * y_new[6]))
    return atol + rtol, atol + rtol * L


def _sizes(y, f, rtol: float, atol: float):
    """The RMS sizes of y and f, scaled (as adaptive.initial_substep), for adaptive.first_substep."""
    q_scale, L_scale = error_scale(y, y, rtol, atol)
    return math.sqrt(_scaled_square(y, q_scale, L_scale) / 7), math.sqrt(_scaled_square(f, q_scale, L_scale) / 7)


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


STEPPERS = {"adaptive": dop853, "exact_splitting": exact_splitting}


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
        options = dict(method.settings, state=[0.0]) if method.name == "adaptive" else method.settings
        step = _bind(step, options)
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
