"""What a run may ask of an integrator, checked before any step: how often it
records, whether its samples fit in memory, and whether its step keeps a
body's parts within the stability of an explicit method."""

from __future__ import annotations

from typing import Any, Literal, overload

import numpy as np

from tumble.errors import InputError, IntegrationError, RequestTooLargeError, quoted
from tumble.integrators.steps import recorded_samples, whole_steps
from tumble.resources import check_memory

__all__ = [
    "PEAK_PER_VALUE",
    "STABILITY",
    "check_internal_stability",
    "check_record_every",
    "check_recording",
]


@overload
def check_record_every(record_every: Any, *, optional: Literal[False] = False) -> int: ...
@overload
def check_record_every(record_every: Any, *, optional: bool) -> int | None: ...
def check_record_every(record_every: Any, *, optional: bool = False) -> int | None:
    """``record_every``, the number of steps between recorded states: an integer
    >= 1 (a numpy integer too), or None where ``optional`` (only the final
    state is kept). Returns it as an int (or None).

    Raises
    ------
    InputError
        Anything else: a fraction of a step, a string, a bool, a number < 1.
    """
    if type(record_every) is int and record_every >= 1:  # the usual case, at once
        return record_every
    if record_every is None and optional:
        return None
    if (
        isinstance(record_every, bool)
        or not isinstance(record_every, int | np.integer)
        or record_every < 1
    ):
        what = "None or an integer" if optional else "an integer"
        raise InputError(f"Expected `record_every` to be {what} >= 1, got {quoted(record_every)}.")
    return int(record_every)


#: Memory a recorded sample takes while a run ends, per value kept (t, ω, q
#: and the parts' values, 8 bytes each): the kernels' output, its conversion to
#: body axes and the trajectory's arrays (measured: 1.9 times the 8 bytes for a
#: rigid body, 2.8 with a rotor, 3.1 with a damper).
PEAK_PER_VALUE = 4 * 8


def check_recording(
    duration: float,
    step: float,
    record_every: int,
    part_values: int,
    advice: str = "Record less often (record_every), or ask for a shorter duration or a larger dt.",
) -> float:
    """Refuse a run whose recorded samples cannot fit in the memory budget
    (:mod:`tumble.resources`), or of more than 2^53 steps, before any work.
    Returns the memory they take, bytes (the estimate checked).

    ``advice`` says how to ask for less.

    Raises
    ------
    RequestTooLargeError
        With the estimate and the advice.
    """
    whole_steps(duration, step)  # at most 2^53 steps
    samples = recorded_samples(duration, step, record_every)
    values = 8 + part_values
    needed = samples * values * PEAK_PER_VALUE
    check_memory(
        needed,
        lambda: (
            f"{samples:.3g} recorded samples of {values} values ({duration:.3g} s at dt = "
            f"{step:.3g} s, every {record_every} step{'s' if record_every > 1 else ''})"
        ),
        advice,
    )
    return needed


#: The stability intervals of the explicit methods on the negative real axis,
#: |h λ| (Hairer & Wanner, *Solving ODEs II*, §IV.2): RK4 2.785, Dormand–Prince
#: 5(4) 3.3. A part's motion faster than this for the step diverges.
STABILITY = {"stepping": 2.78, "adaptive": 3.3}


def check_internal_stability(
    rate: float, names: list[str], kind: str, step: float, duration: float, most_steps: float
) -> None:
    """Refuse, before any work, a run whose parts move too fast for an explicit
    method: ``rate`` (1/s) the bound of their own motion's fastest rate
    (:func:`tumble.parts.internal_rate`, of the kinds ``names``), ``kind`` the
    integrator's ("stepping", "adaptive"; others are not checked), ``step`` its
    step (s), ``duration`` the run's (s).

    Raises
    ------
    IntegrationError
        A fixed step beyond the stability interval for that rate: the run
        would diverge.
    RequestTooLargeError
        An adaptive run that would need more than ``most_steps`` steps to stay
        within the interval (a stiff part).
    """
    limit = STABILITY.get(kind)
    if not rate > 0 or limit is None:
        return
    whose = f"the {names[0]}'s" if len(set(names)) == 1 else f"the parts' ({', '.join(names)})"
    if kind == "stepping" and step * rate > limit:
        raise IntegrationError(
            f"Expected dt within the stability of the method for {whose} own rate "
            f"({rate:.3g} 1/s): dt × rate <= {limit}, got dt = {step:.3g} s, dt × rate = "
            f"{step * rate:.3g} (the run would diverge); use dt <= {limit / rate:.3g} s, or "
            "less damping or stiffness."
        )
    needed = duration * rate / limit
    if kind == "adaptive" and needed > most_steps:
        raise RequestTooLargeError(
            f"Expected the adaptive integration to end within {most_steps:.3g} steps "
            f"(max_steps), got at least {needed:.3g} steps: {whose} own rate "
            f"({rate:.3g} 1/s) holds an explicit method's step under {limit / rate:.3g} s "
            "(a stiff part); ask for a shorter duration, less damping or stiffness, or raise "
            "`max_steps=`."
        )
