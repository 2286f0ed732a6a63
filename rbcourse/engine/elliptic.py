"""Carlson's symmetric elliptic integrals R_F, R_C, R_J and Jacobi's elliptic functions sn, cn, dn, on
plain floats (compiled: scalars and tuples only, no array), for the exact free flow of an asymmetric
body (exact_flow.free_rotation), the step of the method exact_splitting.

Written here, and not taken from scipy.special, on purpose: scipy cannot be called from compiled code,
and the step must be compiled and allocate nothing.  rbcourse/exact/elliptic.py is the other set, built on
scipy.special, for the independent reference rbcourse/exact/ (see exact_flow.py): the two share no code
and no constant, and tests/test_two_exact_flows.py compares the motions they give.

Carlson's integrals (B. C. Carlson, "Numerical computation of real or complex elliptic integrals",
Numer. Algorithms 10 (1995) 13–26; DLMF 19.16, 19.36.i), by the duplication theorem: with
λ = √x√y + √x√z + √y√z, each argument a ← (a + λ)/4 leaves the integral unchanged (R_F, R_C; R_J gains
a term of R_C), until all arguments are within a relative distance ~ eps^(1/6) of their mean A; then a
fifth-order Taylor series in the deviations X = 1 − x/A, … closes it:

    R_F(x, y, z) = ½ ∫₀^∞ dt / √((t + x)(t + y)(t + z))
                 = A^(−½) (1 − E₂/10 + E₃/14 + E₂²/24 − 3E₂E₃/44),   E₂ = XY − Z², E₃ = XYZ
    R_C(x, y)    = R_F(x, y, y) = A^(−½) (1 + 3s²/10 + s³/7 + 3s⁴/8 + 9s⁵/22 + 159s⁶/208 + 9s⁷/8),
                   s = (y − A)/A;  y < 0: the Cauchy principal value √(x/(x − y)) R_C(x − y, −y)
    R_J(x, y, z, p) = 3/2 ∫₀^∞ dt / ((t + p) √((t + x)(t + y)(t + z)))
                 = 4⁻ⁿ A^(−3/2) (1 − 3E₂/14 + E₃/6 + 9E₂²/88 − 3E₄/22 − 9E₂E₃/52 + 3E₅/26)
                   + 3 Σₖ 4⁻ᵏ R_C(αₖ², βₖ),   α = p(√x + √y + √z) + √(xyz),  β = p (p + λ)²  (arguments at
                   step k; Carlson 1979 / Numerical Recipes' rj: free of the cancellation in the 1995 paper's
                   R_C(1, 1 + e) when p ≪ x, y, z);  p < 0: the Cauchy principal value
                   (Carlson 1995 eq. 2.22, as Numerical Recipes' rj): with x ≤ y ≤ z, q = y + (z − y)(y − x)/(y − p),
                   (y − p) R_J(x, y, z, p) = (q − y) R_J(x, y, z, q) − 3 R_F(x, y, z) + 3 R_C(xz/y, pq/y).

Jacobi's sn, cn, dn (u | m), given m' = 1 − m (accurate up to the separatrix, m' → 0):

    m' >= LANDEN_MC:  the arithmetic-geometric mean (A&S 16.4, DLMF 22.20.ii): a₀ = 1, b₀ = √m', c₀ = √m,
        aₖ₊₁ = (aₖ + bₖ)/2, bₖ₊₁ = √(aₖbₖ), cₖ₊₁ = (aₖ − bₖ)/2 until cₙ/aₙ < eps; φₙ = 2ⁿ aₙ u,
        φₖ₋₁ = (φₖ + asin(cₖ sin φₖ/aₖ))/2;  sn = sin φ₀, cn = cos φ₀, dn = √(m' + m cn²)
    0 < m' < LANDEN_MC:  ascending Landen transformations driven by m' (DLMF 22.7.ii), for |u| <= K,
        k₂' = m'/(1 + k)², v = u/(1 + k₂'), sn(u|m) = (1 + k₂') sn cn/dn, cn(u|m) = (1 + k₂')/k₂² (dn² − k₂')/dn,
        dn(u|m) = (1 − k₂')/k₂² (dn² + k₂')/dn (right sides at (v | m₂ = 1 − k₂'²)), until m' < LANDEN_STOP, where
        sn = tanh v + ¼m'(sinh v cosh v − v) sech² v, cn = sech v − ¼m'(sinh v cosh v − v) tanh v sech v,
        dn = sech v + ¼m'(sinh v cosh v + v) tanh v sech v  (A&S 16.15)
    m' = 0:  sn = tanh u, cn = dn = sech u.

K(m) = R_F(0, m', 1) (DLMF 19.25.1); u beyond ±K: sn(u + 2K) = −sn u, cn(u + 2K) = −cn u, dn(u + 2K) = dn u.
A bad argument (outside the documented domain, or NaN) raises ValueError naming it.
"""
from __future__ import annotations

import math

from .jit import inline

EPS = 2.220446049250313e-16
# The descending AGM loses digits as m' → 0: cₖ/aₖ → 1, the asin of its back-substitution is taken near ±1
# (half the digits), and m = 1 − m' itself is rounded.  The ascending Landen steps are driven by m' and are
# exact in it; below m' = 1e-2 they reach LANDEN_STOP in at most 3 steps (m' → ~m'²/16 each).
LANDEN_MC = 1e-2
# The hyperbolic limit with its first-order term (A&S 16.15) is off by O(m'²) relative: below 1e-15 that is
# below 1e-30, nothing in double precision.
LANDEN_STOP = 1e-15
# m' below this is the separatrix (m' = 0: sn = tanh, cn = dn = sech).  Above it every quantity of the Landen
# path is a normal double: m' itself, and e² = exp(−2|v|) >= ~m'/16 in sech v for |v| <= K ≈ ½ ln(16/m')
# (K < 324); a subnormal m' (< 2.2e-308) would carry few digits.  Nothing is lost: m' comes from δ, a
# difference of O(1) terms rounded to ~1e-16, so any m' this small is the separatrix to rounding.
SEPARATRIX_MC = 1e-280
RF_Q = (3.0 * EPS) ** (-1.0 / 6.0)       # Carlson's Q = (3r)^(−1/6) max|A₀ − a|, r the relative error
RC_Q = (3.0 * EPS) ** (-1.0 / 8.0)
RJ_Q = (0.25 * EPS) ** (-1.0 / 6.0)
MAX_STEPS = 200                          # duplication steps (each divides the spread by 4; ~30 for 1e-300)


@inline
def elliprf(x, y, z):
    """Carlson's R_F(x, y, z) (module docstring), x, y, z >= 0, at most one of them 0."""
    if not (x >= 0.0 and y >= 0.0 and z >= 0.0) or int(x == 0.0) + int(y == 0.0) + int(z == 0.0) > 1 \
            or max(x, y, z) == math.inf:
        raise ValueError("elliprf: x, y, z must be >= 0 (finite) with at most one of them 0")
    x0, y0 = x, y
    A0 = (x + y + z) / 3.0
    Q = RF_Q * max(abs(A0 - x), abs(A0 - y), abs(A0 - z))
    A, f = A0, 1.0
    for _ in range(MAX_STEPS):
        if f * Q < abs(A):
            break
        sx, sy, sz = math.sqrt(x), math.sqrt(y), math.sqrt(z)
        lam = sx * sy + sx * sz + sy * sz
        x, y, z, A = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam), 0.25 * (A + lam)
        f *= 0.25
    X, Y = f * (A0 - x0) / A, f * (A0 - y0) / A   # the deviations at the last step
    Z = -X - Y
    E2 = X * Y - Z * Z
    E3 = X * Y * Z
    return (1.0 - E2 / 10.0 + E3 / 14.0 + E2 * E2 / 24.0 - 3.0 * E2 * E3 / 44.0) / math.sqrt(A)


@inline
def elliprc(x, y):
    """Carlson's R_C(x, y) = R_F(x, y, y) (module docstring), x >= 0, y != 0; y < 0 its Cauchy principal value."""
    if not (x >= 0.0 and y == y and abs(y) < math.inf and x < math.inf) or y == 0.0:
        raise ValueError("elliprc: x must be >= 0 and y nonzero (both finite)")
    w = 1.0
    if y < 0.0:
        w = math.sqrt(x / (x - y))
        x, y = x - y, -y
    y0 = y
    A0 = (x + 2.0 * y) / 3.0
    Q = RC_Q * abs(A0 - x)
    A, f = A0, 1.0
    for _ in range(MAX_STEPS):
        if f * Q < abs(A):
            break
        lam = 2.0 * math.sqrt(x) * math.sqrt(y) + y
        x, y, A = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (A + lam)
        f *= 0.25
    s = f * (y0 - A0) / A
    s2 = s * s
    series = 1.0 + s2 * (0.3 + s * (1.0 / 7.0 + s * (0.375 + s * (9.0 / 22.0 + s * (159.0 / 208.0 + s * 1.125)))))
    return w * series / math.sqrt(A)


@inline
def _elliprj_positive(x, y, z, p):
    """R_J(x, y, z, p) for p > 0 by duplication (module docstring)."""
    x0, y0, z0 = x, y, z
    A0 = (x + y + z + 2.0 * p) / 5.0
    Q = RJ_Q * max(abs(A0 - x), abs(A0 - y), abs(A0 - z), abs(A0 - p))
    A, f, total = A0, 1.0, 0.0
    for _ in range(MAX_STEPS):
        if f * Q < abs(A):
            break
        sx, sy, sz, sp = math.sqrt(x), math.sqrt(y), math.sqrt(z), math.sqrt(p)
        lam = sx * sy + sx * sz + sy * sz
        alpha = p * (sx + sy + sz) + sx * sy * sz
        total += f * elliprc(alpha * alpha, p * (p + lam) ** 2)
        x, y, z, p, A = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam), 0.25 * (p + lam), 0.25 * (A + lam)
        f *= 0.25
    X, Y, Z = f * (A0 - x0) / A, f * (A0 - y0) / A, f * (A0 - z0) / A
    P = -0.5 * (X + Y + Z)
    E2 = X * Y + X * Z + Y * Z - 3.0 * P * P
    E3 = X * Y * Z + 2.0 * E2 * P + 4.0 * P * P * P
    E4 = (2.0 * X * Y * Z + E2 * P + 3.0 * P * P * P) * P
    E5 = X * Y * Z * P * P
    series = (1.0 - 3.0 * E2 / 14.0 + E3 / 6.0 + 9.0 * E2 * E2 / 88.0 - 3.0 * E4 / 22.0
              - 9.0 * E2 * E3 / 52.0 + 3.0 * E5 / 26.0)
    return f * series / (A * math.sqrt(A)) + 3.0 * total


@inline
def elliprj(x, y, z, p):
    """Carlson's R_J(x, y, z, p) (module docstring), x, y, z >= 0 with at most one 0, p != 0; p < 0 its
    Cauchy principal value (then the middle of x, y, z must be > 0)."""
    if not (x >= 0.0 and y >= 0.0 and z >= 0.0 and p == p) or int(x == 0.0) + int(y == 0.0) + int(z == 0.0) > 1 \
            or p == 0.0 or max(x, y, z, abs(p)) == math.inf:
        raise ValueError("elliprj: x, y, z must be >= 0 (finite) with at most one of them 0, and p nonzero finite")
    if p > 0.0:
        return _elliprj_positive(x, y, z, p)
    lo, hi = min(x, y, z), max(x, y, z)
    mid = x + y + z - lo - hi
    q = mid + (hi - mid) * (mid - lo) / (mid - p)
    return ((q - mid) * _elliprj_positive(lo, mid, hi, q) - 3.0 * elliprf(lo, mid, hi)
            + 3.0 * elliprc(lo * hi / mid, p * q / mid)) / (mid - p)


@inline
def sech(u):
    """sech u = 2e/(1 + e²), e = exp(−|u|): no overflow for any u."""
    e = math.exp(-abs(u))
    return 2.0 * e / (1.0 + e * e)


@inline
def _landen_kp(mc, i):
    """k₂' of the i-th ascending Landen step from m' = mc (module docstring)."""
    c = mc
    kp = 0.0
    for _ in range(i + 1):
        kp = c / (1.0 + math.sqrt(1.0 - c)) ** 2
        c = kp * kp
    return kp


@inline
def jacobi_landen(u, mc):
    """sn, cn, dn (u | 1 − mc) for 0 <= mc < LANDEN_MC and |u| <= K (module docstring: ascending Landen
    transformations, then the hyperbolic limit with its first-order term)."""
    v, c, n = u, mc, 0
    while c > LANDEN_STOP:
        kp = c / (1.0 + math.sqrt(1.0 - c)) ** 2
        v = v / (1.0 + kp)
        c = kp * kp
        n += 1
    th, se = math.tanh(v), sech(v)
    sh = th / se                                  # |v| <= K < 330 here: no overflow
    a = 0.25 * c * (sh - v * se)                  # ¼ m' (sinh cosh − v) sech
    b = 0.25 * c * (sh + v * se)
    sn, cn, dn = th + a * se, se - a * th, se + b * th
    for i in range(n - 1, -1, -1):
        kp = _landen_kp(mc, i)
        k22 = (1.0 - kp) * (1.0 + kp)
        d2 = dn * dn
        sn, cn, dn = (1.0 + kp) * sn * cn / dn, (1.0 + kp) / k22 * (d2 - kp) / dn, (1.0 - kp) / k22 * (d2 + kp) / dn
    return sn, cn, dn


@inline
def _agm(mc, k):
    """(aₖ, bₖ, cₖ) of the arithmetic-geometric mean from a₀ = 1, b₀ = √m', c₀ = √m (module docstring)."""
    a, b, c = 1.0, math.sqrt(mc), math.sqrt(1.0 - mc)
    for _ in range(k):
        a, b, c = 0.5 * (a + b), math.sqrt(a * b), 0.5 * (a - b)
    return a, b, c


@inline
def jacobi_agm(u, mc):
    """sn, cn, dn (u | 1 − mc) by the arithmetic-geometric mean (module docstring), 0 <= mc <= 1, any u
    (at most 8 steps: enough for m' >= 1e-16)."""
    n = 0
    a, b, c = _agm(mc, 0)
    while n < 8 and abs(c) > EPS * a:
        a, b, c = 0.5 * (a + b), math.sqrt(a * b), 0.5 * (a - b)
        n += 1
    phi = 2.0 ** n * a * u
    for k in range(n, 0, -1):
        ak, _, ck = _agm(mc, k)
        phi = 0.5 * (math.asin(ck * math.sin(phi) / ak) + phi)
    cn = math.cos(phi)
    return math.sin(phi), cn, math.sqrt(mc + (1.0 - mc) * cn * cn)


@inline
def ellipk(mc):
    """K(m) = R_F(0, m', 1), the quarter period, for 0 < mc = m' <= 1 (DLMF 19.25.1)."""
    return elliprf(0.0, mc, 1.0)


@inline
def jacobi_reduced(u, mc):
    """sn, cn, dn (u | 1 − mc) for |u| <= K (or any u when mc >= LANDEN_MC): the regime of m' (module
    docstring) — the separatrix (mc = 0), the Landen transformations (mc < LANDEN_MC), the AGM."""
    if mc == 0.0:
        s = sech(u)
        return math.tanh(u), s, s
    if mc < LANDEN_MC:
        return jacobi_landen(u, mc)
    return jacobi_agm(u, mc)


@inline
def jacobi(u, mc):
    """sn, cn, dn (u | m) for any real u and m' = mc = 1 − m in [0, 1] (given directly: accurate up to the
    separatrix): u reduced to |u| <= K by the half period 2K (module docstring) where the Landen
    transformations need it, then jacobi_reduced."""
    if not (mc >= 0.0 and mc <= 1.0) or not abs(u) < math.inf:
        raise ValueError("jacobi: m' = 1 - m must be in [0, 1] and u finite")
    if mc == 0.0 or mc >= LANDEN_MC:
        return jacobi_reduced(u, mc)
    K = ellipk(mc)
    if abs(u) <= K:
        return jacobi_reduced(u, mc)
    j = round(u / (2.0 * K))
    sn, cn, dn = jacobi_reduced(u - j * 2.0 * K, mc)
    if j % 2:
        return -sn, -cn, dn
    return sn, cn, dn


@inline
def ellipj(u, m):
    """sn, cn, dn (u | m) for 0 <= m <= 1 (scipy.special.ellipj's argument; near m = 1 call jacobi with m')."""
    if not (m >= 0.0 and m <= 1.0):
        raise ValueError("ellipj: m must be in [0, 1]")
    return jacobi(u, 1.0 - m)
