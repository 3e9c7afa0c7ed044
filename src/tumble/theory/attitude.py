"""Spacecraft attitude in closed form: the libration of a body in a circular orbit
under the gravity-gradient torque, and a slew under quaternion feedback."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.massprops import MassProperties, as_mass_properties, readonly
from tumble.theory.common import as_times, positive
from tumble.theory.gyrostats import principal_axis
from tumble.units import to_si

__all__ = ["AttitudeSlew", "Libration", "attitude_slew", "gravity_gradient_libration"]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Libration:
    """Small librations about the equilibrium of a body in a circular orbit (see
    :func:`gravity_gradient_libration`).

    Attributes
    ----------
    orbit_rate : n, rad/s.
    moments : (A, B, C), kg·m²: about the radial axis, the along-track axis and
        the orbit normal at equilibrium.
    k1, k3 : Hughes's inertia ratios (C − A) / B and (C − B) / A.
    pitch_frequency : rad/s, √(3 (B − A) / C) n (NaN when pitch is unstable).
    roll_yaw_frequencies : (2,) rad/s, the two frequencies of the coupled roll and
        yaw (NaN when unstable), slower first.
    pitch_stable, roll_yaw_stable : linear stability of each motion.
    region : ``"Lagrange"`` (C > B > A), ``"DeBra-Delp"`` (the second stable
        region, with the along-track axis major and the normal minor) or
        ``"unstable"``.
    """

    orbit_rate: float
    moments: tuple[float, float, float]
    k1: float
    k3: float
    pitch_frequency: float
    roll_yaw_frequencies: Array
    pitch_stable: bool
    roll_yaw_stable: bool
    region: str

    @property
    def stable(self) -> bool:
        return self.pitch_stable and self.roll_yaw_stable

    def pitch_frequency_at(self, amplitude: float) -> float:
        """The frequency (rad/s) of a pitch libration of any ``amplitude`` θ_max
        (rad, below 90°): ``θ̈ = −(ω_p² / 2) sin 2θ`` is a pendulum in 2θ, of period
        ``4 K(sin² θ_max) / ω_p`` (K the complete elliptic integral of the first
        kind, parameter m = k²): ω_p (1 − θ_max² / 4 + …) for small swings."""
        from scipy.special import ellipk

        if not self.pitch_stable:
            return math.nan
        quarter = float(ellipk(math.sin(amplitude) ** 2))
        return 2.0 * math.pi * self.pitch_frequency / (4.0 * quarter)

    def pitch_amplitude(self, angle: float, rate: float) -> float:
        """The amplitude θ_max (rad) of the pitch libration through ``angle`` (rad)
        at ``rate`` (rad/s, relative to the orbiting frame): from the first
        integral ``θ̇² + ω_p² sin² θ = ω_p² sin² θ_max``."""
        sine = math.sin(angle) ** 2 + (rate / self.pitch_frequency) ** 2
        return math.asin(min(1.0, math.sqrt(sine)))


def gravity_gradient_libration(
    mp: MassProperties,
    orbit_rate: Any,
    radial: Any = (1.0, 0.0, 0.0),
    normal: Any = (0.0, 0.0, 1.0),
) -> Libration:
    """Small librations of a body in a circular orbit of rate n about its equilibrium:
    the principal axis ``radial`` along the local vertical, ``normal`` along the
    orbit normal, at rest in the orbiting frame.

    With A, B, C the principal moments about the radial, along-track
    (normal × radial) and normal axes, linearised (Hughes, *Spacecraft
    Attitude Dynamics*, 1986, §9.3; derived afresh and checked by simulation
    in ``tests/test_theory_gyrostats.py``)::

        pitch:     C θ̈ + 3 n² (B − A) θ = 0
        roll–yaw:  s⁴ + (1 + 3 k1 + k1 k3) n² s² + 4 k1 k3 n⁴ = 0,
                   k1 = (C − A) / B,   k3 = (C − B) / A

    Pitch is stable iff B > A; roll and yaw iff k1 k3 > 0, 1 + 3 k1 + k1 k3 > 0
    and (1 + 3 k1 + k1 k3)² > 16 k1 k3. With pitch, that leaves the Lagrange
    region C > B > A and the small DeBra–Delp region.

    Parameters
    ----------
    mp : the body.
    orbit_rate : n, rad/s (> 0).
    radial, normal : two perpendicular principal axes of the body (body coordinates).

    Raises
    ------
    InputError
        Bad values, axes that are not principal or not perpendicular.

    Examples
    --------
    Moments C > B > A (the Lagrange region): stable, the pitch libration at
    ``n √(3 (B − A) / C)``.

    >>> import numpy as np
    >>> import tumble as tb
    >>> satellite = tb.MassProperties(100.0, [0, 0, 0], np.diag([80.0, 100.0, 120.0]))
    >>> swing = tb.theory.gravity_gradient_libration(satellite, orbit_rate=0.0011)
    >>> swing.region, swing.pitch_stable, swing.roll_yaw_stable
    ('Lagrange', True, True)
    >>> print(f"{swing.pitch_frequency / 0.0011:.6f}")  # √(3 × 20 / 120)
    0.707107
    """
    mp = as_mass_properties(mp)
    n = positive(orbit_rate, "angular_velocity", "orbit_rate")
    e_radial, a, _ = principal_axis(mp, radial, "radial")
    e_normal, c, _ = principal_axis(mp, normal, "normal")
    if abs(float(e_radial @ e_normal)) > 1e-9:
        raise InputError(
            f"Expected `radial` perpendicular to `normal`, got {e_radial.tolist()} and "
            f"{e_normal.tolist()}."
        )
    along = np.cross(e_normal, e_radial)
    b = float(along @ mp.inertia @ along)
    k1 = (c - a) / b
    k3 = (c - b) / a
    pitch_square = 3.0 * (b - a) / c
    linear = 1.0 + 3.0 * k1 + k1 * k3
    discriminant = linear * linear - 16.0 * k1 * k3
    roll_yaw_stable = k1 * k3 > 0 and linear > 0 and discriminant > 0
    if roll_yaw_stable:
        root = math.sqrt(discriminant)
        frequencies = n * np.sqrt([(linear - root) / 2.0, (linear + root) / 2.0])
    else:
        frequencies = np.full(2, math.nan)
    pitch_stable = pitch_square > 0
    if pitch_stable and roll_yaw_stable:
        region = "Lagrange" if k1 > 0 else "DeBra-Delp"
    else:
        region = "unstable"
    return Libration(
        orbit_rate=n,
        moments=(a, b, c),
        k1=k1,
        k3=k3,
        pitch_frequency=n * math.sqrt(pitch_square) if pitch_stable else math.nan,
        roll_yaw_frequencies=readonly(frequencies),
        pitch_stable=pitch_stable,
        roll_yaw_stable=roll_yaw_stable,
        region=region,
    )


@dataclass(frozen=True)
class AttitudeSlew:
    """A rotation about a principal axis under quaternion feedback (see
    :func:`attitude_slew`).

    Attributes
    ----------
    moment : I about the axis, kg·m².
    natural_frequency : ω_n = √(K / (2 I)), rad/s.
    damping_ratio : ζ = C / √(2 K I).
    decay_rate : 1/s, the slowest exponential rate of the linear motion near the
        target: ζ ω_n when ζ < 1, ω_n (ζ − √(ζ² − 1)) when overdamped.
    """

    moment: float
    natural_frequency: float
    damping_ratio: float
    decay_rate: float

    def angle(self, t: Any, angle0: float) -> Array:
        """The angle from the target (rad) at times ``t`` (s) after a small
        rest-to-rest step of ``angle0`` rad: the damped oscillator of the
        linearised law."""
        times, shape = as_times(t)
        wn, zeta = self.natural_frequency, self.damping_ratio
        if zeta < 1.0:
            wd = wn * math.sqrt(1.0 - zeta * zeta)
            values = np.exp(-zeta * wn * times) * (
                np.cos(wd * times) + zeta * wn / wd * np.sin(wd * times)
            )
        elif zeta == 1.0:
            values = np.exp(-wn * times) * (1.0 + wn * times)
        else:
            root = wn * math.sqrt(zeta * zeta - 1.0)
            slow, fast = -zeta * wn + root, -zeta * wn - root
            values = (fast * np.exp(slow * times) - slow * np.exp(fast * times)) / (fast - slow)
        return readonly(np.reshape(angle0 * values, shape))


def attitude_slew(
    mp: MassProperties, stiffness: Any, damping: Any, axis: Any = (0.0, 0.0, 1.0)
) -> AttitudeSlew:
    """A slew about the principal axis ``axis`` under ``τ = −K ε − C ω``
    (:class:`tumble.torques.AttitudeController`): the error angle φ obeys
    ``I φ̈ = −K sin(φ/2) − C φ̇`` (ε = sin(φ/2) along the axis), so near the
    target ω_n = √(K / (2 I)) and ζ = C / √(2 K I) (Wie, *Space Vehicle
    Dynamics and Control*, §7.3). The body's rotors, if they produce the torque,
    are locked in ``mp``: I is the whole moment about the axis.

    Raises
    ------
    InputError
        Bad gains, an axis that is not principal.

    Examples
    --------
    >>> import tumble as tb
    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)  # I = 0.008 kg·m²
    >>> slew = tb.theory.attitude_slew(ball, stiffness=0.016, damping=0.008)
    >>> print(f"ω_n = {slew.natural_frequency:.6f} rad/s, ζ = {slew.damping_ratio:.6f}")
    ω_n = 1.000000 rad/s, ζ = 0.500000
    """
    mp = as_mass_properties(mp)
    k = positive(stiffness, "torque", "stiffness")
    c = to_si(damping, "damping", "damping")
    if c < 0:
        raise InputError(f"Expected `damping` >= 0 N·m·s, got {c!r}.")
    _, moment, _ = principal_axis(mp, axis)
    wn = math.sqrt(k / (2.0 * moment))
    zeta = c / math.sqrt(2.0 * k * moment)
    rate = zeta * wn if zeta < 1.0 else wn * (zeta - math.sqrt(zeta * zeta - 1.0))
    return AttitudeSlew(moment, wn, zeta, rate)
