"""Closed-form mass properties of uniform solids and idealised thin bodies.

Every shape is centred on its centre of mass (``center_of_mass == 0``) and has
its symmetry axis along body z unless stated. Dimensions are full edges,
radii or lengths in metres (or quantities such as ``"3 cm"``); masses in kg (or
``"250 g"``). The formulas are the standard results of integrating
``∫ (r² δ_ij − x_i x_j) dm`` over each body (e.g. Meriam & Kraige, Engineering
Mechanics: Dynamics, Appendix B); the tests re-derive each with sympy.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from tumble.errors import InputError
from tumble.massprops import MassProperties
from tumble.units import to_si, vector_to_si

__all__ = [
    "box",
    "capsule",
    "ellipsoid",
    "hollow_cylinder",
    "hollow_sphere",
    "regular_tetrahedron",
    "solid_cone",
    "solid_cylinder",
    "solid_sphere",
    "spherical_shell",
    "thin_disk",
    "thin_ring",
    "thin_rod",
    "torus",
]

_ORIGIN = np.zeros(3)


def _mass(mass: Any) -> float:
    value = to_si(mass, "mass", "mass")
    if value <= 0:
        raise InputError(f"Expected `mass` > 0 kg, got {value!r}.")
    return value


def _positive_length(value: Any, name: str) -> float:
    length = to_si(value, "length", name)
    if length <= 0:
        raise InputError(f"Expected `{name}` > 0 m, got {length!r}.")
    return length


#: Below this a float64 keeps fewer digits (subnormal), down to 0: a moment there
#: would be silently wrong, or zero for a body of positive size.
_SMALLEST_MOMENT = float(np.finfo(float).tiny)


def _body(mass: float, ixx: float, iyy: float, izz: float) -> MassProperties:
    """The solid's MassProperties from its closed-form moments about its centre of
    mass, refused where a moment of a body of positive size underflows float64
    (a thin rod's axial moment is exactly zero, and stays valid)."""
    moments = [ixx, iyy, izz]
    if not all(math.isfinite(moment) for moment in moments):
        raise InputError(
            f"Expected moments of inertia within float64's range, got "
            f"{[float(f'{m:.3g}') for m in moments]} kg·m² for a mass of {mass:.3g} kg: the body "
            "is too heavy or too large for SI in float64."
        )
    if any(0 < abs(moment) < _SMALLEST_MOMENT for moment in moments) or not any(moments):
        raise InputError(
            f"Expected moments of inertia of at least {_SMALLEST_MOMENT:.3g} kg·m², float64's "
            f"smallest full-precision number, got {[float(f'{m:.3g}') for m in moments]} for a "
            f"mass of {mass:.3g} kg: the body is too light or too small for SI in float64."
        )
    return MassProperties(mass, _ORIGIN, np.diag(moments))


def box(mass: Any, size: Any) -> MassProperties:
    """Uniform rectangular box with full edges ``size = (a, b, c)`` along body x, y, z.

    ``I_xx = m (b² + c²) / 12`` and cyclic.

    Examples
    --------
    >>> import numpy as np
    >>> import tumble as tb
    >>> brick = tb.shapes.box(1.2, "10, 20, 30 cm")
    >>> np.allclose(np.diag(brick.inertia), 1.2 * np.array([0.13, 0.10, 0.05]) / 12)
    True
    """
    m = _mass(mass)
    # Python floats: a product beyond float64's range is inf, refused below, with no
    # numpy overflow warning printed before the refusal.
    a, b, c = (float(edge) for edge in vector_to_si(size, "length", "size", (3,)))
    for name, edge in zip(("size[0]", "size[1]", "size[2]"), (a, b, c), strict=True):
        edge = float(edge)
        if edge <= 0:
            raise InputError(f"Expected `{name}` > 0 m, got {edge!r}.")
    return _body(m, m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12)


def solid_cylinder(mass: Any, radius: Any, height: Any) -> MassProperties:
    """Uniform solid cylinder, axis along body z.

    ``I_zz = m r² / 2``, ``I_xx = I_yy = m (3 r² + h²) / 12``.

    Examples
    --------
    A flat puck has its largest moment about its axis:

    >>> import tumble as tb
    >>> puck = tb.shapes.solid_cylinder("250 g", "3 cm", "1 cm")
    >>> print(f"I_zz = {puck.inertia[2, 2]:.4e}, I_xx = {puck.inertia[0, 0]:.4e} kg·m²")
    I_zz = 1.1250e-04, I_xx = 5.8333e-05 kg·m²
    """
    m = _mass(mass)
    r = _positive_length(radius, "radius")
    h = _positive_length(height, "height")
    transverse = m * (3 * r * r + h * h) / 12
    return _body(m, transverse, transverse, m * r * r / 2)


def hollow_cylinder(mass: Any, inner_radius: Any, outer_radius: Any, height: Any) -> MassProperties:
    """Uniform thick-walled tube, axis along body z, ``0 <= inner_radius <= outer_radius``.

    ``I_zz = m (r1² + r2²) / 2``, ``I_xx = I_yy = m (3 (r1² + r2²) + h²) / 12``.
    ``inner_radius == outer_radius`` is the thin-walled tube.
    """
    m = _mass(mass)
    r1 = to_si(inner_radius, "length", "inner_radius")
    r2 = _positive_length(outer_radius, "outer_radius")
    h = _positive_length(height, "height")
    if not 0 <= r1 <= r2:
        raise InputError(f"Expected 0 <= `inner_radius` <= `outer_radius` = {r2!r} m, got {r1!r}.")
    radial = r1 * r1 + r2 * r2
    transverse = m * (3 * radial + h * h) / 12
    return _body(m, transverse, transverse, m * radial / 2)


def solid_sphere(mass: Any, radius: Any) -> MassProperties:
    """Uniform solid ball: ``I = 2 m r² / 5`` about every axis.

    Examples
    --------
    >>> import tumble as tb
    >>> ball = tb.shapes.solid_sphere("2 kg", "10 cm")
    >>> print(f"{ball.inertia[0, 0]:.6f} kg·m²")  # 2/5 × 2 kg × (0.1 m)²
    0.008000 kg·m²
    """
    m = _mass(mass)
    r = _positive_length(radius, "radius")
    moment = 2 * m * r * r / 5
    return _body(m, moment, moment, moment)


def spherical_shell(mass: Any, radius: Any) -> MassProperties:
    """Thin spherical shell (mass on the surface): ``I = 2 m r² / 3`` about every axis."""
    m = _mass(mass)
    r = _positive_length(radius, "radius")
    moment = 2 * m * r * r / 3
    return _body(m, moment, moment, moment)


def hollow_sphere(mass: Any, inner_radius: Any, outer_radius: Any) -> MassProperties:
    """Uniform thick spherical shell, ``0 <= inner_radius <= outer_radius``.

    ``I = (2 m / 5) (r2⁵ − r1⁵) / (r2³ − r1³)``, evaluated as the ratio of the
    quotient polynomials so that a thin shell (``r1 → r2``) does not cancel; it
    tends to ``2 m r² / 3``.

    Examples
    --------
    From a solid ball (``r1 = 0``, ``2 m r² / 5``) to a thin shell (``r1 = r2``, ``2 m r² / 3``):

    >>> import tumble as tb
    >>> for inner in (0.0, 0.05, 0.1):
    ...     shell = tb.shapes.hollow_sphere(1.0, inner, 0.1)
    ...     print(f"{inner:.2f} m: {shell.inertia[0, 0]:.6f} kg·m²")
    0.00 m: 0.004000 kg·m²
    0.05 m: 0.004429 kg·m²
    0.10 m: 0.006667 kg·m²
    """
    m = _mass(mass)
    r1 = to_si(inner_radius, "length", "inner_radius")
    r2 = _positive_length(outer_radius, "outer_radius")
    if not 0 <= r1 <= r2:
        raise InputError(f"Expected 0 <= `inner_radius` <= `outer_radius` = {r2!r} m, got {r1!r}.")
    # (r2⁵ − r1⁵) / (r2³ − r1³) without the cancellation of a thin shell, and in
    # the ratio t = r1 / r2 so that no power leaves float64's range on the way.
    t = r1 / r2
    moment = 2 * m * r2 * r2 * (1 + t + t * t + t**3 + t**4) / (5 * (1 + t + t * t))
    return _body(m, moment, moment, moment)


def solid_cone(mass: Any, radius: Any, height: Any) -> MassProperties:
    """Uniform right circular cone, axis along body z, apex towards +z.

    The body origin is the centre of mass, a quarter of the height above the
    base: the base is at ``z = −h/4`` and the apex at ``z = 3h/4``.
    ``I_zz = 3 m r² / 10``, ``I_xx = I_yy = m (3 r² / 20 + 3 h² / 80)``.
    """
    m = _mass(mass)
    r = _positive_length(radius, "radius")
    h = _positive_length(height, "height")
    transverse = m * (3 * r * r / 20 + 3 * h * h / 80)
    return _body(m, transverse, transverse, 3 * m * r * r / 10)


def thin_rod(mass: Any, length: Any) -> MassProperties:
    """Thin uniform rod along body z: ``I_xx = I_yy = m L² / 12``, ``I_zz = 0``.

    The zero moment is exact for the idealisation; such a body has mass
    properties but cannot be simulated on its own.

    Examples
    --------
    About one end the moment is ``m L² / 3`` (parallel-axis theorem):

    >>> import tumble as tb
    >>> rod = tb.shapes.thin_rod(0.6, "1 m")
    >>> print(f"{rod.inertia[0, 0]:.4f} {rod.inertia_about([0, 0, 0.5])[0, 0]:.4f} kg·m²")
    0.0500 0.2000 kg·m²
    """
    m = _mass(mass)
    length_si = _positive_length(length, "length")
    transverse = m * length_si * length_si / 12
    return _body(m, transverse, transverse, 0.0)


def thin_disk(mass: Any, radius: Any) -> MassProperties:
    """Flat uniform disk in the body xy plane: ``I_zz = m r² / 2``, ``I_xx = I_yy = m r² / 4``.

    Examples
    --------
    A flat body obeys the perpendicular-axis theorem ``I_zz = I_xx + I_yy``:

    >>> import tumble as tb
    >>> disk = tb.shapes.thin_disk(1.0, 0.2)
    >>> ixx, iyy, izz = disk.inertia.diagonal()
    >>> print(f"{izz:.4f} = {ixx:.4f} + {iyy:.4f}")
    0.0200 = 0.0100 + 0.0100
    """
    m = _mass(mass)
    r = _positive_length(radius, "radius")
    return _body(m, m * r * r / 4, m * r * r / 4, m * r * r / 2)


def thin_ring(mass: Any, radius: Any) -> MassProperties:
    """Thin hoop in the body xy plane: ``I_zz = m r²``, ``I_xx = I_yy = m r² / 2``."""
    m = _mass(mass)
    r = _positive_length(radius, "radius")
    return _body(m, m * r * r / 2, m * r * r / 2, m * r * r)


def ellipsoid(mass: Any, semi_axes: Any) -> MassProperties:
    """Uniform solid ellipsoid with semi-axes ``(a, b, c)`` along body x, y, z.

    ``I_xx = m (b² + c²) / 5`` and cyclic.
    """
    m = _mass(mass)
    a, b, c = (float(axis) for axis in vector_to_si(semi_axes, "length", "semi_axes", (3,)))
    for name, axis in zip(("semi_axes[0]", "semi_axes[1]", "semi_axes[2]"), (a, b, c), strict=True):
        axis = float(axis)
        if axis <= 0:
            raise InputError(f"Expected `{name}` > 0 m, got {axis!r}.")
    return _body(m, m * (b * b + c * c) / 5, m * (a * a + c * c) / 5, m * (a * a + b * b) / 5)


def torus(mass: Any, major_radius: Any, minor_radius: Any) -> MassProperties:
    """Uniform solid torus, symmetry axis along body z, ``0 < minor_radius <= major_radius``.

    ``major_radius`` R is the radius of the tube's centre circle, ``minor_radius``
    r the radius of the tube. ``I_zz = m (R² + 3 r² / 4)``,
    ``I_xx = I_yy = m (R² / 2 + 5 r² / 8)``.
    """
    m = _mass(mass)
    big = _positive_length(major_radius, "major_radius")
    small = _positive_length(minor_radius, "minor_radius")
    if small > big:
        raise InputError(
            f"Expected `minor_radius` <= `major_radius` = {big!r} m (a self-intersecting "
            f"torus has no single solid), got {small!r}."
        )
    transverse = m * (big * big / 2 + 5 * small * small / 8)
    return _body(m, transverse, transverse, m * (big * big + 3 * small * small / 4))


def capsule(mass: Any, radius: Any, cylinder_height: Any) -> MassProperties:
    """Uniform capsule: a cylinder of height h capped by two solid hemispheres.

    Axis along body z; total length ``h + 2 r``; ``cylinder_height`` may be 0
    (a sphere). With ``m_c`` and ``m_s`` the masses of the cylinder and of the
    two caps together (in proportion to their volumes):
    ``I_zz = m_c r² / 2 + 2 m_s r² / 5``,
    ``I_xx = m_c (3 r² + h²) / 12 + m_s (2 r² / 5 + h² / 4 + 3 h r / 8)``.
    """
    m = _mass(mass)
    r = _positive_length(radius, "radius")
    h = to_si(cylinder_height, "length", "cylinder_height")
    if h < 0:
        raise InputError(f"Expected `cylinder_height` >= 0 m, got {h!r}.")
    # The masses in proportion to the volumes π r² h and 4 π r³ / 3, divided by
    # π r² first: no power of r leaves float64's range on the way.
    m_cylinder = m * h / (h + 4 * r / 3)
    m_caps = m - m_cylinder
    axial = m_cylinder * r * r / 2 + 2 * m_caps * r * r / 5
    transverse = m_cylinder * (3 * r * r + h * h) / 12 + m_caps * (
        2 * r * r / 5 + h * h / 4 + 3 * h * r / 8
    )
    return _body(m, transverse, transverse, axial)


def regular_tetrahedron(mass: Any, edge: Any) -> MassProperties:
    """Uniform regular tetrahedron of edge a, centred: isotropic, ``I = m a² / 20``.

    Orientation does not change an isotropic tensor; for meshes, its vertices
    are ``(a / √8) (±1, ±1, ±1)`` with an even number of minus signs.
    """
    m = _mass(mass)
    a = _positive_length(edge, "edge")
    moment = m * a * a / 20
    return _body(m, moment, moment, moment)
