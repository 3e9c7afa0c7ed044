"""The vectorisable cosine and sine against the C library's (also run with
NUMBA_DISABLE_JIT=1, so the function runs as Python)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tumble.core._jit import njit, njit_vector, prange
from tumble.core.trig import LARGEST_ANGLE, QUARTER_TURN, cos_sin, cos_sin_small, library_cos_sin


@njit
def _in_order(x, c, s):  # type: ignore[no-untyped-def]
    for i in range(x.shape[0]):
        c[i], s[i] = cos_sin(x[i])


@njit_vector
def _vectorised(x, c, s):  # type: ignore[no-untyped-def]
    for i in prange(x.shape[0]):
        c[i], s[i] = cos_sin(x[i])


def _evaluate(kernel, x):  # type: ignore[no-untyped-def]
    c = np.empty_like(x)
    s = np.empty_like(x)
    kernel(x, c, s)
    return c, s


def test_within_two_units_in_the_last_place_of_the_library_on_the_reduced_range() -> None:
    # fdlibm's kernels on [−π/4, π/4], evaluated in order: < 1 ulp each; libm's
    # own result is within 1 ulp of the truth, and the Horner sums round a few
    # times: 2 ulp of the result, measured 1.
    x = np.random.default_rng(1).uniform(-math.pi / 4, math.pi / 4, 20_000)
    c, s = _evaluate(_in_order, x)
    assert np.all(np.abs(c - np.cos(x)) <= 2 * np.spacing(np.abs(np.cos(x))))
    assert np.all(np.abs(s - np.sin(x)) <= 2 * np.spacing(np.abs(np.sin(x))))


@pytest.mark.parametrize("kernel", [_in_order, _vectorised], ids=["in order", "vectorised"])
@pytest.mark.parametrize("largest", [10.0, 1e6, 1e12, LARGEST_ANGLE])
def test_errs_by_less_than_the_rounding_of_the_angle_itself(kernel, largest: float) -> None:
    # Beyond π/4 the reduction by k π/2 decides the error: absolute, at most
    # ulp(x)/2 where the compiler keeps the order of the operations and ulp(x)/4
    # more where it reassociates (vectorised). An angle known to ulp(x) has no
    # better sine: the bound is ulp(largest), measured 0.5. And the pair stays on
    # the unit circle to a few ε (measured 2 ε) at any angle.
    rng = np.random.default_rng(2)
    x = np.concatenate([rng.uniform(-largest, largest, 20_000), [largest, -largest]])
    c, s = _evaluate(kernel, x)
    bound = max(np.spacing(largest), np.spacing(1.0))
    assert np.max(np.abs(c - np.cos(x))) <= bound
    assert np.max(np.abs(s - np.sin(x))) <= bound
    assert np.max(np.abs(c * c + s * s - 1.0)) <= 4 * np.spacing(1.0)


def test_quadrants_at_and_between_the_multiples_of_a_right_angle() -> None:
    # At fl(k π/2) the sine or cosine is the tiny remainder k π/2 − fl(k π/2)
    # (6e-17 for k = 1), which the three-part reduction gets to its third part's
    # precision (measured 2e-31 from libm's); elsewhere 2 ulp as above.
    x = np.array([0.0, math.pi / 2, math.pi, -math.pi / 2, 3 * math.pi / 4, -3 * math.pi / 4])
    c, s = _evaluate(_in_order, x)
    assert_allclose(c, np.cos(x), rtol=4 * np.spacing(1.0), atol=1e-30)
    assert_allclose(s, np.sin(x), rtol=4 * np.spacing(1.0), atol=1e-30)


def test_an_angle_that_is_not_finite_gives_nan() -> None:
    for kernel in (_in_order, _vectorised):
        with np.errstate(invalid="ignore"):  # run as Python (NUMBA_DISABLE_JIT), inf − inf
            c, s = _evaluate(kernel, np.array([math.nan, math.inf, -math.inf]))
        assert np.all(np.isnan(c)) and np.all(np.isnan(s))


@njit
def _library(x, c, s):  # type: ignore[no-untyped-def]
    for i in range(x.shape[0]):
        c[i], s[i] = library_cos_sin(x[i])


def test_the_library_form_gives_the_library_values_and_nan_where_not_finite() -> None:
    # Compiled, the C library's own values; as Python (NUMBA_DISABLE_JIT), math.cos
    # and math.sin, which raise where the C library gives NaN: the same NaN.
    x = np.array([0.0, 0.3, -2.0, 1e6, math.nan, math.inf, -math.inf])
    c, s = _evaluate(_library, x)
    assert c[:4].tolist() == [math.cos(v) for v in x[:4]]
    assert s[:4].tolist() == [math.sin(v) for v in x[:4]]
    assert np.all(np.isnan(c[4:])) and np.all(np.isnan(s[4:]))


@njit
def _small(x, c, s):  # type: ignore[no-untyped-def]
    for i in range(x.shape[0]):
        c[i], s[i] = cos_sin_small(x[i])


def test_the_small_angle_form_gives_the_same_values_within_a_quarter_turn() -> None:
    # Within ±π/4 the reduction is the identity (k = 0): the same polynomials,
    # so the same bits, including at ±π/4 itself.
    x = np.concatenate([np.random.default_rng(3).uniform(-1, 1, 20_000), [-1.0, 1.0]])
    x *= QUARTER_TURN
    general = _evaluate(_in_order, x)
    small = _evaluate(_small, x)
    assert np.array_equal(general[0], small[0]) and np.array_equal(general[1], small[1])
