"""Recordings sampled far faster than their motion needs, averaged to fewer
samples before a fit: :func:`averaged`.

A gyroscope read at hundreds of kHz gives millions of samples of a motion that
turns by a few thousandths of a radian between them. The fit's work grows with
the samples (its Jacobian holds 33 numbers a sample), so blocks of consecutive
samples are averaged: the mean of k samples has the noise σ/√k, and it differs
from the motion at the block's mean time by about ``|ω̈| D² / 24`` (D the
block's duration), which for blocks of at most :data:`MAX_TURN` of turn is
``4e-6 |ω|`` at most (each time derivative of a free body's ω brings a factor
of at most about |ω|): far below the noise of any gyroscope.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["MAX_SAMPLES", "MAX_TURN", "averaged"]

Array = NDArray[np.float64]

#: The most samples a fit takes without averaging: beyond, blocks of samples are
#: averaged to about this many (a fit of them takes seconds).
MAX_SAMPLES = 20_000

#: The most a block of averaged samples may turn, rad (at the recording's
#: fastest rate): its average then keeps the motion to 4e-6 of |ω|.
MAX_TURN = 0.01


def averaged(
    times: Array, rates: Array, window: tuple[float, float] | None = None
) -> tuple[Array, Array, int, str]:
    """The samples ``times`` (n,) s, ``rates`` (n, 3) rad/s averaged in blocks
    of k consecutive samples when the window to fit (``window``, s; None: all
    samples) holds more than :data:`MAX_SAMPLES` and blocks of k samples turn by
    at most :data:`MAX_TURN`.

    Returns
    -------
    times, rates : the block means (the samples themselves when k = 1).
    k : the samples in a block (the last block may hold fewer).
    note : what was done, one sentence; "" when nothing was.
    """
    count = times.size
    if window is not None:
        count = int(np.count_nonzero((times >= window[0]) & (times <= window[1])))
    if count <= MAX_SAMPLES or times.size < 2:
        return times, rates, 1, ""
    step = float(np.median(np.diff(times)))
    # The motion's fastest rate, robust to spikes (impacts, glitches).
    speed = float(np.percentile(np.linalg.norm(rates, axis=1), 99))
    wanted = math.ceil(count / MAX_SAMPLES)
    allowed = math.floor(MAX_TURN / (speed * step)) if speed * step > 0 else wanted
    k = min(wanted, allowed)
    if k < 2:
        return times, rates, 1, ""
    starts = np.arange(0, times.size, k)
    sizes = np.diff(np.append(starts, times.size)).astype(float)
    # Times summed from the first: a clock of 1.7e9 s (Unix time) keeps its µs.
    mean_times = times[0] + np.add.reduceat(times - times[0], starts) / sizes
    mean_rates = np.add.reduceat(rates, starts, axis=0) / sizes[:, None]
    note = (
        f"averaged {k} samples at a time ({times.size} samples at about "
        f"{_frequency(1.0 / step)} to {starts.size}; each average spans "
        f"{k * step * speed:.2g} rad of turn at most)"
    )
    return mean_times, mean_rates, k, note


def _frequency(hertz: float) -> str:
    """``590 kHz``: a sampling rate for people."""
    for unit, size in (("MHz", 1e6), ("kHz", 1e3)):
        if hertz >= size:
            return f"{hertz / size:.3g} {unit}"
    return f"{hertz:.3g} Hz"
