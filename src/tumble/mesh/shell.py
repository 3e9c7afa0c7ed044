"""Mass properties of a thin shell over a triangle mesh: sheet metal, thin-walled
parts, open surfaces (:func:`tumble.mesh.from_mesh` with ``shell_thickness``).

The mass lies on the surface with a uniform surface density (``density ×
thickness``, or ``mass`` over the area): the limit of a wall whose thickness is
small against the part. A wall of finite thickness t differs by O(t / size)
(its inner and outer faces, its edges). The surface need not be closed or
consistently wound.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from tumble.core.polyhedron import shell_integrals
from tumble.errors import InputError, MeshError
from tumble.massprops import MassProperties
from tumble.mesh.validation import bounds_and_centre, check_arrays, scaled_inertia

__all__ = ["shell_mass_properties"]


def shell_mass_properties(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    thickness: float,
    *,
    density: float | None = None,
    mass: float | None = None,
    label: str = "mesh",
) -> MassProperties:
    """Mass properties of the surface of ``faces`` as a shell of ``thickness``
    (m, > 0): exactly one of ``density`` (kg/m³, of the wall's material) and
    ``mass`` (kg). ``vertices`` (n, 3) in m. The centre of mass is in the
    mesh's coordinates, the inertia about it in its axes.

    Raises
    ------
    MeshError
        No triangles, indices out of range, non-finite vertices, zero area.
    """
    check_arrays(vertices, faces, label)
    corner_low, corner_high, reference = bounds_and_centre(vertices)
    size = float(np.max(corner_high - corner_low))
    if not size > 0:
        raise MeshError(f"Expected {label} to have a surface, got all its vertices at one point.")
    # In units of the mesh's size about a point near it, as the solid's integrals.
    integrals = shell_integrals((vertices - reference) / size, faces, np.zeros(3))
    area = integrals[0]
    if not area > 0:
        raise MeshError(f"Expected {label} to have a surface, got zero area.")
    scale = np.float64(size)  # numpy powers: inf for a huge mesh, not an OverflowError
    with np.errstate(over="ignore"):
        total = float(mass if mass is not None else density * thickness * area * scale**2)  # type: ignore[operator]
    if not 0 < total < np.inf:
        raise InputError(
            f"Expected the mass of the shell of {label} (density × thickness × area) within "
            f"float range, got {total!r} kg."
        )
    centroid = integrals[1:4] / area
    sxx, syy, szz, sxy, sxz, syz = integrals[4:10]
    second = np.array([[sxx, sxy, sxz], [sxy, syy, syz], [sxz, syz, szz]])
    second -= area * np.outer(centroid, centroid)
    inertia = scaled_inertia(total, size, (np.trace(second) * np.eye(3) - second) / area, label)
    return MassProperties(total, reference + size * centroid, inertia)
