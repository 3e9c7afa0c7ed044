"""Classical Runge–Kutta for a rigid body: one body, and batches vectorised across bodies.

The equations are those of :mod:`tumble.core.dynamics`; the quaternion is
renormalised after every step. The kernels are built for one torque function
(:func:`tumble.core.torques.combine`) by the factories below, which the
integrator registry (:mod:`tumble.integrators`) calls and caches.

Batches are structures of arrays: ``w`` (3, N) principal-frame angular
velocities, ``q`` (4, N) quaternions (principal → space), ``inertia`` (3, N)
principal moments, ``params`` (rows, M) the packed torque parameters, shared
(M = 1) or one column per body (M = N).
"""

from __future__ import annotations

import numpy as np

from tumble.core._jit import FINITE, njit, njit_vector, prange, specialise
from tumble.core.dynamics import euler_coefficients, is_finite, normalised, rates, record
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

#: Bodies per block of the batch kernels: a block's state and coefficients stay
#: in L1 cache for all its steps, and the inner loop over the block's bodies is
#: what the compiler vectorises.
BLOCK = 128


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


def single_kernel(torque, identity):  # type: ignore[no-untyped-def]
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

    @specialise(njit, f"rk4.single|{identity}")
    def run(w, q, inertia, params, context, dt, n_steps, first_step, record_every, out_w, out_q):  # type: ignore[no-untyped-def]
        coefficients = euler_coefficients(inertia[0], inertia[1], inertia[2])
        state = (w[0], w[1], w[2], q[0], q[1], q[2], q[3])
        status = FINITE
        for k in range(n_steps):
            step = rk4_step(
                torque, (first_step + k) * dt, dt, state, coefficients, params, 0, context
            )
            if not is_finite(step):
                status = first_step + k + 1
                break
            state = step
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
def _block_steps(torque, t0, dt, n_steps, state, coefficients, params, context):  # type: ignore[no-untyped-def]
    """``n_steps`` RK4 steps of every body of a block, in place."""
    w1, w2, w3, q0, q1, q2, q3 = state
    c1, c2, c3, r1, r2, r3 = coefficients
    for k in range(n_steps):
        t = t0 + k * dt
        for j in range(w1.shape[0]):
            new = rk4_step(
                torque, t, dt, (w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j]),
                (c1[j], c2[j], c3[j], r1[j], r2[j], r3[j]), params, j, context,
            )  # fmt: skip
            w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j] = new


def batch_kernel(torque, identity):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, t0, dt, n_steps, status)``: advance N
    bodies in place by ``n_steps`` steps of ``dt`` s from time ``t0``, in parallel
    over blocks of ``BLOCK`` bodies, vectorised within a block. A body whose
    state became NaN or infinite keeps that state (fast-math may not keep a
    finiteness test inside the loop): the caller checks; ``status`` is left as is.
    """

    @specialise(njit_vector, f"rk4.batch|{identity}")
    def batch(w, q, inertia, params, context, t0, dt, n_steps, status):  # type: ignore[no-untyped-def]
        n = w.shape[1]
        for block in prange((n + BLOCK - 1) // BLOCK):
            start = block * BLOCK
            stop = min(start + BLOCK, n)
            state, coefficients, block_params = load_block(w, q, inertia, params, start, stop)
            _block_steps(torque, t0, dt, n_steps, state, coefficients, block_params, context)
            store_block(w, q, start, state)

    return batch


def metrics_kernel(torque, identity):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status)``:
    as :func:`batch_kernel`, measuring each body after every step into ``out``
    (``N_METRICS``, N) (see :mod:`tumble.core.metrics`; ``axis`` (3, N) the
    nominal axes)."""

    @specialise(njit_vector, f"rk4.metrics|{identity}")
    def batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status):  # type: ignore[no-untyped-def]
        n = w.shape[1]
        for block in prange((n + BLOCK - 1) // BLOCK):
            start = block * BLOCK
            stop = min(start + BLOCK, n)
            _metrics_block(
                torque, w, q, inertia, params, context, axis, t0, dt, n_steps, out, start, stop
            )

    return batch


@njit(inline="always")
def _metrics_block(  # type: ignore[no-untyped-def]
    torque, w, q, inertia, params, context, axis, t0, dt, n_steps, out, start, stop
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
        _block_steps(torque, t0 + k * dt, dt, 1, state, coefficients, block_params, context)
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
