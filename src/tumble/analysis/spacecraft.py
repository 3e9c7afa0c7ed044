"""Measurements of spacecraft motions: the pointing error from a target, the
deviation from the gravity-gradient equilibrium of an orbit, exponential rates
and oscillation frequencies of sampled signals."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.analysis.common import (
    as_trajectory,
    spectral_frequency,
    turning_points,
    unit_vector,
)
from tumble.errors import InputError
from tumble.trajectory import Trajectory

__all__ = ["exponential_rate", "orbit_deviation", "oscillation_frequency", "pointing_error"]

Array = NDArray[np.float64]


def pointing_error(trajectory: Trajectory, target: Any) -> Array:
    """(n,) the angle of the rotation from ``target`` to the body's attitude, rad, in
    [0, π]; ``target`` a quaternion ``[w, x, y, z]`` (body → space) or a scipy
    ``Rotation``."""
    traj = as_trajectory(trajectory)
    if not isinstance(target, Rotation):
        quaternion = np.asarray(target, dtype=float)
        if quaternion.shape != (4,) or not np.linalg.norm(quaternion) > 0:
            raise InputError(
                f"Expected `target` to be a non-zero quaternion [w, x, y, z], got "
                f"{quaternion.tolist()}."
            )
        target = Rotation.from_quat(quaternion, scalar_first=True)
    return np.asarray((target.inv() * traj.rotation).magnitude())


def orbit_deviation(
    trajectory: Trajectory,
    orbit_rate: float,
    radial_axis: Any,
    normal_axis: Any,
    radial0: Any = (1.0, 0.0, 0.0),
    orbit_normal: Any = (0.0, 0.0, 1.0),
) -> Array:
    """(n, 3) the small rotation (rad) that takes a body from its equilibrium in a
    circular orbit to its attitude: yaw about the body's ``radial_axis``, roll
    about the along-track axis (normal × radial) and pitch about ``normal_axis``
    (body coordinates), with the orbit of :class:`tumble.torques.GravityGradient`
    (``orbit_rate`` n, the unit vector to the body starting at ``radial0`` and
    turning about ``orbit_normal``, space axes). At equilibrium the body's radial
    axis points along that vector and its normal axis along the orbit's normal.
    """
    traj = as_trajectory(trajectory)
    body_radial = unit_vector(radial_axis, "radial_axis")
    body_normal = unit_vector(normal_axis, "normal_axis")
    normal = unit_vector(orbit_normal, "orbit_normal")
    start = np.asarray(radial0, dtype=float)
    first = start - (start @ normal) * normal
    if not np.linalg.norm(first) > 0:
        raise InputError(f"Expected `radial0` off the orbit's normal, got {start.tolist()}.")
    first /= np.linalg.norm(first)
    body_along = np.cross(body_normal, body_radial)
    # Body → orbiting frame at equilibrium: the body's (radial, along, normal) on
    # the frame's (e1, e2, n); the orbiting frame turns about n at the orbit rate.
    body_frame = np.column_stack([body_radial, body_along, body_normal])
    orbit_frame = np.column_stack([first, np.cross(normal, first), normal])
    turned = Rotation.from_rotvec(np.outer(orbit_rate * traj.t, normal))
    equilibrium = turned * Rotation.from_matrix(orbit_frame @ body_frame.T)
    rotation = (equilibrium.inv() * traj.rotation).as_rotvec()  # body coordinates
    return np.asarray(rotation @ body_frame)


def exponential_rate(t: Any, values: Any, band: tuple[float, float] | None = None) -> float:
    """The rate (1/s) of exponential growth (> 0) or decay of ``values``: the
    least-squares slope of log |values| against ``t``, over the first stretch of
    samples with |value| inside ``band`` (low, high) when given: the linear stage
    of a growth, above the noise and below saturation (a motion that grows and
    shrinks again, such as a body that flips, enters the band more than once).

    Raises
    ------
    InputError
        Fewer than 3 samples in the band.

    Examples
    --------
    >>> import numpy as np
    >>> import tumble as tb
    >>> t = np.linspace(0.0, 2.0, 21)
    >>> print(f"{tb.analysis.exponential_rate(t, 0.01 * np.exp(0.7 * t)):.6f} 1/s")
    0.700000 1/s
    >>> print(f"{tb.analysis.exponential_rate(t, 2.0 * np.exp(-0.3 * t)):.6f} 1/s")
    -0.300000 1/s
    """
    times = np.asarray(t, dtype=float)
    sizes = np.abs(np.asarray(values, dtype=float))
    keep = sizes > 0
    if band is not None:
        keep &= (sizes >= band[0]) & (sizes <= band[1])
        inside = np.flatnonzero(keep)
        if inside.size:
            breaks = np.flatnonzero(np.diff(inside) > 1)
            last = inside[breaks[0]] if breaks.size else inside[-1]
            keep[last + 1 :] = False
    if np.count_nonzero(keep) < 3:
        raise InputError(
            f"Expected at least 3 samples to fit an exponential rate, got "
            f"{int(np.count_nonzero(keep))} (band {band})."
        )
    return float(np.polyfit(times[keep], np.log(sizes[keep]), 1)[0])


def oscillation_frequency(t: Any, values: Any) -> float:
    """The angular frequency (rad/s) of an oscillating signal: 2π over the mean time
    between its maxima (refined by parabolas), or the spectral peak when it has
    fewer than 3 maxima.

    Examples
    --------
    >>> import numpy as np
    >>> import tumble as tb
    >>> t = np.linspace(0.0, 10.0, 1001)
    >>> print(f"{tb.analysis.oscillation_frequency(t, np.sin(3.0 * t + 0.4)):.4f} rad/s")
    3.0000 rad/s
    """
    times = np.asarray(t, dtype=float)
    signal = np.asarray(values, dtype=float)
    maxima = turning_points(times, signal)[0]
    if maxima.size >= 3:
        return float(2 * math.pi * (maxima.size - 1) / (maxima[-1] - maxima[0]))
    return spectral_frequency(times, signal)
