"""RK4 for batches of bodies carrying parts, stepped in blocks of bodies.

The kernels of :mod:`tumble.core.parts` step one body per thread: each body's
state is an array whose length the parts decide, and the compiler vectorises
nothing across bodies. Here ``BLOCK`` bodies step together, as the free body's
blocks do (:mod:`tumble.core.stepping`): the block's states are the columns of
one array (7 + m, BLOCK); each body's state is read from its column as a tuple
(its length fixed by the layout), stepped in registers by the shared RK4 of
tuples (:func:`tumble.core.rk4.rk4_tuple_step` of
:func:`tumble.core.parts.state_rates`) and written back, one body after the
other in a loop across the block, which the compiler vectorises. No array is
made per body: a view of a column, passed to the parts' equations as an array,
is counted by numba's reference counting, and those calls kept the loop from
being vectorised. The parts' and the torque's columns are copied into the
block, one per body, so that every load is contiguous.

The kernels take the arguments of the one-body-per-thread kernels and give their
statuses and measures; with the floating-point freedoms of the free body's
blocks (:data:`tumble.core._jit.VECTOR_FASTMATH`: FMA contraction, reassociation),
each body's state and measures are its own run's to round-off
(``tests/core/test_parts_kernels.py``; ``bench/batch_parts.py`` for the speed).
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import (
    FINITE,
    njit,
    njit_block_inline,
    njit_vector,
    own_name,
    prange,
    specialise,
)
from tumble.core.part_measures import RUNNING, body_measures, finish_measures
from tumble.core.parts import layout_identity, part_model, state_rates
from tumble.core.rk4 import entry_by_entry, rk4_tuple_step

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
def _put_column(block, j, state):  # type: ignore[no-untyped-def]
    """The tuple ``state`` into column ``j`` of ``block``."""
    for i in range(len(state)):
        block[i, j] = state[i]


@njit(inline="always")
def _inverse_at(inverse, j):  # type: ignore[no-untyped-def]
    """Body ``j``'s inverse platform moments, a tuple (3,)."""
    return inverse[0, j], inverse[1, j], inverse[2, j]


@njit(inline="always")
def _kept(old, new, alive):  # type: ignore[no-untyped-def]
    """``(state, alive)`` after a step from ``old`` to ``new`` (tuples) of a body
    that was ``alive``: ``new`` with its quaternion, entries 3–6, scaled to unit
    length, if the body was alive and that is finite (the sum of its entries and
    its quaternion's norm finite, that norm above zero, as the one-body kernels
    check); else ``old``, and the body no longer alive. Written without branches,
    so that the block's loop is vectorised."""
    scale = 1.0 / math.sqrt(new[3] * new[3] + new[4] * new[4] + new[5] * new[5] + new[6] * new[6])
    quaternion = (new[3] * scale, new[4] * scale, new[5] * scale, new[6] * scale)
    unit = new[:3] + quaternion + new[7:]
    total = 0.0
    for i in range(len(unit)):
        total += unit[i]
    norm = unit[3] * unit[3] + unit[4] * unit[4] + unit[5] * unit[5] + unit[6] * unit[6]
    keep = alive & math.isfinite(total) & math.isfinite(norm) & (norm > 0.0)
    return (unit if keep else old), keep


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
    (its model as :func:`_loaded` gives it): each body's state read as a tuple,
    stepped (:func:`tumble.core.rk4.rk4_tuple_step`), kept or not
    (:func:`_kept`) and written back, in a loop across the bodies that the
    compiler vectorises. Step k runs from global step ``round(t0 / dt) + k``; the
    first ``count`` bodies are the block's own (``start`` the first's index in
    ``status``, which gets the number of the step at which a body stopped). After
    each step, ``observer(number, alive, arguments)`` (:func:`_no_block_observer`)."""
    velocity, _, rates, _ = part_model(layout)
    size = 7 + sum(entry[1] for entry in layout)
    column = njit(inline="always", cache=False)(
        entry_by_entry("column", "block, j", "block[{i}, j]", size)
    )

    @njit(inline="always", cache=False)
    def derivatives(torque, t, y, held, params, j, context):  # type: ignore[no-untyped-def]
        hold, inverse, parts = held
        system = (inverse, inverse, parts, j, params, j, context)
        return state_rates(torque, drive, velocity, rates, t, hold, y, system)

    step = rk4_tuple_step(derivatives)

    @njit(inline="always", cache=False)
    def advance(state, model, t0, dt, n_steps, status, start, count, observer, arguments):  # type: ignore[no-untyped-def]
        inverse, parts, params, context = model
        alive = np.ones(BLOCK, dtype=np.bool_)
        stopped = np.full(BLOCK, FINITE, dtype=np.int64)
        first = int(t0 / dt + 0.5) if dt > 0.0 else 0
        for k in range(n_steps):
            t = (first + k) * dt
            hold = t + 0.5 * dt
            for j in range(BLOCK):
                old = column(state, j)
                held = (hold, _inverse_at(inverse, j), parts)
                new, keep = _kept(old, step(torque, t, dt, old, held, params, j, context), alive[j])
                _put_column(state, j, new)
                stopped[j] = first + k + 1 if alive[j] and not keep else stopped[j]
                alive[j] = keep
            observer(first + k + 1, alive, arguments)
        for j in range(count):
            if stopped[j] != FINITE:
                status[start + j] = stopped[j]

    return advance, column


def rk4_block_kernel(torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """:func:`tumble.core.parts.batch_kernel` of RK4 (the same arguments and
    statuses), stepping ``BLOCK`` bodies together (:func:`_block_advance`), in
    parallel over blocks. With the floating-point freedoms of the free body's
    blocks (:data:`tumble.core._jit.VECTOR_FASTMATH`: FMA contraction,
    reassociation), each body's state is its own run's to round-off."""
    advance, _ = _block_advance(torque, drive, layout)
    key = layout_identity(layout)

    @njit_block_inline
    @own_name(f"parts.rk4_block|{key}|{identity}")
    def stepped_block(y, moments, parts, params, context, t0, dt, n_steps, status, start, stop):  # type: ignore[no-untyped-def]
        state, model = _loaded(y, moments, parts, params, context, start, stop)
        count = stop - start
        advance(state, model, t0, dt, n_steps, status, start, count, _no_block_observer, ())
        y[:, start:stop] = state[:, :count]

    @specialise(njit_vector, f"parts.rk4_batch|{key}|{identity}")
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
        finish_measures(running, j, out, energy0, start + j, dt)


def rk4_block_measuring_kernel(torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """:func:`tumble.core.part_measures.measuring_kernel` of RK4 (the same arguments,
    measures and statuses), stepping ``BLOCK`` bodies together as
    :func:`rk4_block_kernel` does and measuring each after every step, as there,
    to round-off."""
    advance, column = _block_advance(torque, drive, layout)
    start_body, after_body = body_measures(layout)
    key = layout_identity(layout)

    @njit(inline="always", cache=False)
    def observer(number, alive, arguments):  # type: ignore[no-untyped-def]
        state, inverse, parts, running, dt = arguments
        for j in range(BLOCK):
            if alive[j]:
                body = column(state, j)
                after_body(body, _inverse_at(inverse, j), parts, j, running, j, number * dt)

    @njit_block_inline
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
            body = column(state, j)
            start_body(body, _inverse_at(inverse, j), block_parts, j, a1, a2, a3, running, j)
        count = stop - start
        arguments = (state, inverse, block_parts, running, dt)
        advance(state, model, t0, dt, n_steps, status, start, count, observer, arguments)
        _finish_block(running, out, energy0, start, count, dt)
        y[:, start:stop] = state[:, :count]

    @specialise(njit_vector, f"parts.rk4_measure|{key}|{identity}")
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
