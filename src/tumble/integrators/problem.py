"""What a single-body driver takes and gives back: the :class:`Problem` (the
body, its bound torque, the initial state), the :class:`Schedule` (the steps and
the recorded times) and the :class:`Samples` (the recorded states, body axes)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from tumble.body import RigidBody
from tumble.errors import InputError
from tumble.integrators.limits import check_recording
from tumble.integrators.steps import time_step, warn_if_coarse, whole_steps
from tumble.torques import BoundTorque

__all__ = ["PartsStart", "Problem", "Samples", "Schedule", "parts_start"]

Array = NDArray[np.float64]


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
        """The parts' layout for their kernels (:func:`tumble.parts.pack_parts`)."""
        return self.body.layout


@dataclass(frozen=True, eq=False)
class PartsStart:
    """What a driver hands the kernels of a body carrying parts, before any step:
    the kernel, the initial kernel state (7 + m,) (read-only: each run steps a
    copy), the packed parts (rows, 1) and the principal moments (3,), kg·m²."""

    kernel: Any
    state: Array
    parts: Array
    moments: Array


@lru_cache(maxsize=64)
def parts_start(integrator: Any, problem: Problem) -> PartsStart:
    """The :class:`PartsStart` of ``integrator``'s single-body kernel for ``problem``,
    made once for the last problems asked (both immutable, named by identity):
    the calls of :func:`tumble.simulate` that describe the same motion share a
    problem."""
    body = problem.body
    state = body.kernel_state(problem.omega0, problem.attitude0)
    state.flags.writeable = False
    return PartsStart(
        integrator.kernel("parts_single", problem.torque, problem.layout),
        state,
        np.array(body.packed_parts),
        np.ascontiguousarray(body.moments),
    )


class Samples(NamedTuple):
    """What a driver returns: ω (n, 3) rad/s and the attitude (n, 4) body → space in
    body axes, the parts' values (n, p) (p the sum of the parts'
    :attr:`~tumble.parts.InternalPart.size`) and the number of steps taken (a
    tuple: made at every run, at the cost of one)."""

    omega: Array
    quaternion: Array
    values: Array
    steps: int

    @classmethod
    def rigid(cls, problem: Problem, w: Array, q: Array, steps: int) -> Samples:
        """From principal-frame ω (n, 3) and attitudes (n, 4) of a body without parts."""
        body = problem.body
        values = np.zeros((len(w), 0))
        return cls(body.from_principal(w), body.attitude_from_principal(q), values, steps)


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

    @classmethod
    def sampled(
        cls,
        total_time: float,
        dt: Any,
        fastest: float,
        what: str,
        record_every: int,
        samples: int | None,
        columns: int,
    ) -> Schedule:
        """The steps of a model over ``total_time`` s: ``dt``, or by default 1/200 of
        a turn at ``fastest`` rad/s, the rate of ``what`` (a coarser ``dt`` warns);
        every ``record_every``-th kept, or about ``samples`` of them, each with
        ``columns`` values of the model's own besides the trajectory's.

        Raises
        ------
        InputError
            Both ``record_every`` and ``samples``, or ``samples`` not an integer >= 1.
        RequestTooLargeError
            Samples that would not fit in the memory budget.
        """
        step = time_step(dt, fastest, total_time)
        if dt is not None:
            warn_if_coarse(step, fastest, what, stacklevel=4)
        if samples is not None:
            if record_every != 1:
                raise InputError(
                    f"Expected one of `record_every` and `samples`, got both ({record_every!r}, "
                    f"{samples!r})."
                )
            if (
                isinstance(samples, bool)
                or not isinstance(samples, int | np.integer)
                or samples < 1
            ):
                raise InputError(f"Expected `samples` to be an integer >= 1, got {samples!r}.")
            record_every = max(1, whole_steps(total_time, step) // int(samples))
        check_recording(
            total_time,
            step,
            record_every,
            columns,
            "Record less often (record_every or samples), or ask for a shorter duration or a "
            "larger dt.",
        )
        return cls.build(total_time, step, record_every)
