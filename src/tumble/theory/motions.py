"""Exact motions at any times, without stepping: the torque-free rigid body, the
torque-free gyrostat and the heavy symmetric (Lagrange) top. SI units; ω
(rad/s) in body axes and the attitude a unit quaternion ``[w, x, y, z]``, body →
space, except in :func:`exact_principal`, which works in the principal frame.

These closed forms are what ``method="exact"`` samples
(:func:`tumble.integrators.drivers.run_exact`), and what
:func:`tumble.theory.free_motion` and :func:`tumble.theory.gyroscope` evaluate.

The rigid body's ω follows from Jacobi elliptic functions
(:func:`tumble.core.freebody.free_omega`) and its attitude is written with
z-x-z Euler angles about the fixed L (Landau & Lifshitz, *Mechanics* §37): with
L along the Z axis of a space frame R_L, ``A = R_L Rz(φ) Rx(θ) Rz(ψ)``, where
``cos θ = L3/L`` and ``tan ψ = L1/L2`` follow from ω, and φ is the integral of
``φ̇ = L (I1 ω1² + I2 ω2²)/(I1² ω1² + I2² ω2²)``
(:func:`tumble.core.freebody.free_precession_angle`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.body import ZERO_MOMENT, RigidBody, body_model
from tumble.errors import InputError, IntegrationError
from tumble.massprops import MassProperties

__all__ = [
    "MAX_PHASE",
    "LagrangeTop",
    "exact_principal",
    "exact_solution",
    "gyrostat_solution",
    "lagrange_top",
    "symmetric_gyrostat",
    "symmetric_top",
]

Array = NDArray[np.float64]


def exact_solution(
    mp: MassProperties, omega0: Array, attitude0: Array, times: Array
) -> tuple[Array, Array]:
    """The exact torque-free motion of ``mp`` about its centre of mass at ``times``
    (s): ω (n, 3) in body axes, rad/s, and the attitude (n, 4) body → space, from
    ω0 (body axes, rad/s) and the unit quaternion ``attitude0``."""
    body = body_model(mp)
    moments = body.moments
    if moments[0] <= ZERO_MOMENT * moments[2]:
        raise InputError(
            f"Expected a body with no zero principal moment, got moments {moments.tolist()} kg·m²."
        )
    w, q = exact_principal(
        moments, body.to_principal(omega0), body.attitude_to_principal(attitude0), times
    )
    return body.from_principal(w), body.attitude_from_principal(q)


def exact_principal(moments: Array, w0: Array, q0: Array, times: Array) -> tuple[Array, Array]:
    """Exact torque-free ω (principal frame, rad/s) and attitude (principal →
    space) at ``times`` (s), from ω0 and q0 in the principal frame of the
    ascending principal ``moments`` (kg·m²)."""
    from tumble.core.freebody import free_attitude, momentum_frame

    w0 = np.asarray(w0, dtype=float)
    moment_exponent, rate_exponent = _order_one(moments, w0)
    phases = _phases(times, rate_exponent)
    moments, w0 = np.ldexp(moments, -moment_exponent), np.ldexp(w0, -rate_exponent)
    if np.count_nonzero(w0 == 0.0) >= 2 or moments[0] == moments[2]:
        # Steady rotation about a principal axis, or any rotation of a sphere.
        start = Rotation.from_quat(q0, scalar_first=True)
        attitude = start * Rotation.from_rotvec(np.outer(phases, w0))
        w, q = np.tile(w0, (times.size, 1)), attitude.as_quat(scalar_first=True)
    else:
        frame = momentum_frame(moments, w0, np.asarray(q0, dtype=float))  # its z axis along L
        w, q = free_attitude(moments, w0, frame, phases)
    return np.ldexp(w, rate_exponent), q


def _order_one(moments: Array, rates: Array) -> tuple[int, int]:
    """The powers of two that bring the largest of ``moments`` and of ``|rates|``
    to [0.5, 1).

    A torque-free motion depends on the ratios of the moments only, and ω0
    scaled by s gives s ω(s t): the closed forms are evaluated for the scaled
    body, so that |L|², 2T and the elliptic constants (powers of up to four of
    the moments and rates) stay far from float64's limits for any mass and any
    rate it holds. Scaling by powers of two is exact.
    """
    largest_rate = _largest([abs(rate) for rate in np.asarray(rates, dtype=float).tolist()])
    largest_moment = _largest(np.asarray(moments, dtype=float).tolist())
    return math.frexp(largest_moment)[1], math.frexp(largest_rate)[1]


def _largest(values: list[float]) -> float:
    """``np.max`` of a few floats (NaN if any is NaN), without numpy's call."""
    return math.nan if any(math.isnan(v) for v in values) else max(values)


#: The largest phase (rad) a closed form is evaluated at: beyond 2^53 rad,
#: neighbouring float64 numbers are a radian or more apart and a turn is lost.
MAX_PHASE = 2.0**53


def _phases(times: Array, rate_exponent: int) -> Array:
    """``times`` (s) in the time unit of the rates scaled by 2^-``rate_exponent``
    (:func:`_order_one`), in which a unit of time is about a radian of the motion.

    Raises
    ------
    IntegrationError
        When the last of them is past :data:`MAX_PHASE`.
    """
    scaled = np.ldexp(np.asarray(times, dtype=float), rate_exponent)
    largest = float(np.max(np.abs(scaled), initial=0.0))
    if not largest <= MAX_PHASE:
        longest = float(np.max(np.abs(times)))
        raise IntegrationError(
            f"Expected a motion of at most 2**53 rad of phase for the closed form, got "
            f"about {largest:.3g} rad (its rates times t = {longest:.6g} s), where a turn "
            "is below float64's round-off: ask for a shorter duration or slower rates."
        )
    return scaled


def symmetric_gyrostat(
    body: RigidBody, omega0: Array, attitude0: Array, times: Array
) -> tuple[Array, Array, Array]:
    """The exact torque-free motion of a symmetric gyrostat
    (:meth:`tumble.body.RigidBody.symmetric_gyrostat_axis`): ω (n, 3) and the
    attitude (n, 4), body axes, and the rotors' values (n, k), at ``times`` (s).

    With e the symmetry axis, A and C the platform's transverse and axial
    moments and h the rotors' axial momentum along e (constant: no motor), the
    momentum in the body is ``H = A ω⊥ + (C ω_e + h) e``. Euler's equations
    give ``ω̇⊥ = λ e × ω⊥``, ``λ = ((C − A) ω_e + h) / A``, with ω_e constant:
    ω⊥ turns about e at λ. Since ``ω = (|H| / A) Ĥ − λ e``, the attitude is a
    turn about the fixed Ĥ at |H| / A after a turn about e at −λ (Hughes,
    *Spacecraft Attitude Dynamics*, §7.2; the rigid body's steady precession,
    Landau & Lifshitz §33, with the rotors' momentum added)."""
    axis = body.symmetric_gyrostat_axis()
    if axis is None:
        raise InputError(
            "Expected a symmetric gyrostat (two equal platform moments, rotors without "
            "motors on the axis of symmetry) for the exact solution, got another body."
        )
    e = np.eye(3)[axis]
    w0 = body.to_principal(np.asarray(omega0, dtype=float))
    values0 = body.initial_values(np.asarray(omega0, dtype=float))
    # Scaled to order one, as in exact_principal (h as a moment times a rate).
    moment_exponent, _ = _order_one(body.moments, w0)
    moments = np.ldexp(body.moments, -moment_exponent)
    h = math.ldexp(_axial_momentum(body, omega0, body.from_principal(e)), -moment_exponent)
    transverse, axial = moments[(axis + 1) % 3], moments[axis]
    _, rate_exponent = _order_one(moments, np.append(w0, h / axial))
    w0, h = np.ldexp(w0, -rate_exponent), math.ldexp(h, -rate_exponent)
    phases = _phases(times, rate_exponent)
    spin = float(w0 @ e)
    rate = ((axial - transverse) * spin + h) / transverse
    momentum = transverse * (w0 - spin * e) + (axial * spin + h) * e
    size = float(np.linalg.norm(momentum))
    start = Rotation.from_quat(body.attitude_to_principal(attitude0), scalar_first=True)
    direction = start.apply(momentum / size)  # Ĥ in space
    about_h = Rotation.from_rotvec(np.outer(phases * size / transverse, direction))
    about_e = Rotation.from_rotvec(np.outer(-rate * phases, e))
    attitude = about_h * start * about_e
    turned = Rotation.from_rotvec(np.outer(rate * phases, e)).apply(w0 - spin * e)
    w = np.ldexp(turned + spin * e, rate_exponent)
    omega = body.from_principal(w)
    q = body.attitude_from_principal(attitude.as_quat(scalar_first=True))
    return omega, q, np.tile(values0, (len(times), 1))


def _axial_momentum(body: RigidBody, omega0: Array, axis: Array) -> float:
    """The parts' own momentum along the unit ``axis`` (body axes; kg·m²/s): for
    rotors, each J (a·ω + Ω) with the sign of a·axis, constant without motors
    (every part is gyrostatic: the caller's gyrostat axis says so)."""
    omega0 = np.asarray(omega0, dtype=float)
    h = 0.0
    for part, values in zip(body.parts, body.split_values(None, omega0), strict=True):
        h += float(part.momentum(omega0, values) @ axis)
    return h


def _gyrostat_frame(body: RigidBody, axis: Array) -> tuple[Array, Array]:
    """The platform's principal axes with the rotor ``axis`` third, as the
    columns of a proper rotation (body axes), and their moments (kg·m²): the
    other two diagonalise the platform inertia in the plane normal to the axis
    (whatever frame the body chose within a plane of equal moments)."""
    inertia = body.platform_inertia
    plane = np.linalg.svd(axis[None, :])[2][1:].T  # (3, 2) orthonormal, normal to axis
    moments, turn = np.linalg.eigh(plane.T @ inertia @ plane)
    first, second = plane @ turn[:, 0], plane @ turn[:, 1]
    if np.cross(first, second) @ axis < 0.0:
        second = -second
    frame = np.column_stack([first, second, axis])
    return frame, np.array([moments[0], moments[1], float(axis @ inertia @ axis)])


def gyrostat_solution(
    body: RigidBody, omega0: Array, attitude0: Array, times: Array
) -> tuple[Array, Array, Array]:
    """The exact torque-free motion of a gyrostat whose rotors, free of motors,
    lie on one principal axis of the platform
    (:meth:`tumble.body.RigidBody.gyrostat_axis`): ω (n, 3) and the attitude
    (n, 4), body axes, and the rotors' values (n, k), at ``times`` (s).

    A symmetric platform about that axis precesses steadily
    (:func:`symmetric_gyrostat`); otherwise H in the body follows Jacobi
    elliptic functions (:mod:`tumble.core.gyrostat`), in the platform's
    principal axes with the rotors' third, and the attitude is written, as for
    the rigid body, with z-x-z Euler angles about the fixed H:
    ``cos θ = H3/|H|``, ``tan ψ = H1/H2`` and
    ``φ̇ = |H| (H1 ω1 + H2 ω2) / (H1² + H2²)``, integrated over one period to
    round-off by Chebyshev panels (:func:`tumble.core.freebody.panel_series`).
    """
    from tumble.core.gyrostat import gyrostat_constants

    axis = body.gyrostat_axis()
    if axis is None:
        raise InputError(
            "Expected a gyrostat for the exact solution (rotors without motors, all on "
            "one principal axis of the platform), got another body."
        )
    if body.symmetric_gyrostat_axis() is not None:
        return symmetric_gyrostat(body, omega0, attitude0, times)
    omega0 = np.asarray(omega0, dtype=float)
    times = np.asarray(times, dtype=float)
    frame, moments = _gyrostat_frame(body, axis)
    to_body = Rotation.from_matrix(frame)
    h = _axial_momentum(body, omega0, axis)
    w0 = frame.T @ omega0
    start = Rotation.from_quat(attitude0, scalar_first=True) * to_body
    # Scaled to order one, as in exact_principal (the rotors' momentum h as a moment
    # times a rate), and back after.
    moment_exponent, _ = _order_one(moments, w0)
    moments, h = np.ldexp(moments, -moment_exponent), math.ldexp(h, -moment_exponent)
    _, rate_exponent = _order_one(moments, np.append(w0, h / moments[2]))
    w0, h = np.ldexp(w0, -rate_exponent), math.ldexp(h, -rate_exponent)
    times = _phases(times, rate_exponent)
    rotor_momentum = np.array([0.0, 0.0, h])
    h0 = moments * w0 + rotor_momentum
    if h == 0.0:  # the rotors carry no momentum: the platform turns as a rigid body
        w, q = exact_principal(moments, w0, start.as_quat(scalar_first=True), times)
        attitude = Rotation.from_quat(q, scalar_first=True)
    elif np.linalg.norm(np.cross(w0, h0)) <= 1e-14 * np.linalg.norm(w0) * np.linalg.norm(h0):
        # ω parallel to H: a steady rotation
        w = np.tile(w0, (times.size, 1))
        attitude = start * Rotation.from_rotvec(np.outer(times, w0))
    else:
        w, attitude = _gyrostat_motion(
            gyrostat_constants(moments, h, *w0), moments, h0, rotor_momentum, start, times
        )
    omega = np.ldexp(w, rate_exponent) @ frame.T
    quaternion = (attitude * to_body.inv()).as_quat(scalar_first=True)
    momenta0 = [part.momenta(omega0, part.initial_values(omega0)) for part in body.parts]
    values = np.concatenate(
        [
            part.values_from(omega, np.broadcast_to(m, (len(times), 1)))
            for part, m in zip(body.parts, momenta0, strict=True)
        ],
        axis=1,
    )
    return omega, quaternion, values


def _gyrostat_motion(
    constants: Array,
    moments: Array,
    h0: Array,
    rotor_momentum: Array,
    start: Rotation,
    times: Array,
) -> tuple[Array, Rotation]:
    """ω (n, 3) and the attitude of the gyrostat of :func:`gyrostat_solution`
    in the frame of its rotor axis (``h0``: H at t = 0 there, ``rotor_momentum``
    the rotors' part of it, along axis 3; ``start``: that frame's attitude at t = 0)."""
    from tumble.core.freebody import panel_nodes, panel_series, periodic_integral
    from tumble.core.gyrostat import gyrostat_momentum, gyrostat_period

    momentum = gyrostat_momentum(constants, times)
    size = float(np.linalg.norm(h0))
    period = gyrostat_period(constants)
    # Panels a quarter wide in the elliptic argument, as for the rigid body.
    panels = max(8, int(np.ceil(period * abs(constants[8]) / 0.25)))
    nodes = panel_nodes(period / panels, panels)
    at_nodes = gyrostat_momentum(constants, nodes)
    rates_at_nodes = (at_nodes - rotor_momentum) / moments
    # Euler angles about the axis (third or first) H stays farthest from, as
    # for the rigid body (tumble.core.freebody.free_attitude): about an axis H
    # passes close to, φ̇ = |H| (ω_i H_i + ω_j H_j) / (H_i² + H_j²) has a sharp peak.
    first = np.min(at_nodes[:, 1] ** 2 + at_nodes[:, 2] ** 2) > np.min(
        at_nodes[:, 0] ** 2 + at_nodes[:, 1] ** 2
    )
    order = [1, 2, 0] if first else [0, 1, 2]  # the axes (x', y', z') of the angles
    cycle = Rotation.from_quat([0.5, 0.5, 0.5, 0.5] if first else [1.0, 0, 0, 0], scalar_first=True)
    x, y = at_nodes[:, order[0]], at_nodes[:, order[1]]
    wx, wy = rates_at_nodes[:, order[0]], rates_at_nodes[:, order[1]]
    rates = size * (wx * x + wy * y) / (x * x + y * y)
    phi = periodic_integral(panel_series(rates, period / panels, panels), period, times)
    turned, turned0 = momentum[:, order], h0[order]
    theta = np.arctan2(np.hypot(turned[:, 0], turned[:, 1]), turned[:, 2])
    psi = np.arctan2(turned[:, 0], turned[:, 1])
    initial = Rotation.from_euler(
        "ZXZ",
        [
            0.0,
            np.arctan2(np.hypot(turned0[0], turned0[1]), turned0[2]),
            np.arctan2(turned0[0], turned0[1]),
        ],
    )
    frame = start * cycle * initial.inv()  # space axes with z along H
    attitude = frame * Rotation.from_euler("ZXZ", np.column_stack([phi, theta, psi])) * cycle.inv()
    return (momentum - rotor_momentum) / moments, attitude


@dataclass(frozen=True, eq=False)
class LagrangeTop:
    """The closed-form motion of a heavy symmetric top (:func:`lagrange_top`).

    Attributes
    ----------
    constants : the constants of :mod:`tumble.core.lagrange` (None for a
        sleeping top: a steady rotation about the vertical axis).
    frame : (3, 3) columns e1, e2, e in body axes: a proper rotation whose third
        column is the symmetry axis, from the pivot towards the centre of mass.
    omega0 : (3,) ω at t = 0, body axes, rad/s.
    attitude0 : (4,) the attitude at t = 0, body → space.
    vertical : (3,) the upward vertical −g/|g|, space axes.
    """

    constants: Array | None
    frame: Array
    omega0: Array
    attitude0: Array
    vertical: Array
    # The quaternions around the motion in the frame (left ⊗ q(t) ⊗ right) and
    # the Jacobi table of its modulus: computed once, used by every call of `at`.
    _left: Array = field(init=False, repr=False)
    _right: Array = field(init=False, repr=False)
    _table: Array = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if self.constants is None:
            return
        from tumble.core.elliptic import jacobi_table
        from tumble.core.lagrange import top_start

        theta0, psi0 = top_start(self.constants)
        to_frame = Rotation.from_matrix(self.frame)
        begin = Rotation.from_euler("ZXZ", [0.0, theta0, psi0])
        left = Rotation.from_quat(self.attitude0, scalar_first=True) * to_frame * begin.inv()
        mc = float(self.constants[2])
        object.__setattr__(self, "_left", left.as_quat(scalar_first=True))
        object.__setattr__(self, "_right", to_frame.inv().as_quat(scalar_first=True))
        object.__setattr__(self, "_table", jacobi_table(mc, 0.0) if mc > 0.0 else np.zeros(1))

    def at(self, times: Array) -> tuple[Array, Array]:
        """ω (n, 3), body axes, rad/s, and the attitude (n, 4), body → space, at
        ``times`` (s, any order and sign): O(1) a sample, compiled."""
        from tumble.core.lagrange import top_motion

        times = np.ascontiguousarray(times, dtype=float)
        if self.constants is None:  # a steady rotation about the vertical axis
            turns = Rotation.from_rotvec(np.outer(times, self.omega0))
            start = Rotation.from_quat(self.attitude0, scalar_first=True)
            quaternion = (start * turns).as_quat(scalar_first=True)
            return np.tile(self.omega0, (times.size, 1)), quaternion
        w = np.empty((times.size, 3))
        q = np.empty((times.size, 4))
        top_motion(self.constants, times, self._table, self._left, self._right, w, q)
        return w @ self.frame.T, q

    def mean_rates(self) -> tuple[float, float, float]:
        """The nutation period (s; ``inf`` on a separatrix, where the axis tends to
        the upright position, and for a motion without nutation, 0 is never
        returned) and the mean precession rate of the axis about the upward
        vertical and the mean spin rate ψ̇ over it, rad/s."""
        from tumble.core.lagrange import top_mean_rates

        if self.constants is None:
            return math.inf, 0.0, float(self.omega0 @ self.frame[:, 2])
        period, precession, spin = top_mean_rates(self.constants)
        return float(period), float(precession), float(spin)


def lagrange_top(body: RigidBody, gravity: Array, omega0: Array, attitude0: Array) -> LagrangeTop:
    """The heavy symmetric top in closed form (:mod:`tumble.core.lagrange`): a
    body on a pivot with equal moments about two axes through it and its
    centre of mass on the third (:meth:`tumble.body.RigidBody.symmetric_top_axis`),
    under uniform ``gravity`` (3,) m/s², space axes, from ω0 (body axes, rad/s)
    and the attitude ``attitude0`` (body → space) at t = 0.

    Raises
    ------
    InputError
        A body that is not such a top, or no gravity.
    """
    axis = body.symmetric_top_axis()
    if axis is None or not np.any(gravity):
        raise InputError(
            "Expected a symmetric top (two equal moments about the pivot, the pivot and "
            "the centre of mass on the symmetry axis) under gravity for the closed form, "
            "got " + ("no gravity." if axis is not None else "another body.")
        )
    # e1 normal to the axis, from the body axis least aligned with it; e2 = e × e1.
    first = np.cross(axis, np.eye(3)[int(np.argmin(np.abs(axis)))])
    first /= np.linalg.norm(first)
    frame = np.column_stack([first, np.cross(axis, first), axis])
    second = frame[:, 1]
    inertia = body.inertia
    transverse = 0.5 * float(first @ inertia @ first + second @ inertia @ second)
    mass_lever = body.mass_properties.mass * float(body.lever @ axis)
    return symmetric_top(
        frame, transverse, float(axis @ inertia @ axis), mass_lever, gravity, omega0, attitude0
    )


def symmetric_top(
    frame: Array,
    transverse: float,
    axial: float,
    mass_lever: float,
    gravity: Array,
    omega0: Array,
    attitude0: Array,
) -> LagrangeTop:
    """The Lagrange top of :func:`lagrange_top` from its parts: ``frame`` (3, 3)
    a proper rotation whose third column (body axes) is the symmetry axis from
    the pivot towards the centre of mass, the moments A (``transverse``) and C
    (``axial``) about the pivot (kg·m²), m l (``mass_lever``, kg·m, > 0) and
    ``gravity`` (3,) m/s² in space axes (≠ 0)."""
    g = np.asarray(gravity, dtype=float)
    weight = math.hypot(*g)  # no underflow of the squares of a tiny gravity
    up = -g / weight
    omega0 = np.asarray(omega0, dtype=float)
    attitude0 = np.asarray(attitude0, dtype=float)
    w = frame.T @ omega0
    k = frame.T @ Rotation.from_quat(attitude0, scalar_first=True).inv().apply(up)
    if k[0] == 0.0 and k[1] == 0.0 and w[0] == 0.0 and w[1] == 0.0:
        return LagrangeTop(None, frame, omega0, attitude0, up)  # a sleeping top
    from tumble.core.lagrange import top_constants

    # Ratios of the moments first: a top of any mass within float64's range.
    beta = 2.0 * (mass_lever / transverse) * weight
    spin = axial / transverse * w[2]
    constants = top_constants(beta, spin, w[2], k[0], k[1], k[2], w[0], w[1])
    return LagrangeTop(constants, frame, omega0, attitude0, up)
