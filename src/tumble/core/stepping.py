"""Loops that step one body, or a batch of bodies, with a one-step scheme.

A *stepper* is a compiled function of the rigid body's state in its principal
frame, ``(ω1, ω2, ω3, q0, q1, q2, q3)`` (:mod:`tumble.core.dynamics`)::

    @njit(inline="always")
    def step(torque, t, dt, state, coefficients, params, column, context):
        ...  # the new state after dt s from time t, its quaternion renormalised

with the body's Euler coefficients and the torque function, its ``params``
column and ``context`` (:mod:`tumble.core.torques`). The factories below build,
for one stepper and one torque, the kernels the integrator registry
(:mod:`tumble.integrators`) takes: one body with recording, batches
vectorised across bodies, and batches measured as they step
(:mod:`tumble.core.metrics`). RK4 (:mod:`tumble.core.rk4`) is such a
stepper; an integrator whose scheme is one is a step function and a registry
entry.

Batches are structures of arrays: ``w`` (3, N) principal-frame angular
velocities, ``q`` (4, N) quaternions (principal → space), ``inertia`` (3, N)
principal moments, ``params`` (rows, M) the packed torque parameters, shared
(M = 1) or one column per body (M = N).
"""

from __future__ import annotations

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

__all__ = ["BLOCK", "batch_kernel", "load_block", "metrics_kernel", "single_kernel", "store_block"]

#: Bodies per block of the batch kernels: a block's state and coefficients stay
#: in L1 cache for all its steps, and the inner loop over the block's bodies is
#: what the compiler vectorises.
BLOCK = 128


def single_kernel(step, torque, identity):  # type: ignore[no-untyped-def]
    """``run(w, q, inertia, params, context, dt, n_steps, first_step, record_every,
    out_w, out_q) -> status``: advance one body's (w, q) in place by ``n_steps``
    steps of ``dt`` s.

    After global step ``first_step + k + 1`` (k = 0 … n_steps − 1), if that
    number is a multiple of ``record_every``, the state is written to row
    ``number // record_every`` of ``out_w`` (·, 3) and ``out_q`` (·, 4). The
    time of global step k is ``k dt``. Returns ``FINITE`` if every step stayed
    finite, else the global number of the first step that did not (the state
    is left as it was before that step).
    """

    @specialise(njit, f"stepping.single|{file_stamp(step)}|{identity}")
    def run(w, q, inertia, params, context, dt, n_steps, first_step, record_every, out_w, out_q):  # type: ignore[no-untyped-def]
        coefficients = euler_coefficients(inertia[0], inertia[1], inertia[2])
        state = (w[0], w[1], w[2], q[0], q[1], q[2], q[3])
        status = FINITE
        for k in range(n_steps):
            new = step(torque, (first_step + k) * dt, dt, state, coefficients, params, 0, context)
            if not is_finite(new):
                status = first_step + k + 1
                break
            state = new
            record(first_step + k + 1, record_every, out_w, out_q, state)
        for i in range(3):
            w[i] = state[i]
        for i in range(4):
            q[i] = state[3 + i]
        return status

    return run


@njit(inline="always")
def load_block(w, q, inertia, params, start, stop):  # type: ignore[no-untyped-def]
    """The block of bodies ``start:stop`` as its own arrays (they stay in L1 cache
    through its steps): ω1, ω2, ω3, q0 … q3, the Euler coefficients, and the
    block's columns of ``params`` (shared or per body) as (rows, m)."""
    m = stop - start
    block_params = np.empty((params.shape[0], m))
    shared = params.shape[1] == 1
    for r in range(params.shape[0]):
        for j in range(m):
            block_params[r, j] = params[r, 0] if shared else params[r, start + j]
    coefficients = euler_coefficients(
        inertia[0, start:stop], inertia[1, start:stop], inertia[2, start:stop]
    )
    state = (
        w[0, start:stop].copy(), w[1, start:stop].copy(), w[2, start:stop].copy(),
        q[0, start:stop].copy(), q[1, start:stop].copy(), q[2, start:stop].copy(),
        q[3, start:stop].copy(),
    )  # fmt: skip
    return state, coefficients, block_params


@njit(inline="always")
def store_block(w, q, start, state):  # type: ignore[no-untyped-def]
    """Write a block's state arrays back into ``w`` (3, N) and ``q`` (4, N)."""
    for j in range(state[0].shape[0]):
        for i in range(3):
            w[i, start + j] = state[i][j]
        for i in range(4):
            q[i, start + j] = state[3 + i][j]


@njit(inline="always")
def _block_steps(step, torque, t0, dt, n_steps, state, coefficients, params, context):  # type: ignore[no-untyped-def]
    """``n_steps`` steps of every body of a block, in place."""
    w1, w2, w3, q0, q1, q2, q3 = state
    c1, c2, c3, r1, r2, r3 = coefficients
    for k in range(n_steps):
        t = t0 + k * dt
        for j in range(w1.shape[0]):
            new = step(
                torque, t, dt, (w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j]),
                (c1[j], c2[j], c3[j], r1[j], r2[j], r3[j]), params, j, context,
            )  # fmt: skip
            w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j] = new


def batch_kernel(step, torque, identity):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, t0, dt, n_steps, status)``: advance N
    bodies in place by ``n_steps`` steps of ``dt`` s from time ``t0``, in parallel
    over blocks of ``BLOCK`` bodies, vectorised within a block. A body whose
    state became NaN or infinite keeps that state (fast-math may not keep a
    finiteness test inside the loop): the caller checks; ``status`` is left as is.
    """

    @specialise(njit_vector, f"stepping.batch|{file_stamp(step)}|{identity}")
    def batch(w, q, inertia, params, context, t0, dt, n_steps, status):  # type: ignore[no-untyped-def]
        n = w.shape[1]
        for block in prange((n + BLOCK - 1) // BLOCK):
            start = block * BLOCK
            stop = min(start + BLOCK, n)
            state, coefficients, block_params = load_block(w, q, inertia, params, start, stop)
            _block_steps(step, torque, t0, dt, n_steps, state, coefficients, block_params, context)
            store_block(w, q, start, state)

    return batch


def metrics_kernel(step, torque, identity):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status)``:
    as :func:`batch_kernel`, measuring each body after every step into ``out``
    (``N_METRICS``, N) (see :mod:`tumble.core.metrics`; ``axis`` (3, N) the
    nominal axes)."""

    @specialise(njit_vector, f"stepping.metrics|{file_stamp(step)}|{identity}")
    def batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status):  # type: ignore[no-untyped-def]
        n = w.shape[1]
        for block in prange((n + BLOCK - 1) // BLOCK):
            start = block * BLOCK
            stop = min(start + BLOCK, n)
            _metrics_block(
                step, torque, w, q, inertia, params, context, axis, t0, dt, n_steps, out, start,
                stop,
            )  # fmt: skip

    return batch


@njit(inline="always")
def _metrics_block(  # type: ignore[no-untyped-def]
    step, torque, w, q, inertia, params, context, axis, t0, dt, n_steps, out, start, stop
):
    state, coefficients, block_params = load_block(w, q, inertia, params, start, stop)
    w1, w2, w3 = state[0], state[1], state[2]
    m = stop - start
    i1 = inertia[0, start:stop]
    i2 = inertia[1, start:stop]
    i3 = inertia[2, start:stop]
    a1 = axis[0, start:stop]
    a2 = axis[1, start:stop]
    a3 = axis[2, start:stop]
    reference = np.empty(m)
    flips = np.zeros(m)
    crossed_at = np.zeros(m)
    before = np.zeros(m)
    after = np.zeros(m)
    lowest = np.empty(m)
    energy0 = np.empty(m)
    energy_dev = np.zeros(m)
    squared0 = np.empty(m)
    smallest = np.empty(m)
    largest = np.empty(m)
    for j in range(m):
        along, energy, squared, ratio = initial(
            w1[j], w2[j], w3[j], i1[j], i2[j], i3[j], a1[j], a2[j], a3[j]
        )
        reference[j] = along
        lowest[j] = ratio
        energy0[j] = energy
        squared0[j] = squared
        smallest[j] = squared
        largest[j] = squared
    for k in range(n_steps):
        _block_steps(step, torque, t0 + k * dt, dt, 1, state, coefficients, block_params, context)
        t = t0 + (k + 1) * dt
        # A loop of its own: with the measures in the stepping loop, that loop
        # stores to too many arrays for the compiler to vectorise it (5× slower).
        for j in range(m):
            (
                reference[j], flips[j], crossed_at[j], before[j], after[j], lowest[j],
                energy_dev[j], smallest[j], largest[j],
            ) = observe(
                t, w1[j], w2[j], w3[j], i1[j], i2[j], i3[j], a1[j], a2[j], a3[j], reference[j],
                flips[j], crossed_at[j], before[j], after[j], lowest[j], energy0[j],
                energy_dev[j], smallest[j], largest[j],
            )  # fmt: skip
    store_block(w, q, start, state)
    for j in range(m):
        k = start + j
        (
            out[FLIPS, k], out[FIRST_FLIP, k], out[MIN_COS, k], out[ENERGY_DEVIATION, k],
            out[MOMENTUM_DEVIATION, k],
        ) = finish(
            dt, flips[j], crossed_at[j], before[j], after[j], lowest[j], energy_dev[j],
            squared0[j], smallest[j], largest[j],
        )  # fmt: skip
