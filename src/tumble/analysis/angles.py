"""The precession and nutation of a body axis about a vertical, and the precession
of ω in the body."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.analysis.common import (
    STEADY_SWING,
    as_trajectory,
    azimuth,
    space_axis,
    spectral_frequency,
    tilt_from,
    time_mean,
    turning_points,
    unit_vector,
    vertical_of,
)
from tumble.errors import InputError
from tumble.trajectory import Trajectory

__all__ = ["Nutation", "Precession", "body_precession_rate", "nutation", "precession"]

Array = NDArray[np.float64]


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

    Examples
    --------
    A top (a disk spun at 3000 rpm, 5 cm above its pivot) released from rest
    at 30°: its axis precesses about the vertical at the mean rate
    :func:`tumble.theory.gyroscope` gives.

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> import tumble as tb
    >>> disk = tb.shapes.solid_cylinder(0.5, 0.03, 0.01)
    >>> spin, pivot = 2 * np.pi * 50, [0, 0, -0.05]  # 3000 rpm; 5 cm below the centre
    >>> tilt = Rotation.from_euler("x", 30, degrees=True)
    >>> traj = tb.simulate(disk, [0, 0, spin], attitude0=tilt, pivot=pivot,
    ...                    gravity=[0, 0, -9.81], duration=1.0, dt=0.001)
    >>> top = tb.theory.gyroscope(disk, pivot, spin_rate=spin, tilt="30 deg")
    >>> turn = tb.analysis.precession(traj)
    >>> print(f"{turn.rate:.4f} rad/s ({turn.method}), theory {top.mean_precession_rate:.4f}")
    3.6858 rad/s (whole nutation periods), theory 3.6858
    """
    traj = as_trajectory(trajectory)
    up = vertical_of(traj, vertical)
    _, directions = space_axis(traj, axis)
    angle = azimuth(directions, up, "`axis`", traj.t)
    tilt = tilt_from(directions, up)
    times = traj.t
    maxima_times = np.empty(0)
    if np.ptp(tilt) > STEADY_SWING:
        maxima_times = turning_points(times, tilt)[0]
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
    the ``nutation_amplitude`` of :class:`tumble.theory.Gyroscope` and to half
    the difference of its ``nutation_limits``.

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

    Examples
    --------
    The default scenario's top (a thin disk of 1 kg and 10 cm radius, its pivot
    10 cm along its axis, spun at 200 rad/s) released from rest at 60°: its tilt
    nods with the period and between the limits of the exact solution
    (:func:`tumble.theory.gyroscope`).

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> import tumble as tb
    >>> disk, pivot = tb.shapes.thin_disk(1.0, 0.1), [0, 0, -0.1]
    >>> traj = tb.simulate(disk, [0, 0, 200.0], pivot=pivot, gravity=[0, 0, -9.81],
    ...                    attitude0=Rotation.from_euler("x", 60, degrees=True),
    ...                    duration=2.0, dt=0.001)
    >>> top = tb.theory.gyroscope(disk, pivot, spin_rate=200.0, tilt="60 deg")
    >>> nod = tb.analysis.nutation(traj)
    >>> print(f"{nod.frequency:.4f} rad/s, theory {2 * np.pi / top.nutation_period:.4f}")
    79.0410 rad/s, theory 79.0410
    >>> low, high = top.nutation_limits
    >>> print(f"amplitude {nod.amplitude:.6f} rad, theory {(high - low) / 2:.6f}")
    amplitude 0.010815 rad, theory 0.010815
    """
    traj = as_trajectory(trajectory)
    up = vertical_of(traj, vertical)
    _, directions = space_axis(traj, axis)
    tilt = tilt_from(directions, up)
    times = traj.t
    swing = float(np.ptp(tilt))
    if not swing > STEADY_SWING:
        raise InputError(
            f"Expected the tilt of `axis` to nutate (a swing above {STEADY_SWING:g} rad), got "
            f"a swing of {swing:.3g} rad over {times[-1] - times[0]:.6g} s."
        )
    max_t, max_v, min_t, min_v = turning_points(times, tilt)
    if max_t.size + min_t.size < 2:
        raise InputError(
            "Expected a trajectory covering at least one nutation period (two turning points "
            f"of the tilt), got {max_t.size + min_t.size} over {times[-1] - times[0]:.6g} s."
        )
    if max_t.size >= 3:
        frequency = 2 * math.pi * (max_t.size - 1) / (max_t[-1] - max_t[0])
        method = "turning points"
    else:
        frequency = spectral_frequency(times, tilt)
        method = "spectrum"
    if max_v.size and min_v.size:
        amplitude = 0.5 * (float(max_v.mean()) - float(min_v.mean()))
    else:
        amplitude = 0.5 * swing
    if max_t.size >= 2:
        mean_tilt = time_mean(times, tilt, float(max_t[0]), float(max_t[-1]))
    else:
        mean_tilt = time_mean(times, tilt, float(times[0]), float(times[-1]))
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


def body_precession_rate(trajectory: Trajectory, axis: Any) -> float:
    """Least-squares rate (rad/s) at which ω, in body coordinates, turns about the
    body ``axis``, positive by the right-hand rule about it (a free symmetric
    top's ω turns about its symmetry axis at ``(Is − I⊥)/I⊥ · ωs``)."""
    traj = as_trajectory(trajectory)
    unit = unit_vector(axis, "axis")
    angle = azimuth(traj.omega, unit, "ω", traj.t)
    times = traj.t
    return float(np.polyfit(times - times.mean(), angle, 1)[0])
