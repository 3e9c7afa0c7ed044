"""Drivers that run one body's integration with the registry's kernels.

One driver per kind of integrator (:data:`tumble.integrators.Kind`), each
``run(integrator, problem, schedule, progress) -> Samples`` (body axes): fixed
steps in chunks between progress reports (:func:`run_stepping`), adaptive steps
sampled by dense output (:func:`run_adaptive`), or the closed forms of
:mod:`tumble.theory.motions` sampled directly (:func:`run_exact`). A body
carrying parts (rotors, dampers) runs on the integrator's kernels for parts
(:mod:`tumble.core.parts`), whose state holds the parts' momenta besides the
body's.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.body import RigidBody
from tumble.core._jit import FINITE
from tumble.errors import (
    CoarseStepWarning,
    InputError,
    IntegrationError,
    RequestTooLargeError,
)
from tumble.resources import DEFAULT_MAX_STEPS_TEXT
from tumble.theory.motions import exact_principal, gyrostat_solution, lagrange_top
from tumble.torques import BoundTorque
from tumble.units import to_si

__all__ = [
    "ADAPTIVE_CHUNK",
    "DEFAULT_STEPS_PER_TURN",
    "MAX_STEPS",
    "MIN_STEPS_PER_TURN",
    "PROGRESS_CHUNK",
    "Problem",
    "Samples",
    "Schedule",
    "recorded_samples",
    "run_adaptive",
    "run_exact",
    "run_stepping",
    "step_in_chunks",
    "time_step",
    "warn_if_coarse",
    "whole_steps",
]

Array = NDArray[np.float64]
Progress = Callable[[int, int], object] | None

#: Steps per call of a compiled kernel between progress reports.
PROGRESS_CHUNK = 1 << 17

#: Samples per call of the adaptive kernel between progress reports.
ADAPTIVE_CHUNK = 4096


@dataclass(frozen=True, eq=False)
class Problem:
    """One body's integration: the body (with its parts), its bound torque and the
    initial state in body axes (ω0, rad/s; the attitude body → space)."""

    body: RigidBody
    torque: BoundTorque
    omega0: Array
    attitude0: Array

    @property
    def layout(self) -> Any:
        """The parts' layout for their kernels (:func:`tumble.parts.kernel_layout`)."""
        return self.body.layout


@dataclass(frozen=True, eq=False)
class Samples:
    """What a driver returns: ω (n, 3) rad/s and the attitude (n, 4) body → space in
    body axes, the parts' values (n, p) (p the sum of the parts'
    :attr:`~tumble.parts.InternalPart.size`) and the number of steps taken."""

    omega: Array
    quaternion: Array
    values: Array
    steps: int


def _rigid(problem: Problem, w: Array, q: Array, steps: int) -> Samples:
    """Samples from principal-frame ω and attitudes of a body without parts."""
    body = problem.body
    values = np.zeros((len(w), 0))
    return Samples(body.from_principal(w), body.attitude_from_principal(q), values, steps)


@dataclass(frozen=True, eq=False)
class Schedule:
    """When to step and what to keep: ``times`` (n,) the recorded times (s; the
    last is the end, also when it is not a whole number of ``record_every``
    steps); ``n_steps`` steps of ``step`` s; the adaptive tolerances and the
    most steps the adaptive method may try."""

    times: Array
    n_steps: int
    step: float
    record_every: int
    rtol: float = 1e-10
    atol: float = 1e-12
    most_steps: float = 2.0**53

    @classmethod
    def build(
        cls, duration: float, step: float, record_every: int, **tolerances: float
    ) -> Schedule:
        """Whole steps over ``duration`` (s): ``step`` shortened slightly so that they
        span it; every ``record_every``-th step kept, and the last."""
        n_steps = whole_steps(duration, step)
        step = duration / n_steps
        times = np.arange(n_steps // record_every + 1) * (record_every * step)
        if n_steps % record_every != 0:
            times = np.append(times, duration)
        return cls(np.asarray(times, dtype=float), n_steps, step, record_every, **tolerances)


#: The most steps a run may take: step times are ``k · dt`` in float64, whose
#: integers are exact up to 2⁵³ (and at 1e8 steps a second, 2⁵³ steps are three years).
MAX_STEPS = 2**53


def whole_steps(duration: float, step: float) -> int:
    """The number of whole steps of about ``step`` s that span ``duration`` s.

    Raises
    ------
    RequestTooLargeError
        More than :data:`MAX_STEPS` steps.
    """
    count = duration / step * (1 - 1e-12) if step > 0.0 else math.inf
    if not count <= MAX_STEPS:
        raise RequestTooLargeError(
            f"Expected at most 2^53 steps (step times are counted in float64), got "
            f"duration / dt = {duration:.3g} s / {step:.3g} s = {count:.3g} steps: use a larger "
            "dt or a shorter duration."
        )
    return max(1, math.ceil(count))


def recorded_samples(duration: float, step: float, record_every: int) -> float:
    """How many samples :meth:`Schedule.build` would record (an upper bound,
    as a float so that it never overflows)."""
    return duration / step / record_every + 2


def step_in_chunks(
    run: Callable[[int, int], int],
    n_steps: int,
    step: float,
    progress: Progress,
) -> None:
    """Call ``run(done, count)`` (a compiled kernel's status: ``FINITE`` or the
    number of the first non-finite step) over chunks of ``PROGRESS_CHUNK``
    steps, reporting ``progress(done, n_steps)`` after each.

    Raises
    ------
    IntegrationError
        When a chunk reports a non-finite step; the message names it and its time.
    """
    done = 0
    while done < n_steps:
        count = min(PROGRESS_CHUNK, n_steps - done)
        status = int(run(done, count))
        if status != FINITE:
            raise IntegrationError(
                f"Expected the integration to stay finite, got NaN or inf at step {status} "
                f"(t = {status * step:.6g} s) with dt = {step:.3g} s: reduce dt."
            )
        done += count
        if progress is not None:
            progress(done, n_steps)


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
            w, q, inertia, torque.params, torque.context, schedule.step, count, done,
            schedule.record_every, out_w, out_q,
        )  # fmt: skip
        return int(status)

    step_in_chunks(run, schedule.n_steps, schedule.step, progress)
    if schedule.n_steps % schedule.record_every != 0:
        out_w[-1], out_q[-1] = w, q
    return _rigid(problem, out_w, out_q, schedule.n_steps)


def _run_parts_stepping(
    integrator: Any, problem: Problem, schedule: Schedule, progress: Progress
) -> Samples:
    """Fixed steps of a body carrying parts (:mod:`tumble.core.parts`)."""
    body = problem.body
    kernel = integrator.kernel("parts_single", problem.torque, problem.layout)
    y = body.kernel_state(problem.omega0, problem.attitude0)
    out = np.empty((len(schedule.times), y.size))
    out[0] = y
    torque = problem.torque
    parts = np.array(body.packed_parts)
    moments = np.ascontiguousarray(body.moments)

    def run(done: int, count: int) -> int:
        status = kernel(
            y, moments, parts, torque.params, torque.context, schedule.step, count, done,
            schedule.record_every, out,
        )  # fmt: skip
        return int(status)

    step_in_chunks(run, schedule.n_steps, schedule.step, progress)
    if schedule.n_steps % schedule.record_every != 0:
        out[-1] = y
    omega, quaternion, values = body.from_kernel_state(out)
    return Samples(omega, quaternion, values, schedule.n_steps)


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

        kernel = integrator.kernel("parts_single", torque, problem.layout)
        y = body.kernel_state(problem.omega0, problem.attitude0)
        out = np.empty((times.size, y.size))
        out[0] = y
        parts = np.array(body.packed_parts)

        def advance(start: float, stop: float, rows: slice) -> int:
            status = kernel(
                y, moments, parts, torque.params, torque.context, start, stop, control,
                times[rows], out[rows],
            )  # fmt: skip
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
                w, q, moments, torque.params, torque.context, start, stop, control,
                times[rows], out_w[rows], out_q[rows],
            )  # fmt: skip
            return int(status)

        stops = np.zeros(0)
    _adaptive_chunks(advance, times, stops, progress, control)
    steps = int(control[ACCEPTED])
    if body.parts:
        omega, quaternion, values = body.from_kernel_state(out)
        return Samples(omega, quaternion, values, steps)
    return _rigid(problem, out_w, out_q, steps)


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


def run_exact(integrator: Any, problem: Problem, schedule: Schedule, progress: Progress) -> Samples:
    """The exact solution at ``schedule.times``: torque-free (a rigid body or a
    gyrostat) or the Lagrange top under uniform gravity; no steps.

    Raises
    ------
    IntegrationError
        When the solution is not finite at some time (:func:`check_finite_motion`).
    """
    body = problem.body
    if not problem.torque.torque_free:
        # Every term is uniform gravity here (the registry's rule for the closed form).
        accelerations = (term.uniform_gravity() for term in problem.torque.terms)
        gravity = sum((g for g in accelerations if g is not None), np.zeros(3))
        top = lagrange_top(body, gravity, problem.omega0, problem.attitude0)
        samples = Samples(*top.at(schedule.times), np.zeros((schedule.times.size, 0)), 0)
    elif body.parts:
        omega, quaternion, values = gyrostat_solution(
            body, problem.omega0, problem.attitude0, schedule.times
        )
        samples = Samples(omega, quaternion, values, 0)
    else:
        w, q = exact_principal(
            body.moments,
            body.to_principal(problem.omega0),
            body.attitude_to_principal(problem.attitude0),
            schedule.times,
        )
        samples = _rigid(problem, w, q, 0)
    check_finite_motion(schedule.times, samples)
    if progress is not None:
        progress(schedule.n_steps, schedule.n_steps)
    return samples


def check_finite_motion(times: Array, samples: Samples) -> None:
    """Refuse a closed-form motion that is not finite at some of ``times`` (s).

    The closed forms are evaluated at a scale of order one, so what is left is
    a motion whose own numbers leave float64 (a rotor's momentum beyond 1e308
    kg·m²/s) or a phase lost at times so long that a turn is below round-off.

    Raises
    ------
    IntegrationError
        Naming the first such time.
    """
    arrays = (samples.omega, samples.quaternion, samples.values)
    if all(np.isfinite(array).all() for array in arrays):
        return
    finite = np.isfinite(samples.omega).all(axis=1) & np.isfinite(samples.quaternion).all(axis=1)
    finite &= np.isfinite(samples.values).all(axis=1)
    if not finite.all():
        first = int(np.argmin(finite))
        raise IntegrationError(
            "Expected the closed-form motion to stay finite, got NaN or inf at "
            f"t = {times[first]:.6g} s (sample {first}): its momentum or energy is beyond "
            "float64's range, or t is too long to keep its phase; use SI values of an "
            "ordinary size or a shorter duration."
        )


#: Fewer integration steps than this per turn of the fastest rotation trigger a
#: :class:`~tumble.errors.CoarseStepWarning`: RK4's phase error per turn grows as
#: (2π/n)⁴/120 and passes 1e-4 below about 20 steps a turn.
MIN_STEPS_PER_TURN = 20

#: Steps per turn of the fastest rotation when ``dt`` is not given: RK4 then
#: keeps ω and the attitude to about 2e-9 (relative, and rad) per turn.
DEFAULT_STEPS_PER_TURN = 200


def time_step(dt: Any, fastest: float, duration: float) -> float:
    """The time step, s: ``dt`` (any time quantity, > 0), or when it is None
    1/``DEFAULT_STEPS_PER_TURN`` of a turn at ``fastest`` rad/s (``duration``
    when nothing turns).

    Raises
    ------
    InputError
        A ``dt`` that is not a positive time.
    """
    if dt is None:
        return 2 * math.pi / fastest / DEFAULT_STEPS_PER_TURN if fastest > 0 else duration
    step = to_si(dt, "time", "dt")
    if step <= 0:
        raise InputError(f"Expected `dt` > 0 s, got {step!r}.")
    return step


def warn_if_coarse(step: float, fastest: float, what: str, stacklevel: int = 3) -> None:
    """Warn (:class:`~tumble.errors.CoarseStepWarning`) when a step of ``step`` s
    gives fewer than ``MIN_STEPS_PER_TURN`` steps per turn at ``fastest`` rad/s,
    the rate of ``what`` (e.g. "the fastest rotation")."""
    if fastest <= 0:
        return
    per_turn = 2 * math.pi / (fastest * step)
    if per_turn < MIN_STEPS_PER_TURN:
        warnings.warn(
            f"dt = {step:.3g} s gives {per_turn:.1f} steps per turn of {what} "
            f"({fastest:.3g} rad/s); below {MIN_STEPS_PER_TURN} the result is inaccurate.",
            CoarseStepWarning,
            stacklevel=stacklevel,
        )
