"""The driver of the adaptive integrator: its kernel advances from one sample
time to the next by dense output, in chunks of samples between progress
reports, never across a switch of a part's inputs."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core._jit import FINITE
from tumble.errors import IntegrationError, RequestTooLargeError
from tumble.integrators.problem import Problem, Samples, Schedule, parts_start
from tumble.integrators.steps import Progress
from tumble.resources import DEFAULT_MAX_STEPS_TEXT

__all__ = ["ADAPTIVE_CHUNK", "run_adaptive"]

Array = NDArray[np.float64]

#: Samples per call of the adaptive kernel between progress reports.
ADAPTIVE_CHUNK = 4096


def run_adaptive(
    integrator: Any, problem: Problem, schedule: Schedule, progress: Progress
) -> Samples:
    """Adaptive steps, sampled at ``schedule.times`` (times[0] = 0) by dense output."""
    from tumble.core.adaptive import ACCEPTED

    body = problem.body
    torque = problem.torque
    times = schedule.times
    moments = np.ascontiguousarray(body.moments)
    control = np.array([0.0, schedule.rtol, schedule.atol, 0.0, 0.0, 0.0, schedule.most_steps])
    if body.parts:
        from tumble.parts import switch_times

        start = parts_start(integrator, problem)
        kernel, parts = start.kernel, start.parts
        y = start.state.copy()
        out = np.empty((times.size, y.size))
        out[0] = y

        def advance(start: float, stop: float, rows: slice) -> int:
            status = kernel(
                y,
                moments,
                parts,
                torque.params,
                torque.context,
                start,
                stop,
                control,
                times[rows],
                out[rows],
            )
            return int(status)

        stops = switch_times(body.parts, float(times[-1]))
    else:
        kernel = integrator.kernel("single", torque)
        out_w = np.empty((times.size, 3))
        out_q = np.empty((times.size, 4))
        w = np.array(body.to_principal(problem.omega0), dtype=float)
        q = np.array(body.attitude_to_principal(problem.attitude0), dtype=float)
        out_w[0], out_q[0] = w, q

        def advance(start: float, stop: float, rows: slice) -> int:
            status = kernel(
                w,
                q,
                moments,
                torque.params,
                torque.context,
                start,
                stop,
                control,
                times[rows],
                out_w[rows],
                out_q[rows],
            )
            return int(status)

        stops = np.zeros(0)
    _adaptive_chunks(advance, times, stops, progress, control)
    steps = int(control[ACCEPTED])
    if body.parts:
        omega, quaternion, values = body.from_kernel_state(out)
        return Samples(omega, quaternion, values, steps)
    return Samples.rigid(problem, out_w, out_q, steps)


def _adaptive_chunks(
    advance: Callable[[float, float, slice], int],
    times: Array,
    stops: Array,
    progress: Progress,
    control: Array,
) -> None:
    """Call ``advance(start, stop, rows)`` over chunks of at most ``ADAPTIVE_CHUNK``
    samples, each ending at a sample time or at one of ``stops`` (the switches
    of the parts' schedules, where the solution has a kink the steps must not
    straddle); ``rows`` are the samples in (start, stop].

    Raises
    ------
    RequestTooLargeError
        When the kernel has tried the most steps ``control`` allows.
    IntegrationError
        When the step size fell below round-off.
    """
    from tumble.core.adaptive import ACCEPTED, FAILED_AT, MOST_STEPS, REJECTED, STEP_LIMIT

    total = times.size - 1
    start = float(times[0])
    first = 1
    while first < times.size:
        last = min(first + ADAPTIVE_CHUNK, times.size)
        stop = float(times[last - 1])
        inside = stops[(stops > start) & (stops < stop)]
        if inside.size:
            stop = float(inside[0])
            last = first + int(np.searchsorted(times[first:last], stop, side="right"))
        status = advance(start, stop, slice(first, last))
        if status == STEP_LIMIT:
            tried = control[ACCEPTED] + control[REJECTED]
            raise RequestTooLargeError(
                f"Expected the adaptive integration to end within {control[MOST_STEPS]:.3g} "
                f"steps (max_steps), got {tried:.3g} steps to t = {control[FAILED_AT]:.6g} s "
                f"of {times[-1]:.6g} s: the motion is too fast or too stiff for it; ask for a "
                "shorter duration, give dt with a fixed-step method (rk4), or raise "
                f"`max_steps=` (default {DEFAULT_MAX_STEPS_TEXT})."
            )
        if status != FINITE:
            raise IntegrationError(
                "Expected the integration to stay finite, got a step size below round-off at "
                f"t = {control[FAILED_AT]:.6g} s (the state became NaN or infinite, "
                "or the torque is singular there)."
            )
        start = stop
        first = last
        if progress is not None:
            progress(last - 1, total)
