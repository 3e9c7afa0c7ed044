"""Measurements on a simulated :class:`~tumble.Trajectory`.

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
* :func:`herpolhode` — ω in space on the invariable plane (the Poinsot
  construction: the inertia ellipsoid rolling on that plane).
* :func:`body_precession_rate` — the rate at which ω turns about a body axis.
* :func:`drift` — the relative drift of the conserved quantities.
* :func:`pointing_error` — the angle of the attitude from a target.
* :func:`orbit_deviation` — yaw, roll and pitch from the gravity-gradient
  equilibrium of a circular orbit.
* :func:`exponential_rate`, :func:`oscillation_frequency` — the rate of an
  exponential growth or decay, the frequency of an oscillation, of any signal.

These measurements side by side with a closed form of :mod:`tumble.theory` are
the theory checks of :mod:`tumble.checks`.

Conventions as in the rest of tumble: SI units (s, rad, rad/s), body axes for
``axis``, space axes for ``vertical``, quaternions ``[w, x, y, z]`` body → space.
Angles are unwrapped, so a sample must not be more than half a turn of the
azimuth away from the next (sample at least twice per turn).
"""

from __future__ import annotations

from tumble.analysis.angles import (
    Nutation,
    Precession,
    body_precession_rate,
    nutation,
    precession,
)
from tumble.analysis.common import STEADY_SWING
from tumble.analysis.motion import Flips, Herpolhode, Polhode, drift, flips, herpolhode, polhode
from tumble.analysis.spacecraft import (
    exponential_rate,
    orbit_deviation,
    oscillation_frequency,
    pointing_error,
)

__all__ = [
    "STEADY_SWING",
    "Flips",
    "Herpolhode",
    "Nutation",
    "Polhode",
    "Precession",
    "body_precession_rate",
    "drift",
    "exponential_rate",
    "flips",
    "herpolhode",
    "nutation",
    "orbit_deviation",
    "oscillation_frequency",
    "pointing_error",
    "polhode",
    "precession",
]
