"""Jacobi's elliptic functions sn, cn, dn and the incomplete integral of the third kind Π, as the
exact torque-free motion (free_body.py) needs them — accurate up to the separatrix (m' → 0).

sn, cn, dn (u | m), m = 1 − m'.  For m' >= LANDEN_MC = 1e-2: scipy.special.ellipj (after the
reduction to |u| <= K, K = R_F(0, m', 1)).  Closer to the separatrix scipy's ellipj loses digits
(it takes m, not m', and uses a first-order expansion for m' < 1e-9), so sn, cn, dn come from
ascending Landen transformations (DLMF 22.7.ii) driven by m' itself,

    k₂' = (1 − k)/(1 + k) = m'/(1 + k)²,  m₂' = k₂'²,  v = u/(1 + k₂'),
    sn(u|m) = (1 + k₂') sn cn/dn,  cn(u|m) = (1 + k₂')/k₂² (dn² − k₂')/dn,
    dn(u|m) = (1 − k₂')/k₂² (dn² + k₂')/dn          (right sides at (v | m₂)),

down to m' < LANDEN_STOP = 1e-15, where the hyperbolic limit with its first-order correction
(A&S 16.15) is exact to rounding:  sn = tanh v + ¼m'(sinh v cosh v − v) sech² v, … .
Exactly on the separatrix (m' = 0): sn = tanh u, cn = dn = sech u.

Π in Carlson's symmetric forms (scipy.special.elliprf, elliprc, elliprj), with Λ = Π − τ:

    Λ(τ) = Π(am τ, n | m) − τ = (n/3) sn³τ R_J(cn²τ, dn²τ, 1, 1 − n sn²τ)        (|n| <= 1, |τ| <= K)
    Π(am τ, n | m) = sn R_C(cn² dn², (1 − n sn²)(1 − w sn²)) − (w/3) sn³ R_J(cn², dn², 1, 1 − w sn²)
                                                       (|n| > 1: the n → w = m/n transformation, DLMF 19.7.9)
    Π(am τ, n | 1) = (τ + √ν atan(√ν tanh τ))/(1 + ν),  ν = −n                   (on the separatrix)

and over a half period τ → τ + 2K each gains `half` (free_body.Elliptic.half).

These are the reference's (rbcourse/exact/, the independent reference the methods are checked against),
built on scipy.special.  The compiled engine has its own (rbcourse/engine/elliptic.py: scipy cannot be
called from compiled code), with its own constants: nothing here is shared with it, so that the reference
checks the engine's exact flow instead of repeating it (tests/test_two_exact_flows.py).
"""
from __future__ import annotations

import numpy as np
from scipy import special

LANDEN_MC = 1e-2          # m' below this: our own Landen evaluation instead of scipy's ellipj
LANDEN_STOP = 1e-15       # Landen steps until m' is below this
SEPARATRIX_MC = 1e-280    # m' below this is the separatrix itself (m' = 0: sn = tanh; m' this small is
                          # the separatrix to the rounding of δ, and no step of the Landen path is subnormal)
ZERO_COMPONENT = 1e-150   # |μᵢ| below this is taken as 0 (a spin along a principal axis; free_body's)


def sech(u, exp=np.exp):
    """sech u = 2e/(1 + e²), e = exp(−|u|): no overflow for any u.  exp=math.exp for a plain float."""
    e = exp(-abs(u))
    return 2.0 * e / (1.0 + e * e)


def jacobi(u, mc, sep):
    """sn, cn, dn (u | m = 1 − mc) for u (T, n) reduced to |u| <= K, mc (n,) given directly;
    sep (n,): the columns exactly on the separatrix (mc = 0)."""
    sn, cn, dn = np.empty_like(u), np.empty_like(u), np.empty_like(u)
    big = mc >= LANDEN_MC
    near = ~big & ~sep
    if big.all():
        sn, cn, dn, _ = special.ellipj(u, 1.0 - mc)
        return sn, cn, dn
    if big.any():
        c = np.flatnonzero(big)
        sn[:, c], cn[:, c], dn[:, c], _ = special.ellipj(u[:, c], 1.0 - mc[c])
    if sep.any():
        c = np.flatnonzero(sep)
        sn[:, c], cn[:, c] = np.tanh(u[:, c]), sech(u[:, c])
        dn[:, c] = cn[:, c]
    if near.any():
        c = np.flatnonzero(near)
        sn[:, c], cn[:, c], dn[:, c] = jacobi_landen(u[:, c], mc[c])
    return sn, cn, dn


def _landen(v, c, more, sqrt, tanh, exp):
    """The ascending Landen transformations (module docstring) from (v, m' = c) while more(c)."""
    kps = []
    while more(c):
        kp = c / (1.0 + sqrt(1.0 - c)) ** 2
        kps.append(kp)
        v = v / (1.0 + kp)
        c = kp * kp
    th, se = tanh(v), sech(v, exp)
    sh = th / se                                  # |v| <= K < 330 here: no overflow
    a = 0.25 * c * (sh - v * se)                  # ¼ m' (sinh cosh − v) sech
    b = 0.25 * c * (sh + v * se)
    sn, cn, dn = th + a * se, se - a * th, se + b * th
    for kp in reversed(kps):
        k22 = (1.0 - kp) * (1.0 + kp)
        d2 = dn * dn
        sn, cn, dn = (1.0 + kp) * sn * cn / dn, (1.0 + kp) / k22 * (d2 - kp) / dn, (1.0 - kp) / k22 * (d2 + kp) / dn
    return sn, cn, dn


def jacobi_landen(u, mc):
    """sn, cn, dn (u | m = 1 − mc) for m' = mc small (< LANDEN_MC) by ascending Landen
    transformations (see the module docstring), until m' < LANDEN_STOP, then the hyperbolic limit
    with its first-order term.  u (T, n) arrays with |u| <= K, mc (n,)."""
    c = np.broadcast_to(mc, u.shape).copy()
    return _landen(u.copy(), c, lambda c: np.any(c > LANDEN_STOP), np.sqrt, np.tanh, np.exp)


def pi_big_n(sn, cn, dn, n, w):
    """Π(am τ, n | m) for |n| > 1 by the n → w = m/n transformation (DLMF 19.7.9), free of the
    cancellation F + (n/3)(…):  sn R_C(cn² dn², (1 − n sn²)(1 − w sn²)) − (w/3) sn³ R_J(cn², dn², 1, 1 − w sn²).
    Arrays or numbers (sn, cn, dn at τ)."""
    s2, c2, d2 = sn * sn, cn * cn, dn * dn
    return (sn * special.elliprc(c2 * d2, (1.0 - n * s2) * (1.0 - w * s2))
            - w / 3.0 * sn * s2 * special.elliprj(c2, d2, 1.0, 1.0 - w * s2))


def phase(u, sn, cn, dn, j, n, w, sep, big, half):
    """Λ(τ) = Π(am τ, n | m) − τ (|n| <= 1) or Π(am τ, n | m) itself (|n| > 1), (T, k) arrays.

    τ = u + 2jK with |u| <= K and sn, cn, dn at u; n, w = m/n, sep (on the separatrix), big (|n| > 1)
    and half (the gain over τ → τ + 2K) per column (k,).  The three forms of the module docstring."""
    out = np.empty_like(u)
    for cols, kind in ((~sep & ~big, 0), (~sep & big, 1), (sep, 2)):
        if not cols.any():
            continue
        cols = np.flatnonzero(cols)
        nc = n[cols]
        uu, s = u[:, cols], sn[:, cols]
        if kind == 2:
            nu = -nc
            r = np.sqrt(nu)
            at = r * np.arctan(r * np.tanh(uu))
            out[:, cols] = np.where(big[cols], uu + at, at - nu * uu) / (1.0 + nu)
            continue
        if kind == 0:
            c2, d2, s2 = cn[:, cols] ** 2, dn[:, cols] ** 2, s * s
            val = nc / 3.0 * s * s2 * special.elliprj(c2, d2, 1.0, 1.0 - nc * s2)
        else:
            val = pi_big_n(s, cn[:, cols], dn[:, cols], nc, w[cols])
        out[:, cols] = val + j[:, cols] * half[cols]
    return out
