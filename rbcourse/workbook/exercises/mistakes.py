"""The catalogue of the mistakes a check can name (MISTAKES, by id): each Mistake says what is wrong (its
English text here, the French in french.py: MISTAKE_TEXTS) and where the course says it right (a slide's
title or another source, slides.py).
"""
from __future__ import annotations

from dataclasses import dataclass

from ..language import LANGUAGES, text
from .french_mistakes import MISTAKES_FR
from .slides import BOX, ETAT, EULER, FORMULES, ITERATION_1, ITERATION_2, PROJECTION, SLIDES
from .slides import slide_text  # noqa: F401 (importable from here too, as before texts.py and slides.py)
from .texts import TEXTS, tr  # noqa: F401 (the same)


@dataclass(frozen=True)
class Mistake:
    """A known mistake: what is wrong (text) and where the slides say it right (slide), both in the active
    language (rbcourse.workbook.language.current()).  english: its English text; source: a slide's title
    (the same in every language) or the id of another source in TEXTS, texts.py (PROJECTION, BOX)."""
    id: str
    english: str
    source: str

    @property
    def text(self) -> str:
        """What is wrong, in the active language (MISTAKE_TEXTS)."""
        return text(MISTAKE_TEXTS, self.id)

    @property
    def slide(self) -> str:
        """Where to reread: the slide's title, or the other source in the active language."""
        return self.source if self.source in SLIDES else tr(self.source)

_MISTAKES = [
    # --- box_inertia: I_body = M/12 · diag(b² + c², a² + c², a² + b²)
    Mistake("box_not_squared", "the sides must be squared: I_xx = M/12 · (b² + c²), not M/12 · (b + c) "
            "(an inertia is in kg·m²)", BOX),
    Mistake("box_wrong_pairing", "the sides are paired wrongly: the moment about an axis uses the two sides "
            "perpendicular to that axis — I_xx = M/12 (b² + c²), I_yy = M/12 (a² + c²), I_zz = M/12 (a² + b²) "
            "for the sides a, b, c along x, y, z", BOX),
    Mistake("box_missing_twelfth", "the factor 1/12 is missing: I_body = M/12 · diag(b² + c², a² + c², a² + b²)",
            BOX),
    Mistake("box_half_sizes", "you used the half sides (a/2, b/2, c/2) in M/12 (b² + c²): the formula takes "
            "the full side lengths", BOX),
    Mistake("box_missing_mass", "the mass M is missing: I_body = M/12 · diag(b² + c², a² + c², a² + b²)", BOX),
    Mistake("box_moments_not_matrix", "you returned the three moments: return the 3×3 matrix "
            "I_body = np.diag([I_xx, I_yy, I_zz])", BOX),
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
            "Fᵢ ∧ (rᵢ − x), or (x − rᵢ) ∧ Fᵢ (a cross product changes sign when its factors swap)", FORMULES),
    Mistake("lever_arm", "the lever arm is rᵢ − x(t), from the barycentre to the point where the force acts; "
            "you used rᵢ, which gives the torque about the world origin", FORMULES),
    Mistake("tau_sign_and_lever_arm", "two mistakes in τ: the lever arm is rᵢ − x(t) (you used rᵢ) and it comes "
            "first: τ = (rᵢ − x) ∧ Fᵢ (you computed Fᵢ ∧ rᵢ)", FORMULES),
    Mistake("last_force_only", "only the last force counts in your sums: F = Σ Fᵢ and τ = Σ (rᵢ − x) ∧ Fᵢ add "
            "up every force (F += Fᵢ in the loop, not F = Fᵢ)", FORMULES),
    Mistake("F_tau_swapped", "return (F, τ) in this order: you returned (τ, F)", FORMULES),
    Mistake("empty_forces", "with no force (forces = [], as for the box after its push in Part 7) F and τ must be "
            "zero vectors of shape (3,): start both sums from np.zeros(3) (np.vstack and np.stack refuse an empty "
            "list, sum() of nothing is the integer 0)", FORMULES),
    # --- dxdt: (v, ω* R, F, τ)
    Mistake("R_dot_order", "Ṙ = ω* · R, with ω* on the left (each body axis, a column X' of R, turns as "
            "dX'/dt = ω ∧ X'); you wrote R · ω*", FORMULES),
    Mistake("R_dot_missing_R", "Ṙ = ω* · R: you returned ω* alone", FORMULES),
    Mistake("omega_star_sign", "your ω* has the wrong sign (or is transposed: ω*ᵀ = −ω*): ω* a = ω ∧ a, so "
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
    Mistake("forces_once", "forces_at was called only once, before the loop: the forces change with t and with the "
            "state (a force's point rᵢ = x + R bᵢ moves with the body) — call forces_at(t, X) inside the loop, at "
            "each step, with that step's t and X", ITERATION_2),
    Mistake("returned_one_state", "returned one state, not the list of states: simulate returns the arrays of all "
            "n_steps + 1 states X₀, X₁, …, X_n (x of shape (n_steps + 1, 3), R of shape (n_steps + 1, 3, 3), …), "
            "not only the last one", ITERATION_2),
    Mistake("extra_step", "one step too many: n_steps steps give n_steps + 1 states X₀ … X_n, your loop makes "
            "n_steps + 1 (range(n_steps + 1)?)", ITERATION_2),
    Mistake("ignores_dt", "the time step dt given to simulate is not the one passed to step: each iteration is "
            "X = step(M, I_body_inv, X, forces_at(t, X), dt), with that dt", ITERATION_2),
    Mistake("no_step_parameter", "keep the signature simulate(M, I_body_inv, X0, forces_at, dt, n_steps, "
            "step=euler_step): the check passes step=…", ITERATION_2),
    # --- project_so3 and the projected step
    Mistake("svd_V_transposed", "np.linalg.svd returns (U, S, Vᵀ): its third output is already Vᵀ, so the "
            "nearest rotation is U @ Vt (you used U @ Vt.T)", PROJECTION),
    Mistake("svd_not_projected", "you returned R unchanged (U Σ Vᵀ is R itself): the nearest rotation drops Σ, "
            "U Vᵀ", PROJECTION),
    Mistake("columns_normalized", "normalising the columns (or rows) is not enough: they must also be "
            "perpendicular (RᵀR = I); use the SVD R = U Σ Vᵀ → U Vᵀ", PROJECTION),
    Mistake("projection_transposed", "you returned the transpose of the nearest rotation: U Vᵀ, not V Uᵀ", PROJECTION),
    Mistake("not_nearest", "your matrix is a rotation, but not the one nearest R (another update of R, or "
            "np.linalg.qr's Q, which may flip columns): the fix changes R as little as possible; use the SVD "
            "R = U Σ Vᵀ → U Vᵀ", PROJECTION),
    Mistake("not_a_rotation", "the result is not a rotation (RᵀR ≠ I or det R ≠ 1); use the SVD R = U Σ Vᵀ → U Vᵀ",
            PROJECTION),
    Mistake("step_not_projected", "R(t+Δt) is not projected: apply project_so3 to R after the Euler step", PROJECTION),
    Mistake("projected_before", "project R after the Euler step (the step is what pushes R off SO(3)), "
            "not before it", PROJECTION),
    # --- what a function returned (any check)
    Mistake("returned_list", "it returned a Python list, not a NumPy array: later `dt * v` raises a TypeError "
            "and `x + v` joins two lists; return np.array([...]) (or compute with arrays: P / M)", EULER),
    Mistake("integer_array", "your array holds integers (dtype int): an array made from integers, "
            "np.array([0, 0, 0]) or np.zeros(3, dtype=int), truncates every value written into it (0.7 → 0); "
            "start from floats: np.zeros(3), np.array([0.0, 0.0, 0.0])", EULER),
    Mistake("complex_array", "your array holds complex numbers (np.linalg.eig? a square root of a negative "
            "number?): every quantity here is real", EULER),
    Mistake("returned_matrix", "it returned an np.matrix: use plain arrays (np.array) and `@` for products — "
            "with np.matrix, `*` is a matrix product and vectors become 1×3 matrices", EULER),
    Mistake("args_swapped", "arguments in the wrong order: your function gives the right result when its "
            "arguments are swapped ({detail}); keep the exercise's signature {signature}", EULER),
    # --- box_inertia, more
    Mistake("box_inverted", "you returned the inverse I_body⁻¹: box_inertia returns I_body itself, "
            "M/12 · diag(b² + c², a² + c², a² + b²) (the inverse comes later, I_body_inv)", BOX),
    Mistake("box_third", "M/3 goes with the half sides (M/3 · ((b/2)² + (c/2)²)); with the full sides a, b, c "
            "it is M/12: I_body = M/12 · diag(b² + c², a² + c², a² + b²)", BOX),
    Mistake("box_one_moment", "{detail}: each moment uses the two sides perpendicular to its axis, "
            "I_xx = M/12 (b² + c²), I_yy = M/12 (a² + c²), I_zz = M/12 (a² + b²)", BOX),
    Mistake("box_sum_all", "each moment uses only the two sides perpendicular to its axis: "
            "I_xx = M/12 (b² + c²), not M/12 (a² + b² + c²)", BOX),
    # --- velocity, more
    Mistake("velocity_no_mass", "v = P / M: you returned P itself (the momentum, not the velocity); with "
            "M ≠ 1 they differ", EULER),
    Mistake("velocity_mass_squared", "v = P / M: you divided by M twice (P / M²)", EULER),
    Mistake("floor_division", "integer arithmetic: `//` is floor division and int() truncates (both round down "
            "to whole numbers): divide with `/` and keep floats (v = P / M, M / 12)", EULER),
    # --- inverse_inertia, more
    Mistake("R_inverse_not_transpose", "R⁻¹ instead of Rᵀ: equal only for an exact rotation; Euler's R is not "
            "one (R + Δt ω* R leaves SO(3)), and then R · I⁻¹_body · R⁻¹ is not the slides' "
            "I⁻¹(t) = R · I⁻¹_body · Rᵀ — write R.T, not np.linalg.inv(R)", EULER),
    Mistake("missing_transpose", "the transpose is missing: I⁻¹(t) = R · I⁻¹_body · Rᵀ, you computed "
            "R · I⁻¹_body · R (R.T on the right)", EULER),
    Mistake("transpose_both", "only the right-hand R is transposed: I⁻¹(t) = R · I⁻¹_body · Rᵀ, you computed "
            "Rᵀ · I⁻¹_body · Rᵀ", EULER),
    Mistake("missing_R_left", "R is missing on the left: I⁻¹(t) = R · I⁻¹_body · Rᵀ, not I⁻¹_body · Rᵀ "
            "(or Rᵀ · I⁻¹_body)", EULER),
    # --- resultants, more
    Mistake("tau_missing", "τ is zero: the torques were never added up, τ = Σ (rᵢ − x) ∧ Fᵢ", FORMULES),
    Mistake("lever_arm_plus", "the lever arm is rᵢ − x(t), from the barycentre to the point: you used rᵢ + x(t)",
            FORMULES),
    Mistake("first_force_only", "only the first force counts in your sums: F = Σ Fᵢ and τ = Σ (rᵢ − x) ∧ Fᵢ "
            "add up every force (did you return inside the loop?)", FORMULES),
    Mistake("force_skipped", "one force is left out of your sums (range(len(forces) - 1)? forces[1:]?): "
            "F = Σ Fᵢ and τ = Σ (rᵢ − x) ∧ Fᵢ run over every force", FORMULES),
    Mistake("dot_for_cross", "τ is a vector: (rᵢ − x) ∧ Fᵢ is the cross product np.cross(r - x, F), not the "
            "dot product np.dot (a number)", FORMULES),
    Mistake("tau_of_sums", "the torque of the sum is not the sum of the torques: τ = Σ (rᵢ − x) ∧ Fᵢ, each "
            "force with its own lever arm, not (Σ rᵢ − x) ∧ Σ Fᵢ or (r̄ − x) ∧ F", FORMULES),
    Mistake("force_pair_order", "each pair is (rᵢ, Fᵢ), the point first: `for r, F in forces`; you read "
            "them as (Fᵢ, rᵢ)", FORMULES),
    Mistake("forces_averaged", "F = Σ Fᵢ and τ = Σ (rᵢ − x) ∧ Fᵢ are sums, not averages (no / len(forces))",
            FORMULES),
    # --- dxdt, more
    Mistake("R_dot_elementwise", "Ṙ = ω* · R is a matrix product: `ω* * R` multiplies element by element; "
            "write star(omega) @ R", FORMULES),
    Mistake("star_wrong", "your ω* is not the cross-product matrix of ω (ω* a must equal ω ∧ a): "
            "ω* = [[0, −ω_z, ω_y], [ω_z, 0, −ω_x], [−ω_y, ω_x, 0]] — check each entry", FORMULES),
    Mistake("R_dot_is_omega", "dR/dt = ω* · R is a 3×3 matrix: you returned the vector ω", FORMULES),
    Mistake("R_dot_body_frame", "you wrote Ṙ = R · (ω_body)* with ω_body = I⁻¹_body Rᵀ L: it equals ω* R only "
            "while R is an exact rotation, and Euler's R is not one; the slides' Ṙ = ω* · R with the world ω", FORMULES),
    Mistake("cross_rows", "np.cross(omega, R) crosses ω with each row of R, but the body axes X', Y', Z' are the "
            "columns of R: Ṙ = ω* · R = star(omega) @ R (or np.cross(omega, R, axis=0))", FORMULES),
    Mistake("R_dot_transposed", "you returned (ω* R)ᵀ: Ṙ = ω* · R, not its transpose (each column of R, a body "
            "axis, turns as dX'/dt = ω ∧ X')", FORMULES),
    Mistake("dP_times_mass", "dP/dt = F: you multiplied F by M", FORMULES),
    Mistake("rates_order", "return the rates in the state's order (v, ω* R, F, τ): you returned τ before F",
            FORMULES),
    Mistake("dP_is_P", "dP/dt = F: you returned P itself", FORMULES),
    Mistake("dL_is_L", "dL/dt = τ: you returned L itself", FORMULES),
    # --- euler_step, more
    Mistake("L_step_uses_F", "L(t+Δt) = L(t) + Δt · τ(t): you added Δt · F (the force, not the torque)", EULER),
    Mistake("P_step_uses_tau", "P(t+Δt) = P(t) + Δt · F(t): you added Δt · τ (the torque, not the force)", EULER),
    Mistake("dt_twice", "Δt is applied twice (Δt² · dX/dt): X(t+Δt) = X(t) + Δt · dX/dt, once — did your "
            "dxdt multiply by dt already?", EULER),
    Mistake("R_exact_rotation", "you turned R by an exact rotation (expm(Δt ω*) · R, or Rodrigues): the slides' "
            "Euler step is R(t+Δt) = R(t) + Δt · ω* R(t) — its drift off SO(3) is what Part 8 studies", EULER),
    Mistake("projected_in_euler_step", "you projected R back onto SO(3) inside euler_step: the slides' Euler "
            "step is R + Δt · ω* R, unprojected; the projection is Part 8's fix (euler_step_projected)", EULER),
    Mistake("R_dot_times_R", "Ṙ = ω* R already holds R: R(t+Δt) = R + Δt · Ṙ, not R + Δt · Ṙ · R", EULER),
    Mistake("rates_after_update", "τ was computed about the new x(t+Δt): the slides' explicit Euler takes all "
            "of dX/dt = (v, ω* R, F, τ) from X(t) — compute it first, then update x, R, P, L", ITERATION_1),
    Mistake("half_step", "you stepped by Δt/2: X(t+Δt) = X(t) + Δt · dX/dt, a whole step", EULER),
    Mistake("state_order", "return the new state in the order X = (x, R, P, L)", EULER),
    Mistake("scaled", "your result is {detail} × the right one: the formula is right up to a constant factor — "
            "look for a factor too many or missing", EULER),
    Mistake("rounded", "your result is rounded ({detail}): return the full-precision value (no np.round, int() "
            "or formatted strings)", EULER),
    Mistake("returned_rates", "you returned dX/dt, the rates: euler_step returns the new state "
            "X(t+Δt) = X(t) + Δt · dX/dt", EULER),
    Mistake("returned_increment", "you returned Δt · dX/dt, the change only: add it to X(t), "
            "X(t+Δt) = X(t) + Δt · dX/dt", EULER),
    Mistake("euler_minus", "X(t+Δt) = X(t) + Δt · dX/dt: you subtracted the rates (time runs backwards)", EULER),
    # --- project_so3, more
    Mistake("svd_no_det_fix", "here det(U Vᵀ) = −1 and U Vᵀ is a reflection, not a rotation: flip the sign of "
            "the last column of U (the smallest singular value) when det(U Vᵀ) < 0, then U Vᵀ", PROJECTION),
    Mistake("svd_negated", "−U Vᵀ has det +1 but is far from R (it turns every axis around): when "
            "det(U Vᵀ) < 0, flip only the last column of U (the smallest singular value)", PROJECTION),
    Mistake("svd_wrong_column", "when det(U Vᵀ) < 0, flip the column of U that goes with the smallest "
            "singular value, the last one (U[:, 2]), not the first or the second", PROJECTION),
    Mistake("svd_flip_always", "flip U's last column only when det(U Vᵀ) < 0: flipped always, U diag(1, 1, −1) Vᵀ "
            "is a reflection whenever U Vᵀ is already a rotation", PROJECTION),
    Mistake("svd_factors_swapped", "the nearest rotation is U @ Vt (U first): you computed Vt @ U", PROJECTION),
    Mistake("svd_U_only", "U alone is not the nearest rotation: R = U Σ Vᵀ → U Vᵀ (keep Vᵀ, drop Σ)",
            PROJECTION),
    Mistake("scaled_by_det", "dividing R by det(R)^(1/3) fixes its volume, not its angles (RᵀR ≠ I still): "
            "use the SVD R = U Σ Vᵀ → U Vᵀ", PROJECTION),
    # --- issue 30: the families of slips, whatever way they are written
    Mistake("precedence", "operator precedence: `M/12*b**2 + c**2` is (M/12)·b² + c² — the sum needs its "
            "parentheses, M/12 * (b**2 + c**2)", BOX),
    Mistake("square_of_sum", "(b + c)² is not b² + c²: square each side, then add, b**2 + c**2", BOX),
    Mistake("moments_full_matrix", "the three moments fill the whole 3×3 matrix (broadcast over rows or columns): "
            "they go on the diagonal only, np.diag([I_xx, I_yy, I_zz]), zeros elsewhere", BOX),
    Mistake("xor_power", "`^` is not a power in Python: it is XOR (bitwise exclusive or), which floats do not have "
            "— write b**2 (or b * b)", BOX),
    Mistake("factor_order", "the factors are in the wrong order: I⁻¹(t) = R · I⁻¹_body · Rᵀ, R first and Rᵀ last "
            "(a matrix product does not commute, and Euler's R is not a rotation: R Rᵀ ≠ I)", EULER),
    Mistake("cross_for_product", "ω = I⁻¹(t) · L is a matrix times a vector, I_inv @ L: np.cross is the cross "
            "product ∧, which has no place here", EULER),
    Mistake("elementwise_cross", "(rᵢ − x) ∧ Fᵢ is the cross product np.cross(r - x, F): `*` (or np.multiply, "
            "einsum without the ε) multiplies element by element", FORMULES),
    Mistake("int_in_place", "an array of integers cannot take a float in place: np.array([0, 0, 0]) (or "
            "np.zeros(3, dtype=int)) holds integers, and `F += F_i` would have to truncate, so NumPy refuses; start "
            "from floats: np.zeros(3)", EULER),
    Mistake("state_attributes", "X.x works on the checks' StateTuple, but simulate passes your function the state "
            "your step returned, a plain tuple (x, R, P, L), which has no .x: unpack it, x, R, P, L = X", EULER),
    Mistake("tuple_arithmetic", "X is a tuple of four arrays of different shapes: a tuple times a float raises, "
            "`X + Y` joins two tuples end to end, np.array(X) cannot hold a (3,) and a (3, 3) together — update "
            "each part: x + dt * v, R + dt * R_dot, P + dt * F, L + dt * tau", EULER),
    Mistake("other_method", "another method than the slides' explicit Euler: X(t+Δt) = X(t) + Δt · dX/dt(t), "
            "with dX/dt evaluated once, at X(t)", EULER),
    Mistake("call_order", "{detail}: the loop's call is X = step(M, I_body_inv, X, forces_at(t, X), dt) — "
            "forces_at(t, X) takes the time first, step takes the forces before dt", ITERATION_2),
    Mistake("states_transposed", "one state per row: x of shape (n_steps + 1, 3), R (n_steps + 1, 3, 3); yours are "
            "transposed (.T, np.column_stack, np.stack(…, axis=-1)) — np.array(list_of_x) stacks the states as "
            "rows", ITERATION_2),
    Mistake("state_not_advanced", "X is never replaced by the new state: each step must start from the last one, "
            "X = step(M, I_body_inv, X, forces_at(t, X), dt) — yours starts every step from X₀", ITERATION_2),
    Mistake("scipy_negative_det", "scipy's Rotation.from_matrix refuses a matrix with det R < 0 (a ValueError): "
            "here det(U Vᵀ) = −1 — use the SVD, U, S, Vt = np.linalg.svd(R), and flip U's last column when "
            "det(U @ Vt) < 0", PROJECTION),
    Mistake("forces_changed", "step must get the forces forces_at(t_k, X_k) returned at this step, as they are (not "
            "kept from earlier steps, added to, or changed): X = step(M, I_body_inv, X, forces_at(t, X), dt)",
            ITERATION_2),
    Mistake("stateful", "your function answers from an earlier call ({detail}): a cache, a global, a mutable "
            "default or a flag set at the first call? Compute the answer from the arguments, every time", EULER),
    Mistake("float32", "your array is float32, which keeps about 7 digits: every check asks float64 (NumPy's "
            "default, np.zeros(3), np.array([…], dtype=float)), right to 1e-7 relative — no dtype=np.float32, "
            ".astype(np.float32)", EULER),
    Mistake("parts_order", "the parts of the result are in another order: {detail}", EULER),
    Mistake("column_vector", "a (3, 1) column where a vector of shape (3,) is asked: build vectors as "
            "np.array([a, b, c]), not [[a], [b], [c]] (or flatten with .ravel())", EULER),
]
MISTAKES: dict[str, Mistake] = {m.id: m for m in _MISTAKES}
"""Every mistake a check can name, by id (the CheckResult.mistake of a diagnosis).  Besides these, a
result's mistake may be "not_done", "error", "not_a_function", "returned_none", "not_numbers",
"wrong_return", "wrong_shape", "wrong_result" or "check_failed" (a bug in the check itself), whose texts are
templates in TEXTS (texts.py).  A mistake's text may hold {detail} (and other fields) that the check fills in."""

MISTAKE_TEXTS = {"en": {m.id: m.english for m in _MISTAKES}, "fr": MISTAKES_FR}
"""Every mistake's text, by language, then by id (Mistake.text reads it in the active language)."""
assert all(set(MISTAKE_TEXTS[code]) == set(MISTAKES) for code in LANGUAGES), "a mistake without a translation"
