"""Classical Runge–Kutta, written once for each way a state is held.

:func:`rk4_tuple_step` makes the step of a small state held as a tuple, in registers: the rigid
body (:func:`rk4_step`, the equations of :mod:`tumble.core.dynamics`, the quaternion
renormalised after every step; the loops that run it over one body or a batch are
:mod:`tumble.core.stepping`'s), the gimbal (:mod:`tumble.core.gimbal`) and the
blocks of bodies carrying parts (:mod:`tumble.core.part_blocks`).
:func:`rk4_array_step` steps a state held in an array, its rates given by a compiled
function of the model's: the bodies carrying parts (:mod:`tumble.core.parts`), the
rotor's whirl, the fitted drag; :func:`fixed_step_run` makes a model's compiled run of
many steps from its rates alone. Each is inlined where it is called, with the model's
rates, so a model pays nothing for sharing it (``bench/model_steppers.py``).
"""

from __future__ import annotations

import math
from functools import cache
from typing import Any

import numpy as np
from numba.core.extending import overload

from tumble.core._jit import FINITE, file_stamp, njit, specialise
from tumble.core.dynamics import normalised, rates

__all__ = ["entry_by_entry", "fixed_step_run", "rk4_array_step", "rk4_step", "rk4_tuple_step"]


def rk4_tuple_step(derivatives: Any) -> Any:
    """The classical Runge–Kutta step of a state held as a tuple (n,), kept in
    registers, whose rates are ``derivatives(torque, t, state, coefficients, params,
    column, context)`` (a compiled function returning a tuple (n,)), with the
    arguments of a rigid body's rates (:func:`tumble.core.dynamics.rates`: the
    torque function, the Euler coefficients, the torque's parameters, their column
    and context; a model of its own passes its parameters as ``coefficients`` and
    None for what it does not use): ``step(torque, t, dt, state, coefficients,
    params, column, context)``, the new state after ``dt`` s from time ``t``.

    Made once per model, at import: ``derivatives`` is the step's closure constant,
    so the compiler inlines it where the step is inlined, as it inlines a function
    it calls by name (a function passed as an argument is called, not inlined).
    The arguments go one by one, not held in one tuple, as the rigid body's kernels
    always passed them."""

    @njit(inline="always", cache=False)
    def step(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
        h = 0.5 * dt
        a = derivatives(torque, t, state, coefficients, params, column, context)
        b = derivatives(torque, t + h, _plus(state, h, a), coefficients, params, column, context)
        c = derivatives(torque, t + h, _plus(state, h, b), coefficients, params, column, context)
        d = derivatives(torque, t + dt, _plus(state, dt, c), coefficients, params, column, context)
        return _combined(state, dt / 6.0, a, b, c, d)

    return step


def _plus(state: tuple[float, ...], h: float, slope: tuple[float, ...]) -> tuple[float, ...]:
    """``state + h slope``, entry by entry, of tuples (n,)."""
    return tuple(s + h * k for s, k in zip(state, slope, strict=True))


def _combined(state: Any, sixth: float, a: Any, b: Any, c: Any, d: Any) -> tuple[float, ...]:
    """The RK4 update ``state + (dt/6)(a + 2(b + c) + d)``, entry by entry."""
    return tuple(
        s + sixth * (ka + 2.0 * (kb + kc) + kd)
        for s, ka, kb, kc, kd in zip(state, a, b, c, d, strict=True)
    )


# Compiled, the two above are each tuple's entries written out one by one, for its
# count of entries (a constant of its type): the code the compiler sees is that of
# the rigid body's step as it was written by hand for seven entries, whose batch
# loops it vectorises across bodies (the same results, bit for bit).
@cache
def entry_by_entry(name: str, arguments: str, entry: str, count: int) -> Any:
    """The Python function ``name(arguments)`` that returns the tuple of ``entry``
    (an expression of ``{i}``, the entry's index) for i = 0 … count − 1."""
    entries = ", ".join(entry.format(i=i) for i in range(count))
    namespace: dict[str, Any] = {}
    exec(f"def {name}({arguments}):\n    return ({entries},)\n", namespace)
    return namespace[name]


@overload(_plus, inline="always")
def _compiled_plus(state, h, slope):  # type: ignore[no-untyped-def]
    return entry_by_entry("plus", "state, h, slope", "state[{i}] + h * slope[{i}]", len(state))


@overload(_combined, inline="always")
def _compiled_combined(state, sixth, a, b, c, d):  # type: ignore[no-untyped-def]
    entry = "state[{i}] + sixth * (a[{i}] + 2.0 * (b[{i}] + c[{i}]) + d[{i}])"
    return entry_by_entry("combined", "state, sixth, a, b, c, d", entry, len(state))


_rigid_body_step = rk4_tuple_step(rates)


@njit(inline="always")
def rk4_step(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """One RK4 step of ``dt`` s of a rigid body from ``state`` at time ``t``
    (:func:`rk4_tuple_step` of :func:`tumble.core.dynamics.rates`); the new state,
    its quaternion renormalised."""
    new = _rigid_body_step(torque, t, dt, state, coefficients, params, column, context)
    return normalised(new)


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
