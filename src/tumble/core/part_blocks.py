"""Batches of bodies carrying parts, stepped in blocks of bodies.

The kernels of :mod:`tumble.core.parts` step one body per thread: each body's
state is an array whose length the parts decide, and the compiler vectorises
nothing across bodies. Here ``BLOCK`` bodies step together, as the free body's
blocks do (:mod:`tumble.core.stepping`): the block's states are the columns of
one array (7 + m, BLOCK); each body's state is read from its column as a tuple
(its length fixed by the layout), stepped in registers and written back, one
body after the other in a loop across the block, which the compiler vectorises.
No array is made per body: a view of a column, passed to the parts' equations
as an array, is counted by numba's reference counting, and those calls kept the
loop from being vectorised. The parts' and the torque's columns are copied into
the block, one per body, so that every load is contiguous.

A body's step is made by one of :func:`rk4_body_step` (the shared RK4 of
tuples, :func:`tumble.core.rk4.rk4_tuple_step` of
:func:`tumble.core.parts.state_rates`), :func:`strang_body_step` and
:func:`yoshida_body_step` (the gyrostat splitting's sub-steps,
:func:`tumble.core.parts.splitting_sub_step`, turning by the vectorised sines
:func:`tumble.core.trig.cos_sin` where one body alone turns by the C library's).

The kernels take the arguments of the one-body-per-thread kernels and give their
statuses and measures; with the floating-point freedoms of the free body's
blocks (:data:`tumble.core._jit.VECTOR_FASTMATH`: FMA contraction, reassociation)
and, for the splittings, the other sines, each body's state and measures are its
own run's to round-off (``tests/core/test_parts_kernels.py``;
``bench/batch_parts.py`` for the speed).
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from tumble.core._jit import (
    FINITE,
    file_stamp,
    njit,
    njit_block,
    njit_block_inline,
    njit_vector,
    own_name,
    prange,
    specialise,
)
from tumble.core.part_measures import RUNNING, body_measures, finish_measures
from tumble.core.parts import (
    gyrostat_flow,
    layout_identity,
    nothing_after,
    part_model,
    splitting_sub_step,
    state_rates,
)
from tumble.core.rk4 import entry_by_entry, rk4_tuple_step
from tumble.core.splitting import sub_steps
from tumble.core.trig import cos_sin

__all__ = [
    "BLOCK",
    "BodyStep",
    "block_kernel",
    "block_measuring_kernel",
    "rk4_body_step",
    "strang_body_step",
    "yoshida_body_step",
]


#: Bodies a thread steps together in :func:`block_kernel`.
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
def _three_at(block, j):  # type: ignore[no-untyped-def]
    """Column ``j`` of a block (3, BLOCK) (body ``j``'s platform moments or their
    inverses), a tuple (3,)."""
    return block[0, j], block[1, j], block[2, j]


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
    (7 + m, BLOCK) and their model ``(moments, inverse, parts, params, context)``:
    the platform moments and their inverses (3, BLOCK), the parts and the torque's
    parameters a column per body, the torque's context."""
    block_moments = _block_of(moments, start, stop)
    model = (
        block_moments,
        1.0 / block_moments,
        _block_of(parts, start, stop),
        _block_of(params, start, stop),
        context,
    )
    return _block_of(y, start, stop), model


class BodyStep(NamedTuple):
    """A method's step of one body of a block, made by ``make(torque, drive,
    layout)`` (:func:`rk4_body_step`, :func:`strang_body_step`,
    :func:`yoshida_body_step`): ``step(torque, t, dt, sub, state, body, params, j,
    context)`` is the body's state (a tuple, its quaternion not renormalised)
    after sub-step ``sub`` of a step of ``dt`` s from time ``t``, with ``body`` =
    (moments, inverse, parts): the body's platform moments and their inverses
    (tuples (3,)) and the block's parts, its column ``j`` (as the torque's);
    ``sub_steps`` how many sub-steps make a step; ``finish(sines, dt, state,
    inverse)`` the state after what the step adds after its last sub-step
    (:class:`tumble.core.parts.GyrostatFlow`)."""

    step: Any
    sub_steps: int
    finish: Any


def rk4_body_step(torque, drive, layout):  # type: ignore[no-untyped-def]
    """The classical Runge–Kutta step (:func:`tumble.core.rk4.rk4_tuple_step` of
    :func:`tumble.core.parts.state_rates`), the parts' inputs read at the step's
    middle; one sub-step."""
    velocity, _, rates, _, _ = part_model(layout)

    @njit(inline="always", cache=False)
    def derivatives(torque, t, y, held, params, j, context):  # type: ignore[no-untyped-def]
        hold, moments, inverse, parts = held
        system = (moments, inverse, parts, j, params, j, context)
        return state_rates(torque, drive, velocity, rates, t, hold, y, system)

    stages = rk4_tuple_step(derivatives)

    @njit(inline="always", cache=False)
    def step(torque, t, dt, sub, state, body, params, j, context):  # type: ignore[no-untyped-def]
        moments, inverse, parts = body
        held = (t + 0.5 * dt, moments, inverse, parts)
        return stages(torque, t, dt, state, held, params, j, context)

    return BodyStep(step, 1, nothing_after)


def _splitting_body_step(torque, drive, layout, order):  # type: ignore[no-untyped-def]
    """:func:`tumble.core.parts.splitting_sub_step` of ``order``, turning by the
    vectorised sines."""
    momentum = part_model(layout).momentum
    flow, finish, kick = gyrostat_flow(torque, drive, layout)

    @njit(inline="always", cache=False)
    def step(torque, t, dt, sub, state, body, params, j, context):  # type: ignore[no-untyped-def]
        moments, inverse, parts = body
        system = (moments, inverse, parts, j, params, j, context)
        sines = cos_sin
        return splitting_sub_step(
            torque, drive, momentum, kick, flow, sines, t, dt, sub, state, system, order
        )

    return BodyStep(step, sub_steps(order), finish)


def strang_body_step(torque, drive, layout):  # type: ignore[no-untyped-def]
    """The gyrostat's Strang splitting (order 2): one sub-step."""
    return _splitting_body_step(torque, drive, layout, 2)


def yoshida_body_step(torque, drive, layout):  # type: ignore[no-untyped-def]
    """Yoshida's triple jump of the gyrostat's Strang splitting (order 4): three
    sub-steps."""
    return _splitting_body_step(torque, drive, layout, 4)


def _block_advance(make_step, torque, drive, layout):  # type: ignore[no-untyped-def]
    """``advance(state, model, t0, dt, n_steps, status, start, count, observer,
    arguments)``: ``n_steps`` steps (``make_step``'s, :class:`BodyStep`) of a
    block's states (7 + m, BLOCK) in place (its model as :func:`_loaded` gives
    it): each body's state read as a tuple, stepped, kept or not (:func:`_kept`)
    and written back, in a loop across the bodies that the compiler vectorises.
    A step of several sub-steps takes a loop across the bodies for each, so that
    the compiler inlines the sub-step once (the Yoshida splitting's three Strang
    steps, written out in one loop, took 102 s to compile; so, 26 s, as Strang's
    one), and the states before the step are kept aside for :func:`_kept`. Step k runs
    from global step ``round(t0 / dt) + k``; the first ``count`` bodies are the
    block's own (``start`` the first's index in ``status``, which gets the number
    of the step at which a body stopped). After each step, ``observer(number,
    alive, arguments)`` (:func:`_no_block_observer`). The step's ``finish`` runs in
    the loop that keeps it, after its sub-steps."""
    step, n_sub, finish = make_step(torque, drive, layout)
    size = part_model(layout).size
    column = njit(inline="always", cache=False)(
        entry_by_entry("column", "block, j", "block[{i}, j]", size)
    )

    @njit(inline="always", cache=False)
    def advance(state, model, t0, dt, n_steps, status, start, count, observer, arguments):  # type: ignore[no-untyped-def]
        moments, inverse, parts, params, context = model
        alive = np.ones(BLOCK, dtype=np.bool_)
        stopped = np.full(BLOCK, FINITE, dtype=np.int64)
        before = np.empty((size, BLOCK)) if n_sub > 1 else np.empty((0, 0))
        first = int(t0 / dt + 0.5) if dt > 0.0 else 0
        for k in range(n_steps):
            t = (first + k) * dt
            if n_sub > 1:  # the sub-steps, each a loop across the block
                for i in range(size):
                    for j in range(BLOCK):
                        before[i, j] = state[i, j]
                for sub in range(n_sub):
                    for j in range(BLOCK):
                        body = (_three_at(moments, j), _three_at(inverse, j), parts)
                        now = step(torque, t, dt, sub, column(state, j), body, params, j, context)
                        _put_column(state, j, now)
            for j in range(BLOCK):
                if n_sub > 1:  # stepped above
                    old = column(before, j)
                    stepped = column(state, j)
                else:  # stepped here, in the loop that keeps it
                    old = column(state, j)
                    body = (_three_at(moments, j), _three_at(inverse, j), parts)
                    stepped = step(torque, t, dt, 0, old, body, params, j, context)
                stepped = finish(cos_sin, dt, stepped, _three_at(inverse, j))
                new, keep = _kept(old, stepped, alive[j])
                _put_column(state, j, new)
                stopped[j] = first + k + 1 if alive[j] and not keep else stopped[j]
                alive[j] = keep
            observer(first + k + 1, alive, arguments)
        for j in range(count):
            if stopped[j] != FINITE:
                status[start + j] = stopped[j]

    return advance, column


def _block_compiler(make_step):  # type: ignore[no-untyped-def]
    """How the work on one block is compiled: inlined into the kernel's parallel
    loop for RK4 (:data:`tumble.core._jit.njit_block_inline`, as fast in the
    process that compiles it as loaded from the cache); a function of its own for
    the splittings (:data:`~tumble.core._jit.njit_block`): inlined there, numba's
    analysis of the parallel loop fails on the splitting's step (an assertion on
    the shapes it infers for the tuples of the state)."""
    return njit_block_inline if make_step is rk4_body_step else njit_block


def block_kernel(make_step, torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """:func:`tumble.core.parts.batch_kernel` of ``make_step``'s method (the same
    arguments and statuses), stepping ``BLOCK`` bodies together
    (:func:`_block_advance`), in parallel over blocks: each body's state is its
    own run's to round-off (the module's docstring)."""
    advance, _ = _block_advance(make_step, torque, drive, layout)
    key = f"{file_stamp(make_step)}|{layout_identity(layout)}"

    @_block_compiler(make_step)
    @own_name(f"parts.block|{key}|{identity}")
    def stepped_block(y, moments, parts, params, context, t0, dt, n_steps, status, start, stop):  # type: ignore[no-untyped-def]
        state, model = _loaded(y, moments, parts, params, context, start, stop)
        count = stop - start
        advance(state, model, t0, dt, n_steps, status, start, count, _no_block_observer, ())
        y[:, start:stop] = state[:, :count]

    @specialise(njit_vector, f"parts.block_batch|{key}|{identity}")
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


def block_measuring_kernel(make_step, torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """:func:`tumble.core.part_measures.measuring_kernel` of ``make_step``'s method
    (the same arguments, measures and statuses), stepping ``BLOCK`` bodies together
    as :func:`block_kernel` does and measuring each after every step, as there,
    to round-off."""
    advance, column = _block_advance(make_step, torque, drive, layout)
    start_body, after_body = body_measures(layout)
    key = f"{file_stamp(make_step)}|{layout_identity(layout)}"

    @njit(inline="always", cache=False)
    def observer(number, alive, arguments):  # type: ignore[no-untyped-def]
        state, inverse, parts, running, dt = arguments
        for j in range(BLOCK):
            if alive[j]:
                body = column(state, j)
                after_body(body, _three_at(inverse, j), parts, j, running, j, number * dt)

    @_block_compiler(make_step)
    @own_name(f"parts.block_measured|{key}|{identity}")
    def measured_block(  # type: ignore[no-untyped-def]
        y, moments, parts, params, context, axis, t0, dt, n_steps, out, energy0, status, start, stop
    ):
        state, model = _loaded(y, moments, parts, params, context, start, stop)
        inverse, block_parts = model[1], model[2]
        nominal = _block_of(axis, start, stop)
        running = np.empty((len(RUNNING), BLOCK))
        for j in range(BLOCK):
            a1, a2, a3 = nominal[0, j], nominal[1, j], nominal[2, j]
            body = column(state, j)
            start_body(body, _three_at(inverse, j), block_parts, j, a1, a2, a3, running, j)
        count = stop - start
        arguments = (state, inverse, block_parts, running, dt)
        advance(state, model, t0, dt, n_steps, status, start, count, observer, arguments)
        _finish_block(running, out, energy0, start, count, dt)
        y[:, start:stop] = state[:, :count]

    @specialise(njit_vector, f"parts.block_measure|{key}|{identity}")
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
