"""Adaptive embedded Runge–Kutta: Dormand–Prince 5(4) with dense output.

The method of Dormand & Prince (J. Comput. Appl. Math. 6 (1980) 19) with the
step-size control and the fourth-order continuous extension of Hairer,
Nørsett & Wanner, *Solving Ordinary Differential Equations I* (2nd ed.,
§II.4–II.6; the coefficients as in their code ``DOPRI5``). :func:`adaptive_loop`
integrates any state whose entries 3 … 6 are the attitude quaternion: a rigid
body's ω (principal-body, rad/s) and quaternion (principal → space), seven
numbers (:func:`single_kernel`), or a body carrying parts
(:mod:`tumble.core.parts`). The local error is measured, component by
component, against ``atol + rtol · max(|y_old|, |y_new|)`` in the
root-mean-square norm. The quaternion is renormalised after each accepted step
and at each sample.
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import FINITE, njit, specialise
from tumble.core.dynamics import euler_coefficients, rates

# Butcher tableau (c, a) of Dormand–Prince 5(4).
C2, C3, C4, C5 = 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0
A21 = 1.0 / 5.0
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63, A64, A65 = (
    9017.0 / 3168.0,
    -355.0 / 33.0,
    46732.0 / 5247.0,
    49.0 / 176.0,
    -5103.0 / 18656.0,
)
A71, A73, A74, A75, A76 = (
    35.0 / 384.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
)
#: The tableau as arrays for the stage loop: row s holds a[s, :s]; stage 6 is
#: the new solution (first same as last), and ``WEIGHTS_ERROR`` the error row.
NODES = np.array([0.0, C2, C3, C4, C5, 1.0, 1.0])
TABLEAU = np.zeros((7, 7))
TABLEAU[1, :1] = (A21,)
TABLEAU[2, :2] = (A31, A32)
TABLEAU[3, :3] = (A41, A42, A43)
TABLEAU[4, :4] = (A51, A52, A53, A54)
TABLEAU[5, :5] = (A61, A62, A63, A64, A65)
TABLEAU[6, :6] = (A71, 0.0, A73, A74, A75, A76)

# Error estimate: the fifth-order solution minus the embedded fourth-order one.
E1, E3, E4, E5, E6, E7 = (
    71.0 / 57600.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
)
WEIGHTS_ERROR = np.array([E1, 0.0, E3, E4, E5, E6, E7])

# Dense output (continuous extension of order 4).
WEIGHTS_DENSE = np.array(
    [
        -12715105075.0 / 11282082432.0,
        0.0,
        87487479700.0 / 32700410799.0,
        -10690763975.0 / 1880347072.0,
        701980252875.0 / 199316789632.0,
        -1453857185.0 / 822651844.0,
        69997945.0 / 29380423.0,
    ]
)

#: Bounds on the step-size change per step and the safety factor (HNW §II.4).
SAFETY = 0.9
GROWTH_MAX = 10.0
SHRINK_MAX = 0.2

#: Status codes of the adaptive kernel besides ``FINITE``.
STEP_UNDERFLOW = -2
STEP_LIMIT = -3

# Slots of the ``control`` array shared with the caller.
STEP, RTOL, ATOL, ACCEPTED, REJECTED, FAILED_AT, MOST_STEPS = 0, 1, 2, 3, 4, 5, 6


def single_kernel(torque, identity):  # type: ignore[no-untyped-def]
    """``run(w, q, inertia, params, context, t_start, t_stop, control, sample_times,
    out_w, out_q) -> status``: integrate (w, q) in place from ``t_start`` to
    ``t_stop`` (s) with adaptive steps.

    Parameters
    ----------
    w, q : (3,), (4,) state at ``t_start``; overwritten with the state at ``t_stop``.
    inertia : (3,) principal moments, kg·m²; ``params``, ``context``: the torque's
        (:mod:`tumble.core.torques`).
    control : float64 array ``[h, rtol, atol, accepted, rejected, failed_at,
        most_steps]``: ``h`` the first trial step (≤ 0: chosen here), updated to
        the next trial step; the step counts are incremented; ``failed_at``
        receives the time of a failure; ``most_steps`` bounds the steps tried
        (accepted and rejected, over all calls).
    sample_times : (m,) increasing times in (t_start, t_stop]; the state at
        each, by the dense output, is written to the rows of ``out_w``, ``out_q``.

    Returns
    -------
    ``FINITE`` (−1) on success; ``STEP_UNDERFLOW`` (−2) when the step size fell
    below round-off of t (the state became NaN or infinite, or the solution is
    singular), ``STEP_LIMIT`` (−3) when ``most_steps`` steps were tried; the
    state is then left at the last accepted step.
    """

    @njit(inline="always", cache=False)
    def rigid_rates(t, y, dy, args):  # type: ignore[no-untyped-def]
        coefficients, params, context = args
        state = (y[0], y[1], y[2], y[3], y[4], y[5], y[6])
        r = rates(torque, t, state, coefficients, params, 0, context)
        for i in range(7):
            dy[i] = r[i]

    @specialise(njit, f"adaptive.single|{identity}")
    def run(w, q, inertia, params, context, t_start, t_stop, control, sample_times, out_w, out_q):  # type: ignore[no-untyped-def]
        coefficients = euler_coefficients(inertia[0], inertia[1], inertia[2])
        y = np.empty(7)
        y[0:3] = w
        y[3:7] = q
        out = np.empty((sample_times.shape[0], 7))
        status = adaptive_loop(
            rigid_rates,
            (coefficients, params, context),
            y,
            t_start,
            t_stop,
            control,
            sample_times,
            out,
        )
        out_w[:, :] = out[:, 0:3]
        out_q[:, :] = out[:, 3:7]
        w[:] = y[0:3]
        q[:] = y[3:7]
        return status

    return run


@njit
def _error_norm(y, y_new, err, rtol, atol):  # type: ignore[no-untyped-def]
    n = y.shape[0]
    total = 0.0
    for i in range(n):
        scale = atol + rtol * max(abs(y[i]), abs(y_new[i]))
        total += (err[i] / scale) ** 2
    return math.sqrt(total / n)


@njit(inline="always")
def _dense_sample(y, stage, k, step, theta, work, row):  # type: ignore[no-untyped-def]
    """The state at ``t + θ step`` of the step from ``y`` (at t) to ``stage``, by
    Dormand–Prince's continuous extension of order 4 (HNW §II.6) from the stage
    derivatives ``k``, its quaternion scaled to unit length, into ``row``
    (``work`` (n,) scratch)."""
    n = y.shape[0]
    theta1 = 1.0 - theta
    for i in range(n):
        difference = stage[i] - y[i]
        slope = step * k[0, i] - difference
        curve = difference - step * k[6, i] - slope
        total = 0.0
        for j in range(7):
            total += WEIGHTS_DENSE[j] * k[j, i]
        work[i] = y[i] + theta * (
            difference + theta1 * (slope + theta * (curve + theta1 * step * total))
        )
    _normalised_into(row, work)


@njit(inline="always")
def _normalised_into(target, source):  # type: ignore[no-untyped-def]
    """``source`` copied into ``target``, entries 3 … 6 (a quaternion) scaled to
    unit length."""
    scale = 1.0 / math.sqrt(source[3] ** 2 + source[4] ** 2 + source[5] ** 2 + source[6] ** 2)
    for i in range(source.shape[0]):
        target[i] = source[i]
    for i in range(3, 7):
        target[i] = source[i] * scale


@njit(inline="always")
def adaptive_loop(f, args, y, t_start, t_stop, control, sample_times, out):  # type: ignore[no-untyped-def]
    """Dormand–Prince 5(4) for any state ``y`` (n,) whose entries 3 … 6 are a unit
    quaternion, in place from ``t_start`` to ``t_stop``: ``f(t, y, dy, args)``
    writes ẏ at time t into ``dy``; the state at each of ``sample_times`` is
    written to the rows of ``out`` (m, n). ``control`` and the status as in
    :func:`single_kernel`."""
    n = y.shape[0]
    rtol = control[RTOL]
    atol = control[ATOL]
    k = np.empty((7, n))  # stage derivatives k[s, :]
    stage = np.empty(n)
    err = np.empty(n)
    t = t_start
    h = control[STEP]
    first = 0  # the first stage to evaluate: 0 on the first step, then 1 (k[0] = last k[6])
    next_sample = 0
    n_samples = sample_times.shape[0]
    rejected_last = False
    while t < t_stop:
        if control[ACCEPTED] + control[REJECTED] >= control[MOST_STEPS]:
            control[FAILED_AT] = t
            return STEP_LIMIT
        # ``h`` is the proposed step; the last one is cut (or stretched by up to
        # 1 %) to land on t_stop, and a cut step does not shrink the proposal.
        clipped = t + 1.01 * h >= t_stop
        step = t_stop - t if clipped else h
        valid = step > 1e-14 * max(abs(t), abs(t_stop)) and math.isfinite(step)
        if not valid and not (first == 0 and h <= 0.0):  # no proposal yet: chosen below
            control[FAILED_AT] = t
            return STEP_UNDERFLOW
        for s in range(first, 7):
            for i in range(n):
                total = 0.0
                for j in range(s):
                    total += TABLEAU[s, j] * k[j, i]
                stage[i] = y[i] + step * total
            f(t + NODES[s] * step, stage, k[s], args)
            if s == 0 and h <= 0.0:
                # No step proposed: the first from the sizes of y and ẏ (HNW §II.4).
                h = min(_initial_step(y, k[0], rtol, atol), t_stop - t)
                step = t_stop - t if t + 1.01 * h >= t_stop else h
                clipped = t + 1.01 * h >= t_stop
        first = 1
        for i in range(n):
            total = 0.0
            for j in range(7):
                total += WEIGHTS_ERROR[j] * k[j, i]
            err[i] = step * total
        norm = _error_norm(y, stage, err, rtol, atol)
        if not math.isfinite(norm):
            h = step * SHRINK_MAX
            rejected_last = True
            control[REJECTED] += 1
            continue
        factor = SAFETY * norm ** (-0.2) if norm > 0.0 else GROWTH_MAX
        if norm > 1.0:
            h = step * max(SHRINK_MAX, factor)
            rejected_last = True
            control[REJECTED] += 1
            continue
        # Accepted: samples in (t, t + step] from the continuous extension.
        t_new = t_stop if clipped else t + step
        while next_sample < n_samples and sample_times[next_sample] <= t_new:
            theta = (sample_times[next_sample] - t) / step
            _dense_sample(y, stage, k, step, theta, err, out[next_sample])
            next_sample += 1
        control[ACCEPTED] += 1
        t = t_new
        _normalised_into(y, stage)
        # First same as last: k[6] was taken at the unnormalised new state,
        # which differs from y by the local error only.
        k[0, :] = k[6, :]
        growth = min(GROWTH_MAX, factor)
        if rejected_last:
            growth = min(1.0, growth)
        rejected_last = False
        h = max(h, step * growth) if clipped else step * growth
        control[STEP] = h
    return FINITE


@njit
def _initial_step(y, dy, rtol, atol):  # type: ignore[no-untyped-def]
    """``0.01 ‖y‖ / ‖ẏ‖`` in the error norm: the first stage of the starting
    step of HNW §II.4 (the controller corrects it within a few steps)."""
    size = 0.0
    rate = 0.0
    for i in range(y.shape[0]):
        scale = atol + rtol * abs(y[i])
        size += (y[i] / scale) ** 2
        rate += (dy[i] / scale) ** 2
    if size < 1e-10 or rate < 1e-10:
        return 1e-6
    return 0.01 * math.sqrt(size / rate)
