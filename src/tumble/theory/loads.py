"""The rotating skew rod and unbalanced rotors: L not parallel to ω, and the
torque and bearing loads a steady rotation needs."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.massprops import (
    MassProperties,
    as_mass_properties,
    readonly,
)
from tumble.theory.common import (
    as_times,
    positive,
    rotate_about_z,
    spin_axis,
)
from tumble.units import to_si, vector_to_si

__all__ = ["PivotLoads", "RotorLoads", "SkewRod", "pivot_loads", "rotor_loads", "skew_rod"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class SkewRod:
    """The rotating skew rod (see :func:`skew_rod`). SI units.

    Attributes
    ----------
    angular_momentum : |L| = 2 m ℓ² |ω cos α|, kg·m²/s.
    angular_momentum_axial : L · ẑ = 2 m ℓ² ω cos² α, the component along ω
        (signed like ω), kg·m²/s.
    angular_momentum_transverse : |L_h| = 2 m ℓ² |ω sin α cos α|, the part
        perpendicular to ω, which sweeps a circle at ω, kg·m²/s.
    torque : |τ| = |ω| |L_h| = 2 m ℓ² ω² |sin α cos α|, N·m, the torque the shaft
        must supply (perpendicular to both ω and L_h).
    angular_momentum_vector, torque_vector : (3,) L and τ at t = 0, when the rod
        lies in the x-z plane with the first mass at ℓ (cos α, 0, sin α):
        ``L(0) = 2 m ℓ² ω cos α (−sin α, 0, cos α)``,
        ``τ(0) = −2 m ℓ² ω² sin α cos α ŷ``. Both turn about z at ω.
    bearing_force : magnitude |τ| / d of each bearing force, N (None without a
        bearing separation).
    bearing_forces : (2, 3) at t = 0, the forces the bearings at z = +d/2 and
        z = −d/2 exert on the shaft, N: equal, opposite and horizontal, turning
        with the rod; the loads on the bearings are their opposites. None
        without a bearing separation.
    """

    mass: float
    half_length: float
    alpha: float
    omega: float
    bearing_separation: float | None
    angular_momentum: float
    angular_momentum_axial: float
    angular_momentum_transverse: float
    torque: float
    angular_momentum_vector: Array
    torque_vector: Array
    bearing_force: float | None
    bearing_forces: Array | None

    def angular_momentum_at(self, t: Any) -> Array:
        """L(t) in space coordinates, kg·m²/s: shape (3,) for a scalar t (s), else (n, 3)."""
        times, shape = as_times(t)
        return rotate_about_z(self.angular_momentum_vector, self.omega * times).reshape((*shape, 3))

    def torque_at(self, t: Any) -> Array:
        """τ(t) = dL/dt in space coordinates, N·m: shape (3,) or (n, 3)."""
        times, shape = as_times(t)
        return rotate_about_z(self.torque_vector, self.omega * times).reshape((*shape, 3))

    def bearing_forces_at(self, t: Any) -> Array:
        """The two bearing forces on the shaft at time t, N: shape (2, 3) or (n, 2, 3)."""
        if self.bearing_forces is None:
            raise InputError(
                "Expected `bearing_separation` to have been given to skew_rod(), got None."
            )
        times, shape = as_times(t)
        return rotate_about_z(self.bearing_forces, self.omega * times).reshape((*shape, 2, 3))


def skew_rod(
    mass: Any, half_length: Any, alpha: Any, omega: Any, bearing_separation: Any = None
) -> SkewRod:
    """Angular momentum, torque and bearing forces of the rotating skew rod.

    Two point masses m at ±ℓ on a massless rod through the origin, at angle α to
    the plane perpendicular to the spin axis z, turn at a constant rate ω about
    z. At t = 0 the rod lies in the x-z plane, the first mass at
    ``ℓ (cos α, 0, sin α)``. From ``L = Σ m r × (ω × r)``:
    ``L = 2 m ℓ² ω cos α (−sin α cos ωt, −sin α sin ωt, cos α)``, so
    ``|L| = 2 m ℓ² ω cos α`` with the part ``L_h = 2 m ℓ² ω sin α cos α``
    perpendicular to ω sweeping a circle; keeping the rotation steady takes the
    torque ``τ = dL/dt = ω × L``, ``|τ| = ω L_h = 2 m ℓ² ω² sin α cos α``
    (Kleppner & Kolenkow, An Introduction to Mechanics, ch. 7; Goldstein,
    Classical Mechanics, §5.1).

    Parameters
    ----------
    mass : mass of each of the two point masses, kg (> 0).
    half_length : ℓ, the distance of each mass from the axis point, m (> 0).
    alpha : α, angle of the rod from the plane perpendicular to z, rad or a
        quantity such as ``"30 deg"``; any value (α = 0: the rod is perpendicular
        to the axis and balanced; α = ±90°: along the axis, no L).
    omega : ω, constant spin rate about +z, rad/s (signed), e.g. ``"3000 rpm"``.
    bearing_separation : d, distance between two bearings on the axis at
        z = ±d/2, m (> 0); None to skip the bearing forces.

    Returns
    -------
    SkewRod. Gravity is not included: the bearing forces are the dynamic loads
    only (on the vertical shaft the rod's weight, m g, is a constant load along
    the shaft, taken by a thrust bearing).

    Raises
    ------
    InputError
        If the mass, half length or bearing separation is not positive, or any
        value is non-finite or in the wrong units.

    Examples
    --------
    Two 1 kg masses 0.5 m from the centre, the rod 30° from the plane of
    rotation, at 10 rad/s between bearings 0.4 m apart:

    >>> import tumble as tb
    >>> rod = tb.theory.skew_rod(1.0, 0.5, "30 deg", 10.0, bearing_separation=0.4)
    >>> print(f"|L| = {rod.angular_momentum:.6f} kg·m²/s, τ = {rod.torque:.6f} N·m")
    |L| = 4.330127 kg·m²/s, τ = 21.650635 N·m
    >>> print(f"each bearing: {rod.bearing_force:.6f} N")  # τ / d
    each bearing: 54.126588 N
    """
    m = positive(mass, "mass", "mass")
    ell = positive(half_length, "length", "half_length")
    a = to_si(alpha, "angle", "alpha")
    w = to_si(omega, "angular_velocity", "omega")
    d = (
        None
        if bearing_separation is None
        else positive(bearing_separation, "length", "bearing_separation")
    )
    ca, sa = math.cos(a), math.sin(a)
    scale = 2.0 * m * ell * ell
    momentum = scale * w * ca * np.array([-sa, 0.0, ca])
    torque = np.array([0.0, -scale * w * w * sa * ca, 0.0])  # ω ẑ × L(0)
    magnitude = scale * w * w * abs(sa * ca)
    forces = None
    if d is not None:
        # Bearings at ±d/2: F_top + F_bottom = 0 (the centre of mass is fixed) and
        # d ẑ × F_top = τ, so F_top = τ × ẑ / d.
        top = np.cross(torque, [0.0, 0.0, 1.0]) / d
        forces = readonly([top, -top])
    return SkewRod(
        mass=m,
        half_length=ell,
        alpha=a,
        omega=w,
        bearing_separation=d,
        angular_momentum=scale * abs(w * ca),
        angular_momentum_axial=scale * w * ca * ca,
        angular_momentum_transverse=scale * abs(w * sa * ca),
        torque=magnitude,
        angular_momentum_vector=readonly(momentum),
        torque_vector=readonly(torque),
        bearing_force=None if d is None else magnitude / d,
        bearing_forces=forces,
    )


@dataclass(frozen=True, eq=False)
class RotorLoads:
    """Loads on a body turning about a fixed axis (see :func:`rotor_loads`).

    All vectors are in **body** coordinates at the instant; in space they turn
    with the body about the axis. SI units.

    Attributes
    ----------
    axis : (3,) unit vector of the spin axis.
    point : (3,) the body point on the axis about which moments are taken, m.
    omega : spin rate about ``axis``, rad/s (signed).
    omega_dot : angular acceleration about ``axis``, rad/s² (signed).
    angular_momentum : (3,) L = I_P ω about ``point``, kg·m²/s.
    torque : (3,) τ = I_P ω̇ + ω × (I_P ω), the rate of change of L about
        ``point``: the moment of every external load (supports, drive and
        gravity), N·m. Perpendicular to the axis at a constant rate (then it
        needs no drive torque); zero at a constant rate when the axis is a
        principal axis of I_P.
    force : (3,) the net force the supports exert, m a_c − m g, N: the
        acceleration of the centre of mass (centripetal, m ω² r⊥ for a static
        imbalance, and tangential at ω̇) less its weight. Zero at a constant rate
        without gravity when the axis passes through the centre of mass.
    drive_torque : the moment about the axis that the drive must supply, N·m:
        I_nn ω̇ less gravity's moment about the axis (bearings cannot supply it).
    bearings : (2,) positions of the two bearings along the axis, measured
        from ``point``, m; None if not given.
    bearing_forces : (2, 3) the forces the two bearings exert on the body, N.
        Their sum is ``force`` and their moment about ``point`` is ``torque``
        less gravity's moment and the drive's; the first bearing (a thrust
        bearing) takes the axial force, the second only radial force. The loads
        on the bearings are their opposites. None if no bearings were given.
    """

    axis: Array
    point: Array
    omega: float
    omega_dot: float
    angular_momentum: Array
    torque: Array
    force: Array
    drive_torque: float
    bearings: Array | None
    bearing_forces: Array | None


@dataclass(frozen=True, eq=False)
class PivotLoads:
    """The support's force and torque on a body in a given motion about a pivot
    (see :func:`pivot_loads`), body coordinates at the instant, SI units.

    Attributes
    ----------
    force : (3,) F = m a_c − m g, N.
    torque : (3,) M = I_P ω̇ + ω × I_P ω − r_c × m g about the pivot, N·m (zero
        for a ball joint in a motion that gravity and the motion balance).
    """

    force: Array
    torque: Array


def pivot_loads(
    mp: MassProperties,
    omega: Any,
    omega_dot: Any,
    pivot: Any = (0.0, 0.0, 0.0),
    gravity: Any = None,
) -> PivotLoads:
    """The force and torque a support exerts on a body in a given instantaneous motion.

    A body point P (the pivot) is held fixed in space; the body turns at ω and
    ω̇ (body coordinates). Newton's law for the centre of mass at ``r_c`` from P,
    ``m a_c = F + m g`` with ``a_c = ω̇ × r_c + ω × (ω × r_c)``, and Euler's
    about P, ``I_P ω̇ + ω × I_P ω = M + r_c × m g``, give the support's
    ``F = m a_c − m g`` and ``M = I_P ω̇ + ω × I_P ω − r_c × m g`` (Meriam &
    Kraige, Dynamics, §7/9). A ball joint supplies F alone: M must then be zero
    for the motion to be possible (a precessing gyroscope, for one).

    Parameters
    ----------
    mp : the body.
    omega : (3,) angular velocity, rad/s, body coordinates.
    omega_dot : (3,) angular acceleration, rad/s², body coordinates (the
        derivative of ω, the same seen from space or from the body).
    pivot : (3,) the fixed body point P, m, body coordinates.
    gravity : None, or (3,) the acceleration of gravity in body coordinates at
        this instant, m/s² (e.g. ``(0, 0, -9.80665)`` when the body's z is up).

    Returns
    -------
    PivotLoads, in body coordinates.

    Examples
    --------
    A 2 kg disk of radius 0.1 m spinning at 150 rad/s on a horizontal shaft,
    its centre 0.15 m from a ball joint, precessing at Ω = m g l / (I_s ω_s):
    the joint carries the weight and the centripetal force, and no moment:

    >>> import numpy as np
    >>> import tumble as tb
    >>> from scipy.spatial.transform import Rotation
    >>> disk = tb.shapes.thin_disk(2.0, 0.1).transformed(
    ...     rotation=Rotation.from_rotvec([0, np.pi / 2, 0]), translation=[0.15, 0, 0])
    >>> precession = 2.0 * 9.80665 * 0.15 / (0.01 * 150.0)  # m g l / (I_s ω_s), I_s = m r²/2
    >>> loads = tb.theory.pivot_loads(disk, [150.0, 0, precession], [0, precession * 150.0, 0],
    ...                               gravity=[0, 0, -9.80665])
    >>> print(loads.force.round(6), np.abs(loads.torque).max() < 1e-12)
    [-1.154045  0.       19.6133  ] True
    """
    mp = as_mass_properties(mp)
    w = vector_to_si(omega, "angular_velocity", "omega", (3,))
    w_dot = vector_to_si(omega_dot, "angular_acceleration", "omega_dot", (3,))
    p = vector_to_si(pivot, "length", "pivot", (3,))
    g = np.zeros(3) if gravity is None else vector_to_si(gravity, "acceleration", "gravity", (3,))
    r = mp.center_of_mass - p
    inertia = mp.inertia_about(p)
    force = mp.mass * (np.cross(w_dot, r) + np.cross(w, np.cross(w, r))) - mp.mass * g
    torque = inertia @ w_dot + np.cross(w, inertia @ w) - np.cross(r, mp.mass * g)
    return PivotLoads(force=readonly(force), torque=readonly(torque))


def rotor_loads(
    mp: MassProperties,
    omega: Any,
    axis: Any = (0.0, 0.0, 1.0),
    point: Any = (0.0, 0.0, 0.0),
    bearings: Any = None,
    omega_dot: Any = 0.0,
    gravity: Any = None,
) -> RotorLoads:
    """Torque, drive torque and bearing forces of a body turning about a fixed axis.

    The body turns at ω, speeding up at ω̇, about a line fixed in space and in
    the body (a shaft in bearings), through ``point``. About that fixed point
    ``L = I_P ω``, so the loads must supply ``τ = I_P ω̇ + ω × (I_P ω)``
    (dynamic imbalance: products of inertia with the axis) and the force
    ``F = m a_c − m g`` with ``a_c = ω̇ × r_c + ω × (ω × r_c)`` for the centre of
    mass at ``r_c`` from the axis point (static imbalance, |F| = m ω² r⊥ at a
    constant rate), less gravity's weight. The drive supplies the moment about
    the axis, ``n · (τ − r_c × m g)``, which bearings cannot. With two bearings
    at axial positions ``s_A``, ``s_B``, the first taking the axial force, the
    radial parts solve ``F_A⊥ + F_B = F⊥`` and ``s_A n × F_A + s_B n × F_B = M⊥``
    (M the moment of the supports, ``τ − r_c × m g``):
    ``F_A⊥ = (M⊥ − s_B n × F⊥) × n / (s_A − s_B)``, ``F_B = F⊥ − F_A⊥``
    (Goldstein, Classical Mechanics, §5.6; Meriam & Kraige, Dynamics, rotor
    balancing).

    Parameters
    ----------
    mp : the body.
    omega : spin rate about ``axis``, rad/s (signed), e.g. ``"3000 rpm"``.
    axis : (3,) direction of the spin axis in body coordinates (any length > 0).
    point : (3,) a body point on the axis, m (default the body origin); moments
        (``torque``, ``angular_momentum``) are about it and bearing positions
        are measured from it.
    bearings : None, or the two axial positions ``(s_A, s_B)`` of the bearings
        along ``axis`` from ``point``, m (distinct); the first takes the axial
        force.
    omega_dot : angular acceleration about ``axis``, rad/s² (default 0).
    gravity : None (default: no gravity), or (3,) the acceleration of gravity in
        body coordinates at this instant, m/s².

    Returns
    -------
    RotorLoads, in body coordinates. At the defaults (constant rate, no
    gravity) the loads are the dynamic ones of a steady rotation.

    Raises
    ------
    InputError
        If ``mp`` is not a MassProperties, the axis is zero, or the two bearings
        coincide.

    Examples
    --------
    Static imbalance: a 2 kg disk whose centre of mass is 1 mm off the shaft,
    at 100 rad/s, pulls on its supports with ``m ω² e = 20 N``, shared by
    bearings 5 cm either side:

    >>> import numpy as np
    >>> import tumble as tb
    >>> disk = tb.shapes.thin_disk(2.0, 0.1)
    >>> off_centre = disk.transformed(translation=[0.001, 0, 0])
    >>> loads = tb.theory.rotor_loads(off_centre, 100.0, bearings=(0.05, -0.05))
    >>> print(f"{np.linalg.norm(loads.force):.6f} N")
    20.000000 N
    >>> print(np.linalg.norm(loads.bearing_forces, axis=1).round(6))
    [10. 10.]

    Dynamic imbalance: the same disk centred but tilted 1° on the shaft needs
    the torque ``ω² (I_s − I⊥) sin α cos α``:

    >>> from scipy.spatial.transform import Rotation
    >>> tilted = disk.transformed(rotation=Rotation.from_rotvec([np.radians(1.0), 0, 0]))
    >>> loads = tb.theory.rotor_loads(tilted, 100.0)
    >>> print(f"{np.linalg.norm(loads.torque):.6f} N·m")
    0.872487 N·m
    """
    mp = as_mass_properties(mp)
    w = to_si(omega, "angular_velocity", "omega")
    w_dot = to_si(omega_dot, "angular_acceleration", "omega_dot")
    n = spin_axis(axis)
    p = vector_to_si(point, "length", "point", (3,))
    inertia = mp.inertia_about(p)
    momentum = inertia @ (w * n)
    torque = inertia @ (w_dot * n) + np.cross(w * n, momentum)
    motion = pivot_loads(mp, w * n, w_dot * n, p, gravity)  # the supports' force and moment
    force = np.array(motion.force)
    drive = float(n @ motion.torque)
    positions = None
    forces = None
    if bearings is not None:
        positions = vector_to_si(bearings, "length", "bearings", (2,))
        s_a, s_b = float(positions[0]), float(positions[1])
        if s_a == s_b:
            raise InputError(
                f"Expected `bearings` to be two different axial positions, got {s_a!r} twice."
            )
        radial = force - (n @ force) * n
        moment = motion.torque - drive * n
        f_a = np.cross(moment - s_b * np.cross(n, radial), n) / (s_a - s_b)
        forces = readonly([f_a + (n @ force) * n, radial - f_a])
        positions = readonly(positions)
    return RotorLoads(
        axis=readonly(n),
        point=readonly(p),
        omega=w,
        omega_dot=w_dot,
        angular_momentum=readonly(momentum),
        torque=readonly(torque),
        force=readonly(force),
        drive_torque=drive,
        bearings=positions,
        bearing_forces=forces,
    )
