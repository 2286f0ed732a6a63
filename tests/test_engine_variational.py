"""The Lie group variational integrator (rbcourse/engine/variational.py; Lee, Leok & McClamroch 2005): compiled
against the same run as Python (fast=False), its order against the exact torque-free motion, its invariants
(R on SO(3), a free body's world L, |L| and energy, L_z about a top's pivot), the bounded energy of a long top
run, the step that cannot exist (h |ω| > 1), and bad inputs."""
import numpy as np
import pytest

import rbcourse as rb
from rbcourse.bench.problems import problem_A, problem_C
from rbcourse.engine.variational import discrete_rotor
from test_engine_implicit import CASES, spread, top_run

M = "variational"


@pytest.mark.parametrize("name", ["free", "free_fast_spin_full_inertia", "gravity", "point_body_f(t)",
                                  "spring_damped", "heavy_top", "three_bodies_spring_0_2"])
def test_compiled_equals_python(name):
    scene, X0 = CASES[name]()
    fast = rb.simulate(scene, X0, 0.5, 1e-3, M)
    slow = rb.simulate(scene, X0, 0.5, 1e-3, M, fast=False)
    for k in "xRPL":
        d = spread(getattr(fast, k), getattr(slow, k))
        assert d <= 1e-12, (name, k, d)


def test_rotor_solves_the_discrete_equation():
    """(F J_d − J_d Fᵀ)^∨ = h Π with J_d = tr(J)/2 I − J, F a rotation (a full, non-diagonal J)."""
    J = np.array([[0.02, 0.001, 0.0], [0.001, 0.03, 0.002], [0.0, 0.002, 0.04]])
    Pi, h = np.array([0.01, 0.3, -0.05]), 0.05
    F, ok = discrete_rotor(tuple(map(tuple, J)), tuple(map(tuple, np.linalg.inv(J))), tuple(Pi), h)
    F = np.array(F)
    Jd = np.trace(J) / 2 * np.eye(3) - J
    S = F @ Jd - Jd @ F.T
    assert ok
    np.testing.assert_allclose([S[2, 1], S[0, 2], S[1, 0]], h * Pi, rtol=0, atol=1e-15)
    np.testing.assert_allclose(F.T @ F, np.eye(3), atol=1e-15)


def test_order_2_against_the_exact_free_motion():
    """The tennis racket (A) for 2 s against rb.exact_free_body: rotation error ~ dt², order 2 ± 0.3."""
    p = problem_A()
    body = p.scene.bodies[0]
    errs = []
    for dt in (4e-2, 2e-2, 1e-2):
        traj = rb.simulate(p.scene, p.X0, 2.0, dt, M)
        R_ref = rb.exact_free_body(body, p.X0, np.array([2.0])).R[-1]
        errs.append(np.linalg.norm(traj.R[-1] - R_ref))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(orders - 2.0) <= 0.3), orders


def test_free_body_invariants_to_rounding():
    """A (200 s, dt = 1e-2, 2·10⁴ steps): RᵀR − I, world L, |L| and the energy to rounding (the discrete
    Moser–Veselov rotor keeps them all), while the body flips."""
    p = problem_A()
    traj = rb.simulate(p.scene, p.X0, 200.0, 1e-2, M)
    R, L, E = traj.R, traj.angular_momentum(), traj.kinetic_energy()
    assert np.abs(np.einsum("kji,kjl->kil", R, R) - np.eye(3)).max() <= 1e-14
    assert np.abs(L - L[0]).max() <= 1e-14 * np.linalg.norm(L[0])
    assert np.ptp(np.linalg.norm(L, axis=1)) <= 1e-14 * np.linalg.norm(L[0])
    assert np.abs(E - E[0]).max() <= 1e-13 * E[0]
    assert np.abs(R[:, 1, 1]).min() < 0.5                  # the racket does flip: not kept by standing still


@pytest.mark.parametrize("dt", [2e-3, 4e-3])
def test_heavy_top_keeps_Lz_and_its_tilt(dt):
    """C (5 s): L_z about the pivot to rounding (gravity's torque about it is horizontal, and only the kicks
    change L); the tilt stays within the true 30°–33.7° (+0.1°: measured 30°–33.68° at dt = 2e-3)."""
    traj, dLz, tilt = top_run(M, dt)
    assert dLz <= 1e-12, dLz
    assert 29.99 <= tilt.min() and tilt.max() <= 33.8, (tilt.min(), tilt.max())
    assert np.ptp(tilt) > 1.0


def test_no_discrete_rotor_beyond_a_quarter_turn():
    """C at dt = 1e-2 is ω·Δt = 2: J₃ sin θ = h Π₃ has no solution (sin θ = 2), so the run stops at its first
    step with SimulationDiverged (the start kept), never a silently wrong step."""
    with pytest.raises(rb.SimulationDiverged) as err:
        top_run(M, 1e-2)
    assert err.value.trajectory.t[-1] == 0.0 and "variational" in str(err.value)


def test_energy_bounded_on_a_long_top_run():
    """C for 50 s at dt = 2e-3 (2.5·10⁴ steps): the energy error oscillates, it does not drift — the last fifth's
    largest error is within 1.5× of the first fifth's (a drift of the size of the oscillation would double it)."""
    p = problem_C()
    traj = rb.simulate(p.scene, p.X0, 50.0, 2e-3, M, record_every=10)
    E = traj.kinetic_energy() + p.scene.bodies[0].mass * 9.81 * traj.x[:, 2]
    dE = np.abs(E - E[0]) / abs(E[0])
    n = len(dE) // 5
    assert 0.0 < dE[-n:].max() <= 1.5 * dE[:n].max(), (dE[:n].max(), dE[-n:].max())
    assert dE.max() <= 1e-4


def test_bad_inputs_rejected():
    scene, X0 = CASES["free"]()
    with pytest.raises(ValueError, match="takes no options"):
        rb.METHODS[M].configured(rtol=1e-6)
    with pytest.raises(ValueError, match="dt"):
        rb.simulate(scene, X0, 1.0, -1e-3, M)
    with pytest.raises(ValueError, match="method"):
        rb.simulate(scene, X0, 1.0, 1e-3, "variationnal")


def test_declared_properties():
    m = rb.METHODS[M]
    assert m.order == 2 and {"SO(3)", "L", "|L|", "energy"} <= m.keeps
    assert "Lee" in m.reference and "Leok" in m.reference


def test_symmetric():
    """A step of −h from the result of a step of h gives the start back, to rounding (free, gravity, heavy top)."""
    from rbcourse.engine.driver import encode
    from rbcourse.engine.motion import work
    from rbcourse.engine.system import compile_scene
    from rbcourse.engine.variational import variational_step
    from rbcourse.integrators.tableaus import MIDPOINT
    A, b = np.ascontiguousarray(MIDPOINT.A), np.ascontiguousarray(MIDPOINT.b)
    for name in ["free", "gravity", "heavy_top", "free_fast_spin_full_inertia"]:
        scene, X0 = CASES[name]()
        sys = compile_scene(scene).system
        Y = encode("matrix", scene.to_engine(X0))
        Y1, Y2, U, K, w = np.empty_like(Y), np.empty_like(Y), np.empty_like(Y), np.empty((4,) + Y.shape), work(1)
        values = np.zeros((4, 0, 3))
        variational_step(sys, values, np.zeros(0), A, b, float(MIDPOINT.den), Y, Y1, 2e-2, K, U, w)
        variational_step(sys, values, np.zeros(0), A, b, float(MIDPOINT.den), Y1, Y2, -2e-2, K, U, w)
        assert spread(Y1, Y) > 1e-4
        assert spread(Y2, Y) <= 1e-14, (name, spread(Y2, Y))
