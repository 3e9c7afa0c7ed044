"""Batched integrators that measure each body's motion while they step it.

A sweep over millions of bodies cannot keep their histories, so the measures
it reports are accumulated step by step, in registers, by the same compiled
loops that advance the state (the integrators of :mod:`tumble.core.rigid` and
:mod:`tumble.core.splitting`, with the same arithmetic).

Arrays are structures of arrays, as in :func:`tumble.core.rigid.rk4_batch`:
``w`` (3, N) principal-frame angular velocities (rad/s), ``q`` (4, N)
quaternions (principal → space), ``inertia`` (3, N) principal moments
(kg·m²), ``params`` (``N_TORQUE_PARAMS``, M) the packed torque, shared (M = 1)
or per body (M = N), and ``axis`` (3, N) each body's *nominal axis*: a unit
vector in principal-body coordinates (the axis it was spun about).

After every step, with ``L = I ω`` the angular momentum in body coordinates
and ``a`` the nominal axis, the kernels update the rows of ``out`` (5, N):

0. the number of sign changes of ``a · ω`` (equivalently of ``a · L``): each
   one is a *flip*, the nominal axis crossing the plane perpendicular to L, so
   a body spun near its intermediate axis flips twice per period of ω(t);
1. the time of the first flip, s, from linear interpolation of ``a · ω``
   between the two steps around it (``inf`` if there is none; should the step
   before land exactly on zero, the last non-zero value stands in for it);
2. the smallest ``a · L / |L|`` over the run, the initial state included: the
   cosine of the largest angle between the nominal axis and L (the nutation);
3. the largest ``|2 E − 2 E₀|``, with ``2 E = ω · I ω`` (J, times two);
4. the largest ``| |L| − |L₀| |`` (kg·m²/s).
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit, njit_parallel, njit_vector, prange
from tumble.core.rigid import (
    BLOCK,
    FINITE,
    _block_params,
    any_attitude_torque,
    has_attitude_torque,
    load_block,
    no_extra_torque,
    rk4_body_step,
)
from tumble.core.splitting import splitting_step

#: Rows of the ``out`` array the kernels fill.
N_METRICS = 5
FLIPS, FIRST_FLIP, MIN_COS, ENERGY_DEVIATION, MOMENTUM_DEVIATION = range(N_METRICS)


@njit(inline="always")
def _observe(  # type: ignore[no-untyped-def]
    t, w1, w2, w3, i1, i2, i3, a1, a2, a3, reference, flips, crossed_at, before, after,
    lowest, energy0, energy_dev, smallest, largest,
):  # fmt: skip
    """Update one body's running measures after the step that ended at time ``t``.

    ``reference`` is the last non-zero ``a · ω`` (so a sample exactly on zero
    neither hides nor doubles a flip). At the first flip, its time ``t`` and the
    values of ``a · ω`` on both sides are kept, to interpolate once at the end.
    The nutation is tracked as ``min (a·L)|a·L| / |L|²`` (the signed squared
    cosine) and |L| by the extremes of |L|²: one division and no square root
    per step. Written without branches so the loop over a block vectorises.
    """
    along = a1 * w1 + a2 * w2 + a3 * w3
    crossing = reference * along < 0.0
    first = crossing and flips == 0.0
    flips += 1.0 if crossing else 0.0
    crossed_at = t if first else crossed_at
    before = reference if first else before
    after = along if first else after
    reference = along if along != 0.0 else reference
    l1 = i1 * w1
    l2 = i2 * w2
    l3 = i3 * w3
    squared = l1 * l1 + l2 * l2 + l3 * l3
    c = a1 * l1 + a2 * l2 + a3 * l3
    lowest = min(lowest, c * abs(c) / squared if squared > 0.0 else 1.0)
    energy_dev = max(energy_dev, abs(l1 * w1 + l2 * w2 + l3 * w3 - energy0))
    smallest = min(smallest, squared)
    largest = max(largest, squared)
    return reference, flips, crossed_at, before, after, lowest, energy_dev, smallest, largest


@njit(inline="always")
def _initial(w1, w2, w3, i1, i2, i3, a1, a2, a3):  # type: ignore[no-untyped-def]
    """(a · ω, 2 E, |L|², signed squared cosine) of the initial state."""
    l1 = i1 * w1
    l2 = i2 * w2
    l3 = i3 * w3
    squared = l1 * l1 + l2 * l2 + l3 * l3
    c = a1 * l1 + a2 * l2 + a3 * l3
    ratio = c * abs(c) / squared if squared > 0.0 else 1.0
    return a1 * w1 + a2 * w2 + a3 * w3, l1 * w1 + l2 * w2 + l3 * w3, squared, ratio


@njit(inline="always")
def _finish(dt, flips, crossed_at, before, after, lowest, energy_dev, squared0, smallest, largest):  # type: ignore[no-untyped-def]
    """The measures of ``out`` from the running ones."""
    first = math.inf
    if flips > 0.0:
        gap = before - after
        first = crossed_at - dt + (dt * before / gap if gap != 0.0 else 0.0)
    cosine = math.copysign(math.sqrt(abs(lowest)), lowest)
    size = math.sqrt(squared0)
    momentum_dev = max(abs(math.sqrt(largest) - size), abs(math.sqrt(smallest) - size))
    return flips, first, cosine, energy_dev, momentum_dev


@njit_vector
def rk4_metrics_batch(w, q, inertia, params, axis, dt, n_steps, out):  # type: ignore[no-untyped-def]
    """Advance N bodies by ``n_steps`` RK4 steps of ``dt`` s and measure them.

    The stepping is :func:`tumble.core.rigid.rk4_batch`'s (blocks of
    ``BLOCK`` bodies in parallel, vectorised within a block); ``out`` (5, N)
    receives the measures listed in the module's docstring. A body whose state
    became NaN or infinite keeps it; the caller checks.
    """
    n = w.shape[1]
    n_blocks = (n + BLOCK - 1) // BLOCK
    attitude_torque = any_attitude_torque(params)
    for block in prange(n_blocks):
        start = block * BLOCK
        stop = min(start + BLOCK, n)
        if attitude_torque:
            _metrics_block(w, q, inertia, params, axis, dt, n_steps, out, start, stop, True)
        else:
            _metrics_block(w, q, inertia, params, axis, dt, n_steps, out, start, stop, False)


@njit(inline="always")
def _metrics_block(  # type: ignore[no-untyped-def]
    w, q, inertia, params, axis, dt, n_steps, out, start, stop, attitude_torque
):
    """One block of :func:`rk4_metrics_batch`; ``attitude_torque`` is a
    literal, so the torque-free loop has no branch."""
    m = stop - start
    w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3 = load_block(w, q, inertia, start, stop)
    i1 = inertia[0, start:stop]
    i2 = inertia[1, start:stop]
    i3 = inertia[2, start:stop]
    a1 = axis[0, start:stop]
    a2 = axis[1, start:stop]
    a3 = axis[2, start:stop]
    p = _block_params(params, start, m)
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
        along, energy, squared, ratio = _initial(
            w1[j], w2[j], w3[j], i1[j], i2[j], i3[j], a1[j], a2[j], a3[j]
        )
        reference[j] = along
        lowest[j] = ratio
        energy0[j] = energy
        squared0[j] = squared
        smallest[j] = squared
        largest[j] = squared
    for step in range(n_steps):
        t = (step + 1) * dt
        for j in range(m):
            rk4_body_step(
                j, w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, p, dt, attitude_torque
            )
        # A loop of its own: with the measures in the stepping loop, that loop
        # stores to too many arrays for the compiler to vectorise it (5× slower).
        for j in range(m):
            (
                reference[j], flips[j], crossed_at[j], before[j], after[j], lowest[j],
                energy_dev[j], smallest[j], largest[j],
            ) = _observe(
                t, w1[j], w2[j], w3[j], i1[j], i2[j], i3[j], a1[j], a2[j], a3[j], reference[j],
                flips[j], crossed_at[j], before[j], after[j], lowest[j], energy0[j],
                energy_dev[j], smallest[j], largest[j],
            )  # fmt: skip
    for j in range(m):
        k = start + j
        w[0, k] = w1[j]
        w[1, k] = w2[j]
        w[2, k] = w3[j]
        q[0, k] = q0[j]
        q[1, k] = q1[j]
        q[2, k] = q2[j]
        q[3, k] = q3[j]
        (
            out[FLIPS, k], out[FIRST_FLIP, k], out[MIN_COS, k], out[ENERGY_DEVIATION, k],
            out[MOMENTUM_DEVIATION, k],
        ) = _finish(
            dt, flips[j], crossed_at[j], before[j], after[j], lowest[j], energy_dev[j],
            squared0[j], smallest[j], largest[j],
        )  # fmt: skip


@njit_parallel
def splitting_metrics_batch(w, q, inertia, params, axis, dt, n_steps, order, out, status):  # type: ignore[no-untyped-def]
    """Advance N bodies by ``n_steps`` splitting steps (``order`` 2: Strang, 4:
    Yoshida) and measure them, one body per thread at a time.

    The stepping is :func:`tumble.core.splitting.splitting_batch`'s; ``out``
    (5, N) receives the measures, ``status`` (N,) int64 ``FINITE`` or the
    number of the first step that was not finite (the body then keeps its last
    finite state, and its measures stop there).
    """
    n = w.shape[1]
    stride = 0 if params.shape[1] == 1 else 1
    for body in prange(n):
        status[body] = _splitting_body(
            w[:, body], q[:, body], inertia[:, body], params[:, body * stride], axis[:, body],
            dt, n_steps, order, out[:, body],
        )  # fmt: skip


@njit
def _splitting_body(w, q, inertia, params, axis, dt, n_steps, order, out):  # type: ignore[no-untyped-def]
    i1 = inertia[0]
    i2 = inertia[1]
    i3 = inertia[2]
    a1 = axis[0]
    a2 = axis[1]
    a3 = axis[2]
    attitude_torque = has_attitude_torque(params)
    l1, l2, l3 = i1 * w[0], i2 * w[1], i3 * w[2]
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    reference, energy0, squared0, lowest = _initial(w[0], w[1], w[2], i1, i2, i3, a1, a2, a3)
    flips = 0.0
    crossed_at = before = after = 0.0
    energy_dev = 0.0
    smallest = largest = squared0
    status = FINITE
    for k in range(n_steps):
        t = k * dt
        m1, m2, m3, p0, p1, p2, p3 = splitting_step(
            t, dt, order, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque,
            no_extra_torque, 0.0,
        )  # fmt: skip
        norm = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3)
        if not (math.isfinite(norm) and math.isfinite(m1 + m2 + m3) and norm > 0.0):
            status = k + 1
            break
        l1, l2, l3 = m1, m2, m3
        q0, q1, q2, q3 = p0 / norm, p1 / norm, p2 / norm, p3 / norm
        reference, flips, crossed_at, before, after, lowest, energy_dev, smallest, largest = (
            _observe(
                (k + 1) * dt, l1 / i1, l2 / i2, l3 / i3, i1, i2, i3, a1, a2, a3, reference, flips,
                crossed_at, before, after, lowest, energy0, energy_dev, smallest, largest,
            )
        )  # fmt: skip
    w[0], w[1], w[2] = l1 / i1, l2 / i2, l3 / i3
    q[0], q[1], q[2], q[3] = q0, q1, q2, q3
    (
        out[FLIPS], out[FIRST_FLIP], out[MIN_COS], out[ENERGY_DEVIATION], out[MOMENTUM_DEVIATION],
    ) = _finish(
        dt, flips, crossed_at, before, after, lowest, energy_dev, squared0, smallest, largest
    )  # fmt: skip
    return status
