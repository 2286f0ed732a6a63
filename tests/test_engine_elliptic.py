"""The engine's elliptic functions (rbcourse/engine/elliptic.py) against scipy.special (ellipj, elliprf,
elliprc, elliprj), an independent quadrature where scipy itself loses digits (R_J with p ≪ x, y, z), and
exact identities; compiled, and run as Python (rbcourse.engine.interpreted: the same file)."""
import math

import numpy as np
import pytest
from scipy import integrate, special

from rbcourse.engine import elliptic as compiled
from rbcourse.engine import interpreted
from rbcourse.exact.elliptic import jacobi_landen

REL = 1e-13
rng = np.random.default_rng(20240611)


def rel(a, b):
    return abs(a - b) / abs(b) if b != 0 else abs(a)


@pytest.fixture(params=["compiled", "python"], scope="module")
def E(request):
    return compiled if request.param == "compiled" else interpreted.module("elliptic")


def count(E, n):
    return n if E is compiled else n // 10       # the interpreted run is ~1000x slower


def test_carlson_rf_rc_against_scipy(E):
    n = count(E, 4000)
    x, y, z = 10.0 ** rng.uniform(-12, 12, (3, n))
    x[::5] = 0.0
    assert max(rel(E.elliprf(a, b, c), special.elliprf(a, b, c)) for a, b, c in zip(x, y, z)) <= REL
    ys = y * np.where(rng.random(n) < 0.3, -1.0, 1.0)           # y < 0: the Cauchy principal value
    assert max(rel(E.elliprc(a, b), special.elliprc(a, b)) for a, b in zip(x, ys)) <= REL


def test_carlson_rj_against_scipy(E):
    n = count(E, 4000)
    x, y, z, p = 10.0 ** rng.uniform(-4, 4, (4, n))
    x[::5] = 0.0
    assert max(rel(E.elliprj(a, b, c, d), special.elliprj(a, b, c, d)) for a, b, c, d in zip(x, y, z, p)) <= REL
    # the flow's arguments: R_J(cn², dn², 1, 1 − n sn²), R_J(0, m', 1, 1 − n), n < 0
    s, mc = rng.uniform(-1, 1, n), 10.0 ** rng.uniform(-16, 0, n)
    nn = -(10.0 ** rng.uniform(-6, 6, n))
    c2, d2 = 1 - s * s, 1 - (1 - mc) * s * s
    assert max(rel(E.elliprj(a, b, 1.0, 1 - k * t * t), special.elliprj(a, b, 1.0, 1 - k * t * t))
               for a, b, k, t in zip(c2, d2, nn, s) if t != 0) <= REL
    assert max(rel(E.elliprj(0.0, m, 1.0, 1 - k), special.elliprj(0.0, m, 1.0, 1 - k)) for m, k in zip(mc, nn)) <= REL


def test_carlson_rj_principal_value_against_scipy(E):
    n = count(E, 2000)
    x, y, z, p = 10.0 ** rng.uniform(-3, 3, (4, n))
    # the principal value changes sign: its error is measured against the scale R_J(x, y, z, |p|); only
    # 1e-11 (no oracle here says which of the two loses the digits; the free flow never passes p < 0)
    assert max(abs(E.elliprj(a, b, c, -d) - special.elliprj(a, b, c, -d)) / special.elliprj(a, b, c, d)
               for a, b, c, d in zip(x, y, z, p)) <= 1e-11


def quad_rj(x, y, z, p):
    """R_J(x, y, z, p) = 3/2 ∫₀^∞ dt / ((t + p)√((t + x)(t + y)(t + z))), t = eˢ, split at the arguments."""
    f = lambda s: 1.5 * math.exp(s) / ((math.exp(s) + p) * math.sqrt((math.exp(s) + x) * (math.exp(s) + y) * (math.exp(s) + z)))
    cuts = sorted(math.log(v) for v in (x, y, z, p))
    return sum(integrate.quad(f, lo, hi, epsabs=0, epsrel=1.2e-14, limit=500)[0]
               for lo, hi in zip([-80.0] + cuts, cuts + [90.0]))


@pytest.mark.parametrize("args", [(2524177.207484377, 27196350.72918924, 7790.217741963157, 3.110502110733326e-07),
                                  (23461952.990780596, 71.63971454439852, 6894.368605421237, 1.0325675382749817e-08),
                                  (1e8, 3e6, 5e7, 1e-6)])
def test_carlson_rj_small_p_against_quadrature(E, args):
    """p ≪ x, y, z: scipy's elliprj is off by ~1e-12 there; ours agrees with the integral to rounding."""
    assert rel(E.elliprj(*args), quad_rj(*args)) <= 5e-14


def test_carlson_degenerate_cases(E):
    for x in (1e-300, 1e-8, 0.3, 7.0, 1e200):
        assert rel(E.elliprf(x, x, x), x ** -0.5) <= 1e-15
        assert rel(E.elliprc(x, x), x ** -0.5) <= 1e-15
    for x in (1e-8, 0.3, 7.0, 1e100):
        assert rel(E.elliprj(x, x, x, x), x ** -1.5) <= 1e-15
    assert rel(E.elliprf(0.0, 1.0, 1.0), math.pi / 2) <= 1e-15
    assert rel(E.elliprc(0.0, 1.0), math.pi / 2) <= 1e-15
    assert rel(E.elliprf(0.0, 1e-280, 1.0), special.elliprf(0.0, 1e-280, 1.0)) <= REL     # K near the separatrix
    assert rel(E.ellipk(0.3), special.ellipk(0.7)) <= REL


@pytest.mark.parametrize("call", ["elliprf(-1.0, 1.0, 1.0)", "elliprf(0.0, 0.0, 1.0)", "elliprf(math.nan, 1.0, 1.0)",
                                  "elliprf(math.inf, 1.0, 1.0)", "elliprc(1.0, 0.0)", "elliprc(-1.0, 1.0)",
                                  "elliprj(1.0, 1.0, 1.0, 0.0)", "elliprj(0.0, 0.0, 1.0, 1.0)",
                                  "jacobi(0.5, -0.1)", "jacobi(0.5, 1.5)", "jacobi(math.inf, 0.5)", "ellipj(0.5, 1.2)"])
def test_bad_arguments_raise(E, call):
    with pytest.raises(ValueError, match=call.split("(")[0]):
        eval(call, {"math": math}, {k: getattr(E, k) for k in ("elliprf", "elliprc", "elliprj", "jacobi", "ellipj")})


def test_jacobi_against_scipy(E):
    """m in [0, 0.99] (m' >= LANDEN_MC: where scipy's ellipj is accurate; closer to 1 its dn = √(1 − m sn²)
    cancels, ours is √(m' + m cn²)), |u| <= 30: |Δ| <= 1e-13 (values in [−1, 1]),
    and relative <= 1e-13 away from the zeros (|value| > 1e-3)."""
    n = count(E, 4000)
    m = np.concatenate([rng.uniform(0, 0.99, n // 2), 1 - 10.0 ** rng.uniform(-2, -0.01, n // 2)])
    m[:5] = 0.0
    u = rng.uniform(-30, 30, len(m))
    worst = 0.0
    for a, b in zip(u, m):
        ref = np.array(special.ellipj(a, b)[:3])
        ours = np.array(E.jacobi(a, 1.0 - b))
        assert np.array_equal(ours, E.ellipj(a, b))
        err = np.abs(ours - ref)
        assert np.all(err <= REL), (a, b, ours, ref)
        worst = max(worst, np.max(np.where(np.abs(ref) > 1e-3, err / np.abs(ref), 0.0)))
    assert worst <= REL


def test_jacobi_large_u(E):
    """|u| up to 1e4 (many periods): the argument itself carries |u| eps; |Δ| <= 1e-13 + 10 |u| eps."""
    for a, b in zip(rng.uniform(-1e4, 1e4, count(E, 500)), rng.uniform(0, 0.999, count(E, 500))):
        ref = np.array(special.ellipj(a, b)[:3])
        assert np.all(np.abs(np.array(E.jacobi(a, 1.0 - b)) - ref) <= REL + 10 * abs(a) * 2.2e-16), (a, b)


def test_jacobi_near_the_separatrix(E):
    """m' from 1e-2 down to 1e-16 and 0 (scipy's ellipj takes m and loses m' there): against the numpy
    Landen evaluation of rbcourse/exact/elliptic.py, the identities sn² + cn² = 1, dn² + m sn² = 1, and
    m' = 0: sn = tanh, cn = dn = sech; u over a few periods (reduced by 2K)."""
    n = count(E, 2000)
    mc = 10.0 ** rng.uniform(-16, -2, n)
    mc[:3] = 0.0
    for c in mc:
        K = special.elliprf(0.0, c, 1.0) if c > 0 else 20.0
        for a in rng.uniform(-K, K, 3):
            sn, cn, dn = E.jacobi(a, c)
            if c > 0:
                ref = np.array(jacobi_landen(np.array([[a]]), np.array([c])))[:, 0, 0]
                assert np.all(np.abs(np.array([sn, cn, dn]) - ref) <= REL * np.maximum(1.0, 0.0)), (a, c)
            else:
                assert (sn, cn, dn) == (pytest.approx(math.tanh(a), abs=4e-16), pytest.approx(1 / math.cosh(a), abs=4e-16),
                                        pytest.approx(1 / math.cosh(a), abs=4e-16))
            assert abs(sn * sn + cn * cn - 1) <= 4e-15 and abs(dn * dn + (1 - c) * sn * sn - 1) <= 1e-14
        if c > 0:                                   # beyond K: the half-period reduction
            a = 2.6 * K
            s2, c2, d2 = E.jacobi(a, c)
            s1, c1, d1 = E.jacobi(a - 2 * K, c)
            assert abs(s2 + s1) <= 1e-12 and abs(c2 + c1) <= 1e-12 and abs(d2 - d1) <= 1e-12


def test_jacobi_degenerate_parameters(E):
    for u in (-7.0, -0.3, 0.0, 1e-9, 2.5, 40.0):
        assert E.jacobi(u, 1.0) == pytest.approx((math.sin(u), math.cos(u), 1.0), abs=1e-15)
        sn, cn, dn = E.jacobi(u, 0.0)
        assert sn == pytest.approx(math.tanh(u), abs=4e-16) and cn == dn == pytest.approx(1 / math.cosh(u), abs=4e-16)
    assert E.sech(1000.0) == 0.0 and E.sech(-800.0) >= 0.0


def test_compiled_equals_python():
    """The same file run as Python gives the compiled numbers (to rounding: LLVM may fuse operations)."""
    py = interpreted.module("elliptic")
    for a, b, c, d in 10.0 ** rng.uniform(-6, 6, (200, 4)):
        for name, args in (("elliprf", (a, b, c)), ("elliprc", (a, b)), ("elliprj", (a, b, c, d)),
                           ("elliprj", (a, b, c, -d))):
            x, y = getattr(compiled, name)(*args), getattr(py, name)(*args)
            assert rel(x, y) <= 1e-14, (name, args)
    for u, mc in zip(rng.uniform(-40, 40, 300), 10.0 ** rng.uniform(-17, 0, 300)):
        assert np.abs(np.array(compiled.jacobi(u, mc)) - np.array(py.jacobi(u, mc))).max() <= 1e-14
