"""Oracle tests for the compiled elliptic functions in ``tumble.core.elliptic``.

Three kinds of oracle, each independent of the code under test:

* mpmath at 40+ significant digits (``mpmath.ellipfun``, ``agm``, ``elliprf``,
  ``elliprj``, ``elliprc``): the reference wherever scipy is not accurate. Near
  ``m = 1`` sn, cn, dn come from the Jacobi imaginary transformation
  ``sn(u|m) = -i sn(iu|mc)/cn(iu|mc)``, ``cn(u|m) = 1/cn(iu|mc)``,
  ``dn(u|m) = dn(iu|mc)/cn(iu|mc)`` (DLMF 22.6.12-14), whose theta series in the
  small parameter ``mc`` converge fast, after reducing u to [-K, K] with
  ``sn(u ± 2K) = -sn(u)``; the working precision grows with ``-log10(mc)``, which
  that series needs to resolve terms of relative size ``mc``.
* scipy.special, where it is accurate: ``ellipk``, ``ellipkm1`` and the Carlson
  integrals for arguments of moderate size, ``ellipj`` for ``|u| <= K``,
  ``m <= 0.9``.
* identities that hold exactly: ``sn² + cn² = 1``, ``dn² + m sn² = 1``, the
  derivatives, the half- and quarter-period shifts, ``K(m) = RF(0, 1-m, 1)``,
  Legendre's relation, homogeneity of RF, RC, RJ, and published values.

Tolerances
----------
``sn, cn, dn`` are judged in units of ``eps (|f| + (|ũ| + 2^-48 |u|) |f'(ũ)|)``,
with ``ũ`` the argument reduced to [-2K, 2K]: the first term is the rounding of
the result, the second the rounding of the phase to a double, which reaches the
result through the derivative ``f' = cn dn, -sn dn, -m sn cn``, and the third
the double-double period used to reduce u (it counts only within 2^-48 |u| of a
zero, e.g. at u = float(4K × 100003)).
Measured worst case over ~1500 mpmath comparisons (m and mc over their whole
range, |u| up to 10⁶): 2.3 units. The tests allow ``ELLIPJ_UNITS = 6`` for other
platforms' libm. On the same measure scipy's ``ellipj`` reaches ~30 units at
|u| < 10 and 5e6 units at |u| ~ 10⁶ (it does not reduce u modulo 4K: absolute
error ~1e-10), and ~1e11 units near ``m = 1`` (its ``m > 1 - 1e-9`` branch is a
first-order expansion in ``1 - m`` that fails away from u = 0: at
m = 1 - 2^-50, u = 37 it returns cn = -1.30).

K, RF, RC, RJ are judged in relative ulps (``eps`` = 2^-52): measured worst 2.4
(K), 2.6 (RF), 1.8 (RC), 3.3 (RJ, p > 0).

These tests also run with ``NUMBA_DISABLE_JIT=1``; the mpmath references
dominate their run time, so the mpmath-backed hypothesis tests draw a fixed,
small number of examples.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
import scipy.special as sc
from hypothesis import given, settings
from hypothesis import strategies as st
from mpmath import mpf

from tumble.core.elliptic import (
    ellipj,
    ellipj_mc,
    ellipk,
    ellipk_mc,
    elliprc,
    elliprf,
    elliprj,
)

EPS = 2.0**-52
ELLIPJ_UNITS = 6
K_ULPS = 4
CARLSON_ULPS = 6
# scipy's own measured worst case (ulps) for K and the Carlson integrals at
# moderate arguments; a comparison with scipy allows the sum of both errors.
SCIPY_ULPS = 5

# Named parameters: the ends of the range, m = 1/2, and the approach to m = 1
# (as floats, 1 - 1e-8 and 1 - 1e-15 are 1 - 99999999.39e-16 and 1 - 9.99e-16).
M_VALUES = [0.0, 1e-300, 1e-16, 1e-3, 0.5, 0.9, 1 - 1e-8, 1 - 1e-15]
# Complementary parameters down to the smallest subnormal, for ellipj_mc / ellipk_mc.
MC_VALUES = [1e-8, 1e-15, 2.0**-52, 1e-30, 1e-100, 1e-300, 5e-324]
NAN = math.nan
INF = math.inf


# --------------------------------------------------------------------------
# mpmath references
# --------------------------------------------------------------------------


def _digits_for(mc: float) -> int:
    return 40 + (max(0, -math.floor(math.log10(mc))) if 0 < mc < 0.5 else 0)


def ref_ellipj(u, m=None, mc=None):
    """(sn, cn, dn, ũ, m) as mpf at the float u, for the float parameter m or mc.

    ``m`` or ``mc`` is taken exactly as given; ``ũ`` is u reduced to [-2K, 2K].
    """
    if u == 0:  # mpmath's ellipfun returns sn(0) = ±1e-47 or so, not 0
        return mpf(0), mpf(1), mpf(1), mpf(0), mpf(m if m is not None else 1 - mc)
    small = mc if mc is not None else (1.0 - m if m > 0.5 else 1.0)
    with mpmath.workdps(_digits_for(small)):
        if mc is None:
            big_m = mpf(m)
            big_mc = 1 - big_m  # exact for m >= 1/2; only K needs it otherwise
        else:
            big_mc = mpf(mc)
            big_m = 1 - big_mc  # exact for mc >= 1/2; only the dn scale needs it otherwise
        k = mpmath.pi / (2 * mpmath.agm(1, mpmath.sqrt(big_mc)))
        with mpmath.extradps(20):
            ured = mpf(u) - 4 * k * mpmath.nint(mpf(u) / (4 * k))
            t, sign = ured, 1
            if t > k:
                t, sign = t - 2 * k, -1
            elif t < -k:
                t, sign = t + 2 * k, -1
        if big_mc >= 0.5:
            sn, cn, dn = (mpmath.ellipfun(f, t, m=big_m) for f in ("sn", "cn", "dn"))
        else:
            s, c, d = (mpmath.ellipfun(f, 1j * t, m=big_mc) for f in ("sn", "cn", "dn"))
            sn, cn, dn = (-1j * s / c).real, (1 / c).real, (d / c).real
        return sign * sn, sign * cn, dn, ured, big_m


def ellipj_units(got, u, m=None, mc=None):
    """Errors of (sn, cn, dn) in units of eps (|f| + (|ũ| + 2^-48 |u|) |f'(ũ)|)."""
    sn, cn, dn, ured, big_m = ref_ellipj(u, m=m, mc=mc)
    phase = abs(ured) + 2.0**-48 * abs(u)
    out = []
    for g, f, df in zip(got, (sn, cn, dn), (cn * dn, -sn * dn, -big_m * sn * cn), strict=True):
        error = abs(mpf(float(g)) - f)
        out.append(0.0 if error == 0 else float(error / (EPS * (abs(f) + phase * abs(df)))))
    return out


def assert_ellipj(got, u, m=None, mc=None, units=ELLIPJ_UNITS):
    errors = ellipj_units(got, u, m=m, mc=mc)
    for name, e in zip(("sn", "cn", "dn"), errors, strict=True):
        assert e <= units, (
            f"{name}(u={u!r}, m={m!r}, mc={mc!r}) = {got}: error {e:.1f} > {units} units"
        )


def mp_ellipk_mc(mc):
    return mpmath.pi / (2 * mpmath.agm(1, mpmath.sqrt(mpf(mc))))


def ulps(got, expected):
    """Relative error of a float against an mpf (or float) reference, in units of eps."""
    return float(abs(mpf(float(got)) - expected) / (EPS * abs(expected)))


# --------------------------------------------------------------------------
# K
# --------------------------------------------------------------------------


@pytest.mark.parametrize("m", [*M_VALUES[:-1], -1e-3, -0.5, -7.0, -1e6, 0.999, 1 - 2.0**-40])
def test_ellipk_matches_scipy(m: float) -> None:
    assert ellipk(m) == pytest.approx(sc.ellipk(m), rel=(K_ULPS + SCIPY_ULPS) * EPS, abs=0)


def test_ellipk_mc_matches_scipy_ellipkm1_over_its_whole_range() -> None:
    # scipy's Cephes polynomial for small mc is accurate to ~1 ulp (measured 1.2).
    for mc in [*np.logspace(-320, 300, 311), *MC_VALUES, 1.0, 0.5]:
        assert ellipk_mc(mc) == pytest.approx(
            sc.ellipkm1(mc), rel=(K_ULPS + SCIPY_ULPS) * EPS, abs=0
        ), mc


@pytest.mark.parametrize("mc", [5e-324, 1e-300, 2.0**-1022, 1e-16, 0.25, 3.0, 1e300, 1.7e308])
def test_ellipk_mc_against_mpmath_at_the_extremes(mc: float) -> None:
    with mpmath.workdps(40):
        assert ulps(ellipk_mc(mc), mp_ellipk_mc(mc)) <= K_ULPS


def test_ellipk_mc_follows_the_logarithm_near_m_1() -> None:
    # K = ln(4/√mc) + O(mc ln mc) (DLMF 19.12.1): exact to double precision below 1e-20.
    for mc in [1e-20, 1e-100, 1e-300, 5e-324]:
        assert ellipk_mc(mc) == pytest.approx(math.log(4.0) - 0.5 * math.log(mc), rel=4 * EPS)


def test_ellipk_special_values() -> None:
    assert ellipk(0.0) == pytest.approx(math.pi / 2, rel=EPS, abs=0)
    assert ellipk(1.0) == INF
    assert ellipk_mc(0.0) == INF
    assert ellipk(-INF) == 0.0
    assert ellipk_mc(INF) == 0.0
    assert math.isnan(ellipk(1.5))  # complex for m > 1, as in scipy
    assert math.isnan(ellipk_mc(-1.0))
    assert math.isnan(ellipk(NAN))
    assert math.isnan(ellipk_mc(NAN))


@given(st.floats(0.0, 1.0, exclude_max=True))
def test_ellipk_is_rf_at_0_mc_1(m: float) -> None:
    # AGM and duplication are independent algorithms for the same number.
    assert ellipk(m) == pytest.approx(
        elliprf(0.0, 1.0 - m, 1.0), rel=(K_ULPS + CARLSON_ULPS) * EPS, abs=0
    )


@given(st.floats(0.05, 0.95))
def test_legendre_relation(m: float) -> None:
    # E K' + E' K - K K' = π/2 (DLMF 19.7.1), with E(m) = RF(0, mc, 1) - m/3 RJ(0, mc, 1, 1)
    # (DLMF 19.25.1): ties ellipk to RF and RJ. The three products, each a few ulps
    # off, cancel down to π/2; the tolerance is 16 eps of their total size.
    mc = 1.0 - m
    k, kp = ellipk(m), ellipk(mc)
    e = elliprf(0.0, mc, 1.0) - m / 3.0 * elliprj(0.0, mc, 1.0, 1.0)
    ep = elliprf(0.0, m, 1.0) - mc / 3.0 * elliprj(0.0, m, 1.0, 1.0)
    size = e * kp + ep * k + k * kp
    assert abs(e * kp + ep * k - k * kp - math.pi / 2) <= 16 * EPS * size


# --------------------------------------------------------------------------
# sn, cn, dn against mpmath and scipy
# --------------------------------------------------------------------------


def _u_values(k: float) -> list[float]:
    """Arguments of every size, and the quarter periods where the functions turn."""
    return [
        1e-200, 1e-5, 0.3, -1.0, 7.0, -33.3, 1e3, -1e6, 987654.321,
        0.5 * k, k, -1.5 * k, 2.0 * k, 3.0 * k, 4.0 * k * 100_003,
    ]  # fmt: skip


@pytest.mark.parametrize("m", M_VALUES)
def test_ellipj_against_mpmath_on_a_grid(m: float) -> None:
    for u in _u_values(ellipk(m)):
        assert_ellipj(ellipj(u, m), u, m=m)


@pytest.mark.parametrize("mc", MC_VALUES)
def test_ellipj_mc_against_mpmath_near_m_1(mc: float) -> None:
    k = ellipk_mc(mc)
    for u in [0.3, -4.0, 0.5 * k, k, 1.5 * k, -2.0 * k, 3.7 * k, 1e3, -1e6]:
        assert_ellipj(ellipj_mc(u, mc), u, mc=mc)


@settings(max_examples=40)
@given(st.floats(-1e6, 1e6), st.floats(0.0, 1.0, exclude_max=True))
def test_ellipj_against_mpmath_sampled(u: float, m: float) -> None:
    assert_ellipj(ellipj(u, m), u, m=m)


@settings(max_examples=25)
@given(st.floats(-1e3, 1e3), st.floats(-300.0, 0.0))
def test_ellipj_mc_against_mpmath_sampled(u: float, log10_mc: float) -> None:
    mc = 10.0**log10_mc
    assert_ellipj(ellipj_mc(u, mc), u, mc=mc)


def test_ellipj_reduces_the_phase_exactly_near_a_zero_far_out() -> None:
    # Near u = 4K n, sn is small and mpmath's reference is relative there: the phase
    # of a float u ~ 1e6 has to be reduced with far more than double precision.
    for m in [0.5, 0.99]:
        with mpmath.workdps(40):
            four_k = 4 * mpmath.ellipk(m)
            for n in [1, 12_345, 250_000]:
                u = float(four_k * n) + 3e-9
                sn, _, _, _, _ = ref_ellipj(u, m=m)
                assert ulps(ellipj(u, m)[0], sn) <= ELLIPJ_UNITS


def test_ellipj_matches_scipy_within_a_quarter_period() -> None:
    # Within |u| <= K and m <= 0.9 scipy's sn, cn are within 4e-16 of mpmath and its
    # dn within 1.3e-15 (its dn = cos φ / cos(φ₁ - φ) loses a few ulp); ours are
    # within 3.2e-16 (both measured over 400 samples), hence 2e-15.
    rng = np.random.default_rng(7)
    m = rng.uniform(0.0, 0.9, 200)
    u = rng.uniform(-1.0, 1.0, 200) * sc.ellipk(m)
    expected = np.array(sc.ellipj(u, m)[:3]).T
    got = np.array([ellipj(ui, mi) for ui, mi in zip(u, m, strict=True)])
    np.testing.assert_allclose(got, expected, rtol=0, atol=2e-15)


@pytest.mark.parametrize("m", [-1e-3, -0.5, -3.0, -1e3, 1.0 + 1e-9, 1.5, 4.0, 1e3])
def test_ellipj_outside_0_1_against_mpmath(m: float) -> None:
    # m < 0 and m > 1 go through the modulus transformations (A&S 16.10, 16.11).
    for u in [-4.1, -0.7, 0.2, 1.3, 3.9]:
        with mpmath.workdps(40):
            ref = [mpmath.ellipfun(f, mpf(u), m=mpf(m)) for f in ("sn", "cn", "dn")]
            sn, cn, dn = ref
            derivative = (cn * dn, -sn * dn, -m * sn * cn)
            for g, f, df in zip(ellipj(u, m), ref, derivative, strict=True):
                assert abs(mpf(g) - f) <= ELLIPJ_UNITS * EPS * (abs(f) + abs(u * df)), (u, m)


# --------------------------------------------------------------------------
# sn, cn, dn: identities and limits
# --------------------------------------------------------------------------


@given(st.floats(-1e6, 1e6), st.floats(0.0, 1.0))
def test_pythagorean_identities(u: float, m: float) -> None:
    sn, cn, dn = ellipj(u, m)
    assert abs(sn * sn + cn * cn - 1.0) <= 4 * EPS
    assert abs(dn * dn + m * sn * sn - 1.0) <= 4 * EPS
    assert -1.0 <= sn <= 1.0
    assert -1.0 <= cn <= 1.0
    assert 0.0 <= dn <= 1.0


@given(st.floats(0.0, 1.0), st.floats(-300.0, 0.0))
def test_dn_keeps_relative_accuracy_near_m_1(fraction: float, log10_mc: float) -> None:
    # dn² - m cn² = mc (DLMF 22.6.1) taken relative to its terms: when mc is tiny
    # and u near K, dn ~ √mc, and an absolute error of eps in dn (as from
    # √(mc + m cn²) with an absolute-accurate cn) would break it by many orders.
    # With the per-function bound U eps (|f| + |u f'|), |m sn cn| <= dn and
    # |cn| <= dn, the identity holds to (2U(1 + 2|u|) + 4) eps of dn² + m cn² + mc.
    mc = 10.0**log10_mc
    m = 1.0 - mc
    u = fraction * ellipk_mc(mc)
    _, cn, dn = ellipj_mc(u, mc)
    size = dn * dn + m * cn * cn + mc
    bound = (2 * ELLIPJ_UNITS * (1 + 2 * u) + 4) * EPS * size
    assert abs(dn * dn - m * cn * cn - mc) <= bound


@pytest.mark.parametrize("mc", [*MC_VALUES, 0.01, 0.5, 1.0])
def test_values_at_the_quarter_period(mc: float) -> None:
    # sn(K) = 1, cn(K) = 0, dn(K) = √mc (DLMF 22.5.2). The float K is off by
    # δ <= 3 ulp(K), which moves sn by O(δ²), cn by √mc δ, dn by √mc O(δ²).
    k = ellipk_mc(mc)
    sn, cn, dn = ellipj_mc(k, mc)
    assert sn == pytest.approx(1.0, abs=4 * EPS)
    assert abs(cn) <= 4 * EPS * k * math.sqrt(mc) + 4 * EPS * math.sqrt(mc)
    assert dn == pytest.approx(math.sqrt(mc), rel=ELLIPJ_UNITS * EPS)


@given(st.floats(-4.0, 4.0), st.floats(0.0, 1.0, exclude_max=True))
def test_half_period_shift(t: float, m: float) -> None:
    # sn(u + 2K) = -sn(u), cn(u + 2K) = -cn(u), dn(u + 2K) = dn(u) (DLMF 22.4.3).
    # Both sides carry the per-function bound, and the shifted argument also the
    # rounding of u + 2K and of K (3 ulp), all through the derivative (|f'| <= 1).
    k = ellipk(m)
    u = t * k
    shifted = ellipj(u + 2.0 * k, m)
    base = ellipj(u, m)
    for a, b, sign in zip(shifted, base, (-1.0, -1.0, 1.0), strict=True):
        bound = (2 * ELLIPJ_UNITS + 8) * EPS * (abs(b) + abs(u) + 2 * k)
        assert abs(a - sign * b) <= bound


@given(st.floats(-1.0, 1.0), st.floats(-300.0, 0.0))
def test_quarter_period_shift_of_dn(t: float, log10_mc: float) -> None:
    # dn(u + K) dn(u) = √mc (DLMF 22.4.3), relative: dn's relative error is at
    # most U eps (1 + |u|) (since |m sn cn| <= dn), and the rounding of u + K and
    # of K moves dn(u + K) by at most 4 eps (|u| + K) relative (|dn'/dn| <= 1).
    mc = 10.0**log10_mc
    k = ellipk_mc(mc)
    u = t * k
    product = ellipj_mc(u + k, mc)[2] * ellipj_mc(u, mc)[2]
    r = abs(u) + k
    bound = (ELLIPJ_UNITS * (2 + abs(u) + r) + 4 * r + 2) * EPS
    assert product == pytest.approx(math.sqrt(mc), rel=bound)


@given(st.floats(-6.0, 6.0), st.floats(0.0, 1.0 - 1e-6))
def test_derivatives_by_finite_differences(u: float, m: float) -> None:
    # d sn/du = cn dn, d cn/du = -sn dn, d dn/du = -m sn cn (DLMF 22.13.1-3), by the
    # five-point stencil with h = 1e-3: truncation h⁴/30 |f⁽⁵⁾| < 1e-12 (|f⁽⁵⁾| < 50
    # for m <= 1) plus rounding 1.5 eps/h < 4e-13, hence 1e-10.
    h = 1e-3
    points = [np.array(ellipj(u + k * h, m)) for k in (-2, -1, 1, 2)]
    derivative = (points[0] - 8 * points[1] + 8 * points[2] - points[3]) / (12 * h)
    sn, cn, dn = ellipj(u, m)
    np.testing.assert_allclose(derivative, [cn * dn, -sn * dn, -m * sn * cn], rtol=0, atol=1e-10)


@given(st.floats(-1e6, 1e6), st.floats(0.5, 1.0))
def test_parameter_and_complement_agree_exactly(u: float, m: float) -> None:
    # For m >= 1/2, 1 - m is exact, so both entry points see the same parameter.
    assert ellipj(u, m) == ellipj_mc(u, 1.0 - m)


@given(st.floats(-700.0, 700.0))
def test_limits_m_0_and_m_1(u: float) -> None:
    assert ellipj(u, 0.0) == (math.sin(u), math.cos(u), 1.0)
    sech = 1.0 / math.cosh(u)
    assert ellipj(u, 1.0) == (math.tanh(u), sech, sech)
    assert ellipj_mc(u, 0.0) == (math.tanh(u), sech, sech)


@given(st.floats(-5.0, 5.0))
def test_tiny_mc_approaches_the_m_1_limit(u: float) -> None:
    # sn(u|m) = tanh u + O(mc cosh² u) (DLMF 22.10.8): below double precision here.
    sech = 1.0 / math.cosh(u)
    sn, cn, dn = ellipj_mc(u, 1e-300)
    assert sn == pytest.approx(math.tanh(u), rel=4 * EPS, abs=4 * EPS)
    assert cn == pytest.approx(sech, rel=(4 + 2 * abs(u)) * EPS)
    assert dn == pytest.approx(sech, rel=(4 + 2 * abs(u)) * EPS)


@pytest.mark.parametrize(
    ("u", "m", "expected"),
    [
        (0.0, 0.5, (0.0, 1.0, 1.0)),
        (-0.0, 0.5, (-0.0, 1.0, 1.0)),
        (1e-310, 0.7, (1e-310, 1.0, 1.0)),
        (INF, 1.0, (1.0, 0.0, 0.0)),  # the limits of tanh and sech
        (-INF, 0.0, (NAN, NAN, 1.0)),  # dn = 1 for every u at m = 0
        (NAN, 0.5, (NAN, NAN, NAN)),
        (INF, 0.5, (NAN, NAN, NAN)),  # no limit at infinity
        (-INF, 0.99, (NAN, NAN, NAN)),
        (1.0, NAN, (NAN, NAN, NAN)),
    ],
)
def test_ellipj_special_values(u: float, m: float, expected: tuple[float, float, float]) -> None:
    got = ellipj(u, m)
    for g, e in zip(got, expected, strict=True):
        if math.isnan(e):
            assert math.isnan(g)
        else:
            assert g == e
            assert math.copysign(1.0, g) == math.copysign(1.0, e)


def test_ellipj_stays_on_the_circle_for_huge_u() -> None:
    # Past |u| ~ 2^53 K the phase is meaningless, but the results are still values
    # of sn, cn, dn at some argument: finite and on both circles.
    for u in [1e20, -3e150, 1e300, 1.7e308]:
        sn, cn, dn = ellipj(u, 0.5)
        assert abs(sn * sn + cn * cn - 1.0) <= 4 * EPS
        assert abs(dn * dn + 0.5 * sn * sn - 1.0) <= 4 * EPS


# --------------------------------------------------------------------------
# Carlson's integrals
# --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("got", "expected"),
    [
        # Carlson (1995), section 3: test values given to 14 digits.
        (lambda: elliprf(1.0, 2.0, 0.0), 1.3110287771461),
        (lambda: elliprf(2.0, 3.0, 4.0), 0.58408284167715),
        (lambda: elliprc(0.0, 0.25), math.pi),
        (lambda: elliprc(2.25, 2.0), math.log(2.0)),
        (lambda: elliprc(0.25, -2.0), math.log(2.0) / 3.0),  # principal value
        (lambda: elliprj(0.0, 1.0, 2.0, 3.0), 0.77688623778582),
        (lambda: elliprj(2.0, 3.0, 4.0, 5.0), 0.14297579667157),
        (lambda: elliprj(2.0, 3.0, 4.0, -0.5), 0.24723819703052),  # principal value
        (lambda: elliprj(2.0, 3.0, 4.0, -5.0), -0.12711230042964),  # principal value
    ],
)
def test_carlson_published_values(got, expected: float) -> None:
    assert got() == pytest.approx(expected, rel=5e-14, abs=0)


# Not subnormal: scipy's RC(5e-324, -2) is 0, the principal value 1.1e-162.
moderate = st.one_of(st.just(0.0), st.floats(1e-300, 4.0))
positive = st.floats(1e-3, 4.0)


@given(moderate, positive, positive)
def test_elliprf_matches_scipy(x: float, y: float, z: float) -> None:
    assert elliprf(x, y, z) == pytest.approx(
        sc.elliprf(x, y, z), rel=(CARLSON_ULPS + SCIPY_ULPS) * EPS, abs=0
    )


@given(moderate, st.floats(-4.0, 4.0).filter(lambda y: abs(y) > 1e-3))
def test_elliprc_matches_scipy(x: float, y: float) -> None:
    assert elliprc(x, y) == pytest.approx(
        sc.elliprc(x, y), rel=(CARLSON_ULPS + SCIPY_ULPS) * EPS, abs=0
    )


@given(moderate, positive, positive, positive)
def test_elliprj_matches_scipy(x: float, y: float, z: float, p: float) -> None:
    assert elliprj(x, y, z, p) == pytest.approx(
        sc.elliprj(x, y, z, p), rel=(CARLSON_ULPS + SCIPY_ULPS) * EPS, abs=0
    )


def _spread(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi).map(lambda e: 10.0**e)


def _assert_carlson_against_mpmath(ours: float, reference) -> None:
    # 120 digits: at 40, mpmath's own RJ is wrong for arguments 1e180 apart.
    if mpf(2) ** -1022 < abs(reference) < mpf(2) ** 1024:  # the result is a normal double
        assert ulps(ours, reference) <= CARLSON_ULPS


@settings(max_examples=30)
@given(_spread(-300, 300), _spread(-300, 300), _spread(-300, 300))
def test_elliprf_against_mpmath_over_the_whole_range(x: float, y: float, z: float) -> None:
    with mpmath.workdps(120):
        _assert_carlson_against_mpmath(elliprf(x, y, z), mpmath.elliprf(x, y, z))


@settings(max_examples=30)
@given(_spread(-300, 300), _spread(-300, 300))
def test_elliprc_against_mpmath_over_the_whole_range(x: float, y: float) -> None:
    with mpmath.workdps(60):
        _assert_carlson_against_mpmath(elliprc(x, y), mpmath.elliprc(x, y))
        _assert_carlson_against_mpmath(elliprc(x, -y), mpmath.elliprc(x, -y, pv=True))


@settings(max_examples=30)
@given(_spread(-100, 100), _spread(-100, 100), _spread(-100, 100), _spread(-100, 100))
def test_elliprj_against_mpmath_over_a_wide_range(x: float, y: float, z: float, p: float) -> None:
    with mpmath.workdps(120):
        _assert_carlson_against_mpmath(elliprj(x, y, z, p), mpmath.elliprj(x, y, z, p))


@settings(max_examples=30)
@given(_spread(-3, 3), _spread(-3, 3), _spread(-3, 3), _spread(-40, 40))
def test_elliprj_with_p_far_from_x_y_z(x: float, y: float, z: float, p: float) -> None:
    # p << x, y, z puts e_m near -1 (scipy loses up to 4000 ulp there); p >> x, y, z
    # crosses into the asymptotic form at max(x, y, z) = 2^-60 p.
    with mpmath.workdps(60):
        _assert_carlson_against_mpmath(elliprj(x, y, z, p), mpmath.elliprj(x, y, z, p))


def _principal_value_terms(x, y, z, p):
    """RJ(x, y, z, p < 0) and the size of the terms it is a difference of, in mpmath.

    Carlson (1995, eq. 2.22) with z the largest:
    ``RJ = ((p'-z) RJ(p') - 3 RF + 3 √(xyz/(xy+p'q)) RC(xy+p'q, p'q)) / (z - p)``.
    """
    a, b, c = (mpf(v) for v in sorted((x, y, z)))
    q = -mpf(p)
    pp = (c * (a + b + q) - a * b) / (c + q)
    terms = (
        (pp - c) * mpmath.elliprj(a, b, c, pp),
        -3 * mpmath.elliprf(a, b, c),
        3 * mpmath.sqrt(a * b * c / (a * b + pp * q)) * mpmath.elliprc(a * b + pp * q, pp * q),
    )
    return sum(terms) / (c + q), sum(abs(t) for t in terms) / (c + q)


@pytest.mark.parametrize(
    "args",
    [(0.3, 1.1, 2.5, -0.7), (1.9, 1.3, 0.09, -0.2), (0.01, 2.0, 3.0, -1.5), (1.0, 1.0, 1.0, -3.9)],
)
def test_principal_value_formula_against_mpmath(args) -> None:
    # mpmath's RJ is complex for p < 0, with the principal value as its real part
    # (and takes ~0.3 s a value, 2 s with x = 0): it checks the transformation itself.
    with mpmath.workdps(40):
        value, _ = _principal_value_terms(*args)
        assert abs(value - mpmath.re(mpmath.elliprj(*args))) < mpf(10) ** -30
        assert ulps(elliprj(*args), value) <= 4 * CARLSON_ULPS


@given(moderate, positive, positive, st.floats(-4.0, -1e-3))
def test_elliprj_principal_value(x: float, y: float, z: float, p: float) -> None:
    # The principal value is a difference, which may cancel: each term carries a
    # few ulps, so the bound is 2 CARLSON_ULPS eps of the sum of their magnitudes.
    # (Measured: up to 14 ulp of the result at moderate arguments, 80 when the
    # terms cancel hard; scipy, by the same formula, 19 and 67.)
    with mpmath.workdps(40):
        value, size = _principal_value_terms(x, y, z, p)
        assert abs(mpf(elliprj(x, y, z, p)) - value) <= 2 * CARLSON_ULPS * EPS * size


@given(moderate, positive, positive, positive, st.integers(-300, 300))
def test_homogeneity_is_exact(x: float, y: float, z: float, p: float, k: int) -> None:
    # RF, RC scale as λ^(-1/2), RJ as λ^(-3/2) (DLMF 19.20.1); with λ a power of 4
    # every step of the algorithms scales exactly, including across the internal
    # rescaling of very large and very small arguments.
    f = 4.0**k
    assert elliprf(x * f, y * f, z * f) == math.ldexp(elliprf(x, y, z), -k)
    assert elliprc(x * f, y * f) == math.ldexp(elliprc(x, y), -k)
    if k <= 200:  # RJ(λ·) ~ λ^(-3/2) stays a normal double
        assert elliprj(x * f, y * f, z * f, p * f) == math.ldexp(elliprj(x, y, z, p), -3 * k)


@given(positive, positive)
def test_rc_is_rf_with_two_equal_arguments(x: float, y: float) -> None:
    assert elliprc(x, y) == pytest.approx(elliprf(x, y, y), rel=2 * CARLSON_ULPS * EPS, abs=0)


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (lambda: elliprf(0.0, 0.0, 1.0), INF),  # two zeros: divergent
        (lambda: elliprf(0.0, 1.0, INF), 0.0),
        (lambda: elliprf(-1.0, 1.0, 1.0), NAN),
        (lambda: elliprf(NAN, 1.0, 1.0), NAN),
        (lambda: elliprc(1.0, 0.0), INF),
        (lambda: elliprc(0.0, -1.0), 0.0),  # principal value
        (lambda: elliprc(INF, 1.0), 0.0),
        (lambda: elliprc(-1.0, 1.0), NAN),
        (lambda: elliprc(1.0, NAN), NAN),
        (lambda: elliprj(0.0, 1.0, 2.0, 0.0), INF),  # p = 0: divergent
        (lambda: elliprj(0.0, 0.0, 2.0, 1.0), INF),
        (lambda: elliprj(1.0, 2.0, 3.0, INF), 0.0),
        (lambda: elliprj(1.0, 2.0, 3.0, -INF), 0.0),
        (lambda: elliprj(-1.0, 2.0, 3.0, 1.0), NAN),
        (lambda: elliprj(1.0, 2.0, 3.0, NAN), NAN),
    ],
)
def test_carlson_domain(value, expected: float) -> None:
    got = value()
    if math.isnan(expected):
        assert math.isnan(got)
    else:
        assert got == expected


def test_carlson_extreme_arguments() -> None:
    # Subnormal and near-overflow arguments are rescaled, not lost.
    with mpmath.workdps(40):
        for args in [(1e-320, 1e-320, 1e-320), (1.7e308, 1.7e308, 1.7e308), (5e-324, 1.0, 1.7e308)]:
            assert ulps(elliprf(*args), mpmath.elliprf(*args)) <= CARLSON_ULPS
        for args in [(5e-324, 5e-324), (1.7e308, 1e-300), (1e-310, 3e-310)]:
            assert ulps(elliprc(*args), mpmath.elliprc(*args)) <= CARLSON_ULPS
        for args in [(5e-324, -2.0), (1e-168, -1e142), (1.7e308, -1.7e308)]:
            assert ulps(elliprc(*args), mpmath.elliprc(*args, pv=True)) <= CARLSON_ULPS
        for args in [
            (5e-324, 5e-324, 1.0, 1.0),
            (1.7e308, 1.0, 1.0, 1.0),
            (1.0, 1.0, 1.0, 1.7e308),
        ]:
            assert ulps(elliprj(*args), mpmath.elliprj(*args)) <= CARLSON_ULPS
