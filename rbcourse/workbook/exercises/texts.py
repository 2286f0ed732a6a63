"""The generic message templates of the checks (not done, an error, a wrong result, …), by language then by id
(TEXTS; the English here, the French in french.py), and tr: a template in the active language.  With the
mistakes' texts (mistakes.py), every text a check prints, so that it can be translated."""
from __future__ import annotations

from ..language import text
from .french import TEXTS_FR


TEXTS_EN = {
    "part": "{part}: ",
    "the_euler_step": "the Euler step",
    "pass": "✓ {name}: {formula} — correct on {count}{note}",
    "fail": "✗ {name}: {text}\n   → reread {slide}",
    "slide": "the slide “{slide}”",
    "projection": "Part 8 of the notebook: the nearest rotation, R = U Σ Vᵀ → U Vᵀ (the slides stop at Euler)",
    "box": "Baraff's notes, the inertia of a box (eq. 2-27): the slides take I_body as given",
    "random_inputs": "{n} random inputs",
    "random_runs": "{n} random runs",
    "formula_project": "R ← U Vᵀ, the nearest rotation",
    "formula_projected": "Euler step, then R ← U Vᵀ",
    "formula_simulate": "X_{k+1} = step(X_k), forces_at(k·Δt, X_k), n_steps + 1 states",
    "not_done": "○ {name}: not done yet (it raises NotImplementedError)",
    "not_done_calls": "○ {name}: not done yet (it calls {callee}, which raises NotImplementedError)",
    "not_defined": "○ {name}: not done (the notebook defines no function {name})",
    "out_of_time": "✗ {name}: still running when its time was up (an endless loop?)",
    "library_call": "✗ {name}: it takes its answer from rbcourse ({detail}): the library's own implementation is "
                    "not a solution — write the formula yourself, with numpy",
    "error": "✗ {name} raised {exc}{where}\n   on the input {input}",
    "error_reading": "✗ {name}: what it returned could not be read ({exc}{where})\n   on the input {input}",
    "not_a_function": "✗ check_{name} takes your function itself: check_{name}({name}), not its result — got {got}",
    "check_failed": "✗ check_{name} itself failed ({exc}): please tell your teacher",
    "returned_none": "it returned None — did you forget `return`?",
    "not_numbers": "it returned {got}, which is not an array of numbers",
    "wrong_return": "it returned {got}; expected {want}",
    "wrong_count": "it returned {n} values; expected {k}: {want}",
    "wrong_result": "wrong result: expected {want}, got {got}{nan} — on the input {input}",
    "wrong_part": "wrong result: {label} should be {want}, got {got}{nan}{also} — on the input {input}",
    "wrong_state": "wrong result: {label} differs first at state {k}: expected {want}, got {got} — on the input {input}",
    "nan": " (it contains NaN or inf)",
    "also_one": "; {labels} is wrong too",
    "also_many": "; {labels} are wrong too",
    "seen_in": "seen in {label}",
    "on_input": "on the input {input}",
    "in_label": "in {label}: ",
    "part_shape": "{label} has shape {got}; expected {want}",
    "shape": "it returned shape {got}; expected {want}",
    "shape_on_input": "{shape} (on the input {input})",
    "raised": "it raised {exc}{where}",
    "changed": "it changed {names}",
    "detail_on_input": "{text} (on the input {input})",
    "swapped": "the check calls {call}; your {name}{declared} takes {b} where {a} is passed, and {a} where {b} is",
    "list_detail": "{where}it returned {got}",
    "int_detail": "{where}dtype {dtype}, values {values}",
    "complex_detail": "{where}{real} + i·{imag}",
    "tuple_want": "a tuple ({labels})",
    "arrays_want": "the arrays ({labels})",
    "rounded_detail": "to {k} decimals",
    "moment_wrong": "{moments} {verb} wrong (expected {formulas})",
    "is": "is",
    "are": "are",
    "and": " and ",
    "gram_schmidt": "a rotation close to R, though not the nearest one — Gram–Schmidt? Fine for this fix",
    "list_of_states": "it returned a list of {n} states: return four arrays (x, R, P, L), e.g. "
                      "x = np.array([X[0] for X in states])",
    "got_states": "got {got} states for n_steps = {n}",
    "times": "your times: {got}…, expected {want}…",
    "stale_at": "at step {i} it got a state other than X_{i}",
    "called_times": "it was called {k} times for n_steps = {n}",
    "dt_given": "step got dt = {got} instead of {want}",
    "X0_changed": "X0",
    "where": " (in {name}, line {line}: {code})",
    "where_no_code": " (in {name}, line {line})",
    "heun": "Heun's method (a predictor step, then the mean of the two slopes)",
    "midpoint": "the midpoint method (the slope taken at X(t) + Δt/2 · dX/dt)",
    "called": "simulate called {fn}({got})",
    "bad_step_call": "step(M, I_body_inv, X, forces, dt) takes the list of forces, then the number dt",
    "bad_forces_at_call": "forces_at(t, X) takes the time t (a number) first, then the state X",
    # the pushed box (runs.py)
    "run_not_done": "{name}() is not done yet",
    "run_not_passing": "{name}() does not pass its check yet",
    "your_code": "{method} (your code)",
    "run_yours": "your simulate() with {step}(): {n} steps of Δt = {dt} s, t = 0 → {t_end} s; {pushed}",
    "run_diverged": "   diverged at t = {t} s ({reason}); kept up to t = {kept} s",
    "run_raised": "your simulate() raised {exc}",
    "run_reference": "{why} → the reference engine instead: rbcourse.simulate(scene, X0, t_end={t_end}, dt={dt}, "
                     "method={method}); {pushed}",
    "pushed": "the box pushed by F = {F} N for {T} s",
    "first_state": "its first state is already {reason}",
    "iter_reference": "with the reference Euler step (your euler_step is not written yet)",
    "iter_yours": "with your euler_step",
    "iter_not_passing": "with your euler_step — it does not pass check_euler_step yet, so these are not the slides' "
                        "numbers:\n    {first}",
    "iter_no_check": "it does not pass its check",
    "iter_stopped": "● Itération {i}: your euler_step {text} — stopped here",
    "iter_raised": "raised {exc}",
    "iter_shapes": "it returned shapes {shapes}, expected (3,), (3, 3), (3,), (3,)",
    "iter_head": "● Itération {i}  (t = {t0} → {t1} s):  F = {F},  τ = {tau}",
    "unchanged": "unchanged",
    "moved": "moved",
    "turned": "turned",
}

TEXTS = {"en": TEXTS_EN, "fr": TEXTS_FR}
"""The generic message templates (str.format), by language, then by id: with MISTAKES, every text a check
prints.  Every language has the same ids with the same {placeholders} (tests/workbook/test_mistakes.py)."""


def tr(key: str) -> str:
    """The template of id `key` in the active language: TEXTS[current()][key]."""
    return text(TEXTS, key)
