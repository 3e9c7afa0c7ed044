"""Classical Runge–Kutta for a rigid body: the step.

The equations are those of :mod:`tumble.core.dynamics`; the quaternion is
renormalised after every step. The loops that run it over one body or a batch
are :mod:`tumble.core.stepping`'s.
"""

from __future__ import annotations

from tumble.core._jit import njit
from tumble.core.dynamics import normalised, rates

__all__ = ["rk4_step"]


@njit(inline="always")
def rk4_step(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """One RK4 step of ``dt`` s from ``state`` at time ``t``; the new state, its
    quaternion renormalised (see :func:`tumble.core.dynamics.rates`)."""
    h = 0.5 * dt
    a = rates(torque, t, state, coefficients, params, column, context)
    b = rates(torque, t + h, _plus(state, h, a), coefficients, params, column, context)
    c = rates(torque, t + h, _plus(state, h, b), coefficients, params, column, context)
    d = rates(torque, t + dt, _plus(state, dt, c), coefficients, params, column, context)
    sixth = dt / 6.0
    return normalised(
        (
            state[0] + sixth * (a[0] + 2.0 * (b[0] + c[0]) + d[0]),
            state[1] + sixth * (a[1] + 2.0 * (b[1] + c[1]) + d[1]),
            state[2] + sixth * (a[2] + 2.0 * (b[2] + c[2]) + d[2]),
            state[3] + sixth * (a[3] + 2.0 * (b[3] + c[3]) + d[3]),
            state[4] + sixth * (a[4] + 2.0 * (b[4] + c[4]) + d[4]),
            state[5] + sixth * (a[5] + 2.0 * (b[5] + c[5]) + d[5]),
            state[6] + sixth * (a[6] + 2.0 * (b[6] + c[6]) + d[6]),
        )
    )


@njit(inline="always")
def _plus(state, h, slope):  # type: ignore[no-untyped-def]
    return (
        state[0] + h * slope[0],
        state[1] + h * slope[1],
        state[2] + h * slope[2],
        state[3] + h * slope[3],
        state[4] + h * slope[4],
        state[5] + h * slope[5],
        state[6] + h * slope[6],
    )
