"""Checks for the two-hour exercise (notebooks/01_exercise_euler.ipynb, slide "EXERCICE (2h)").

The student writes, from the slides, one function at a time; after each one a check cell runs it on
random inputs (seeded: the same inputs every time) against the reference engine (rbcourse) and prints
one verdict:

    ✓ velocity: v = P/M — correct on 20 random inputs
    ✗ inverse_inertia: the rotation is on the wrong side … → reread the slide “Evolution temporelle (Euler)”
    ○ velocity: not done yet (it raises NotImplementedError)

A wrong answer is diagnosed from the function's behaviour alone, never from its source text:
- what it returned: None, a Python list, an integer (truncating), complex or np.matrix array, a wrong shape;
- its arguments in another order: it is right when two of them are swapped (the declared parameter
  names then tell "arguments in the wrong order" from a formula that swaps them, as M / P does);
- the known wrong formulas computed on the same input (τ = F ∧ r, Ṙ = R ω*, R I⁻¹_body R⁻¹, U Vᵀ with
  det −1, L + Δt·F, …): one that gives the whole output, or, for a tuple (dX/dt, X(t+Δt)), one fully
  present in it (every part it changes is as it makes it), named with the part where it shows;
- a result off by a constant factor, or rounded; a ω* that is not the cross-product matrix;
otherwise the check shows the input, the expected and the returned value (with enough digits to differ).
The inputs are chosen so that the mistakes differ: R off SO(3) as Euler leaves it (where Rᵀ ≠ R⁻¹),
matrices with det(U Vᵀ) = −1 for the projection, several forces, masses other than 1.
A check never raises: a NotImplementedError is "not done yet", any other exception in the student's code
is shown as its type, message and line of the student's own code (no traceback, no line of rbcourse), and
named when it is a classic slip (crashes.py: `^` for a power, arithmetic on the tuple X, a float added in place
to an int array, X.x on a plain tuple, scipy on det R < 0, np.vstack of no force).  Each check returns a CheckResult (passed,
mistake, message); MISTAKES lists every mistake it can name, TEXTS the templates of the other messages
(every text in mistakes.py and texts.py, so that it can be translated).

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

X is the tuple (x, R, P, L) — the checks pass a StateTuple, and a plain tuple too (simulate passes a step back
what it returned, so ``X.x`` fails later where ``x, R, P, L = X`` works); a function may return a plain tuple, a
list or a StateTuple.  Each check tries, after its random inputs, the ones the notebook gives the function later:
forces = [] (the box after its push), one force, X a plain tuple, n_steps = 0 and 1, a push that stops.  ``forces`` is a list of pairs (rᵢ, Fᵢ): world point,
world force.  ``forces_at(t, X)`` returns that list at time t for the state X.

The pushed box (pushed_box(), simulate_or_reference()) runs the student's simulate when its checks
pass, else the reference engine rbcourse.simulate(..., method="euler"), and says which it used.

The language of every message: ex.langue("fr") (or ex.language), ex.current() — rbcourse.workbook.language.

The package, one concept a module:
    result     the verdict (CheckResult)
    mistakes   the catalogue of named mistakes (MISTAKES)
    slides     where a message sends the student to reread (SLIDES, the other sources)
    texts      the other messages' templates (TEXTS), tr
    french     the French of every text
    reference  the reference formulas the checks compare with (the engine's), on X as a StateTuple
    harness    calling the student's function safely: random inputs, the call, reading its output
    crashes    what a raw exception means: the classic slips that raise (explain)
    verdict    comparing with the reference and naming the mistake
    variants   the known wrong formulas, computed on a check's input
    checks     the check_* of the formulas of the state (box_inertia … resultants)
    stepping   check_dxdt, check_euler_step
    projection check_project_so3, check_euler_step_projected
    loop       check_simulate: the loop, checked by watching what it calls
    runs       the pushed box: simulate_or_reference, show_iterations
"""

from ..language import LANGUAGES, current, langue, language
from .checks import (check_angular_velocity, check_box_inertia, check_inverse_inertia, check_resultants,
                     check_velocity)
from .loop import check_simulate
from .mistakes import MISTAKES, Mistake
from .projection import check_euler_step_projected, check_project_so3
from .reference import StateTuple
from .result import CheckResult
from .runs import PushedBox, pushed_box, show_iterations, simulate_or_reference
from .slides import SLIDES
from .stepping import check_dxdt, check_euler_step

__all__ = [
    "LANGUAGES", "langue", "language", "current",
    "StateTuple", "CheckResult", "Mistake", "MISTAKES", "SLIDES",
    "check_box_inertia", "check_velocity", "check_inverse_inertia", "check_angular_velocity",
    "check_resultants", "check_dxdt", "check_euler_step", "check_simulate", "check_project_so3",
    "check_euler_step_projected", "PushedBox", "pushed_box", "simulate_or_reference", "show_iterations",
]
