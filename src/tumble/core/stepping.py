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
from tumble.core.dynamics import euler_coefficients, is_finite, record
from tumble.core.metrics import (
    ENERGY_DEVIATION,
    FIRST_FLIP,
    FLIPS,
    MIN_COS,
    MOMENTUM_DEVIATION,
    finish,
    initial,
    nutation_start,
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
    "no_observer",
    "single_kernel",
    "store_block",
]

#: Bodies per block of the batch kernels: a block's state and coefficients stay
#: in L1 cache for all its steps, and the inner loop over the block's bodies is
#: what the compiler vectorises.
BLOCK = 128

#: Bodies per block of the measuring kernels. A block's state, coefficients and
#: running measures are rows of one array (:func:`_measuring_rows`), 25 of which
#: are read at each step: 27 KiB, in L1 cache.
METRICS_BLOCK = 128

#: Entries per row of a measuring block's array: a row is 8 entries longer than
#: the block, so that the same entry of two rows is never a multiple of 4 KiB
#: apart. A processor that matches a load against earlier stores by the low 12
#: bits of their addresses would otherwise make loads of one row wait for stores
#: to another ("4K aliasing"): measured, rows of exactly 128 entries cost 15 % to
#: 40 % over plain stepping from one run to the next, rows of 136 a steady 15 %.
_ROW = METRICS_BLOCK + 8

# The rows of a measuring block's array: the stepper's 7 variables, the 9 Euler
# coefficients (the moments last), the nominal axis as the kernel's ``Nominal``
# keeps it, and the running measures.
_STATE, _COEFFICIENTS, _AXIS = 0, 7, 16
# The last non-zero ``c`` (:func:`tumble.core.metrics.observe`), in one of two
# rows: a step reads one and writes the other, so at a first flip both are at
# hand; odd steps swap their roles.
_REFERENCE_EVEN, _REFERENCE_ODD = 19, 20
_FLIPS, _NUMERATOR, _DENOMINATOR, _ENERGY0, _ENERGY_DEVIATION = 21, 22, 23, 24, 25
_SMALLEST, _LARGEST, _SQUARED0, _RECORDED, _CROSSED_AT, _BEFORE, _AFTER = range(26, 33)
_ROWS = 33


class Variables(NamedTuple):
    """The variables a stepper steps, as three compiled functions of ``(state,
    coefficients)``: ``enter`` from ``(ω, q)`` to them, ``leave`` back, and
    ``vectors`` the body's ``(L1, L2, L3, ω1, ω2, ω3)`` (principal frame) for the
    measures. The loops convert once when they load a body and when they record
    or store it, never between steps, so a stepper of other variables (the
    splittings step ``(L, q)``) accumulates no round-off from the conversions;
    the measures take the vector they step as it is and make the other with a
    product by I or 1/I (ω = L / I, a division a body and step in the measuring
    loop, cost Strang's measuring kernel 7 % of its speed, measured)."""

    enter: Any
    leave: Any
    vectors: Any


@njit(inline="always")
def _unchanged(state, coefficients):  # type: ignore[no-untyped-def]
    return state


@njit(inline="always")
def _velocity_vectors(state, coefficients):  # type: ignore[no-untyped-def]
    """``(L, ω)`` of the state ``(ω, q)``: L = I ω."""
    w1, w2, w3 = state[0], state[1], state[2]
    return coefficients[6] * w1, coefficients[7] * w2, coefficients[8] * w3, w1, w2, w3


#: The stepper steps ``(ω, q)`` itself (RK4).
VELOCITY = Variables(_unchanged, _unchanged, _velocity_vectors)


def _stamp(step: Any, variables: Variables, advance: Any = None) -> str:
    """The stepper's part of a kernel's identity."""
    stamp = file_stamp(step)
    if variables is not VELOCITY:
        stamp += "|" + "|".join(file_stamp(function) for function in variables)
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
    enter, leave, _ = variables

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
        inertia[0, start:stop].copy(),
        inertia[1, start:stop].copy(),
        inertia[2, start:stop].copy(),
    )
    state = (
        np.empty(m),
        np.empty(m),
        np.empty(m),
        np.empty(m),
        np.empty(m),
        np.empty(m),
        np.empty(m),
    )
    for j in range(m):
        k = start + j
        entered = enter(
            (w[0, k], w[1, k], w[2, k], q[0, k], q[1, k], q[2, k], q[3, k]),
            _coefficients(coefficients, j),
        )
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
def no_observer(k, arguments):  # type: ignore[no-untyped-def]
    """The observer of a block advance that observes nothing."""


@njit(inline="always")
def block_steps(  # type: ignore[no-untyped-def]
    step, torque, t0, dt, n_steps, state, coefficients, params, context, observer, arguments
):
    """``n_steps`` steps of every body of a block, in place: the state arrays, the
    arrays of the Euler coefficients and the block's ``params`` of
    :func:`load_block`; one body after the other within a step, which the
    compiler vectorises. Step k (from 0) runs from ``t0 + k dt`` to
    ``t0 + (k + 1) dt``; after it, ``observer(k, arguments)`` is called, with
    ``arguments`` what it needs to find the block's state (:func:`no_observer`
    for none). The batch kernels' default ``advance``."""
    w1, w2, w3, q0, q1, q2, q3 = state
    for k in range(n_steps):
        t = t0 + k * dt
        for j in range(w1.shape[0]):
            new = step(
                torque,
                t,
                dt,
                (w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j]),
                _coefficients(coefficients, j),
                params,
                j,
                context,
            )
            w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j] = new
        observer(k, arguments)


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
    ``variables``: those ``step`` steps; ``advance(step, torque, observed=False)``:
    for a stepper with a faster way for whole blocks, a compiled function of
    :func:`block_steps`'s arguments that steps a block in place and, if
    ``observed``, calls the observer after each step; or None
    (:func:`block_steps` itself).
    """
    enter, leave, _ = variables
    advance, stamp = _advance(step, torque, variables, advance)

    @njit_block_inline
    @own_name(f"stepping.batch.block|{stamp}|{identity}")
    def stepped_block(w, q, inertia, params, context, t0, dt, n_steps, start, stop):  # type: ignore[no-untyped-def]
        """The steps of bodies ``start:stop``."""
        state, coefficients, block_params = load_block(enter, w, q, inertia, params, start, stop)
        advance(
            step,
            torque,
            t0,
            dt,
            n_steps,
            state,
            coefficients,
            block_params,
            context,
            no_observer,
            (),
        )
        store_block(leave, w, q, start, state, coefficients)

    @specialise(njit_vector, f"stepping.batch|{stamp}|{identity}")
    def batch(w, q, inertia, params, context, t0, dt, n_steps, status):  # type: ignore[no-untyped-def]
        n = w.shape[1]
        for block in prange((n + BLOCK - 1) // BLOCK):
            start = block * BLOCK
            stop = min(start + BLOCK, n)
            stepped_block(w, q, inertia, params, context, t0, dt, n_steps, start, stop)

    return batch


def metrics_kernel(  # type: ignore[no-untyped-def]
    step, torque, identity, variables=VELOCITY, advance=None, principal_axis=None, attitude=True
):
    """``batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status)``:
    as :func:`batch_kernel`, measuring each body after every step into ``out``
    (``N_METRICS``, N) (see :mod:`tumble.core.metrics`; ``axis`` (3, N) the
    nominal axes). ``principal_axis`` (0, 1 or 2): a kernel only for nominal axes
    on that principal axis (the other two rows of ``axis`` zero, none of the
    third), which measures about them as :func:`_on_axis` says: the same measures
    to round-off, with three fewer multiplications a body and step than the
    kernel for any axis (see bench/sweep.py for what that saves).

    ``attitude=False``: a kernel that leaves ``q`` as it was given, for a torque
    that does not depend on the attitude (``torque`` must not read the
    quaternion) and a stepper whose failed steps show in its first three
    variables. The measures need only ω (or L), which such a body's motion
    does not couple to q: the stepping loop keeps none of the quaternion's
    results, so the compiler drops their arithmetic, about half of an RK4 step
    (with the default ``advance``; a stepper's own still steps q, unwritten).
    ``w`` and the measures are those of the kernel with the attitude, to
    round-off (the compiler may contract the loop's arithmetic otherwise).

    With the default ``advance``, a body is measured in the loop that steps it,
    while its new state is still in registers. A stepper's own ``advance`` steps
    the whole block through all its steps, and its observer measures the block
    after each one, in a second loop over it.
    """
    enter, leave, vectors = variables
    chosen = None if advance is None else advance(step, torque, observed=True)
    stamp = _stamp(step, variables, chosen)
    start_nominal, about = _ANY_AXIS if principal_axis is None else _on_axis(principal_axis)

    @njit(inline="always", cache=False)
    def measured_vectors(rows, j, state, coefficients):  # type: ignore[no-untyped-def]
        """Body j's L and ω (``vectors``) and its numbers about its nominal axis
        (``about``)."""
        l1, l2, l3, w1, w2, w3 = vectors(state, coefficients)
        c, signed, squared = about(rows, j, l1, l2, l3)
        return l1, l2, l3, w1, w2, w3, c, signed, squared

    @njit(inline="always", cache=False)
    def measure(k, arguments):  # type: ignore[no-untyped-def]
        """The observer of ``chosen``: the measures of a block after its step k;
        ``arguments`` its measuring array, the time of its first step and dt."""
        rows, t0, dt = arguments
        # Two calls, so that the rows each reads and writes are constants: held in
        # variables, the compiler could not tell that they do not overlap, and the
        # loop would not vectorise.
        if k % 2 == 0:
            _measured(measured_vectors, t0 + k * dt, dt, rows, _REFERENCE_EVEN, _REFERENCE_ODD)
        else:
            _measured(measured_vectors, t0 + k * dt, dt, rows, _REFERENCE_ODD, _REFERENCE_EVEN)

    put = _put_state if attitude else _put_rates
    # Chosen here, not by a test in the kernel: the compiler inlines every branch
    # before it prunes the dead one, and the body-by-body loop (a whole step,
    # inlined twice) added a tenth to the compile time of a kernel that advances
    # whole blocks (measured).
    steps = _measured_steps if chosen is None else _advanced_steps

    @njit_block
    @own_name(
        f"stepping.metrics.block|{stamp}|axis {principal_axis}|attitude {attitude}|{identity}"
    )
    def measured_block(w, q, inertia, params, context, axis, t0, dt, n_steps, out, start, stop):  # type: ignore[no-untyped-def]
        """The steps and measures of bodies ``start:stop``."""
        rows, block_params = _measuring_rows(
            enter, vectors, start_nominal, about, w, q, inertia, params, axis, start, stop
        )
        steps(
            step,
            measured_vectors,
            put,
            chosen,
            measure,
            torque,
            t0,
            dt,
            n_steps,
            rows,
            block_params,
            context,
        )
        _finish_rows(leave, rows, w, q, dt, out, start, stop, attitude)

    @specialise(
        njit_vector,
        f"stepping.metrics|{stamp}|axis {principal_axis}|attitude {attitude}|{identity}",
    )
    def batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status):  # type: ignore[no-untyped-def]
        n = w.shape[1]
        for block in prange((n + METRICS_BLOCK - 1) // METRICS_BLOCK):
            start = block * METRICS_BLOCK
            stop = min(start + METRICS_BLOCK, n)
            measured_block(w, q, inertia, params, context, axis, t0, dt, n_steps, out, start, stop)

    return batch


@njit(inline="always")
def _measured_steps(  # type: ignore[no-untyped-def]
    step, measured_vectors, put, advance, measure, torque, t0, dt, n_steps, rows, params, context
):
    """``n_steps`` steps of ``dt`` s from time ``t0`` of a measuring block, each
    body measured (:func:`tumble.core.metrics.observe`) in the loop that steps it
    and its new state written by ``put`` (:func:`_put_state`, or
    :func:`_put_rates` to leave the attitude). ``advance`` and ``measure`` are
    not used: the arguments are :func:`_advanced_steps`'s."""
    for k in range(n_steps):
        # As in ``measure``: the rows of the reference ``c`` as constants.
        if k % 2 == 0:
            _stepped_and_measured(
                step,
                measured_vectors,
                put,
                torque,
                t0 + k * dt,
                dt,
                rows,
                params,
                context,
                _REFERENCE_EVEN,
                _REFERENCE_ODD,
            )
        else:
            _stepped_and_measured(
                step,
                measured_vectors,
                put,
                torque,
                t0 + k * dt,
                dt,
                rows,
                params,
                context,
                _REFERENCE_ODD,
                _REFERENCE_EVEN,
            )


@njit(inline="always")
def _advanced_steps(  # type: ignore[no-untyped-def]
    step, measured_vectors, put, advance, measure, torque, t0, dt, n_steps, rows, params, context
):
    """As :func:`_measured_steps`, by a stepper's own ``advance`` of the whole
    block, with ``measure`` its observer (which reads the state from the block's
    array: ``put`` is not used)."""
    advance(
        step,
        torque,
        t0,
        dt,
        n_steps,
        _state_views(rows),
        _coefficient_views(rows),
        params,
        context,
        measure,
        (rows, t0, dt),
    )


@njit(inline="always")
def _at(rows, row, j):  # type: ignore[no-untyped-def]
    """Entry j of row ``row`` of a measuring block's array."""
    return rows[row * _ROW + j]


@njit(inline="always")
def _state_at(rows, j):  # type: ignore[no-untyped-def]
    """Body j's 7 state variables in a measuring block's array."""
    r, s = rows, _STATE * _ROW + j
    return (
        r[s],
        r[s + _ROW],
        r[s + 2 * _ROW],
        r[s + 3 * _ROW],
        r[s + 4 * _ROW],
        r[s + 5 * _ROW],
        r[s + 6 * _ROW],
    )


@njit(inline="always")
def _coefficients_at(rows, j):  # type: ignore[no-untyped-def]
    """Body j's 9 Euler coefficients in a measuring block's array."""
    r, s = rows, _COEFFICIENTS * _ROW + j
    return (
        r[s],
        r[s + _ROW],
        r[s + 2 * _ROW],
        r[s + 3 * _ROW],
        r[s + 4 * _ROW],
        r[s + 5 * _ROW],
        r[s + 6 * _ROW],
        r[s + 7 * _ROW],
        r[s + 8 * _ROW],
    )


# The rows of a measuring block's array that a stepper's own ``advance`` takes, as
# tuples of arrays of ``METRICS_BLOCK`` entries. The bounds are written out:
# numba's analysis of the parallel loop fails on slices whose bounds are
# arguments, or that come out of a nested tuple.


@njit(inline="always")
def _state_views(rows):  # type: ignore[no-untyped-def]
    """The 7 state rows."""
    return (
        rows[_STATE * _ROW : _STATE * _ROW + METRICS_BLOCK],
        rows[(_STATE + 1) * _ROW : (_STATE + 1) * _ROW + METRICS_BLOCK],
        rows[(_STATE + 2) * _ROW : (_STATE + 2) * _ROW + METRICS_BLOCK],
        rows[(_STATE + 3) * _ROW : (_STATE + 3) * _ROW + METRICS_BLOCK],
        rows[(_STATE + 4) * _ROW : (_STATE + 4) * _ROW + METRICS_BLOCK],
        rows[(_STATE + 5) * _ROW : (_STATE + 5) * _ROW + METRICS_BLOCK],
        rows[(_STATE + 6) * _ROW : (_STATE + 6) * _ROW + METRICS_BLOCK],
    )


@njit(inline="always")
def _coefficient_views(rows):  # type: ignore[no-untyped-def]
    """The 9 rows of the Euler coefficients."""
    return (
        rows[_COEFFICIENTS * _ROW : _COEFFICIENTS * _ROW + METRICS_BLOCK],
        rows[(_COEFFICIENTS + 1) * _ROW : (_COEFFICIENTS + 1) * _ROW + METRICS_BLOCK],
        rows[(_COEFFICIENTS + 2) * _ROW : (_COEFFICIENTS + 2) * _ROW + METRICS_BLOCK],
        rows[(_COEFFICIENTS + 3) * _ROW : (_COEFFICIENTS + 3) * _ROW + METRICS_BLOCK],
        rows[(_COEFFICIENTS + 4) * _ROW : (_COEFFICIENTS + 4) * _ROW + METRICS_BLOCK],
        rows[(_COEFFICIENTS + 5) * _ROW : (_COEFFICIENTS + 5) * _ROW + METRICS_BLOCK],
        rows[(_COEFFICIENTS + 6) * _ROW : (_COEFFICIENTS + 6) * _ROW + METRICS_BLOCK],
        rows[(_COEFFICIENTS + 7) * _ROW : (_COEFFICIENTS + 7) * _ROW + METRICS_BLOCK],
        rows[(_COEFFICIENTS + 8) * _ROW : (_COEFFICIENTS + 8) * _ROW + METRICS_BLOCK],
    )


@njit(inline="always")
def _put_state(rows, j, state):  # type: ignore[no-untyped-def]
    """Write body j's 7 state variables into a measuring block's array."""
    r, s = rows, _STATE * _ROW + j
    r[s], r[s + _ROW], r[s + 2 * _ROW], r[s + 3 * _ROW] = state[0], state[1], state[2], state[3]
    r[s + 4 * _ROW], r[s + 5 * _ROW], r[s + 6 * _ROW] = state[4], state[5], state[6]


@njit(inline="always")
def _put_rates(rows, j, state):  # type: ignore[no-untyped-def]
    """Write body j's first 3 state variables (ω, or L), not its quaternion, into a
    measuring block's array."""
    r, s = rows, _STATE * _ROW + j
    r[s], r[s + _ROW], r[s + 2 * _ROW] = state[0], state[1], state[2]


@njit(inline="always")
def _measuring_rows(  # type: ignore[no-untyped-def]
    enter, vectors, start_nominal, about, w, q, inertia, params, axis, start, stop
):
    """The measuring array of bodies ``start:stop`` (``_ROWS`` rows of ``_ROW``) and
    their columns of ``params`` as (rows, ``METRICS_BLOCK``). A last block of fewer
    than ``METRICS_BLOCK`` bodies is filled up with copies of its last body: the
    loops then always run ``METRICS_BLOCK`` times, which lets the compiler see
    that the rows they read and write do not overlap. The measures start from the
    state as the steps will see it: L₀ and ω₀ from ``vectors`` of the entered
    state, the numbers about the nominal axis from ``about``."""
    m = stop - start
    block_params = np.empty((params.shape[0], METRICS_BLOCK))
    shared = params.shape[1] == 1
    for r in range(params.shape[0]):
        for j in range(METRICS_BLOCK):
            block_params[r, j] = params[r, 0] if shared else params[r, start + min(j, m - 1)]
    rows = np.zeros(_ROWS * _ROW)
    for j in range(METRICS_BLOCK):
        k = start + min(j, m - 1)
        coefficients = euler_coefficients(inertia[0, k], inertia[1, k], inertia[2, k])
        c, s = coefficients, _COEFFICIENTS * _ROW + j
        rows[s], rows[s + _ROW], rows[s + 2 * _ROW] = c[0], c[1], c[2]
        rows[s + 3 * _ROW], rows[s + 4 * _ROW], rows[s + 5 * _ROW] = c[3], c[4], c[5]
        rows[s + 6 * _ROW], rows[s + 7 * _ROW], rows[s + 8 * _ROW] = c[6], c[7], c[8]
        state = enter((w[0, k], w[1, k], w[2, k], q[0, k], q[1, k], q[2, k], q[3, k]), c)
        _put_state(rows, j, state)
        l1, l2, l3, w1, w2, w3 = vectors(state, c)
        b1, b2, b3, energy = initial(l1, l2, l3, w1, w2, w3, axis[0, k], axis[1, k], axis[2, k])
        start_nominal(rows, j, b1, b2, b3)
        along, signed, squared = about(rows, j, l1, l2, l3)
        numerator, denominator = nutation_start(signed, squared)
        rows[_REFERENCE_EVEN * _ROW + j] = along
        rows[_NUMERATOR * _ROW + j] = numerator
        rows[_DENOMINATOR * _ROW + j] = denominator
        rows[_ENERGY0 * _ROW + j] = energy
        rows[_SQUARED0 * _ROW + j] = squared
        rows[_SMALLEST * _ROW + j] = squared
        rows[_LARGEST * _ROW + j] = squared
    return rows, block_params


class Nominal(NamedTuple):
    """How a measuring kernel takes the nominal axes, as two compiled functions:
    ``start(rows, j, b1, b2, b3)`` writes what ``about`` reads of body j's scaled
    axis ``b = a / |L₀|`` (:func:`tumble.core.metrics.initial`) into its block's
    array, and ``about(rows, j, l1, l2, l3)`` gives, from its L, the three numbers
    :func:`tumble.core.metrics.observe` takes: ``(c, signed, squared)``, ``c``
    whose sign changes are those of a · L, the nutation's signed square
    ``(b·L)|b·L|`` and |L|²."""

    start: Any
    about: Any


@njit(inline="always")
def _start_any(rows, j, b1, b2, b3):  # type: ignore[no-untyped-def]
    """Body j's b, whole."""
    rows[_AXIS * _ROW + j], rows[(_AXIS + 1) * _ROW + j] = b1, b2
    rows[(_AXIS + 2) * _ROW + j] = b3


@njit(inline="always")
def _about_any(rows, j, l1, l2, l3):  # type: ignore[no-untyped-def]
    """b · L, (b·L)|b·L| and |L|² of body j, for a nominal axis in any direction."""
    c = _at(rows, _AXIS, j) * l1 + _at(rows, _AXIS + 1, j) * l2 + _at(rows, _AXIS + 2, j) * l3
    return c, c * abs(c), l1 * l1 + l2 * l2 + l3 * l3


#: The measures about nominal axes in any direction.
_ANY_AXIS = Nominal(_start_any, _about_any)


def _on_axis(k: int) -> Nominal:
    """The measures about nominal axes on principal axis ``k`` (0, 1 or 2), of
    either sense. There ``b · L = b_k L_k``, so ``c`` is ``L_k`` itself: it has the
    sign of a · L or the opposite for every step of a body, which makes the same
    flips, and the first flip's time, which interpolates by a ratio of two of
    them, the same to round-off. The signed square ``(b·L)|b·L|`` is the weight
    ``b_k|b_k|``, made once a body by ``start`` and kept in row ``_AXIS + k``,
    times ``L_k|L_k|``, the ``L_k²`` of |L|² with L_k's sign (a copy of a bit):
    three multiplications fewer a body and step than :func:`_about_any`."""
    row = _AXIS + k

    @njit(inline="always", cache=False)
    def start(rows, j, b1, b2, b3):  # type: ignore[no-untyped-def]
        """Body j's weight b_k|b_k|."""
        b = (b1, b2, b3)[k]
        rows[row * _ROW + j] = b * abs(b)

    @njit(inline="always", cache=False)
    def about(rows, j, l1, l2, l3):  # type: ignore[no-untyped-def]
        """L_k, b_k|b_k| L_k|L_k| and |L|² of body j."""
        along = (l1, l2, l3)[k]
        square = along * along
        squared = (
            (square if k == 0 else l1 * l1)
            + (square if k == 1 else l2 * l2)
            + (square if k == 2 else l3 * l3)
        )
        return along, _at(rows, row, j) * math.copysign(square, along), squared

    return Nominal(start, about)


@njit(inline="always")
def _observed(measured_vectors, rows, j, state, coefficients, last, current):  # type: ignore[no-untyped-def]
    """Update body j's running measures in a measuring block's array from its new
    ``state`` (:func:`tumble.core.metrics.observe` of its L, ω and its numbers
    about its nominal axis, from ``measured_vectors(rows, j, state,
    coefficients)``), and say whether this step was its first flip. ``last`` and
    ``current``: the rows of the reference ``c`` this step reads and writes."""
    l1, l2, l3, w1, w2, w3, c, signed, squared = measured_vectors(rows, j, state, coefficients)
    (
        first,
        rows[current * _ROW + j],
        rows[_FLIPS * _ROW + j],
        rows[_NUMERATOR * _ROW + j],
        rows[_DENOMINATOR * _ROW + j],
        rows[_ENERGY_DEVIATION * _ROW + j],
        rows[_SMALLEST * _ROW + j],
        rows[_LARGEST * _ROW + j],
    ) = observe(
        l1 * w1 + l2 * w2 + l3 * w3,
        c,
        signed,
        squared,
        _at(rows, last, j),
        _at(rows, _FLIPS, j),
        _at(rows, _NUMERATOR, j),
        _at(rows, _DENOMINATOR, j),
        _at(rows, _ENERGY0, j),
        _at(rows, _ENERGY_DEVIATION, j),
        _at(rows, _SMALLEST, j),
        _at(rows, _LARGEST, j),
    )
    return first


@njit(inline="always")
def _first_flips(rows, t, dt, last, current):  # type: ignore[no-untyped-def]
    """Record the first flips of the step of ``dt`` s from time ``t``: its end and
    the ``c`` before and after it. Called only for the rare steps that have one:
    stored at every step, or under a mask in the measuring loop, they cost more
    than the test."""
    for j in range(METRICS_BLOCK):
        if _at(rows, _FLIPS, j) > 0.0 and _at(rows, _RECORDED, j) == 0.0:
            rows[_RECORDED * _ROW + j] = 1.0
            rows[_CROSSED_AT * _ROW + j] = t + dt
            rows[_BEFORE * _ROW + j] = _at(rows, last, j)
            rows[_AFTER * _ROW + j] = _at(rows, current, j)


@njit(inline="always")
def _stepped_and_measured(  # type: ignore[no-untyped-def]
    step, measured_vectors, put, torque, t, dt, rows, params, context, last, current
):
    """One step of ``dt`` s from time ``t`` of a measuring block, each body
    measured in the loop that steps it (:func:`_observed`) and its new state
    written by ``put``."""
    firsts = False
    for j in range(METRICS_BLOCK):
        coefficients = _coefficients_at(rows, j)
        new = step(torque, t, dt, _state_at(rows, j), coefficients, params, j, context)
        put(rows, j, new)
        firsts |= _observed(measured_vectors, rows, j, new, coefficients, last, current)
    if firsts:  # at most once a body in a run
        _first_flips(rows, t, dt, last, current)


@njit(inline="always")
def _measured(measured_vectors, t, dt, rows, last, current):  # type: ignore[no-untyped-def]
    """The measures of a measuring block after its step of ``dt`` s from time
    ``t`` (:func:`_observed`)."""
    firsts = False
    for j in range(METRICS_BLOCK):
        firsts |= _observed(
            measured_vectors,
            rows,
            j,
            _state_at(rows, j),
            _coefficients_at(rows, j),
            last,
            current,
        )
    if firsts:
        _first_flips(rows, t, dt, last, current)


@njit(inline="always")
def _finish_rows(leave, rows, w, q, dt, out, start, stop, attitude):  # type: ignore[no-untyped-def]
    """Write a measuring block's final state into ``w`` and, if ``attitude``, ``q``,
    and its measures into ``out`` (:func:`tumble.core.metrics.finish`)."""
    for j in range(stop - start):
        k = start + j
        final = leave(_state_at(rows, j), _coefficients_at(rows, j))
        for i in range(3):
            w[i, k] = final[i]
        if attitude:
            for i in range(4):
                q[i, k] = final[3 + i]
        (
            out[FLIPS, k],
            out[FIRST_FLIP, k],
            out[MIN_COS, k],
            out[ENERGY_DEVIATION, k],
            out[MOMENTUM_DEVIATION, k],
        ) = finish(
            dt,
            _at(rows, _FLIPS, j),
            _at(rows, _CROSSED_AT, j),
            _at(rows, _BEFORE, j),
            _at(rows, _AFTER, j),
            _at(rows, _NUMERATOR, j),
            _at(rows, _DENOMINATOR, j),
            _at(rows, _ENERGY_DEVIATION, j),
            _at(rows, _SQUARED0, j),
            _at(rows, _SMALLEST, j),
            _at(rows, _LARGEST, j),
        )
