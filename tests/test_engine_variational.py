"""The Lie group variational integrator with the Cayley map (rbcourse/engine/variational.py; Bou-Rabee & Marsden
2009, Kobilarov, Crane & Desbrun 2009): compiled against the same run as Python (fast=False), its rotor equation,
its order against the exact torque-free motion, its invariants (R on SO(3), a free body's world L and |L|, the
energy of a free symmetric body, L_z and the spin L₃ about a top's pivot), the bounded energy of free and top runs,
a step at any h|ω| (the top at ω·Δt = 2 keeps its tilt), and bad inputs."""
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


def cayley_parameter(F):
    """a with F = cay(a):  a = 2 (F − Fᵀ)^∨ / (1 + tr F)."""
    S = F - F.T
    return 2.0 * np.array([S[2, 1], S[0, 2], S[1, 0]]) / (1.0 + np.trace(F))


def test_rotor_solves_the_discrete_equation():
    """h Π = J a + ½ a × J a + ¼ (a·J a) a with F = cay(a) a rotation (a full, non-diagonal J, a slow and a fast
    step), and the world momentum it leaves: F (J a − ½ a × J a + ¼ (a·J a) a) = h Π."""
    J = np.array([[0.02, 0.001, 0.0], [0.001, 0.03, 0.002], [0.0, 0.002, 0.04]])
    for Pi, h in [(np.array([0.01, 0.3, -0.05]), 0.05), (np.array([0.5, -2.0, 4.0]), 0.1)]:
        F, ok = discrete_rotor(tuple(map(tuple, J)), tuple(map(tuple, np.linalg.inv(J))), tuple(Pi), h)
        F = np.array(F)
        a = cayley_parameter(F)
        Ja = J @ a
        assert ok and np.linalg.norm(a) > 0.1
        np.testing.assert_allclose(Ja + 0.5 * np.cross(a, Ja) + 0.25 * (a @ Ja) * a, h * Pi, rtol=0, atol=1e-15)
        np.testing.assert_allclose(F @ (Ja - 0.5 * np.cross(a, Ja) + 0.25 * (a @ Ja) * a), h * Pi, rtol=0,
                                   atol=1e-15)
        np.testing.assert_allclose(F.T @ F, np.eye(3), atol=1e-15)


@pytest.mark.parametrize("h_omega", [0.5, 2.0, 10.0, 1e3])
def test_a_step_at_any_spin_about_a_principal_axis(h_omega):
    """About a principal axis the rotor turns by θ = 2 atan(u/2), u + u³/4 = h|ω| — a solution for every
    step (the exponential's Moser–Veselov rotor has none past h|ω| = 1): J₃ = 0.04, h = 0.01."""
    J = np.diag([0.02, 0.03, 0.04])
    h = 1e-2
    Pi = np.array([0.0, 0.0, 0.04 * h_omega / h])
    F, ok = discrete_rotor(tuple(map(tuple, J)), tuple(map(tuple, np.linalg.inv(J))), tuple(Pi), h)
    u = np.roots([0.25, 0.0, 1.0, -h_omega])
    u = u[np.abs(u.imag) < 1e-9].real[0]
    assert ok
    np.testing.assert_allclose(np.array(F), rb.rotation.rotation_about([0, 0, 1], 2 * np.arctan(u / 2)),
                               rtol=0, atol=1e-14)


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
    """A (200 s, dt = 1e-2, 2·10⁴ steps): RᵀR − I, world L and |L| to rounding while the body flips; the energy of
    three different moments is not kept (¼ (a·J a) a·J⁻¹(a × J a) per step) but stays bounded: the last fifth's
    largest error within 1.5× of the first fifth's, below 5e-4 (measured 2.1e-4)."""
    p = problem_A()
    traj = rb.simulate(p.scene, p.X0, 200.0, 1e-2, M)
    R, L, E = traj.R, traj.angular_momentum(), traj.kinetic_energy()
    assert np.abs(np.einsum("kji,kjl->kil", R, R) - np.eye(3)).max() <= 1e-14
    assert np.abs(L - L[0]).max() <= 1e-14 * np.linalg.norm(L[0])
    assert np.ptp(np.linalg.norm(L, axis=1)) <= 1e-14 * np.linalg.norm(L[0])
    assert np.abs(R[:, 1, 1]).min() < 0.5                  # the racket does flip: not kept by standing still
    dE = np.abs(E - E[0]) / E[0]
    n = len(dE) // 5
    assert 1e-8 < dE.max() <= 5e-4, dE.max()
    assert dE[-n:].max() <= 1.5 * dE[:n].max(), (dE[:n].max(), dE[-n:].max())


def test_free_symmetric_body_keeps_its_energy():
    """J₁ = J₂: a·J⁻¹(a × J a) = 0, so the rotor keeps ½ Π·J⁻¹Π to rounding (a tilted spin, 10⁴ steps)."""
    body = rb.RigidBody.box(1.0, (0.2, 0.2, 0.6))
    X0 = rb.State.from_velocities(body, [0, 0, 0], np.eye(3), [0, 0, 0], [3.0, 1.0, 40.0])
    traj = rb.simulate(body, X0, 100.0, 1e-2, M)
    E = traj.kinetic_energy()
    assert np.ptp(E) <= 1e-13 * E[0], np.ptp(E) / E[0]
    assert np.ptp(np.linalg.norm(traj.L, axis=1)) <= 1e-13 * np.linalg.norm(traj.L[0])


@pytest.mark.parametrize("dt, top", [(2e-3, 34.0), (4e-3, 34.4), (1e-2, 36.5)])
def test_heavy_top_keeps_Lz_and_its_tilt(dt, top):
    """C (5 s, spin 200 rad/s; dt = 1e-2 is ω·Δt = 2): L_z about the pivot to rounding (gravity's torque about it
    is horizontal, and only the kicks change L) and the spin L₃ (that torque has no part along the axis, and
    the rotor keeps e₃·Π of a symmetric body); the top does not fall: its tilt stays within the true
    30°–33.7°, widened by the step (measured 33.89°, 34.29°, 35.94°; implicit_midpoint 39.8° at ω·Δt = 2)."""
    traj, dLz, tilt = top_run(M, dt)
    L3 = np.einsum("kji,kj->ki", traj.R, traj.L)[:, 2]               # (Rᵀ L)₃ = I₃ ω₃
    assert dLz <= 1e-12, dLz
    assert np.ptp(L3) <= 1e-12 * abs(L3[0]), np.ptp(L3) / abs(L3[0])
    assert 29.99 <= tilt.min() and tilt.max() <= top, (tilt.min(), tilt.max())
    assert np.ptp(tilt) > 1.0


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
    assert m.order == 2 and m.keeps == {"SO(3)", "L", "|L|"}
    assert "Bou-Rabee" in m.reference and "Cayley" in m.reference


def test_symmetric():
    """A step of −h from the result of a step of h gives the start back, to rounding (free, gravity, heavy top)."""
    from rbcourse.driver import encode
    from rbcourse.engine.motion import work
    from rbcourse.engine.variational import variational_step
    from rbcourse.engine.tableaus import MIDPOINT
    A, b = np.ascontiguousarray(MIDPOINT.A), np.ascontiguousarray(MIDPOINT.b)
    for name in ["free", "gravity", "heavy_top", "free_fast_spin_full_inertia"]:
        scene, X0 = CASES[name]()
        sys = scene.compile().system
        Y = encode("matrix", scene.to_engine(X0))
        Y1, Y2, U, K, w = np.empty_like(Y), np.empty_like(Y), np.empty_like(Y), np.empty((4,) + Y.shape), work(1)
        values = np.zeros((4, 0, 3))
        variational_step(sys, values, np.zeros(0), A, b, float(MIDPOINT.den), Y, Y1, 2e-2, K, U, w)
        variational_step(sys, values, np.zeros(0), A, b, float(MIDPOINT.den), Y1, Y2, -2e-2, K, U, w)
        assert spread(Y1, Y) > 1e-4
        assert spread(Y2, Y) <= 1e-14, (name, spread(Y2, Y))
