"""How long a step is and how many there are: the default step, the warning
of a coarse one, the whole steps that span a duration, the samples they record,
the chunks of steps that compiled kernels take between progress reports, and the
compiled kernels' machine code called directly.

:func:`tumble.simulate`, the batch driver, the gyrocompass model, scenario and
sweep files size their steps with these.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numba
import numpy as np

from tumble.core._jit import FINITE
from tumble.errors import CoarseStepWarning, InputError, IntegrationError, RequestTooLargeError
from tumble.units import to_si

__all__ = [
    "DEFAULT_STEPS_PER_TURN",
    "MAX_STEPS",
    "MIN_STEPS_PER_TURN",
    "PROGRESS_CHUNK",
    "Progress",
    "check_finite",
    "compiled_for",
    "recorded_samples",
    "step_in_chunks",
    "time_step",
    "too_coarse",
    "warn_if_coarse",
    "whole_steps",
]

Progress = Callable[[int, int], object] | None

#: Steps per call of a compiled kernel between progress reports.
PROGRESS_CHUNK = 1 << 17

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
    """How many samples :meth:`tumble.integrators.problem.Schedule.build` would
    record (an upper bound, as a float so that it never overflows)."""
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
        check_finite(run(done, count), step)
        done += count
        if progress is not None:
            progress(done, n_steps)


def compiled_for(function: Any, arguments: tuple[Any, ...]) -> Any:
    """The machine code a compiled ``function`` (a numba dispatcher) runs for
    arguments of the types of ``arguments``, compiled or loaded from the cache if it
    is not yet, to be called without numba's dispatch by the arguments' types;
    ``function`` itself where it is plain Python (``NUMBA_DISABLE_JIT=1``) or
    numba gives no machine code for it (a dispatcher whose compilation is disabled).

    Call it only with arguments of those very types (as :func:`numba.typeof` names
    them: dtype, dimensions, layout, read-only or not): it reads them as such and
    does not check. The dispatch costs about 7 µs a call when the processor's caches
    are cold (of a short run's 80 µs, ``bench/cold_call.py``). Kept for the last 256
    functions and types asked for in a process (``numba.typeof`` of an array takes
    6 µs, and ``compile`` 16 µs even when it finds the code compiled): a few µs
    after."""
    if getattr(function, "compile", None) is None:
        return function
    return _machine_code(function, tuple(map(_argument_type, arguments)))


@lru_cache(maxsize=256)
def _machine_code(function: Any, signature: tuple[Any, ...]) -> Any:
    # numba's Dispatcher.compile returns the machine code's entry point. It raises
    # RuntimeError where compiling is disabled (a dispatcher given its signatures),
    # even for a signature compiled; then, or were it to return nothing callable,
    # the dispatcher serves.
    try:
        machine = function.compile(signature)
    except RuntimeError:
        return function
    return machine if callable(machine) else function


#: The numba types of the arrays met, by what names them (:func:`_argument_type`).
_ARRAY_TYPES: dict[tuple[Any, ...], Any] = {}


def _argument_type(value: Any) -> Any:
    """``numba.typeof(value)``; for an array of numbers, kept by what numba names its
    type by (its dtype, dimensions, layout and whether it is read-only). Not for
    records: numba's type of a structured dtype tells whether it is an aligned
    struct, which numpy's equality of dtypes does not."""
    if type(value) is not np.ndarray or value.dtype.fields is not None:
        return numba.typeof(value)
    flags = value.flags
    key = (value.dtype, value.ndim, flags.c_contiguous, flags.f_contiguous, flags.writeable)
    found = _ARRAY_TYPES.get(key)
    if found is None:
        found = _ARRAY_TYPES[key] = numba.typeof(value)
    return found


def check_finite(status: int, step: float) -> None:
    """Refuse a compiled kernel's ``status`` that is not ``FINITE``: the number of
    its first non-finite step of ``step`` s.

    Raises
    ------
    IntegrationError
        The message names the step and its time.
    """
    if status != FINITE:
        raise IntegrationError(
            f"Expected the integration to stay finite, got NaN or inf at step {status} "
            f"(t = {status * step:.6g} s) with dt = {step:.3g} s: reduce dt."
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


def too_coarse(step: float, fastest: float) -> bool:
    """Whether a step of ``step`` s gives fewer than ``MIN_STEPS_PER_TURN`` steps
    per turn at ``fastest`` rad/s (never when nothing turns)."""
    return fastest > 0 and 2 * math.pi / (fastest * step) < MIN_STEPS_PER_TURN


def warn_if_coarse(step: float, fastest: float, what: str, stacklevel: int = 3) -> None:
    """Warn (:class:`~tumble.errors.CoarseStepWarning`) when a step of ``step`` s
    gives fewer than ``MIN_STEPS_PER_TURN`` steps per turn at ``fastest`` rad/s
    (:func:`too_coarse`), the rate of ``what`` (e.g. "the fastest rotation")."""
    if too_coarse(step, fastest):
        per_turn = 2 * math.pi / (fastest * step)
        warnings.warn(
            f"dt = {step:.3g} s gives {per_turn:.1f} steps per turn of {what} "
            f"({fastest:.3g} rad/s); below {MIN_STEPS_PER_TURN} the result is inaccurate.",
            CoarseStepWarning,
            stacklevel=stacklevel,
        )
