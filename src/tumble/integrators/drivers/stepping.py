"""The driver of the fixed-step integrators: their single-body kernels (for a
body carrying parts, the kernels of :mod:`tumble.core.parts`) called in chunks
of steps between progress reports."""

from __future__ import annotations

import itertools
from collections.abc import Callable
from typing import Any

import numpy as np

from tumble.integrators.problem import Problem, Samples, Schedule, parts_start
from tumble.integrators.steps import (
    PROGRESS_CHUNK,
    Progress,
    check_finite,
    compiled_for,
    step_in_chunks,
)

__all__ = ["ready_stepping", "run_stepping"]


def run_stepping(
    integrator: Any, problem: Problem, schedule: Schedule, progress: Progress
) -> Samples:
    """Fixed steps with the integrator's single-body kernel."""
    return ready_stepping(integrator, problem, schedule)(progress)


def ready_stepping(
    integrator: Any, problem: Problem, schedule: Schedule
) -> Callable[[Progress], Samples]:
    """:func:`run_stepping` made ready: ``run(progress) -> Samples``, which starts
    from a copy of the initial state at each call. Without progress reports, a
    run of at most ``PROGRESS_CHUNK`` steps is one call of the kernel, with
    nothing between the caller and the compiled steps but the samples' arrays;
    from the second run on, one call of its machine code
    (:func:`~tumble.integrators.steps.compiled_for`): the arguments' types are
    the same at every run. The first goes through numba's dispatch, which compiles
    or loads the kernel; a run made once does not pay for finding the machine
    code."""
    if problem.body.parts:
        return _ready_parts(integrator, problem, schedule)
    body, torque = problem.body, problem.torque
    kernel = integrator.kernel("single", torque)
    inertia = np.ascontiguousarray(body.moments)
    w0 = np.array(body.to_principal(problem.omega0), dtype=float)
    q0 = np.array(body.attitude_to_principal(problem.attitude0), dtype=float)
    params, context = torque.params, torque.context
    step, n_steps, every = schedule.step, schedule.n_steps, schedule.record_every
    rows = len(schedule.times)
    calls = [kernel]  # its machine code from the second run on
    runs = itertools.count()

    def run(progress: Progress) -> Samples:
        w, q = w0.copy(), q0.copy()
        out_w, out_q = np.empty((rows, 3)), np.empty((rows, 4))
        out_w[0], out_q[0] = w, q
        if next(runs) == 1:
            arguments = (w, q, inertia, params, context, step, n_steps, 0, every, out_w, out_q)
            calls[0] = compiled_for(kernel, arguments)

        if progress is None and n_steps <= PROGRESS_CHUNK:
            status = calls[0](w, q, inertia, params, context, step, n_steps, 0, every, out_w, out_q)
            check_finite(status, step)
        else:

            def steps(done: int, count: int) -> int:
                return int(
                    kernel(w, q, inertia, params, context, step, count, done, every, out_w, out_q)
                )

            step_in_chunks(steps, n_steps, step, progress)
        if n_steps % every != 0:
            out_w[-1], out_q[-1] = w, q
        return Samples.rigid(problem, out_w, out_q, n_steps)

    return run


def _ready_parts(
    integrator: Any, problem: Problem, schedule: Schedule
) -> Callable[[Progress], Samples]:
    """:func:`ready_stepping` for a body carrying parts (:mod:`tumble.core.parts`),
    which calls the machine code of the reading of its states as well (where every
    part's values are read compiled)."""
    start = parts_start(integrator, problem)
    kernel, moments, parts, state = start.kernel, start.moments, start.parts, start.state
    body, torque = problem.body, problem.torque
    reading = body.compiled_reading
    read_arguments = () if reading is None else reading[1]
    params, context = torque.params, torque.context
    step, n_steps, every = schedule.step, schedule.n_steps, schedule.record_every
    rows, width = len(schedule.times), state.size
    calls = [kernel, None if reading is None else reading[0]]
    runs = itertools.count()

    def run(progress: Progress) -> Samples:
        y = state.copy()
        out = np.empty((rows, width))
        out[0] = y
        if next(runs) == 1:  # the second run: the machine code from now on
            arguments = (y, moments, parts, params, context, step, n_steps, 0, every, out)
            calls[0] = compiled_for(kernel, arguments)
            if reading is not None:  # the arrays it writes are of the type of out
                calls[1] = compiled_for(reading[0], (out, *read_arguments, out, out, out))
        step_kernel, read = calls

        if progress is None and n_steps <= PROGRESS_CHUNK:
            status = step_kernel(y, moments, parts, params, context, step, n_steps, 0, every, out)
            check_finite(status, step)
        else:

            def steps(done: int, count: int) -> int:
                return int(
                    kernel(y, moments, parts, params, context, step, count, done, every, out)
                )

            step_in_chunks(steps, n_steps, step, progress)
        if n_steps % every != 0:
            out[-1] = y
        if reading is None:
            omega, quaternion, values = body.from_kernel_state(out)
        else:  # from_kernel_state's compiled path, written out: one call less
            omega, quaternion = np.empty((rows, 3)), np.empty((rows, 4))
            values = np.empty((rows, width - 7))
            read(out, *read_arguments, omega, quaternion, values)
        return Samples(omega, quaternion, values, n_steps)

    return run
