"""Checks for the two-hour exercise (notebooks/01_exercise_euler.ipynb, slide "EXERCICE (2h)").

The student writes, from the slides, one function at a time; after each one a check cell runs it on
random inputs (seeded: the same inputs every time) against the reference engine (rbcourse) and prints
one verdict:

    ✓ velocity: v = P/M — correct on 20 random inputs
    ✗ inverse_inertia: the rotation is on the wrong side … → reread the slide “Evolution temporelle (Euler)”
    ○ velocity: not done yet (it raises NotImplementedError)

A wrong answer is diagnosed by computing, on the same input, the known wrong formulas (τ = F ∧ r,
Ṙ = R ω*, I⁻¹_body used as the world inertia, …): the first one that matches the student's output is
named, with the slide to reread; otherwise the check shows the input, the expected and the returned
value.  A check never raises: a NotImplementedError is "not done yet", any other exception is shown
as its type and message (no traceback).  Each check returns a CheckResult (passed, mistake, message);
MISTAKES lists every mistake it can name.

What the student writes (the signatures the checks call):

    box_inertia(mass, size)                     -> I_body (3, 3) = M/12 · diag(b² + c², a² + c², a² + b²)
    velocity(P, M)                              -> v = P / M
    inverse_inertia(R, I_body_inv)              -> I⁻¹(t) = R · I⁻¹_body · Rᵀ
    angular_velocity(I_inv, L)                  -> ω = I⁻¹(t) · L
    resultants(x, forces)                       -> (F, τ):  F = Σ Fᵢ,  τ = Σ (rᵢ − x) ∧ Fᵢ
    dxdt(M, I_body_inv, X, forces)              -> (v, ω* R, F, τ)              (slide "Les Formules")
    euler_step(M, I_body_inv, X, forces, dt)    -> X(t+Δt) = X(t) + Δt · dX/dt  (slide "Evolution temporelle")
    simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=euler_step)
                                                -> (x, R, P, L), arrays of n_steps + 1 rows
    project_so3(R)                              -> the nearest rotation U Vᵀ   (the fix)

X is the tuple (x, R, P, L) — the checks pass a StateTuple, so both ``x, R, P, L = X`` and ``X.x``
work; a function may return a plain tuple.  ``forces`` is a list of pairs (rᵢ, Fᵢ): world point,
world force.  ``forces_at(t, X)`` returns that list at time t for the state X.

The pushed box (pushed_box(), simulate_or_reference()) runs the student's simulate when its checks
pass, else the reference engine rbcourse.simulate(..., method="euler"), and says which it used.
"""
from __future__ import annotations

import copy
import os
import sysconfig
import traceback
import warnings
from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np

from ..body import RigidBody
from ..effects import PointForce
from ..forces import resultants as _engine_resultants
from ..rotation import exp_so3, project_so3 as _engine_project_so3, star
from ..scene import Scene
from ..state import State, angular_velocity as _engine_angular_velocity
from ..state import inverse_inertia as _engine_inverse_inertia, velocity as _engine_velocity

__all__ = [
    "StateTuple", "CheckResult", "Mistake", "MISTAKES", "SLIDES",
    "check_box_inertia", "check_velocity", "check_inverse_inertia", "check_angular_velocity",
    "check_resultants", "check_dxdt", "check_euler_step", "check_simulate", "check_project_so3",
    "check_euler_step_projected", "PushedBox", "pushed_box", "simulate_or_reference", "show_iterations",
]


class StateTuple(NamedTuple):
    """X = (x, R, P, L): position of the barycentre, orientation, quantité de mouvement, moment cinétique."""
    x: np.ndarray
    R: np.ndarray
    P: np.ndarray
    L: np.ndarray


# =====================================================================================
# Results and the mistakes a check can name
# =====================================================================================

class CheckResult:
    """What a check found: passed (bool), mistake (an id of MISTAKES, or "not_done", "error", … ;
    None when passed), message (the line(s) printed).

    The check prints the message; shown as the value of the cell that printed it, the result shows
    nothing more (no second copy); shown in a later cell, it shows the message.
    """

    def __init__(self, name: str, passed: bool, mistake: str | None, message: str):
        self.name = name
        self.passed = passed
        self.mistake = mistake
        self.message = message
        self._printed_in = None       # the IPython cell (execution count) that printed the message

    def __repr__(self) -> str:
        return f"CheckResult(name={self.name!r}, passed={self.passed}, mistake={self.mistake!r})"

    def __str__(self) -> str:
        return self.message

    def _ipython_display_(self):
        if self._printed_in is None or self._printed_in != _execution_count():
            print(self.message)


def _execution_count():
    """The number of the IPython cell running now (None outside IPython)."""
    try:
        from IPython import get_ipython
    except ImportError:
        return None
    shell = get_ipython()
    return None if shell is None else shell.execution_count


@dataclass(frozen=True)
class Mistake:
    """A known mistake: what is wrong (text) and where the slides say it right (slide)."""
    id: str
    text: str
    slide: str


FORMULES = "Les Formules"
ETAT = "Vecteur d'état du Rigidbody"
EULER = "Evolution temporelle (Euler)"
ITERATION_1 = "Itération 1"
ITERATION_2 = "Itération 2"
BIBLIO = "Bibliographie"
SLIDES = (FORMULES, ETAT, EULER, ITERATION_1, ITERATION_2, BIBLIO)
_BOX = "Baraff's notes, the inertia of a box (eq. 2-27): the slides take I_body as given"

_MISTAKES = [
    # --- box_inertia: I_body = M/12 · diag(b² + c², a² + c², a² + b²)
    Mistake("box_not_squared", "the sides must be squared: I_xx = M/12 · (b² + c²), not M/12 · (b + c) "
            "(an inertia is in kg·m²)", _BOX),
    Mistake("box_wrong_pairing", "the sides are paired wrongly: the moment about an axis uses the two sides "
            "perpendicular to that axis — I_xx = M/12 (b² + c²), I_yy = M/12 (a² + c²), I_zz = M/12 (a² + b²) "
            "for the sides a, b, c along x, y, z", _BOX),
    Mistake("box_missing_twelfth", "the factor 1/12 is missing: I_body = M/12 · diag(b² + c², a² + c², a² + b²)",
            _BOX),
    Mistake("box_half_sizes", "you used the half sides (a/2, b/2, c/2) in M/12 (b² + c²): the formula takes "
            "the full side lengths", _BOX),
    Mistake("box_missing_mass", "the mass M is missing: I_body = M/12 · diag(b² + c², a² + c², a² + b²)", _BOX),
    Mistake("box_moments_not_matrix", "you returned the three moments: return the 3×3 matrix "
            "I_body = np.diag([I_xx, I_yy, I_zz])", _BOX),
    # --- velocity: v = P / M
    Mistake("velocity_times_mass", "v = P / M: you multiplied P by M", EULER),
    Mistake("velocity_mass_over_P", "v = P / M, not M / P", EULER),
    # --- inverse_inertia: I⁻¹(t) = R · I⁻¹_body · Rᵀ
    Mistake("I_body_as_world", "I⁻¹_body was used as the world inertia (no R … Rᵀ): the body-frame inertia "
            "turns with the body, I⁻¹(t) = R(t) · I⁻¹_body · R(t)ᵀ", EULER),
    Mistake("R_inverse_I_R", "the rotation is on the wrong side: you computed R⁻¹ · I⁻¹_body · R "
            "(= Rᵀ · I⁻¹_body · R); the slides' I⁻¹(t) = R · I⁻¹_body · Rᵀ, with R on the left", EULER),
    Mistake("missing_RT", "Rᵀ is missing on the right: I⁻¹(t) = R · I⁻¹_body · Rᵀ, not R · I⁻¹_body", EULER),
    Mistake("inverse_inertia_not_inverted", "you computed I(t) = R · I_body · Rᵀ, the inertia itself: the "
            "slides want its inverse, I⁻¹(t) = R · I⁻¹_body · Rᵀ (no np.linalg.inv needed)", EULER),
    Mistake("elementwise", "`*` multiplies NumPy arrays element by element: a matrix product is `@` "
            "(R @ I_body_inv @ R.T, I_inv @ L)", EULER),
    # --- angular_velocity: ω = I⁻¹(t) · L
    Mistake("omega_uses_inertia", "ω = I⁻¹(t) · L: you multiplied L by I(t), the inverse of I⁻¹(t)", EULER),
    # --- resultants: F = Σ Fᵢ, τ = Σ (rᵢ − x) ∧ Fᵢ
    Mistake("tau_sign", "τ has the wrong sign: τ = (rᵢ − x) ∧ Fᵢ, lever arm first; you computed "
            "Fᵢ ∧ (rᵢ − x) (a cross product changes sign when its factors swap)", FORMULES),
    Mistake("lever_arm", "the lever arm is rᵢ − x(t), from the barycentre to the point where the force acts; "
            "you used rᵢ, which gives the torque about the world origin", FORMULES),
    Mistake("tau_sign_and_lever_arm", "two mistakes in τ: the lever arm is rᵢ − x(t) (you used rᵢ) and it comes "
            "first: τ = (rᵢ − x) ∧ Fᵢ (you computed Fᵢ ∧ rᵢ)", FORMULES),
    Mistake("last_force_only", "only the last force counts in your sums: F = Σ Fᵢ and τ = Σ (rᵢ − x) ∧ Fᵢ add "
            "up every force (F += Fᵢ in the loop, not F = Fᵢ)", FORMULES),
    Mistake("F_tau_swapped", "return (F, τ) in this order: you returned (τ, F)", FORMULES),
    Mistake("empty_forces", "with no force (forces = []) F and τ must be zero vectors of shape (3,): start "
            "both sums from np.zeros(3)", FORMULES),
    # --- dxdt: (v, ω* R, F, τ)
    Mistake("R_dot_order", "Ṙ = ω* · R, with ω* on the left (each body axis, a column X' of R, turns as "
            "dX'/dt = ω ∧ X'); you wrote R · ω*", FORMULES),
    Mistake("R_dot_missing_R", "Ṙ = ω* · R: you returned ω* alone", FORMULES),
    Mistake("omega_star_sign", "your ω* has the wrong sign: ω* a = ω ∧ a, so "
            "ω* = [[0, −ω_z, ω_y], [ω_z, 0, −ω_x], [−ω_y, ω_x, 0]]", FORMULES),
    Mistake("omega_from_P", "ω was computed from P: ω(t) = I⁻¹(t) · L(t) — L (moment cinétique) carries the "
            "rotation, P (quantité de mouvement) the translation", ETAT),
    Mistake("v_from_L", "v was computed from L: v(t) = P(t) / M — P (quantité de mouvement) carries the "
            "translation, L (moment cinétique) the rotation", ETAT),
    Mistake("P_L_swapped", "P and L are swapped: v = P / M (quantité de mouvement → translation) and "
            "ω = I⁻¹(t) · L (moment cinétique → rotation)", ETAT),
    Mistake("dx_is_P", "dx/dt = v = P / M: you returned P itself", FORMULES),
    Mistake("dP_is_acceleration", "dP/dt = F (P is a momentum): you returned F / M, an acceleration", FORMULES),
    Mistake("dL_is_angular_acceleration", "dL/dt = τ (L is a momentum): you returned I⁻¹(t) · τ", FORMULES),
    # --- euler_step: X(t+Δt) = X(t) + Δt · (v, ω* R, F, τ)
    Mistake("R_not_updated", "R is not updated: R(t+Δt) = R(t) + Δt · ω* R(t) — without it the body never "
            "turns", EULER),
    Mistake("x_not_updated", "x is not updated: x(t+Δt) = x(t) + Δt · v(t) — without it the body never "
            "moves", EULER),
    Mistake("P_not_updated", "P is not updated: P(t+Δt) = P(t) + Δt · F(t)", EULER),
    Mistake("L_not_updated", "L is not updated: L(t+Δt) = L(t) + Δt · τ(t)", EULER),
    Mistake("semi_implicit", "you moved x or R with the new momentum P(t+Δt) or L(t+Δt): that is semi-implicit "
            "Euler. The slides' explicit Euler takes all of dX/dt = (v, ω* R, F, τ) from X(t) — compute it "
            "first, then update; from rest, x and R must not move in the first iteration", ITERATION_1),
    Mistake("no_dt", "the rates must be multiplied by Δt: X(t+Δt) = X(t) + Δt · dX/dt", EULER),
    Mistake("modified_input", "your function changed its input in place (x += …, P[:] = …, a list you "
            "appended to): build new arrays instead (x_new = x + dt * v) — the caller still needs X(t)", EULER),
    # --- simulate
    Mistake("missing_initial", "the arrays start at X₁: they must start with X₀ — n_steps steps give "
            "n_steps + 1 states X₀, X₁, …, X_n", ITERATION_2),
    Mistake("missing_final", "the last state X_n is missing: n_steps steps give n_steps + 1 states "
            "X₀, X₁, …, X_n", ITERATION_2),
    Mistake("wrong_length", "the arrays must hold n_steps + 1 states X₀, X₁, …, X_n", ITERATION_2),
    Mistake("aliasing", "every recorded state is the same (the last one): you stored arrays and then changed "
            "them in place; store new arrays (x = x + …, not x += …) or copies", ITERATION_2),
    Mistake("wrong_time", "forces_at(t, X) was called at the wrong times: step k starts at t = k · Δt "
            "(0, Δt, 2Δt, …)", ITERATION_2),
    Mistake("stale_state", "forces_at(t, X) must get the current state X_k (a force's point rᵢ = x + R bᵢ moves "
            "with the body)", ITERATION_2),
    Mistake("ignores_step", "simulate never called the step function it was given: each iteration is "
            "X = step(M, I_body_inv, X, forces_at(t, X), dt), so that the same loop runs the fixed step later",
            ITERATION_2),
    Mistake("step_count", "step must be called once per step: n_steps times", ITERATION_2),
    Mistake("no_step_parameter", "keep the signature simulate(M, I_body_inv, X0, forces_at, dt, n_steps, "
            "step=euler_step): the check passes step=…", ITERATION_2),
    # --- project_so3 and the projected step
    Mistake("svd_V_transposed", "np.linalg.svd returns (U, S, Vᵀ): its third output is already Vᵀ, so the "
            "nearest rotation is U @ Vt (you used U @ Vt.T)", BIBLIO),
    Mistake("svd_not_projected", "you returned R unchanged (U Σ Vᵀ is R itself): the nearest rotation drops Σ, "
            "U Vᵀ", BIBLIO),
    Mistake("columns_normalized", "normalising the columns (or rows) is not enough: they must also be "
            "perpendicular (RᵀR = I); use the SVD R = U Σ Vᵀ → U Vᵀ", BIBLIO),
    Mistake("projection_transposed", "you returned the transpose of the nearest rotation: U Vᵀ, not V Uᵀ", BIBLIO),
    Mistake("not_nearest", "your matrix is a rotation, but far from R: the fix must change R as little as "
            "possible (np.linalg.qr's Q may flip columns); use the SVD R = U Σ Vᵀ → U Vᵀ", BIBLIO),
    Mistake("not_a_rotation", "the result is not a rotation (RᵀR ≠ I or det R ≠ 1); use the SVD R = U Σ Vᵀ → U Vᵀ",
            BIBLIO),
    Mistake("step_not_projected", "R(t+Δt) is not projected: apply project_so3 to R after the Euler step", BIBLIO),
    Mistake("projected_before", "project R after the Euler step (the step is what pushes R off SO(3)), "
            "not before it", BIBLIO),
]
MISTAKES: dict[str, Mistake] = {m.id: m for m in _MISTAKES}
"""Every mistake a check can name, by id (the CheckResult.mistake of a diagnosis).  Besides these, a
result's mistake may be "not_done", "error", "not_a_function", "returned_none", "not_numbers",
"wrong_return", "wrong_shape", "wrong_result" or "check_failed" (a bug in the check itself)."""


# =====================================================================================
# The reference (the engine's formulas; the wrong ones are built from the same pieces)
# =====================================================================================

def _ref_box_inertia(mass, size):
    """I_body = M/12 · diag(b² + c², a² + c², a² + b²)  (rbcourse.RigidBody.box)."""
    return np.array(RigidBody.box(mass, size).I_body)


def _ref_resultants(x, forces):
    """F = Σ Fᵢ,  τ = Σ (rᵢ − x) ∧ Fᵢ  (rbcourse.resultants)."""
    return _engine_resultants(x, forces)


def _unpack(X):
    """(x, R, P, L) from a tuple, a StateTuple, an rbcourse State or anything with .x .R .P .L."""
    if all(hasattr(X, k) for k in "xRPL"):
        return X.x, X.R, X.P, X.L
    x, R, P, L = X
    return x, R, P, L


def _as_floats(X):
    return tuple(np.asarray(a, dtype=float) for a in _unpack(X))


def _ref_dxdt(M, I_body_inv, X, forces):
    """dX/dt = (v, ω* R, F, τ) with v = P/M, I⁻¹(t) = R I⁻¹_body Rᵀ, ω = I⁻¹(t) L  (slide "Les Formules")."""
    x, R, P, L = _as_floats(X)
    v = _engine_velocity(P, M)
    omega = _engine_angular_velocity(_engine_inverse_inertia(R, np.asarray(I_body_inv, float)), L)
    F, tau = _ref_resultants(x, forces)
    return (v, star(omega) @ R, F, tau)


def _ref_euler_step(M, I_body_inv, X, forces, dt):
    """X(t+Δt) = X(t) + Δt · dX/dt(t)  (slide "Evolution temporelle (Euler)")."""
    X = _as_floats(X)
    return StateTuple(*(a + dt * d for a, d in zip(X, _ref_dxdt(M, I_body_inv, X, forces))))


def _ref_euler_step_projected(M, I_body_inv, X, forces, dt):
    """The Euler step, then R ← its nearest rotation."""
    x, R, P, L = _ref_euler_step(M, I_body_inv, X, forces, dt)
    return StateTuple(x, _engine_project_so3(R), P, L)


def _ref_simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=_ref_euler_step):
    """X₀, X₁ = step(X₀), …: arrays x (n+1, 3), R (n+1, 3, 3), P (n+1, 3), L (n+1, 3)."""
    X = StateTuple(*_as_floats(X0))
    states = [X]
    for k in range(n_steps):
        X = StateTuple(*_as_floats(step(M, I_body_inv, X, forces_at(k * dt, X), dt)))
        states.append(X)
    return tuple(np.array([s[i] for s in states]) for i in range(4))


# =====================================================================================
# Random inputs (seeded)
# =====================================================================================

def _rotation(rng):
    return exp_so3(rng.normal(size=3) * 1.2)


def _spd(rng):
    """A symmetric positive-definite 3×3 matrix (an inverse inertia in some axes)."""
    Q = _rotation(rng)
    return Q @ np.diag(rng.uniform(0.5, 4.0, 3)) @ Q.T


def _forces(rng, x, k):
    return [(x + rng.normal(0.0, 0.6, 3), rng.normal(0.0, 2.0, 3)) for _ in range(k)]


def _state(rng, off_so3: float = 0.0):
    R = _rotation(rng) + off_so3 * rng.normal(size=(3, 3))
    return StateTuple(rng.normal(0.0, 1.0, 3), R, rng.normal(0.0, 1.5, 3), rng.normal(0.0, 1.5, 3))


# =====================================================================================
# The machinery: call the student's function, read what it returns, compare, diagnose
# =====================================================================================

_N = 20                     # random inputs per check
_RTOL, _ATOL = 1e-7, 1e-9


class _BadOutput(Exception):
    def __init__(self, mistake: str, text: str):
        super().__init__(text)
        self.mistake = mistake
        self.text = text


@dataclass
class _Case:
    args: tuple                          # passed to the student's function (as copies)
    names: tuple                         # the names of the arguments, for messages
    expected: object                     # np.ndarray, or a tuple of them
    candidates: Callable = lambda: ()    # -> iterable of (mistake id, wrong value, prefix)
    special: str | None = None           # a mistake id: any failure on this input is that mistake
    kwargs: dict | None = None


@dataclass
class _Spec:
    name: str                            # the student's function
    formula: str                         # shown in the pass line
    slide: str                           # to reread after a generic failure
    labels: tuple | None = None          # the components of a tuple result (None: one array)
    count: str = f"{_N} random inputs"


def _fmt(a, digits: int = 4) -> str:
    """A number, vector, matrix, tuple or list of them on one line (4 significant digits)."""
    if isinstance(a, tuple):
        return "(" + ", ".join(_fmt(v, digits) for v in a) + ")"
    if isinstance(a, list) and any(isinstance(v, tuple) for v in a):
        return "[" + ", ".join(_fmt(v, digits) for v in a) + "]"
    try:
        arr = np.asarray(a, dtype=float)
    except (TypeError, ValueError):
        return repr(a) if len(repr(a)) <= 80 else repr(a)[:77] + "…"
    if arr.ndim == 0:
        return f"{float(arr) + 0.0:.{digits}g}"
    return "[" + ", ".join(_fmt(v, digits) for v in arr) + "]"


def _shown(case: _Case) -> str:
    return ", ".join(f"{n} = {_fmt(v)}" for n, v in zip(case.names, case.args))


def _close(got, want) -> bool:
    if isinstance(want, tuple):
        return isinstance(got, tuple) and len(got) == len(want) and all(_close(g, w) for g, w in zip(got, want))
    if isinstance(got, tuple) or got.shape != want.shape or not np.all(np.isfinite(got)):
        return False
    scale = max(1.0, float(np.abs(want).max())) if want.size else 1.0
    return bool(np.allclose(got, want, rtol=_RTOL, atol=_ATOL * scale))


def _same(a, b) -> bool:
    """Exactly the same content (to detect in-place changes of an input)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        try:
            return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)
        except (TypeError, ValueError):
            return False
    if isinstance(a, (list, tuple)):
        return isinstance(b, (list, tuple)) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    try:
        return bool(a == b)
    except Exception:       # noqa: BLE001
        return False


_LIBRARY_DIRS = tuple({os.path.dirname(__file__), os.path.dirname(os.__file__)} |
                      {sysconfig.get_paths()[k] for k in ("stdlib", "platstdlib", "purelib", "platlib")})


def _where(exc: BaseException) -> str:
    """ ' (in velocity, line 3: return P @ M)' — the last frame of the student's own code."""
    frames = [f for f in traceback.extract_tb(exc.__traceback__)
              if not f.filename.startswith(_LIBRARY_DIRS)]
    if not frames:
        return ""
    f = frames[-1]
    line = f" line {f.lineno}: {f.line.strip()}" if f.line else f" line {f.lineno}"
    return f" (in {f.name},{line})"


def _exc_text(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    text = text[0] if text else ""
    text = text if len(text) <= 200 else text[:197] + "…"
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _not_done(name: str, exc: NotImplementedError) -> str:
    """One line: the function is a stub (or calls one, named)."""
    frames = [f for f in traceback.extract_tb(exc.__traceback__) if not f.filename.startswith(_LIBRARY_DIRS)]
    if len(frames) > 1 and frames[-1].name != frames[0].name:
        return f"○ {name}: not done yet (it calls {frames[-1].name}, which raises NotImplementedError)"
    return f"○ {name}: not done yet (it raises NotImplementedError)"


def _call(fn, args, kwargs=None):
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return fn(*args, **(kwargs or {}))


def _array(out) -> np.ndarray:
    if out is None:
        raise _BadOutput("returned_none", "it returned None — did you forget `return`?")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            arr = np.asarray(out, dtype=float)
    except (TypeError, ValueError):
        raise _BadOutput("not_numbers", f"it returned {_short(out)}, which is not an array of numbers") from None
    return arr


def _tuple(out, labels) -> tuple:
    if out is None:
        raise _BadOutput("returned_none", "it returned None — did you forget `return`?")
    want = f"a tuple ({', '.join(labels)})"
    if len(labels) == 4 and all(hasattr(out, k) for k in "xRPL"):
        items = [out.x, out.R, out.P, out.L]
    elif isinstance(out, (tuple, list)) or (isinstance(out, np.ndarray) and out.ndim >= 1):
        items = list(out)
    else:
        raise _BadOutput("wrong_return", f"it returned {_short(out)}; expected {want}")
    if len(items) != len(labels):
        raise _BadOutput("wrong_return", f"it returned {len(items)} values; expected {len(labels)}: {want}")
    return tuple(_array(v) for v in items)


def _short(obj) -> str:
    text = repr(obj)
    text = text if len(text) <= 80 else text[:77] + "…"
    return f"{type(obj).__name__} {text}" if not isinstance(obj, (list, tuple)) else text


def _shape_problem(got, want, labels) -> str | None:
    if isinstance(want, tuple):
        for g, w, label in zip(got, want, labels):
            if g.shape != w.shape:
                return f"{label} has shape {g.shape}; expected {w.shape}"
        return None
    return None if got.shape == want.shape else f"it returned shape {got.shape}; expected {want.shape}"


def _fail(spec: _Spec, mistake: str, detail: str = "", prefix: str = "") -> CheckResult:
    m = MISTAKES.get(mistake)
    if m is None:           # a generic failure
        text, slide = detail, spec.slide
    else:
        text = prefix + m.text + (f" ({detail})" if detail else "")
        slide = m.slide
    return CheckResult(spec.name, False, mistake, f"✗ {spec.name}: {text}\n   → reread {_slide(slide)}")


def _slide(slide: str) -> str:
    return f"the slide “{slide}”" if slide in SLIDES else slide


def _diagnose(spec: _Spec, case: _Case, got, last_resort=None) -> CheckResult:
    """The student's output differs from the reference: name the mistake.  last_resort(got, case) -> a
    mistake id or None, tried before the generic "wrong result"."""
    if case.special:
        return _fail(spec, case.special, f"on the input {_shown(case)}")
    for mistake, wrong, prefix in case.candidates():
        if _close(got, wrong) and not _close(got, case.expected):
            return _fail(spec, mistake, prefix=prefix)
    shape = _shape_problem(got, case.expected, spec.labels)
    if shape:
        return _fail(spec, "wrong_shape", f"{shape} (on the input {_shown(case)})")
    late = last_resort(got, case) if last_resort else None
    if late:
        return _fail(spec, late)
    nan = " (it contains NaN or inf)" if not all(np.all(np.isfinite(g)) for g in _parts(got)) else ""
    if isinstance(case.expected, tuple):
        wrong = [i for i, (g, w) in enumerate(zip(got, case.expected)) if not _close(g, w)]
        first = wrong[0]
        others = [spec.labels[i] for i in wrong[1:]]
        also = f"; {', '.join(others)} {'is' if len(others) == 1 else 'are'} wrong too" if others else ""
        for mistake, bad, prefix in case.candidates():       # a mistake that explains the first wrong part
            if _close(got[first], bad[first]) and not _close(bad[first], case.expected[first]):
                return _fail(spec, mistake, f"seen in {spec.labels[first]}{also}", prefix=prefix)
        return _fail(spec, "wrong_result",
                     f"wrong result: {spec.labels[first]} should be {_fmt(case.expected[first])}, got "
                     f"{_fmt(got[first])}{nan}{also} — on the input {_shown(case)}")
    return _fail(spec, "wrong_result", f"wrong result: expected {_fmt(case.expected)}, got {_fmt(got)}{nan} — "
                                       f"on the input {_shown(case)}")


def _parts(got):
    return got if isinstance(got, tuple) else (got,)


def _judge(spec: _Spec, fn, cases, accept=None, last_resort=None) -> CheckResult:
    """Run fn on every case; the first failure is diagnosed.  accept(got, case) -> a note: an
    output different from the reference that is right all the same (then the pass line adds the note)."""
    if not callable(fn):
        return CheckResult(spec.name, False, "not_a_function",
                           f"✗ check_{spec.name} takes your function itself: check_{spec.name}({spec.name}), "
                           f"not its result — got {_short(fn)}")
    notes = []
    for case in cases:
        args = copy.deepcopy(case.args)
        try:
            out = _call(fn, args, case.kwargs)
        except NotImplementedError as e:
            return CheckResult(spec.name, False, "not_done", _not_done(spec.name, e))
        except (Exception, SystemExit) as e:        # noqa: BLE001 — a check never raises
            if case.special:
                return _fail(spec, case.special, f"it raised {_exc_text(e)}{_where(e)}")
            return CheckResult(spec.name, False, "error",
                               f"✗ {spec.name} raised {_exc_text(e)}{_where(e)}\n   on the input {_shown(case)}")
        changed = [n for n, a, b in zip(case.names, case.args, args) if not _same(a, b)]
        if changed:
            return _fail(spec, "modified_input", f"it changed {', '.join(changed)}")
        try:
            got = _tuple(out, spec.labels) if spec.labels else _array(out)
        except _BadOutput as b:
            if case.special:
                return _fail(spec, case.special, b.text)
            return _fail(spec, b.mistake, b.text + f" (on the input {_shown(case)})")
        if _close(got, case.expected):
            continue
        note = accept(got, case) if accept else None
        if note:
            notes.append(note)
            continue
        return _diagnose(spec, case, got, last_resort)
    extra = f" ({notes[0]})" if notes else ""
    return CheckResult(spec.name, True, None, f"✓ {spec.name}: {spec.formula} — correct on {spec.count}{extra}")


def _run(spec: _Spec, fn, make_cases, verbose: bool, seed, accept=None, last_resort=None) -> CheckResult:
    try:
        result = _judge(spec, fn, make_cases(np.random.default_rng(seed)), accept, last_resort)
    except Exception as e:      # noqa: BLE001 — a bug in the check must not stop the notebook
        result = CheckResult(spec.name, False, "check_failed",
                             f"✗ check_{spec.name} itself failed ({_exc_text(e)}): please tell your teacher")
    return _print(result, verbose)


# =====================================================================================
# The checks
# =====================================================================================

def check_box_inertia(box_inertia, *, verbose: bool = True, seed: int = 2001) -> CheckResult:
    """box_inertia(mass, size) -> I_body, the 3×3 inertia of a solid box of full sides size = (a, b, c)
    along the body axes x, y, z:

        I_body = M/12 · diag(b² + c², a² + c², a² + b²)
    """
    spec = _Spec("box_inertia", "I_body = M/12 · diag(b² + c², a² + c², a² + b²)", _BOX)

    def cases(rng):
        out = []
        for _ in range(_N):
            M = float(rng.uniform(0.5, 5.0))
            a, b, c = (float(s) for s in rng.uniform(0.1, 2.0, 3))
            moments = M / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])

            def candidates(M=M, a=a, b=b, c=c, moments=moments):
                yield "box_not_squared", M / 12 * np.diag([b + c, a + c, a + b]), ""
                for perm in ((0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
                    yield "box_wrong_pairing", np.diag(moments[list(perm)]), ""
                yield "box_wrong_pairing", M / 12 * np.diag([a * a, b * b, c * c]), ""
                yield "box_missing_twelfth", 12 * np.diag(moments), ""
                yield "box_half_sizes", np.diag(moments) / 4, ""
                yield "box_missing_mass", np.diag(moments) / M, ""
                yield "box_moments_not_matrix", moments, ""
            out.append(_Case((M, (a, b, c)), ("mass", "size"), _ref_box_inertia(M, (a, b, c)), candidates))
        return out
    return _run(spec, box_inertia, cases, verbose, seed)


def check_velocity(velocity, *, verbose: bool = True, seed: int = 2002) -> CheckResult:
    """velocity(P, M) -> v(t) = P(t) / M."""
    spec = _Spec("velocity", "v = P/M", EULER)

    def cases(rng):
        out = []
        for _ in range(_N):
            P, M = rng.normal(0.0, 2.0, 3), float(rng.uniform(0.5, 5.0))
            out.append(_Case((P, M), ("P", "M"), P / M,
                             lambda P=P, M=M: [("velocity_times_mass", P * M, ""), ("velocity_mass_over_P", M / P, "")]))
        return out
    return _run(spec, velocity, cases, verbose, seed)


def check_inverse_inertia(inverse_inertia, *, verbose: bool = True, seed: int = 2003) -> CheckResult:
    """inverse_inertia(R, I_body_inv) -> I⁻¹(t) = R(t) · I⁻¹_body · R(t)ᵀ   (world axes)."""
    spec = _Spec("inverse_inertia", "I⁻¹(t) = R · I⁻¹_body · Rᵀ", EULER)

    def cases(rng):
        out = []
        for _ in range(_N):
            R, Ib = _rotation(rng), _spd(rng)

            def candidates(R=R, Ib=Ib):
                yield "I_body_as_world", Ib, ""
                yield "R_inverse_I_R", R.T @ Ib @ R, ""
                yield "missing_RT", R @ Ib, ""
                yield "inverse_inertia_not_inverted", R @ np.linalg.inv(Ib) @ R.T, ""
                yield "elementwise", R * Ib * R.T, ""
                yield "elementwise", R * Ib @ R.T, ""
                yield "elementwise", R @ Ib * R.T, ""
            out.append(_Case((R, Ib), ("R", "I_body_inv"), _engine_inverse_inertia(R, Ib), candidates))
        return out
    return _run(spec, inverse_inertia, cases, verbose, seed)


def check_angular_velocity(angular_velocity, *, verbose: bool = True, seed: int = 2004) -> CheckResult:
    """angular_velocity(I_inv, L) -> ω(t) = I⁻¹(t) · L(t)."""
    spec = _Spec("angular_velocity", "ω = I⁻¹(t) · L", EULER)

    def cases(rng):
        out = []
        for _ in range(_N):
            I_inv, L = _spd(rng), rng.normal(0.0, 2.0, 3)

            def candidates(I_inv=I_inv, L=L):
                yield "elementwise", I_inv * L, ""
                yield "elementwise", L * np.diag(I_inv), ""
                yield "omega_uses_inertia", np.linalg.solve(I_inv, L), ""
            out.append(_Case((I_inv, L), ("I_inv", "L"), I_inv @ L, candidates))
        return out
    return _run(spec, angular_velocity, cases, verbose, seed)


def _resultant_variants(x, forces):
    """The wrong resultants: (id, (F, τ))."""
    r = np.array([p for p, _ in forces]).reshape(-1, 3)
    f = np.array([q for _, q in forces]).reshape(-1, 3)
    F = f.sum(0)
    yield "tau_sign", (F, np.cross(f, r - x).sum(0))
    yield "lever_arm", (F, np.cross(r, f).sum(0))
    yield "tau_sign_and_lever_arm", (F, np.cross(f, r).sum(0))
    if len(forces) > 1:
        yield "last_force_only", (f[-1], np.cross(r[-1] - x, f[-1]))
    yield "F_tau_swapped", (np.cross(r - x, f).sum(0), F)


def check_resultants(resultants, *, verbose: bool = True, seed: int = 2005) -> CheckResult:
    """resultants(x, forces) -> (F, τ) for forces = [(r₁, F₁), (r₂, F₂), …] (world points, world forces):

        F = Σ Fᵢ          τ = Σ (rᵢ − x(t)) ∧ Fᵢ        (slide "Les Formules": les résultantes)
    """
    spec = _Spec("resultants", "F = Σ Fᵢ, τ = Σ (rᵢ − x) ∧ Fᵢ", FORMULES, labels=("F", "τ"))

    def cases(rng):
        out = []
        for i in range(_N):
            x = rng.normal(0.0, 1.0, 3)
            k = 0 if i == _N - 1 else int(rng.integers(2, 5)) if i < 10 else int(rng.integers(1, 5))
            forces = _forces(rng, x, k)
            expected = tuple(np.asarray(a, float) for a in _ref_resultants(x, forces))
            out.append(_Case((x, forces), ("x", "forces"), expected,
                             lambda x=x, forces=forces: ((m, v, "") for m, v in _resultant_variants(x, forces)),
                             special="empty_forces" if k == 0 else None))
        return out
    return _run(spec, resultants, cases, verbose, seed)


def _dxdt_variants(M, Ib, X, forces):
    """The wrong dX/dt: (id, (dx, dR, dP, dL), prefix) — the slides' formula with one piece wrong."""
    x, R, P, L = _as_floats(X)
    F, tau = (np.asarray(a, float) for a in _ref_resultants(x, forces))
    I_inv = R @ Ib @ R.T
    v, omega = P / M, I_inv @ L
    S = star(omega)
    SR = S @ R
    yield "R_dot_order", (v, R @ S, F, tau), ""
    yield "R_dot_missing_R", (v, S, F, tau), ""
    yield "omega_star_sign", (v, -SR, F, tau), ""
    yield "omega_from_P", (v, star(I_inv @ P) @ R, F, tau), ""
    yield "v_from_L", (L / M, SR, F, tau), ""
    yield "P_L_swapped", (L / M, star(I_inv @ P) @ R, F, tau), ""
    yield "dx_is_P", (P, SR, F, tau), ""
    yield "dP_is_acceleration", (v, SR, F / M, tau), ""
    yield "dL_is_angular_acceleration", (v, SR, F, I_inv @ tau), ""
    # a derived quantity computed wrongly (the student's velocity / inverse_inertia / angular_velocity)
    yield "velocity_times_mass", (P * M, SR, F, tau), "v: "
    for mistake, J in (("I_body_as_world", Ib), ("R_inverse_I_R", R.T @ Ib @ R), ("missing_RT", R @ Ib),
                       ("inverse_inertia_not_inverted", R @ np.linalg.inv(Ib) @ R.T)):
        yield mistake, (v, star(J @ L) @ R, F, tau), "I⁻¹(t): "
    yield "omega_uses_inertia", (v, star(np.linalg.solve(I_inv, L)) @ R, F, tau), "ω: "
    # the resultants computed wrongly (the student's resultants)
    for mistake, (F_bad, tau_bad) in _resultant_variants(x, forces):
        yield mistake, (v, SR, F_bad, tau_bad), "F, τ: "


def _dxdt_cases(rng, n=_N, off_so3=0.0, with_dt=False):
    out = []
    for _ in range(n):
        M, Ib = float(rng.uniform(0.5, 5.0)), _spd(rng)
        X = _state(rng, off_so3)
        forces = _forces(rng, X.x, int(rng.integers(2, 4)))
        args = (M, Ib, X, forces) + ((float(rng.uniform(0.02, 0.1)),) if with_dt else ())
        out.append(args)
    return out


def check_dxdt(dxdt, *, verbose: bool = True, seed: int = 2006) -> CheckResult:
    """dxdt(M, I_body_inv, X, forces) -> (v, ω* R, F, τ), the rates of X = (x, R, P, L):

        d/dt (x, R, P, L) = (v(t), ω(t)* R(t), F(t), τ(t))          (slide "Les Formules")
        v = P/M,  I⁻¹(t) = R I⁻¹_body Rᵀ,  ω = I⁻¹(t) L,  F = Σ Fᵢ,  τ = Σ (rᵢ − x) ∧ Fᵢ
    """
    spec = _Spec("dxdt", "dX/dt = (v, ω* R, F, τ)", FORMULES, labels=("dx/dt", "dR/dt", "dP/dt", "dL/dt"))

    def cases(rng):
        return [_Case(args, ("M", "I_body_inv", "X", "forces"), _ref_dxdt(*args),
                      lambda args=args: _dxdt_variants(*args))
                for args in _dxdt_cases(rng)]
    return _run(spec, dxdt, cases, verbose, seed)


def _euler_variants(M, Ib, X, forces, dt):
    """The wrong Euler steps: (id, X(t+Δt), prefix)."""
    x, R, P, L = _as_floats(X)
    v, R_dot, F, tau = _ref_dxdt(M, Ib, X, forces)
    x1, R1, P1, L1 = x + dt * v, R + dt * R_dot, P + dt * F, L + dt * tau
    yield "R_not_updated", (x1, R, P1, L1), ""
    yield "x_not_updated", (x, R1, P1, L1), ""
    yield "P_not_updated", (x1, R1, P, L1), ""
    yield "L_not_updated", (x1, R1, P1, L), ""
    yield "no_dt", (x + v, R + R_dot, P + F, L + tau), ""
    x_new_P = x + dt * P1 / M                                       # semi-implicit: the new momenta move x, R
    R_new_L = R + dt * star(R @ Ib @ R.T @ L1) @ R
    yield "semi_implicit", (x_new_P, R1, P1, L1), ""
    yield "semi_implicit", (x1, R_new_L, P1, L1), ""
    yield "semi_implicit", (x_new_P, R_new_L, P1, L1), ""
    for mistake, d, prefix in _dxdt_variants(M, Ib, X, forces):     # a wrong dX/dt, stepped correctly
        yield mistake, tuple(a + dt * b for a, b in zip((x, R, P, L), d)), "dX/dt: " + prefix


_STATE_LABELS = ("x(t+Δt)", "R(t+Δt)", "P(t+Δt)", "L(t+Δt)")


def check_euler_step(euler_step, *, verbose: bool = True, seed: int = 2007) -> CheckResult:
    """euler_step(M, I_body_inv, X, forces, dt) -> X(t+Δt), the slides' explicit Euler:

        X(t + Δt) = X(t) + Δt · dX/dt(t) = (x + Δt v,  R + Δt ω* R,  P + Δt F,  L + Δt τ)

    every rate taken at t (slide "Evolution temporelle (Euler)"; "Itération i").
    """
    spec = _Spec("euler_step", "X(t+Δt) = X(t) + Δt · dX/dt", EULER, labels=_STATE_LABELS)

    def cases(rng):
        return [_Case(args, ("M", "I_body_inv", "X", "forces", "dt"), tuple(_ref_euler_step(*args)),
                      lambda args=args: _euler_variants(*args))
                for args in _dxdt_cases(rng, with_dt=True)]
    return _run(spec, euler_step, cases, verbose, seed)


def _is_rotation(Q) -> bool:
    return bool(np.all(np.isfinite(Q)) and np.abs(Q.T @ Q - np.eye(3)).max() < 1e-9
                and abs(np.linalg.det(Q) - 1.0) < 1e-9)


def check_project_so3(project_so3, *, verbose: bool = True, seed: int = 2008) -> CheckResult:
    """project_so3(R) -> the rotation nearest to R (R a little off SO(3), as after Euler steps):

        R = U Σ Vᵀ  (np.linalg.svd)   →   U Vᵀ
    """
    spec = _Spec("project_so3", "R ← U Vᵀ, the nearest rotation", BIBLIO)

    def cases(rng):
        out = []
        for _ in range(_N):
            R = _rotation(rng) + 0.08 * rng.normal(size=(3, 3))
            Q = _engine_project_so3(R)

            def candidates(R=R, Q=Q):
                U, _, Vt = np.linalg.svd(R)
                yield "svd_V_transposed", U @ Vt.T, ""
                yield "svd_not_projected", R, ""
                yield "columns_normalized", R / np.linalg.norm(R, axis=0), ""
                yield "columns_normalized", R / np.linalg.norm(R, axis=1)[:, None], ""
                yield "projection_transposed", Q.T, ""
            out.append(_Case((R,), ("R",), Q, candidates))
        return out

    def accept(got, case):
        R, Q = case.args[0], case.expected
        if got.shape == (3, 3) and _is_rotation(got) and np.linalg.norm(got - R) <= 1.5 * np.linalg.norm(Q - R):
            return "a rotation close to R, though not the nearest one — Gram–Schmidt? Fine for this fix"
        return None

    def last_resort(got, case):
        if got.shape != (3, 3):
            return None
        return "not_nearest" if _is_rotation(got) else "not_a_rotation"

    return _run(spec, project_so3, cases, verbose, seed, accept, last_resort)


def _print(result: CheckResult, verbose: bool) -> CheckResult:
    if verbose:
        print(result.message)
        result._printed_in = _execution_count()
    return result


def check_euler_step_projected(euler_step_projected, *, verbose: bool = True, seed: int = 2009) -> CheckResult:
    """euler_step_projected(M, I_body_inv, X, forces, dt): the Euler step, then R(t+Δt) ← its nearest
    rotation U Vᵀ (the fix for R drifting off SO(3))."""
    spec = _Spec("euler_step_projected", "Euler step, then R ← U Vᵀ", BIBLIO, labels=_STATE_LABELS)

    def variants(M, Ib, X, forces, dt):
        x, R, P, L = _ref_euler_step(M, Ib, X, forces, dt)
        yield "step_not_projected", (x, R, P, L), ""
        x0, R0, P0, L0 = _as_floats(X)
        yield "projected_before", tuple(_ref_euler_step(M, Ib, (x0, _engine_project_so3(R0), P0, L0), forces, dt)), ""
        for mistake, (xb, Rb, Pb, Lb), prefix in _euler_variants(M, Ib, X, forces, dt):
            yield mistake, (xb, _engine_project_so3(Rb), Pb, Lb), "the Euler step: " + prefix

    def cases(rng):
        return [_Case(args, ("M", "I_body_inv", "X", "forces", "dt"), tuple(_ref_euler_step_projected(*args)),
                      lambda args=args: variants(*args))
                for args in _dxdt_cases(rng, off_so3=0.05, with_dt=True)]
    return _run(spec, euler_step_projected, cases, verbose, seed)


# --- simulate: the loop, checked by watching what it calls --------------------------

class _Recorder:
    """forces_at and step as the student's simulate sees them; they record how they are called."""

    def __init__(self, b, F0, G, step):
        self.b, self.F0, self.G, self._step = b, F0, G, step
        self.times, self.states, self.steps = [], [], 0

    def forces_at(self, t, X):
        """Forces attached to body points bᵢ: rᵢ = x + R bᵢ, Fᵢ(t) = F0ᵢ + t Gᵢ."""
        if isinstance(t, (tuple, list, np.ndarray)) and not np.ndim(t) == 0:
            raise TypeError("forces_at(t, X) takes the time t (a number) first, then the state X")
        x, R, P, L = _as_floats(X)
        self.times.append(float(t))
        self.states.append((x.copy(), R.copy(), P.copy(), L.copy()))
        return [(x + R @ bi, F0 + float(t) * G) for bi, F0, G in zip(self.b, self.F0, self.G)]

    def step(self, M, I_body_inv, X, forces, dt):
        self.steps += 1
        return self._step(M, I_body_inv, X, forces, dt)


def check_simulate(simulate, *, verbose: bool = True, seed: int = 2010) -> CheckResult:
    """simulate(M, I_body_inv, X0, forces_at, dt, n_steps, step=euler_step) -> (x, R, P, L), the slides'
    iterations repeated:

        X₀ given;  X_{k+1} = step(M, I_body_inv, X_k, forces_at(t_k, X_k), dt),  t_k = k · Δt
        x, R, P, L: arrays of the n_steps + 1 states X₀ … X_n  ((n+1, 3), (n+1, 3, 3), (n+1, 3), (n+1, 3))

    The check passes its own step (the reference Euler step, or a projected one) and forces_at, and
    watches how they are called.
    """
    spec = _Spec("simulate", "X_{k+1} = step(X_k), forces_at(k·Δt, X_k), n_steps + 1 states",
                 ITERATION_2, labels=("x", "R", "P", "L"), count="6 random runs")
    try:
        result = _judge_simulate(spec, simulate, np.random.default_rng(seed))
    except Exception as e:      # noqa: BLE001
        result = CheckResult(spec.name, False, "check_failed",
                             f"✗ check_simulate itself failed ({_exc_text(e)}): please tell your teacher")
    return _print(result, verbose)


def _judge_simulate(spec: _Spec, simulate, rng) -> CheckResult:
    if not callable(simulate):
        return CheckResult(spec.name, False, "not_a_function",
                           f"✗ check_simulate takes your function itself: check_simulate(simulate), not its result"
                           f" — got {_short(simulate)}")
    for run in range(6):
        M, Ib = float(rng.uniform(0.5, 5.0)), _spd(rng)
        X0 = _state(rng)
        k = int(rng.integers(1, 3))
        b, F0, G = rng.normal(0, 0.5, (k, 3)), rng.normal(0, 2.0, (k, 3)), rng.normal(0, 5.0, (k, 3))
        dt, n = float(rng.uniform(0.01, 0.05)), int(rng.integers(6, 12))
        ref_step = _ref_euler_step if run % 2 == 0 else _ref_euler_step_projected
        rec = _Recorder(b, F0, G, ref_step)
        expected = _ref_simulate(M, Ib, X0, _Recorder(b, F0, G, ref_step).forces_at, dt, n, ref_step)
        args = (M, Ib, copy.deepcopy(X0), rec.forces_at, dt, n)
        shown = f"M = {_fmt(M)}, X0 = {_fmt(tuple(X0))}, dt = {_fmt(dt)}, n_steps = {n}"
        try:
            out = _call(simulate, args, {"step": rec.step})
        except NotImplementedError as e:
            return CheckResult(spec.name, False, "not_done", _not_done(spec.name, e))
        except TypeError as e:
            if "step" in str(e) and "argument" in str(e):
                return _fail(spec, "no_step_parameter", _exc_text(e))
            return CheckResult(spec.name, False, "error", f"✗ simulate raised {_exc_text(e)}{_where(e)}\n   on {shown}")
        except (Exception, SystemExit) as e:        # noqa: BLE001
            return CheckResult(spec.name, False, "error", f"✗ simulate raised {_exc_text(e)}{_where(e)}\n   on {shown}")
        if not _same(tuple(X0), tuple(args[2])):
            return _fail(spec, "modified_input", "it changed X0")
        if isinstance(out, (list, tuple)) and len(out) in (n, n + 1) and all(
                isinstance(s, (list, tuple)) and len(s) == 4 for s in out):
            return _fail(spec, "wrong_return", f"it returned a list of {len(out)} states: return four arrays "
                                               f"(x, R, P, L), e.g. x = np.array([X[0] for X in states])")
        try:
            got = _tuple(out, spec.labels)
        except _BadOutput as e:
            return _fail(spec, e.mistake, e.text.replace("expected a tuple", "expected the arrays"))
        if rec.steps == 0:
            return _fail(spec, "ignores_step")
        if _close(got, expected):
            continue
        lengths = {len(g) if g.ndim else 0 for g in got}
        if lengths == {n}:
            if _close(got, tuple(e[1:] for e in expected)):
                return _fail(spec, "missing_initial")
            if _close(got, tuple(e[:-1] for e in expected)):
                return _fail(spec, "missing_final")
        if lengths != {n + 1}:
            got_n = " and ".join(str(v) for v in sorted(lengths))
            return _fail(spec, "wrong_length", f"got {got_n} states for n_steps = {n}")
        shape = _shape_problem(got, expected, spec.labels)
        if shape:
            return _fail(spec, "wrong_shape", shape)
        if all(np.all(g == g[-1]) for g in got) and any(not np.allclose(e[0], e[-1]) for e in expected):
            return _fail(spec, "aliasing")
        times = np.array(rec.times)
        want_t = dt * np.arange(len(times))
        if len(times) and not np.allclose(times, want_t, rtol=0, atol=1e-9):
            return _fail(spec, "wrong_time", f"your times: {_fmt(times[:4])}…, expected {_fmt(want_t[:4])}…")
        for i, state in enumerate(rec.states[: n]):
            if not _close(tuple(state), tuple(e[i] for e in expected)):
                return _fail(spec, "stale_state", f"at step {i} it got a state other than X_{i}")
        if rec.steps != n:
            return _fail(spec, "step_count", f"it was called {rec.steps} times for n_steps = {n}")
        for i, label in enumerate(spec.labels):
            if not _close(got[i], expected[i]):
                k = int(np.argmax([not _close(g, e) for g, e in zip(got[i], expected[i])]))
                return _fail(spec, "wrong_result", f"wrong result: {label} differs first at state {k}: expected "
                                                   f"{_fmt(expected[i][k])}, got {_fmt(got[i][k])} — on {shown}")
    return CheckResult(spec.name, True, None, f"✓ simulate: {spec.formula} — correct on {spec.count}")


# =====================================================================================
# The pushed box: the student's code when it is ready, else the reference engine
# =====================================================================================

class _Push:
    """F(t) = force while t < t_push (a hair earlier, so that t += dt rounding never adds a step), then 0."""

    def __init__(self, force, t_push: float):
        self.force, self.t_push = np.asarray(force, dtype=float), float(t_push)

    def on(self, t) -> bool:
        return t < self.t_push - 1e-9

    def __call__(self, t) -> np.ndarray:
        return self.force if self.on(t) else np.zeros(3)

    def __repr__(self) -> str:
        return f"push {self.force.tolist()} N for 0 <= t < {self.t_push:g} s"


@dataclass(frozen=True)
class PushedBox:
    """The slides' box (1 kg, 0.3 × 0.2 × 0.05 m), at rest, pushed at a corner by F = (0, 0, 10) N for
    0.1 s, then tumbling freely (no gravity).

    M, I_body, I_body_inv: the constants;  X0: the StateTuple at rest;  push: F(t);
    forces_at(t, X): [(rᵢ, Fᵢ)] with the corner rᵢ = x + R b (b in body axes) — the force stops at t = 0.1 s;
    scene, X0_state: the same problem for the reference engine (rbcourse.simulate).
    """
    M: float
    size: tuple
    I_body: np.ndarray
    I_body_inv: np.ndarray
    corner: np.ndarray
    push: _Push
    X0: StateTuple
    scene: Scene
    X0_state: State

    def forces_at(self, t, X):
        """The forces at time t on the state X: the push at the corner r = x + R b while it lasts, then none."""
        if not self.push.on(t):
            return []
        x, R = np.asarray(X[0], float), np.asarray(X[1], float)
        return [(x + R @ self.corner, self.push.force)]


def pushed_box(mass: float = 1.0, size=(0.3, 0.2, 0.05), push=(0.0, 0.0, 10.0), t_push: float = 0.1) -> PushedBox:
    """The box of the notebook: pushed at its corner (a/2, b/2, c/2) by `push` (N, world) for t_push seconds."""
    body = RigidBody.box(mass, size)
    corner = np.array(size, dtype=float) / 2
    F = _Push(push, t_push)
    scene = Scene(body, [PointForce(corner, F, frame="world")], name="pushed box")
    X0 = StateTuple(np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3))
    return PushedBox(body.mass, tuple(size), np.array(body.I_body), np.array(body.I_body_inv), corner, F, X0,
                     scene, State.at_rest())


def simulate_or_reference(simulate, step, t_end: float, dt: float, *, reference: str = "euler",
                          problem: PushedBox | None = None):
    """The pushed box over [0, t_end] with steps dt, as a rbcourse Trajectory (for viewer and plots).

    Your simulate(..., step=step) when both pass their checks (check_simulate, and check_euler_step —
    or check_euler_step_projected when reference = "euler_project"); otherwise the reference engine,
    rbcourse.simulate(scene, X0, t_end, dt, method=reference, on_divergence="stop").  Prints which one ran.

    A run that blows up (the slides' Euler does, after about 3 s at dt = 1 ms) is part of the lesson,
    not an error: either way the trajectory ends at the last good state, is marked diverged
    (traj.diverged, traj.divergence, traj.outcome: "diverged at t = …"), and a line says so.
    """
    from ..simulate import simulate as engine_simulate
    from ..trajectory import Divergence, Trajectory, first_blow_up

    box = problem or pushed_box()
    n = max(1, round(t_end / dt))
    step_check = check_euler_step_projected if reference == "euler_project" else check_euler_step
    ready = [check_simulate(simulate, verbose=False), step_check(step, verbose=False)]
    step_name = getattr(step, "__name__", "step")
    waiting = [r for r in ready if not r.passed]
    if waiting:
        r = waiting[0]
        why = f"{r.name}() is not done yet" if r.mistake == "not_done" else f"{r.name}() does not pass its check yet"
    else:
        try:
            out = _call(simulate, (box.M, box.I_body_inv, box.X0, box.forces_at, dt, n), {"step": step})
            x, R, P, L = _tuple(out, ("x", "R", "P", "L"))
            t = dt * np.arange(len(x))
            last, reason = first_blow_up([("x", x), ("R", R), ("P", P), ("L", L)])   # as the engine checks
            if last == 0:
                raise _BadOutput("not_finite", f"its first state is already {reason}")
            divergence = Divergence(float(t[last]), last, reason) if last < len(t) else None
            traj = Trajectory(t[:last], x[:last], R[:last], P[:last], L[:last], scene=box.scene,
                              method=f"{reference} (your code)", dt=dt, divergence=divergence)
            print(f"your simulate() with {step_name}(): {n} steps of Δt = {dt:g} s, t = 0 → {n * dt:g} s")
            if traj.diverged:
                print(f"   {traj.outcome}; kept up to t = {traj.t[-1]:.4g} s")
            return traj
        except Exception as e:      # noqa: BLE001
            why = f"your simulate() raised {_exc_text(e)}"
    print(f"{why} → the reference engine instead: rbcourse.simulate(scene, X0, t_end={n * dt:g}, dt={dt:g}, "
          f"method={reference!r})")
    traj = engine_simulate(box.scene, box.X0_state, n * dt, dt, method=reference, on_divergence="stop")
    if traj.diverged:
        print(f"   {traj.outcome}; kept up to t = {traj.t[-1]:.4g} s")
    return traj


def show_iterations(euler_step, dt: float = 0.01, iterations: int = 2, problem: PushedBox | None = None) -> None:
    """The slides' "Itération 1" and "Itération 2" on the pushed box, from rest, with your euler_step
    (the reference step if it does not pass its check yet): prints X after each iteration."""
    box = problem or pushed_box()
    mine = check_euler_step(euler_step, verbose=False).passed
    step = euler_step if mine else _ref_euler_step
    print("with your euler_step" if mine else "with the reference Euler step (your euler_step is not ready yet)")
    X = box.X0
    num = lambda v: _fmt(v, 6)                                      # noqa: E731
    vec = lambda a: _fmt(np.asarray(a), 6)                          # noqa: E731
    for i in range(1, iterations + 1):
        forces = box.forces_at((i - 1) * dt, X)
        F, tau = _ref_resultants(X[0], forces) if forces else (np.zeros(3), np.zeros(3))
        Y = _as_floats(_call(step, (box.M, box.I_body_inv, X, forces, dt)))
        x0, R0 = _as_floats(X)[:2]
        print(f"● Itération {i}  (t = {num((i - 1) * dt)} → {num(i * dt)} s):  F = {vec(F)},  τ = {vec(tau)}")
        print(f"    x(t+Δt) = {vec(Y[0])}" + ("   unchanged" if np.array_equal(Y[0], x0) else "   moved"))
        print(f"    R(t+Δt) = {vec(Y[1])}" + ("   unchanged" if np.array_equal(Y[1], R0) else "   turned"))
        print(f"    P(t+Δt) = {vec(Y[2])}")
        print(f"    L(t+Δt) = {vec(Y[3])}")
        X = StateTuple(*Y)
