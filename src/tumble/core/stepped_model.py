"""Body rates under any compiled torque function, stepped to given sample times.

The rates a fit of a torque model to measured rates compares with the samples
(:mod:`tumble.identification.torque_fit`): Euler's equations with the torque
function of a bound torque model (:mod:`tumble.core.torques`), stepped by the
classical Runge–Kutta step of :mod:`tumble.core.rk4` from ω(0) at time 0, forwards
to the times after it and backwards to those before, each interval between samples
cut into substeps that turn the body by at most ``most_turn`` rad (the step's error
then lies far below any gyroscope's noise: see :mod:`tumble.core.drag_model`).
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit
from tumble.core.rk4 import rk4_step

__all__ = ["stepped_rates"]


@njit
def stepped_rates(torque, coefficients, params, context, omega0, times, most_turn, most_substeps):  # type: ignore[no-untyped-def]
    """(n, 3) body rates (rad/s, principal axes) at ``times`` (n,) (s, ascending, any
    sign) from ``omega0`` (3,) at time 0, under ``torque`` with its ``params`` column 0
    and ``context``, for the body's Euler ``coefficients``
    (:func:`tumble.core.dynamics.euler_coefficients`); non-finite rates from the first
    interval the call's substeps, ``most_substeps`` a sample in all, do not reach (a
    motion run away)."""
    count = times.shape[0]
    out = np.empty((count, 3))
    first = 0
    while first < count and times[first] < 0.0:
        first += 1
    budget = most_substeps * max(count, 1)  # over the whole call (see the docstring)
    given_up = False
    for forwards in (False, True):
        state = (omega0[0], omega0[1], omega0[2], 1.0, 0.0, 0.0, 0.0)
        now = 0.0
        for k in range(count - first if forwards else first):
            n = first + k if forwards else first - 1 - k
            span = times[n] - now
            speed = math.sqrt(state[0] ** 2 + state[1] ** 2 + state[2] ** 2)
            turn = abs(span) * speed / most_turn
            if given_up or not turn <= budget:
                given_up = True
                out[n] = np.nan
                continue
            substeps = max(1, math.ceil(turn))
            budget -= substeps
            h = span / substeps
            for step in range(substeps):
                state = rk4_step(torque, now + step * h, h, state, coefficients, params, 0, context)
            now = times[n]
            out[n, 0] = state[0]
            out[n, 1] = state[1]
            out[n, 2] = state[2]
    return out
