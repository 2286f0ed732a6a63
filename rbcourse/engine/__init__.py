"""The kernel: the slides' physics written once, per body, compiled with numba (or run as Python).

It is arrays and numba only: it imports nothing of rbcourse outside engine/.  The layers above build its
data (Scene.compile: a System, system.py) and drive it (rbcourse/simulate.py, with driver.py).

Where each formula of the slides is (follow rb.simulate(..., "euler"): simulate.py: simulate_compiled →
run.py: run_euler (the loop, given euler.euler_family_step) → euler.py: euler_step → motion.py):

    X(t + Δt) = X(t) + Δt · dX/dt        euler.py: euler_step            ("Evolution temporelle (Euler)",
                                                                          "Itération 1 / Itération 2")
    dX/dt = (v, Ṙ, F, τ)                 motion.py: dxdt                  ("Les Formules")
    v = P / M                            motion.py: velocity
    I⁻¹(t) = R I⁻¹_body Rᵀ               motion.py: inverse_inertia
    ω = I⁻¹(t) L                         motion.py: angular_velocity
    Ṙ = ω* R                             motion.py: rotation_rate (ω*: algebra.py: star)
    rᵢ = x + R bᵢ                        motion.py: body_point
    τᵢ = (rᵢ − x) ∧ Fᵢ                   motion.py: torque
    F = Σ Fᵢ,  τ = Σ τᵢ                  motion.py: resultants            ("Les résultantes")
    each effect's force                  motion.py: effect_on_body (gravity, point forces, springs, drags;
                                         effect_on: a spring that joins two bodies)

The rest, file by file: jit.py the switch (compiled or not); algebra.py 3-vectors and 3×3 matrices as tuples;
system.py a scene as data; plan.py how a method is stepped, as data (the layouts of the state rows);
tableaus.py the Butcher tables; control.py the adaptive step-size control; quaternion.py the quaternion
states; stages.py the explicit Runge–Kutta stage loop; steps.py every method's step, in one signature; geometric.py,
implicit.py, variational.py, adaptive.py, exact_flow.py (with elliptic.py, compositions.py) the other methods;
orthonormalize.py R back onto SO(3); contact.py (with contact_points.py, least_norm.py, symmetric.py) the
ground, and grounds.py every ground of a scene after each step, inside the loop; profiles.py forces over time as data;
rows.py the same formulas over many rows (the numpy face: rbcourse/rowwise.py); run.py the checked, recorded
loop, and a named loop per method (numba compiles a run's own method only, its forces only if the scene has some,
its contact solve only if it has a ground, its kicks only if it has impulses: kicks.py, the scene's kicks sorted by
time, a step that holds some split at their times); cache.py numba's disk cache; interpreted.py the same files
loaded as plain Python.

Importing this package loads nothing (numba loads with jit.py, at the first compiled run).
"""


def __getattr__(name):
    if name in ("COMPILED", "IMPLEMENTATION", "WHY"):
        from . import jit
        return getattr(jit, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["COMPILED", "IMPLEMENTATION", "WHY"]
