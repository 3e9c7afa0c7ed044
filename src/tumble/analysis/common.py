"""What the measurements of :mod:`tumble.analysis` share: their thresholds, the
checks of their inputs, angles about an axis, turning points of a sampled curve."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.trajectory import Trajectory
from tumble.units import vector_to_si

__all__ = [
    "MIN_AZIMUTH_ANGLE",
    "MIN_SAMPLES",
    "STEADY_SWING",
    "as_trajectory",
    "azimuth",
    "frame",
    "space_axis",
    "spectral_frequency",
    "tilt_from",
    "time_mean",
    "turning_points",
    "unit_vector",
    "vertex",
    "vertical_of",
]

Array = NDArray[np.float64]

#: A tilt whose whole swing over the trajectory is below this, rad, is taken as
#: steady (no nutation): round-off in long runs stays orders of magnitude below
#: it, and a nutation of a few nano-radians is still measured.
STEADY_SWING = 1e-9

#: Fewest samples any measurement needs (a parabola through three points).
MIN_SAMPLES = 3

#: The azimuth of a body axis is undefined on the vertical; closer than this, rad,
#: it is refused rather than returned as noise.
MIN_AZIMUTH_ANGLE = 1e-6


def as_trajectory(trajectory: Any) -> Trajectory:
    """``trajectory`` if it is a Trajectory of at least ``MIN_SAMPLES`` samples."""
    if not isinstance(trajectory, Trajectory):
        raise InputError(
            f"Expected `trajectory` to be a Trajectory, got {type(trajectory).__name__}."
        )
    if trajectory.t.size < MIN_SAMPLES:
        raise InputError(
            f"Expected `trajectory` to hold at least {MIN_SAMPLES} samples, "
            f"got {trajectory.t.size}."
        )
    return trajectory


def unit_vector(value: Any, name: str) -> Array:
    """``value`` (3,) normalised; refused when zero."""
    vector = vector_to_si(value, "dimensionless", name, (3,))
    norm = float(np.linalg.norm(vector))
    if not norm > 0:
        raise InputError(f"Expected `{name}` to be a non-zero vector, got {vector.tolist()}.")
    return vector / norm


def vertical_of(trajectory: Trajectory, vertical: Any) -> Array:
    """The given vertical, or −gravity's direction, or space z without gravity."""
    if vertical is not None:
        return unit_vector(vertical, "vertical")
    g = np.asarray(trajectory.gravity, dtype=float)
    size = math.hypot(*g)
    return -g / size if size > 0 else np.array([0.0, 0.0, 1.0])


def frame(normal: Array) -> tuple[Array, Array]:
    """Unit vectors (e1, e2) with (e1, e2, normal) right-handed and orthonormal:
    e1 is the space axis least aligned with ``normal`` (x for a vertical z), made
    perpendicular to it."""
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    first = helper - (helper @ normal) * normal
    first /= np.linalg.norm(first)
    return first, np.cross(normal, first)


def azimuth(vectors: Array, normal: Array, name: str, times: Array) -> Array:
    """Unwrapped azimuth of each vector about ``normal``, rad, counter-clockwise."""
    first, second = frame(normal)
    x, y = vectors @ first, vectors @ second
    along = vectors @ normal
    angles = np.arctan2(np.hypot(x, y), np.abs(along))
    k = int(np.argmin(angles))
    if angles[k] < MIN_AZIMUTH_ANGLE:
        raise InputError(
            f"Expected {name} to stay off the axis of the azimuth ({normal.tolist()}) to "
            f"measure it, got an angle of {angles[k]:.3g} rad at t = {times[k]:.6g} s."
        )
    return np.asarray(np.unwrap(np.arctan2(y, x)))


def space_axis(trajectory: Trajectory, axis: Any) -> tuple[Array, Array]:
    """The body axis (unit, body coordinates) and its direction in space (n, 3)."""
    body = unit_vector(axis, "axis")
    return body, np.asarray(trajectory.rotation.apply(body))


def tilt_from(directions: Array, vertical: Array) -> Array:
    """Angle of each unit vector from ``vertical``, rad; atan2 keeps it accurate near 0 and π."""
    return np.asarray(
        np.arctan2(np.linalg.norm(np.cross(directions, vertical), axis=1), directions @ vertical)
    )


def vertex(t: Array, y: Array, k: int) -> tuple[float, float]:
    """Time and value of the vertex of the parabola through samples k−1, k, k+1.

    Works for uneven spacing; the time is kept between the outer two samples.
    """
    d0, d2 = t[k - 1] - t[k], t[k + 1] - t[k]
    y0, y2 = y[k - 1] - y[k], y[k + 1] - y[k]
    det = d0 * d2 * (d0 - d2)
    a = (y0 * d2 - y2 * d0) / det
    b = (y2 * d0 * d0 - y0 * d2 * d2) / det
    if a == 0:
        return float(t[k]), float(y[k])
    offset = min(max(-b / (2 * a), d0), d2)
    return float(t[k] + offset), float(y[k] + a * offset * offset + b * offset)


def turning_points(t: Array, y: Array) -> tuple[Array, Array, Array, Array]:
    """Maxima and minima of a sampled oscillation: (max times, max values, min times, min values).

    A Schmitt trigger splits the record into excursions above ``mid + band`` and
    below ``mid − band`` (mid the middle of the sampled range, band a quarter of
    its half-range), so round-off wiggles near the middle make no extra turning
    points. Each excursion contributes its extreme sample, refined by a parabola
    through it and its two neighbours, unless that sample is the first or the
    last of the record (an excursion cut by the ends of the record).
    """
    high, low = float(np.max(y)), float(np.min(y))
    mid, band = 0.5 * (high + low), 0.125 * (high - low)
    state = np.zeros(y.size, dtype=np.int8)  # +1 above mid + band, −1 below mid − band
    state[y > mid + band] = 1
    state[y < mid - band] = -1
    marked = np.flatnonzero(state)
    found: dict[int, list[tuple[float, float]]] = {1: [], -1: []}
    if marked.size == 0:
        empty = np.empty(0)
        return empty, empty, empty, empty
    # Runs of the same state among the marked samples; an excursion's window runs
    # from just after the previous run's last marked sample to just before the
    # next run's first one.
    changes = np.flatnonzero(np.diff(state[marked])) + 1
    starts = np.concatenate(([0], changes))
    ends = np.concatenate((changes, [marked.size]))
    for first, last in zip(starts, ends, strict=True):
        side = int(state[marked[first]])
        lo = 0 if first == 0 else int(marked[first - 1]) + 1
        hi = y.size if last == marked.size else int(marked[last])
        segment = side * y[lo:hi]
        k = lo + int(np.argmax(segment))
        if 0 < k < y.size - 1:
            found[side].append(vertex(t, side * y, k))
    result = []
    for side in (1, -1):
        points = np.array(found[side]).reshape(-1, 2)
        result += [points[:, 0], side * points[:, 1]]
    return result[0], result[1], result[2], result[3]


def time_mean(t: Array, y: Array, start: float, stop: float) -> float:
    """Time average of the sampled y over [start, stop] (trapezoids, ends interpolated)."""
    inside = (t > start) & (t < stop)
    times = np.concatenate(([start], t[inside], [stop]))
    values = np.concatenate(([np.interp(start, t, y)], y[inside], [np.interp(stop, t, y)]))
    return float(np.trapezoid(values, times) / (stop - start))


def spectral_frequency(t: Array, y: Array) -> float:
    """Angular frequency of the strongest spectral peak of y, rad/s.

    The samples are interpolated to an even grid, the mean removed, a Hann window
    applied and the spectrum zero-padded 16-fold; the peak is refined by a
    parabola through the logarithms of the peak bin and its two neighbours.
    """
    n = t.size
    grid = np.linspace(t[0], t[-1], n)
    values = np.interp(grid, t, y)
    values = (values - values.mean()) * np.hanning(n)
    size = 16 * (1 << int(n - 1).bit_length())
    spectrum = np.abs(np.fft.rfft(values, size))
    step = (t[-1] - t[0]) / (n - 1)
    frequencies = np.fft.rfftfreq(size, step)
    # Skip the leakage of the removed mean: below one cycle over the record.
    first = int(np.searchsorted(frequencies, 1.0 / (t[-1] - t[0])))
    k = first + int(np.argmax(spectrum[first:-1]))
    if k > first:
        logs = np.log(np.maximum(spectrum[k - 1 : k + 2], np.finfo(float).tiny))
        curvature = logs[0] - 2 * logs[1] + logs[2]
        shift = 0.5 * (logs[0] - logs[2]) / curvature if curvature < 0 else 0.0
    else:
        shift = 0.0
    return float(2 * math.pi * (frequencies[k] + shift * (frequencies[1] - frequencies[0])))
