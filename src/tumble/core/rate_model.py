"""The model of measured body rates that :func:`tumble.identify` fits, compiled.

A sample is ``ω_measured(t) = R ω(t) + b``: ω(t) the exact torque-free angular
velocity in the principal frame (:func:`tumble.core.freebody.free_omega`), R
the principal axes as columns in the sensor's axes, b the sensor's bias. The
least squares evaluate it hundreds of thousands of times, mostly for a few
hundred samples, where numpy and scipy's per-call costs (a rotation built from
its vector, the sorting of the moments, the products) took five times as long
as the motion itself (measured: 90 µs an evaluation, of which 13 µs the
elliptic functions); here one call does it all.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from tumble.core._jit import file_stamp, njit, specialise
from tumble.core.freebody import free_omega

__all__ = [
    "forward_differences",
    "moments_and_axes",
    "principal_rates",
    "rate_jacobian",
    "rate_residuals",
    "rotation_matrix",
]

#: The largest exponent of a fitted moment ratio: a step of the solver far off
#: must not overflow (e^±60 is no body).
LARGEST_EXPONENT = 60.0


@njit
def rotation_matrix(rotation_vector):  # type: ignore[no-untyped-def]
    """The rotation matrix (3, 3) of a rotation vector (rad): a turn by its norm
    about its direction. By the unit quaternion (cos θ/2, sin θ/2 n), as scipy's
    ``Rotation.from_rotvec``, with sin(θ/2)/θ from its Taylor series below
    θ = 1e-3, where the division would lose digits."""
    x, y, z = rotation_vector[0], rotation_vector[1], rotation_vector[2]
    angle = math.sqrt(x * x + y * y + z * z)
    if angle <= 1e-3:
        squared = angle * angle
        scale = 0.5 - squared / 48.0 + squared * squared / 3840.0
    else:
        scale = math.sin(0.5 * angle) / angle
    w, a, b, c = math.cos(0.5 * angle), scale * x, scale * y, scale * z
    out = np.empty((3, 3))
    out[0, 0] = w * w + a * a - b * b - c * c
    out[0, 1] = 2.0 * (a * b - c * w)
    out[0, 2] = 2.0 * (a * c + b * w)
    out[1, 0] = 2.0 * (a * b + c * w)
    out[1, 1] = w * w - a * a + b * b - c * c
    out[1, 2] = 2.0 * (b * c - a * w)
    out[2, 0] = 2.0 * (a * c - b * w)
    out[2, 1] = 2.0 * (b * c + a * w)
    out[2, 2] = w * w - a * a - b * b + c * c
    return out


@njit
def principal_rates(moments, omega0, times):  # type: ignore[no-untyped-def]
    """(n, 3) exact torque-free ω(t) (rad/s) in the principal frame for moments
    (3,) in any order (all > 0), ω(0) = ``omega0`` (rad/s), at ``times`` (s).

    The exact solution takes ascending moments; a permutation P of the axes (a
    reflection when odd) maps the motion to ``det(P) P ω``, which obeys the same
    Euler equations for the permuted moments, so the motion is solved sorted
    and mapped back. Equal moments keep their order (a stable sort)."""
    order = np.arange(3)
    for i in range(1, 3):  # insertion sort: stable
        j = i
        while j > 0 and moments[order[j - 1]] > moments[order[j]]:
            order[j - 1], order[j] = order[j], order[j - 1]
            j -= 1
    # The even permutations of three are the rotations of (0, 1, 2).
    sign = 1.0 if (order[1] - order[0]) % 3 == 1 and (order[2] - order[1]) % 3 == 1 else -1.0
    sorted_moments = np.empty(3)
    sorted_omega = np.empty(3)
    for k in range(3):
        sorted_moments[k] = moments[order[k]]
        sorted_omega[k] = sign * omega0[order[k]]
    solved = free_omega(sorted_moments, sorted_omega, times)
    out = np.empty_like(solved)
    for n in range(solved.shape[0]):
        for k in range(3):
            out[n, order[k]] = sign * solved[n, k]
    return out


@njit
def moments_and_axes(x, frame):  # type: ignore[no-untyped-def]
    """The moments (I1/I3, I2/I3, 1) and principal axes (3, 3), columns in the
    sensor's axes, of the parameters ``x`` (see :func:`rate_residuals`): the
    logarithms of the ratios clipped to ±:data:`LARGEST_EXPONENT`, ``frame``
    (3, 3) turned by the rotation vector ``x[2:5]``."""
    moments = np.array(
        [
            math.exp(min(max(x[0], -LARGEST_EXPONENT), LARGEST_EXPONENT)),
            math.exp(min(max(x[1], -LARGEST_EXPONENT), LARGEST_EXPONENT)),
            1.0,
        ]
    )
    turn = rotation_matrix(x[2:5])
    axes = np.empty((3, 3))
    for r in range(3):
        for c in range(3):
            axes[r, c] = (
                frame[r, 0] * turn[0, c] + frame[r, 1] * turn[1, c] + frame[r, 2] * turn[2, c]
            )
    return moments, axes


@njit
def rate_residuals(x, frame, times, measured, with_bias):  # type: ignore[no-untyped-def]
    """The residuals (3 n,), rad/s, of the model of ``measured`` (n, 3) rates at
    ``times`` (n,) (s) with the parameters ``x``: the logarithms of I1/I3 and
    I2/I3, a rotation vector turning the axes ``frame`` (3, 3) into the
    principal axes (:func:`moments_and_axes`), ω(0) in those axes, and, if
    ``with_bias``, the bias. Sample by sample, the model less the measurement
    (the row-major flattening of their (n, 3) difference)."""
    moments, axes = moments_and_axes(x, frame)
    rates = principal_rates(moments, x[5:8], times)
    out = np.empty(3 * rates.shape[0])
    for n in range(rates.shape[0]):
        for r in range(3):
            model = axes[r, 0] * rates[n, 0] + axes[r, 1] * rates[n, 1] + axes[r, 2] * rates[n, 2]
            if with_bias:
                model += x[8 + r]
            out[3 * n + r] = model - measured[n, r]
    return out


def forward_differences(residuals: Any, relative_step: float) -> Any:
    """The compiled Jacobian ``(3 n, len(x))`` of a compiled model of measured rates
    ``residuals(x, frame, times, measured, with_bias, *model)`` (the parameters laid out
    as :func:`rate_residuals`'s: ω0 at 5–7, the bias at 8–10 when fitted, any others
    after), by forward differences in one call: the least squares would otherwise call
    the model once a parameter, each call costing more in the solver than in the model.

    Each step is ``relative_step`` of its parameter's scale (the logarithms, the rotation
    and any torque's parameters: 1; the rates and the bias: |ω0|)."""

    @specialise(njit, f"rate_model.forward_differences|{file_stamp(residuals)}|{relative_step!r}")
    def jacobian(x, frame, times, measured, with_bias, *model):  # type: ignore[no-untyped-def]
        rate_scale = max(math.sqrt(x[5] * x[5] + x[6] * x[6] + x[7] * x[7]), 1e-12)
        here = residuals(x, frame, times, measured, with_bias, *model)
        out = np.empty((here.shape[0], x.shape[0]))
        shifted = x.copy()
        for j in range(x.shape[0]):
            scale = rate_scale if 5 <= j < 8 or (with_bias and 8 <= j < 11) else 1.0
            step = relative_step * max(abs(x[j]), scale)
            shifted[j] = x[j] + step
            forward = residuals(shifted, frame, times, measured, with_bias, *model)
            shifted[j] = x[j]
            for i in range(out.shape[0]):
                out[i, j] = (forward[i] - here[i]) / step
        return out

    return jacobian


#: The Jacobian of :func:`rate_residuals` (see :func:`forward_differences`): the exact
#: model is smooth to round-off, so the step is √ε ≈ 1.5e-8 (scipy's own for forward
#: differences), which balances truncation and round-off at ~1e-8 relative; a
#: direction the recording does not determine shows as a singular value far below it.
rate_jacobian = forward_differences(rate_residuals, 1.4901161193847656e-08)
