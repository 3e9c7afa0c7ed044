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
)
from tumble.units import to_si, vector_to_si

__all__ = ["RotorLoads", "SkewRod", "rotor_loads", "skew_rod"]

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
    """Loads on a body spun at a constant rate about a fixed axis (see :func:`rotor_loads`).

    All vectors are in **body** coordinates, so they are constant; in space they
    turn with the body about the axis. SI units.

    Attributes
    ----------
    axis : (3,) unit vector of the spin axis.
    point : (3,) the body point on the axis about which moments are taken, m.
    omega : spin rate about ``axis``, rad/s (signed).
    angular_momentum : (3,) L = I_P ω about ``point``, kg·m²/s.
    torque : (3,) τ = ω × (I_P ω), the torque about ``point`` that keeps the
        rotation steady, N·m; perpendicular to the axis (it needs no drive torque).
        Zero when the axis is a principal axis of I_P.
    force : (3,) the net force the supports exert, m ω × (ω × (c − P)), N: the
        centripetal force of an off-axis centre of mass, of magnitude m ω² r⊥
        (static imbalance). Zero when the axis passes through the centre of mass.
    bearings : (2,) positions of the two bearings along the axis, measured
        from ``point``, m; None if not given.
    bearing_forces : (2, 3) the forces the two bearings exert on the body, N,
        perpendicular to the axis (the axial thrust is zero: the motion needs
        none). Their sum is ``force`` and their moment about ``point`` is
        ``torque``. The loads on the bearings are their opposites. None if no
        bearings were given.
    """

    axis: Array
    point: Array
    omega: float
    angular_momentum: Array
    torque: Array
    force: Array
    bearings: Array | None
    bearing_forces: Array | None


def rotor_loads(
    mp: MassProperties,
    omega: Any,
    axis: Any = (0.0, 0.0, 1.0),
    point: Any = (0.0, 0.0, 0.0),
    bearings: Any = None,
) -> RotorLoads:
    """Torque and bearing forces that keep a body spinning at a constant rate about a fixed axis.

    The body turns at ω about a line fixed in space and in the body (a shaft in
    bearings), through ``point``. About that fixed point ``L = I_P ω`` is
    constant in the body and turns with it, so the supports must supply
    ``τ = dL/dt = ω × (I_P ω)`` (dynamic imbalance: products of inertia with the
    axis) and the force ``F = m ω × (ω × r_c)`` that keeps the centre of mass,
    at ``r_c`` from the axis point, on its circle (static imbalance,
    |F| = m ω² r⊥). With two bearings at axial positions ``s_A``, ``s_B``, the
    bearing forces ``F_A``, ``F_B`` (perpendicular to the axis) solve
    ``F_A + F_B = F`` and ``s_A n × F_A + s_B n × F_B = τ``:
    ``F_A = (τ − s_B n × F) × n / (s_A − s_B)``, ``F_B = F − F_A``
    (Goldstein, Classical Mechanics, §5.6; Meriam & Kraige, Dynamics, rotor balancing).

    Parameters
    ----------
    mp : the body.
    omega : constant spin rate about ``axis``, rad/s (signed), e.g. ``"3000 rpm"``.
    axis : (3,) direction of the spin axis in body coordinates (any length > 0).
    point : (3,) a body point on the axis, m (default the body origin); moments
        (``torque``, ``angular_momentum``) are about it and bearing positions
        are measured from it.
    bearings : None, or the two axial positions ``(s_A, s_B)`` of the bearings
        along ``axis`` from ``point``, m (distinct).

    Returns
    -------
    RotorLoads, in body coordinates. Gravity is not included: these are the
    dynamic loads (add the static weight of the rotor separately).

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
    direction = vector_to_si(axis, "dimensionless", "axis", (3,))
    length = float(np.linalg.norm(direction))
    if not length > 0:
        raise InputError(f"Expected `axis` to be a non-zero vector, got {direction.tolist()}.")
    n = direction / length
    p = vector_to_si(point, "length", "point", (3,))
    omega_vector = w * n
    momentum = mp.inertia_about(p) @ omega_vector
    torque = np.cross(omega_vector, momentum)
    force = mp.mass * np.cross(omega_vector, np.cross(omega_vector, mp.center_of_mass - p))
    positions = None
    forces = None
    if bearings is not None:
        positions = vector_to_si(bearings, "length", "bearings", (2,))
        s_a, s_b = float(positions[0]), float(positions[1])
        if s_a == s_b:
            raise InputError(
                f"Expected `bearings` to be two different axial positions, got {s_a!r} twice."
            )
        f_a = np.cross(torque - s_b * np.cross(n, force), n) / (s_a - s_b)
        forces = readonly([f_a, force - f_a])
        positions = readonly(positions)
    return RotorLoads(
        axis=readonly(n),
        point=readonly(p),
        omega=w,
        angular_momentum=readonly(momentum),
        torque=readonly(torque),
        force=readonly(force),
        bearings=positions,
        bearing_forces=forces,
    )
