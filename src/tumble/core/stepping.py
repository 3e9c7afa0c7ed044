"""Loops that step one body, or a batch of bodies, with a one-step scheme.

A *stepper* is a compiled function of the rigid body's state in its principal
frame, ``(ω1, ω2, ω3, q0, q1, q2, q3)`` (:mod:`tumble.core.dynamics`)::

    @njit(inline="always")
    def step(torque, t, dt, state, coefficients, params, column, context):
        ...  # the new state after dt s from time t, its quaternion renormalised

with the body's :func:`~tumble.core.dynamics.euler_coefficients` and the
torque function, its ``params`` column and ``context``
(:mod:`tumble.core.torques`). The factories below build,
for one stepper and one torque, the kernels the integrator registry
(:mod:`tumble.integrators`) takes: one body with recording, batches
vectorised across bodies, and batches measured as they step
(:mod:`tumble.core.metrics`). RK4 (:mod:`tumble.core.rk4`) is such a
stepper, and so are the splittings (:mod:`tumble.core.splitting`); an
integrator whose scheme is one is a step function and a registry entry.

Batches are structures of arrays: ``w`` (3, N) principal-frame angular
velocities, ``q`` (4, N) quaternions (principal → space), ``inertia`` (3, N)
principal moments, ``params`` (rows, M) the packed torque parameters, shared
(M = 1) or one column per body (M = N).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from tumble.core._jit import FINITE, file_stamp, njit, njit_vector, prange, specialise
from tumble.core.dynamics import euler_coefficients, is_finite, record
from tumble.core.metrics import (
    ENERGY_DEVIATION,
    FIRST_FLIP,
    FLIPS,
    MIN_COS,
    MOMENTUM_DEVIATION,
    finish,
    initial,
    observe,
)

__all__ = [
    "BLOCK",
    "METRICS_BLOCK",
    "VELOCITY",
    "Variables",
    "batch_kernel",
    "block_steps",
    "load_block",
    "metrics_kernel",
    "single_kernel",
    "store_block",
]

#: Bodies per block of the batch kernels: a block's state and coefficients stay
#: in L1 cache for all its steps, and the inner loop over the block's bodies is
#: what the compiler vectorises.
BLOCK = 128

#: Bodies per block of the measuring kernels: the measures' 18 arrays come in
#: besides the block's, and at 64 bodies they all stay in L1 cache.
METRICS_BLOCK = 64


class Variables(NamedTuple):
    """The variables a stepper steps, as two compiled functions of ``(state,
    coefficients)``: ``enter`` from ``(ω, q)`` to them and ``leave`` back. The
    loops convert once when they load a body and when they record, store or
    measure it, never between steps, so a stepper of other variables (the
    splittings step ``(L, q)``) accumulates no round-off from the conversions."""

    enter: Any
    leave: Any


@njit(inline="always")
def _unchanged(state, coefficients):  # type: ignore[no-untyped-def]
    return state


#: The stepper steps ``(ω, q)`` itself (RK4).
VELOCITY = Variables(_unchanged, _unchanged)


def _stamp(step: Any, variables: Variables, advance: Any = None) -> str:
    """The stepper's part of a kernel's identity."""
    stamp = file_stamp(step)
    if variables is not VELOCITY:
        stamp += f"|{file_stamp(variables.enter)}|{file_stamp(variables.leave)}"
    if advance is not None:
        stamp += f"|{file_stamp(advance)}"
    return stamp


def single_kernel(step, torque, identity, variables=VELOCITY):  # type: ignore[no-untyped-def]
    """``run(w, q, inertia, params, context, dt, n_steps, first_step, record_every,
    out_w, out_q) -> status``: advance one body's (w, q) in place by ``n_steps``
    steps of ``dt`` s.

    After global step ``first_step + k + 1`` (k = 0 … n_steps − 1), if that
    number is a multiple of ``record_every``, the state is written to row
    ``number // record_every`` of ``out_w`` (·, 3) and ``out_q`` (·, 4). The
    time of global step k is ``k dt``. Returns ``FINITE`` if every step stayed
    finite, else the global number of the first step that did not (the state
    is left as it was before that step). ``variables``: those ``step`` steps.
    """
    enter, leave = variables

    @specialise(njit, f"stepping.single|{_stamp(step, variables)}|{identity}")
    def run(w, q, inertia, params, context, dt, n_steps, first_step, record_every, out_w, out_q):  # type: ignore[no-untyped-def]
        coefficients = euler_coefficients(inertia[0], inertia[1], inertia[2])
        state = enter((w[0], w[1], w[2], q[0], q[1], q[2], q[3]), coefficients)
        status = FINITE
        for k in range(n_steps):
            new = step(torque, (first_step + k) * dt, dt, state, coefficients, params, 0, context)
            if not is_finite(new):
                status = first_step + k + 1
                break
            state = new
            if (first_step + k + 1) % record_every == 0:
                record(first_step + k + 1, record_every, out_w, out_q, leave(state, coefficients))
        final = leave(state, coefficients)
        for i in range(3):
            w[i] = final[i]
        for i in range(4):
            q[i] = final[3 + i]
        return status

    return run


@njit(inline="always")
def _entries(arrays, j):  # type: ignore[no-untyped-def]
    """Entry j of each of a state's 7 arrays, as a tuple."""
    a = arrays
    return (a[0][j], a[1][j], a[2][j], a[3][j], a[4][j], a[5][j], a[6][j])


@njit(inline="always")
def _coefficients(arrays, j):  # type: ignore[no-untyped-def]
    """Entry j of each of the 9 arrays of a block's Euler coefficients."""
    a = arrays
    return (a[0][j], a[1][j], a[2][j], a[3][j], a[4][j], a[5][j], a[6][j], a[7][j], a[8][j])


@njit(inline="always")
def load_block(enter, w, q, inertia, params, start, stop):  # type: ignore[no-untyped-def]
    """The block of bodies ``start:stop`` as its own arrays (they stay in L1 cache
    through its steps): the stepper's variables (``enter`` of ω1, ω2, ω3, q0 …
    q3), the Euler coefficients, and the block's columns of ``params`` (shared
    or per body) as (rows, m)."""
    m = stop - start
    block_params = np.empty((params.shape[0], m))
    shared = params.shape[1] == 1
    for r in range(params.shape[0]):
        for j in range(m):
            block_params[r, j] = params[r, 0] if shared else params[r, start + j]
    coefficients = euler_coefficients(
        inertia[0, start:stop].copy(), inertia[1, start:stop].copy(),
        inertia[2, start:stop].copy(),
    )  # fmt: skip
    state = (
        np.empty(m), np.empty(m), np.empty(m), np.empty(m), np.empty(m), np.empty(m), np.empty(m)
    )  # fmt: skip
    for j in range(m):
        k = start + j
        entered = enter(
            (w[0, k], w[1, k], w[2, k], q[0, k], q[1, k], q[2, k], q[3, k]),
            _coefficients(coefficients, j),
        )  # fmt: skip
        for i in range(7):
            state[i][j] = entered[i]
    return state, coefficients, block_params


@njit(inline="always")
def store_block(leave, w, q, start, state, coefficients):  # type: ignore[no-untyped-def]
    """Write a block's state arrays back into ``w`` (3, N) and ``q`` (4, N), as
    ω and q (``leave``)."""
    for j in range(state[0].shape[0]):
        final = leave(_entries(state, j), _coefficients(coefficients, j))
        for i in range(3):
            w[i, start + j] = final[i]
        for i in range(4):
            q[i, start + j] = final[3 + i]


@njit(inline="always")
def block_steps(step, torque, t0, dt, n_steps, state, coefficients, params, context):  # type: ignore[no-untyped-def]
    """``n_steps`` steps of every body of a block, in place: the state arrays, the
    arrays of the Euler coefficients and the block's ``params`` of
    :func:`load_block`; one body after the other within a step, which the
    compiler vectorises. The batch kernels' default ``advance``."""
    w1, w2, w3, q0, q1, q2, q3 = state
    for k in range(n_steps):
        t = t0 + k * dt
        for j in range(w1.shape[0]):
            new = step(
                torque, t, dt, (w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j]),
                _coefficients(coefficients, j), params, j, context,
            )  # fmt: skip
            w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j] = new


def _advance(step: Any, torque: Any, variables: Variables, chooser: Any) -> tuple[Any, str]:
    """The block advance a batch kernel runs (``chooser(step, torque)``, or
    :func:`block_steps` where it has none) and the stepper's part of the
    kernel's identity."""
    chosen = None if chooser is None else chooser(step, torque)
    stamp = _stamp(step, variables, chosen)
    return (block_steps if chosen is None else chosen), stamp


def batch_kernel(step, torque, identity, variables=VELOCITY, advance=None):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, t0, dt, n_steps, status)``: advance N
    bodies in place by ``n_steps`` steps of ``dt`` s from time ``t0``, in parallel
    over blocks of ``BLOCK`` bodies, vectorised within a block. A body whose
    state became NaN or infinite keeps that state (fast-math may not keep a
    finiteness test inside the loop): the caller checks; ``status`` is left as is.
    ``variables``: those ``step`` steps; ``advance(step, torque)``: for a stepper
    with a faster way for whole blocks, a compiled function of
    :func:`block_steps`'s arguments that steps a block in place, or None
    (:func:`block_steps` itself).
    """
    enter, leave = variables
    advance, stamp = _advance(step, torque, variables, advance)

    @specialise(njit_vector, f"stepping.batch|{stamp}|{identity}")
    def batch(w, q, inertia, params, context, t0, dt, n_steps, status):  # type: ignore[no-untyped-def]
        n = w.shape[1]
        for block in prange((n + BLOCK - 1) // BLOCK):
            start = block * BLOCK
            stop = min(start + BLOCK, n)
            state, coefficients, block_params = load_block(
                enter, w, q, inertia, params, start, stop
            )
            advance(step, torque, t0, dt, n_steps, state, coefficients, block_params, context)
            store_block(leave, w, q, start, state, coefficients)

    return batch


def metrics_kernel(step, torque, identity, variables=VELOCITY, advance=None):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status)``:
    as :func:`batch_kernel`, measuring each body after every step into ``out``
    (``N_METRICS``, N) (see :mod:`tumble.core.metrics`; ``axis`` (3, N) the
    nominal axes)."""
    advance, stamp = _advance(step, torque, variables, advance)

    @specialise(njit_vector, f"stepping.metrics|{stamp}|{identity}")
    def batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status):  # type: ignore[no-untyped-def]
        n = w.shape[1]
        for block in prange((n + METRICS_BLOCK - 1) // METRICS_BLOCK):
            start = block * METRICS_BLOCK
            stop = min(start + METRICS_BLOCK, n)
            _metrics_block(
                step, variables, advance, torque, w, q, inertia, params, context, axis, t0, dt,
                n_steps, out, start, stop,
            )  # fmt: skip

    return batch


@njit(inline="always")
def _metrics_block(  # type: ignore[no-untyped-def]
    step, variables, advance, torque, w, q, inertia, params, context, axis, t0, dt, n_steps, out,
    start, stop,
):  # fmt: skip
    enter, leave = variables
    state, coefficients, block_params = load_block(enter, w, q, inertia, params, start, stop)
    m = stop - start
    # The arrays of the measuring loop are rows of one: the compiler sees they
    # do not overlap and checks nothing at each entry of the loop.
    packed = np.zeros((18, METRICS_BLOCK))
    i1, i2, i3, a1, a2, a3 = packed[0], packed[1], packed[2], packed[3], packed[4], packed[5]
    for j in range(m):
        i1[j] = inertia[0, start + j]
        i2[j] = inertia[1, start + j]
        i3[j] = inertia[2, start + j]
        a1[j] = axis[0, start + j]
        a2[j] = axis[1, start + j]
        a3[j] = axis[2, start + j]
    # The last non-zero a · L before and after a step: the loop reads one and
    # writes the other, and they swap, so at a first flip both are at hand.
    last = packed[6]
    current = packed[7]
    flips = packed[8]
    lowest = packed[9]
    energy0 = packed[10]
    energy_dev = packed[11]
    smallest = packed[12]
    largest = packed[13]
    recorded = packed[14]  # 1 once the body's first flip is recorded
    crossed_at = packed[15]
    before = packed[16]
    after = packed[17]
    squared0 = np.empty(m)
    for j in range(m):
        w1, w2, w3 = w[0, start + j], w[1, start + j], w[2, start + j]
        along, energy, squared, ratio = initial(
            w1, w2, w3, i1[j], i2[j], i3[j], a1[j], a2[j], a3[j]
        )
        last[j] = along
        lowest[j] = ratio
        energy0[j] = energy
        squared0[j] = squared
        smallest[j] = squared
        largest[j] = squared
    for k in range(n_steps):
        advance(step, torque, t0 + k * dt, dt, 1, state, coefficients, block_params, context)
        t = t0 + (k + 1) * dt
        # A loop of its own, storing to six arrays: with the measures in the
        # stepping loop, or the first flip's data stored at every step, the
        # loop stops vectorising or its stores bound its speed. The first
        # flips are recorded apart, in the rare steps that have one.
        firsts = 0
        for j in range(m):
            w1, w2, w3 = leave(_entries(state, j), _coefficients(coefficients, j))[:3]
            first, current[j], flips[j], lowest[j], energy_dev[j], smallest[j], largest[j] = (
                observe(
                    w1, w2, w3, i1[j], i2[j], i3[j], a1[j], a2[j], a3[j], last[j], flips[j],
                    lowest[j], energy0[j], energy_dev[j], smallest[j], largest[j],
                )
            )  # fmt: skip
            firsts += 1 if first else 0
        if firsts > 0:  # at most once a body in a run
            for j in range(m):
                if flips[j] > 0.0 and recorded[j] == 0.0:
                    recorded[j] = 1.0
                    crossed_at[j] = t
                    before[j] = last[j]
                    after[j] = current[j]
        last, current = current, last
    store_block(leave, w, q, start, state, coefficients)
    for j in range(m):
        k = start + j
        (
            out[FLIPS, k], out[FIRST_FLIP, k], out[MIN_COS, k], out[ENERGY_DEVIATION, k],
            out[MOMENTUM_DEVIATION, k],
        ) = finish(
            dt, flips[j], crossed_at[j], before[j], after[j], lowest[j], energy_dev[j],
            squared0[j], smallest[j], largest[j],
        )  # fmt: skip
