"""The checks of what :func:`tumble.identify` is given: the samples, the window
and whether the motion in it can show a body at all."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError

__all__ = ["MIN_SAMPLES", "check_motion", "samples", "window_bounds"]

Array = NDArray[np.float64]

#: Fewest samples a fit takes: 11 parameters, and enough beyond them for the
#: residuals to say how good the fit is.
MIN_SAMPLES = 30


def samples(t: Any, omega: Any) -> tuple[Array, Array]:
    """``t`` (n,) and ``omega`` (n, 3) as float arrays, checked: shapes, enough
    samples, finite values, increasing times."""
    times = np.asarray(t, dtype=float)
    rates = np.asarray(omega, dtype=float)
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
        raise InputError(
            f"Expected finite times and rates, got {int(bad.sum())} samples that are not "
            f"(the first is sample {k}: t = {times[k]!r}, omega = {rates[k].tolist()})."
        )
    steps = np.diff(times)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0))
        raise InputError(
            f"Expected increasing times, got t[{k + 1}] = {times[k + 1]!r} after "
            f"t[{k}] = {times[k]!r}."
        )
    return times, rates


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
