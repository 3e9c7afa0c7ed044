"""Bodies carrying rotors and dampers in closed form: the stability of a spinning
gyrostat (dual spin), the decay of nutation by a Kane damper, the spin-up of a
wheel.

Each body is given by its mass properties with every part inside it as if
locked (tumble's convention, :mod:`tumble.parts`), spinning about one of its
principal axes. The formulas were derived by linearising the equations of
:mod:`tumble.core.parts` (checked with sympy and against simulations in
``tests/test_theory_gyrostats.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.massprops import MassProperties, as_mass_properties, readonly
from tumble.theory.common import as_times, format_values, positive
from tumble.units import to_si, vector_to_si

__all__ = [
    "GyrostatStability",
    "KaneDamperDecay",
    "WheelSpinUp",
    "gyrostat_stability",
    "kane_damper_decay",
    "principal_axis",
    "wheel_spin_up",
]

Array = NDArray[np.float64]

#: How far from a principal axis an axis may be: |I a − (a·I a) a| / |I|.
AXIS_TOLERANCE = 1e-9


def principal_axis(mp: MassProperties, axis: Any, name: str = "axis") -> tuple[Array, float, Array]:
    """``axis`` (body coordinates) as a unit vector, the moment about it and the two
    other principal moments (ascending), for a body with that principal axis.

    Raises
    ------
    InputError
        A zero axis, or one that is not a principal axis of ``mp`` (about the
        centre of mass).
    """
    vector = vector_to_si(axis, "dimensionless", name, (3,))
    size = float(np.linalg.norm(vector))
    if not size > 0:
        raise InputError(f"Expected `{name}` to be a non-zero vector, got {vector.tolist()}.")
    unit = vector / size
    inertia = mp.inertia
    moment = float(unit @ inertia @ unit)
    if np.linalg.norm(inertia @ unit - moment * unit) > AXIS_TOLERANCE * np.linalg.norm(inertia):
        _, axes = mp.principal()
        raise InputError(
            f"Expected `{name}` along a principal axis of the body, got {unit.tolist()} "
            f"(its principal axes, as columns: {np.round(axes, 6).tolist()})."
        )
    moments = np.linalg.eigvalsh(inertia)
    others = np.delete(moments, int(np.argmin(np.abs(moments - moment))))
    return unit, moment, others


# ------------------------------------------------------------------ dual spin
@dataclass(frozen=True)
class GyrostatStability:
    """The steady spin of a gyrostat about a principal axis (see :func:`gyrostat_stability`).

    Attributes
    ----------
    spin_rate : Ω, the body's spin about the axis, rad/s.
    rotor_momentum : h = J Ω_rel, the rotors' momentum along the axis (relative
        spin), kg·m²/s.
    spin_moment, transverse_moments : I_k and (I_i, I_j), kg·m² (parts locked).
    stable : True when small deviations stay small.
    nutation_frequency : rad/s, the frequency of small deviations of ω in the
        body (NaN when unstable).
    growth_rate : 1/s, the exponential rate of growth of a deviation (0 when stable).
    unstable_between : the range of h (kg·m²/s) in which this spin is unstable:
        between ``(I_i − I_k) Ω`` and ``(I_j − I_k) Ω``.
    """

    spin_rate: float
    rotor_momentum: float
    spin_moment: float
    transverse_moments: tuple[float, float]
    stable: bool
    nutation_frequency: float
    growth_rate: float
    unstable_between: tuple[float, float]


def gyrostat_stability(
    mp: MassProperties, spin_rate: Any, rotor_momentum: Any = 0.0, axis: Any = (0.0, 0.0, 1.0)
) -> GyrostatStability:
    """Linear stability of a gyrostat spinning at ``spin_rate`` Ω about the principal
    axis ``axis`` with rotors of momentum ``rotor_momentum`` h along it.

    With the body's locked principal moments I_k about the axis and I_i, I_j
    about the other two, small deviations of ω obey ``ẍ = −P x / (I_i I_j)``,
    ``P = ((I_i − I_k) Ω − h)((I_j − I_k) Ω − h)``: the spin is stable iff
    P > 0, with nutation at √(P / (I_i I_j)), and grows at √(−P / (I_i I_j))
    otherwise. For the intermediate axis (k = 2) P is
    ``(h − (I3 − I2) Ω)(h + (I2 − I1) Ω)``: a rotor spinning with the body
    faster than ``h > (I3 − I2) Ω`` stabilises it (the dual-spin satellite;
    Hughes, *Spacecraft Attitude Dynamics*, §7.2; Likins, J. Spacecraft 4 (1967)
    1638). With h = 0 this is the rigid body's
    :func:`tumble.theory.axis_stability`. h is J Ω_rel at the steady spin: the
    same holds for a motor holding the rotor's relative speed and for a free
    rotor (which keeps J (ω·a + Ω_rel) instead); the sign of h is that of Ω
    when the rotor turns the same way as the body.

    Parameters
    ----------
    mp : the body, its rotors locked inside.
    spin_rate : Ω, rad/s (not 0).
    rotor_momentum : h, kg·m²/s.
    axis : a principal axis of the body (body coordinates).

    Raises
    ------
    InputError
        A zero spin, an axis that is not principal.

    Examples
    --------
    Alone, a spin about the intermediate axis of (1, 2, 3) kg·m² is
    unstable; a rotor along it with ``h > (I3 − I2) Ω`` makes it stable
    (the dual-spin satellite):

    >>> import numpy as np
    >>> import tumble as tb
    >>> body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    >>> bare = tb.theory.gyrostat_stability(body, 1.0, axis=[0, 1, 0])
    >>> bare.stable, bare.unstable_between
    (False, (-1.0, 1.0))
    >>> print(f"{bare.growth_rate:.6f} 1/s")  # as tb.theory.axis_stability
    0.577350 1/s
    >>> tb.theory.gyrostat_stability(body, 1.0, rotor_momentum=2.0, axis=[0, 1, 0]).stable
    True
    """
    mp = as_mass_properties(mp)
    spin = to_si(spin_rate, "angular_velocity", "spin_rate")
    if spin == 0:
        raise InputError("Expected `spin_rate` ≠ 0 rad/s, got 0.0.")
    h = to_si(rotor_momentum, "angular_momentum", "rotor_momentum")
    _, moment, (first, second) = principal_axis(mp, axis)
    product = ((first - moment) * spin - h) * ((second - moment) * spin - h)
    square = product / (first * second)
    edges = sorted(((first - moment) * spin, (second - moment) * spin))
    return GyrostatStability(
        spin_rate=spin,
        rotor_momentum=h,
        spin_moment=moment,
        transverse_moments=(float(first), float(second)),
        stable=bool(square > 0),
        nutation_frequency=math.sqrt(square) if square > 0 else math.nan,
        growth_rate=math.sqrt(-square) if square < 0 else 0.0,
        unstable_between=(float(edges[0]), float(edges[1])),
    )


# ------------------------------------------------------------------ energy sink
@dataclass(frozen=True)
class KaneDamperDecay:
    """The linearised motion of a body with a Kane damper about a steady spin
    (see :func:`kane_damper_decay`).

    Attributes
    ----------
    nutation_frequency : rad/s, the frequency of the nutation mode in the body.
    decay_rate : 1/s, −Re of the nutation mode's exponent: > 0 the nutation
        decays, < 0 it grows (a spin about the minor or intermediate axis).
    time_constant : s, 1 / |decay_rate| (inf when neutral).
    exponents : (4,) every exponent of the transverse motion (the nutation mode
        and the damper's own mode, with their conjugates), 1/s.
    spin_down_rate : 1/s, the rate at which the sphere's axial spin relative to
        the body dies out, D I_k / (J (I_k − J)).
    """

    nutation_frequency: float
    decay_rate: float
    time_constant: float
    exponents: Array
    spin_down_rate: float

    @property
    def grows(self) -> bool:
        """True when the nutation grows (the spin is not about the major axis)."""
        return self.decay_rate < 0


def kane_damper_decay(
    mp: MassProperties,
    damper_inertia: Any,
    damping: Any,
    spin_rate: Any,
    axis: Any = (0.0, 0.0, 1.0),
) -> KaneDamperDecay:
    """The nutation of a body with a Kane damper spinning at Ω about a principal axis,
    linearised: its frequency and its rate of decay (or growth).

    The damper is a sphere of moment J turning in a fluid with coupling D
    (:class:`tumble.KaneDamper`), in the body's locked mass properties. With
    x the deviation of ω and z the sphere's rate relative to the body in the
    plane transverse to the spin, platform moments A' = I_i − J, B' = I_j − J::

        A' ẋ_i = −Ω (I_k − I_j) x_j + D z_i        ż_i = −ẋ_i − (D / J) z_i + Ω z_j
        B' ẋ_j = +Ω (I_k − I_i) x_i + D z_j        ż_j = −ẋ_j − (D / J) z_j − Ω z_i

    The exponents are the eigenvalues of this 4 × 4 system; the nutation mode
    is the slowest to decay. By Routh–Hurwitz it decays for any D > 0 about the
    major axis and grows about the others: the major-axis rule of energy
    dissipation (Explorer 1, Bracewell & Garriott, Nature 182 (1958) 760). For
    a small D, ``decay_rate ≈ D (I3 − I_t) / ((I_t − J)(I3 − J))`` for an
    axisymmetric body (I_t transverse); Likins, JPL TR 32-860 (1966), gives
    the energy-sink approximation of the same.

    Parameters
    ----------
    mp : the body, the damper's sphere locked inside.
    damper_inertia, damping : the damper's J (kg·m², > 0) and D (N·m·s, > 0).
    spin_rate : Ω, rad/s (not 0).
    axis : a principal axis (body coordinates).

    Raises
    ------
    InputError
        Bad values; a damper inertia the body cannot hold (J >= a transverse moment).

    Examples
    --------
    The major-axis rule: the same damper damps the nutation of a spin about
    the largest moment and makes it grow about the smallest.

    >>> import numpy as np
    >>> import tumble as tb
    >>> oblate = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 1.0, 2.0]))
    >>> prolate = tb.MassProperties(1.0, [0, 0, 0], np.diag([2.0, 2.0, 1.0]))
    >>> for body in (oblate, prolate):
    ...     decay = tb.theory.kane_damper_decay(body, 0.05, 0.1, spin_rate=1.0)
    ...     print(f"{decay.decay_rate:+.6f} 1/s")
    +0.026644 1/s
    -0.002938 1/s
    """
    mp = as_mass_properties(mp)
    j = positive(damper_inertia, "inertia", "damper_inertia")
    d = positive(damping, "damping", "damping")
    spin = to_si(spin_rate, "angular_velocity", "spin_rate")
    if spin == 0:
        raise InputError("Expected `spin_rate` ≠ 0 rad/s, got 0.0.")
    _, moment, (first, second) = principal_axis(mp, axis)
    if j >= min(first, second, moment):
        raise InputError(
            f"Expected `damper_inertia` below the body's principal moments "
            f"{format_values([first, second, moment])} kg·m² (the sphere is inside it), got {j!r}."
        )
    a, b = first - j, second - j
    # Rows: ẋ_i, ẋ_j, ż_i, ż_j as linear forms in (x_i, x_j, z_i, z_j).
    xi = np.array([0.0, -spin * (moment - second) / a, d / a, 0.0])
    xj = np.array([spin * (moment - first) / b, 0.0, 0.0, d / b])
    zi = -xi + np.array([0.0, 0.0, -d / j, spin])
    zj = -xj + np.array([0.0, 0.0, -spin, -d / j])
    exponents = np.linalg.eigvals(np.array([xi, xj, zi, zj]))
    exponents.setflags(write=False)
    nutation = exponents[int(np.argmax(exponents.real))]
    rate = -float(nutation.real)
    return KaneDamperDecay(
        nutation_frequency=abs(float(nutation.imag)),
        decay_rate=rate,
        time_constant=1.0 / abs(rate) if rate != 0 else math.inf,
        exponents=exponents,
        spin_down_rate=d * moment / (j * (moment - j)),
    )


# ------------------------------------------------------------------ spin-up
@dataclass(frozen=True)
class WheelSpinUp:
    """A wheel on a principal axis spun up by a constant motor torque from a body
    at rest (see :func:`wheel_spin_up`).

    Attributes
    ----------
    body_acceleration : ω̇ of the body about the axis, rad/s² (= −u / (I − J)).
    rotor_acceleration : Ω̇ of the wheel relative to the body, rad/s² (= u / J + u / (I − J)).
    rotor_speed0 : the wheel's relative speed at t = 0, rad/s.
    moment, rotor_inertia, motor_torque : I (locked), J, u.
    axis : the unit axis, body coordinates.
    """

    body_acceleration: float
    rotor_acceleration: float
    rotor_speed0: float
    moment: float
    rotor_inertia: float
    motor_torque: float
    axis: Array

    def at(self, t: Any) -> tuple[Array, Array, Array, Array]:
        """At times ``t`` (s): the body's rate about the axis (rad/s), the wheel's
        relative speed (rad/s), the angle the body has turned about the axis
        (rad) and the kinetic energy (J)."""
        times, shape = as_times(t)
        rate = self.body_acceleration * times
        speed = self.rotor_speed0 + self.rotor_acceleration * times
        angle = 0.5 * self.body_acceleration * times**2
        h = self.rotor_inertia * self.rotor_speed0 + self.motor_torque * times
        energy = 0.5 * (self.moment - self.rotor_inertia) * rate**2 + h**2 / (
            2 * self.rotor_inertia
        )
        return tuple(  # type: ignore[return-value]
            readonly(np.reshape(v, shape)) for v in (rate, speed, angle, energy)
        )


def wheel_spin_up(
    mp: MassProperties,
    rotor_inertia: Any,
    motor_torque: Any,
    axis: Any = (0.0, 0.0, 1.0),
    rotor_speed0: Any = 0.0,
) -> WheelSpinUp:
    """A wheel of moment J on the principal axis ``axis`` of a body at rest, driven by
    the motor torque u from t = 0 (the wheel may already spin at ``rotor_speed0``).

    Nothing acts from outside and the body starts at rest, so the total angular
    momentum J Ω0 a stays: the body turns about the axis only, and with
    ``h = J (ω + Ω)`` the wheel's axial momentum, ḣ = u and ``(I − J) ω + h = J Ω0``::

        ω̇ = −u / (I − J),        Ω̇ = u / J + u / (I − J)

    The body turns by −u t² / (2 (I − J)); the motor's work ∫ u Ω dt is the
    kinetic energy ``½ (I − J) ω² + h² / (2 J)``.

    Parameters
    ----------
    mp : the body, the wheel locked inside (I its moment about ``axis``).
    rotor_inertia : J, kg·m² (> 0, below I).
    motor_torque : u, N·m, on the wheel (the body feels −u).
    axis : a principal axis (body coordinates).
    rotor_speed0 : the wheel's relative speed at t = 0, rad/s.

    Raises
    ------
    InputError
        Bad values, an axis that is not principal, J >= I.

    Examples
    --------
    A wheel of 0.002 kg·m² driven at 1 mN·m in a body of 0.008 kg·m² (wheel
    locked): after 1 s the body turns back at ``u t / (I − J)``.

    >>> import tumble as tb
    >>> body = tb.shapes.solid_sphere(2.0, 0.1)
    >>> spin_up = tb.theory.wheel_spin_up(body, rotor_inertia=0.002, motor_torque=0.001)
    >>> body_rate, wheel_speed, angle, energy = spin_up.at(1.0)
    >>> print(f"body {body_rate:.4f} rad/s, wheel {wheel_speed:.4f} rad/s")
    body -0.1667 rad/s, wheel 0.6667 rad/s
    """
    mp = as_mass_properties(mp)
    j = positive(rotor_inertia, "inertia", "rotor_inertia")
    u = to_si(motor_torque, "torque", "motor_torque")
    speed0 = to_si(rotor_speed0, "angular_velocity", "rotor_speed0")
    unit, moment, _ = principal_axis(mp, axis)
    if j >= moment:
        raise InputError(
            f"Expected `rotor_inertia` below the body's moment {moment:.6g} kg·m² about the "
            f"axis (the wheel is inside it), got {j!r}."
        )
    return WheelSpinUp(
        body_acceleration=-u / (moment - j),
        rotor_acceleration=u / j + u / (moment - j),
        rotor_speed0=speed0,
        moment=moment,
        rotor_inertia=j,
        motor_torque=u,
        axis=readonly(unit),
    )
