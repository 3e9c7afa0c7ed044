"""The free flight inside a recording of body rates: :func:`free_flight`.

A thrown phone is torque-free from the hand to the catch; before and after,
the hand holds it. The rule that tells them apart comes from Euler's
equations: in free flight ``ω̇_i = (I_j − I_k) ω_j ω_k / I_i``, and since every
physical body has ``|I_j − I_k| ≤ I_i`` (the triangle inequality of its
moments), ``|ω̇| ≤ |ω|²`` (even ``|ω|²/√3``:
:data:`~tumble.identification.validation.FREE_BODY_BOUND`; the rule keeps the
rounder bound, a margin for the noise of a plain difference). A hand turning
the phone, a throw that spins it up and a catch all break that bound (the
hand's torque), and so do impacts. The samples kept are those where

* ``|ω̇| ≤ 1.5 |ω|² + 6 σ̇``, with σ̇ the noise of ``ω̇`` from differences of
  the samples (so noise alone does not break the bound), and
* ``|ω| ≥`` a quarter of the recording's 99th percentile of ``|ω|`` (a thrown
  phone spins faster than a hand turns it; this also drops the still parts,
  where the bound holds trivially);

the free flight is the longest run of such samples, less 3 samples at each end
(the edges of a throw and of a catch). ``identify(window=(start, end))``
overrides it. :func:`free_flights` finds every such run of a long recording
(throws with catches and holding between them), in time order; its ``fast``
threshold is the whole recording's, so it suits throws of similar speeds.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError

__all__ = ["free_flight", "free_flights", "noise_level"]

Array = NDArray[np.float64]

#: Fewest samples a free flight has (see :data:`tumble.identification.validation.MIN_SAMPLES`).
MIN_FLIGHT = 30

#: Samples dropped at each end of the run found: the edges of the throw and catch.
EDGE = 3


def noise_level(t: Array, omega: Array) -> float:
    """The sensor's noise σ (rad/s, per component), from the third differences of the
    samples: for smooth motion sampled finely they are the noise's, with variance
    C(6, 3) σ² = 20 σ² (robust: the median absolute deviation, so impacts do not
    count). Third, not second, differences: a body turning at 10 rad/s sampled at
    100 Hz leaves a second difference of its motion comparable with a phone
    gyroscope's noise (0.0035 rad/s measured as 0.0046), a third one a tenth of it."""
    third = np.diff(omega, n=3, axis=0)
    if third.size == 0:
        return 0.0
    return float(1.4826 * np.median(np.abs(third)) / np.sqrt(20.0))


def free_flight(t: Array, omega: Array) -> tuple[float, float]:
    """(start, end), s: the free flight of a recording ``t`` (n,) s, ``omega``
    (n, 3) rad/s, by the rule of this module's docstring (the longest, when
    there are several).

    Raises
    ------
    InputError
        When no run of at least ``MIN_FLIGHT`` samples follows the rule.
    """
    runs = _free_runs(t, omega)
    start, stop = max(runs, key=lambda run: run[1] - run[0], default=(0, 0))
    if stop - start - 2 * EDGE < MIN_FLIGHT:
        raise _no_flight(stop - start)
    return float(t[start + EDGE]), float(t[stop - 1 - EDGE])


def free_flights(t: Array, omega: Array) -> list[tuple[float, float]]:
    """[(start, end), ...], s, in time order: every free flight of a recording
    ``t`` (n,) s, ``omega`` (n, 3) rad/s (throws with catches and holding
    between them), by the rule of this module's docstring: each run of at
    least ``MIN_FLIGHT`` samples once ``EDGE`` are dropped at each end.

    The rule's ``fast`` threshold is a quarter of the whole recording's 99th
    percentile of ``|ω|``: a throw far slower than the others is missed.

    Raises
    ------
    InputError
        When no run of at least ``MIN_FLIGHT`` samples follows the rule.
    """
    runs = _free_runs(t, omega)
    flights = [
        (float(t[start + EDGE]), float(t[stop - 1 - EDGE]))
        for start, stop in runs
        if stop - start - 2 * EDGE >= MIN_FLIGHT
    ]
    if not flights:
        raise _no_flight(max((stop - start for start, stop in runs), default=0))
    return flights


def _free_runs(t: Array, omega: Array) -> list[tuple[int, int]]:
    """[(start, stop), ...]: the runs of samples ``start:stop`` that follow the
    rule of this module's docstring, in time order."""
    speed = np.linalg.norm(omega, axis=1)
    acceleration = np.linalg.norm(np.gradient(omega, t, axis=0), axis=1)
    step = float(np.median(np.diff(t)))
    sigma = noise_level(t, omega)
    # np.gradient's central difference: (ω[k+1] − ω[k−1]) / 2h, noise σ/(√2 h) per
    # component, √3 times that in the norm of three.
    rate_noise = np.sqrt(1.5) * sigma / step
    fast = speed >= 0.25 * np.percentile(speed, 99)
    free = fast & (acceleration <= 1.5 * speed**2 + 6.0 * rate_noise)
    edges = np.diff(np.concatenate([[0], free.astype(np.int8), [0]]))
    starts = np.flatnonzero(edges == 1)
    stops = np.flatnonzero(edges == -1)
    return [(int(a), int(b)) for a, b in zip(starts, stops, strict=True)]


def _no_flight(longest: int) -> InputError:
    """The error of a recording without a free flight (``longest``: the longest run found)."""
    return InputError(
        f"Expected a free flight of at least {MIN_FLIGHT} samples (|dω/dt| ≤ |ω|², as "
        f"Euler's equations allow a torque-free body, and |ω| near its largest), got "
        f"{max(longest, 0)} at most: choose the window by hand (window=(start, end), or "
        "--window START,END)."
    )
