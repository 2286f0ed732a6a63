"""The two exact torque-free motions, one against the other.

rbcourse/exact/ (free_body.py: Jacobi's solution with scipy.special, as arrays) is the independent
reference; rbcourse/engine/exact_flow.py (compiled, plain floats, its own elliptic functions in
engine/elliptic.py) is the step of the method exact_splitting.  They share no code and no constant, so
each checks the other: here the engine's exact free flow (exact_flow.free_flow, the compiled function the
step calls: one flow over t from X0, retraction and all) equals rb.exact_free_body at several times, in
rotation and angular momentum (world L, and body L = Rᵀ L, which follows the polhode).

Tolerance 1e-10, on max |R_engine − R_reference| (entries of rotations: absolute is relative) and on
|L_engine − L_reference| / |L|: both are exact to rounding, and what rounding can do here is about
1e-16 per radian of motion (|L| t / I <= ~1e3 rad: ~1e-13) times, near the separatrix, the motion's
sensitivity to m' and to the phase near a flip.  Observed: <= 1.4e-13 away from the separatrix, 4e-13 to
1e-11 near it (m' from 1e-14 to 1e-9).  A slip of either side moves R by far more: C·(1 + 1e-8) in the
engine's ψ gives 2e-7, a sign of the reference's relabelling gives 1 (both tried: the test fails).
"""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.engine import exact_flow
from rbcourse.state import to_matrix

TOL = 1e-10
TIMES = (-20.0, -1.3, 0.05, 1.0, 7.5, 20.0)
R_TILT = rb.rotation.rotation_about([1.0, 2.0, 3.0], 0.4)
R_START = rb.rotation.rotation_about([0.2, -0.3, 1.0], 1.3)
BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))                            # asymmetric, y the middle axis
TILTED = rb.RigidBody(1.0, R_TILT @ np.diag([1.0, 2.0, 3.0]) @ R_TILT.T)  # asymmetric, non-diagonal inertia


CASES = {
    "asymmetric_box": (BOX, (0.3, 2.0, 0.5)),
    "asymmetric_tilted_inertia": (TILTED, (1.3, -2.0, 0.7)),
    "asymmetric_near_major_axis": (BOX, (0.1, 0.1, 20.0)),
    "near_symmetric_1e-9_pair_23": (rb.RigidBody(1.0, [1.0, 2.0, 2.0 + 1e-9]), (3.0, 3.0, 3e-7)),
    "near_symmetric_1e-12_pair_12": (rb.RigidBody(1.0, [1.0, 1.0 + 1e-12, 1.7]), (1.3, -2.0, 0.7)),
    "near_symmetric_4e-15": (rb.RigidBody(1.0, [1.0, 1.7 - 4e-15, 1.7]), (3e-7, 3.0, 3.0)),
    "symmetric_cylinder": (rb.RigidBody.cylinder(mass=1.0, radius=0.04, height=0.3), (0.3, 2.0, 0.5)),
    "symmetric_rod": (rb.RigidBody.box(0.5, (0.4, 0.1, 0.1)), (5.0, 1.0, -0.5)),
    "spherical_cube": (rb.RigidBody.box(1.0, (0.2, 0.2, 0.2)), (0.3, 2.0, 0.5)),
    "separatrix_near_side_3": (BOX, (1e-6, 5.0, 1e-6)),          # m' ~ 1e-14, polhode about the major axis
    "separatrix_near_side_1": (BOX, (3e-6, 5.0, 1e-6)),          # … about the minor axis (relabelled)
    "separatrix_1e-9_above": (BOX, (2e-4, 5.0, 1e-4)),
    # spins along a principal axis (R0 = I: the body momentum has exact zeros; a rounding 1e-17 off the
    # unstable middle axis would grow as e^(λt) on both sides alike, an ill-conditioned problem, not a check)
    "spin_minor_axis": (BOX, (5.0, 0.0, 0.0)),
    "spin_middle_axis": (BOX, (0.0, 5.0, 0.0)),
    "spin_major_axis": (BOX, (0.0, 0.0, -5.0)),
    "at_rest": (BOX, (0.0, 0.0, 0.0)),
}
UPRIGHT = {"spin_minor_axis", "spin_middle_axis", "spin_major_axis"}


def start(case):
    """(body, X0) of a case: ω given in body axes, R0 = R_START (the identity for the spins, UPRIGHT)."""
    body, omega = CASES[case]
    R0 = np.eye(3) if case in UPRIGHT else R_START
    return body, rb.State.from_velocities(body, x=(0.0, 0.0, 1.0), R=R0, v=(0.1, -0.2, 0.3),
                                          omega=R0 @ np.asarray(omega, dtype=float))


def engine_flow(body, X0, t):
    """x, R, P, L (one body) after the engine's exact free flow over t from X0 (compiled)."""
    scene = rb.Scene(body)
    sys = scene.compile().system
    S = to_matrix(scene.to_engine(scene.batch(X0)))            # S (1, 18) = [x, R, P, L]
    exact_flow.free_flow(sys, S, t)
    return S[0, 0:3], S[0, 3:12].reshape(3, 3), S[0, 12:15], S[0, 15:18]


@pytest.mark.parametrize("case", sorted(CASES))
def test_engine_flow_equals_the_reference(case):
    body, X0 = start(case)
    ref = rb.exact_free_body(body, X0, np.array(TIMES))
    Ln = max(float(np.linalg.norm(X0.L)), 1e-300)
    for i, t in enumerate(TIMES):
        x, R, P, L = engine_flow(body, X0, t)
        dR = np.abs(R - ref.R[i]).max()
        assert dR <= TOL, f"{case}, t = {t}: R differs by {dR:.3g}"
        assert np.linalg.norm(L - ref.L[i]) / Ln <= TOL, f"{case}, t = {t}: L"
        dm = np.linalg.norm(R.T @ L - ref.R[i].T @ ref.L[i]) / Ln
        assert dm <= TOL, f"{case}, t = {t}: the body angular momentum differs by {dm:.3g}"
        assert np.abs(x - ref.x[i]).max() <= TOL * (1.0 + np.abs(ref.x[i]).max()), f"{case}, t = {t}: x"
        np.testing.assert_array_equal(P, ref.P[i])
    if case != "at_rest":
        assert np.abs(ref.R[-1] - ref.R[2]).max() > 1e-2                # the body turned


def test_the_cases_cover_both_sides_of_the_separatrix():
    """The near-separatrix cases are near it (m' < 1e-12), one on each side (polhode about axis 3, then
    about axis 1: the relabelled branch); the 1e-9 case off it, and the spins have no elliptic part."""
    from rbcourse.exact.free_body import Motion

    def motion(case):
        body, X0 = start(case)
        mp = np.asarray(body.principal_axes).T @ X0.R.T @ X0.L
        return Motion(np.asarray(body.principal_moments)[None], mp[None])

    flips = []
    for case in ("separatrix_near_side_3", "separatrix_near_side_1"):
        ell = motion(case).ell
        assert 0 < ell.mc[0] < 1e-12
        flips.append(bool(ell.flip[0]))
    assert flips == [False, True]
    assert 1e-12 < motion("separatrix_1e-9_above").ell.mc[0] < 1e-6
    for case in ("spin_minor_axis", "spin_middle_axis", "spin_major_axis", "at_rest"):
        assert motion(case).ie.size == 0
