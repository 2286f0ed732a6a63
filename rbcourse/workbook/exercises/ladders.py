"""The probing ladders of the checks (probing.py): for each function, its inputs from the simplest to the general
one, each rung adding one feature to the ones below it — the first rung that breaks the student's function
names what breaks it ("as soon as R is not the identity", "as soon as a force acts off the barycentre", …).

    BOX:        M = 1, a cube of side 1 → a side ≠ 1 → three different sides → M ≠ 1
    VELOCITY:   P along x, M = 1 → P any → M ≠ 1
    INVERSE:    R = I, I⁻¹_body diagonal → R about z → R any → I⁻¹_body full → R off SO(3) as Euler leaves it
    OMEGA:      I⁻¹ = 1 → diagonal → full
    RESULTANTS: no force → one at the barycentre → off it → x ≠ 0 → two forces → four
    STATE:      at rest, nothing acting → P ≠ 0 → x ≠ 0 → M ≠ 1 → (Δt ≠ 0.01) → L ≠ 0 → I⁻¹_body ≠ 1 → R any →
                I⁻¹_body full → a force at the barycentre → off it → several → R off SO(3) → X a plain tuple → a list
    PROJECTION: R a rotation → about z, scaled → R off SO(3) as Euler leaves it → det(U Vᵀ) = −1
"""
from __future__ import annotations

import itertools

import numpy as np

from ...rotation import exp_so3, project_so3
from .harness import drifted_rotation, random_rotation, random_spd
from .probing import Rung
from .reference import StateTuple

DT = 0.01          # the notebook's step for the first rungs (then another)


def _about_z(rng):
    return exp_so3(np.array([0.0, 0.0, rng.uniform(0.3, 2.5)]))


def _diag(rng):
    return np.diag(rng.uniform(0.5, 4.0, 3))


def _vector(rng, scale=1.5):
    return rng.normal(0.0, scale, 3)


# ---- the inputs as a function that misses a feature reads them (Rung.alts)

def _set(i, value):
    """args with argument i replaced by value(old)."""
    return lambda args: args[:i] + (value(args[i]),) + args[i + 1:]


def _in_state(part, value):
    """args (M, I_body_inv, X, forces[, dt]) with X's part (0 x, 1 R, 2 P, 3 L) replaced by value(old)."""
    def alter(args):
        X = list(args[2])
        X[part] = value(X[part])
        return args[:2] + (StateTuple(*X),) + args[3:]
    return alter


def _forces_in(i, keep):
    """args with the list of forces (argument i) cut to keep(forces) (its first one, its last one)."""
    return _set(i, keep)


def _mass_1(i):
    return ("alt_mass_ignored", _set(i, lambda M: 1.0))


def _first_last(i):
    return (("alt_first_force", _forces_in(i, lambda f: f[:1])), ("alt_last_force", _forces_in(i, lambda f: f[-1:])))


def _diagonal(i, key):
    return (key, _set(i, lambda A: np.diag(np.diag(A))))


# ---- box_inertia(mass, size), velocity(P, M), inverse_inertia(R, I_body_inv), angular_velocity(I_inv, L)

BOX = (
    Rung("simplest_box", lambda rng: (1.0, (1.0, 1.0, 1.0))),
    Rung("side_not_1", lambda rng: (1.0, (float(rng.uniform(0.2, 0.8)),) * 3)),
    Rung("sides_differ", lambda rng: (1.0, tuple(float(s) for s in rng.uniform(0.1, 2.0, 3)))),
    Rung("mass_not_1", lambda rng: (float(rng.uniform(1.5, 5.0)), tuple(float(s) for s in rng.uniform(0.1, 2.0, 3))),
         (_mass_1(0),)),
)

VELOCITY = (
    Rung("simplest_velocity", lambda rng: (np.array([rng.uniform(0.5, 2.0), 0.0, 0.0]), 1.0)),
    Rung("P_any", lambda rng: (_vector(rng), 1.0)),
    Rung("mass_not_1", lambda rng: (_vector(rng), float(rng.uniform(1.5, 5.0))), (_mass_1(1),)),
    Rung("P_tiny", lambda rng: (1e-14 * _vector(rng), float(rng.uniform(1.5, 5.0)))),
)

INVERSE = (
    Rung("simplest_inverse", lambda rng: (np.eye(3), _diag(rng))),
    Rung("R_about_z", lambda rng: (_about_z(rng), _diag(rng))),
    Rung("R_any", lambda rng: (random_rotation(rng), _diag(rng))),
    Rung("inertia_full", lambda rng: (random_rotation(rng), random_spd(rng)), (_diagonal(1, "alt_body_diagonal"),)),
    Rung("R_off_so3", lambda rng: (drifted_rotation(rng), random_spd(rng)),
         (("alt_R_as_rotation", _set(0, project_so3)),)),
)

OMEGA = (
    Rung("simplest_omega", lambda rng: (np.eye(3), _vector(rng))),
    Rung("inertia_diagonal", lambda rng: (_diag(rng), _vector(rng))),
    Rung("inertia_full", lambda rng: (random_spd(rng), _vector(rng)), (_diagonal(0, "alt_world_diagonal"),)),
    Rung("L_tiny", lambda rng: (random_spd(rng), 1e-12 * _vector(rng))),
    Rung("L_huge", lambda rng: (random_spd(rng), 1e4 * _vector(rng))),
)


# ---- resultants(x, forces)

def _forces(rng, x, k, at_centre=False):
    return [((x.copy() if at_centre else x + rng.normal(0.0, 0.6, 3)), _vector(rng, 2.0)) for _ in range(k)]


RESULTANTS = (
    Rung("no_force", lambda rng: (np.zeros(3), [])),
    Rung("force_at_centre", lambda rng: (np.zeros(3), _forces(rng, np.zeros(3), 1, at_centre=True))),
    Rung("force_off_centre", lambda rng: (np.zeros(3), _forces(rng, np.zeros(3), 1))),
    Rung("x_not_0", lambda rng: ((x := _vector(rng, 1.0)), _forces(rng, x, 1)),
         (("alt_x_ignored", _set(0, np.zeros_like)),)),
    Rung("two_forces", lambda rng: ((x := _vector(rng, 1.0)), _forces(rng, x, 2)), _first_last(1)),
    Rung("four_forces", lambda rng: ((x := _vector(rng, 1.0)), _forces(rng, x, 4)), _first_last(1)),
    Rung("same_force_twice", lambda rng: ((x := _vector(rng, 1.0)), (f := _forces(rng, x, 2)) + f[:1])),
    Rung("short_lever", lambda rng: ((x := _vector(rng, 1.0)), [(x + 1e-4 * _vector(rng, 1.0), _vector(rng, 2.0))])),
    Rung("tiny_forces", lambda rng: ((x := _vector(rng, 1.0)), [(r, 1e-8 * F) for r, F in _forces(rng, x, 3)])),
)


# ---- dxdt(M, I_body_inv, X, forces), euler_step(…, dt), euler_step_projected(…, dt)

STATE_FEATURES = ("simplest_state", "P_not_0", "x_not_0", "mass_not_1", "dt_not_default", "L_not_0",
                  "inertia_not_1", "R_any", "inertia_full", "force_at_centre", "force_off_centre", "several_forces",
                  "R_off_so3", "X_plain_tuple", "X_list")
"""The state ladder's features, in order: each rung has every feature before it."""
VARIATIONS = ("same_force_twice", "tiny_forces", "fast_spin", "slow_spin", "long_step", "far_away")
"""Then rungs of one variation each, on the general input (every feature above): a force given twice, forces of
1e-8 N, a fast spin, a slow one, a long step (0.5 s), the body far away and fast."""


def _state_input(rng, level: int, with_dt: bool, variation: str | None = None) -> tuple:
    """The arguments with the first `level` + 1 features of STATE_FEATURES on, and one of VARIATIONS."""
    on = set(STATE_FEATURES[: level + 1]) | {variation}
    M = float(rng.uniform(1.5, 5.0)) if "mass_not_1" in on else 1.0
    Ib = random_spd(rng) if "inertia_full" in on else _diag(rng) if "inertia_not_1" in on else np.eye(3)
    x = _vector(rng, 1.0) if "x_not_0" in on else np.zeros(3)
    R = drifted_rotation(rng) if "R_off_so3" in on else random_rotation(rng) if "R_any" in on else np.eye(3)
    P = _vector(rng) if "P_not_0" in on else np.zeros(3)
    L = _vector(rng) * (150.0 if "fast_spin" in on else 1e-4 if "slow_spin" in on else 1.0) if "L_not_0" in on \
        else np.zeros(3)
    if "far_away" in on:                         # 1 km away, at some hundred m/s
        x, P = x + 1e3, 300.0 * P
    k = 3 if "several_forces" in on else 1 if "force_at_centre" in on else 0
    forces = _forces(rng, x, k, at_centre="force_off_centre" not in on)
    if "same_force_twice" in on:
        forces.append((forces[0][0].copy(), forces[0][1].copy()))
    if "tiny_forces" in on:
        forces = [(r, 1e-8 * F) for r, F in forces]
    X = StateTuple(x, R, P, L)
    X = list(X) if "X_list" in on else tuple(X) if "X_plain_tuple" in on else X
    dt = 0.5 if "long_step" in on else float(rng.uniform(0.02, 0.08)) if "dt_not_default" in on else DT
    return (M, Ib, X, forces) + ((dt,) if with_dt else ())


STATE_ALTS = {
    "mass_not_1": (_mass_1(0),),
    "x_not_0": (("alt_x_ignored", _in_state(0, np.zeros_like)),),
    "dt_not_default": (("alt_dt_fixed", _set(4, lambda dt: DT)),),
    "inertia_full": (_diagonal(1, "alt_body_diagonal"),),
    "several_forces": _first_last(3),
    "R_off_so3": (("alt_R_as_rotation", _in_state(1, project_so3)),),
}
"""The state ladder's alts, by feature."""


def state_ladder(with_dt: bool) -> tuple:
    """The state ladder (Δt ≠ 0.01 only where there is a Δt)."""
    top = len(STATE_FEATURES) - 1
    return tuple(Rung(f, lambda rng, level=level: _state_input(rng, level, with_dt), STATE_ALTS.get(f, ()))
                 for level, f in enumerate(STATE_FEATURES) if with_dt or f != "dt_not_default") + tuple(
        Rung(v, lambda rng, v=v: _state_input(rng, top, with_dt, v)) for v in VARIATIONS if with_dt or v != "long_step")


STATE = state_ladder(False)
STEP = state_ladder(True)


# ---- project_so3(R)

def _reflected(rng):
    """R with det(U Vᵀ) = −1: the nearest rotation flips U's last column."""
    s = np.sort(rng.uniform(0.2, 1.2, 3))[::-1] * np.array([1.0, 1.0, -1.0])
    return random_rotation(rng) @ np.diag(s) @ random_rotation(rng)


PROJECTION = (
    Rung("simplest_projection", lambda rng: (random_rotation(rng),)),
    Rung("scaled_rotation", lambda rng: (float(rng.uniform(1.05, 1.5)) * _about_z(rng),)),
    Rung("R_off_so3", lambda rng: (drifted_rotation(rng),)),
    Rung("R_far_off", lambda rng: (random_rotation(rng) + 0.08 * rng.normal(size=(3, 3)),)),
    Rung("reflection", lambda rng: (_reflected(rng),)),
)


# ---- other formulas a probe may find (Spec.formulas): the products the inputs allow, named

def _products(named, length: int = 3):
    """(text, value) of every product of 1 to `length` of the named matrices ("R · I⁻¹_body · Rᵀ", …)."""
    for k in range(1, length + 1):
        for combo in itertools.product(named, repeat=k):
            value = combo[0][1]
            for _, m in combo[1:]:
                value = value @ m
            yield " · ".join(n for n, _ in combo), value


def inverse_formulas(R, Ib):
    """What inverse_inertia may compute instead of R · I⁻¹_body · Rᵀ: products of R, Rᵀ, R⁻¹, I⁻¹_body, I_body."""
    named = [("R", R), ("Rᵀ", R.T), ("R⁻¹", np.linalg.inv(R)), ("I⁻¹_body", Ib), ("I_body", np.linalg.inv(Ib))]
    return _products(named)


def omega_formulas(I_inv, L):
    """What angular_velocity may compute instead of I⁻¹(t) · L."""
    yield "L / diag(I⁻¹(t))", L / np.diag(I_inv)
    yield "diag(I⁻¹(t)) · L (element by element)", np.diag(I_inv) * L
    yield "I(t) · L = np.linalg.inv(I⁻¹(t)) @ L", np.linalg.inv(I_inv) @ L
    yield "L · I⁻¹(t) (L @ I_inv)", L @ I_inv
    yield "I⁻¹(t) · L summed over rows", I_inv.sum(0) * L


# ---- the ends of the scales (Spec.scales): the units of a small or a large body, far away — each a case of its check
# (after its random ones) and a rung of its ladder. A threshold ("below 1e-9 it is zero"), a clamp, a clean-up of
# small numbers or a sum that cancels far from the origin shows there; the right formula does not care.

def _scaled(*factors):
    """args with argument i multiplied by factors[i] (None: as it is; a list of pairs scaled pair by pair)."""
    def alter(args):
        out = []
        for a, f in zip(args, factors):
            if f is None:
                out.append(a)
            elif isinstance(a, list):
                out.append([(r, f * np.asarray(F, float)) for r, F in a])
            else:
                out.append(f * np.asarray(a, float) if isinstance(a, (np.ndarray, tuple)) else f * a)
        return tuple(out)
    return alter


def _state_scaled(M=1.0, Ib=1.0, P=1.0, L=1.0, forces=1.0, shift=0.0):
    """(M, I_body_inv, X, forces[, dt]) with M, I⁻¹_body, P, L and the forces scaled, x and the points moved by
    shift."""
    def alter(args):
        x, R, P0, L0 = args[2]
        X = StateTuple(np.asarray(x, float) + shift, R, P * np.asarray(P0, float), L * np.asarray(L0, float))
        fs = [(np.asarray(r, float) + shift, forces * np.asarray(F, float)) for r, F in args[3]]
        return (M * args[0], Ib * np.asarray(args[1], float), X, fs) + args[4:]
    return alter


def _moved(shift):
    """resultants' x and points moved by shift (1000 km: r − x still exact to 1e-10 there; np.allclose(r, x) holds
    for a lever arm of 1 m)."""
    def alter(args):
        x, forces = args
        return (np.asarray(x, float) + shift, [(np.asarray(r, float) + shift, F) for r, F in forces])
    return alter


SCALES = {
    "box_inertia": (("tiny_scale", _scaled(1e-6, 1e-4)), ("huge_scale", _scaled(1e6, 1e3))),
    "velocity": (("tiny_scale", _scaled(1e-12, 1e-8)), ("huge_scale", _scaled(1e12, 1e6)),
                 ("P_tiny", _scaled(1e-14, None))),
    "inverse_inertia": (("tiny_scale", _scaled(None, 1e-14)), ("huge_scale", _scaled(None, 1e12))),
    "angular_velocity": (("tiny_scale", _scaled(1e-7, 1e-7)), ("huge_scale", _scaled(1e6, 1e6)),
                         ("L_tiny", _scaled(None, 1e-12))),
    "resultants": (("tiny_scale", _scaled(None, 1e-13)), ("huge_scale", _scaled(None, 1e9)), ("far_away", _moved(1e6))),
    "state": (("tiny_scale", _state_scaled(M=1e-8, Ib=1e14, P=1e-8, L=1e-14, forces=1e-8)),    # a speck of dust:
              ("huge_scale", _state_scaled(M=1e6, Ib=1e-9, P=1e6, L=1e9, forces=1e6)),       # v, ω as usual
              ("far_away", _state_scaled(shift=1e6))),
}
"""The alterations to the ends of the scales, by check ("state": dxdt, euler_step and euler_step_projected)."""


def scale_rungs(ladder, scales) -> tuple:
    """The ladder with a rung for each end of the scales, on the inputs of its most general rung (the last one that
    is not a variation)."""
    last = next(r for r in reversed(ladder) if r.feature not in VARIATIONS)
    return ladder + tuple(Rung(feature, lambda rng, alter=alter: alter(last.make(rng))) for feature, alter in scales)
