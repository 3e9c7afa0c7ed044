"""The checks of what :func:`tumble.identify` is given: the samples, the window
and whether the motion in it can show a body at all."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, quoted, unknown_choice
from tumble.units import pint, vector_to_si

__all__ = [
    "FREE_BODY_BOUND",
    "LOSSES",
    "MIN_SAMPLES",
    "breaks_free_body",
    "check_bias",
    "check_loss",
    "check_motion",
    "flag",
    "free_body_ratio",
    "samples",
    "window_bounds",
]

Array = NDArray[np.float64]

#: Fewest samples a fit takes: 11 parameters, and enough beyond them for the
#: residuals to say how good the fit is.
MIN_SAMPLES = 30

#: The losses of ``scipy.optimize.least_squares`` a fit takes.
LOSSES = ("linear", "soft_l1", "huber", "cauchy", "arctan")

#: The most |dω/dt| / |ω|² of a torque-free body. Euler's equations give
#: ``ω̇_i = (I_j − I_k) ω_j ω_k / I_i`` and the triangle inequality of the moments
#: ``|I_j − I_k| ≤ I_i``, so ``ω̇_i² ≤ ω_j² ω_k²``; summed over i,
#: ``|ω̇|² ≤ ω₁²ω₂² + ω₂²ω₃² + ω₃²ω₁² ≤ (ω₁² + ω₂² + ω₃²)² / 3`` (for a, b, c ≥ 0,
#: ab + bc + ca ≤ (a + b + c)²/3, equal when a = b = c). A flat plate ever closer
#: to a rod (I = ε, 1, 1 + ε with ε → 0: all three factors (I_j − I_k)/I_i tend
#: to 1) spinning with ω's three components equal approaches it, so no smaller
#: bound holds for every body.
FREE_BODY_BOUND = 1.0 / math.sqrt(3.0)

#: How far beyond :data:`FREE_BODY_BOUND` the measured ratio may go before a
#: refusal of a window that no body fits says the bound is broken too: the
#: derivative of smoothed noisy samples, and |ω|² of the samples with their
#: bias, are estimates (the shipped recording reaches 0.85 of the bound), while
#: rates in deg/s read as rad/s are 57 times too small.
FREE_BODY_MARGIN = 2.0

#: The share of a window's samples whose |dω/dt| / |ω|² is judged (a high
#: percentile: a few samples spoilt by noise or an impact do not decide).
FREE_BODY_PERCENTILE = 90.0


def _as_array(value: Any, kind: str, name: str, shape: tuple[int, ...]) -> Array:
    """``value`` as a float array in SI: plain numbers as they are (a recording
    holds up to millions, which numpy reads at once), quantities and strings
    converted by :func:`tumble.units.vector_to_si`."""
    if not isinstance(value, str | pint.Quantity):
        try:
            return np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            pass  # quantities among the values, or no numbers at all: said below
    return vector_to_si(value, kind, name, shape)


def samples(t: Any, omega: Any) -> tuple[Array, Array]:
    """``t`` (n,) s and ``omega`` (n, 3) rad/s as float arrays (numbers, or pint
    quantities of any registry, converted), checked: shapes, enough samples,
    finite values, increasing times."""
    times = _as_array(t, "time", "t", (-1,))
    rates = _as_array(omega, "angular_velocity", "omega", (-1, 3))
    if times.ndim != 1 or rates.shape != (times.size, 3):
        raise InputError(
            f"Expected t of shape (n,) and omega of shape (n, 3), got {times.shape} and "
            f"{rates.shape}."
        )
    if times.size < MIN_SAMPLES:
        raise InputError(f"Expected at least {MIN_SAMPLES} samples, got {times.size}.")
    bad = ~np.isfinite(times) | ~np.isfinite(rates).all(axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        count = int(bad.sum())
        which = "1 sample that is not" if count == 1 else f"{count} samples that are not"
        raise InputError(
            f"Expected finite times and rates, got {which} (the first is sample {k}: "
            f"t = {float(times[k])!r}, omega = {rates[k].tolist()})."
        )
    steps = np.diff(times)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0))
        raise InputError(
            f"Expected increasing times, got t[{k + 1}] = {float(times[k + 1])!r} after "
            f"t[{k}] = {float(times[k])!r}."
        )
    return times, rates


def flag(value: Any, name: str) -> bool:
    """``value`` as a bool: True or False only (numpy's too), not a truthy string
    such as ``"no"``."""
    if not isinstance(value, bool | np.bool_):
        raise InputError(f"Expected `{name}` to be True or False, got {quoted(value)}.")
    return bool(value)


def check_loss(loss: Any, name: str = "`loss`") -> str:
    """``loss``, one of :data:`LOSSES` (``name``: how the message calls it)."""
    if not isinstance(loss, str) or loss not in LOSSES:
        raise unknown_choice(loss, LOSSES, name)
    return loss


def window_bounds(window: Any, times: Array) -> tuple[float, float]:
    """``window`` as (start, end), s, checked against the samples' ``times``."""
    try:
        start, end = (float(v) for v in window)
    except (TypeError, ValueError):
        raise InputError(f"Expected `window` to be (start, end) in s, got {window!r}.") from None
    if not (np.isfinite(start) and np.isfinite(end) and start < end):
        raise InputError(f"Expected `window` start < end, both finite, got {window!r}.")
    if end < times[0] or start > times[-1]:
        raise InputError(
            f"Expected `window` to overlap the samples ({times[0]:.6g}–{times[-1]:.6g} s), "
            f"got {start:.6g}–{end:.6g} s."
        )
    return start, end


def check_motion(rates: Array, noise: float) -> None:
    """Refuse a window whose rate stays constant within the noise: a spin about
    a principal axis, which no moment ratio changes."""
    spread = float(np.max(np.linalg.norm(rates - rates.mean(axis=0), axis=1)))
    if spread <= 5 * noise + 1e-12 * float(np.abs(rates).max()):
        raise InputError(
            f"Expected the angular velocity to change in the window, got changes of at most "
            f"{spread:.3g} rad/s against noise of {noise:.3g} rad/s: a steady spin about one "
            "principal axis does not reveal the moment ratios."
        )


def free_body_ratio(smooth: Array, derivative: Array) -> float:
    """|dω/dt| / |ω|² over a window, its :data:`FREE_BODY_PERCENTILE` th percentile,
    from the smoothed rates ``smooth`` (n, 3) and their derivative
    ``derivative`` (n, 3); 0 for a body at rest."""
    speed = np.sum(smooth**2, axis=1)
    moving = speed > 0.0
    if not moving.any():
        return 0.0
    ratio = np.linalg.norm(derivative[moving], axis=1) / speed[moving]
    return float(np.percentile(ratio, FREE_BODY_PERCENTILE))


def breaks_free_body(ratio: float) -> bool:
    """Whether a window's :func:`free_body_ratio` is beyond what any torque-free
    body shows (:data:`FREE_BODY_BOUND`, with the margin :data:`FREE_BODY_MARGIN`)."""
    return ratio > FREE_BODY_MARGIN * FREE_BODY_BOUND


def check_bias(bias: Array, rates: Array) -> None:
    """Refuse a fit whose sensor bias (rad/s, sensor axes) is larger than the rates
    measured (``rates`` (n, 3), their median length). No gyroscope reads mostly its
    own offset in flight; a fit does so when the rates are in a unit larger than
    they are read in, so too small by its factor (57.3 for deg/s read as rad/s):
    the rates then break |dω/dt| ≤ |ω|²/√3, which every torque-free body keeps,
    and the fit makes up the difference with a fast spin hidden in the bias
    (the shipped recording in deg/s read as rad/s: a bias of 7.4 rad/s against
    rates of 0.21 rad/s; in rad/s, 0.027 against 12)."""
    offset = float(np.linalg.norm(bias))
    typical = float(np.median(np.linalg.norm(rates, axis=1)))
    if offset > typical:
        raise InputError(
            f"Expected a sensor bias smaller than the rates measured, got a fit whose bias "
            f"({offset:.3g} rad/s) exceeds the rates' median ({typical:.3g} rad/s): the rates "
            "look too small for their unit (they break |dω/dt| ≤ |ω|²/√3, which every "
            "torque-free body keeps, and the bias makes up the rest): were they in deg/s read "
            "as rad/s (57.3 times), or in turn/s (6.28 times)? (Give them in rad/s, or as "
            "quantities with their unit.)"
        )
