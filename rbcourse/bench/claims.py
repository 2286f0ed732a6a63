"""What each method promises on the named hard cases (bench/hardcases.py): a table, method -> Claims.

The methods themselves (rbcourse.methods.METHODS) keep only their own properties (order,
invariants, cost, reference); these promises are in the bench's vocabulary, checked by
stability.broken_claims on every cell of the stability matrix (tests/bench/test_stability.py).
"""
from __future__ import annotations

from dataclasses import dataclass, field

AT_REST = {"box_at_rest": "faithful"}      # a box lying on the floor stays put, under every method
P_KEPT = {"P": 1e-12}                      # no external force: total momentum to rounding


@dataclass(frozen=True)
class Claims:
    """A method's promises on the hard cases.

    stable: the promises in words.
    finite: finishes every case;  diverges_on: the cases where it must blow up (a clear error).
    so3: max ‖RᵀR − I‖ on every finished run;  free_L, free_norm_L, free_energy: relative tolerances
        on world L, |L| and the energy of a free body (these four are "kept to rounding": tolerances
        for 10⁴ steps, growing in proportion beyond, as rounding adds up — stability.rounding_budget).
    energy_bounded: over the long free runs the energy error does not drift (last half <= 3 × first
        half, or below 1e-10);  dissipative: a free body's energy never increases.
    keeps: {invariant: tolerance} for the invariants of stability.INVARIANTS a case declares beyond the
        free body's (e.g. "L_z" on the tops, "P" on the pair): kept to rounding, on every finished case that
        declares it (the same budget per 10⁴ steps).
    outcomes: {case: outcome}: the category (stability.OUTCOMES) this method's cell must have there.
    (None, empty: no such promise.)
    """
    stable: str
    finite: bool = False
    diverges_on: tuple = ()
    so3: float | None = None
    free_L: float | None = None
    free_norm_L: float | None = None
    free_energy: float | None = None
    energy_bounded: bool = False
    dissipative: bool = False
    keeps: dict = field(default_factory=dict)
    outcomes: dict = field(default_factory=dict)


CLAIMS: dict[str, Claims] = {
    "euler": Claims(
        "none: energy grows; it overflows on fast spins and the heavy top (B, C, thin disk, rod), "
        "and stops there with the divergence error",
        finite=False, free_L=1e-15,
        diverges_on=("fast_spin_large_step", "fast_thin_disk", "slender_rod", "heavy_top_coarse", "heavy_top_fine",
                     "symmetric_body")),
    "euler_project": Claims(
        "finite on every hard case but the stiff spring (its energy grows there until it overflows at t = 2.9 s), "
        "R on SO(3); but the energy error is large (first order)",
        finite=True, diverges_on=("stiff_spring",), so3=1e-12, free_L=1e-15, keeps={"L_z": 1e-12, **P_KEPT},
        outcomes=AT_REST),
    "quaternion_euler": Claims(
        "Baraff's (x, q, P, L): on SO(3) on every hard case; a free body's world L and |L| exact (L is "
        "never changed) and so its energy bounded by |L|²/2I_min, but not kept: it grows toward that bound "
        "(first order); the heavy top's vertical L about the pivot exact; the stiff spring's energy grows until it "
        "overflows (t = 2.9 s)",
        finite=True, diverges_on=("stiff_spring",), so3=1e-12, free_L=1e-15, free_norm_L=1e-15,
        keeps={"L_z": 1e-12, **P_KEPT}, outcomes=AT_REST),
    "quaternion_euler_body": Claims(
        "(x, q, P, L_b): R on SO(3) while it runs; world L drifts (Euler on L_b's gyroscopic rate L_b × ω_b); "
        "energy grows without bound and it overflows on B at dt = 1e-2, the rod and the coarse heavy top",
        finite=False, so3=1e-12, diverges_on=("fast_spin_large_step", "slender_rod", "heavy_top_coarse"),
        keeps=P_KEPT, outcomes={"fast_thin_disk": "ran away", **AT_REST}),
    "rk4": Claims(
        "finite on every hard case at small steps; energy drifts slowly; on the body-frame L_b it cannot keep L_z "
        "(the world vertical is not a body-frame quantity)",
        finite=True, so3=1e-12, keeps=P_KEPT, outcomes=AT_REST),
    "rkmk4": Claims(
        "R on SO(3) to rounding; energy drifts slowly",
        finite=True, so3=1e-12, free_L=1e-12, keeps={"L_z": 1e-12, **P_KEPT}, outcomes=AT_REST),
    "adaptive": Claims(
        "finite on every hard case (the substep shrinks as needed); energy drift set by rtol",
        finite=True, so3=1e-12, keeps=P_KEPT,
        outcomes={"heavy_top_coarse": "faithful", "heavy_top_fine": "faithful", "mass_ratio_pair": "faithful",
                  "stiff_spring": "faithful", **AT_REST}),
    "symplectic_euler": Claims(
        "finite and on SO(3) on every hard case, L and |L| exact for a free body; the energy is not kept "
        "(it drifts to the largest value |L|²/2I_min allows)",
        finite=True, so3=1e-12, free_L=1e-12, free_norm_L=1e-12, keeps={"L_z": 1e-12, **P_KEPT}, outcomes=AT_REST),
    "implicit_gyro": Claims(
        "finite and on SO(3) at any step; energy never grows (dissipative)",
        finite=True, so3=1e-12, dissipative=True, keeps=P_KEPT, outcomes=AT_REST),
    "implicit_midpoint": Claims(
        "finite and on SO(3) on every hard case; a free body's L, |L| and energy exact, and a top's L_z about its "
        "pivot exact (the midpoint on the world momenta, R' = R exp(h ω̄*)); its Newton solve, with the forces' "
        "derivative, settles on the stiff spring (ω Δt = 1.97) and keeps that linear spring's energy to rounding",
        finite=True, so3=1e-12, free_L=1e-12, free_norm_L=1e-12, free_energy=1e-12,
        keeps={"L_z": 1e-12, **P_KEPT}, outcomes=AT_REST),
    "splitting": Claims(
        "finite and on SO(3) on every hard case; |L| exact; energy bounded without drift",
        finite=True, so3=1e-12, free_L=1e-12, free_norm_L=1e-12, energy_bounded=True,
        keeps={"L_z": 1e-12, **P_KEPT}, outcomes=AT_REST),
    "exact_splitting": Claims(
        "exact for a free body at any step (|L|, energy, SO(3)); with torques, symplectic: energy bounded",
        finite=True, so3=1e-12, free_L=1e-12, free_norm_L=1e-12, free_energy=1e-12, energy_bounded=True,
        keeps={"L_z": 1e-12, **P_KEPT},
        outcomes={"heavy_top_fine": "faithful", "mass_ratio_pair": "faithful", **AT_REST}),
    "variational": Claims(
        "Lie-group variational with the Cayley map (Hamilton–Pontryagin; Bou-Rabee & Marsden, Kobilarov, Crane & "
        "Desbrun): R on SO(3), a free body's L and |L| exact, a top's L_z about its pivot exact, energy bounded "
        "(exact for a free symmetric body); a step exists at any h|ω|, so it finishes every hard case",
        finite=True, so3=1e-12, free_L=1e-12, free_norm_L=1e-12, energy_bounded=True,
        keeps={"L_z": 1e-12, **P_KEPT}, outcomes=AT_REST),
}
