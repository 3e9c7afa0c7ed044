"""Complete elliptic integrals, Jacobi elliptic functions and Carlson's integrals, compiled.

The exact torque-free motion of a rigid body is written with these functions, and
``scipy.special`` cannot be called from numba's nopython code, so they are here.
All take and return float64 scalars and never raise.

Conventions
-----------
Everything is written with the **parameter** ``m = k²`` (as in scipy, mpmath and
Abramowitz & Stegun ch. 16-17), never the modulus ``k``. Each function of ``m``
has a twin ``*_mc`` taking the complementary parameter ``mc = 1 - m`` itself: near
``m = 1`` the value of ``1 - m`` decides the result (``K ≈ ln(4/√mc)``), and a
float ``m`` cannot carry it (``1 - 1e-300`` is ``1.0``), so callers that know
``mc`` accurately should pass it.

Accuracy
--------
Measured against mpmath at 40+ digits (see ``tests/core/test_elliptic.py``):

* ``ellipk``, ``ellipk_mc``: within 2.4 ulp over the whole range, ``mc`` down to
  the smallest subnormal.
* ``ellipj``, ``ellipj_mc`` for ``0 ≤ m ≤ 1``: the error in each of sn, cn, dn is
  within a few ulp of ``|f| + |ũ f'(ũ)|``, where ``ũ`` is ``u`` reduced to
  ``[-2K, 2K]``: the rounding of the phase to a double propagates through the
  derivative (measured worst 2.3 such units). Because ``u`` is reduced with a
  double-double period first, ``u = 10⁶ K`` is as accurate as ``u = K``.
* ``elliprf``, ``elliprc``, ``elliprj``: within 2.6, 1.8 and 3.3 ulp; the
  principal value of RJ (``p < 0``) loses what its formula cancels.

Error handling
--------------
No checks and no exceptions: where the mathematics gives no real value (a
negative argument of a square root, ``K`` of ``m > 1``) the result is NaN, where
an integral diverges it is ``inf``, and NaN in gives NaN out.
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit

__all__ = [
    "dd_add",
    "dd_mul",
    "dd_sqrt",
    "ellipj",
    "ellipj_mc",
    "ellipk",
    "ellipk_mc",
    "elliprc",
    "elliprf",
    "elliprj",
    "fast_two_sum",
    "inverse_period",
    "two_prod",
    "two_sum",
]

# Arithmetic-geometric mean in double: once |a - b| <= 2^-26 a, the mean (a + b)/2
# is within (a - b)²/(16 a) <= 2^-56 a of the limit, below half an ulp.
_AGM_TOL = 2.0**-26
# AGM(1, √mc) needs at most 11 steps (for the smallest subnormal mc, and for the
# largest finite one); room to spare.
_MAX_AGM = 20

# Dekker's splitting constant 2^27 + 1 for exact products without FMA.
_SPLIT = 134217729.0
# Products are split exactly only below this size; larger factors are scaled first.
_SPLIT_LIMIT = 2.0**995

# 1/(4π) as a double-double (hi + lo), from mpmath at 300 bits.
_INV_4PI_HI = 0.5 * 0.15915494309189535
_INV_4PI_LO = 0.5 * -9.839338337591243e-18

# Below this |u| (or reduced phase) sn = u, cn = dn = 1 exactly in double, and
# the cotangent recurrence below would overflow.
_TINY = 2.0**-333

# Carlson's duplication: iterate until 4^-n Q < |A_n| with Q = c max|A0 - x_i|;
# the truncated series then has relative error below r = 2^-52 (Carlson 1995,
# eqs. 2.2, 2.12, 2.20): c = (3r)^(-1/6) for RF, (3r)^(-1/8) for RC, (r/4)^(-1/6) for RJ.
_R = 2.0**-52
_RF_Q = (3.0 * _R) ** (-1.0 / 6.0)
_RC_Q = (3.0 * _R) ** (-1.0 / 8.0)
_RJ_Q = (_R / 4.0) ** (-1.0 / 6.0)
# Duplication steps needed: about log4(spread of the arguments) + 6, at most ~40
# given the asymptotic branch for RJ with a dominant p; NaN stops here.
_MAX_DUP = 64
# RJ with max(x, y, z) < 2^-60 p takes its asymptotic form.
_RJ_HUGE_P = 2.0**-60


# --------------------------------------------------------------------------
# Double-double arithmetic (Dekker 1971), used to reduce u modulo 4K (and by
# tumble.core.freebody for the phase λ t).
# --------------------------------------------------------------------------


@njit
def two_sum(a, b):  # type: ignore[no-untyped-def]
    """``a + b = s + e`` exactly (Knuth)."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


@njit
def fast_two_sum(a, b):  # type: ignore[no-untyped-def]
    """``a + b = s + e`` exactly, for ``|a| >= |b|``."""
    s = a + b
    e = b - (s - a)
    return s, e


@njit
def two_prod(a, b):  # type: ignore[no-untyped-def]
    """``a b = p + e`` exactly (Dekker's product), for ``|a|, |b| < 2^995``."""
    p = a * b
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * b
    bh = t - (t - b)
    bl = b - bh
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e


@njit
def dd_add(ah, al, bh, bl):  # type: ignore[no-untyped-def]
    s, e = two_sum(ah, bh)
    return fast_two_sum(s, e + (al + bl))


@njit
def dd_mul(ah, al, bh, bl):  # type: ignore[no-untyped-def]
    p, e = two_prod(ah, bh)
    return fast_two_sum(p, e + (ah * bl + al * bh))


@njit
def dd_sqrt(ah, al):  # type: ignore[no-untyped-def]
    """Square root of a positive double-double, one Newton step from the double root."""
    s = math.sqrt(ah)
    if s == 0.0:
        return 0.0, 0.0
    p, e = two_prod(s, s)
    return fast_two_sum(s, ((ah - p) - e + al) / (2.0 * s))


# --------------------------------------------------------------------------
# Complete elliptic integral of the first kind
# --------------------------------------------------------------------------


@njit
def ellipk_mc(mc):  # type: ignore[no-untyped-def]
    """Complete elliptic integral of the first kind, from the complementary parameter.

    ``K = ∫₀^{π/2} dθ / √(1 - m sin²θ)`` with ``m = 1 - mc`` (parameter, not
    modulus: ``m = k²``). Same as ``scipy.special.ellipkm1(mc)``.

    Parameters
    ----------
    mc : float64, ``mc = 1 - m > 0``. Tiny ``mc`` (down to the smallest
        subnormal) keeps full relative accuracy, where ``K ≈ ln(4/√mc)``;
        ``mc > 1`` is ``m < 0``.

    Returns
    -------
    float64 ``K``: ``inf`` at ``mc = 0`` (``m = 1``), ``0`` at ``mc = inf``, NaN for
    ``mc < 0`` (``m > 1``, where ``K`` is complex) and for NaN.

    Algorithm: Gauss's arithmetic-geometric mean, ``K = π / (2 AGM(1, √mc))``
    (DLMF 19.8.5; Abramowitz & Stegun 17.6), quadratically convergent: at most
    11 steps. Relative error a few ulp (measured worst 2.4 against mpmath).
    """
    if not mc > 0.0:
        return math.inf if mc == 0.0 else math.nan
    a = 1.0
    b = math.sqrt(mc)
    for _ in range(_MAX_AGM):
        if abs(a - b) <= _AGM_TOL * a:
            break
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return math.pi / (a + b)


@njit
def ellipk(m):  # type: ignore[no-untyped-def]
    """Complete elliptic integral of the first kind ``K(m)``, parameter ``m = k²``.

    ``K(m) = ∫₀^{π/2} dθ / √(1 - m sin²θ)``, as ``scipy.special.ellipk(m)``.
    Domain ``m < 1`` (``m < 0`` included); ``K(1) = inf``, NaN for ``m > 1``.
    Computed as :func:`ellipk_mc` of ``1 - m``: exact for ``m >= 1/2``, but ``m``
    itself cannot be closer to 1 than ``2^-53``: near ``m = 1`` pass ``mc`` to
    :func:`ellipk_mc` instead.
    """
    return ellipk_mc(1.0 - m)


# --------------------------------------------------------------------------
# Jacobi elliptic functions
# --------------------------------------------------------------------------


@njit
def inverse_period(mc, mc_lo):  # type: ignore[no-untyped-def]
    """``1 / 4K = A / 2π`` in double-double, ``A = AGM(1, √(mc + mc_lo))``."""
    ah = 1.0
    al = 0.0
    if mc < 2.0**-900:
        # The square root's residual would be subnormal and lose bits: scale by 4^500.
        bh, bl = dd_sqrt(mc * 2.0**1000, mc_lo * 2.0**1000)
        bh *= 2.0**-500
        bl *= 2.0**-500
    else:
        bh, bl = dd_sqrt(mc, mc_lo)
    for _ in range(_MAX_AGM):
        if abs(ah - bh) <= _AGM_TOL * ah:
            break
        sh, sl = dd_add(ah, al, bh, bl)
        ph, pl = dd_mul(ah, al, bh, bl)
        bh, bl = dd_sqrt(ph, pl)
        ah = 0.5 * sh
        al = 0.5 * sl
    # With x = (a - b)/(a + b) <= 2^-27, AGM(a, b) = (a + b)/2 (1 - x²/4 - 5x⁴/64 - ...);
    # the x⁴ term is below 2^-108, so the x² term finishes the mean in double-double
    # one step before the ladder itself would.
    sh, sl = dd_add(ah, al, bh, bl)
    x = ((ah - bh) + (al - bl)) / sh  # ah - bh is exact; the low parts matter at x ~ 2^-40
    sh, sl = fast_two_sum(sh, sl - sh * (0.25 * x * x))  # 2A
    fh, fl = dd_mul(sh, sl, _INV_4PI_HI, _INV_4PI_LO)  # A / (2π) = 1 / (4K)
    return fh, fl


@njit
def _reduce(u, fh, fl):  # type: ignore[no-untyped-def]
    """``2π`` times the fractional part of ``u (fh + fl)``, with ``fh + fl = 1/4K``
    in double-double (from :func:`inverse_period`), in ``[-π, π]``.

    The product is taken exactly, so the fraction carries an error of one
    rounding plus about ``|u / 4K| 2^-104`` rather than the ``|u / 4K| 2^-53`` of
    a double product: the second term is below the first unless the fraction lies
    within ``2^-50 |u / 4K|`` of zero, or ``|u|`` exceeds ``2^50 K``.
    """
    scale = 1.0
    if abs(u) > _SPLIT_LIMIT:
        u *= 2.0**-64
        scale = 2.0**64
    p, e = two_prod(u, fh)
    p *= scale
    e = (e + u * fl) * scale
    # u / 4K = p + e; p - round(p) is exact (Sterbenz), e adds the low part.
    f = (p - math.floor(p + 0.5)) + e
    f -= math.floor(f + 0.5)  # only matters past |u| ~ 2^53 K, where e > 1/2
    return 2.0 * math.pi * f


@njit
def _sech(u):  # type: ignore[no-untyped-def]
    """``1/cosh(u)``, without overflowing cosh past ``|u| = 710``."""
    a = abs(u)
    if a < 700.0:
        return 1.0 / math.cosh(a)
    return 2.0 * math.exp(-a)  # cosh = e^a/2 (1 + e^-2a), and e^-1400 is nothing


#: Layout of the table from :func:`jacobi_table`: the AGM means a_i and b_i,
#: then the ladder's top index, A = AGM(1, √mc), 1/4K in double-double (NaN
#: until needed), and mc in double-double.
_TABLE_TOP = 2 * _MAX_AGM
_TABLE_SIZE = 2 * _MAX_AGM + 6


@njit
def jacobi_table(mc, mc_lo, with_period=True):  # type: ignore[no-untyped-def]
    """What sn, cn, dn need from the parameter alone, for ``0 < mc + mc_lo <= 1``:
    the AGM ladder and (``with_period``, else on first need) the double-double
    inverse period. Computing it once and calling :func:`jacobi_from_table` for
    many u saves most of :func:`ellipj`'s cost per call."""
    table = np.empty(_TABLE_SIZE)
    a = 1.0
    b = math.sqrt(mc)
    c = 1.0
    top = 0
    for i in range(_MAX_AGM):
        table[i] = a
        table[_MAX_AGM + i] = b
        top = i
        c = 0.5 * (a + b)
        if abs(a - b) <= _AGM_TOL * a:
            break
        b = math.sqrt(a * b)
        a = c
    table[_TABLE_TOP] = top
    # c = AGM(1, √mc) = π/(2K): the phase u c runs through 2π in one period 4K.
    table[_TABLE_TOP + 1] = c
    table[_TABLE_TOP + 4] = mc
    table[_TABLE_TOP + 5] = mc_lo
    table[_TABLE_TOP + 2] = math.nan
    table[_TABLE_TOP + 3] = math.nan
    if with_period:
        _fill_period(table)
    return table


@njit
def _fill_period(table):  # type: ignore[no-untyped-def]
    fh, fl = inverse_period(table[_TABLE_TOP + 4], table[_TABLE_TOP + 5])
    table[_TABLE_TOP + 2] = fh
    table[_TABLE_TOP + 3] = fl


@njit
def jacobi_from_table(u, table, u_lo=0.0):  # type: ignore[no-untyped-def]
    """sn, cn, dn of ``u + u_lo`` for the parameter of ``table``
    (:func:`jacobi_table`); Bulirsch's descending Gauss transformation (see
    :func:`ellipj`). ``u_lo`` carries the low part of an argument known in
    double-double (a phase ``λ t`` at very large t), so its reduction modulo
    the period stays exact."""
    if not abs(u) < math.inf:
        return math.nan, math.nan, math.nan
    if abs(u) < _TINY:
        return u, 1.0, 1.0
    top = int(table[_TABLE_TOP])
    c = table[_TABLE_TOP + 1]
    v = u * c + u_lo * c
    if not abs(v) <= math.pi:
        if table[_TABLE_TOP + 2] != table[_TABLE_TOP + 2]:
            _fill_period(table)
        fh = table[_TABLE_TOP + 2]
        v = _reduce(u, fh, table[_TABLE_TOP + 3])
        v = v + 2.0 * math.pi * (u_lo * fh)  # the low part's share of the phase
    if abs(v) < _TINY:
        return v / c, 1.0, 1.0
    s = math.sin(v)
    # Backward recurrence for the ratio cs = cn/sn and for dn (Bulirsch 1965):
    # dn enters only as a ratio of sums of positive terms, so it keeps full
    # relative accuracy where it is tiny (dn(K) = √mc as m -> 1), unlike
    # √(mc + m cn²) or Cephes' cos φ / cos(φ₁ - φ), which is 0/0 at u = K.
    a = math.cos(v) / s
    c *= a
    dn = 1.0
    for i in range(top, -1, -1):
        b = table[i]
        a *= c
        c *= dn
        dn = (table[_MAX_AGM + i] + a) / (b + a)
        a = c / b
    sn = math.copysign(1.0 / math.sqrt(c * c + 1.0), s)
    return sn, c * sn, dn


@njit
def _ellipj_unit(u, mc, mc_lo):  # type: ignore[no-untyped-def]
    """sn, cn, dn for ``0 <= mc = mc + mc_lo <= 1``; Bulirsch's descending Gauss transformation."""
    if mc == 0.0:
        s = _sech(u)
        return math.tanh(u), s, s
    if not abs(u) < math.inf:
        return math.nan, math.nan, math.nan
    if abs(u) < _TINY:
        return u, 1.0, 1.0
    return jacobi_from_table(u, jacobi_table(mc, mc_lo, False))


@njit
def _ellipj(u, mc, mc_lo):  # type: ignore[no-untyped-def]
    """sn, cn, dn for any real ``m = 1 - (mc + mc_lo)``, by the modulus transformations."""
    if not abs(mc) < math.inf or u != u:
        return math.nan, math.nan, math.nan
    if mc > 1.0:
        # m < 0: imaginary-modulus transformation (A&S 16.10) to μ = -m/(1-m) in
        # (0, 1), 1 - μ = 1/mc; sn = sd(v|μ)/√mc, cn = cd(v|μ), dn = nd(v|μ).
        r = math.sqrt(mc)
        sn, cn, dn = _ellipj_unit(u * r, 1.0 / (mc + mc_lo), 0.0)
        return sn / (r * dn), cn / dn, 1.0 / dn
    if mc < 0.0:
        # m > 1: reciprocal-modulus transformation (A&S 16.11) to 1/m, 1 - 1/m = -mc/m;
        # sn = sn(v|1/m)/√m, cn = dn(v|1/m), dn = cn(v|1/m).
        m = (1.0 - mc) - mc_lo
        r = math.sqrt(m)
        sn, cn, dn = _ellipj_unit(u * r, -(mc + mc_lo) / m, 0.0)
        return sn / r, dn, cn
    if mc == 1.0 and mc_lo == 0.0:
        if not abs(u) < math.inf:
            return math.nan, math.nan, 1.0
        return math.sin(u), math.cos(u), 1.0
    return _ellipj_unit(u, mc, mc_lo)


@njit
def ellipj_mc(u, mc):  # type: ignore[no-untyped-def]
    """Jacobi elliptic functions ``(sn, cn, dn)`` of ``u``, from the complementary parameter.

    The same as :func:`ellipj` with ``m = 1 - mc``, for callers who know ``mc``
    better than ``1 - m`` can carry it: near ``m = 1`` (``mc`` down to the
    smallest subnormal) all three keep their relative accuracy, ``dn`` included
    where it is as small as ``√mc``. ``mc = 0`` gives ``(tanh u, sech u, sech u)``.
    See :func:`ellipj` for definitions, domain, algorithm and accuracy.
    """
    return _ellipj(u, mc, 0.0)


@njit
def ellipj(u, m):  # type: ignore[no-untyped-def]
    """Jacobi elliptic functions ``(sn, cn, dn)`` of ``u`` with parameter ``m = k²``.

    With the amplitude ``φ = am(u|m)`` defined by ``u = ∫₀^φ dθ / √(1 - m sin²θ)``:
    ``sn = sin φ``, ``cn = cos φ``, ``dn = √(1 - m sn²)`` (as
    ``scipy.special.ellipj(u, m)``, which returns a fourth value φ; DLMF 22.2).
    sn and cn have period ``4K(m)``, dn ``2K(m)``; ``m = 0`` gives
    ``(sin u, cos u, 1)`` and ``m = 1`` gives ``(tanh u, sech u, sech u)``.

    Parameters
    ----------
    u : float64, any finite value (dimensionless). NaN gives NaN, and so does
        ``±inf``, except for the limits ``(±1, 0, 0)`` at ``m = 1`` and ``dn = 1``
        at ``m = 0``.
    m : float64, any real value; ``0 <= m <= 1`` is the usual range. ``m < 0``
        and ``m > 1`` are mapped there by the imaginary- and reciprocal-modulus
        transformations (A&S 16.10, 16.11), after which the phase of a large
        ``u`` is no longer reduced exactly. Near ``m = 1`` prefer
        :func:`ellipj_mc`, since a float ``m`` cannot be closer to 1 than 2^-53.

    Returns
    -------
    (sn, cn, dn) : three float64.

    Algorithm: the arithmetic-geometric mean ``A = AGM(1, √(1-m)) = π/(2K)`` and
    Bulirsch's descending Gauss transformation (R. Bulirsch, "Numerical
    calculation of elliptic integrals and elliptic functions", Numer. Math. 7
    (1965) 78-90; the ``sncndn`` of Numerical Recipes, 3rd ed., §6.12), which
    starts from ``cot(A u)`` and carries the ratio ``cn/sn`` and ``dn`` back up
    the AGM ladder. Two changes make it accurate everywhere:

    * the phase ``A u`` is reduced modulo ``2π`` (``u`` modulo ``4K``) with ``A``
      and the product in double-double, so the phase error does not grow with
      ``|u|`` (plain double arithmetic, as in Cephes/scipy, loses about
      ``|u| 2^-53`` absolute: ``1e-10`` at ``u = 10⁶``);
    * ``1 - m`` is taken exactly (a double-double), so it is ``m``, not a
      rounded ``1 - m``, whose period is used.

    Accuracy (0 <= m <= 1): each of sn, cn, dn is within a few ulp (measured
    worst 2.3) of ``|f| + (|ũ| + 2^-48 |u|) |f'|``, with ``ũ`` the reduced ``u``
    in ``[-2K, 2K]`` and ``f' = cn dn, -sn dn, -m sn cn``: about 1e-15 absolute
    where the derivatives are O(1), relative where sn, cn or dn are small and
    slowly varying (dn near ``u = K`` as m -> 1). The ``ũ f'`` term is what
    rounding the phase to a double does by itself; the ``2^-48 |u|`` term, from
    the double-double period, counts only within ``2^-48 |u|`` of a zero.
    """
    mc, mc_lo = two_sum(1.0, -m)
    return _ellipj(u, mc, mc_lo)


# --------------------------------------------------------------------------
# Carlson's symmetric elliptic integrals
# --------------------------------------------------------------------------


@njit
def _scale_exponent(s, hi):  # type: ignore[no-untyped-def]
    """k such that scaling by ``4^-k`` brings the largest argument ``s`` into range, else 0.

    Below ``2^-500`` it goes up to [1, 4), which is exact; above ``hi`` down to
    [hi/4, hi), which is exact unless it takes an argument below the smallest
    subnormal (one more than ``2^1074 hi`` times smaller than the largest), which
    then counts as zero.
    """
    if 2.0**-500 <= s <= hi or not 0.0 < s < math.inf:
        return 0
    _, e = math.frexp(s)  # s = f 2^e, 1/2 <= f < 1
    if s < 1.0:
        return (e - 1) // 2
    _, e_hi = math.frexp(hi)
    return (e - e_hi) // 2 + 1


@njit
def elliprf(x, y, z):  # type: ignore[no-untyped-def]
    """Carlson's symmetric elliptic integral of the first kind ``RF(x, y, z)``.

    ``RF(x, y, z) = ½ ∫₀^∞ dt / √((t + x)(t + y)(t + z))``, as ``scipy.special.elliprf``
    (DLMF 19.16.1). For example ``K(m) = RF(0, 1 - m, 1)``.

    Domain ``x, y, z >= 0``, at most one of them zero (two zeros: ``inf``, the
    integral diverges; any negative: NaN; ``+inf`` with the others finite: 0).
    RF is homogeneous of degree -1/2; arguments beyond ``2^1000`` or all below
    ``2^-500`` are first scaled by a power of 4.

    Algorithm: Carlson's duplication theorem and the Taylor series about the
    mean, truncated after the fifth-order terms (B. C. Carlson, "Numerical
    computation of real or complex elliptic integrals", Numer. Algorithms 10
    (1995) 13-26, Algorithm 1, with r = 2^-52). Relative error a few ulp.
    """
    if not (x >= 0.0 and y >= 0.0 and z >= 0.0):
        return math.nan
    if (x == 0.0) + (y == 0.0) + (z == 0.0) >= 2:
        return math.inf
    if x == math.inf or y == math.inf or z == math.inf:
        return 0.0
    k = _scale_exponent(max(x, y, z), 2.0**1000)
    if k != 0:
        return math.ldexp(
            elliprf(math.ldexp(x, -2 * k), math.ldexp(y, -2 * k), math.ldexp(z, -2 * k)), -k
        )
    a0 = (x + y + z) / 3.0
    q = _RF_Q * max(abs(a0 - x), abs(a0 - y), abs(a0 - z))
    am = a0
    xm = x
    ym = y
    zm = z
    fourn = 1.0
    for _ in range(_MAX_DUP):
        if q < fourn * abs(am):
            break
        sx = math.sqrt(xm)
        sy = math.sqrt(ym)
        sz = math.sqrt(zm)
        lam = sx * (sy + sz) + sy * sz
        am = 0.25 * (am + lam)
        xm = 0.25 * (xm + lam)
        ym = 0.25 * (ym + lam)
        zm = 0.25 * (zm + lam)
        fourn *= 4.0
    # X = (A_n - x_n)/A_n, written without the cancellation in A_n - x_n.
    xx = (a0 - x) / (fourn * am)
    yy = (a0 - y) / (fourn * am)
    zz = -(xx + yy)
    e2 = xx * yy - zz * zz
    e3 = xx * yy * zz
    series = 1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0
    return series / math.sqrt(am)


@njit
def elliprc(x, y):  # type: ignore[no-untyped-def]
    """Carlson's degenerate elliptic integral ``RC(x, y) = RF(x, y, y)``.

    ``RC(x, y) = ½ ∫₀^∞ dt / (√(t + x) (t + y))``, as ``scipy.special.elliprc``
    (DLMF 19.2.17): ``arccos(√(x/y))/√(y-x)`` for ``x < y``,
    ``arccosh(√(x/y))/√(x-y)`` for ``x > y``, ``1/√x`` at ``x = y``.

    Domain ``x >= 0``, ``y != 0``; for ``y < 0`` the Cauchy principal value
    ``√(x/(x-y)) RC(x-y, -y)`` (Carlson 1995, eq. 2.14). ``y = 0`` gives ``inf``
    (the integral diverges), ``x < 0`` NaN. RC is homogeneous of degree -1/2;
    arguments beyond ``2^1000`` or both below ``2^-500`` are first scaled by a
    power of 4.

    Algorithm: Carlson's duplication and series to seventh order (Carlson 1995,
    Algorithm 2, with r = 2^-52), free of the cancellation that the closed forms
    above suffer near ``x = y``. Relative error a few ulp.
    """
    if not x >= 0.0 or y != y:
        return math.nan
    if y == 0.0:
        return math.inf
    if x == math.inf or abs(y) == math.inf:
        return 0.0
    k = _scale_exponent(max(x, abs(y)), 2.0**1000)
    if k != 0:
        return math.ldexp(elliprc(math.ldexp(x, -2 * k), math.ldexp(y, -2 * k)), -k)
    w = 1.0
    if y < 0.0:
        # √x/√(x - y), not √(x/(x - y)), which can be subnormal and lose bits.
        w = math.sqrt(x) / math.sqrt(x - y)
        x, y = x - y, -y
    a0 = (x + 2.0 * y) / 3.0
    q = _RC_Q * abs(a0 - x)
    am = a0
    xm = x
    ym = y
    fourn = 1.0
    for _ in range(_MAX_DUP):
        if q < fourn * abs(am):
            break
        lam = 2.0 * math.sqrt(xm) * math.sqrt(ym) + ym
        am = 0.25 * (am + lam)
        xm = 0.25 * (xm + lam)
        ym = 0.25 * (ym + lam)
        fourn *= 4.0
    s = (y - a0) / (fourn * am)
    series = 1.0 + s * s * (
        3.0 / 10.0
        + s * (1.0 / 7.0 + s * (3.0 / 8.0 + s * (9.0 / 22.0 + s * (159.0 / 208.0 + s * 9.0 / 8.0))))
    )
    return w * series / math.sqrt(am)


@njit
def _rc_one_plus(e, one_plus_e):  # type: ignore[no-untyped-def]
    """``RC(1, 1 + e)`` in closed form, given ``e`` and ``1 + e > 0`` each without cancellation.

    ``arctan(√e)/√e`` for ``e > 0``, ``artanh(√-e)/√-e`` for ``-1 < e < 0``
    (DLMF 19.2.18-19.2.19, as Boost's ``ellint_rc1p``), the latter as
    ``ln((1 + √-e)/√(1 + e))/√-e`` near ``e = -1``. Each step is accurate to an
    ulp or two, and it is several times faster than :func:`elliprc`.
    """
    if e > 0.0:
        s = math.sqrt(e)
        return math.atan(s) / s
    if e == 0.0:
        return 1.0
    s = math.sqrt(-e)
    if e > -0.5:
        return math.atanh(s) / s
    return math.log((1.0 + s) / math.sqrt(one_plus_e)) / s


@njit
def _elliprj_positive(x, y, z, p):  # type: ignore[no-untyped-def]
    """RJ for ``p > 0`` and arguments below ``2^600``; Carlson's Algorithm 3."""
    a0 = (x + y + z + 2.0 * p) / 5.0
    q = _RJ_Q * max(abs(a0 - x), abs(a0 - y), abs(a0 - z), abs(a0 - p))
    am = a0
    xm = x
    ym = y
    zm = z
    pm = p
    # p_n - x_n = (p - x)/4^n, exactly.
    dx = p - x
    dy = p - y
    dz = p - z
    fourn = 1.0
    total = 0.0
    for _ in range(_MAX_DUP):
        if q < fourn * abs(am):
            break
        sx = math.sqrt(xm)
        sy = math.sqrt(ym)
        sz = math.sqrt(zm)
        sp = math.sqrt(pm)
        lam = sx * (sy + sz) + sy * sz
        tx = sp + sx
        ty = sp + sy
        tz = sp + sz
        d = tx * ty * tz
        # Carlson's e_m = 4^-3m (p-x)(p-y)(p-z)/d_m² as a product of three ratios
        # in [-1, 1], and 1 + e_m = 2√p (p + λ)/d_m, both free of overflow and of
        # cancellation: e_m -> -1 when p is much smaller than x, y, z.
        e = (dx / (tx * tx)) * (dy / (ty * ty)) * (dz / (tz * tz))
        one_plus_e = 2.0 * sp * ((pm + lam) / (ty * tz)) / tx
        total += _rc_one_plus(e, one_plus_e) / (fourn * d)
        am = 0.25 * (am + lam)
        xm = 0.25 * (xm + lam)
        ym = 0.25 * (ym + lam)
        zm = 0.25 * (zm + lam)
        pm = 0.25 * (pm + lam)
        dx *= 0.25
        dy *= 0.25
        dz *= 0.25
        fourn *= 4.0
    xx = (a0 - x) / (fourn * am)
    yy = (a0 - y) / (fourn * am)
    zz = (a0 - z) / (fourn * am)
    pp = -0.5 * (xx + yy + zz)
    pp2 = pp * pp
    xyz = xx * yy * zz
    e2 = xx * yy + xx * zz + yy * zz - 3.0 * pp2
    e3 = xyz + 2.0 * e2 * pp + 4.0 * pp2 * pp
    e4 = (2.0 * xyz + e2 * pp + 3.0 * pp2 * pp) * pp
    e5 = xyz * pp2
    series = (
        1.0
        - 3.0 * e2 / 14.0
        + e3 / 6.0
        + 9.0 * e2 * e2 / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0
        + 3.0 * e5 / 26.0
    )
    return series / (fourn * am * math.sqrt(am)) + 6.0 * total


@njit
def elliprj(x, y, z, p):  # type: ignore[no-untyped-def]
    """Carlson's symmetric elliptic integral of the third kind ``RJ(x, y, z, p)``.

    ``RJ(x, y, z, p) = 3/2 ∫₀^∞ dt / ((t + p) √((t + x)(t + y)(t + z)))``, as
    ``scipy.special.elliprj`` (DLMF 19.16.2). For example
    ``Π(n|m) = K(m) + n/3 RJ(0, 1 - m, 1, 1 - n)``.

    Domain ``x, y, z >= 0`` with at most one zero, ``p != 0``. For ``p < 0`` the
    Cauchy principal value, through Carlson's transformation to a positive
    fourth argument (Carlson 1995, eq. 2.22, with z the largest as in Boost's
    ``ellint_rj``). Two zeros among x, y, z, or ``p = 0``: ``inf`` (divergent);
    a negative x, y or z: NaN; an infinite argument: 0. RJ is homogeneous of
    degree -3/2; arguments beyond ``2^600`` or all below ``2^-500`` are first
    scaled by a power of 4.

    Algorithm: Carlson's duplication with the series truncated after the
    fifth-order terms, and the sum of ``RC(1, 1 + e_m)`` terms taken in closed
    form (Carlson 1995, Algorithm 3, with r = 2^-52); ``e_m`` and ``1 + e_m`` are
    formed without cancellation, so ``p`` much smaller than x, y, z loses
    nothing. Relative error a few ulp for ``p > 0``; the principal value is a
    difference of terms and loses what that difference cancels (a few ulp more
    for arguments of comparable size).
    """
    if not (x >= 0.0 and y >= 0.0 and z >= 0.0) or p != p:
        return math.nan
    if (x == 0.0) + (y == 0.0) + (z == 0.0) >= 2 or p == 0.0:
        return math.inf
    if x == math.inf or y == math.inf or z == math.inf or abs(p) == math.inf:
        return 0.0
    if p > 0.0 and max(x, y, z) < _RJ_HUGE_P * p:
        # Far beyond x, y, z, p only enters through 1/(t + p) ≈ 1/p - t/(p(t + p)):
        # RJ = 3 (RF(x, y, z) - π/(2√p))/p with relative error about 2 max(x, y, z)/p
        # (DLMF 19.27.11), below 2^-59 here. The duplication would need ~log4(p/x) steps.
        return 3.0 * (elliprf(x, y, z) - 0.5 * math.pi / math.sqrt(p)) / p
    k = _scale_exponent(max(x, y, z, abs(p)), 2.0**600)
    if k != 0:
        j = -2 * k
        scaled = elliprj(math.ldexp(x, j), math.ldexp(y, j), math.ldexp(z, j), math.ldexp(p, j))
        return math.ldexp(scaled, -3 * k)
    if p > 0.0:
        return _elliprj_positive(x, y, z, p)
    # Principal value: sort so that z is the largest, then move to p' > 0.
    if x > y:
        x, y = y, x
    if y > z:
        y, z = z, y
    if x > y:
        x, y = y, x
    q = -p
    pp = (z * (x + y + q) - x * y) / (z + q)
    value = (pp - z) * _elliprj_positive(x, y, z, pp) - 3.0 * elliprf(x, y, z)
    xy_pq = x * y + pp * q
    value += 3.0 * math.sqrt(x * y * z / xy_pq) * elliprc(xy_pq, pp * q)
    return value / (z + q)
