"""The measures of a sweep, taken of bodies carrying parts after every step.

A sweep measures each body as :mod:`tumble.core.metrics` says of a rigid body,
with H, the total angular momentum, for L, and twice the energy of the body and
its parts, ``ω · H + Σ ε`` (:func:`tumble.core.parts.measured_energy`), for
``ω · I ω``. The running measures of one body are a column of :data:`RUNNING`
rows, updated by the functions :func:`body_measures` makes and written out by
:func:`finish_measures`: the one body per thread of :func:`measuring_kernel`
(the reference) and the blocks of bodies of
:func:`tumble.core.part_blocks.block_measuring_kernel` (which sweeps run) take the
same.
"""

from __future__ import annotations

import numpy as np

from tumble.core._jit import FINITE, file_stamp, njit, njit_parallel, prange, specialise
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
from tumble.core.parts import finite_state, layout_identity, measured_energy, part_model

__all__ = ["RUNNING", "body_measures", "finish_measures", "measuring_kernel"]


#: The rows of one body's running measures:
#: the axis b of :func:`tumble.core.metrics.initial`, then the measures of
#: :func:`tumble.core.metrics.observe`, the first flip's time and its two values of
#: c, twice the energy at the start.
RUNNING = (
    "b1",
    "b2",
    "b3",
    "reference",
    "squared0",
    "numerator",
    "denominator",
    "flips",
    "deviation",
    "smallest",
    "largest",
    "crossed_at",
    "before",
    "after",
    "twice0",
)
(
    _B1,
    _B2,
    _B3,
    _REFERENCE,
    _SQUARED0,
    _NUMERATOR,
    _DENOMINATOR,
    _FLIPS,
    _DEVIATION,
    _SMALLEST,
    _LARGEST,
    _CROSSED_AT,
    _BEFORE,
    _AFTER,
    _TWICE0,
) = range(len(RUNNING))


def body_measures(layout):  # type: ignore[no-untyped-def]
    """``(start, after)``: the measures of one body (its state ``y`` an array or a
    tuple), column ``mc`` of ``m`` its running measures (:data:`RUNNING`):
    ``start(y, inverse, parts, pc, a1, a2, a3, m, mc)`` before the first step,
    about the nominal axis a (principal-platform axes); ``after(y, inverse,
    parts, pc, m, mc, time)`` after a step that ends at ``time`` (s)."""
    velocity = part_model(layout).velocity
    shares = measured_energy(layout)

    @njit(inline="always", cache=False)
    def twice_energy(y, inverse, parts, pc):  # type: ignore[no-untyped-def]
        w1, w2, w3 = velocity(y, inverse, parts, pc)
        return y[0] * w1 + y[1] * w2 + y[2] * w3 + shares(y, parts, pc, (w1, w2, w3)), w1, w2, w3

    @njit(inline="always", cache=False)
    def start(y, inverse, parts, pc, a1, a2, a3, m, mc):  # type: ignore[no-untyped-def]
        twice0, w1, w2, w3 = twice_energy(y, inverse, parts, pc)
        m[_B1, mc], m[_B2, mc], m[_B3, mc], _ = initial(y[0], y[1], y[2], w1, w2, w3, a1, a2, a3)
        reference = m[_B1, mc] * y[0] + m[_B2, mc] * y[1] + m[_B3, mc] * y[2]
        squared0 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2]
        m[_NUMERATOR, mc], m[_DENOMINATOR, mc] = nutation_start(
            reference * abs(reference), squared0
        )
        m[_REFERENCE, mc], m[_SQUARED0, mc], m[_SMALLEST, mc], m[_LARGEST, mc] = (
            reference,
            squared0,
            squared0,
            squared0,
        )
        m[_FLIPS, mc], m[_DEVIATION, mc], m[_CROSSED_AT, mc], m[_BEFORE, mc], m[_AFTER, mc] = (
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
        )
        m[_TWICE0, mc] = twice0

    @njit(inline="always", cache=False)
    def after(y, inverse, parts, pc, m, mc, time):  # type: ignore[no-untyped-def]
        twice, _, _, _ = twice_energy(y, inverse, parts, pc)
        c = m[_B1, mc] * y[0] + m[_B2, mc] * y[1] + m[_B3, mc] * y[2]
        last = m[_REFERENCE, mc]
        (
            first,
            m[_REFERENCE, mc],
            m[_FLIPS, mc],
            m[_NUMERATOR, mc],
            m[_DENOMINATOR, mc],
            m[_DEVIATION, mc],
            m[_SMALLEST, mc],
            m[_LARGEST, mc],
        ) = observe(
            twice,
            c,
            c * abs(c),
            y[0] * y[0] + y[1] * y[1] + y[2] * y[2],
            last,
            m[_FLIPS, mc],
            m[_NUMERATOR, mc],
            m[_DENOMINATOR, mc],
            m[_TWICE0, mc],
            m[_DEVIATION, mc],
            m[_SMALLEST, mc],
            m[_LARGEST, mc],
        )
        # Written whether or not this step flipped first, so that a block's loop
        # over its bodies has no branch to keep it from being vectorised.
        m[_CROSSED_AT, mc] = time if first else m[_CROSSED_AT, mc]
        m[_BEFORE, mc] = last if first else m[_BEFORE, mc]
        m[_AFTER, mc] = c if first else m[_AFTER, mc]

    return start, after


@njit(inline="always")
def finish_measures(m, mc, out, energy0, body, dt):  # type: ignore[no-untyped-def]
    """A body's running measures, column ``mc`` of ``m`` (:data:`RUNNING`), as its
    measures, into column ``body`` of ``out`` (``N_METRICS``, N), and twice its
    energy at the start into ``energy0[body]``; ``dt`` the step (s)."""
    (
        out[FLIPS, body],
        out[FIRST_FLIP, body],
        out[MIN_COS, body],
        out[ENERGY_DEVIATION, body],
        out[MOMENTUM_DEVIATION, body],
    ) = finish(
        dt,
        m[_FLIPS, mc],
        m[_CROSSED_AT, mc],
        m[_BEFORE, mc],
        m[_AFTER, mc],
        m[_NUMERATOR, mc],
        m[_DENOMINATOR, mc],
        m[_DEVIATION, mc],
        m[_SQUARED0, mc],
        m[_SMALLEST, mc],
        m[_LARGEST, mc],
    )
    energy0[body] = m[_TWICE0, mc]


def measuring_kernel(make_step, torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """``measure(y, moments, parts, params, context, axis, t0, dt, n_steps, out,
    energy0, status)``: as :func:`tumble.core.parts.batch_kernel`, each body
    measured after every step about its nominal axis (``axis`` (3, N),
    principal-platform axes) into ``out`` (``N_METRICS``, N) (:func:`body_measures`);
    ``energy0`` (N,) receives twice its energy at the start."""
    step = make_step(torque, drive, layout)
    start, after = body_measures(layout)
    key = layout_identity(layout)

    @specialise(njit, f"parts.measured|{file_stamp(make_step)}|{key}|{identity}")
    def one_body(  # type: ignore[no-untyped-def]
        y, moments, parts, pc, params, column, context, axis, t0, dt, n_steps, out, energy0, body
    ):
        inverse = 1.0 / moments
        system = (moments, inverse, parts, pc, params, column, context)
        n = y.shape[0]
        saved = np.empty(n)
        running = np.empty((len(RUNNING), 1))
        start(y, inverse, parts, pc, axis[0, body], axis[1, body], axis[2, body], running, 0)
        status = FINITE
        first_step = int(t0 / dt + 0.5) if dt > 0.0 else 0
        # The step and its check written out as in tumble.core.parts' loop: behind
        # a function that returns whether the step was kept, the loop ran 20 %
        # slower (bench/batch_parts.py).
        for k in range(n_steps):
            number = first_step + k
            for i in range(n):
                saved[i] = y[i]
            step(number * dt, dt, y, system)
            if not finite_state(y):
                for i in range(n):
                    y[i] = saved[i]
                status = number + 1
                break
            after(y, inverse, parts, pc, running, 0, (number + 1) * dt)
        finish_measures(running, 0, out, energy0, body, dt)
        return status

    @specialise(njit_parallel, f"parts.measure|{file_stamp(make_step)}|{key}|{identity}")
    def measure(y, moments, parts, params, context, axis, t0, dt, n_steps, out, energy0, status):  # type: ignore[no-untyped-def]
        part_stride = 0 if parts.shape[1] == 1 else 1
        param_stride = 0 if params.shape[1] == 1 else 1
        for body in prange(y.shape[1]):
            state = y[:, body].copy()
            status[body] = one_body(
                state,
                moments[:, body].copy(),
                parts,
                body * part_stride,
                params,
                body * param_stride,
                context,
                axis,
                t0,
                dt,
                n_steps,
                out,
                energy0,
                body,
            )
            y[:, body] = state

    return measure
