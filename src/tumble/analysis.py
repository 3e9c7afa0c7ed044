"""Measurements on a simulated :class:`~tumble.simulation.Trajectory`.

Each function measures one physical quantity from the samples, in a way that
depends as little as possible on the sampling interval, and says how:

* :func:`precession` — the azimuth φ(t) of a body axis about a vertical; its mean
  rate over whole nutation periods (between maxima of the tilt), or a
  least-squares slope when the tilt does not nutate.
* :func:`nutation` — the tilt θ(t) of a body axis from the vertical; turning
  points by parabolic refinement of the sampled extrema, the frequency from the
  times between successive maxima (the spectrum when there are fewer than 3).
* :func:`flips` — the sign changes of ω along the intermediate principal axis
  (the tennis-racket flips), by linear interpolation between samples.
* :func:`polhode` — L in the principal axes with the energy ellipsoid and the
  momentum sphere it lies on.
* :func:`body_precession_rate` — the rate at which ω turns about a body axis.
* :func:`drift` — the relative drift of the conserved quantities.

These measurements side by side with a closed form of :mod:`tumble.theory` are
the theory checks of :mod:`tumble.checks`.

Conventions as in the rest of tumble: SI units (s, rad, rad/s), body axes for
``axis``, space axes for ``vertical``, quaternions ``[w, x, y, z]`` body → space.
Angles are unwrapped, so a sample must not be more than half a turn of the
azimuth away from the next (sample at least twice per turn).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import trapezoid

from tumble.errors import InputError
from tumble.trajectory import Trajectory
from tumble.units import vector_to_si

__all__ = [
    "STEADY_SWING",
    "Flips",
    "Nutation",
    "Polhode",
    "Precession",
    "body_precession_rate",
    "drift",
    "flips",
    "nutation",
    "polhode",
    "precession",
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


# ----------------------------------------------------------------- results
@dataclass(frozen=True, eq=False)
class Precession:
    """The precession of a body axis about a vertical (see :func:`precession`).

    Attributes
    ----------
    rate : mean rate dφ/dt of the azimuth, rad/s, positive counter-clockwise
        about ``vertical`` (right-handed).
    angle : (n,) the azimuth φ(t), unwrapped, rad, with φ(0) in (−π, π]; measured
        from the space axis least aligned with the vertical (x for a vertical z,
        so φ = atan2(a_y, a_x) of the body axis a), projected off the vertical.
    vertical : (3,) the unit vertical used, space coordinates.
    method : how ``rate`` was measured: ``"whole nutation periods"`` or
        ``"least squares"``.
    """

    rate: float
    angle: Array
    vertical: Array
    method: str


@dataclass(frozen=True, eq=False)
class Nutation:
    """The nutation of a body axis: its tilt from a vertical (see :func:`nutation`).

    Attributes
    ----------
    frequency : angular frequency of the tilt's oscillation, rad/s.
    amplitude : half the swing of the tilt, (θ_max − θ_min)/2, rad (the mean
        refined maximum minus the mean refined minimum, halved).
    tilt : (n,) θ(t), the angle of the body axis from the vertical, rad, in [0, π].
    mean_tilt : time average of θ over whole periods (between the first and last
        maxima; over the whole record when there are fewer than 2), rad.
    maxima_times, maxima : times (s) and values (rad) of the maxima of θ,
        refined by a parabola through the three samples around each.
    minima_times, minima : the same for the minima.
    vertical : (3,) the unit vertical used, space coordinates.
    method : how ``frequency`` was measured: ``"turning points"`` or ``"spectrum"``.
    """

    frequency: float
    amplitude: float
    tilt: Array
    mean_tilt: float
    maxima_times: Array
    maxima: Array
    minima_times: Array
    minima: Array
    vertical: Array
    method: str


@dataclass(frozen=True, eq=False)
class Flips:
    """Sign changes of ω along the intermediate principal axis (see :func:`flips`).

    Attributes
    ----------
    times : the times of the sign changes, s, each linearly interpolated
        between the two samples around it.
    period : twice the mean interval between successive flips, s: the full
        period of ω(t), comparable to :func:`tumble.theory.flip_period`.
    count : the number of flips.
    axis : (3,) the intermediate principal axis, body coordinates.
    """

    times: Array
    period: float
    count: int
    axis: Array


@dataclass(frozen=True, eq=False)
class Polhode:
    """The polhode: L in the principal axes (see :func:`polhode`). SI units.

    Attributes
    ----------
    angular_momentum_body : (n, 3) L in the principal axes, kg·m²/s (about the
        centre of mass, or about the pivot).
    moments : (3,) principal moments, ascending, kg·m².
    axes : (3, 3) principal axes as columns, body coordinates.
    energy_ellipsoid : (3,) semi-axes √(2 E I_k) of the ellipsoid
        ``Σ L_k² / (2 E I_k) = 1`` on which L lies, E the kinetic energy at t = 0, kg·m²/s.
    momentum_sphere : |L| at t = 0, kg·m²/s: the radius of the sphere on which
        L lies; the polhode is the intersection of the two (torque-free motion).
    """

    angular_momentum_body: Array
    moments: Array
    axes: Array
    energy_ellipsoid: Array
    momentum_sphere: float


# ----------------------------------------------------------------- helpers
def _trajectory(trajectory: Any) -> Trajectory:
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


def _unit(value: Any, name: str) -> Array:
    vector = vector_to_si(value, "dimensionless", name, (3,))
    norm = float(np.linalg.norm(vector))
    if not norm > 0:
        raise InputError(f"Expected `{name}` to be a non-zero vector, got {vector.tolist()}.")
    return vector / norm


def _vertical(trajectory: Trajectory, vertical: Any) -> Array:
    """The given vertical, or −gravity's direction, or space z without gravity."""
    if vertical is not None:
        return _unit(vertical, "vertical")
    g = np.asarray(trajectory.gravity, dtype=float)
    size = float(np.linalg.norm(g))
    return -g / size if size > 0 else np.array([0.0, 0.0, 1.0])


def _frame(normal: Array) -> tuple[Array, Array]:
    """Unit vectors (e1, e2) with (e1, e2, normal) right-handed and orthonormal:
    e1 is the space axis least aligned with ``normal`` (x for a vertical z), made
    perpendicular to it."""
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    first = helper - (helper @ normal) * normal
    first /= np.linalg.norm(first)
    return first, np.cross(normal, first)


def _azimuth(vectors: Array, normal: Array, name: str, times: Array) -> Array:
    """Unwrapped azimuth of each vector about ``normal``, rad, counter-clockwise."""
    first, second = _frame(normal)
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


def _space_axis(trajectory: Trajectory, axis: Any) -> tuple[Array, Array]:
    """The body axis (unit, body coordinates) and its direction in space (n, 3)."""
    body = _unit(axis, "axis")
    return body, np.asarray(trajectory.rotation.apply(body))


def _tilt(directions: Array, vertical: Array) -> Array:
    """Angle of each unit vector from ``vertical``, rad; atan2 keeps it accurate near 0 and π."""
    return np.asarray(
        np.arctan2(np.linalg.norm(np.cross(directions, vertical), axis=1), directions @ vertical)
    )


def _vertex(t: Array, y: Array, k: int) -> tuple[float, float]:
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


def _turning_points(t: Array, y: Array) -> tuple[Array, Array, Array, Array]:
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
            found[side].append(_vertex(t, side * y, k))
    result = []
    for side in (1, -1):
        points = np.array(found[side]).reshape(-1, 2)
        result += [points[:, 0], side * points[:, 1]]
    return result[0], result[1], result[2], result[3]


def _time_mean(t: Array, y: Array, start: float, stop: float) -> float:
    """Time average of the sampled y over [start, stop] (trapezoids, ends interpolated)."""
    inside = (t > start) & (t < stop)
    times = np.concatenate(([start], t[inside], [stop]))
    values = np.concatenate(([np.interp(start, t, y)], y[inside], [np.interp(stop, t, y)]))
    return float(trapezoid(values, times) / (stop - start))


def _spectral_frequency(t: Array, y: Array) -> float:
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


# ----------------------------------------------------------------- measurements
def precession(trajectory: Trajectory, axis: Any = (0, 0, 1), vertical: Any = None) -> Precession:
    """Precession of a body axis about a vertical: the mean rate of its azimuth.

    The body axis ``axis`` is carried into space by the attitude; its azimuth
    φ(t) about ``vertical`` (counter-clockwise, right-handed) is unwrapped. The
    rate is the mean dφ/dt over whole nutation periods: the change of φ between
    the first and the last maximum of the tilt (refined times, see
    :func:`nutation`, φ linearly interpolated there), divided by the time
    between them, so the nutation does not bias it whatever the sampling. When
    the tilt has fewer than two maxima (a steady precession, or a record shorter
    than a nutation period) the rate is the least-squares slope of φ(t).

    Parameters
    ----------
    trajectory : a Trajectory from :func:`tumble.simulate`.
    axis : (3,) body axis, body coordinates (any length > 0); default body z,
        the symmetry axis of tumble's tops.
    vertical : (3,) space direction to precess about; default the upward
        vertical −g/|g| of the trajectory's gravity, or space z without gravity.

    Returns
    -------
    Precession.

    Raises
    ------
    InputError
        Fewer than 3 samples, a zero ``axis`` or ``vertical``, or an axis that
        comes within 1e-6 rad of the vertical (its azimuth is undefined there).
    """
    traj = _trajectory(trajectory)
    up = _vertical(traj, vertical)
    _, directions = _space_axis(traj, axis)
    angle = _azimuth(directions, up, "`axis`", traj.t)
    tilt = _tilt(directions, up)
    times = traj.t
    maxima_times = np.empty(0)
    if np.ptp(tilt) > STEADY_SWING:
        maxima_times = _turning_points(times, tilt)[0]
    if maxima_times.size >= 2:
        start, stop = float(maxima_times[0]), float(maxima_times[-1])
        rate = (np.interp(stop, times, angle) - np.interp(start, times, angle)) / (stop - start)
        method = "whole nutation periods"
    else:
        rate = np.polyfit(times - times.mean(), angle, 1)[0]
        method = "least squares"
    return Precession(rate=float(rate), angle=angle, vertical=up, method=method)


def nutation(trajectory: Trajectory, axis: Any = (0, 0, 1), vertical: Any = None) -> Nutation:
    """Nutation of a body axis: the oscillation of its tilt θ(t) from a vertical.

    θ is the angle between the body axis ``axis`` (carried into space) and
    ``vertical``. Its turning points are the extreme samples of each swing,
    refined by the vertex of the parabola through the sample and its two
    neighbours (exact for a parabolic peak; for a sinusoid sampled n times a
    period, the time is off by at most ~(2π/n)³/24 of a radian of phase). The
    frequency is 2π over the mean time between successive maxima; with fewer
    than 3 maxima it is the peak of the spectrum of θ (coarser: a fraction of
    2π/duration). The amplitude is half the swing: (mean refined maximum − mean
    refined minimum) / 2, comparable to
    :attr:`tumble.theory.Gyroscope.nutation_amplitude` and to half the
    difference of its ``nutation_limits``.

    Parameters
    ----------
    trajectory : a Trajectory from :func:`tumble.simulate`.
    axis : (3,) body axis, body coordinates; default body z.
    vertical : (3,) space direction θ is measured from; default −g/|g|, or
        space z without gravity.

    Returns
    -------
    Nutation.

    Raises
    ------
    InputError
        Fewer than 3 samples, a zero ``axis`` or ``vertical``, a tilt that does
        not nutate (a swing below ``STEADY_SWING`` rad), or fewer than two
        turning points (less than about one period of nutation).
    """
    traj = _trajectory(trajectory)
    up = _vertical(traj, vertical)
    _, directions = _space_axis(traj, axis)
    tilt = _tilt(directions, up)
    times = traj.t
    swing = float(np.ptp(tilt))
    if not swing > STEADY_SWING:
        raise InputError(
            f"Expected the tilt of `axis` to nutate (a swing above {STEADY_SWING:g} rad), got "
            f"a swing of {swing:.3g} rad over {times[-1] - times[0]:.6g} s."
        )
    max_t, max_v, min_t, min_v = _turning_points(times, tilt)
    if max_t.size + min_t.size < 2:
        raise InputError(
            "Expected a trajectory covering at least one nutation period (two turning points "
            f"of the tilt), got {max_t.size + min_t.size} over {times[-1] - times[0]:.6g} s."
        )
    if max_t.size >= 3:
        frequency = 2 * math.pi * (max_t.size - 1) / (max_t[-1] - max_t[0])
        method = "turning points"
    else:
        frequency = _spectral_frequency(times, tilt)
        method = "spectrum"
    if max_v.size and min_v.size:
        amplitude = 0.5 * (float(max_v.mean()) - float(min_v.mean()))
    else:
        amplitude = 0.5 * swing
    if max_t.size >= 2:
        mean_tilt = _time_mean(times, tilt, float(max_t[0]), float(max_t[-1]))
    else:
        mean_tilt = _time_mean(times, tilt, float(times[0]), float(times[-1]))
    return Nutation(
        frequency=float(frequency),
        amplitude=amplitude,
        tilt=tilt,
        mean_tilt=mean_tilt,
        maxima_times=max_t,
        maxima=max_v,
        minima_times=min_t,
        minima=min_v,
        vertical=up,
        method=method,
    )


def _principal(trajectory: Trajectory) -> tuple[Array, Array]:
    """Principal moments (ascending) and axes of the inertia the dynamics used."""
    from tumble.massprops import principal_decomposition

    mp = trajectory.mass_properties
    inertia = mp.inertia if trajectory.pivot is None else mp.inertia_about(trajectory.pivot)
    return principal_decomposition(inertia)


def flips(trajectory: Trajectory) -> Flips:
    """The flips of a torque-free body: sign changes of ω along its intermediate axis.

    The component of ω (body coordinates) along the intermediate principal axis
    (of the inertia about the centre of mass, or about the pivot) is sampled;
    each sign change between two successive samples is located by linear
    interpolation (its error is third order in the sampling interval where the
    component crosses zero with no curvature, as the Jacobi sn and cn do).
    Samples within 1e-12 of the largest |ω| of zero are skipped, so round-off
    about an exact zero makes no flips. The period is twice the mean interval
    between successive flips: ω(t) changes sign twice in each of its periods,
    the period given by :func:`tumble.theory.flip_period`.

    Raises
    ------
    InputError
        Fewer than 3 samples, or fewer than two sign changes (no period can be
        measured: a record too short, or a body that does not flip).
    """
    traj = _trajectory(trajectory)
    _, axes = _principal(traj)
    middle = axes[:, 1]
    component = traj.omega @ middle
    scale = float(np.max(np.abs(traj.omega)))
    keep = np.flatnonzero(np.abs(component) > 1e-12 * scale)
    t, w = traj.t[keep], component[keep]
    change = np.flatnonzero(np.signbit(w[1:]) != np.signbit(w[:-1]))
    times = t[change] - w[change] * (t[change + 1] - t[change]) / (w[change + 1] - w[change])
    if times.size < 2:
        raise InputError(
            "Expected ω to change sign along the intermediate principal axis at least twice "
            f"to measure the flip period, got {times.size} sign changes over "
            f"{traj.t[-1] - traj.t[0]:.6g} s."
        )
    period = 2.0 * (times[-1] - times[0]) / (times.size - 1)
    return Flips(times=times, period=float(period), count=int(times.size), axis=middle)


def polhode(trajectory: Trajectory) -> Polhode:
    """The angular momentum in the principal axes, with the surfaces that hold it.

    ``L_k = I_k ω_k`` in the principal axes of the inertia about the centre of
    mass (or about the pivot). For torque-free motion L stays on the sphere
    ``|L| = const`` and on the energy ellipsoid ``Σ L_k² / (2 E I_k) = 1`` (semi-axes
    √(2 E I_k)): their intersection is the polhode. Both are taken at t = 0.

    Raises
    ------
    InputError
        Fewer than 3 samples.
    """
    traj = _trajectory(trajectory)
    moments, axes = _principal(traj)
    momentum = (traj.omega @ axes) * moments
    energy = 0.5 * float(np.sum(momentum[0] ** 2 / moments))
    return Polhode(
        angular_momentum_body=momentum,
        moments=moments,
        axes=axes,
        energy_ellipsoid=np.sqrt(2.0 * energy * moments),
        momentum_sphere=float(np.linalg.norm(momentum[0])),
    )


def drift(trajectory: Trajectory) -> dict[str, float]:
    """Largest relative drift of each quantity the motion conserves over the
    trajectory (:attr:`tumble.Trajectory.drift`; a copy)."""
    traj = _trajectory(trajectory)
    return dict(traj.drift)


def body_precession_rate(trajectory: Trajectory, axis: Any) -> float:
    """Least-squares rate (rad/s) at which ω, in body coordinates, turns about the
    body ``axis`` (a free symmetric top's ω turns about its symmetry axis at
    ``(I⊥ − Is)/I⊥ · ωs``)."""
    traj = _trajectory(trajectory)
    unit = _unit(axis, "axis")
    angle = _azimuth(traj.omega, unit, "ω", traj.t)
    times = traj.t
    return float(np.polyfit(times - times.mean(), angle, 1)[0])
