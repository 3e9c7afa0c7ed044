"""The heavy symmetric (Lagrange) top on a fixed pivot: precession, nutation,
the exact tilt of a top released from rest."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import special

from tumble.core.elliptic import ellipj_mc
from tumble.errors import InputError
from tumble.massprops import (
    PHYSICAL_TOLERANCE,
    MassProperties,
    as_mass_properties,
    axisymmetric_moments,
)
from tumble.theory.common import (
    as_times,
    format_values,
)
from tumble.units import to_si, vector_to_si

__all__ = ["Gyroscope", "gyroscope"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Gyroscope:
    """Heavy symmetric top on a fixed pivot (see :func:`gyroscope`). SI units, angles in rad.

    Attributes
    ----------
    axial_moment : I_s, moment about the symmetry axis, kg·m².
    transverse_moment : I⊥' = I⊥ + m l², transverse moment about the pivot, kg·m².
    lever_arm : l, signed distance from the pivot to the centre of mass along
        body +z, m (negative: the centre of mass is below a pivot at tilt < 90°).
    mass, gravity, spin_rate, tilt : as given (kg, m/s², rad/s, rad).
    precession_rate : m g l / (I_s ω_s), rad/s: the fast-top steady precession rate.
    precession_rates : (slow, fast) exact steady-precession rates at this tilt,
        rad/s, the roots of ``I⊥' cos θ Ω² − I_s ω_s Ω + m g l = 0`` (slow: the
        smaller in magnitude, → m g l / (I_s ω_s) for a fast top; fast:
        → I_s ω_s / (I⊥' cos θ)); None where the discriminant
        ``(I_s ω_s)² − 4 I⊥' m g l cos θ`` is negative (the spin is too slow for
        steady precession at this tilt).
    nutation_frequency : I_s ω_s / I⊥', rad/s: the fast-top nutation frequency.
    small_nutation_frequencies : (slow, fast) exact angular frequency of small
        nutation about each steady precession, rad/s,
        ``√((I_s ω_s / I⊥' − 2 Ω cos θ)² + Ω² sin² θ)``; None with
        ``precession_rates``.
    nutation_amplitude : m g l I⊥' sin θ0 / (I_s ω_s)², rad, in magnitude: the
        fast-top half-amplitude of the tilt's swing, (θ_max − θ_min)/2, of a top
        released from rest (its axis swings between θ0 and θ0 + 2 × this).
    nutation_limits : (θ_min, θ_max), rad: the exact turning points of the tilt
        of a top released from rest at θ0 (one of them is θ0).
    nutation_period : exact period of θ(t) of a top released from rest, s
        (``inf`` on a separatrix: an upright top spun below the sleeping-top limit).
    """

    mass: float
    gravity: float
    spin_rate: float
    tilt: float
    axial_moment: float
    transverse_moment: float
    lever_arm: float
    precession_rate: float
    precession_rates: tuple[float, float] | None
    nutation_frequency: float
    small_nutation_frequencies: tuple[float, float] | None
    nutation_amplitude: float
    nutation_limits: tuple[float, float]
    nutation_period: float
    # The solution u = cos θ of the top released from rest, in the variable
    # v = sign(l) u: v(t) = v0 − Δ (1 − m) sd²(p t | m) = v1 + Δ cd²(p t | m),
    # with _drop = Δ = v0 − v1, _mc = 1 − m, _low = 1 + v1, _rate = p.
    _sign: float = field(repr=False)
    _drop: float = field(repr=False)
    _mc: float = field(repr=False)
    _low: float = field(repr=False)
    _rate: float = field(repr=False)

    def tilt_at(self, t: Any) -> Array:
        """Exact tilt θ(t) from the upward vertical of the top released from rest at θ0, rad.

        With ``u = cos θ``, energy and the two conserved angular momenta give
        ``u̇² = f(u)``, a cubic whose roots ``u1 ≤ u0 ≤ u3`` bound the motion
        (for l > 0; for l < 0 the same holds for −u);
        ``u(t) = u0 − (u0 − u1) (1 − m) sd²(p t | m)`` with ``m = (u0 − u1)/(u3 − u1)``
        and ``p = √(β (u3 − u1)) / 2``, β = 2 m g l / I⊥'
        (Goldstein, Classical Mechanics, §5.7; Whittaker, Analytical Dynamics, §71).

        Parameters
        ----------
        t : time since release, s: a scalar or a 1-D array.

        Returns
        -------
        θ(t), rad: a float array of the shape of ``t``.
        """
        times, shape = as_times(t)
        # tumble's sn, cn, dn take 1 − m itself, which near the separatrix (m → 1)
        # a float m cannot carry; a Python loop, as they are compiled scalars.
        sd2 = np.empty(times.size)
        cd2 = np.empty(times.size)
        for n, phase in enumerate(self._rate * times):
            sn, cn, dn = ellipj_mc(float(phase), self._mc)
            sd2[n] = (sn / dn) ** 2
            cd2[n] = (cn / dn) ** 2
        # v = v0 − Δ (1 − m) sd² = v1 + Δ cd²: 1 − v from the first form and
        # 1 + v from the second, each a sum of non-negative terms.
        v_angle = _v_angle(self.tilt, self._sign)
        one_minus = 2.0 * math.sin(0.5 * v_angle) ** 2 + self._drop * self._mc * sd2
        one_plus = self._low + self._drop * cd2
        return _tilt_from(self._sign, one_minus, one_plus).reshape(shape)


def _tilt_from(sign: float, one_minus: Any, one_plus: Any) -> Array:
    """θ from ``1 − v`` and ``1 + v``, ``v = sign cos θ``: ``θ_v = 2 atan2(√(1 − v), √(1 + v))``,
    accurate near both poles."""
    angle = 2.0 * np.arctan2(np.sqrt(one_minus), np.sqrt(one_plus))
    return np.asarray(angle if sign > 0 else math.pi - angle)


def _v_angle(tilt: float, sign: float) -> float:
    """The tilt in the variable v = sign(l) cos θ: θ for l ≥ 0, π − θ for l < 0."""
    return tilt if sign > 0 else math.pi - tilt


def gyroscope(
    mp: MassProperties, pivot: Any, spin_rate: Any, tilt: Any, gravity: Any = 9.81
) -> Gyroscope:
    """Precession and nutation of a heavy symmetric top on a fixed pivot (the Lagrange top).

    The body is symmetric about body z (inertia about the centre of mass
    ``diag(I⊥, I⊥, I_s)``) and turns about a pivot on that axis, held fixed,
    under gravity g acting at the centre of mass, a distance l along +z from the
    pivot. With z-x-z Euler angles (precession φ about the upward vertical, tilt θ
    of the body z axis from it, spin ψ) the Lagrangian is
    ``½ I⊥' (θ̇² + φ̇² sin² θ) + ½ I_s (ψ̇ + φ̇ cos θ)² − m g l cos θ`` with
    ``I⊥' = I⊥ + m l²`` about the pivot. Two momenta are conserved, ``I_s ω_s``
    with ``ω_s = ψ̇ + φ̇ cos θ`` and ``p_φ``, and so is the energy (Goldstein,
    Classical Mechanics, §5.7; Landau & Lifshitz, Mechanics, §35, problem 1).

    ``spin_rate`` is ``ω_s``, the **total** angular velocity component along the
    symmetry axis (constant in the motion), not the spin ψ̇ relative to the
    precessing frame; the two differ by ``φ̇ cos θ``, and are equal at release
    from rest (φ̇ = 0).

    * Steady precession at tilt θ (θ̇ = 0, φ̇ = Ω constant) needs
      ``I⊥' cos θ Ω² − I_s ω_s Ω + m g l = 0``; for a fast top the slow root is
      ``Ω ≈ m g l / (I_s ω_s)``.
    * Small nutation about a steady precession has the frequency
      ``√((I_s ω_s / I⊥' − 2 Ω cos θ)² + Ω² sin² θ)``, ≈ ``I_s ω_s / I⊥'`` for a fast top.
    * Released from rest (θ̇ = φ̇ = 0) at θ0 the tilt nutates between θ0 and a
      turning point θ1; with ``u = cos θ``, ``a = I_s ω_s / I⊥'`` and
      ``β = 2 m g l / I⊥'``, ``u̇² = (u0 − u)(β (1 − u²) − a² (u0 − u))``, so
      ``u0 − u1`` is the positive root of ``β Δ² + (a² − 2 β u0) Δ − β (1 − u0²) = 0``:
      for a fast top ``Δ ≈ β sin² θ0 / a²``, i.e. the tilt swings by
      ``θ1 − θ0 ≈ 2 m g l I⊥' sin θ0 / (I_s ω_s)²``, and nutates at ≈ a.
      θ(t) follows from Jacobi's sn (:meth:`Gyroscope.tilt_at`).

    Parameters
    ----------
    mp : the top, symmetric about body z.
    pivot : (3,) body coordinates of the pivot, m, on the symmetry axis (the line
        through the centre of mass along z).
    spin_rate : ω_s, rad/s (signed, about body +z; ≠ 0), e.g. ``"3000 rpm"``.
    tilt : θ0, angle of body +z from the upward vertical, rad or ``"30 deg"``, in [0, π].
    gravity : g, magnitude of the acceleration of gravity, m/s² (≥ 0).

    Returns
    -------
    Gyroscope: the fast-top approximations and the exact values side by side.
    Precession rates are positive counter-clockwise about the upward vertical.

    Raises
    ------
    InputError
        If the body is not symmetric about body z, has no moment about it, the
        pivot is off the axis, the spin rate is zero, the tilt is outside [0, π]
        or gravity is negative.
    """
    mp = as_mass_properties(mp)
    axial, transverse_com = axisymmetric_moments(mp)
    p = vector_to_si(pivot, "length", "pivot", (3,))
    offset = mp.center_of_mass - p
    off_axis = math.hypot(float(offset[0]), float(offset[1]))
    size = max(float(np.linalg.norm(offset)), math.sqrt(float(np.trace(mp.inertia)) / mp.mass))
    if off_axis > PHYSICAL_TOLERANCE * size:
        raise InputError(
            "Expected `pivot` on the symmetry axis (x, y of the centre of mass = "
            f"{format_values(mp.center_of_mass[:2])} m), got {format_values(p)} m, "
            f"{off_axis:.6g} m off the axis."
        )
    w = to_si(spin_rate, "angular_velocity", "spin_rate")
    if w == 0:
        raise InputError(
            "Expected `spin_rate` ≠ 0 rad/s (a top without spin is a spherical pendulum), got 0.0."
        )
    theta = to_si(tilt, "angle", "tilt")
    if not 0 <= theta <= math.pi:
        raise InputError(f"Expected `tilt` in [0, π] rad (0 = upright), got {theta!r}.")
    g = to_si(gravity, "acceleration", "gravity")
    if g < 0:
        raise InputError(f"Expected `gravity` >= 0 m/s² (its magnitude), got {g!r}.")
    m = mp.mass
    arm = float(offset[2])
    transverse = transverse_com + m * arm * arm
    spin_momentum = axial * w
    torque = m * g * arm  # m g l
    cos_t, sin_t = math.cos(theta), math.sin(theta)

    rates: tuple[float, float] | None = None
    small: tuple[float, float] | None = None
    a_coef = transverse * cos_t
    discriminant = spin_momentum * spin_momentum - 4.0 * a_coef * torque
    if discriminant >= 0:
        root = math.copysign(math.sqrt(discriminant), spin_momentum) + spin_momentum
        slow = 2.0 * torque / root
        fast = root / (2.0 * a_coef) if a_coef != 0 else math.copysign(math.inf, root)
        rates = (slow, fast)
        a = spin_momentum / transverse
        small = (
            math.hypot(a - 2.0 * slow * cos_t, slow * sin_t),
            math.hypot(a - 2.0 * fast * cos_t, fast * sin_t),
        )

    sign, drop, mc, rate, low = _released_top(
        spin_momentum / transverse, 2.0 * torque / transverse, theta
    )
    one_minus = 2.0 * math.sin(0.5 * _v_angle(theta, sign)) ** 2 + drop
    other = float(_tilt_from(sign, one_minus, low))
    period = 2.0 * float(special.ellipkm1(mc)) / rate if rate > 0 else math.inf
    return Gyroscope(
        mass=m,
        gravity=g,
        spin_rate=w,
        tilt=theta,
        axial_moment=axial,
        transverse_moment=transverse,
        lever_arm=arm,
        precession_rate=torque / spin_momentum,
        precession_rates=rates,
        nutation_frequency=abs(spin_momentum) / transverse,
        small_nutation_frequencies=small,
        nutation_amplitude=abs(torque) * transverse * sin_t / spin_momentum**2,
        nutation_limits=(min(theta, other), max(theta, other)),
        nutation_period=period,
        _sign=sign,
        _drop=drop,
        _mc=mc,
        _low=low,
        _rate=rate,
    )


def _released_top(a: float, beta: float, theta0: float) -> tuple[float, float, float, float, float]:
    """The cubic of a top released from rest, solved for the Jacobi form of u(t).

    In ``v = s cos θ`` with ``s = sign(β)`` (``β = 2 m g l / I⊥'``, ``a = I_s ω_s / I⊥'``)
    the motion is ``v̇² = (v0 − v)(B (1 − v²) − a² (v0 − v))``, ``B = |β|``, between
    ``v1 = v0 − Δ`` and ``v0``, the third root ``v3 ≥ 1``. Returns ``(s, Δ, 1 − m, p, 1 + v1)``
    with ``m = Δ/(v3 − v1)``, ``p = √(B (v3 − v1))/2 = ((a² − 2Bv0)² + 4B²(1 − v0²))^¼ / 2``;
    ``1 + v1`` is the smaller root x of ``B x² − (2B + a²) x + a² (1 + v0) = 0``.
    Each quantity is formed so that a fast top (``a² ≫ B``), a slow one that falls
    to the bottom (``1 + v1 → 0``), B = 0 and v0 = ±1 lose no digits to cancellation.
    """
    sign = -1.0 if beta < 0 else 1.0
    big_b = abs(beta)
    v_angle = _v_angle(theta0, sign)
    v0 = math.cos(v_angle)
    sin2 = math.sin(v_angle) ** 2  # 1 − v0²
    c = a * a - 2.0 * big_b * v0
    root = math.sqrt(c * c + 4.0 * big_b * big_b * sin2)  # B (v3 − v1)
    if root == 0:  # a² = 2B at v0 = 1: upright at the sleeping-top limit, a triple root
        return sign, 0.0, 0.0, 0.0, 2.0
    if c >= 0:
        drop = 2.0 * big_b * sin2 / (c + root)
        mc = (c + root) / (2.0 * root)  # (v3 − v0) / (v3 − v1)
    else:
        drop = (root - c) / (2.0 * big_b)
        mc = 2.0 * big_b * big_b * sin2 / (root * (root - c))
    one_plus = 2.0 * math.cos(0.5 * v_angle) ** 2  # 1 + v0
    b_sum = 2.0 * big_b + a * a
    low = (
        2.0 * a * a * one_plus / (b_sum + math.sqrt(b_sum * b_sum - 4.0 * big_b * a * a * one_plus))
    )
    return sign, drop, mc, 0.5 * math.sqrt(root), low
