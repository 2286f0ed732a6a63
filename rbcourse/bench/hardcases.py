"""The hard cases: named scenes on which easy methods go wrong (../shared/benchmarks.md).

Each case is a named set-up of examples.py (EXAMPLES) with the case's own data: its full
length and a short one (`quick`, used under test with the environment flag RBCOURSE_QUICK=1), a step
size, a reference where one exists, and what goes wrong.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..support.language import say
from ..scene import Scene
from ..state import State
from ..examples import EXAMPLES


@dataclass(frozen=True)
class HardCase:
    """A hard case: a scene, an initial state, how long and with what step, and what goes wrong."""
    name: str
    scene: Scene
    X0: State
    T: float
    dt: float
    T_quick: float
    reference: str               # "exact" (torque-free), "dop853" (benchmark C's), "fine" (adaptive at
                                 # rtol = atol = 1e-12), "rest" (X0: nothing moves) or "" (none: chaotic)
    said: tuple                  # what goes wrong with naive methods: (in English, in French)
    invariants: tuple = ()       # what the physics keeps: names of stability.INVARIANTS

    @property
    def goes_wrong(self) -> str:
        """What goes wrong with naive methods, in the active language."""
        return say(*self.said)

    @property
    def free(self) -> bool:
        """No force, no torque: the exact torque-free solution applies and L, |L|, E are invariants."""
        return not self.scene.effects

    def duration(self, quick: bool = False) -> float:
        """T, or the short T_quick (quick: passed down from rbcourse.support.config.quick_mode by the caller)."""
        return self.T_quick if quick else self.T


FREE = ("energy", "L", "norm_L")      # a free body keeps its energy, its world L and so |L|
TOP = ("energy", "L_z", "L3")          # a symmetric heavy top: energy, L_z about the pivot, the spin L₃

CASES = [
    # name, set-up (EXAMPLES), T, dt, T_quick, reference, what goes wrong, invariants (default: FREE)
    ("racket_long", "tennis_racket", 200.0, 1e-2, 40.0, "exact",
     "energy drift makes the flips come at the wrong times, or not at all"),
    ("fast_spin_large_step", "fast_spin", 10.0, 1e-2, 10.0, "exact",
     "half a radian (29°) per step: the explicit gyroscopic term gains energy and blows up"),
    ("fast_thin_disk", "thin_disk", 10.0, 1e-2, 10.0, "exact",
     "energy gain when h|ω| is large (|ω| = 40 rad/s, h|ω| = 0.4)"),
    ("slender_rod", "slender_rod", 10.0, 1e-3, 2.0, "exact",
     "inertia ratio 1000:1:1000, spun about an oblique axis: stiff gyroscopic coupling (h ω = 0.3)"),
    ("heavy_top_coarse", "heavy_top", 5.0, 1e-2, 1.0, "dop853",
     "2 rad of spin per step: Euler blows up; implicit_gyro damps the top and it falls", TOP),
    ("heavy_top_fine", "heavy_top", 5.0, 1e-3, 1.0, "dop853",
     "Euler still blows up; implicit_gyro still damps", TOP),
    ("near_separatrix", "near_separatrix", 20.0, 1e-2, 20.0, "exact",
     "elliptic parameter → 1: the exact formulas lose digits; tiny errors decide the flip time"),
    ("principal_axis_spin", "principal_axis_spin", 20.0, 1e-2, 20.0, "exact",
     "spin exactly along the (unstable) intermediate axis: exact formulas divide by zero"),
    ("long_run", "tumbling_box", 1000.0, 1e-3, 10.0, "exact",
     "10⁶ steps: R leaves SO(3); |L| and the energy drift"),
    ("sphere", "sphere", 10.0, 1e-2, 10.0, "exact",
     "a spherical body: every axis is principal (degenerate eigenvectors)"),
    ("symmetric_body", "symmetric_body", 10.0, 1e-2, 10.0, "exact",
     "two equal moments: steady precession; the elliptic formulas degenerate"),
    ("light_body", "light_box", 10.0, 1e-2, 10.0, "exact",
     "1 mg: tiny moments of inertia (3.5e-9 to 1.1e-8 kg m²), the same motion"),
    ("heavy_body", "heavy_box", 10.0, 1e-2, 10.0, "exact",
     "1000 t: huge moments of inertia (3.5e3 to 1.1e4 kg m²), the same motion"),
    ("asymmetric_top", "asymmetric_top", 5.0, 1e-3, 1.0, "",
     "no symmetry axis: chaotic, only the energy and L_z are kept (no reference: a rotation error after 5 s of "
     "chaos measures nothing)", ("energy", "L_z")),
    ("stiff_spring", "stiff_spring", 10.0, 1e-2, 10.0, "fine",
     "k Δt²/m = 3.9 (ω Δt = 1.97): beyond explicit Euler's limit, at the edge of the leapfrog's (ω Δt < 2)",
     ("energy",)),
    ("box_at_rest", "box_at_rest", 100.0, 1e-3, 1.0, "rest",
     "10⁵ steps lying on the floor: the contact must not make it creep, bounce or gain energy",
     ("energy", "rest")),
    ("mass_ratio_pair", "mass_ratio_pair", 10.0, 1e-2, 2.0, "fine",
     "masses 1000 : 1 joined by a spring: the light body's fast motion sets the step",
     ("energy", "P", "L")),
    ("racket_coarse", "tennis_racket", 40.0, 5e-2, 10.0, "exact",
     "the Dzhanibekov flip at a coarse step (ω Δt = 0.25): four flips, whose times an energy error moves"),
]
"""Every hard case: its name, the set-up it runs (a key of workbook.examples.EXAMPLES), its full and
short durations T and T_quick, its step dt, its reference, what goes wrong and the invariants its
physics keeps (names of stability.INVARIANTS; FREE when not given)."""


GOES_WRONG_FR = {
    "racket_long": "la dérive de l'énergie fait venir les retournements aux mauvais instants, ou pas du tout",
    "fast_spin_large_step": "un demi-radian (29°) par pas : le terme gyroscopique explicite gagne de l'énergie et diverge",
    "fast_thin_disk": "gain d'énergie quand h|ω| est grand (|ω| = 40 rad/s, h|ω| = 0.4)",
    "slender_rod": "rapport d'inertie 1000:1:1000, lancée autour d'un axe oblique : couplage gyroscopique raide (h ω = 0.3)",
    "heavy_top_coarse": "2 rad de rotation propre par pas : Euler diverge ; implicit_gyro amortit la toupie, qui tombe",
    "heavy_top_fine": "Euler diverge encore ; implicit_gyro amortit encore",
    "near_separatrix": "paramètre elliptique → 1 : les formules exactes perdent des chiffres ; d'infimes erreurs décident "
                       "de l'instant du retournement",
    "principal_axis_spin": "rotation exactement selon l'axe intermédiaire (instable) : les formules exactes divisent par zéro",
    "long_run": "10⁶ pas : R quitte SO(3) ; |L| et l'énergie dérivent",
    "sphere": "un corps sphérique : tout axe est principal (vecteurs propres dégénérés)",
    "symmetric_body": "deux moments égaux : précession régulière ; les formules elliptiques dégénèrent",
    "light_body": "1 mg : des moments d'inertie minuscules (3.5e-9 à 1.1e-8 kg m²), le même mouvement",
    "heavy_body": "1000 t : des moments d'inertie énormes (3.5e3 à 1.1e4 kg m²), le même mouvement",
    "asymmetric_top": "aucun axe de symétrie : chaotique, seuls l'énergie et L_z sont gardés (pas de référence : une erreur "
                      "de rotation après 5 s de chaos ne mesure rien)",
    "stiff_spring": "k Δt²/m = 3.9 (ω Δt = 1.97) : au-delà de la limite de la méthode d'Euler explicite, au bord de celle "
                    "du saute-mouton (ω Δt < 2)",
    "box_at_rest": "10⁵ pas posée au sol : le contact ne doit ni la faire glisser, ni la faire rebondir, ni lui donner "
                   "de l'énergie",
    "mass_ratio_pair": "masses 1000 : 1 reliées par un ressort : le mouvement rapide du corps léger impose le pas",
    "racket_coarse": "le retournement de Djanibekov à grand pas (ω Δt = 0.25) : quatre retournements, dont une erreur "
                     "d'énergie déplace les instants",
}
"""What goes wrong on each hard case, in French (CASES has it in English)."""


def names() -> list[str]:
    """The hard cases' names, sorted (nothing built: the command line lists them)."""
    return sorted(case[0] for case in CASES)


def catalogue() -> dict[str, HardCase]:
    """Every hard case, by name (each built afresh from its set-up)."""
    cases = {}
    for name, setup, T, dt, T_quick, reference, goes_wrong, *invariants in CASES:
        ex = EXAMPLES[setup]()
        cases[name] = HardCase(name, ex.scene, ex.X0, T, dt, T_quick, reference, (goes_wrong, GOES_WRONG_FR[name]),
                               tuple(invariants[0]) if invariants else FREE)
    return cases
