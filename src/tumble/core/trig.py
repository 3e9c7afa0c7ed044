"""Cosine and sine written out, so that loops over many angles vectorise.

numba compiles ``math.sin`` and ``math.cos`` to calls of the C library, one
angle at a time; it vectorises them only with Intel's SVML, an optional
x86-only runtime that the package index's numba does not bring. The splitting
kernels turn every body of a block by its own angle each step, so they take
:func:`cos_sin`: a few multiply-adds and selects with no call and no branch,
which the compiler turns into SIMD code on any CPU (about 1 ns an angle on one
AVX-512 core, ten times less than the library's pair of calls).

Method (fdlibm's, Sun Microsystems 1993, as in FreeBSD's ``msun``): the angle
x is reduced to r = x − k π/2 with |r| ≤ π/4 by Cody & Waite's three-part
π/2 (the parts' products with k are exact for |k| < 2^20 and fused into
multiply-adds where the compiler contracts), then ``__kernel_sin`` and
``__kernel_cos``'s minimax polynomials on [−π/4, π/4] and the quadrant k mod 4
give sin x and cos x to within 2 units in the last place, and c² + s² = 1 to
a few ε. (Where the compiler may reassociate, as in the vectorised kernels,
the reduction errs by up to ulp(x)/4, within the rounding of x itself.) The
angle must not exceed :data:`LARGEST_ANGLE`: beyond it the reduced angle's
error, about ulp(x), would carry it out of the polynomials' range. The
callers check that bound once for all the angles of a step, not every angle.

One angle at a time, as in the kernels of a single body, the C library is the
faster (its fast path for small angles; measured 10 % on the heavy top's whole
step): :func:`library_cos_sin`.
"""

from __future__ import annotations

import math

import numpy as np
from numba.core.extending import overload

from tumble.core._jit import njit

__all__ = ["LARGEST_ANGLE", "QUARTER_TURN", "cos_sin", "cos_sin_small", "library_cos_sin"]

#: The largest |x| (rad) :func:`cos_sin` evaluates: 2^45, some 5.6e12 turns.
#: (Measured: c² + s² − 1 stays within 2 ε up to 1e15.)
LARGEST_ANGLE = 2.0**45

#: π/4: the largest |x| of :func:`cos_sin_small`.
QUARTER_TURN = 0.78539816339744830962

_TWO_OVER_PI = 0.63661977236758134308
# π/2 in three parts of 33 bits (fdlibm's pio2_1, pio2_2, pio2_3).
_PIO2_1 = 1.57079632673412561417e00
_PIO2_2 = 6.07710050630396597660e-11
_PIO2_3 = 2.02226624871116645580e-21
# fdlibm's __kernel_sin: sin r ≈ r + r³ (S1 + r² (S2 + … )).
_S1 = -1.66666666666666324348e-01
_S2 = 8.33333333332248946124e-03
_S3 = -1.98412698298579493134e-04
_S4 = 2.75573137070700676789e-06
_S5 = -2.50507602534068634195e-08
_S6 = 1.58969099521155010221e-10
# fdlibm's __kernel_cos: cos r ≈ 1 − r²/2 + r⁴ (C1 + r² (C2 + … )).
_C1 = 4.16666666666666019037e-02
_C2 = -1.38888888888741095749e-03
_C3 = 2.48015872894767294178e-05
_C4 = -2.75573143513906633035e-07
_C5 = 2.08757232129817482790e-09
_C6 = -1.13596475577881948265e-11


@njit(inline="always")
def _polynomials(r):  # type: ignore[no-untyped-def]
    """(cos r, sin r) for |r| ≤ π/4: fdlibm's kernels."""
    z = r * r
    sine = r + r * z * (_S1 + z * (_S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))))
    half = 0.5 * z
    cosine = (1.0 - half) + z * z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6)))))
    return cosine, sine


@njit(inline="always")
def cos_sin(x):  # type: ignore[no-untyped-def]
    """``(cos x, sin x)`` of an angle x (rad), |x| ≤ :data:`LARGEST_ANGLE`,
    branch-free so that a loop of them vectorises; NaN for x not finite."""
    k = np.rint(x * _TWO_OVER_PI)
    cosine, sine = _polynomials(((x - k * _PIO2_1) - k * _PIO2_2) - k * _PIO2_3)
    quadrant = k - 4.0 * np.floor(0.25 * k)  # k mod 4, as a float
    odd = (quadrant == 1.0) | (quadrant == 3.0)
    s = cosine if odd else sine
    c = sine if odd else cosine
    s = -s if quadrant >= 2.0 else s
    c = -c if (quadrant == 1.0) | (quadrant == 2.0) else c
    return c, s


@njit(inline="always")
def cos_sin_small(x):  # type: ignore[no-untyped-def]
    """:func:`cos_sin` of an angle known to be within ±:data:`QUARTER_TURN`: the
    same values (there k = 0, r = x) at half the cost, without the reduction."""
    return _polynomials(x)


def library_cos_sin(x):  # type: ignore[no-untyped-def]
    """(cos x, sin x) from the C library: within 1 ulp at any x, and faster than
    :func:`cos_sin` one angle at a time, but calls that a loop cannot vectorise;
    NaN for x not finite, compiled or not (Python's ``math.cos`` raises there)."""
    if not math.isfinite(x):
        return math.nan, math.nan
    return math.cos(x), math.sin(x)


@overload(library_cos_sin, inline="always")
def _compiled_library_cos_sin(x):  # type: ignore[no-untyped-def]
    def library(x):  # type: ignore[no-untyped-def]
        return math.cos(x), math.sin(x)  # NaN for x not finite, as the C library gives

    return library
