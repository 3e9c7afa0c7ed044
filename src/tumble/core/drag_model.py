"""The model of measured body rates with air drag that :func:`tumble.identify` fits, compiled.

The body's rates in its principal frame obey Euler's equations with a drag torque
per principal axis, scaled by the largest moment (moments ``(r1, r2, 1)``):

``r_i ω̇_i = −(ω × (r ω))_i − k_i ω_i``          (linear drag, k_i = c_i / I3 in 1/s)
``r_i ω̇_i = −(ω × (r ω))_i − k_i ω_i |ω_i|``    (quadratic drag, k_i = c_i / I3 in 1/rad)

No closed form exists: the rates are stepped with the classical Runge–Kutta method
(:func:`tumble.core.rk4.rk4_array_step`),
each interval between samples cut into substeps that turn the body by at most
:data:`MOST_TURN` rad, where the method's error (≈ (|ω| h)⁵ / 120 a step relative to
|ω|, some 3e-9; over a throw of a few hundred substeps ~1e-6 of |ω|) stays far below
any gyroscope's noise (~1e-3 of |ω| for a phone's). A sample is
``ω_measured(t) = R ω(t) + b`` as in :mod:`tumble.core.rate_model`. The Jacobian is
taken by forward differences in one compiled call
(:func:`tumble.core.rate_model.forward_differences`).
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit
from tumble.core.rate_model import forward_differences, moments_and_axes
from tumble.core.rk4 import rk4_array_step

__all__ = ["MOST_TURN", "drag_jacobian", "drag_rates", "drag_residuals"]

#: The most a substep of the integration turns the body, rad.
MOST_TURN = 0.05

#: The residual of a sample whose motion the model gave up, rad/s.
GIVEN_UP = 1e6

#: The most substeps a sample, over a whole call: beyond it (a trial step of the solver
#: to a drag or a rate no sample shows) the model gives up at once with non-finite
#: rates. 100 substeps a sample turn the body by 5 rad between two samples, ten times
#: more than any recording that resolves its motion shows; trial steps beyond it cost
#: the search seconds of stepping for nothing.
MOST_SUBSTEPS = 100


@njit(inline="always")
def _rates_of_change(t, w, out, model):  # type: ignore[no-untyped-def]
    """ω̇ (3,) of the principal rates ``w`` under drag (see the module); ``model`` is
    ``(moments, drag, quadratic)`` (no time ``t`` enters)."""
    moments, drag, quadratic = model
    l0, l1, l2 = moments[0] * w[0], moments[1] * w[1], moments[2] * w[2]
    gyro0 = w[1] * l2 - w[2] * l1
    gyro1 = w[2] * l0 - w[0] * l2
    gyro2 = w[0] * l1 - w[1] * l0
    if quadratic:
        out[0] = -(gyro0 + drag[0] * w[0] * abs(w[0])) / moments[0]
        out[1] = -(gyro1 + drag[1] * w[1] * abs(w[1])) / moments[1]
        out[2] = -(gyro2 + drag[2] * w[2] * abs(w[2])) / moments[2]
    else:
        out[0] = -(gyro0 + drag[0] * w[0]) / moments[0]
        out[1] = -(gyro1 + drag[1] * w[1]) / moments[1]
        out[2] = -(gyro2 + drag[2] * w[2]) / moments[2]


@njit
def _advance(moments, drag, quadratic, w, span, budget):  # type: ignore[no-untyped-def]
    """Step ``w`` (3,) in place over ``span`` s (either sign) with RK4 substeps
    (:func:`tumble.core.rk4.rk4_array_step`), at most ``budget`` of them; the substeps
    taken."""
    if span == 0.0:
        return 0
    size = math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    # The fastest decay the drag gives, 1/s: RK4 is stable and accurate while a substep
    # lasts well under its time (h λ ≤ 0.5 here, inside RK4's 2.78).
    decay = 0.0
    for i in range(3):
        rate = drag[i] * (abs(w[i]) if quadratic else 1.0) / moments[i]
        decay = max(decay, abs(rate))
    count = max(1.0, math.ceil(abs(span) * max(size / MOST_TURN, 2.0 * decay)))
    if not count <= budget:
        # No motion of the body a fit can match (a solver's trial step far off, to a
        # drag or a rate that no sample shows): the rates are made non-finite at once.
        for i in range(3):
            w[i] = math.nan
        return 0
    h = span / count
    work = np.empty((5, 3))
    model = (moments, drag, quadratic)
    for _ in range(int(count)):
        rk4_array_step(_rates_of_change, 0.0, h, w, work, model)
    return int(count)


@njit
def drag_rates(moments, drag, quadratic, omega0, times):  # type: ignore[no-untyped-def]
    """(n, 3) principal rates (rad/s) at ``times`` (s, ascending, any sign) of the body
    with ``moments`` (3,) and drag coefficients ``drag`` (3,), ω(0) = ``omega0``."""
    count = times.shape[0]
    out = np.empty((count, 3))
    # Times before 0 are stepped backwards from 0, the others forwards.
    first = 0
    while first < count and times[first] < 0.0:
        first += 1
    # The substeps of the whole call are counted against MOST_SUBSTEPS a sample, so a
    # forecast far from its window is stepped, and a solver's trial far off is not.
    budget = MOST_SUBSTEPS * max(count, 1)
    w = omega0.copy()
    now = 0.0
    for n in range(first - 1, -1, -1):
        budget -= _advance(moments, drag, quadratic, w, times[n] - now, budget)
        now = times[n]
        out[n] = w
    w = omega0.copy()
    now = 0.0
    for n in range(first, count):
        budget -= _advance(moments, drag, quadratic, w, times[n] - now, budget)
        now = times[n]
        out[n] = w
    return out


@njit
def drag_residuals(x, frame, times, measured, with_bias, quadratic):  # type: ignore[no-untyped-def]
    """The residuals (3 n,), rad/s, of the drag model of ``measured`` (n, 3) at ``times``
    (n,) (s, from the window's start) with the parameters ``x``: the logarithms of
    I1/I3 and I2/I3, a rotation vector turning ``frame`` into the principal axes, ω(0)
    in those axes, the bias if ``with_bias``, and last the three drag coefficients
    (:func:`drag_rates`). Sample by sample, the model less the measurement."""
    moments, axes = moments_and_axes(x, frame)
    offset = 8
    bias = np.zeros(3)
    if with_bias:
        bias = x[8:11]
        offset = 11
        # No gyroscope reads mostly its own offset (a fit with a bias beyond the rates'
        # median is refused as a unit error): a trial step to a bias beyond every
        # sample is turned back at once. Without it, a body near a sphere, whose ω0
        # trades off against the bias, lets the solver drift to biases of hundreds of
        # rad/s, whose rates take seconds of substeps an evaluation.
        largest = 0.0
        for n in range(measured.shape[0]):
            size = measured[n, 0] ** 2 + measured[n, 1] ** 2 + measured[n, 2] ** 2
            largest = max(largest, size)
        if not bias[0] ** 2 + bias[1] ** 2 + bias[2] ** 2 <= largest:
            return np.full(3 * measured.shape[0], GIVEN_UP)
    rates = drag_rates(moments, x[offset : offset + 3], quadratic, x[5:8].copy(), times)
    out = np.empty(3 * rates.shape[0])
    for n in range(rates.shape[0]):
        for r in range(3):
            model = axes[r, 0] * rates[n, 0] + axes[r, 1] * rates[n, 1] + axes[r, 2] * rates[n, 2]
            out[3 * n + r] = model + bias[r] - measured[n, r]
            if not math.isfinite(out[3 * n + r]):
                # A motion given up (see _advance): a miss far larger than any sample,
                # finite, so that the solver rejects the step rather than failing.
                out[3 * n + r] = GIVEN_UP
    return out


#: The Jacobian of :func:`drag_residuals` (see
#: :func:`tumble.core.rate_model.forward_differences`), each step 1e-7 of its
#: parameter's scale: the stepped model is smooth only to its integration's error
#: (~1e-9 relative, which jumps where a parameter changes the count of substeps), so a
#: longer step than √ε: truncation ~1e-7 and those jumps ~1e-2 of a derivative at worst,
#: far below what the noise leaves of any parameter.
drag_jacobian = forward_differences(drag_residuals, 1e-7)
