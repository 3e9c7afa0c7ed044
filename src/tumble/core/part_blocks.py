"""RK4 for batches of bodies carrying parts, stepped in blocks of bodies.

The kernels of :mod:`tumble.core.parts` step one body per thread: each body's
state is an array whose length the parts decide, and the compiler vectorises
nothing across bodies. Here ``BLOCK`` bodies step together: the block's states
are one array (7 + m, BLOCK), stepped by the shared RK4 of arrays
(:func:`tumble.core.rk4.rk4_array_step`) as one state; its rates are computed body
after body (:func:`tumble.core.parts.part_rates` on each column), and every loop
runs across the bodies, so the compiler vectorises it, as it does the free
body's blocks (:mod:`tumble.core.stepping`). The parts' and the torque's columns
are copied into the block, one per body, so that every load is contiguous.

The kernels take the arguments of the one-body-per-thread kernels and give their
statuses and measures; with the floating-point freedoms of the free body's
blocks (:data:`tumble.core._jit.njit_block`: FMA contraction, reassociation),
each body's state and measures are its own run's to round-off
(``tests/core/test_parts_kernels.py``; ``bench/batch_parts.py`` for the speed).
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit, njit_block, njit_parallel, own_name, prange, specialise
from tumble.core.part_measures import RUNNING, body_measures, finish_measures
from tumble.core.parts import layout_identity, part_model, part_rates
from tumble.core.rk4 import rk4_array_step

__all__ = ["BLOCK", "rk4_block_kernel", "rk4_block_measuring_kernel"]


#: Bodies a thread steps together in :func:`rk4_block_kernel`.
BLOCK = 64


@njit(inline="always")
def _block_of(source, start, stop):  # type: ignore[no-untyped-def]
    """Columns ``start:stop`` of ``source`` (a single column: shared by every body) as
    a block of ``BLOCK`` columns, the last one repeated to fill it."""
    block = np.empty((source.shape[0], BLOCK))
    shared = source.shape[1] == 1
    for j in range(BLOCK):
        column = 0 if shared else min(start + j, stop - 1)
        for i in range(source.shape[0]):
            block[i, j] = source[i, column]
    return block


@njit(inline="always")
def _normalise_block(state):  # type: ignore[no-untyped-def]
    """Every body's (column's) quaternion, rows 3–6, scaled to unit length, in place."""
    for j in range(BLOCK):
        scale = 1.0 / math.sqrt(
            state[3, j] * state[3, j]
            + state[4, j] * state[4, j]
            + state[5, j] * state[5, j]
            + state[6, j] * state[6, j]
        )
        for i in range(3, 7):
            state[i, j] *= scale


@njit(inline="always")
def _keep_finite(state, saved, total, alive, status, start, count, number):  # type: ignore[no-untyped-def]
    """After global step ``number`` of the first ``count`` bodies of a block: a body
    whose new state is not finite (a sum of its entries, or its quaternion's norm,
    not finite, or that norm zero, as the one-body kernels check; here row by row
    across the block) gets the status ``number`` and stops; a stopped body gets
    back its state before the step. ``total`` (BLOCK,) scratch."""
    for j in range(BLOCK):
        total[j] = 0.0
    for i in range(state.shape[0]):
        for j in range(BLOCK):
            total[j] += state[i, j]
    for j in range(count):
        norm = (
            state[3, j] * state[3, j]
            + state[4, j] * state[4, j]
            + state[5, j] * state[5, j]
            + state[6, j] * state[6, j]
        )
        if alive[j] and not (math.isfinite(total[j]) and math.isfinite(norm) and norm > 0.0):
            alive[j] = False
            status[start + j] = number
        if not alive[j]:
            for i in range(state.shape[0]):
                state[i, j] = saved[i, j]


@njit(inline="always")
def _no_block_observer(number, alive, arguments):  # type: ignore[no-untyped-def]
    """The observer of a block's steps that observes nothing."""


@njit(inline="always")
def _loaded(y, moments, parts, params, context, start, stop):  # type: ignore[no-untyped-def]
    """Bodies ``start:stop`` of a batch as a block (:func:`_block_of`): their states
    (7 + m, BLOCK) and their model ``(inverse, parts, params, context)``, the inverse
    platform moments (3, BLOCK), the parts and the torque's parameters a column per
    body, the torque's context."""
    inverse = 1.0 / _block_of(moments, start, stop)
    model = (inverse, _block_of(parts, start, stop), _block_of(params, start, stop), context)
    return _block_of(y, start, stop), model


def _block_advance(torque, drive, layout):  # type: ignore[no-untyped-def]
    """``advance(state, model, t0, dt, n_steps, status, start, count, observer,
    arguments)``: ``n_steps`` RK4 steps of a block's states (7 + m, BLOCK) in place
    (its model as :func:`_loaded` gives it), by the shared stepper
    (:func:`tumble.core.rk4.rk4_array_step`) over the block as one array, its
    rates body after body: every loop runs across the bodies, and the compiler
    vectorises it. Step k runs from global step ``round(t0 / dt) + k``; the first
    ``count`` bodies are the block's own (``start`` the first's index in
    ``status``: :func:`_keep_finite`). After each step, ``observer(number, alive,
    arguments)`` (:func:`_no_block_observer`)."""
    velocity, _, rates, _ = part_model(layout)
    size = 7 + sum(entry[1] for entry in layout)

    @njit(inline="always", cache=False)
    def derivatives(t, y, dy, held):  # type: ignore[no-untyped-def]
        hold, (inverse, parts, params, context) = held
        states = y.reshape((size, BLOCK))
        slopes = dy.reshape((size, BLOCK))
        for j in range(BLOCK):
            system = (inverse[:, j], inverse[:, j], parts, j, params, j, context)
            part_rates(torque, drive, velocity, rates, t, hold, states[:, j], slopes[:, j], system)

    @njit(inline="always", cache=False)
    def advance(state, model, t0, dt, n_steps, status, start, count, observer, arguments):  # type: ignore[no-untyped-def]
        flat = state.reshape(size * BLOCK)
        saved = np.empty((size, BLOCK))
        work = np.empty((5, size * BLOCK))
        total = np.empty(BLOCK)
        alive = np.ones(BLOCK, dtype=np.bool_)
        first = int(t0 / dt + 0.5) if dt > 0.0 else 0
        for k in range(n_steps):
            t = (first + k) * dt
            saved[:] = state
            rk4_array_step(derivatives, t, dt, flat, work, (t + 0.5 * dt, model))
            _normalise_block(state)
            _keep_finite(state, saved, total, alive, status, start, count, first + k + 1)
            observer(first + k + 1, alive, arguments)

    return advance


def rk4_block_kernel(torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """:func:`tumble.core.parts.batch_kernel` of RK4 (the same arguments and
    statuses), stepping ``BLOCK`` bodies together (:func:`_block_advance`), in
    parallel over blocks. With the floating-point freedoms of the free body's
    blocks (:data:`njit_block`: FMA contraction, reassociation), each body's state
    is its own run's to round-off."""
    advance = _block_advance(torque, drive, layout)
    key = layout_identity(layout)

    @njit_block
    @own_name(f"parts.rk4_block|{key}|{identity}")
    def stepped_block(y, moments, parts, params, context, t0, dt, n_steps, status, start, stop):  # type: ignore[no-untyped-def]
        state, model = _loaded(y, moments, parts, params, context, start, stop)
        count = stop - start
        advance(state, model, t0, dt, n_steps, status, start, count, _no_block_observer, ())
        y[:, start:stop] = state[:, :count]

    @specialise(njit_parallel, f"parts.rk4_batch|{key}|{identity}")
    def batch(y, moments, parts, params, context, t0, dt, n_steps, status):  # type: ignore[no-untyped-def]
        n = y.shape[1]
        for block in prange((n + BLOCK - 1) // BLOCK):
            start = block * BLOCK
            stop = min(start + BLOCK, n)
            stepped_block(y, moments, parts, params, context, t0, dt, n_steps, status, start, stop)

    return batch


@njit(inline="always")
def _finish_block(running, out, energy0, start, count, dt):  # type: ignore[no-untyped-def]
    """The measures of the first ``count`` bodies of a block (their columns of
    ``running``) into columns ``start …`` of ``out`` and ``energy0``."""
    for j in range(count):
        finish_measures(running[:, j], out, energy0, start + j, dt)


def rk4_block_measuring_kernel(torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """:func:`tumble.core.part_measures.measuring_kernel` of RK4 (the same arguments, measures
    and statuses),
    stepping ``BLOCK`` bodies together as :func:`rk4_block_kernel` does and
    measuring each after every step, as there, to round-off."""
    advance = _block_advance(torque, drive, layout)
    start_body, after_body = body_measures(layout)
    key = layout_identity(layout)

    @njit(inline="always", cache=False)
    def observer(number, alive, arguments):  # type: ignore[no-untyped-def]
        state, inverse, parts, running, dt = arguments
        for j in range(BLOCK):
            if alive[j]:
                after_body(state[:, j], inverse[:, j], parts, j, running[:, j], number * dt)

    @njit_block
    @own_name(f"parts.rk4_block_measured|{key}|{identity}")
    def measured_block(  # type: ignore[no-untyped-def]
        y, moments, parts, params, context, axis, t0, dt, n_steps, out, energy0, status, start, stop
    ):
        state, model = _loaded(y, moments, parts, params, context, start, stop)
        inverse, block_parts = model[0], model[1]
        nominal = _block_of(axis, start, stop)
        running = np.empty((len(RUNNING), BLOCK))
        for j in range(BLOCK):
            a1, a2, a3 = nominal[0, j], nominal[1, j], nominal[2, j]
            start_body(state[:, j], inverse[:, j], block_parts, j, a1, a2, a3, running[:, j])
        count = stop - start
        arguments = (state, inverse, block_parts, running, dt)
        advance(state, model, t0, dt, n_steps, status, start, count, observer, arguments)
        _finish_block(running, out, energy0, start, count, dt)
        y[:, start:stop] = state[:, :count]

    @specialise(njit_parallel, f"parts.rk4_measure|{key}|{identity}")
    def measure(y, moments, parts, params, context, axis, t0, dt, n_steps, out, energy0, status):  # type: ignore[no-untyped-def]
        n = y.shape[1]
        for block in prange((n + BLOCK - 1) // BLOCK):
            start = block * BLOCK
            stop = min(start + BLOCK, n)
            measured_block(
                y,
                moments,
                parts,
                params,
                context,
                axis,
                t0,
                dt,
                n_steps,
                out,
                energy0,
                status,
                start,
                stop,
            )

    return measure
