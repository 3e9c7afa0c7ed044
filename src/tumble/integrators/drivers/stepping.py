"""The driver of the fixed-step integrators: their single-body kernels (for a
body carrying parts, the kernels of :mod:`tumble.core.parts`) called in chunks
of steps between progress reports."""

from __future__ import annotations

from typing import Any

import numpy as np

from tumble.integrators.problem import Problem, Samples, Schedule, parts_start
from tumble.integrators.steps import Progress, step_in_chunks

__all__ = ["run_stepping"]


def run_stepping(
    integrator: Any, problem: Problem, schedule: Schedule, progress: Progress
) -> Samples:
    """Fixed steps with the integrator's single-body kernel."""
    if problem.body.parts:
        return _run_parts_stepping(integrator, problem, schedule, progress)
    body = problem.body
    kernel = integrator.kernel("single", problem.torque)
    rows = len(schedule.times)
    out_w = np.empty((rows, 3))
    out_q = np.empty((rows, 4))
    w = np.array(body.to_principal(problem.omega0), dtype=float)
    q = np.array(body.attitude_to_principal(problem.attitude0), dtype=float)
    out_w[0], out_q[0] = w, q
    torque = problem.torque
    inertia = np.ascontiguousarray(body.moments)

    def run(done: int, count: int) -> int:
        status = kernel(
            w,
            q,
            inertia,
            torque.params,
            torque.context,
            schedule.step,
            count,
            done,
            schedule.record_every,
            out_w,
            out_q,
        )
        return int(status)

    step_in_chunks(run, schedule.n_steps, schedule.step, progress)
    if schedule.n_steps % schedule.record_every != 0:
        out_w[-1], out_q[-1] = w, q
    return Samples.rigid(problem, out_w, out_q, schedule.n_steps)


def _run_parts_stepping(
    integrator: Any, problem: Problem, schedule: Schedule, progress: Progress
) -> Samples:
    """Fixed steps of a body carrying parts (:mod:`tumble.core.parts`)."""
    start = parts_start(integrator, problem)
    kernel, moments, parts = start.kernel, start.moments, start.parts
    y = start.state.copy()
    out = np.empty((len(schedule.times), y.size))
    out[0] = y
    torque = problem.torque

    def run(done: int, count: int) -> int:
        status = kernel(
            y,
            moments,
            parts,
            torque.params,
            torque.context,
            schedule.step,
            count,
            done,
            schedule.record_every,
            out,
        )
        return int(status)

    step_in_chunks(run, schedule.n_steps, schedule.step, progress)
    if schedule.n_steps % schedule.record_every != 0:
        out[-1] = y
    omega, quaternion, values = problem.body.from_kernel_state(out)
    return Samples(omega, quaternion, values, schedule.n_steps)
