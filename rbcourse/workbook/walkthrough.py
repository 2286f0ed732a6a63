"""The slides' "Itération 1" and "Itération 2", reproduced by the engine, line by line.

    x(t) connu
    P(t) connu → v(t) = P(t)/M
 ②  R(t) connu → I⁻¹(t) = R(t)·I⁻¹_body·R(t)ᵀ
 ②  L(t) connu → ω(t) = I⁻¹(t)·L(t)  ⇒  Ṙ(t) = ω*·R(t)
 ①  F → dP/dt ;   τ = Σ (rᵢ − x(t)) ∧ Fᵢ → dL/dt
    X(t+Δt) = X(t) + Δt·(v, ω*·R, F, τ)

From rest, iteration 1 gives (x, R, Δt·F, Δt·τ): only the momenta move; x and R
start to move in iteration 2.

The printed lines are in the workbook's language (rbcourse.workbook.langue("fr"): in French): one
table of texts per language, TEXTS, keyed by the same ids with the same {placeholders}.  The slide's
own lines (its formulas, "connu") are the slide's, the same in every language.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..support import checks
from .language import text
from ..body import RigidBody
from ..effects import PointForce
from ..driver import derivative, kernel
from ..engine import interpreted
from ..forces import force_arrays
from ..scene import Scene
from ..simulate import simulate
from ..state import State
from ..trajectory import Divergence, SimulationDiverged, Trajectory


TEXTS = {
    "en": {
        "head": "● Itération {i}   (t = {t0} s → {t1} s, Δt = {dt} s, M = {M} kg)",
        "force": "force {i}: F{s} = {F} at r{s}(t) = {r}",
        "at_rest": "→ at rest v = 0 and ω = 0: X(t+Δt) = (x, R, Δt·F, Δt·τ) — the body has not moved, "
                   "only its momenta have (état actuel de l'itération {next})",
        "moving": "→ v ≠ 0 or ω ≠ 0: {moved} (état actuel de l'itération {next})",
        "moved": "x and R move now",
        "unmoved": "x and R are unchanged",
        "diverged": "the walkthrough diverged at Itération {i} (t = {t} s): {reason}; the iterations before it "
                    "({n}) are kept in .trajectory",
    },
    "fr": {
        "head": "● Itération {i}   (t = {t0} s → {t1} s, Δt = {dt} s, M = {M} kg)",
        "force": "force {i} : F{s} = {F} appliquée en r{s}(t) = {r}",
        "at_rest": "→ au repos, v = 0 et ω = 0 : X(t+Δt) = (x, R, Δt·F, Δt·τ) — l'objet n'a pas bougé, "
                   "seuls P et L ont changé (état actuel de l'itération {next})",
        "moving": "→ v ≠ 0 ou ω ≠ 0 : {moved} (état actuel de l'itération {next})",
        "moved": "x et R bougent désormais",
        "unmoved": "x et R n'ont pas changé",
        "diverged": "le parcours a divergé à l'Itération {i} (t = {t} s) : {reason} ; les itérations précédentes "
                    "({n}) sont conservées dans .trajectory",
    },
}
"""The walkthrough's own words, per language (rbcourse.workbook.language): the same ids and placeholders."""


@dataclass(frozen=True)
class IterationRecord:
    """One iteration of the slides' explicit Euler, with every intermediate quantity."""
    index: int              # 1, 2, ... as "Itération i"
    t: float
    dt: float
    mass: float
    before: State           # X(t)
    v: np.ndarray           # v(t) = P(t)/M
    I_inv: np.ndarray       # I⁻¹(t) = R I⁻¹_body Rᵀ
    omega: np.ndarray       # ω(t) = I⁻¹(t) L(t)
    R_dot: np.ndarray       # Ṙ(t) = ω* R(t)
    points: np.ndarray      # rᵢ(t), (k, 3)
    forces: np.ndarray      # Fᵢ, (k, 3)
    F: np.ndarray           # F = Σ Fᵢ  (= dP/dt)
    tau: np.ndarray         # τ = Σ (rᵢ − x) ∧ Fᵢ  (= dL/dt)
    after: State            # X(t + Δt)

    def lines(self) -> list[str]:
        """The slide's lines, in the slide's order and numbering, in the workbook's language (current())."""
        X, Y = self.before, self.after
        at_rest = not np.any(X.P) and not np.any(X.L)
        pad = " " * 6
        out = [text(TEXTS, "head").format(i=self.index, t0=f"{self.t:.6g}", t1=f"{self.t + self.dt:.6g}",
                                          dt=f"{self.dt:g}", M=f"{self.mass:g}")]
        out.append(f"      x(t) connu                                  x = {_v(X.x)}")
        out.append(f"      P(t) connu  → v(t) = P(t)/M                 P = {_v(X.P)}   v = {_v(self.v)}")
        out.append("  ②   R(t) connu  → I⁻¹(t) = R(t)·I⁻¹_body·R(t)ᵀ")
        out += _m("R(t)", X.R, pad) + _m("I⁻¹(t)", self.I_inv, pad)
        out.append("  ②   L(t) connu  → ω(t) = I⁻¹(t)·L(t)  ⇒  Ṙ(t) = ω*·R(t)")
        out.append(f"{pad}L = {_v(X.L)}   ω = {_v(self.omega)}")
        out += _m("Ṙ(t)", self.R_dot, pad)
        for i, (r, f) in enumerate(zip(self.points, self.forces), 1):
            out.append(pad + text(TEXTS, "force").format(i=i, s=_sub(i), F=_v(f), r=_v(r)))
        out.append(f"  ①   F = Σ Fᵢ → dP/dt                             F = {_v(self.F)}")
        out.append(f"  ①   τ = Σ (rᵢ − x(t)) ∧ Fᵢ → dL/dt               τ = {_v(self.tau)}")
        out.append("      X(t+Δt) = X(t) + Δt·(v, ω*·R, F, τ)")
        out.append(f"{pad}x(t+Δt) = {_v(Y.x)}")
        out += _m("R(t+Δt)", Y.R, pad)
        out.append(f"{pad}P(t+Δt) = {_v(Y.P)}")
        out.append(f"{pad}L(t+Δt) = {_v(Y.L)}")
        if at_rest:
            out.append(pad + text(TEXTS, "at_rest").format(next=self.index + 1))
        else:
            moved = text(TEXTS, "moved" if np.any(Y.x != X.x) or np.any(Y.R != X.R) else "unmoved")
            out.append(pad + text(TEXTS, "moving").format(moved=moved, next=self.index + 1))
        return out

    def __str__(self) -> str:
        return "\n".join(self.lines())


def walkthrough(body: RigidBody, X0: State, forces, dt: float, iterations: int = 2) -> list[IterationRecord]:
    """Run the slides' explicit Euler for `iterations` steps and record every intermediate quantity.

    forces: [(r_i, F_i), ...]: F_i (world, constant) acts at the world point r_i at the
    start; the force stays attached to that body point, b_i = R(0)ᵀ (r_i − x(0)),
    so rᵢ(t) = x(t) + R(t) b_i.
    Returns one IterationRecord per iteration; print(rec) gives the slide's lines.
    """
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a RigidBody, got {body!r}")
    if not isinstance(X0, State) or X0.x.ndim != 1:
        raise ValueError(f"X0 must be the State of one body, got {X0!r}")
    r0, F_i = force_arrays(forces)
    dt = checks.positive("dt", dt)
    iterations = checks.integer("iterations", iterations, low=1, high=10**6)
    b = (r0 - X0.x) @ X0.R          # b_i = R(0)ᵀ (r_i − x(0)), body axes
    scene = Scene(body, [PointForce(bi, fi) for bi, fi in zip(b, F_i)])
    # X(t+Δt) = X(t) + Δt dX/dt: the kernel's Euler (engine/euler.py: euler_step), its functions run as Python
    run = simulate(scene, X0, iterations * dt, dt, "euler", fast=False, on_divergence="stop")
    motion, algebra = interpreted.module("motion"), interpreted.module("algebra")
    python = kernel(fast=False)
    states = [State.unchecked(run.x[k], run.R[k], run.P[k], run.L[k]) for k in range(len(run.t))]
    records = []
    for i in range(1, len(states)):
        X, Y, t = states[i - 1], states[i], float(run.t[i - 1])
        v, R_dot, F, tau = (a[0] for a in derivative(python, scene, t, scene.to_engine(X)))   # dX/dt, as the step used it
        I_inv = motion.inverse_inertia(X.R, body.I_body_inv)                           # R → I⁻¹
        omega = motion.angular_velocity(I_inv, X.L)                                    # L → ω
        r = np.array([motion.body_point(X.x, X.R, bi) for bi in b]).reshape(-1, 3)     # rᵢ(t) = x + R bᵢ
        records.append(IterationRecord(i, t, dt, body.mass, X, v, np.array(I_inv), np.array(omega), R_dot, r,
                                       F_i.copy(), F, tau, Y))
    if run.diverged:                                       # the same check as simulate's
        raise _diverged(scene, records, X0, run.divergence.step, dt, run.divergence.reason)
    return records


def _diverged(scene, records, X0, i: int, dt: float, reason: str) -> SimulationDiverged:
    """Iteration i blew up: the error keeps the states of the iterations before it."""
    states = [X0] + [r.after for r in records]
    traj = Trajectory([k * dt for k in range(len(states))], *(np.array([getattr(X, k) for X in states])
                                                              for k in State.__slots__),
                      scene=scene, method="euler", dt=dt, divergence=Divergence(i * dt, i, reason))
    message = text(TEXTS, "diverged").format(i=i, t=f"{i * dt:.6g}", reason=reason, n=len(records))
    return SimulationDiverged(message, traj, i * dt, i, reason)


def _num(v: float) -> str:
    return f"{float(v) + 0.0:.6g}"      # + 0.0: no "-0"


def _v(a) -> str:
    return "[" + ", ".join(_num(v) for v in np.asarray(a)) + "]"


def _m(name: str, M, pad: str) -> list[str]:
    cells = [[_num(v) for v in row] for row in np.asarray(M)]
    w = max(len(c) for row in cells for c in row)
    rows = ["[" + ", ".join(c.rjust(w) for c in row) + "]" for row in cells]
    head = f"{pad}{name} = "
    return [head + rows[0]] + [" " * len(head) + r for r in rows[1:]]


def _sub(i: int) -> str:
    return "".join("₀₁₂₃₄₅₆₇₈₉"[int(c)] for c in str(i))
