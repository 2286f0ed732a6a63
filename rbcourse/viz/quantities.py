"""What the explorer plots for a scene, and why: which quantity the physics of the scene keeps, so that
any change of it is the method's error ("drift"), and which it does not keep, so that a run is compared
with the reference motion at the same time ("error").

The rules, read from the scene's effects that still act after t₀ (drift_from: a push that is over
by then no longer counts; a force given as f(t) counts if it is nonzero at some sampled time after t₀):

* energy E = T + U (summed over the bodies) is conserved when every acting effect is gravity, an undamped
  spring or a pivot (the pivot does no work):  plotted |E − E₀| / |E₀|, E₀ = E(t₀).
  Otherwise (damping, drag, contacts, a force that keeps acting, an impulse) E is not conserved:
  plotted |E − E_ref| / max |E_ref|, the reference at the same time.
* angular momentum: with no torque about the centres of mass (a free body, uniform gravity) each L is
  conserved, so Σ L (about the centres of mass, world axes) is:  ‖L − L₀‖ / ‖L₀‖.
  A single body held at a pivot or hung from springs whose anchors lie on one vertical line through p,
  under gravity: the vertical component of the angular momentum about p, L_p = L + (x − p) × P, is
  conserved (the forces through p and gravity have no vertical torque about p):  |L_pz − L_pz₀| / ‖L_p₀‖.
  Otherwise: ‖L − L_ref‖ / max ‖L_ref‖ (about the origin, world axes).
* ‖RᵀR − I‖ (the distance of R from SO(3); the largest over the bodies), and the rotation error
  against the reference, the angle of R_refᵀ R (rad; the largest over the bodies) — at every step up to
  ROTATION_EVALS body-steps per run, else at every k-th step and the plotted ones (rotation_rows).

Every value comes from the trajectory's own diagnostics (Trajectory.total_energy, angular_momentum,
orthogonality_error) and rotation.rotation_angle: nothing here re-derives the physics.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..contact import Ground
from ..support.language import say
from ..effects import AngularDrag, Gravity, LinearDrag, PointForce, Spring
from ..impulse import Impulse
from ..pivot import Pivot
from ..profiles import Profile
from ..rotation import rotation_angle

KEYS = ("energy", "momentum", "orthogonality", "rotation")
ROTATION_EVALS = 50_000          # rotation errors evaluated per run (body-steps; each projects two R by an SVD)
MAX_FORCE_SAMPLES = 100_000      # times at which a force f(t) is looked at, after t₀, to see if it still acts


FRENCH_NAMES = {"energy": "énergie", "momentum": "moment cinétique", "orthogonality": "orthogonalité",
                "rotation": "rotation"}


def name(key: str) -> str:
    """A quantity's name in the active language: its key in English, the glossary's word in French."""
    return say(key, FRENCH_NAMES[key])


@dataclass(frozen=True)
class Quantity:
    """One plotted quantity: its key, the plot's title (with the formula), unit, and why it is plotted."""
    key: str
    title: str
    unit: str
    note: str
    mode: str                     # "drift" (from its own value at t₀) or "error" (against the reference)
    why: str = ""                 # for an "error": why the scene does not conserve it, in words


@dataclass(frozen=True)
class Plan:
    """What is measured on every run of one scene (see the module docstring)."""
    quantities: tuple             # four Quantity, in KEYS order
    t0: float                     # drift_from: drifts are measured from the first recorded step at or after it
    energy_conserved: bool
    momentum: str                 # "com" (Σ L about the centres of mass), "vertical" (L_z about p), "origin"
    point: np.ndarray | None      # p for "vertical"

    def __getitem__(self, key: str) -> Quantity:
        return self.quantities[KEYS.index(key)]


def acts_after(effect, t0: float, times: np.ndarray) -> bool:
    """Does the effect still act after t₀?  A PointForce: a nonzero constant, a profile (rb.Pulse, …) nonzero
    at some t >= t₀ (Profile.acts_after: exact), or f(t) nonzero at one of `times` (those >= t₀); an Impulse: due at or after t₀; drag and springs with zero coefficients: no."""
    if isinstance(effect, PointForce):
        if not callable(effect.force):
            return bool(np.any(effect.force != 0))
        if isinstance(effect.force, Profile):            # forces over time as data: known exactly
            return effect.force.acts_after(t0)
        return any(np.any(effect.force_at(float(t)) != 0) for t in times[times >= t0])
    if isinstance(effect, Impulse):
        return effect.time >= t0
    if isinstance(effect, (LinearDrag, AngularDrag)):
        return effect.coefficient > 0
    if isinstance(effect, Spring):
        return effect.stiffness > 0 or effect.damping > 0
    return True


# Why an acting effect breaks a conservation law, in words, by kind of effect: (kind, why E is not conserved, the
# torque it exerts); None: the kind keeps E (a pivot does no work).  No kind is a subclass of another: order is free.
_REASONS = (
    (Spring, ("the spring's damping dissipates energy", "l'amortissement du ressort dissipe l'énergie"),
     ("springs", "des ressorts")),
    ((LinearDrag, AngularDrag), ("drag dissipates energy", "le frottement fluide dissipe l'énergie"),
     ("drag", "du frottement fluide")),
    (Ground, ("contacts with the ground dissipate energy (restitution, friction)",
              "les contacts avec le sol dissipent l'énergie (restitution, frottement)"), ("contacts", "des contacts")),
    (PointForce, ("a force keeps acting and does work", "une force continue d'agir et travaille"),
     ("a force at a point", "une force en un point")),
    (Impulse, ("an impulse kicks the body", "une impulsion frappe le corps"), ("an impulse", "une impulsion")),
    (Pivot, None, ("pivots", "des pivots")),
)


def _reason(effect, column: int) -> str | None:
    """The words of _REASONS for the effect's kind: column 0 why E is not kept, 1 its torque (None: none)."""
    for kind, *words in _REASONS:
        if isinstance(effect, kind):
            return None if words[column] is None else say(*words[column])
    return None


def _why_not_conserved(effect) -> str:
    """Why E is not conserved under the effect, in words (the energy plot's note)."""
    name = type(effect).__name__
    return _reason(effect, 0) or say(f"{name} is not known to conserve it", f"{name} : sa conservation n'est pas établie")


def _torque_reason(effect) -> str:
    """The torque the effect exerts, in words (why no component of L is conserved: the momentum plot's note)."""
    if isinstance(effect, Spring) and effect.other_body is not None:
        return say("springs between bodies or anchors off one vertical",
                   "des ressorts entre corps ou des points d'attache hors d'une même verticale")
    return _reason(effect, 1) or type(effect).__name__


def plan(scene, t0: float, t_end: float, sample_step: float) -> Plan:
    """The quantities plotted for `scene` (module docstring), drifts measured from t₀.
    sample_step: a force f(t) is looked at every sample_step (at most MAX_FORCE_SAMPLES times) after t₀."""
    n = int(np.floor((t_end - t0) / sample_step)) + 1
    times = t0 + sample_step * np.arange(n) if n <= MAX_FORCE_SAMPLES else np.linspace(t0, t_end, MAX_FORCE_SAMPLES)
    acting = [e for e in scene.effects if acts_after(e, t0, times)]
    after = (say(f" from t₀ = {t0:g} s on (before, the push does work: the drift is not plotted there, grey band)",
                 f" à partir de t₀ = {t0:g} s (avant, la poussée travaille : la dérive n'y est pas tracée, bande grise)")
             if t0 > 0 else "")
    since = "E₀ = E(t₀)" if t0 > 0 else "E₀ = E(0)"
    keeps_energy = [e for e in acting if not (isinstance(e, (Gravity, Pivot))
                                              or (isinstance(e, Spring) and e.damping == 0))]
    potentials = sorted({say("gravity M g z", "gravité M g z") if isinstance(e, Gravity) else
                         say("springs ½ k s²", "ressorts ½ k s²") for e in acting if isinstance(e, (Gravity, Spring))})
    E = (say("E = T + U (kinetic + potential: ", "E = T + U (cinétique + potentielle : ") + ", ".join(potentials) + ")"
         if potentials else say("E = T (kinetic energy)", "E = T (énergie cinétique)"))
    bodies = "" if scene.single else say(", summed over the bodies", ", sommée sur les corps")
    relative = say("relative (no unit)", "relative (sans unité)")
    if not keeps_energy:
        energy = Quantity("energy", say("energy drift |E − E₀| / |E₀|", "dérive de l'énergie |E − E₀| / |E₀|"), relative,
                          say(f"{E}{bodies}. The physics of this scene keeps E exactly{after}: any change is "
                              f"the method's error; {since}.",
                              f"{E}{bodies}. La physique de cette scène conserve E exactement{after} : toute variation "
                              f"est l'erreur de la méthode ; {since}."), "drift")
    else:
        why = say("; ", " ; ").join(dict.fromkeys(_why_not_conserved(e) for e in keeps_energy))
        energy = Quantity("energy", say("energy error |E − E_ref| / max |E_ref|",
                                        "erreur sur l'énergie |E − E_ref| / max |E_ref|"), relative,
                          say(f"{E}{bodies}. E is not conserved here ({why}): the run's E is compared with the "
                              "reference's at the same time.",
                              f"{E}{bodies}. E n'est pas conservée ici ({why}) : l'énergie E de la simulation est "
                              "comparée à celle de la référence au même instant."), "error", why)
    momentum_kind, point = "origin", None
    held = [e for e in acting if isinstance(e, (Pivot, Spring))]
    if all(isinstance(e, Gravity) for e in acting):
        momentum_kind = "com"
        why = (say("uniform gravity acts at the centre of mass", "la gravité uniforme agit au centre de masse")
               if acting else say("a free body", "un corps libre"))
        L0 = 'L(t₀)' if t0 > 0 else 'L(0)'
        momentum = Quantity("momentum", say("angular-momentum drift ‖L − L₀‖ / ‖L₀‖",
                                            "dérive du moment cinétique ‖L − L₀‖ / ‖L₀‖"), relative,
                            say(f"L about the centre of mass, world axes{bodies}. No torque acts about the centre of "
                                f"mass ({why}): L is conserved exactly{after}, so any change is the method's error; "
                                f"L₀ = {L0}.",
                                f"L au centre de masse, axes du monde{bodies}. Aucun moment (couple) n'agit au centre "
                                f"de masse ({why}) : L est conservé exactement{after}, donc toute variation est "
                                f"l'erreur de la méthode ; L₀ = {L0}."), "drift")
    elif scene.single and all(isinstance(e, (Gravity, Pivot, Spring)) for e in acting) \
            and all(getattr(e, "other_body", None) is None for e in held) and _one_vertical(held):
        momentum_kind, point = "vertical", np.array(held[0].world_point, dtype=float)
        what = say(" and ", " et ").join(dict.fromkeys(
            "pivot" if isinstance(e, Pivot) else say("spring anchor", "point d'attache du ressort") for e in held))
        p_text = np.round(point, 6).tolist()
        momentum = Quantity("momentum", say("drift of L_z about the " + what + ": |L_z − L_z₀| / ‖L₀‖",
                                            "dérive de L_z autour du " + what + " : |L_z − L_z₀| / ‖L₀‖"), relative,
                            say(f"L about the {what} p = {p_text} (L + (x − p) × P, world axes): "
                                f"its vertical component is conserved exactly (the {what}'s forces pass through p, "
                                "gravity has no vertical torque about p); divided by ‖L(t₀)‖.",
                                f"L autour du {what} p = {p_text} (L + (x − p) × P, axes du monde) : sa composante "
                                f"verticale est conservée exactement (les forces du {what} passent par p, la gravité "
                                "n'a pas de moment vertical autour de p) ; divisée par ‖L(t₀)‖."), "drift")
    else:
        why = say("; ", " ; ").join(dict.fromkeys(_torque_reason(e) for e in acting if not isinstance(e, Gravity)))
        momentum = Quantity("momentum", say("angular-momentum error ‖L − L_ref‖ / max ‖L_ref‖",
                                            "erreur sur le moment cinétique ‖L − L_ref‖ / max ‖L_ref‖"), relative,
                            say(f"L = Σ (L + x × P) about the origin, world axes. No component of it is conserved "
                                f"here ({why}): compared with the reference at the same time.",
                                f"L = Σ (L + x × P) par rapport à l'origine, axes du monde. Aucune de ses composantes "
                                f"n'est conservée ici ({why}) : comparé à la référence au même instant."), "error", why)
    largest = "" if scene.single else say(" (the largest over the bodies)", " (le plus grand sur les corps)")
    orth = Quantity("orthogonality", say("‖RᵀR − I‖ (distance from SO(3))", "‖RᵀR − I‖ (écart à SO(3))"),
                    say("no unit", "sans unité"),
                    say("0 for a rotation matrix; how far R has left SO(3)", "0 pour une matrice de rotation ; de "
                        "combien R s'est écartée de SO(3)") + largest
                    + say(". The drawing uses the nearest rotation.", ". Le dessin utilise la rotation la plus proche."),
                    "drift")
    rot = Quantity("rotation", say("rotation error vs the reference (rad)",
                                   "écart de rotation à la référence (rad)"), "rad",
                   say("the angle of R_refᵀ R: how far the body's orientation is from the reference's",
                       "l'angle de R_refᵀ R : l'écart entre l'orientation du corps et celle de la référence")
                   + largest + ".", "error")
    return Plan((energy, momentum, orth, rot), t0, not keeps_energy, momentum_kind, point)


def _one_vertical(held) -> bool:
    if not held:
        return False
    p = np.array([e.world_point for e in held], dtype=float)
    scale = max(1.0, float(np.abs(p).max()))
    return bool(np.all(np.abs(p[:, :2] - p[0, :2]) <= 1e-12 * scale))


def first_at(t: np.ndarray, t0: float) -> int:
    """The index of the first recorded time at or after t0 (a tolerance of 1e-9 of a step)."""
    step = t[1] - t[0] if len(t) > 1 else 1.0
    return min(int(np.searchsorted(t, t0 - 1e-9 * step)), len(t) - 1)


def rotation_rows(n: int, n_bodies: int, keep=()) -> np.ndarray:
    """The steps at which the rotation error is evaluated: every one if n × bodies <= ROTATION_EVALS, else
    every k-th step (k = ⌈n × bodies / ROTATION_EVALS⌉), with the steps `keep` (the plotted ones) and the last."""
    k = max(1, math.ceil(n * n_bodies / ROTATION_EVALS))
    return np.unique(np.concatenate([np.arange(0, n, k), np.asarray(keep, dtype=int), [n - 1]]))


def drifts(p: Plan, traj) -> dict:
    """What the physics of the scene keeps, measured on run `traj` at each of its recorded steps (arrays (n,),
    NaN before t₀): "energy" (E − E₀)/|E₀| (signed) when E is conserved, "momentum" when L is
    (‖L − L₀‖/‖L₀‖, L about the centres of mass) or L_z about the pivot p is (|L_z − L_z₀|/‖L_p₀‖), and
    "orthogonality" ‖RᵀR − I‖ (the largest over the bodies), always.  A quantity the scene does not
    conserve has no key: its change is physics, not the method's error."""
    k0 = first_at(traj.t, p.t0)
    out = {}
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        if p.energy_conserved:
            E = _total(traj.total_energy())
            out["energy"] = _relative(E - E[k0], abs(E[k0]), k0)
        if p.momentum == "com":
            L = _total_vec(traj.angular_momentum("com"))
            out["momentum"] = _relative(np.linalg.norm(L - L[k0], axis=-1), float(np.linalg.norm(L[k0])), k0)
        elif p.momentum == "vertical":
            L = traj.angular_momentum(p.point)
            out["momentum"] = _relative(np.abs(L[:, 2] - L[k0, 2]), float(np.linalg.norm(L[k0])), k0)
        out["orthogonality"] = _largest(traj.orthogonality_error())
    return out


def values(p: Plan, traj, ref, keep=()) -> dict:
    """The four quantities of run `traj` at each of its recorded steps (arrays (n,); NaN before t₀ for
    drifts), ref: the reference at the same times (a Trajectory of the same scene, at least as long).
    The rotation error is NaN at the steps rotation_rows(n, bodies, keep) leaves out."""
    n = len(traj.t)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        out = {key: np.abs(v) for key, v in drifts(p, traj).items()}
        if not p.energy_conserved:
            E, E_ref = _total(traj.total_energy()), _total(ref.total_energy())[:n]
            out["energy"] = _relative(np.abs(E - E_ref), float(np.max(np.abs(_total(ref.total_energy())))), 0)
        if p.momentum == "origin":
            L, L_ref = _total_vec(traj.angular_momentum()), _total_vec(ref.angular_momentum())
            scale = float(np.max(np.linalg.norm(L_ref, axis=-1)))
            out["momentum"] = _relative(np.linalg.norm(L - L_ref[:n], axis=-1), scale, 0)
        rows = rotation_rows(n, traj.scene.n_bodies, keep)
        out["rotation"] = np.full(n, np.nan)
        out["rotation"][rows] = _largest(rotation_angle(ref.R[rows], traj.R[rows]))
    return out


def _total(a):
    return a if a.ndim == 1 else a.sum(-1)


def _total_vec(a):
    return a if a.ndim == 2 else a.sum(-2)


def _largest(a):
    return a if a.ndim == 1 else a.max(-1)


def _relative(diff: np.ndarray, scale: float, k0: int) -> np.ndarray:
    """diff / scale (diff itself if the scale is 0: nothing to divide by), NaN before index k0."""
    out = diff / scale if scale > 0 and np.isfinite(scale) else diff.astype(float)
    out = np.where(np.isnan(out), np.inf, out)          # an overflowed difference is off the chart, not missing
    out[:k0] = np.nan
    return out
