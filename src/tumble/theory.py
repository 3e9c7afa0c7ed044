"""Closed-form results of rigid-body rotation: no simulation, exact where an exact answer exists.

* :func:`skew_rod` — the rotating skew rod: L not parallel to ω, the torque and
  bearing forces it needs.
* :func:`rotor_loads` — the same for any body spun at a constant rate about a
  fixed axis (unbalanced rotors).
* :func:`flip_period` — period of ω(t) of a torque-free body (the tennis-racket flip).
* :func:`free_symmetric_top` — body and space cones of a torque-free symmetric top.
* :func:`axis_stability` — stability of steady rotation about each principal axis.
* :func:`gyroscope` — heavy symmetric top on a fixed pivot (Lagrange top):
  precession, nutation, the exact tilt θ(t) of a top released from rest.
* :func:`gyrocompass` — the gimballed gyroscope carried round a vertical axis.

Conventions as in the rest of tumble: SI units inside (numbers, pint quantities
or strings such as ``"3000 rpm"`` at the edge), angular velocity in body
coordinates unless said otherwise, inertia tensors about the centre of mass in
body axes unless a point is named, products of inertia ``I_xy = −Σ m x y``.
Each function but :func:`flip_period` returns a small immutable dataclass whose
docstring gives the units.

The lecture notes' gyrocompass equation ``I_AB θ̈ + Ω L_s sin θ = 0`` is the
fast-spin approximation: it drops ``−I_AB Ω² sin θ cos θ``, which
:func:`gyrocompass` keeps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import special

from tumble.core.elliptic import ellipj_mc
from tumble.errors import InputError
from tumble.massprops import PHYSICAL_TOLERANCE, REPEATED_MOMENT_TOLERANCE, MassProperties
from tumble.units import to_si, vector_to_si

__all__ = [
    "AxisStability",
    "FreeSymmetricTop",
    "Gyrocompass",
    "Gyroscope",
    "RotorLoads",
    "SkewRod",
    "axis_stability",
    "flip_period",
    "free_symmetric_top",
    "gyrocompass",
    "gyroscope",
    "rotor_loads",
    "skew_rod",
]

Array = NDArray[np.float64]


# ----------------------------------------------------------------- helpers
def _readonly(values: Any) -> Array:
    array = np.array(values, dtype=float)
    array.setflags(write=False)
    return array


def _positive(value: Any, kind: str, name: str) -> float:
    result = to_si(value, kind, name)
    if result <= 0:
        raise InputError(f"Expected `{name}` > 0 {_UNIT[kind]}, got {result!r}.")
    return result


_UNIT = {"mass": "kg", "length": "m", "acceleration": "m/s²"}


def _times(t: Any) -> tuple[Array, tuple[int, ...]]:
    """Times in s as a flat array, and the shape of ``t`` (``()`` for a scalar)."""
    if np.ndim(t) == 0:
        return np.array([to_si(t, "time", "t")]), ()
    times = vector_to_si(t, "time", "t", (-1,))
    return times, times.shape


def _rotate_about_z(vectors: Array, angles: Array) -> Array:
    """Each (..., 3) vector turned by each angle about +z: result (n, ..., 3)."""
    c = np.cos(angles).reshape((-1,) + (1,) * (vectors.ndim - 1))
    s = np.sin(angles).reshape(c.shape)
    x, y, z = vectors[..., 0], vectors[..., 1], vectors[..., 2]
    return np.stack((c * x - s * y, s * x + c * y, np.broadcast_to(z, (c * x).shape)), axis=-1)


def _check_moments(moments: Array, name: str) -> None:
    """Principal moments usable in Euler's equations: positive, triangle inequality."""
    if np.any(moments <= 0):
        raise InputError(
            f"Expected `{name}` to be three principal moments > 0 kg·m² (Euler's equations "
            f"divide by each; a thin rod or a point mass has none to spin about), "
            f"got {_format(moments)}."
        )
    ordered = np.sort(moments)
    if ordered[0] + ordered[1] < ordered[2] * (1 - PHYSICAL_TOLERANCE):
        raise InputError(
            f"Expected `{name}` to satisfy the triangle inequality I1 + I2 >= I3, got "
            f"{_format(moments)} kg·m² (no distribution of mass has these moments)."
        )


def _principal_state(body: Any, omega0: Any, name: str) -> tuple[Array, Array, Array]:
    """Principal moments, ω0 in the principal frame, and the principal axes.

    ``body`` is a MassProperties (ω0 in its body axes; axes from ``principal()``,
    moments ascending) or three principal moments (ω0 in the same principal axes,
    axes the identity, moments in the order given).
    """
    omega = vector_to_si(omega0, "angular_velocity", "omega0", (3,))
    if isinstance(body, MassProperties):
        moments, axes = body.principal()
        moments = np.array(moments)
        omega = axes.T @ omega
    else:
        moments = vector_to_si(body, "inertia", name, (3,))
        axes = np.eye(3)
    _check_moments(moments, name)
    return moments, omega, axes


def _format(values: Any) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in np.asarray(values, dtype=float)) + "]"


def _mass_properties(mp: Any) -> MassProperties:
    if not isinstance(mp, MassProperties):
        raise InputError(f"Expected `mp` to be a MassProperties, got {type(mp).__name__}.")
    return mp


def _axial_and_transverse(mp: MassProperties) -> tuple[float, float]:
    """I_s and I_⊥ about the centre of mass of a body symmetric about body z."""
    inertia = mp.inertia
    scale = max(float(np.trace(inertia)), np.finfo(float).tiny)
    tol = PHYSICAL_TOLERANCE * scale
    off = max(abs(inertia[0, 1]), abs(inertia[0, 2]), abs(inertia[1, 2]))
    if off > tol or abs(inertia[0, 0] - inertia[1, 1]) > tol:
        raise InputError(
            "Expected `mp` to be symmetric about body z (inertia about the centre of mass "
            "diag(I⊥, I⊥, Is): I_xx = I_yy and no products of inertia), got inertia rows "
            f"{_format(inertia[0])}, {_format(inertia[1])}, {_format(inertia[2])} kg·m²."
        )
    axial = float(inertia[2, 2])
    if axial <= tol:
        raise InputError(
            "Expected `mp` to have a moment about its symmetry axis z > 0 kg·m² (a spin about "
            f"the axis needs one), got I_zz = {axial!r} (a thin rod along z?)."
        )
    return axial, 0.5 * float(inertia[0, 0] + inertia[1, 1])


# ----------------------------------------------------------------- skew rod
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
        times, shape = _times(t)
        return _rotate_about_z(self.angular_momentum_vector, self.omega * times).reshape(
            (*shape, 3)
        )

    def torque_at(self, t: Any) -> Array:
        """τ(t) = dL/dt in space coordinates, N·m: shape (3,) or (n, 3)."""
        times, shape = _times(t)
        return _rotate_about_z(self.torque_vector, self.omega * times).reshape((*shape, 3))

    def bearing_forces_at(self, t: Any) -> Array:
        """The two bearing forces on the shaft at time t, N: shape (2, 3) or (n, 2, 3)."""
        if self.bearing_forces is None:
            raise InputError(
                "Expected `bearing_separation` to have been given to skew_rod(), got None."
            )
        times, shape = _times(t)
        return _rotate_about_z(self.bearing_forces, self.omega * times).reshape((*shape, 2, 3))


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
    only (the rod's weight adds a constant vertical load of m g on each bearing).

    Raises
    ------
    InputError
        If the mass, half length or bearing separation is not positive, or any
        value is non-finite or in the wrong units.
    """
    m = _positive(mass, "mass", "mass")
    ell = _positive(half_length, "length", "half_length")
    a = to_si(alpha, "angle", "alpha")
    w = to_si(omega, "angular_velocity", "omega")
    d = (
        None
        if bearing_separation is None
        else _positive(bearing_separation, "length", "bearing_separation")
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
        forces = _readonly([top, -top])
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
        angular_momentum_vector=_readonly(momentum),
        torque_vector=_readonly(torque),
        bearing_force=None if d is None else magnitude / d,
        bearing_forces=forces,
    )


# ----------------------------------------------------------------- rotor loads
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
    """
    mp = _mass_properties(mp)
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
        forces = _readonly([f_a, force - f_a])
        positions = _readonly(positions)
    return RotorLoads(
        axis=_readonly(n),
        point=_readonly(p),
        omega=w,
        angular_momentum=_readonly(momentum),
        torque=_readonly(torque),
        force=_readonly(force),
        bearings=positions,
        bearing_forces=forces,
    )


# ----------------------------------------------------------------- free body
def flip_period(moments: Any, omega0: Any) -> float:
    """Period of the angular velocity ω(t) of a torque-free body, s.

    A body spun near its intermediate axis flips over twice per period (the
    tennis-racket or Dzhanibekov effect); away from that axis ω(t) wobbles with
    this period. In the principal frame ω(t) is given by Jacobi elliptic
    functions (Landau & Lifshitz, Mechanics, §37), periodic with
    ``T = 4 K(k²) / λ``, where for ``I1 < I2 < I3`` and ``L² > 2 E I2``

        ``λ² = (I3 − I2)(L² − 2 E I1) / (I1 I2 I3)``,
        ``k² = (I2 − I1)(2 E I3 − L²) / ((I3 − I2)(L² − 2 E I1))``,

    and for ``L² < 2 E I2`` the same with I1 and I3 exchanged. These are
    evaluated in exact rational arithmetic on the given floats, so the period
    keeps its accuracy as close to the separatrix as the input can express
    (where it grows like ``ln(1/(1 − k²)) / λ``), and no square underflows.

    Parameters
    ----------
    moments : the three principal moments, kg·m², in any order, with ``omega0``
        in the same principal axes; or a MassProperties, with ``omega0`` in its
        body axes.
    omega0 : (3,) angular velocity at any instant, rad/s.

    Returns
    -------
    float, s. The formula holds everywhere it is defined, and its limits elsewhere:

    * ``inf`` on the separatrix ``L² = 2 E I2``, the rotation about the
      intermediate axis included (the motion takes infinitely long to approach
      that axis);
    * for a rotation exactly about the largest or smallest axis (ω constant),
      ``2π / (ω √((I_k − I_i)(I_k − I_j) / (I_i I_j)))``: the period of the small
      wobble about it (``k² = 0``), the limit of the periods of nearby motions;
    * ``2π / |Ω|`` for a symmetric top (two equal moments I⊥, symmetry moment
      I_s), ``Ω = (I_s − I⊥) ω_s / I⊥``: the period with which ω precesses about
      the symmetry axis in the body (``k² = 0``), also for ω along that axis;
    * ``inf`` where ``λ = 0``: ω in a plane of equal moments (steady rotation
      about a transverse axis of a symmetric top, the limit ω_s → 0 of the
      above), any ω of a spherical body, and ω = 0.

    Raises
    ------
    InputError
        If a moment is not positive, the moments break the triangle inequality,
        or a value has the wrong shape or units.
    """
    inertia, omega, _ = _principal_state(moments, omega0, "moments")
    order = np.argsort(inertia, kind="stable")
    largest = float(np.abs(omega).max())
    if largest == 0:
        return math.inf
    # ω scaled by a power of two (exactly) to a largest component in [1/2, 1).
    _, exponent = math.frexp(largest)
    i1, i2, i3 = (Fraction(float(v)) for v in inertia[order])
    w1, w2, w3 = (Fraction(float(v)) / Fraction(2) ** exponent for v in omega[order])
    p1, p2, p3 = i1 * w1 * w1, i2 * w2 * w2, i3 * w3 * w3
    middle = p1 * (i1 - i2) + p3 * (i3 - i2)  # L² − 2 E I2
    if not (middle >= 0 and i3 > i2):
        # The other side of the separatrix (or a prolate body): exchange 1 and 3.
        i1, i3, p1, p3 = i3, i1, p3, p1
    lower = p2 * (i2 - i1) + p3 * (i3 - i1)  # L² − 2 E I1, ∝ λ²
    if middle == 0 or lower == 0:
        return math.inf
    rate = _sqrt_fraction((i3 - i2) * lower / (i1 * i2 * i3))
    mc = (i3 - i1) * middle / ((i3 - i2) * lower)  # 1 − k², in (0, 1]
    if mc > Fraction(1, 10**300):
        quarter = float(special.ellipkm1(float(mc)))
    else:  # K = ln(4 / √mc) + O(mc ln mc), beyond the float range of mc
        quarter = math.log(4.0) - 0.5 * (math.log(mc.numerator) - math.log(mc.denominator))
    try:
        return math.ldexp(4.0 * quarter / rate, -exponent)
    except OverflowError:
        return math.inf


def _sqrt_fraction(x: Fraction) -> float:
    """√x of a positive rational whose value may lie outside the float range."""
    shift = x.numerator.bit_length() - x.denominator.bit_length()
    shift -= shift % 2
    return math.ldexp(math.sqrt(float(x / Fraction(2) ** shift)), shift // 2)


@dataclass(frozen=True, eq=False)
class FreeSymmetricTop:
    """Torque-free motion of a symmetric top (see :func:`free_symmetric_top`). SI units.

    Attributes
    ----------
    axis : (3,) unit symmetry axis, oriented so that ω has a non-negative
        component along it; in body coordinates (for a MassProperties) or in
        the principal axes the moments were given in.
    axial_moment : I_s, the moment about the symmetry axis, kg·m².
    transverse_moment : I⊥, the two equal moments, kg·m².
    spin_rate : ω_s = ω · axis ≥ 0, rad/s (constant).
    transverse_rate : |ω⊥|, the part of ω perpendicular to the axis, rad/s (constant).
    angular_momentum : |L|, kg·m²/s.
    body_precession_rate : Ω = (I_s − I⊥) ω_s / I⊥, rad/s: the rate at which ω
        (and L) turn about the symmetry axis as seen in the body; positive in the
        sense of the spin (an oblate body, I_s > I⊥), negative against it (prolate).
    space_precession_rate : L / I⊥, rad/s: the rate at which the symmetry axis
        (and ω) turn about the fixed L in space, in the sense of L.
    body_cone_half_angle : angle between ω and the symmetry axis, rad, in [0, π/2].
    space_cone_half_angle : angle between ω and L, rad.
    nutation_angle : angle between the symmetry axis and L, rad (constant).
    """

    axis: Array
    axial_moment: float
    transverse_moment: float
    spin_rate: float
    transverse_rate: float
    angular_momentum: float
    body_precession_rate: float
    space_precession_rate: float
    body_cone_half_angle: float
    space_cone_half_angle: float
    nutation_angle: float


def free_symmetric_top(moments: Any, omega0: Any) -> FreeSymmetricTop:
    """Body and space cones of a torque-free symmetric top.

    For a body with two equal principal moments I⊥ and a third I_s about the
    symmetry axis, Euler's equations give a constant spin ω_s along the axis
    while the transverse part of ω turns about the axis, in the body, at
    ``Ω = (I_s − I⊥) ω_s / I⊥``. In space, ``ω = (L/I⊥) L̂ − Ω ê_s``: the axis
    and ω turn about the fixed L at ``L / I⊥``. ω traces the body cone (about
    the axis) in the body and the space cone (about L) in space, and the body
    cone rolls on the space cone (Landau & Lifshitz, Mechanics, §33 and §36;
    Goldstein, Classical Mechanics, §5.6; Kleppner & Kolenkow, ch. 7).

    Parameters
    ----------
    moments : three principal moments, kg·m², two of them equal (to 1e-9 of the
        trace), in any order, with ``omega0`` in the same principal axes; or a
        symmetric MassProperties, with ``omega0`` in its body axes.
    omega0 : (3,) angular velocity at any instant, rad/s.

    Returns
    -------
    FreeSymmetricTop. A spherical body (three equal moments) is taken with its
    axis along ω: no body precession, both cones of half-angle 0.

    Raises
    ------
    InputError
        If no two moments are equal, a moment is not positive, or the moments
        break the triangle inequality.
    """
    inertia, omega, axes = _principal_state(moments, omega0, "moments")
    tol = REPEATED_MOMENT_TOLERANCE * float(inertia.sum())
    pairs = [(i, j) for i, j in ((0, 1), (1, 2), (0, 2)) if abs(inertia[i] - inertia[j]) <= tol]
    if not pairs:
        raise InputError(
            "Expected `moments` to have two equal principal moments (a symmetric top), got "
            f"{_format(inertia)} kg·m²."
        )
    if len(pairs) == 3:
        k = 2
        speed = float(np.linalg.norm(omega))
        axis = omega / speed if speed > 0 else np.array([0.0, 0.0, 1.0])
    else:
        i, j = pairs[0]
        k = 3 - i - j
        axis = np.eye(3)[k]
        if omega[k] < 0:
            axis = -axis
    axial = float(inertia[k])
    transverse = float(np.delete(inertia, k).mean()) if len(pairs) < 3 else axial
    spin = float(omega @ axis)
    perpendicular = float(np.linalg.norm(omega - spin * axis))
    momentum = math.hypot(axial * spin, transverse * perpendicular)
    body_cone = math.atan2(perpendicular, spin)
    nutation = math.atan2(transverse * perpendicular, axial * spin)
    return FreeSymmetricTop(
        axis=_readonly(axes @ axis),
        axial_moment=axial,
        transverse_moment=transverse,
        spin_rate=spin,
        transverse_rate=perpendicular,
        angular_momentum=momentum,
        body_precession_rate=(axial - transverse) * spin / transverse,
        space_precession_rate=momentum / transverse,
        body_cone_half_angle=body_cone,
        space_cone_half_angle=abs(body_cone - nutation),
        nutation_angle=nutation,
    )


@dataclass(frozen=True, eq=False)
class AxisStability:
    """Stability of steady rotation about each principal axis (see :func:`axis_stability`).

    Attributes (arrays of 3, one per principal axis, in the order of ``moments``)
    ----------
    moments : principal moments, kg·m².
    axes : (3, 3) principal axes as columns (body coordinates for a
        MassProperties, the identity for moments given directly).
    spin_rate : |ω|, rad/s.
    oscillation_frequencies : angular frequency of the small wobble of ω about
        a stable axis, rad/s; 0 for the unstable axis.
    growth_rates : exponential growth rate of a small deviation from an
        unstable axis, 1/s; 0 for a stable one.
    stable : True where a small deviation stays small (linearly stable or
        neutral, as with equal moments).
    """

    moments: Array
    axes: Array
    spin_rate: float
    oscillation_frequencies: Array
    growth_rates: Array
    stable: NDArray[np.bool_]


def axis_stability(moments: Any, spin_rate: Any) -> AxisStability:
    """Linear stability of a torque-free body spinning about each principal axis.

    For a spin ω about principal axis k, with the other two axes i and j, a
    small deviation of ω obeys (linearised Euler equations)
    ``ω̈_i = −s_k ω_i``, ``s_k = ω² (I_k − I_i)(I_k − I_j) / (I_i I_j)``:
    about the largest and smallest axes ``s_k > 0`` and ω wobbles at
    ``√s_k``; about the intermediate axis ``s_k < 0`` and the deviation grows as
    ``exp(γ t)``, ``γ = ω √((I2 − I1)(I3 − I2) / (I1 I3))`` (Landau & Lifshitz,
    Mechanics, §37, problem; Goldstein, Classical Mechanics, §5.6). Equal moments
    give ``s_k = 0``: neutral (no exponential growth), reported as stable with
    frequency 0.

    Parameters
    ----------
    moments : three principal moments, kg·m², in any order; or a MassProperties
        (its principal moments, ascending, and axes).
    spin_rate : ω, rad/s; its sign does not matter.

    Returns
    -------
    AxisStability.

    Raises
    ------
    InputError
        If a moment is not positive or the moments break the triangle inequality.
    """
    inertia, _, axes = _principal_state(moments, np.zeros(3), "moments")
    w = abs(to_si(spin_rate, "angular_velocity", "spin_rate"))
    squares = np.empty(3)
    for k in range(3):
        i, j = (k + 1) % 3, (k + 2) % 3
        squares[k] = (
            w
            * w
            * (inertia[k] - inertia[i])
            * (inertia[k] - inertia[j])
            / (inertia[i] * inertia[j])
        )
    stable = squares >= 0
    stable.setflags(write=False)
    return AxisStability(
        moments=_readonly(inertia),
        axes=_readonly(axes),
        spin_rate=w,
        oscillation_frequencies=_readonly(np.sqrt(np.maximum(squares, 0.0))),
        growth_rates=_readonly(np.sqrt(np.maximum(-squares, 0.0))),
        stable=stable,
    )


# ----------------------------------------------------------------- heavy top
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
        times, shape = _times(t)
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
    mp = _mass_properties(mp)
    axial, transverse_com = _axial_and_transverse(mp)
    p = vector_to_si(pivot, "length", "pivot", (3,))
    offset = mp.center_of_mass - p
    off_axis = math.hypot(float(offset[0]), float(offset[1]))
    size = max(float(np.linalg.norm(offset)), math.sqrt(float(np.trace(mp.inertia)) / mp.mass))
    if off_axis > PHYSICAL_TOLERANCE * size:
        raise InputError(
            "Expected `pivot` on the symmetry axis (x, y of the centre of mass = "
            f"{_format(mp.center_of_mass[:2])} m), got {_format(p)} m, "
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


# ----------------------------------------------------------------- gyrocompass
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
    """
    mp = _mass_properties(mp)
    axial, transverse = _axial_and_transverse(mp)
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


# ----------------------------------------------------------- free motion
@dataclass(frozen=True)
class FreeMotion:
    """The exact torque-free motion of a body about its centre of mass.

    ω(t) from Jacobi elliptic functions and the attitude from the precession
    angle about the fixed L (see :func:`tumble.simulate` with
    ``method="exact"``), at any times, without stepping.

    Attributes
    ----------
    mass_properties : the body; ``omega0`` (3,) rad/s in its body axes;
    ``attitude0`` (4,) ``[w, x, y, z]`` body → space at t = 0.
    """

    mass_properties: MassProperties
    omega0: Array
    attitude0: Array

    def at(self, t: Any) -> tuple[Array, Array]:
        """(ω, q) at time(s) ``t`` (s, a number or an array of any order):
        ω in body axes, rad/s, and the attitude quaternion ``[w, x, y, z]``,
        body → space; shapes (3,), (4,) for a number, (n, 3), (n, 4) for n times."""
        from tumble.simulation import exact_solution

        scalar = np.ndim(t) == 0
        times = np.atleast_1d(np.asarray(t, dtype=float))
        if times.ndim != 1 or not np.all(np.isfinite(times)):
            raise InputError(f"Expected `t` to be finite times in s, got {t!r}.")
        omega, quaternion = exact_solution(self.mass_properties, self.omega0, self.attitude0, times)
        if scalar:
            return omega[0], quaternion[0]
        return omega, quaternion


def free_motion(mp: MassProperties, omega0: Any, attitude0: Any = None) -> FreeMotion:
    """The exact torque-free motion of ``mp`` from ω0 (body axes, rad/s) and
    ``attitude0`` (a quaternion ``[w, x, y, z]`` body → space or a scipy
    Rotation; default the identity). Valid for any inertia, on both sides of
    the separatrix and next to it (Landau & Lifshitz, Mechanics §37)."""
    from tumble.simulation import _attitude

    if not isinstance(mp, MassProperties):
        raise InputError(f"Expected `mp` to be a MassProperties, got {type(mp).__name__}.")
    omega = vector_to_si(omega0, "angular_velocity", "omega0")
    return FreeMotion(mp, omega, _attitude(attitude0))
