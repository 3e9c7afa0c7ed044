"""The gimballed gyroscope carried round a vertical axis (the notes' gyrocompass)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import special

from tumble.errors import InputError
from tumble.massprops import (
    MassProperties,
    as_mass_properties,
    axisymmetric_moments,
)
from tumble.units import to_si, vector_to_si

__all__ = ["Gyrocompass", "gyrocompass"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Gyrocompass:
    """The gimballed gyroscope carried round a vertical axis (see :func:`gyrocompass`). SI units.

    Attributes
    ----------
    axial_moment : I_s, moment of the disk about its spin axis, kg·m².
    gimbal_moment : I_AB, moment of the disk about the gimbal axis AB (its
        transverse moment about the centre of mass), kg·m².
    spin_rate : ω_s, rad/s, as given.
    platform_rate : Ω, rad/s, as given.
    spin_angular_momentum : L_s = I_s |ω_s|, kg·m²/s.
    oscillation_frequency : β = √(L_s |Ω| / I_AB), rad/s: the small-angle
        frequency with the Ω² term dropped (Kleppner & Kolenkow; valid for
        ω_s ≫ Ω).
    small_oscillation_frequency : √(|Ω| (L_s − I_AB |Ω|) / I_AB), rad/s: the exact
        small-angle frequency.
    """

    axial_moment: float
    gimbal_moment: float
    spin_rate: float
    platform_rate: float
    spin_angular_momentum: float
    oscillation_frequency: float
    small_oscillation_frequency: float

    def angular_acceleration(self, theta: Any) -> Array:
        """θ̈ at angle θ: ``−(L_s |Ω| / I_AB) sin θ + Ω² sin θ cos θ``, rad/s².

        ``theta`` is a scalar or a 1-D array, rad (or quantities); the result has its shape.
        """
        if np.ndim(theta) == 0:
            angle = np.asarray(to_si(theta, "angle", "theta"))
        else:
            angle = vector_to_si(theta, "angle", "theta", (-1,))
        return np.asarray(
            np.sin(angle) * (self.platform_rate**2 * np.cos(angle) - self.oscillation_frequency**2)
        )

    def period(self, amplitude: Any) -> float:
        """Exact period of the oscillation of amplitude θ0 (released from rest at θ0), s.

        The energy integral of ``I_AB θ̈ = −L_s Ω sin θ + I_AB Ω² sin θ cos θ`` is
        ``θ̇² = 2 (cos θ − cos θ0)(β² − Ω² (cos θ + cos θ0)/2)``; with
        ``sin(θ/2) = sin(θ0/2) sin φ`` the quarter period becomes a complete
        elliptic integral, and
        ``T = 4 R_F(0, (β² − Ω² cos²(θ0/2)) cos²(θ0/2), β² − Ω² cos θ0)``
        (Carlson's R_F, DLMF 19.16.1). It tends to ``2π / small_oscillation_frequency``
        as θ0 → 0, to the pendulum's ``4 K(sin²(θ0/2)) / β`` as Ω²/β² → 0, and
        to ``inf`` as θ0 → π (the axis released upside down stays there).

        Parameters
        ----------
        amplitude : θ0 in [0, π], rad or ``"30 deg"``.
        """
        theta0 = to_si(amplitude, "angle", "amplitude")
        if not 0 <= theta0 <= math.pi:
            raise InputError(f"Expected `amplitude` in [0, π] rad, got {theta0!r}.")
        beta2 = self.oscillation_frequency**2
        omega2 = self.platform_rate**2
        half = math.cos(0.5 * theta0) ** 2
        return float(
            4.0
            * special.elliprf(
                0.0, (beta2 - omega2 * half) * half, beta2 - omega2 * math.cos(theta0)
            )
        )


def gyrocompass(mp: MassProperties, spin_rate: Any, platform_rate: Any) -> Gyrocompass:
    """The gyroscope in a gimbal carried round a vertical axis: its spin axis seeks Ω.

    A disk, symmetric about body z, spins about z and is pivoted at its centre
    of mass in a (massless) gimbal free to turn about a horizontal axis AB,
    perpendicular to the spin axis; the mount carrying AB is turned about the
    vertical at a constant rate Ω. θ is the angle of the spin axis from the
    vertical, in the plane perpendicular to AB. In a frame turning with the
    mount, the disk's angular velocity is
    ``θ̇ ê_AB + Ω (cos θ ê_s − sin θ ê_⊥) + ψ̇ ê_s``, and the Lagrangian
    ``½ I_AB (θ̇² + Ω² sin² θ) + ½ I_s (ψ̇ + Ω cos θ)²`` has ψ cyclic: the spin
    ``ω_s = ψ̇ + Ω cos θ`` is constant and, with ``L_s = I_s ω_s``,

        ``I_AB θ̈ = −L_s Ω sin θ + I_AB Ω² sin θ cos θ``.

    The spin axis swings about the direction of Ω like a pendulum. Dropping the
    Ω² term (ω_s ≫ Ω) gives the lecture notes' ``I_AB θ̈ + Ω L_s sin θ = 0`` and the
    small-angle frequency ``β = √(L_s Ω / I_AB) = √(ω_s Ω I_s / I_AB)``; with it,
    the small-angle frequency is ``√(β² − Ω²)``, and the direction of Ω is
    stable only when ``L_s > I_AB Ω``. (Kleppner & Kolenkow, An Introduction to
    Mechanics, ch. 7, the gyrocompass; the Ω² term is derived here.)

    Parameters
    ----------
    mp : the disk (any body symmetric about body z, pivoted at its centre of mass).
    spin_rate : ω_s, the total angular velocity component along the spin axis
        (constant when the disk spins freely in frictionless bearings), rad/s;
        with a motor holding the spin relative to the gimbal, ψ̇, instead, the
        equation differs at order Ω².
    platform_rate : Ω, rate of the mount about the vertical, rad/s.

    θ is taken between the spin angular momentum and Ω as vectors, so only
    the magnitudes of the two rates matter: the angular momentum settles along Ω.

    Returns
    -------
    Gyrocompass (with :meth:`Gyrocompass.period` for a large amplitude).

    Raises
    ------
    InputError
        If the body is not symmetric about z, or ``I_s |ω_s| <= I_AB |Ω|`` (the
        direction of Ω is then not stable: the spin is too slow).

    Examples
    --------
    A disk spun at 3000 rpm on a platform turning at 1 rad/s: its axis swings
    about the vertical at β, a little slower with the Ω² term kept; a large
    swing takes longer than a small one, like a pendulum's.

    >>> import numpy as np
    >>> import tumble as tb
    >>> disk = tb.shapes.solid_cylinder(0.5, 0.03, 0.01)
    >>> compass = tb.theory.gyrocompass(disk, spin_rate="3000 rpm", platform_rate=1.0)
    >>> print(f"β = {compass.oscillation_frequency:.4f}, "
    ...       f"exact {compass.small_oscillation_frequency:.4f} rad/s")
    β = 24.6146, exact 24.5943 rad/s
    >>> small = 2 * np.pi / compass.small_oscillation_frequency
    >>> print(f"{small:.6f} s, {compass.period('10 deg'):.6f} s, {compass.period('90 deg'):.6f} s")
    0.255473 s, 0.255958 s, 0.301354 s
    """
    mp = as_mass_properties(mp)
    axial, transverse = axisymmetric_moments(mp)
    w = to_si(spin_rate, "angular_velocity", "spin_rate")
    big_omega = to_si(platform_rate, "angular_velocity", "platform_rate")
    spin_momentum = axial * abs(w)
    if not spin_momentum > transverse * abs(big_omega):
        raise InputError(
            f"Expected |`spin_rate`| > I_AB |Ω| / I_s = {transverse * abs(big_omega) / axial:.6g} "
            f"rad/s for the spin axis to oscillate about the direction of Ω, got {w!r} "
            "(slower, the Ω² term tips it away)."
        )
    beta2 = spin_momentum * abs(big_omega) / transverse
    return Gyrocompass(
        axial_moment=axial,
        gimbal_moment=transverse,
        spin_rate=w,
        platform_rate=big_omega,
        spin_angular_momentum=spin_momentum,
        oscillation_frequency=math.sqrt(beta2),
        small_oscillation_frequency=math.sqrt(beta2 - big_omega * big_omega),
    )
