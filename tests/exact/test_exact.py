"""The exact torque-free solution (rbcourse.exact) against tight numerical integrations.

References:
* scipy DOP853 at rtol = 1e-13, atol = 1e-15 on Euler's equations for the (normalised) body
  angular momentum in principal axes plus the attitude quaternion: ṁ = m × I⁻¹m,
  q̇ = ½ q ⊗ (0, ω_body).
* for benchmark A, a Taylor-series integrator in long double (x87 80-bit), which is
  accurate well beyond DOP853 on that ill-conditioned problem.
The exact solution must agree to 1e-9 rad (rotation error) wherever the reference
itself is that good; conservation, vectorisation, time reversal, the flow used by
splitting methods and the input checks are tested too.
"""
import math

import numpy as np
import pytest
from scipy import special
from scipy.integrate import solve_ivp

import rbcourse as rb
from rbcourse.exact import FreeRotationFlow, exact_free_body, free_rotation_flow
from rbcourse.exact.elliptic import jacobi_landen
from rbcourse.exact.free_body import Motion
from rbcourse.rotation import exp_so3, matrix_from_quat, quat_from_matrix, rotation_angle

BOX = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))          # benchmarks A and B: y is the intermediate axis


# --- references -------------------------------------------------------------------

def dop853(body, X0, ts, rtol=1e-13, atol=1e-15):
    """R at the times ts (all of one sign), integrating from X0 at t = 0 with DOP853
    (the state is normalised, |m| = |q| = 1, so atol = 1e-15 is an absolute 1e-15)."""
    ts = np.asarray(ts, dtype=float)
    A, I = body.principal_axes, body.principal_moments
    Q0 = X0.R @ A
    m0 = Q0.T @ X0.L
    Ln = float(np.linalg.norm(m0))
    i1, i2, i3 = (Ln / v for v in I)

    def f(t, y):
        m1, m2, m3, s, x, yy, z = y
        w1, w2, w3 = m1 * i1, m2 * i2, m3 * i3              # ω body (m normalised)
        return [m2 * w3 - m3 * w2, m3 * w1 - m1 * w3, m1 * w2 - m2 * w1,
                0.5 * (-x * w1 - yy * w2 - z * w3), 0.5 * (s * w1 + yy * w3 - z * w2),
                0.5 * (s * w2 + z * w1 - x * w3), 0.5 * (s * w3 + x * w2 - yy * w1)]

    y0 = np.concatenate([m0 / Ln, quat_from_matrix(Q0)])
    end = ts[np.argmax(np.abs(ts))]
    sol = solve_ivp(f, (0.0, end), y0, method="DOP853", rtol=rtol, atol=atol, t_eval=ts)
    assert sol.success
    return matrix_from_quat(sol.y[3:].T) @ A.T


def taylor_longdouble(body, X0, ts, h=0.05, order=22):
    """Same equations, Taylor series of the given order with fixed steps, in long double."""
    ld = np.longdouble
    A = body.principal_axes
    I = body.principal_moments.astype(ld)
    Q0 = X0.R @ A
    y = np.concatenate([(Q0.T @ X0.L), quat_from_matrix(Q0)]).astype(ld)

    def qmul(a, b):
        s1, v1, s2, v2 = a[:, :1], a[:, 1:], b[:, :1], b[:, 1:]
        return np.concatenate([s1 * s2 - np.sum(v1 * v2, 1, keepdims=True), s1 * v2 + s2 * v1 + np.cross(v1, v2)], 1)

    def step(y, dt):
        Y = np.zeros((order + 1, 7), dtype=ld)
        W = np.zeros((order + 1, 4), dtype=ld)
        Y[0] = y
        for k in range(order):                   # y' = Q(y, y): y_{k+1} = Σ Q(y_i, y_{k-i}) / (k+1)
            W[k, 1:] = Y[k, :3] / I
            a, w = Y[:k + 1], W[k::-1]
            Y[k + 1, :3] = np.cross(a[:, :3], w[:, 1:]).sum(0) / (k + 1)
            Y[k + 1, 3:] = 0.5 * qmul(a[:, 3:], w).sum(0) / (k + 1)
        return (Y * (dt ** np.arange(order + 1, dtype=ld))[:, None]).sum(0)

    out, t = [], ld(0)
    for target in np.sort(ts):
        while t < ld(target):
            dt = min(ld(h), ld(target) - t)
            y, t = step(y, dt), t + dt
        out.append(np.array(y[3:], dtype=float))
    return matrix_from_quat(np.array(out)) @ A.T


# --- helpers ------------------------------------------------------------------------

def state(body, omega_body, R=None, x=(0.0, 0.0, 0.0), v=(0.0, 0.0, 0.0)):
    """ω0 in body coordinates (as in benchmarks.md): L = R I_body ω_body."""
    R = np.eye(3) if R is None else R
    return rb.State(x, R, body.mass * np.asarray(v, float), R @ body.I_body @ np.asarray(omega_body, float))


def random_inertia(rng, kind):
    """Principal moments obeying the triangle inequality; diagonal, permuted or rotated."""
    while True:
        I = rng.uniform(0.2, 2.0, 3)
        if np.all(I <= I.sum() - I):
            break
    if kind == 0:
        return np.diag(I)
    if kind == 1:
        return np.diag(rng.permutation(I))
    Q = matrix_from_quat(rng.normal(size=4))
    return Q @ np.diag(I) @ Q.T


def random_rotation(rng):
    return matrix_from_quat(rng.normal(size=4))


def max_angle(R1, R2):
    return float(np.max(rotation_angle(R1, R2)))


# --- agreement with a tight integration ----------------------------------------------

@pytest.mark.parametrize("seed", range(40))
def test_random_bodies_match_dop853(seed):
    rng = np.random.default_rng(seed)
    body = rb.RigidBody(rng.uniform(0.5, 3.0), random_inertia(rng, seed % 3))
    X0 = rb.State(rng.normal(size=3), random_rotation(rng), rng.normal(size=3), rng.normal(size=3) * 2.0)
    ts = np.concatenate([[0.0], np.sort(rng.uniform(0.0, 20.0, 6)), [20.0]])
    traj = exact_free_body(body, X0, ts)
    assert max_angle(dop853(body, X0, ts), traj.R) < 1e-9


def test_benchmark_A_tennis_racket_matches_dop853():
    X0 = state(BOX, (0.01, 5.0, 0.01))
    ts = np.linspace(0.0, 20.0, 41)
    traj = exact_free_body(BOX, X0, ts)
    assert max_angle(dop853(BOX, X0, ts), traj.R) < 1e-9
    # the body really flips: the y-component of the body angular momentum changes sign
    mb = traj.body_angular_momentum()[:, 1]
    assert mb.min() < -0.99 * np.abs(mb).max() and mb.max() > 0.99 * np.abs(mb).max()


@pytest.mark.skipif(np.finfo(np.longdouble).eps > 1e-18, reason="needs x87 80-bit long double")
def test_benchmark_A_matches_long_double_taylor():
    """A is ill-conditioned (an energy error ε moves R(20) by ~2.6e4 ε): the exact solution
    must match a reference computed with 3 more digits to near double precision."""
    X0 = state(BOX, (0.01, 5.0, 0.01))
    ts = np.linspace(0.0, 20.0, 11)
    assert max_angle(taylor_longdouble(BOX, X0, ts), exact_free_body(BOX, X0, ts).R) < 1e-11


def test_benchmark_B_fast_major_axis_spin_matches_dop853():
    X0 = state(BOX, (0.1, 0.1, 50.0))
    ts = np.linspace(0.0, 10.0, 21)
    assert max_angle(dop853(BOX, X0, ts), exact_free_body(BOX, X0, ts).R) < 1e-9


def test_negative_times_match_dop853_backwards():
    rng = np.random.default_rng(11)
    body = rb.RigidBody(1.0, random_inertia(rng, 2))
    X0 = rb.State(np.zeros(3), random_rotation(rng), np.zeros(3), rng.normal(size=3))
    ts = -np.linspace(0.0, 15.0, 16)
    assert max_angle(dop853(body, X0, ts), exact_free_body(body, X0, ts).R) < 1e-9


# --- symmetric, spherical, principal axes --------------------------------------------------

@pytest.mark.parametrize("inertia, omega", [
    ([1.0, 1.0, 1.6], (0.7, -0.3, 4.0)),                               # oblate, symmetry axis z
    ([0.5, 1.2, 1.2], (3.0, 1.0, -0.5)),                               # prolate, symmetry axis x
    ([0.25, 0.25, 0.5], np.array([0.3, -0.2, 20.0]) / [0.25, 0.25, 0.5]),   # hard case: fast thin disk
    ([2.90833e-3, 2.90833e-3, 8.0e-4], (0.3, 0.0, 200.0)),              # the heavy top's inertia (about the pivot)
])
def test_symmetric_bodies(inertia, omega):
    body = rb.RigidBody(1.0, inertia)
    R0 = rb.rotation.rotation_about([1.0, 0.2, 0.0], 0.5)
    X0 = state(body, omega, R0)
    T = 20.0 / max(1.0, np.linalg.norm(omega) / 10.0)
    ts = np.linspace(0.0, T, 21)
    traj = exact_free_body(body, X0, ts)
    assert max_angle(dop853(body, X0, ts), traj.R) < 1e-9
    # the closed form: R(t) = exp(t L*/I_eq) R0 exp(t (1/I_s − 1/I_eq) m_s e_s*)
    I = np.array(inertia)
    s = 0 if I[1] == I[2] else 2
    I_eq = I[(s + 1) % 3]
    m_s = (R0.T @ X0.L)[s]
    e_s = np.eye(3)[s]
    closed = exp_so3(ts[:, None] * X0.L / I_eq) @ R0 @ exp_so3(ts[:, None] * ((1 / I[s] - 1 / I_eq) * m_s) * e_s)
    assert max_angle(closed, traj.R) < 1e-12


def test_rotated_symmetric_inertia_matches_dop853():
    """A symmetric body given by a full matrix (its eigen-decomposition is only exact to rounding)."""
    Q = rb.rotation.rotation_about([0.3, -1.0, 0.4], 1.1)
    body = rb.RigidBody(2.0, Q @ np.diag([1.0, 1.0, 1.7]) @ Q.T)
    X0 = state(body, (1.0, -2.0, 0.5), rb.rotation.rotation_about([0, 0, 1], 0.3))
    ts = np.linspace(0.0, 20.0, 11)
    assert max_angle(dop853(body, X0, ts), exact_free_body(body, X0, ts).R) < 1e-9


def test_spherical_body_is_a_steady_rotation():
    body = rb.RigidBody.sphere(3.0, 0.2)
    R0 = rb.rotation.rotation_about([1.0, 2.0, 3.0], 2.0)
    X0 = state(body, (1.0, -4.0, 2.5), R0)
    ts = np.linspace(-30.0, 30.0, 61)
    omega = X0.L / body.I_body[0, 0]
    assert max_angle(exp_so3(ts[:, None] * omega) @ R0, exact_free_body(body, X0, ts).R) < 1e-12


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_spin_exactly_along_a_principal_axis(axis):
    """The formulas divide by zero there; the exact motion is a steady spin, even about the
    (unstable) intermediate axis y of the box, for ever.  (R0 is a quarter turn, so that
    R0ᵀL is exactly on the axis: rounding off the axis would be a genuine, tiny, tilt.)"""
    R0 = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
    omega_body = 5.0 * np.eye(3)[axis]
    X0 = state(BOX, omega_body, R0)
    ts = np.array([-1e3, -1.0, 0.0, 0.5, 3.0, 1e3, 1e5])
    traj = exact_free_body(BOX, X0, ts)
    expected = exp_so3(ts[:, None] * (R0 @ omega_body)) @ R0
    err = rotation_angle(expected, traj.R) / np.maximum(1.0, 5.0 * np.abs(ts))   # relative to the angle turned
    assert err.max() < 1e-14
    mb = traj.body_angular_momentum()
    off = np.delete(mb, axis, axis=1)
    assert np.abs(off).max() <= 1e-14 * np.linalg.norm(X0.L)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_spin_along_a_principal_axis_of_a_full_inertia_matrix(axis):
    """A non-diagonal I_body spun about one of its principal axes (exact to rounding only):
    a steady spin, for ever about the stable axes, for a while about the intermediate one."""
    Q = rb.rotation.rotation_about([1.0, -0.5, 0.25], 0.8)
    body = rb.RigidBody(1.0, Q @ BOX.I_body @ Q.T)
    e = body.principal_axes[:, axis]
    R0 = rb.rotation.rotation_about([0.2, 0.3, 1.0], 1.3)
    X0 = state(body, 5.0 * e, R0)
    ts = np.array([-1.0, 0.0, 0.5, 1.0] + ([1e3, 1e5] if axis != 1 else []))
    expected = exp_so3(ts[:, None] * (R0 @ (5.0 * e))) @ R0
    err = rotation_angle(expected, exact_free_body(body, X0, ts).R) / np.maximum(1.0, 5.0 * np.abs(ts))
    assert err.max() < 1e-13


def test_nearly_symmetric_bodies_match_dop853():
    """Moments that differ by a few ulps up to 1e-9, momentum near the equator (n → −∞ in Π)."""
    for d in (1e-9, 1e-12, 4e-15):
        for inertia in ([1.0, 1.0 + d, 1.7], [1.0, 1.7 - d, 1.7]):
            body = rb.RigidBody(1.0, inertia)
            for omega in ((3.0, 3.0, 3e-7), (3e-7, 3.0, 3.0), (1.3, -2.0, 0.7)):
                X0 = state(body, omega)
                ts = np.linspace(0.0, 20.0, 6)
                ref = dop853(body, X0, ts)
                assert max_angle(ref, exact_free_body(body, X0, ts).R) < 1e-10
                flow = FreeRotationFlow(inertia)                                  # one body at a time
                assert max_angle(ref, np.array([flow(X0.R, X0.L, t) for t in ts])) < 1e-10


# --- the separatrix ---------------------------------------------------------------------

@pytest.mark.parametrize("omega", [(1e-6, 5.0, 1e-6), (3e-6, 5.0, 1e-6)])
def test_near_separatrix(omega):
    """Benchmark hard case: m' ~ 1e-14, where scipy's ellipj is wrong in the 9th digit.
    (3e-6, 5, 1e-6) is on the other side (the polhode encircles the minor axis).
    A double-precision integrator cannot follow the motion past the second flip (its
    rounding moves m' itself), so the comparison stops at T = 10 s, after the first."""
    X0 = state(BOX, omega)
    motion = Motion(BOX.principal_moments[None], (X0.R.T @ X0.L)[None])
    assert 0 < motion.ell.mc[0] < 1e-12
    ts = np.linspace(0.0, 10.0, 21)
    traj = exact_free_body(BOX, X0, ts)
    assert max_angle(dop853(BOX, X0, ts), traj.R) < 1e-9
    mb = traj.body_angular_momentum()[:, 1]
    assert mb[0] > 0 and mb[-1] < 0                                         # it flipped once
    # the flow, one body and one step at a time, agrees with the trajectory to rounding, flips included
    flow = FreeRotationFlow(BOX.I_body)
    ts = np.linspace(-20.0, 20.0, 41)
    traj = exact_free_body(BOX, X0, ts)
    assert max_angle(traj.R, np.array([flow(X0.R, X0.L, t) for t in ts])) < 1e-12


@pytest.mark.parametrize("inertia, m", [
    ([3.0, 4.0, 6.0], (1.0, -2.0, 1.0)),      # G = 2 E I2 exactly in floating point, |n| = 1
    ([1.5, 3.0, 4.0], (1.0, 0.7, 2.0)),       # same, |n| = 4 (the transformed Π)
    ([1.5, 3.0, 4.0], (-1.0, 0.0, -2.0)),
])
def test_exactly_on_the_separatrix(inertia, m):
    body = rb.RigidBody(1.0, inertia)
    L = 3.0 * np.array(m)
    R0 = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])   # R0ᵀ (R0 L) == L exactly
    X0 = rb.State(np.zeros(3), R0, np.zeros(3), R0 @ L)
    motion = Motion(body.principal_moments[None], L[None])
    assert motion.ell.mc[0] == 0.0                                           # the separatrix branch
    lam = abs(motion.ell.lam[0])
    ts = np.linspace(0.0, 6.0 / lam, 13)                                     # before DOP853 drifts off (e^6)
    traj = exact_free_body(body, X0, ts)
    assert max_angle(dop853(body, X0, ts), traj.R) < 1e-9
    assert max_angle(dop853(body, X0, -ts), exact_free_body(body, X0, -ts).R) < 1e-9
    flow = FreeRotationFlow(inertia)
    assert max_angle(traj.R, np.array([flow(X0.R, X0.L, t) for t in ts])) < 1e-13
    # continuity: starts 1e-12 off the separatrix, on both sides, give nearly the same motion
    for d in (1e-12, -1e-12):
        X1 = rb.State(np.zeros(3), R0, np.zeros(3), R0 @ (L + [d, 0.0, 0.0]))
        assert 0 < Motion(body.principal_moments[None], (L + [d, 0.0, 0.0])[None]).ell.mc[0] < 1e-11
        assert max_angle(exact_free_body(body, X1, ts).R, traj.R) < 1e-9
    # for ever after (and before), the body angular momentum creeps towards ±e2
    far = exact_free_body(body, X0, [-1e4, -60.0 / lam, 60.0 / lam, 1e4])
    mb = far.body_angular_momentum() / np.linalg.norm(L)
    assert np.all(np.isfinite(far.R))
    assert np.all(np.abs(np.abs(mb[:, 1]) - 1.0) < 1e-12)
    assert mb[0, 1] * mb[-1, 1] < 0                                          # from one end to the other
    assert max_angle(far.R, np.array([flow(X0.R, X0.L, t) for t in far.t])) < 1e-11


# --- invariants, vectorisation, time --------------------------------------------------

@pytest.mark.parametrize("omega", [(0.01, 5.0, 0.01), (1e-6, 5.0, 1e-6), (0.1, 0.1, 50.0), (1.0, 2.0, 3.0)])
def test_energy_and_momentum_conserved(omega):
    X0 = state(BOX, omega, rb.rotation.rotation_about([1.0, 0.0, 1.0], 0.7), v=(1.0, 2.0, 3.0))
    ts = np.concatenate([np.linspace(-1e3, 1e3, 2001), [1e5]])
    traj = exact_free_body(BOX, X0, ts)
    E = traj.kinetic_energy()
    E0 = 0.5 * X0.P @ X0.P / BOX.mass + 0.5 * X0.L @ (X0.R @ BOX.I_body_inv @ X0.R.T @ X0.L)
    assert np.abs(E / E0 - 1.0).max() < 1e-13
    Lb = np.linalg.norm(traj.body_angular_momentum(), axis=1)
    assert np.abs(Lb / np.linalg.norm(X0.L) - 1.0).max() < 1e-13
    assert traj.orthogonality_error().max() < 1e-13
    assert np.all(traj.L == X0.L) and np.all(traj.P == X0.P)


def test_array_of_times_equals_scalar_calls():
    rng = np.random.default_rng(3)
    for kind, omega in ((0, (0.01, 5.0, 0.01)), (1, (1e-6, 5.0, 1e-6)), (2, (0.3, -1.0, 2.0))):
        body = BOX if kind < 2 else rb.RigidBody(1.0, random_inertia(rng, 2))
        X0 = state(body, omega, random_rotation(rng), v=(0.1, 0.2, 0.3))
        ts = np.array([7.3, -2.0, 0.0, 1e3, 0.5, -40.0, 19.99])
        traj = exact_free_body(body, X0, ts)
        for i, t in enumerate(ts):
            one = exact_free_body(body, X0, t)
            assert len(one) == 1 and one.t[0] == t
            assert np.abs(one.R[0] - traj.R[i]).max() < 1e-14
            assert np.abs(one.x[0] - traj.x[i]).max() < 1e-14


def test_t_zero_returns_X0():
    rng = np.random.default_rng(4)
    cases = [(BOX, (0.01, 5.0, 0.01)), (BOX, (0.0, 5.0, 0.0)), (rb.RigidBody.cylinder(1.0, 0.1, 0.3), (1, 2, 3)),
             (rb.RigidBody(1.0, random_inertia(rng, 2)), (1.0, -1.0, 0.5)), (BOX, (0.0, 0.0, 0.0))]
    for body, omega in cases:
        X0 = state(body, omega, random_rotation(rng), x=(1.0, 2.0, 3.0), v=(0.5, 0.0, -1.0))
        assert exact_free_body(body, X0, 0.0).state(0) == X0
        traj = exact_free_body(body, X0, [0.0, 1.0, -0.0])
        assert traj.state(0) == X0 and traj.state(2) == X0


def test_body_at_rest_stays_and_translation_is_uniform():
    R0 = rb.rotation.rotation_about([1.0, 2.0, 0.5], 0.9)
    X0 = rb.State([1.0, 2.0, 3.0], R0, [0.2, -0.4, 0.0], np.zeros(3))
    traj = exact_free_body(BOX, X0, [-5.0, 0.0, 2.0, 1e6])
    assert np.all(traj.R == R0)
    np.testing.assert_allclose(traj.x[-1], X0.x + 1e6 * X0.P / BOX.mass, rtol=1e-15)


def test_forward_after_backward_returns_X0():
    rng = np.random.default_rng(6)
    for _ in range(5):
        body = rb.RigidBody(1.0, random_inertia(rng, 2))
        X0 = rb.State(np.zeros(3), random_rotation(rng), np.zeros(3), 2.0 * rng.normal(size=3))
        X1 = exact_free_body(body, X0, -7.5).state(0)
        X1 = rb.State(X1.x, X1.R, X1.P, X1.L)
        assert max_angle(X0.R, exact_free_body(body, X1, 7.5).R[0]) < 1e-12


def test_trajectory_contents():
    X0 = state(BOX, (0.3, 0.1, 2.0), x=(1.0, -1.0, 0.5), v=(2.0, 0.0, -1.0))
    ts = np.array([0.0, 0.5, 1.0, -2.0])
    traj = exact_free_body(BOX, X0, ts)
    assert traj.method == "exact" and traj.scene.bodies == (BOX,) and not traj.scene.effects
    assert traj.t.shape == (4,) and traj.x.shape == (4, 3) and traj.R.shape == (4, 3, 3)
    assert traj.P.shape == (4, 3) and traj.L.shape == (4, 3)
    np.testing.assert_allclose(traj.x, X0.x + np.outer(ts, X0.P / BOX.mass), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(traj.t, ts)
    assert rb.rotation.is_rotation(traj.R, 1e-13)


# --- the flow for splitting methods -------------------------------------------------

def _flow_cases(rng, n):
    for k in range(n):
        inertia = random_inertia(rng, k % 3)
        if k % 5 == 3:                                          # symmetric
            I = np.sort(np.linalg.eigvalsh(inertia))
            inertia = np.diag([I[0], I[0], min(I[2], 1.9 * I[0])])
        R0 = random_rotation(rng)
        L = rng.normal(size=3)
        if k % 7 == 5:                                          # a principal-axis spin
            w, V = np.linalg.eigh(inertia)
            L = R0 @ V[:, k % 3] * 2.0
        yield inertia, R0, L


def test_flow_matches_exact_free_body():
    rng = np.random.default_rng(8)
    for inertia, R0, L in _flow_cases(rng, 60):
        body = rb.RigidBody(1.0, inertia)
        h = rng.uniform(-5.0, 5.0)
        expected = exact_free_body(body, rb.State(np.zeros(3), R0, np.zeros(3), L), h).R[0]
        flow = FreeRotationFlow(inertia)
        assert max_angle(expected, flow(R0, L, h)) < 1e-13                       # one body
        assert max_angle(expected, FreeRotationFlow(inertia[None])(R0[None], L[None], h)[0]) < 1e-13
        two = FreeRotationFlow(np.stack([inertia, inertia]))(np.stack([R0, R0]), np.stack([L, L]), h)   # arrays
        assert max_angle(expected, two[1]) < 1e-13
        assert max_angle(expected, free_rotation_flow(inertia, R0, L, h)) < 1e-13
        assert max_angle(expected, FreeRotationFlow(body)(R0, L, h)) < 1e-13


def test_flow_composes():
    rng = np.random.default_rng(9)
    for inertia, R0, L in _flow_cases(rng, 30):
        flow = FreeRotationFlow(inertia)
        h1, h2 = rng.uniform(-3.0, 3.0, 2)
        assert max_angle(flow(flow(R0, L, h1), L, h2), flow(R0, L, h1 + h2)) < 1e-12
    # as in a splitting method: 1000 steps of 0.02 s = one step of 20 s (benchmark A)
    L = BOX.I_body @ [0.01, 5.0, 0.01]
    flow = FreeRotationFlow(BOX.I_body)
    R = np.eye(3)
    for _ in range(1000):
        R = flow(R, L, 0.02)
    assert max_angle(R, flow(np.eye(3), L, 20.0)) < 1e-9


def test_flow_on_many_bodies_at_once():
    rng = np.random.default_rng(10)
    cases = list(_flow_cases(rng, 40))
    inertia = np.array([c[0] for c in cases])
    R = np.array([c[1] for c in cases])
    L = np.array([c[2] for c in cases])
    L[3] = 0.0                                                                  # a body at rest
    out = free_rotation_flow(inertia, R, L, 0.7)
    assert out.shape == (40, 3, 3)
    for i in range(40):
        assert max_angle(FreeRotationFlow(inertia[i])(R[i], L[i], 0.7), out[i]) < 1e-14
    np.testing.assert_array_equal(out[3], R[3])
    # one inertia shared by N bodies
    shared = FreeRotationFlow(BOX.I_body)(R, 0.01 * L, -1.3)
    for i in range(40):
        assert max_angle(FreeRotationFlow(BOX.I_body)(R[i], 0.01 * L[i], -1.3), shared[i]) < 1e-14


def test_flow_symmetric_is_two_rotations():
    """For I1 = I2 (the heavy top about its pivot):
    R(h) = exp(h |L|/I1 L̂*) R exp(h (1/I3 − 1/I1) (RᵀL)₃ e3*)."""
    I1, I3 = 2.90833e-3, 8.0e-4
    flow = FreeRotationFlow([I1, I1, I3])
    R = rb.rotation.rotation_about([1.0, 0.0, 0.0], math.radians(30))
    L = R @ np.diag([I1, I1, I3]) @ [0.4, -0.3, 200.0]
    for h in (1e-3, 1e-2, -0.3, 5.0):
        expected = exp_so3(h * L / I1) @ R @ exp_so3(h * (1 / I3 - 1 / I1) * (R.T @ L)[2] * np.eye(3)[2])
        out = flow(R, L, h)
        assert isinstance(out, np.ndarray) and out.shape == (3, 3)
        turned = abs(h) * (np.linalg.norm(L) / I1 + abs((1 / I3 - 1 / I1) * (R.T @ L)[2]))   # rad, ~1e3 at h = 5
        assert max_angle(expected, out) < 1e-13 + 5e-16 * turned       # rounding: ~1e-16 per radian turned
    out = flow(R, L, 0.0)
    assert out is not R and np.array_equal(out, R)


# --- the near-separatrix elliptic functions -----------------------------------------------

def test_landen_jacobi_functions():
    # where scipy's ellipj is still accurate, both agree
    for mc in (9e-3, 1e-3, 1e-4):
        K = special.ellipkm1(mc)
        u = np.linspace(-K, K, 101)[:, None]
        ours = jacobi_landen(u, np.array([mc]))
        ref = special.ellipj(u, 1.0 - mc)[:3]
        for a, b in zip(ours, ref):
            assert np.abs(a - b).max() < 1e-13
    # closer to 1: identities, and the values at the quarter period sn(K) = 1, cn(K) = 0, dn(K) = √m'
    for mc in (1e-8, 1e-14, 1e-20, 1e-100, 1e-250):
        K = special.elliprf(0.0, mc, 1.0)
        u = np.concatenate([np.linspace(-K, K, 201), [K]])[:, None]
        sn, cn, dn = jacobi_landen(u, np.array([mc]))
        assert np.abs(sn ** 2 + cn ** 2 - 1).max() < 1e-15
        assert np.abs(dn ** 2 + (1 - mc) * sn ** 2 - 1).max() < 1e-15
        assert abs(sn[-1, 0] - 1) < 1e-15 and abs(cn[-1, 0]) < 1e-15
        assert abs(dn[-1, 0] / math.sqrt(mc) - 1) < 1e-12
        # far from K, m' is negligible: sn = tanh, dn = cn = sech
        small = np.abs(u[:, 0]) < 0.25 * K
        np.testing.assert_allclose(sn[small, 0], np.tanh(u[small, 0]), rtol=0, atol=1e-15 + 10 * mc * K)


# --- input checks -----------------------------------------------------------------------

_X = state(BOX, (0.0, 1.0, 0.0))


@pytest.mark.parametrize("args, match", [
    (("box", _X, 1.0), "body must be a RigidBody"),
    ((BOX, "not a state", 1.0), "X0 must be a State"),
    ((BOX, rb.State.stack([_X, _X]), 1.0), "X0 must be a single-body State"),
    ((BOX, _X, "soon"), "t must be"),
    ((BOX, _X, [[1.0, 2.0]]), "t must be a real number or a 1-D array"),
    ((BOX, _X, [1.0, np.nan]), "t must contain only finite"),
    ((BOX, _X, np.inf), "t must contain only finite"),
    ((BOX, _X, []), "t must hold at least one time"),
    ((BOX, _X, True), "t must be"),
    ((BOX, _X, 1j), "t must be"),
    ((BOX, rb.State.unchecked(_X.x, 1.1 * np.eye(3), _X.P, _X.L), 1.0), "X0.R must be a rotation"),
    ((BOX, rb.State.unchecked(_X.x, _X.R, _X.P, np.array([np.nan, 0.0, 0.0])), 1.0), "X0.L must be a finite"),
])
def test_exact_free_body_rejects_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        exact_free_body(*args)


@pytest.mark.parametrize("inertia, R, L, h, match", [
    ([1.0, 2.0], np.eye(3), np.ones(3), 0.1, "inertia must have shape"),
    ([[1.0, 2.0, 3.0]] * 2, np.eye(3), np.ones(3), 0.1, "inertia must have shape"),
    ([1.0, -2.0, 3.0], np.eye(3), np.ones(3), 0.1, "inertia must be positive definite"),
    ("heavy", np.eye(3), np.ones(3), 0.1, "inertia must"),
    ([1.0, 2.0, 3.0], np.eye(2), np.ones(3), 0.1, "R must have shape"),
    ([1.0, 2.0, 3.0], np.eye(3), np.ones(4), 0.1, "R must have shape"),
    ([1.0, 2.0, 3.0], np.stack([np.eye(3)] * 2), np.ones((3, 3)), 0.1, "R must have shape"),
    ([1.0, 2.0, 3.0], np.eye(3), np.ones(3), np.nan, "h must be finite"),
    ([1.0, 2.0, 3.0], np.eye(3), np.ones(3), "0.1", "h must be a real number"),
    ([1.0, 2.0, 3.0], np.eye(3), np.ones(3), True, "h must be a real number"),
    ([1.0, 2.0, 3.0], np.eye(3), [np.nan, 0.0, 0.0], 0.1, "L must contain only finite"),
    (np.stack([np.eye(3)] * 2), np.stack([np.eye(3)] * 3), np.ones((3, 3)), 0.1, "holds 2 bodies"),
    (np.stack([np.eye(3)] * 2), np.eye(3), np.ones(3), 0.1, "holds 2 bodies"),
])
def test_flow_rejects_bad_input(inertia, R, L, h, match):
    with pytest.raises(ValueError, match=match):
        free_rotation_flow(inertia, R, L, h)
