"""The stability matrix as Markdown (stability.md): the outcomes and thresholds, the claims a run broke, and
per case a table of each method's outcome, invariant errors, ‖RᵀR − I‖ and end errors."""
from __future__ import annotations

import math

from ..hardcases import catalogue
from .cell import Cell
from .claim_check import broken_claims
from .invariants import INVARIANTS
from .outcomes import FAITHFUL_INVARIANT, FAITHFUL_POSITION, FAITHFUL_ROTATION, RUNAWAY


def _g(v: float) -> str:
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.1e}"


def markdown(cells: list[Cell], quick: bool) -> str:
    cases = catalogue()
    out = ["# Stability matrix" + (" (short runs: the catalogue's short durations)" if quick else ""), "",
           "Written by `python -m rbcourse stability" + (" --quick" if quick else "") + "` (the shipped full-length "
           "copy in rbcourse/bench/results: `python -m rbcourse stability --workers 2 --out rbcourse/bench/results`).",
           "",
           "Per case: each method's outcome, the largest relative error of every invariant the case's physics "
           "keeps, the largest ‖RᵀR − I‖ and the rotation error at the end against the exact (or reference) "
           "solution (and, where a centre moves, its position error at the end).", "",
           f"Outcomes: **faithful** — finished, every invariant within {FAITHFUL_INVARIANT:g} and the end within "
           f"{FAITHFUL_ROTATION:g} rad (and {FAITHFUL_POSITION:g} m) of the reference; **stable but wrong** — "
           f"finished, every invariant bounded (error <= {RUNAWAY:g}) but the motion or an invariant off; "
           f"**ran away** — an invariant off by more than its own size (error > {RUNAWAY:g}: energy ×2); "
           "**diverged** — overflow or NaN (the time given).", "",
           "Invariants: " + "; ".join(f"{k}: {v[0]}" for k, v in INVARIANTS.items()) + ".", ""]
    broken = [(c, why) for c in cells
              for why in broken_claims(c, cases[c.case], round(cases[c.case].duration(quick) / cases[c.case].dt))]
    out += ["## Claims", "", "Every run against what bench/claims.py claims for its method (kept to rounding: the claim's "
            "tolerance per 10⁴ steps):", ""]
    out += [f"- **{c.method}** on {c.case}: {why}" for c, why in broken] or ["- every claim held."]
    out.append("")
    for name in dict.fromkeys(c.case for c in cells):
        case = cases[name]
        T = case.duration(quick)
        inv = list(case.invariants)
        ref = "rotation err" if case.reference else "rotation err (no reference: chaotic)"
        rows = [c for c in cells if c.case == name]
        moves = any(c.finished and c.position_error > 0 for c in rows)   # a centre that moves: its error too
        cols = len(inv) + 2 + moves
        out += [f"## {name} — T = {T:g} s, dt = {case.dt:g} s", "", f"What goes wrong: {case.goes_wrong}.", "",
                "| method | outcome | " + " | ".join(f"{k} err" for k in inv) + f" | ‖RᵀR − I‖ | {ref} |" +
                (" position err (m) |" if moves else ""), "|---|---|" + "---|" * cols]
        for c in rows:
            if not c.finished:        # its last numbers are overflow, not physics: say when it blew up instead
                out.append(f"| {c.method} | diverged at t = {c.diverged_at:.3g} s |" + " |" * cols)
                continue
            out.append(f"| {c.method} | {c.outcome} | " + " | ".join(_g(c.invariant(k)) for k in inv) +
                       f" | {_g(c.orthogonality)} | {_g(c.rotation_error)} |" +
                       (f" {_g(c.position_error)} |" if moves else ""))
        out.append("")
    return "\n".join(out)
