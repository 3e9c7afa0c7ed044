"""The heavy symmetric (Lagrange) top on a fixed pivot: precession, nutation,
and its exact motion from any initial state."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.errors import InputError
from tumble.kinematics import as_attitude
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
from tumble.theory.motions import LagrangeTop, symmetric_top
from tumble.units import to_si, vector_to_si

__all__ = ["Gyroscope", "gyroscope"]

Array = NDArray[np.float64]

_UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True, eq=False)
class Gyroscope:
    """Heavy symmetric top on a fixed pivot (see :func:`gyroscope`). SI units, angles in rad.

    The exact values hold for the motion from the given initial state; the
    fast-top approximations are for a top released from rest at θ0.

    Attributes
    ----------
    axial_moment : I_s, moment about the symmetry axis, kg·m².
    transverse_moment : I⊥' = I⊥ + m l², transverse moment about the pivot, kg·m².
    lever_arm : l, signed distance from the pivot to the centre of mass along
        body +z, m (negative: the centre of mass is below a pivot at tilt < 90°).
    mass, gravity : as given (kg, m/s²).
    spin_rate : ω_s, the component of ω along body z (constant in the motion), rad/s.
    tilt : θ0, the angle of body +z from the upward vertical at t = 0, rad.
    tilt_rate : θ̇0, rad/s (on the vertical, where θ̇ has no sign: |ω⊥|).
    precession_rate0 : φ̇0, the rate of the axis's azimuth about the upward
        vertical at t = 0, rad/s (0 on the vertical).
    precession_rate : m g l / (I_s ω_s), rad/s: the fast-top steady precession rate.
    precession_rates : (slow, fast) exact steady-precession rates at the tilt θ0,
        rad/s, the roots of ``I⊥' cos θ Ω² − I_s ω_s Ω + m g l = 0`` (slow: the
        smaller in magnitude, → m g l / (I_s ω_s) for a fast top; fast:
        → I_s ω_s / (I⊥' cos θ)); None where the discriminant
        ``(I_s ω_s)² − 4 I⊥' m g l cos θ`` is negative (the spin is too slow for
        steady precession at this tilt).
    mean_precession_rate : the exact mean rate of the axis's azimuth about the
        upward vertical over whole nutation periods, rad/s (on a separatrix,
        the rate it tends to). A top released from rest precesses on average
        more slowly than the steady rate, by O((m g l)² I⊥' / (I_s ω_s)³).
    nutation_frequency : I_s ω_s / I⊥', rad/s: the fast-top nutation frequency.
    small_nutation_frequencies : (slow, fast) exact angular frequency of small
        nutation about each steady precession at θ0, rad/s,
        ``√((I_s ω_s / I⊥' − 2 Ω cos θ)² + Ω² sin² θ)``; None with
        ``precession_rates``.
    nutation_amplitude : m g l I⊥' sin θ0 / (I_s ω_s)², rad, in magnitude: the
        fast-top half-amplitude of the tilt's swing, (θ_max − θ_min)/2, of a top
        released from rest (its axis swings between θ0 and θ0 + 2 × this).
    nutation_limits : (θ_min, θ_max), rad: the exact turning points of the tilt
        in this motion (released from rest, one of them is θ0). For a top
        sleeping upright below the sleeping-top limit, those of the separatrix
        it would fall along.
    nutation_period : exact period of θ(t), s (``inf`` on a separatrix, e.g. an
        upright top spun below the sleeping-top limit, and without nutation).
    """

    mass: float
    gravity: float
    spin_rate: float
    tilt: float
    tilt_rate: float
    precession_rate0: float
    axial_moment: float
    transverse_moment: float
    lever_arm: float
    precession_rate: float
    precession_rates: tuple[float, float] | None
    mean_precession_rate: float
    nutation_frequency: float
    small_nutation_frequencies: tuple[float, float] | None
    nutation_amplitude: float
    nutation_limits: tuple[float, float]
    nutation_period: float
    _motion: Any = field(repr=False)

    def at(self, t: Any) -> tuple[Array, Array]:
        """The exact motion at times ``t`` (s, a scalar or a 1-D array): ω in body
        axes (rad/s; (3,) or (n, 3)) and the attitude quaternion body → space
        (space z up; (4,) or (n, 4)), O(1) work a sample
        (:func:`tumble.theory.motions.lagrange_top`; without a torque about
        the pivot, the torque-free solution)."""
        times, shape = as_times(t)
        omega, quaternion = self._motion(times)
        return omega.reshape((*shape, 3)), quaternion.reshape((*shape, 4))

    def tilt_at(self, t: Any) -> Array:
        """Exact tilt θ(t) of body +z from the upward vertical, rad, in [0, π]:
        a float array of the shape of ``t`` (s, a scalar or a 1-D array).

        With ``u = cos θ``, energy and the two conserved angular momenta give
        ``u̇² = f(u)``, a cubic whose roots ``u1 ≤ u2 ≤ 1 ≤ u3`` bound the
        motion: ``u(t) = u1 + (u2 − u1) sn²(p t + τ0 | m)``, with
        ``m = (u2 − u1)/(u3 − u1)`` and ``p = √(β (u3 − u1)) / 2``,
        β = 2 m g l / I⊥' (Goldstein, Classical Mechanics, §5.7; Whittaker,
        Analytical Dynamics, §71).
        """
        times, shape = as_times(t)
        q = self._motion(times)[1]
        # Body z in space: cos θ = w² + z² − x² − y², so θ = 2 atan2(√(x² + y²), √(w² + z²)).
        tilt = 2.0 * np.arctan2(np.hypot(q[:, 1], q[:, 2]), np.hypot(q[:, 0], q[:, 3]))
        return np.asarray(tilt.reshape(shape))


def gyroscope(
    mp: MassProperties,
    pivot: Any,
    spin_rate: Any = None,
    tilt: Any = None,
    gravity: Any = 9.81,
    *,
    tilt_rate: Any = 0.0,
    precession_rate0: Any = 0.0,
    omega0: Any = None,
    attitude0: Any = None,
) -> Gyroscope:
    """Precession and nutation of a heavy symmetric top on a fixed pivot (the Lagrange top).

    The body is symmetric about body z (inertia about the centre of mass
    ``diag(I⊥, I⊥, I_s)``) and turns about a pivot on that axis, held fixed,
    under gravity g acting at the centre of mass, a distance l along +z from the
    pivot; space z is up. With z-x-z Euler angles (precession φ about the upward
    vertical, tilt θ of the body z axis from it, spin ψ) the Lagrangian is
    ``½ I⊥' (θ̇² + φ̇² sin² θ) + ½ I_s (ψ̇ + φ̇ cos θ)² − m g l cos θ`` with
    ``I⊥' = I⊥ + m l²`` about the pivot. Two momenta are conserved, ``I_s ω_s``
    with ``ω_s = ψ̇ + φ̇ cos θ`` and ``p_φ``, and so is the energy (Goldstein,
    Classical Mechanics, §5.7; Landau & Lifshitz, Mechanics, §35, problem 1).

    The initial state is either ``spin_rate``, ``tilt`` and optionally
    ``tilt_rate`` and ``precession_rate0`` (the attitude Rz(0) Rx(θ0) Rz(0),
    so ω0 = (θ̇0, φ̇0 sin θ0, ω_s) in body axes), or ``omega0`` and
    ``attitude0`` themselves. ``spin_rate`` is ``ω_s``, the **total** angular
    velocity component along the symmetry axis (constant in the motion), not the
    spin ψ̇ relative to the precessing frame; the two differ by ``φ̇ cos θ``.

    * The exact motion (:meth:`Gyroscope.at`, :meth:`Gyroscope.tilt_at`): θ from
      Jacobi's sn, φ and ψ from elliptic integrals of the third kind (Carlson's
      R_J and R_C), O(1) work a sample at any time; its turning points, period
      and mean precession rate.
    * Steady precession at tilt θ (θ̇ = 0, φ̇ = Ω constant) needs
      ``I⊥' cos θ Ω² − I_s ω_s Ω + m g l = 0``; for a fast top the slow root is
      ``Ω ≈ m g l / (I_s ω_s)``.
    * Small nutation about a steady precession has the frequency
      ``√((I_s ω_s / I⊥' − 2 Ω cos θ)² + Ω² sin² θ)``, ≈ ``I_s ω_s / I⊥'`` for a fast top.
    * Released from rest (θ̇ = φ̇ = 0) at θ0, a fast top's tilt swings by
      ``θ1 − θ0 ≈ 2 m g l I⊥' sin θ0 / (I_s ω_s)²`` and nutates at ≈ I_s ω_s / I⊥'.

    Parameters
    ----------
    mp : the top, symmetric about body z.
    pivot : (3,) body coordinates of the pivot, m, on the symmetry axis (the line
        through the centre of mass along z).
    spin_rate : ω_s, rad/s (signed, about body +z; ≠ 0), e.g. ``"3000 rpm"``.
    tilt : θ0, angle of body +z from the upward vertical, rad or ``"30 deg"``, in [0, π].
    gravity : g, magnitude of the acceleration of gravity, m/s² (≥ 0), along −z.
    tilt_rate : θ̇0, rad/s.
    precession_rate0 : φ̇0, rad/s, about the upward vertical.
    omega0, attitude0 : instead of the four above: ω0 (3,) in body axes, rad/s
        (its z component ≠ 0), and the attitude body → space (a quaternion
        ``[w, x, y, z]`` or a scipy Rotation).

    Returns
    -------
    Gyroscope: the exact motion, and the fast-top approximations beside the
    exact values. Precession rates are positive counter-clockwise about the
    upward vertical.

    Raises
    ------
    InputError
        If the body is not symmetric about body z, has no moment about it, the
        pivot is off the axis, the spin rate is zero, the tilt is outside [0, π],
        gravity is negative, or the initial state is given both ways or neither.

    Examples
    --------
    A 0.5 kg disk of radius 3 cm on a pivot 5 cm below its centre, spun at
    3000 rpm and released from rest at 30° from the vertical: the fast-top
    precession rate ``m g l / (I_s ω_s)`` beside the exact values.

    >>> import numpy as np
    >>> import tumble as tb
    >>> disk = tb.shapes.solid_cylinder(0.5, 0.03, 0.01)
    >>> top = tb.theory.gyroscope(disk, pivot=[0, 0, -0.05], spin_rate="3000 rpm", tilt="30 deg")
    >>> print(f"fast top {top.precession_rate:.4f}, steady {top.precession_rates[0]:.4f}, "
    ...       f"mean from rest {top.mean_precession_rate:.4f} rad/s")
    fast top 3.4696, steady 3.6986, mean from rest 3.6858 rad/s
    >>> print(f"nutation period {top.nutation_period:.6f} s")
    nutation period 0.137874 s

    The tilt swings between 30° and its other turning point:

    >>> tilt = top.tilt_at([0.0, top.nutation_period / 2, top.nutation_period])
    >>> print(np.degrees(tilt).round(4))
    [30.     34.6481 30.    ]
    """
    mp = as_mass_properties(mp)
    axial, transverse_com = axisymmetric_moments(mp)
    arm = _lever_arm(mp, pivot)
    omega, q0 = _initial_state(spin_rate, tilt, tilt_rate, precession_rate0, omega0, attitude0)
    w = float(omega[2])
    if w == 0:
        raise InputError(
            "Expected `spin_rate` ≠ 0 rad/s (a top without spin is a spherical pendulum), got 0.0."
        )
    g = to_si(gravity, "acceleration", "gravity")
    if g < 0:
        raise InputError(f"Expected `gravity` >= 0 m/s² (its magnitude), got {g!r}.")
    start = _from_the_vertical(omega, q0)

    m = mp.mass
    transverse = transverse_com + m * arm * arm
    # The steady precession I⊥' cos θ Ω² − I_s ω_s Ω + m g l = 0 divided by I⊥':
    # cos θ Ω² − a Ω + b = 0 in rates, free of the mass's scale (a top of 1e308 kg
    # or 1e-300 kg).
    a = axial / transverse * w  # I_s ω_s / I⊥'
    b = m / transverse * arm * g  # m g l / I⊥'
    rates, small = _steady_precession(a, b, start.cos_tilt, start.sin_tilt)
    if b != 0.0:
        motion, limits, period, mean_rate = _heavy(
            transverse, axial, m * arm, g, omega, q0, start.tilt, start.turning
        )
    else:
        motion, limits, period, mean_rate = _free(transverse, axial, omega, q0, start.tilt)
    return Gyroscope(
        mass=m,
        gravity=g,
        spin_rate=w,
        tilt=start.tilt,
        tilt_rate=start.tilt_rate,
        precession_rate0=start.precession_rate,
        axial_moment=axial,
        transverse_moment=transverse,
        lever_arm=arm,
        precession_rate=b / a,
        precession_rates=rates,
        mean_precession_rate=mean_rate,
        nutation_frequency=abs(a),
        small_nutation_frequencies=small,
        nutation_amplitude=abs(b / a) * start.sin_tilt / abs(a),
        nutation_limits=limits,
        nutation_period=period,
        _motion=motion,
    )


def _lever_arm(mp: MassProperties, pivot: Any) -> float:
    """l, the signed distance from the pivot to the centre of mass along body +z, m.

    Raises
    ------
    InputError
        A pivot off the symmetry axis (the line through the centre of mass along z).
    """
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
    return float(offset[2])


@dataclass(frozen=True)
class _Start:
    """The initial state seen from the upward vertical: ``tilt`` θ0 of body +z
    from it (rad, in [0, π]) with its cosine and sine (from the vertical's body
    coordinates, not from θ0), ``tilt_rate`` θ̇0 (rad/s; |ω⊥| on the vertical),
    ``precession_rate`` φ̇0 about it (rad/s; 0 on the vertical), and whether
    θ̇0 = 0 (``turning``: released at a turning point of the tilt)."""

    tilt: float
    cos_tilt: float
    sin_tilt: float
    tilt_rate: float
    precession_rate: float
    turning: bool


def _from_the_vertical(omega: Array, q0: Array) -> _Start:
    """θ0, θ̇0 and φ̇0 of ω0 (body axes, rad/s) at the attitude ``q0`` (body → space)."""
    k = Rotation.from_quat(q0, scalar_first=True).inv().apply(_UP)  # the vertical, body axes
    sin_t = math.hypot(float(k[0]), float(k[1]))
    along = float(omega[0] * k[0] + omega[1] * k[1])  # φ̇ sin² θ
    across = float(k[0] * omega[1] - k[1] * omega[0])  # u̇ = −θ̇ sin θ
    return _Start(
        tilt=math.atan2(sin_t, float(k[2])),
        cos_tilt=float(k[2]),
        sin_tilt=sin_t,
        tilt_rate=-across / sin_t if sin_t > 0 else math.hypot(omega[0], omega[1]),
        precession_rate=along / sin_t**2 if sin_t > 0 else 0.0,
        turning=across == 0.0,
    )


def _steady_precession(
    a: float, b: float, cos_t: float, sin_t: float
) -> tuple[tuple[float, float] | None, tuple[float, float] | None]:
    """The (slow, fast) steady precession rates at the tilt θ of cosine ``cos_t``
    and sine ``sin_t``, the roots of ``cos θ Ω² − a Ω + b = 0`` with
    a = I_s ω_s / I⊥' (rad/s) and b = m g l / I⊥' (rad²/s²), and the frequencies
    of small nutation about each, ``√((a − 2 Ω cos θ)² + Ω² sin² θ)``, rad/s;
    None, None where the spin is too slow for steady precession (a negative
    discriminant)."""
    discriminant = a * a - 4.0 * cos_t * b
    if not discriminant >= 0:
        return None, None
    root = math.copysign(math.sqrt(discriminant), a) + a
    slow = 2.0 * b / root
    fast = root / (2.0 * cos_t) if cos_t != 0 else math.copysign(math.inf, root)
    small = (
        math.hypot(a - 2.0 * slow * cos_t, slow * sin_t),
        math.hypot(a - 2.0 * fast * cos_t, fast * sin_t),
    )
    return (slow, fast), small


def _initial_state(
    spin_rate: Any, tilt: Any, tilt_rate: Any, precession_rate0: Any, omega0: Any, attitude0: Any
) -> tuple[Array, Array]:
    """ω0 (body axes, rad/s) and the attitude quaternion at t = 0, from either form."""
    if omega0 is not None or attitude0 is not None:
        if spin_rate is not None or tilt is not None or omega0 is None or attitude0 is None:
            given = {
                "spin_rate": spin_rate,
                "tilt": tilt,
                "omega0": omega0,
                "attitude0": attitude0,
            }
            raise InputError(
                "Expected the initial state as `spin_rate` and `tilt` (with `tilt_rate`, "
                "`precession_rate0`) or as `omega0` and `attitude0`, got "
                + ", ".join(f"`{name}`" for name, value in given.items() if value is not None)
                + "."
            )
        return vector_to_si(omega0, "angular_velocity", "omega0", (3,)), as_attitude(attitude0)
    if spin_rate is None or tilt is None:
        raise InputError(
            "Expected the initial state as `spin_rate` and `tilt` or as `omega0` and "
            f"`attitude0`, got spin_rate={spin_rate!r}, tilt={tilt!r}."
        )
    w = to_si(spin_rate, "angular_velocity", "spin_rate")
    theta = to_si(tilt, "angle", "tilt")
    if not 0 <= theta <= math.pi:
        raise InputError(f"Expected `tilt` in [0, π] rad (0 = upright), got {theta!r}.")
    theta_dot = to_si(tilt_rate, "angular_velocity", "tilt_rate")
    phi_dot = to_si(precession_rate0, "angular_velocity", "precession_rate0")
    omega = np.array([theta_dot, phi_dot * math.sin(theta), w])
    return omega, np.array([math.cos(0.5 * theta), math.sin(0.5 * theta), 0.0, 0.0])


def _heavy(
    transverse: float,
    axial: float,
    mass_lever: float,
    g: float,
    omega: Array,
    q0: Array,
    theta: float,
    turning: bool,
) -> tuple[Any, tuple[float, float], float, float]:
    """The exact motion under gravity (:func:`tumble.theory.motions.symmetric_top`),
    the tilt's turning points, the nutation period and the mean precession rate.
    The top's own frame has its axis from the pivot towards the centre of mass:
    body −z when the centre of mass is below the pivot along z."""
    from tumble.core.lagrange import top_turning_points

    flip = mass_lever < 0.0
    frame = np.diag([1.0, -1.0, -1.0]) if flip else np.eye(3)
    top: LagrangeTop = symmetric_top(
        frame, transverse, axial, abs(mass_lever), np.array([0.0, 0.0, -g]), omega, q0
    )
    period, mean_rate, _ = top.mean_rates()
    if top.constants is None:  # sleeping on the vertical
        a = axial / transverse * float(omega[2])
        beta = 2.0 * (abs(mass_lever) / transverse) * g
        upright = (theta == 0.0) != flip  # the centre of mass above the pivot
        if upright and a * a < 2.0 * beta:  # unstable: the separatrix's reach
            reach = 2.0 * math.acos(math.sqrt(a * a / (2.0 * beta)))
            low, high = 0.0, reach
        else:  # stable: upright and fast enough, or hanging
            low = high = 0.0 if upright else math.pi
        if flip:
            low, high = math.pi - high, math.pi - low
    else:
        low, high = (float(limit) for limit in top_turning_points(top.constants))
        if flip:
            low, high = math.pi - high, math.pi - low
        if turning:  # released at a turning point: that limit is θ0 itself
            if abs(low - theta) <= abs(high - theta):
                low = theta
            else:
                high = theta
    return top.at, (low, high), period, mean_rate


def _free(
    transverse: float, axial: float, omega: Array, q0: Array, theta: float
) -> tuple[Any, tuple[float, float], float, float]:
    """No torque about the pivot: the free symmetric top (Landau & Lifshitz §33).
    Its axis turns about the fixed L at |L| / I⊥' on a cone of half-angle θ_L,
    so its tilt from the vertical, at γ from L, swings between |γ − θ_L| and
    γ + θ_L (folded into [0, π]), and its azimuth about the vertical advances
    on average only when the cone encloses the vertical."""
    from tumble.theory.motions import exact_principal

    moments = np.array([transverse, transverse, axial])
    order = np.argsort(moments, kind="stable")
    axes = np.eye(3)[:, order]
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]

    def motion(times: Array) -> tuple[Array, Array]:
        w, q = exact_principal(
            moments[order],
            axes.T @ omega,
            (Rotation.from_quat(q0, scalar_first=True) * Rotation.from_matrix(axes)).as_quat(
                scalar_first=True
            ),
            times,
        )
        attitude = Rotation.from_quat(q, scalar_first=True) * Rotation.from_matrix(axes).inv()
        return w @ axes.T, attitude.as_quat(scalar_first=True)

    momentum = Rotation.from_quat(q0, scalar_first=True).apply(moments * omega)  # space axes
    size = float(np.linalg.norm(momentum))
    axis = Rotation.from_quat(q0, scalar_first=True).apply([0.0, 0.0, 1.0])
    if size == 0.0:
        return motion, (theta, theta), math.inf, 0.0
    cone = _angle(axis, momentum)
    gamma = _angle(_UP, momentum)
    low, high = abs(gamma - cone), gamma + cone
    if high > math.pi:
        high = 2.0 * math.pi - high
    rate = size / transverse
    turns = cone > 0.0 and 0.0 < gamma < math.pi
    mean_rate = math.copysign(rate, momentum[2]) if cone > min(gamma, math.pi - gamma) else 0.0
    period = 2 * math.pi / rate if turns else math.inf
    return motion, (min(low, high), max(low, high)), period, mean_rate


def _angle(a: Array, b: Array) -> float:
    """The angle between two vectors, rad, accurate near 0 and π."""
    return math.atan2(float(np.linalg.norm(np.cross(a, b))), float(a @ b))
