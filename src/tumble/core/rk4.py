"""Classical Runge–Kutta: the step of a rigid body, and the step of a model's state
held in an array.

:func:`rk4_step` steps a rigid body's state held as a tuple (the equations of
:mod:`tumble.core.dynamics`; the quaternion renormalised after every step); the
loops that run it over one body or a batch are :mod:`tumble.core.stepping`'s.
:func:`rk4_array_step` steps a state held in an array, its rates given by a compiled
function of the model's (the rotor's whirl, the fitted drag); :func:`fixed_step_run`
makes a model's compiled run of many steps from its rates alone. (The bodies carrying
parts and the gimbal keep steps of their own, measured faster: see
``bench/model_steppers.py``.)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from tumble.core._jit import FINITE, file_stamp, njit, specialise
from tumble.core.dynamics import normalised, rates

__all__ = ["fixed_step_run", "rk4_array_step", "rk4_step"]


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


@njit(inline="always")
def rk4_array_step(derivatives, t, dt, y, work, model):  # type: ignore[no-untyped-def]
    """One classical Runge–Kutta step of ``dt`` s from time ``t``, in place on the state
    ``y`` (n,); ``work`` (5, n) scratch. ``derivatives(t, y, dy, model)`` writes the
    rates of the state ``y`` at time ``t`` into ``dy`` (n,), ``model`` (a tuple) its
    parameters. Inlined where it is called,
    with the model's function, so the compiler sees the whole step."""
    n = y.shape[0]
    half = 0.5 * dt
    k1 = work[0]
    k2 = work[1]
    k3 = work[2]
    k4 = work[3]
    stage = work[4]
    derivatives(t, y, k1, model)
    for i in range(n):
        stage[i] = y[i] + half * k1[i]
    derivatives(t + half, stage, k2, model)
    for i in range(n):
        stage[i] = y[i] + half * k2[i]
    derivatives(t + half, stage, k3, model)
    for i in range(n):
        stage[i] = y[i] + dt * k3[i]
    derivatives(t + dt, stage, k4, model)
    sixth = dt / 6.0
    for i in range(n):
        y[i] += sixth * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i])


def fixed_step_run(derivatives: Any) -> Any:
    """The compiled run of a model whose state (n,) has the rates
    ``derivatives(t, y, dy, model)`` (a compiled function): ``run(y, dt, n_steps,
    first_step, record_every, out, model)`` advances ``y`` in place by ``n_steps``
    steps of :func:`rk4_array_step` of ``dt`` s from the time ``first_step * dt``.

    After global step ``first_step + j + 1`` (j = 0 … n_steps − 1), if that number is
    a multiple of ``record_every``, the state is written to row ``number //
    record_every`` of ``out`` (·, n). Returns ``FINITE`` (−1) if every step stayed
    finite, else the global number of the first step that produced a NaN or an
    infinity (``y`` is left as it was before that step)."""

    @specialise(njit, f"rk4.fixed_step_run|{file_stamp(derivatives)}")
    def run(y, dt, n_steps, first_step, record_every, out, model):  # type: ignore[no-untyped-def]
        n = y.shape[0]
        work = np.empty((5, n))
        before = np.empty(n)
        for j in range(n_steps):
            number = first_step + j
            for i in range(n):
                before[i] = y[i]
            rk4_array_step(derivatives, number * dt, dt, y, work, model)
            total = 0.0
            for i in range(n):
                total += y[i]
            if not math.isfinite(total):
                for i in range(n):
                    y[i] = before[i]
                return number + 1
            if (number + 1) % record_every == 0:
                row = (number + 1) // record_every
                for i in range(n):
                    out[row, i] = y[i]
        return FINITE

    return run
