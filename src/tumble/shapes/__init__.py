"""The catalogue of primitive solids: closed-form mass properties, volumes, boxes
and surfaces.

The closed forms are in ``tumble.shapes.closed_forms`` (re-exported here:
``tumble.shapes.box(mass, size)``), the surfaces to draw them with in
``tumble.shapes.surfaces``. :data:`SHAPE_KINDS` is the catalogue of them, each a
:class:`ShapeKind` (its name in files, its dimensions, its volume, the box around
it and its surface), and a :class:`Shape` one of them of given dimensions, at a
mass or a density: the scenario files' ``[body] shape``, the robot files'
primitives, ``tumble inertia`` and the report's drawings read the catalogue.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, unknown_choice
from tumble.massprops import MassProperties
from tumble.shapes import surfaces
from tumble.shapes.closed_forms import (
    box,
    capsule,
    ellipsoid,
    hollow_cylinder,
    hollow_sphere,
    regular_tetrahedron,
    solid_cone,
    solid_cylinder,
    solid_sphere,
    spherical_shell,
    thin_disk,
    thin_ring,
    thin_rod,
    torus,
)
from tumble.shapes.surfaces import Mesh
from tumble.units import to_si, vector_to_si

__all__ = [
    "SHAPE_KINDS",
    "Shape",
    "ShapeKind",
    "box",
    "capsule",
    "ellipsoid",
    "hollow_cylinder",
    "hollow_sphere",
    "regular_tetrahedron",
    "shape_kind",
    "solid_cone",
    "solid_cylinder",
    "solid_sphere",
    "spherical_shell",
    "thin_disk",
    "thin_ring",
    "thin_rod",
    "torus",
]


# ------------------------------------------------------------------ the catalogue
@dataclass(frozen=True)
class ShapeKind:
    """One primitive of the catalogue: its ``name`` in files and on the command line,
    the closed form ``function(mass, **dimensions)`` above, the names of its
    ``dimensions`` (its keyword arguments, m), its ``volume`` (m³, of the SI
    dimensions; None for an idealised thin body, which has none) and the
    ``box`` around it in its own frame (the lowest and highest corners, m, from
    its centre of mass) and its ``surface``, a triangle mesh to draw it with
    (``tumble.shapes.surfaces``), placed like the closed form."""

    name: str
    function: Callable[..., MassProperties]
    dimensions: tuple[str, ...]
    volume: Callable[..., float] | None
    box: Callable[..., tuple[tuple[float, ...], tuple[float, ...]]]
    surface: Callable[..., Mesh]


def _centred(x: float, y: float, z: float) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The box of half-edges (x, y, z) about the centre of mass."""
    return (-x, -y, -z), (x, y, z)


#: Every primitive by its name, in the order listings show them.
SHAPE_KINDS: dict[str, ShapeKind] = {
    kind.name: kind
    for kind in (
        ShapeKind(
            "box",
            box,
            ("size",),
            lambda size: size[0] * size[1] * size[2],
            lambda size: _centred(size[0] / 2, size[1] / 2, size[2] / 2),
            surfaces.box,
        ),
        ShapeKind(
            "solid-cylinder",
            solid_cylinder,
            ("radius", "height"),
            lambda radius, height: math.pi * radius**2 * height,
            lambda radius, height: _centred(radius, radius, height / 2),
            surfaces.cylinder,
        ),
        ShapeKind(
            "hollow-cylinder",
            hollow_cylinder,
            ("inner_radius", "outer_radius", "height"),
            lambda inner_radius, outer_radius, height: (
                math.pi * (outer_radius**2 - inner_radius**2) * height
            ),
            lambda inner_radius, outer_radius, height: _centred(
                outer_radius, outer_radius, height / 2
            ),
            surfaces.tube,
        ),
        ShapeKind(
            "solid-sphere",
            solid_sphere,
            ("radius",),
            lambda radius: 4 / 3 * math.pi * radius**3,
            lambda radius: _centred(radius, radius, radius),
            surfaces.sphere,
        ),
        ShapeKind(
            "spherical-shell",
            spherical_shell,
            ("radius",),
            None,
            lambda radius: _centred(radius, radius, radius),
            surfaces.sphere,
        ),
        ShapeKind(
            "hollow-sphere",
            hollow_sphere,
            ("inner_radius", "outer_radius"),
            lambda inner_radius, outer_radius: (
                4 / 3 * math.pi * (outer_radius**3 - inner_radius**3)
            ),
            lambda inner_radius, outer_radius: _centred(outer_radius, outer_radius, outer_radius),
            surfaces.hollow_sphere,
        ),
        ShapeKind(
            # The base a quarter of the height below the centre of mass, the apex above.
            "solid-cone",
            solid_cone,
            ("radius", "height"),
            lambda radius, height: math.pi * radius**2 * height / 3,
            lambda radius, height: (
                (-radius, -radius, -height / 4),
                (radius, radius, 0.75 * height),
            ),
            surfaces.cone,
        ),
        ShapeKind(
            "thin-rod",
            thin_rod,
            ("length",),
            None,
            lambda length: _centred(0.0, 0.0, length / 2),
            lambda length: surfaces.cylinder(length / 80.0, length, sections=12),
        ),
        ShapeKind(
            "thin-disk",
            thin_disk,
            ("radius",),
            None,
            lambda radius: _centred(radius, radius, 0.0),
            lambda radius: surfaces.cylinder(radius, radius / 40.0),
        ),
        ShapeKind(
            "thin-ring",
            thin_ring,
            ("radius",),
            None,
            lambda radius: _centred(radius, radius, 0.0),
            lambda radius: surfaces.torus(radius, radius / 30.0, tube_sections=8),
        ),
        ShapeKind(
            "ellipsoid",
            ellipsoid,
            ("semi_axes",),
            lambda semi_axes: 4 / 3 * math.pi * semi_axes[0] * semi_axes[1] * semi_axes[2],
            lambda semi_axes: _centred(*semi_axes),
            surfaces.ellipsoid,
        ),
        ShapeKind(
            "torus",
            torus,
            ("major_radius", "minor_radius"),
            lambda major_radius, minor_radius: 2 * math.pi**2 * major_radius * minor_radius**2,
            lambda major_radius, minor_radius: _centred(
                major_radius + minor_radius, major_radius + minor_radius, minor_radius
            ),
            surfaces.torus,
        ),
        ShapeKind(
            "capsule",
            capsule,
            ("radius", "cylinder_height"),
            lambda radius, cylinder_height: (
                math.pi * radius**2 * (cylinder_height + 4 * radius / 3)
            ),
            lambda radius, cylinder_height: _centred(radius, radius, cylinder_height / 2 + radius),
            surfaces.capsule,
        ),
        ShapeKind(
            # Vertices (a / √8)(±1, ±1, ±1) with an even number of minus signs.
            "regular-tetrahedron",
            regular_tetrahedron,
            ("edge",),
            lambda edge: edge**3 / (6 * math.sqrt(2)),
            lambda edge: _centred(*(edge / math.sqrt(8),) * 3),
            surfaces.tetrahedron,
        ),
    )
}


def shape_kind(name: str) -> ShapeKind:
    """The primitive called ``name`` (``-`` or ``_`` between words, any case).

    Raises
    ------
    InputError
        Another name; the message lists the catalogue and suggests the nearest.
    """
    key = str(name).strip().lower().replace("_", "-")
    if key not in SHAPE_KINDS:
        raise unknown_choice(name, list(SHAPE_KINDS), "a shape")
    return SHAPE_KINDS[key]


@dataclass(frozen=True)
class Shape:
    """A primitive solid of given dimensions, centred on its centre of mass (its
    symmetry axis along z, as its closed form in this module says).

    ``kind`` is its :class:`ShapeKind`; ``dimensions`` its dimensions by name, in SI
    (m; a triple for ``size`` and ``semi_axes``). Make one with :meth:`of`.

    Examples
    --------
    >>> import tumble as tb
    >>> can = tb.shapes.Shape.of("solid-cylinder", radius="3 cm", height="12 cm")
    >>> print(f"{can.volume * 1e6:.2f} cm³, {can.at_density('1000 kg/m^3').mass:.4f} kg")
    339.29 cm³, 0.3393 kg
    """

    kind: ShapeKind
    dimensions: dict[str, Any]

    @classmethod
    def of(cls, kind: str, **dimensions: Any) -> Shape:
        """The primitive ``kind`` (a name of :data:`SHAPE_KINDS`) of ``dimensions``
        (numbers in m, or quantities: ``radius="3 cm"``).

        Raises
        ------
        InputError
            An unknown kind, a dimension it does not take or one it lacks, a value
            that is not a length or not positive (as its closed form refuses it).
        """
        primitive = shape_kind(kind)
        accepted = ", ".join(f"`{name}`" for name in primitive.dimensions)
        for name in dimensions:
            if name not in primitive.dimensions:
                raise InputError(f"Expected only {accepted} for a {primitive.name}, got `{name}`.")
        missing = [name for name in primitive.dimensions if name not in dimensions]
        if missing:
            raise InputError(
                f"Expected `{missing[0]}` for a {primitive.name} (it takes {accepted})."
            )
        values = {
            name: tuple(float(v) for v in vector_to_si(value, "length", name, (3,)))
            if name in ("size", "semi_axes")
            else to_si(value, "length", name)
            for name, value in dimensions.items()
        }
        primitive.function(1.0, **values)  # its closed form refuses what it cannot hold
        return cls(primitive, values)

    @property
    def volume(self) -> float:
        """Its volume, m³.

        Raises
        ------
        InputError
            An idealised thin body (a rod, a disk, a ring, a shell), which has none.
        """
        if self.kind.volume is None:
            raise InputError(
                f"Expected a solid with a volume, got a {self.kind.name} (an idealised thin "
                "body: give its mass)."
            )
        return float(self.kind.volume(**self.dimensions))

    def at_mass(self, mass: Any) -> MassProperties:
        """Its mass properties at ``mass`` (kg or a quantity), about its centre of mass."""
        return self.kind.function(mass, **self.dimensions)

    def at_density(self, density: Any) -> MassProperties:
        """Its mass properties at a uniform ``density`` (kg/m³ or a quantity).

        Raises
        ------
        InputError
            A density that is not positive, or an idealised thin body (no volume).
        """
        rho = to_si(density, "density", "density")
        if not rho > 0:
            raise InputError(f"Expected `density` > 0 kg/m³, got {rho!r}.")
        return self.at_mass(rho * self.volume)

    @property
    def bounding_box(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The lowest and highest corners (3,) of the box around it in its own frame,
        m, from its centre of mass."""
        low, high = self.kind.box(**self.dimensions)
        return np.array(low, dtype=float), np.array(high, dtype=float)

    def surface(self) -> Mesh:
        """A triangle mesh of its surface, m, centred like it: vertices (n, 3) and
        faces (m, 3). An idealised thin body is drawn with a small thickness."""
        return self.kind.surface(**self.dimensions)
