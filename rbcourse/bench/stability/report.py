"""The stability matrix as Markdown (stability.md): the outcomes and thresholds, the claims a run broke, and
per case a table of each method's outcome, invariant errors, ‖RᵀR − I‖ and end errors."""
from __future__ import annotations

import math

from ...support.language import say

from ..hardcases import catalogue
from .cell import Cell
from .claim_check import broken_claims
from .invariants import INVARIANTS, described, named
from .outcomes import FAITHFUL_INVARIANT, FAITHFUL_POSITION, FAITHFUL_ROTATION, RUNAWAY, outcome_said


def _g(v: float) -> str:
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.1e}"


def markdown(cells: list[Cell], quick: bool) -> str:
    """The report, in the active language (the outcomes, invariants and what goes wrong said in it too)."""
    cases = catalogue()
    flag = " --quick" if quick else ""
    out = [say("# Stability matrix" + (" (short runs: the catalogue's short durations)" if quick else ""),
               "# Matrice de stabilité" + (" (simulations courtes : les durées courtes du catalogue)" if quick else "")), "",
           say(f"Written by `python -m rbcourse stability{flag}` (the shipped full-length copy in rbcourse/bench/results: "
               "`python -m rbcourse stability --workers 2 --out rbcourse/bench/results`).",
               f"Écrite par `python -m rbcourse stability{flag}` (la copie complète livrée dans rbcourse/bench/results : "
               "`python -m rbcourse stability --workers 2 --out rbcourse/bench/results`)."), "",
           say("Per case: each method's outcome, the largest relative error of every invariant the case's physics "
               "keeps, the largest ‖RᵀR − I‖ and the rotation error at the end against the exact (or reference) "
               "solution (and, where a centre moves, its position error at the end).",
               "Par cas : l'issue de chaque méthode, la plus grande erreur relative de chaque invariant que la "
               "physique du cas conserve, le plus grand ‖RᵀR − I‖ et l'erreur de rotation à la fin par rapport à la "
               "solution exacte (ou de référence) (et, là où un centre bouge, son erreur de position à la fin)."), "",
           say(f"Outcomes: **faithful** — finished, every invariant within {FAITHFUL_INVARIANT:g} and the end within "
               f"{FAITHFUL_ROTATION:g} rad (and {FAITHFUL_POSITION:g} m) of the reference; **stable but wrong** — "
               f"finished, every invariant bounded (error <= {RUNAWAY:g}) but the motion or an invariant off; "
               f"**ran away** — an invariant off by more than its own size (error > {RUNAWAY:g}: energy ×2); "
               "**diverged** — overflow or NaN (the time given).",
               f"Issues : **fidèle** — terminé, chaque invariant à {FAITHFUL_INVARIANT:g} près et la fin à "
               f"{FAITHFUL_ROTATION:g} rad (et {FAITHFUL_POSITION:g} m) de la référence ; **stable mais faux** — "
               f"terminé, chaque invariant borné (erreur <= {RUNAWAY:g}) mais le mouvement ou un invariant faux ; "
               f"**emballé** — un invariant faux de plus que sa propre taille (erreur > {RUNAWAY:g} : énergie ×2) ; "
               "**divergé** — débordement ou NaN (l'instant donné)."), "",
           say("Invariants: ", "Invariants : ") + "; ".join(f"{named(k)}: {described(k)}" for k in INVARIANTS) + ".", ""]
    broken = [(c, why) for c in cells
              for why in broken_claims(c, cases[c.case], round(cases[c.case].duration(quick) / cases[c.case].dt))]
    out += [say("## Claims", "## Promesses"), "",
            say("Every run against what bench/claims.py claims for its method (kept to rounding: the claim's "
                "tolerance per 10⁴ steps):",
                "Chaque simulation face à ce que bench/claims.py promet pour sa méthode (gardé à l'arrondi près : la "
                "tolérance de la promesse pour 10⁴ pas) :"), ""]
    out += [f"- **{c.method}** {say('on', 'sur')} {c.case}: {why}" for c, why in broken] or [
        say("- every claim held.", "- toutes les promesses ont tenu.")]
    out.append("")
    for name in dict.fromkeys(c.case for c in cells):
        case = cases[name]
        T = case.duration(quick)
        inv = list(case.invariants)
        ref = (say("rotation err", "err. rotation") if case.reference
               else say("rotation err (no reference: chaotic)", "err. rotation (pas de référence : chaotique)"))
        rows = [c for c in cells if c.case == name]
        moves = any(c.finished and c.position_error > 0 for c in rows)   # a centre that moves: its error too
        cols = len(inv) + 2 + moves
        err = say("{} err", "err. {}")
        out += [f"## {name} — T = {T:g} s, dt = {case.dt:g} s", "",
                say(f"What goes wrong: {case.goes_wrong}.", f"Ce qui tourne mal : {case.goes_wrong}."), "",
                say("| method | outcome | ", "| méthode | issue | ") + " | ".join(err.format(named(k)) for k in inv) +
                f" | ‖RᵀR − I‖ | {ref} |" + (say(" position err (m) |", " err. position (m) |") if moves else ""),
                "|---|---|" + "---|" * cols]
        for c in rows:
            if not c.finished:        # its last numbers are overflow, not physics: say when it blew up instead
                out.append(f"| {c.method} | {say('diverged at', 'divergé à')} t = {c.diverged_at:.3g} s |" + " |" * cols)
                continue
            out.append(f"| {c.method} | {outcome_said(c.outcome)} | " + " | ".join(_g(c.invariant(k)) for k in inv) +
                       f" | {_g(c.orthogonality)} | {_g(c.rotation_error)} |" +
                       (f" {_g(c.position_error)} |" if moves else ""))
        out.append("")
    return "\n".join(out)
