"""The gyrocompass: a spinning disk in a gimbal on a turning platform,
:func:`gyrocompass` and what it returns, :class:`GyrocompassRun`.

The gimbal angle θ and its rate are integrated by the compiled kernel of
:mod:`tumble.core.gimbal`; the disk's attitude and body rates follow from θ,
the spin angle and the platform's turn in closed form. The closed form of the
small and large swings is :func:`tumble.theory.gyrocompass`; the check that
compares the two is :class:`tumble.checks.gyrocompass.GyrocompassCheck`, and a
scenario's ``[gyrocompass]`` table runs this model
(:mod:`tumble.scenario.model_kinds.gyrocompass`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.core import gimbal
from tumble.errors import InputError
from tumble.integrators.limits import check_record_every
from tumble.integrators.problem import Schedule
from tumble.integrators.steps import step_in_chunks
from tumble.kinematics import same_hemisphere
from tumble.massprops import MassProperties, as_mass_properties, axisymmetric_moments, readonly
from tumble.trajectory import Trajectory
from tumble.units import to_si

__all__ = ["EARTH_ROTATION_RATE", "GyrocompassRun", "gyrocompass"]

Array = NDArray[np.float64]

#: The Earth's mean angular velocity relative to the stars, rad/s (IERS
#: Conventions 2010, Table 1.1): one turn per sidereal day of 86164.1 s.
EARTH_ROTATION_RATE = 7.292115e-5

#: Platform axes (columns: the gimbal axis AB, then the third axis, then the
#: direction θ is measured from) in the space axes of the Earth case, which
#: are east, north, up at t = 0: AB points down, θ = 0 is north, so θ turns
#: the spin axis from north toward east (a heading, clockwise seen from above).
_EARTH_MOUNT = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])


@dataclass(frozen=True, eq=False)
class GyrocompassRun:
    """A simulated gyrocompass (see :func:`gyrocompass`). SI units.

    Attributes
    ----------
    trajectory : the disk's motion about its centre: ω in the disk's body
        axes, the attitude body → space (platform × gimbal × spin), the disk
        as ``mass_properties``, ``pivot`` its centre of mass, no gravity.
        Its ``energy`` and ``angular_momentum`` are the disk's in the
        (non-rotating) space frame; the energy is **not** conserved: the
        platform, held at a constant rate, does work on the disk.
    angle : (n,) θ, the angle of the spin axis (body +z) from the direction
        of ``effective_platform_rate``, about the gimbal axis AB, rad; in the
        Earth case the heading of the spin axis, east of north.
    angle_rate : (n,) θ̇, rad/s, relative to the platform.
    jacobi_integral : (n,) the energy in the platform's frame,
        ``J = T − Ω_P · L`` with T, L the disk's kinetic energy and angular
        momentum in space and Ω_P the platform's angular velocity:
        ``J = ½ I_AB (θ̇² − Ω_AB²) − ½ I_AB Ω² sin² θ − I_s ω_s Ω cos θ + ½ I_s ω_s²``,
        J. It is conserved without damping; damping dissipates it at
        ``dJ/dt = −c θ̇²``.
    spin_rate : ω_s, the disk's angular velocity about its axis (body z),
        rad/s, constant.
    platform_angular_velocity : (3,) Ω_P in space coordinates, rad/s, constant.
    effective_platform_rate : Ω, the component of Ω_P perpendicular to AB,
        along the direction θ is measured from, rad/s (Ω_E cos λ on the Earth).
    gimbal_axis, reference_direction : (3,) unit vectors, in space
        coordinates at t = 0, of AB and of the direction θ = 0; both turn
        with the platform.
    axial_moment : I_s, kg·m²; ``gimbal_moment``: I_AB, kg·m²; ``damping``:
        c, N·m·s; ``latitude``: λ, rad, or None.
    """

    trajectory: Trajectory
    angle: Array
    angle_rate: Array
    jacobi_integral: Array
    spin_rate: float
    platform_angular_velocity: Array
    effective_platform_rate: float
    gimbal_axis: Array
    reference_direction: Array
    axial_moment: float
    gimbal_moment: float
    damping: float
    latitude: float | None

    def __repr__(self) -> str:
        where = (
            "platform about the vertical"
            if self.latitude is None
            else f"on the Earth at latitude {math.degrees(self.latitude):.6g}°"
        )
        jacobi = self.jacobi_integral
        return (
            f"GyrocompassRun({len(self.angle)} samples over {self.trajectory.t[-1]:.6g} s, "
            f"{where}; ω_s = {self.spin_rate:.6g} rad/s, Ω = {self.effective_platform_rate:.6g} "
            f"rad/s, c = {self.damping:.3g} N·m·s; θ from {self.angle[0]:.6g} to "
            f"{self.angle[-1]:.6g} rad; Jacobi integral changed by {jacobi[-1] - jacobi[0]:.3g} J)"
        )

    def angular_acceleration(self, angle: Any, angle_rate: Any = 0.0) -> Array:
        """θ̈ of the model at angle θ (rad) and rate θ̇ (rad/s):
        ``(−I_s ω_s Ω sin θ + I_AB Ω² sin θ cos θ − c θ̇) / I_AB``, rad/s².

        ``angle`` and ``angle_rate`` are numbers or arrays (broadcast together).
        """
        theta, rate = np.broadcast_arrays(
            np.asarray(angle, dtype=float), np.asarray(angle_rate, dtype=float)
        )
        params = _params(
            self.axial_moment,
            self.gimbal_moment,
            self.spin_rate,
            self.effective_platform_rate,
            self.damping,
        )
        result = np.empty(theta.shape)
        y, dy = np.zeros(3), np.zeros(3)
        for index in np.ndindex(theta.shape):
            y[0], y[1] = theta[index], rate[index]
            gimbal.derivatives(y, params, dy)
            result[index] = dy[1]
        return result


def _params(axial: float, transverse: float, spin: float, rate: float, damping: float) -> Array:
    params = np.zeros(gimbal.N_PARAMS)
    params[0] = axial * spin / transverse
    params[1] = rate
    params[2] = damping / transverse
    return params


def gyrocompass(
    mp: MassProperties,
    spin_rate: Any,
    platform_rate: Any,
    angle0: Any,
    *,
    angle_rate0: Any = 0.0,
    duration: Any,
    dt: Any = None,
    latitude: Any = None,
    damping: Any = 0.0,
    record_every: int = 1,
    samples: int | None = None,
    progress: Callable[[int, int], object] | None = None,
) -> GyrocompassRun:
    """Simulate a spinning disk in a gimbal on a turning platform (a gyrocompass).

    The disk, symmetric about its body z, spins about z in frictionless
    bearings and is pivoted at its centre of mass in a massless gimbal free
    to turn about an axis AB perpendicular to the spin axis; AB is fixed to a
    platform turning at a constant angular velocity Ω_P. θ is the angle of the
    spin axis from Ω, the component of Ω_P perpendicular to AB, turned about
    AB. In the gimbal's axes (AB, its normal, the spin axis) the disk turns at
    ``(θ̇ + Ω_AB, Ω sin θ, Ω cos θ + ψ̇)``, so the Lagrangian
    ``½ I_AB ((θ̇ + Ω_AB)² + Ω² sin² θ) + ½ I_s (ψ̇ + Ω cos θ)²`` leaves the
    spin ``ω_s = ψ̇ + Ω cos θ`` constant and gives, with a viscous torque
    ``−c θ̇`` in the gimbal's bearings,

        ``I_AB θ̈ = −I_s ω_s Ω sin θ + I_AB Ω² sin θ cos θ − c θ̇``,

    the equation of :func:`tumble.theory.gyrocompass` with damping (Ω_AB,
    constant, drops out). The spin's angular momentum swings about Ω like a
    pendulum when ``I_s ω_s Ω > I_AB Ω²`` and, damped, settles along it: at
    θ = 0 if ω_s Ω > 0, at θ = π otherwise (the signs of the rates matter here).

    Two geometries:

    * ``latitude=None`` — the lecture notes' apparatus: the platform turns
      at ``platform_rate`` about the vertical, AB is horizontal. Space axes:
      those of the platform at t = 0; z up (Ω_P = Ω ẑ), AB along x; θ is the
      tilt of the spin axis from the vertical, toward −y.
    * ``latitude=λ`` — a gyrocompass on the Earth: the spin axis is held in
      the local horizontal plane and the gimbal turns about the local
      vertical. The Earth turns at ``platform_rate`` (e.g.
      :data:`EARTH_ROTATION_RATE`) about its axis, which at latitude λ points
      ``cos λ`` north and ``sin λ`` up: Ω_P = Ω_E (0, cos λ, sin λ) in local
      (east, north, up) axes. Its vertical part lies along AB and drops out;
      the rest, Ω = Ω_E cos λ, points north: the spin axis seeks north, with
      ``β = √(I_s ω_s Ω_E cos λ / I_AB)`` (no directive torque at the poles).
      θ is the heading of the spin axis, east of north. Space axes: parallel
      to east, north, up at t = 0, not rotating (the disk's centre moves with
      the ground, which exerts no torque about it).

    The disk's body axes at t = 0 (θ = ψ = 0): x along AB, z along the
    direction θ = 0 — (x, y, z) = (x, y, z) of space without latitude, and
    (down, west, north) on the Earth.

    Parameters
    ----------
    mp : the disk (any body symmetric about body z; its centre of mass is the pivot).
    spin_rate : ω_s, the disk's angular velocity component along its axis
        (body +z), rad/s, signed, e.g. ``"20000 rpm"``; constant in the motion.
    platform_rate : the platform's rate about the vertical (``latitude=None``)
        or the Earth's rate about its axis, rad/s, signed.
    angle0 : θ at t = 0, rad or ``"30 deg"``.
    angle_rate0 : θ̇ at t = 0, relative to the platform, rad/s.
    duration : simulated time, s, > 0.
    dt : integration step, s, > 0; default 1/200 of a turn at the fastest
        rate of θ (``c / I_AB + √(θ̇0² + 4 |I_s ω_s Ω| / I_AB + Ω²)``),
        shortened so that whole steps span ``duration``. The spin does not
        limit it: ``ψ = ω_s t − ∫ Ω cos θ dt`` is exact in ω_s t. To animate
        the spin, sample it finer than a turn (``dt`` below ``π / |ω_s|``).
    latitude : λ, rad or ``"52 deg"``, in [−90°, 90°], positive north; None
        for a platform turning about the vertical.
    damping : c, the viscous torque coefficient of the gimbal's bearings about
        AB, N·m·s, >= 0: the torque is ``−c θ̇``.
    record_every : keep every k-th step (the final state is always kept).
    samples : instead of ``record_every``: about how many samples to keep,
        evenly spaced in steps (with the default ``dt``, the step is known only
        here).
    progress : None or a callable ``progress(done, total)`` in steps.

    Returns
    -------
    GyrocompassRun — θ(t), θ̇(t), the conserved ``jacobi_integral`` and the
    disk's :class:`~tumble.Trajectory` (method ``"rk4"``).

    Raises
    ------
    InputError
        If the disk is not symmetric about body z or has no moment about it,
        the latitude is outside [−90°, 90°], the damping is negative, the
        duration or dt is not positive, ``record_every`` or ``samples`` is not
        an integer >= 1, or both are given.
    RequestTooLargeError
        Before any work, when the recorded samples would not fit in the memory
        budget (:func:`tumble.simulation.check_recording`).
    IntegrationError
        If the integration produced NaN or infinity (``dt`` far too large).

    Warns
    -----
    CoarseStepWarning
        When ``dt`` gives fewer than 20 steps per turn at the fastest rate of θ.

    References: Kleppner & Kolenkow, An Introduction to Mechanics, ch. 7
    (the gyrocompass); Goldstein, Classical Mechanics, §2.7 (the Jacobi
    integral ``h = Σ q̇ ∂L/∂q̇ − L``, which here is ``T − Ω_P · L``).

    Examples
    --------
    A disk spun at 3000 rpm on a platform turning at 1 rad/s, its axis
    released 10° from the vertical: it swings with the exact period of
    :func:`tumble.theory.gyrocompass`, and the Jacobi integral stays.

    >>> import numpy as np
    >>> import tumble as tb
    >>> disk = tb.shapes.solid_cylinder(0.5, 0.03, 0.01)
    >>> run = tb.models.gyrocompass(disk, "3000 rpm", 1.0, "10 deg", duration=1.0)
    >>> rate = tb.analysis.oscillation_frequency(run.trajectory.t, run.angle)
    >>> theory = tb.theory.gyrocompass(disk, "3000 rpm", 1.0)
    >>> print(f"{rate:.4f} rad/s, theory {2 * np.pi / theory.period('10 deg'):.4f}")
    24.5477 rad/s, theory 24.5477
    >>> J = run.jacobi_integral
    >>> bool(np.ptp(J) < 1e-9 * abs(J[0]))
    True
    """
    mp = as_mass_properties(mp)
    axial, transverse = axisymmetric_moments(mp)
    spin = to_si(spin_rate, "angular_velocity", "spin_rate")
    rate = to_si(platform_rate, "angular_velocity", "platform_rate")
    theta0 = to_si(angle0, "angle", "angle0")
    theta_rate0 = to_si(angle_rate0, "angular_velocity", "angle_rate0")
    total_time = to_si(duration, "time", "duration")
    if total_time <= 0:
        raise InputError(f"Expected `duration` > 0 s, got {total_time!r}.")
    c = to_si(damping, "damping", "damping")
    if c < 0:
        raise InputError(f"Expected `damping` >= 0 N·m·s, got {c!r}.")
    record_every = check_record_every(record_every)
    platform = _platform(rate, latitude)
    big_omega = platform.rate
    params = _params(axial, transverse, spin, big_omega, c)
    # The fastest rate of θ, c / I_AB + √(θ̇0² + 4 |I_s ω_s Ω| / I_AB + Ω²), rad/s.
    fastest = params[2] + math.sqrt(
        theta_rate0 * theta_rate0 + 4.0 * abs(params[0] * big_omega) + big_omega * big_omega
    )
    schedule = Schedule.sampled(
        total_time, dt, fastest, "the fastest rate of the gimbal angle", record_every, samples, 3
    )
    out = _integrate(np.array([theta0, theta_rate0, 0.0]), params, schedule, progress)

    times, theta, theta_rate = schedule.times, out[:, 0], out[:, 1]
    # ψ = ω_s t − χ, the fast part reduced first so the angle keeps its digits.
    psi = np.remainder(spin * times, 2 * math.pi) - out[:, 2]
    jacobi = _jacobi_integral(platform, axial, transverse, spin, theta, theta_rate)
    trajectory = Trajectory(
        t=times,
        omega=_body_rates(platform, spin, theta, theta_rate, psi),
        quaternion=_attitude(platform, times, theta, psi),
        mass_properties=mp,
        pivot=np.array(mp.center_of_mass, dtype=float),
        method="rk4",
        reason="gyrocompass model",
        dt=schedule.step,
        steps=schedule.n_steps,
        # The platform does work on the disk: of what a free disk conserves, only
        # the Jacobi integral survives, and only without damping.
        conserved=(),
        invariant_values={} if c else {"jacobi_integral": readonly(jacobi)},
    )
    return GyrocompassRun(
        trajectory=trajectory,
        angle=readonly(theta),
        angle_rate=readonly(theta_rate),
        jacobi_integral=readonly(jacobi),
        spin_rate=spin,
        platform_angular_velocity=readonly(platform.angular_velocity_space),
        effective_platform_rate=platform.rate,
        gimbal_axis=readonly(platform.mount[:, 0]),
        reference_direction=readonly(platform.mount[:, 2]),
        axial_moment=axial,
        gimbal_moment=transverse,
        damping=c,
        latitude=platform.latitude,
    )


@dataclass(frozen=True)
class _Platform:
    """The platform carrying the gimbal: ``mount``, its axes (columns: the gimbal
    axis AB, the third axis, the direction θ = 0) in space axes; ``angular_velocity``
    Ω_P (3,) in those platform axes, rad/s, constant; ``latitude`` λ, rad, or None."""

    mount: Array
    angular_velocity: Array
    latitude: float | None

    @property
    def along_gimbal_axis(self) -> float:
        """Ω_AB, the component of Ω_P along AB, rad/s (it drops out of θ's equation)."""
        return float(self.angular_velocity[0])

    @property
    def rate(self) -> float:
        """Ω, the component of Ω_P along the direction θ = 0, rad/s."""
        return float(self.angular_velocity[2])

    @property
    def angular_velocity_space(self) -> Array:
        """Ω_P (3,) in space axes, rad/s."""
        return np.asarray(self.mount @ self.angular_velocity)


def _platform(rate: float, latitude: Any) -> _Platform:
    """The platform turning at ``rate`` (rad/s) about the vertical (``latitude`` None),
    or the Earth turning at ``rate`` about its axis, seen at ``latitude``.

    Raises
    ------
    InputError
        A latitude outside [−90°, 90°].
    """
    if latitude is None:
        # In platform axes (AB, ·, θ = 0), which are the space axes.
        return _Platform(np.eye(3), np.array([0.0, 0.0, rate]), None)
    lam = to_si(latitude, "angle", "latitude")
    if not -0.5 * math.pi <= lam <= 0.5 * math.pi:
        raise InputError(
            f"Expected `latitude` in [-π/2, π/2] rad (−90° to 90°, positive north), got {lam!r}."
        )
    # Ω_P = Ω_E (0, cos λ, sin λ) in (east, north, up); AB points down.
    up_north = np.array([0.0, rate * math.cos(lam), rate * math.sin(lam)])
    return _Platform(_EARTH_MOUNT, _EARTH_MOUNT.T @ up_north, lam)


def _integrate(
    y: Array, params: Array, schedule: Schedule, progress: Callable[[int, int], object] | None
) -> Array:
    """(n, 3) θ (rad), θ̇ (rad/s) and χ = ∫ Ω cos θ dt (rad) at the schedule's
    times, by the kernel's RK4 from ``y`` = (θ0, θ̇0, 0), which it overwrites."""
    n_steps, step, record_every = schedule.n_steps, schedule.step, schedule.record_every
    out = np.empty((len(schedule.times), 3))
    out[0] = y
    step_in_chunks(
        lambda done, count: gimbal.rk4_run(y, params, step, count, done, record_every, out),
        n_steps,
        step,
        progress,
    )
    if n_steps % record_every != 0:
        out[-1] = y
    return out


def _attitude(platform: _Platform, times: Array, theta: Array, psi: Array) -> Array:
    """(n, 4) the disk's attitude ``[w, x, y, z]``, body → space: the platform's
    turn, its mount, θ about AB (body x), ψ about the spin axis (body z)."""
    attitude = (
        Rotation.from_rotvec(np.outer(times, platform.angular_velocity_space))
        * Rotation.from_matrix(platform.mount)
        * Rotation.from_rotvec(np.outer(theta, [1.0, 0.0, 0.0]))
        * Rotation.from_rotvec(np.outer(psi, [0.0, 0.0, 1.0]))
    )
    return same_hemisphere(np.asarray(attitude.as_quat(scalar_first=True)))


def _body_rates(
    platform: _Platform, spin: float, theta: Array, theta_rate: Array, psi: Array
) -> Array:
    """(n, 3) the disk's ω in its body axes, rad/s: in the gimbal's axes it turns
    at (θ̇ + Ω_AB, Ω sin θ, ω_s); the body axes follow by the spin angle ψ about z."""
    gx = theta_rate + platform.along_gimbal_axis
    gy = platform.rate * np.sin(theta)
    cos_psi, sin_psi = np.cos(psi), np.sin(psi)
    return np.column_stack(
        (cos_psi * gx + sin_psi * gy, cos_psi * gy - sin_psi * gx, np.full(theta.size, spin))
    )


def _jacobi_integral(
    platform: _Platform,
    axial: float,
    transverse: float,
    spin: float,
    theta: Array,
    theta_rate: Array,
) -> Array:
    """(n,) the energy in the platform's frame, J (see :class:`GyrocompassRun`)."""
    along_ab, big_omega = platform.along_gimbal_axis, platform.rate
    spin_momentum = axial * spin
    return (
        0.5 * transverse * (theta_rate * theta_rate - along_ab * along_ab)
        - 0.5 * transverse * (big_omega * np.sin(theta)) ** 2
        - spin_momentum * big_omega * np.cos(theta)
        + 0.5 * spin_momentum * spin
    )
