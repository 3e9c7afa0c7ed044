"""Torque-free bodies: the flip period, the free symmetric top's cones, the
stability of steady spins, and the exact motion at any time."""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import special

from tumble.errors import InputError
from tumble.massprops import (
    REPEATED_MOMENT_TOLERANCE,
    MassProperties,
    as_mass_properties,
    readonly,
)
from tumble.theory.common import (
    format_values,
    principal_state,
)
from tumble.units import to_si, vector_to_si

__all__ = [
    "AxisStability",
    "FreeMotion",
    "FreeSymmetricTop",
    "axis_stability",
    "flip_period",
    "free_motion",
    "free_symmetric_top",
]

Array = NDArray[np.float64]


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

    Examples
    --------
    A body of principal moments (1, 2, 3) kg·m² spun at 1 rad/s near its
    intermediate axis flips over twice in each period of ω(t):

    >>> import tumble as tb
    >>> print(f"{tb.theory.flip_period([1.0, 2.0, 3.0], [0.1, 1.0, 0.1]):.6f} s")
    22.996263 s

    Exactly about the intermediate axis it never leaves (the separatrix):

    >>> tb.theory.flip_period([1.0, 2.0, 3.0], [0.0, 1.0, 0.0])
    inf

    About the largest axis, the period of the small wobble,
    ``2π / (ω √((I3 − I1)(I3 − I2) / (I1 I2)))`` = 2π s here:

    >>> print(f"{tb.theory.flip_period([1.0, 2.0, 3.0], [0.0, 0.0, 1.0]):.6f} s")
    6.283185 s
    """
    inertia, omega, _ = principal_state(moments, omega0, "moments")
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
    if rate == 0.0:  # λ below the float range: the period lies above it
        return math.inf
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

    Examples
    --------
    An oblate top (I_s = 2 I⊥) spinning at 1 rad/s with a small wobble: in
    the body, ω turns about the axis at ``(I_s − I⊥) ω_s / I⊥ = 1 rad/s``;
    in space, the axis turns about L at ``L / I⊥``.

    >>> import tumble as tb
    >>> top = tb.theory.free_symmetric_top([1.0, 1.0, 2.0], [0.1, 0.0, 1.0])
    >>> print(f"{top.body_precession_rate:.6f} {top.space_precession_rate:.6f} rad/s")
    1.000000 2.002498 rad/s
    >>> print(f"nutation {top.nutation_angle:.6f}, body cone {top.body_cone_half_angle:.6f} rad")
    nutation 0.049958, body cone 0.099669 rad
    """
    inertia, omega, axes = principal_state(moments, omega0, "moments")
    tol = REPEATED_MOMENT_TOLERANCE * float(inertia.sum())
    pairs = [(i, j) for i, j in ((0, 1), (1, 2), (0, 2)) if abs(inertia[i] - inertia[j]) <= tol]
    if not pairs:
        raise InputError(
            "Expected `moments` to have two equal principal moments (a symmetric top), got "
            f"{format_values(inertia)} kg·m²."
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
        axis=readonly(axes @ axis),
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

    The attributes are arrays of 3, one per principal axis, in the order of ``moments``.

    Attributes
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

    Examples
    --------
    The intermediate-axis theorem: spins about the smallest and largest axes
    are stable, about the intermediate one a deviation grows as exp(γ t):

    >>> import tumble as tb
    >>> stability = tb.theory.axis_stability([1.0, 2.0, 3.0], spin_rate=1.0)
    >>> stability.stable.tolist()
    [True, False, True]
    >>> print(f"γ = {stability.growth_rates[1]:.6f} 1/s")  # √((2 − 1)(3 − 2) / (1 × 3))
    γ = 0.577350 1/s
    >>> print(", ".join(f"{f:.6f}" for f in stability.oscillation_frequencies))
    0.577350, 0.000000, 1.000000
    """
    inertia, _, axes = principal_state(moments, np.zeros(3), "moments")
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
        moments=readonly(inertia),
        axes=readonly(axes),
        spin_rate=w,
        oscillation_frequencies=readonly(np.sqrt(np.maximum(squares, 0.0))),
        growth_rates=readonly(np.sqrt(np.maximum(-squares, 0.0))),
        stable=stable,
    )


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
        from tumble.theory.motions import exact_solution

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
    the separatrix and next to it (Landau & Lifshitz, Mechanics §37).

    Examples
    --------
    Half a flip period later the body has turned over (ω reversed along the
    intermediate axis); a whole period later ω is back where it started:

    >>> import numpy as np
    >>> import tumble as tb
    >>> body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    >>> motion = tb.theory.free_motion(body, [0.1, 1.0, 0.1])
    >>> period = tb.theory.flip_period(body, [0.1, 1.0, 0.1])
    >>> omega, quaternion = motion.at([0.0, period / 2, period])
    >>> np.allclose(omega, [[0.1, 1.0, 0.1], [-0.1, -1.0, 0.1], [0.1, 1.0, 0.1]])
    True
    >>> np.allclose(np.linalg.norm(quaternion, axis=1), 1.0)
    True
    """
    from tumble.kinematics import as_attitude

    mp = as_mass_properties(mp)
    omega = vector_to_si(omega0, "angular_velocity", "omega0")
    return FreeMotion(mp, omega, as_attitude(attitude0))
