"""Mass properties of a solid bounded by a closed triangle mesh.

Files are read with trimesh (STL, OBJ, PLY, GLB/glTF, OFF, ...); the volume
integrals are tumble's own compiled kernel, :func:`tumble.core.polyhedron.mesh_integrals`,
which is exact for the polyhedron (Tonon 2004, via the divergence theorem).

Before integrating, the mesh is checked, because the integrals of a mesh that
does not bound a solid are meaningless rather than approximately right:

* vertices with bit-identical coordinates are merged (STL files repeat them)
  and triangles that then have a repeated corner (zero area) are dropped;
  vertices that differ by round-off are not merged, and show as holes;
* every edge must be shared by exactly two triangles (watertight and manifold);
* the two triangles of every edge must traverse it in opposite directions
  (consistent winding);
* the signed volume must be non-zero; a negative one (an inside-out mesh, all
  normals inward) is reversed with a :class:`MeshOrientationWarning`;
* separate parts must all be wound the same way, except inward-wound cavities
  nested inside a part; overlapping parts are added (their overlap counts twice).
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core.polyhedron import mesh_integrals
from tumble.core.topology import (
    bounds_and_mean,
    count_nonfinite_rows,
    directed_edge_keys,
    edge_defects,
    face_components,
    index_range,
    merge_by_key,
    renumber_faces,
)
from tumble.errors import InputError, MeshError
from tumble.massprops import MassProperties
from tumble.units import length_scale, to_si

__all__ = ["MeshOrientationWarning", "from_mesh"]

#: A mesh whose |volume| is below this fraction of (surface area × largest
#: extent) encloses nothing: the volume of a flat or self-cancelling surface is
#: round-off, at most about 1e-16 · √n_triangles of that product. A plate of
#: thickness t has a ratio t / (2 · length), so only plates thinner than
#: 2e-9 of their length are refused.
ZERO_VOLUME_FRACTION = 1e-9


class MeshOrientationWarning(UserWarning):
    """An inside-out mesh (inward normals) was reversed before integrating."""


def from_mesh(
    mesh: Any, density: Any = None, mass: Any = None, units: Any = None
) -> MassProperties:
    """Mass properties of the uniform solid bounded by a closed triangle mesh.

    Parameters
    ----------
    mesh : path to a mesh file (anything trimesh reads: STL, OBJ, PLY, GLB, ...),
        or a ``trimesh.Trimesh`` / ``trimesh.Scene``. Body coordinates are the
        mesh's own coordinates.
    density : uniform density, kg/m³ (or e.g. ``"2700 kg/m^3"``). Give exactly
        one of ``density`` and ``mass``.
    mass : total mass, kg (or e.g. ``"1.2 kg"``); the density follows from the volume.
    units : length unit of the mesh coordinates, e.g. ``"mm"`` for most CAD
        files. Default: the unit the file declares (glTF/GLB may), else metres;
        given, it overrides what the file declares.

    Returns
    -------
    MassProperties, with the centre of mass in the mesh's coordinates (m) and
    the inertia about it in the mesh's axes.

    Raises
    ------
    InputError
        Unreadable file, both or neither of density and mass, non-positive
        density or mass, a unit that is not a length.
    MeshError
        No triangles, non-finite vertices, holes (the message counts the
        boundary edges), edges shared by more than two triangles, inconsistent
        winding, or zero volume.

    Warns
    -----
    MeshOrientationWarning
        If the mesh is inside out; its winding is reversed (never a silent abs()).
    """
    if (density is None) == (mass is None):
        raise InputError(
            "Expected exactly one of `density` and `mass`, got "
            + ("both." if density is not None else "neither.")
        )
    label, vertices, faces, file_units = _load(mesh)
    units = units if units is not None else file_units
    if units is not None:
        vertices = vertices * length_scale(units, "units")
    if density is not None:
        rho = to_si(density, "density", "density")
        if rho <= 0:
            raise InputError(f"Expected `density` > 0 kg/m^3, got {rho!r}.")
        return mesh_mass_properties(vertices, faces, density=rho, label=label)
    total = to_si(mass, "mass", "mass")
    if total <= 0:
        raise InputError(f"Expected `mass` > 0 kg, got {total!r}.")
    return mesh_mass_properties(vertices, faces, mass=total, label=label)


def _load(mesh: Any) -> tuple[str, NDArray[np.float64], NDArray[np.int64], str | None]:
    """Vertices, faces and declared length unit of a file or trimesh object, unprocessed."""
    import trimesh

    if isinstance(mesh, str | os.PathLike):
        path = Path(mesh)
        label = f"mesh {str(path)!r}"
        if not path.is_file():
            why = "a directory" if path.is_dir() else "no such file"
            raise InputError(f"Expected `mesh` to be a mesh file, got {str(path)!r} ({why}).")
        try:
            # process=False: keep the file's triangles as they are; merging and
            # the checks below are ours, so that errors can say what is wrong.
            loaded = trimesh.load_mesh(path, process=False)
        except ImportError as exc:
            raise InputError(
                f"Reading {str(path)!r} needs a package that is not installed: {exc}."
            ) from None
        except Exception as exc:  # trimesh raises many types for unreadable files
            raise InputError(
                f"Expected `mesh` to be a readable mesh file (STL, OBJ, PLY, GLB, ...), "
                f"got {str(path)!r}: {exc}"
            ) from None
    elif isinstance(mesh, trimesh.Scene):
        label, loaded = "mesh (scene)", mesh.to_mesh()
    elif isinstance(mesh, trimesh.Trimesh):
        label, loaded = "mesh", mesh
    else:
        raise InputError(
            f"Expected `mesh` to be a file path or a trimesh.Trimesh, got {type(mesh).__name__}."
        )
    vertices = np.ascontiguousarray(loaded.vertices, dtype=float)
    faces = np.ascontiguousarray(loaded.faces, dtype=np.int64)
    declared = getattr(loaded, "units", None)
    return label, vertices, faces, (str(declared) if declared else None)


def mesh_mass_properties(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    *,
    density: float | None = None,
    mass: float | None = None,
    label: str = "mesh",
) -> MassProperties:
    """Mass properties from SI arrays (``vertices`` (n, 3) m, ``faces`` (k, 3));
    exactly one of ``density`` (kg/m³) and ``mass`` (kg). See :func:`from_mesh`."""
    vertices, faces = _checked_topology(vertices, faces, label)
    low, high, reference = bounds_and_mean(vertices)
    size = float(np.max(high - low))
    # Integrate in units of the mesh's own size about a point near it: the sums
    # neither cancel (far from the origin) nor overflow or underflow (1e±100 m).
    scaled = (vertices - reference) / size
    origin = np.zeros(3)
    integrals = mesh_integrals(scaled, faces, origin)
    volume, area = integrals[0], integrals[10]
    if abs(volume) <= ZERO_VOLUME_FRACTION * area:
        raise MeshError(
            f"Expected {label} to enclose a volume, got a signed volume of "
            f"{volume * size**3:.3g} m³ (flat or self-cancelling)."
        )
    _check_parts(scaled, faces, volume, label, size)
    if volume < 0:
        warnings.warn(
            f"{label} is inside out (normals point inward, signed volume "
            f"{volume * size**3:.6g} m³); its winding was reversed.",
            MeshOrientationWarning,
            stacklevel=3,
        )
        integrals = -integrals
        volume = -volume
    first = integrals[1:4]
    sxx, syy, szz, sxy, sxz, syz = integrals[4:10]
    centroid = first / volume  # relative to the reference point, in units of `size`
    # Second moments about the centroid: ∫ x xᵀ dV − V c cᵀ.
    second = np.array([[sxx, sxy, sxz], [sxy, syy, syz], [sxz, syz, szz]])
    second -= volume * np.outer(centroid, centroid)
    if density is not None:
        with np.errstate(over="ignore", under="ignore"):
            total = float(density * volume * np.float64(size) ** 3)
        if not 0 < total < np.inf:
            raise InputError(
                f"Expected the mass of {label} (density × volume) within float range, got "
                f"{total!r} kg from {density!r} kg/m³ and {size:.3g} m across."
            )
    else:
        total = float(mass)  # type: ignore[arg-type]
    # Inertia per unit mass is (trace(C) E − C) / V in units of size²: no size³ or
    # size⁵ factors that would overflow for huge meshes or vanish for tiny ones.
    with np.errstate(over="ignore"):
        inertia = total * size**2 * ((np.trace(second) * np.eye(3) - second) / volume)
    return MassProperties(total, reference + size * centroid, inertia)


def _check_parts(
    scaled: NDArray[np.float64], faces: NDArray[np.int64], volume: float, label: str, size: float
) -> None:
    """Each separate part must be wound like the whole, unless it is a cavity.

    An inside-out part among outward ones would otherwise be subtracted. A
    part of the opposite sign is accepted as a cavity when its bounding box lies
    inside the bounding box of a larger part of the whole's sign (an inner
    shell wound inward); otherwise it is an error. Parts that overlap without
    nesting are added as they are (their common volume counts twice).
    """
    n_parts, labels = face_components(faces, scaled.shape[0])
    if n_parts == 1:
        return
    order = np.argsort(labels, kind="stable")
    bounds = np.flatnonzero(np.diff(labels[order])) + 1
    parts = np.split(order, bounds)
    volumes = np.empty(n_parts)
    boxes = np.empty((n_parts, 2, 3))
    for k, part in enumerate(parts):
        part_faces = np.ascontiguousarray(faces[part])
        volumes[k] = mesh_integrals(scaled, part_faces, np.zeros(3))[0]
        corners = scaled[np.unique(part_faces)]
        boxes[k] = corners.min(axis=0), corners.max(axis=0)
    sign = np.sign(volume)
    for k in (int(k) for k in np.flatnonzero(np.sign(volumes) != sign)):
        inside = [
            j
            for j in np.flatnonzero(np.sign(volumes) == sign)
            if abs(volumes[j]) > abs(volumes[k])
            and np.all(boxes[j, 0] <= boxes[k, 0])
            and np.all(boxes[k, 1] <= boxes[j, 1])
        ]
        if not inside:
            raise MeshError(
                f"Expected every part of {label} to be wound like the whole (or to be a cavity "
                f"inside another part), got part {k + 1} of {n_parts} with signed volume "
                f"{volumes[k] * size**3:.6g} m³ against {volume * size**3:.6g} m³ in all: "
                "it is inside out."
            )


def _checked_topology(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], label: str
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Merge duplicate vertices, drop zero-area triangles, check the mesh is closed and oriented."""
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise MeshError(f"Expected {label} to have triangles, got faces of shape {faces.shape}.")
    if faces.shape[0] == 0:
        raise MeshError(f"Expected {label} to have triangles, got none (is it a mesh file?).")
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise MeshError(f"Expected {label} vertices of shape (n, 3), got {vertices.shape}.")
    low, high = index_range(faces)
    if low < 0 or high >= vertices.shape[0]:
        raise MeshError(
            f"Expected {label} face indices in [0, {vertices.shape[0] - 1}], "
            f"got indices from {low} to {high}."
        )
    bad = count_nonfinite_rows(vertices)
    if bad:
        raise MeshError(f"Expected {label} vertices to be finite, got {bad} with NaN or inf.")
    unique, inverse = _merge_identical_vertices(vertices)
    faces = renumber_faces(faces, inverse)
    if faces.shape[0] == 0:
        raise MeshError(f"Expected {label} to have triangles of non-zero area, got none.")
    _check_edges(faces, unique.shape[0], label)
    return unique, faces


def _merge_identical_vertices(
    vertices: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Unique vertices (exactly equal coordinates merged) and, per input vertex, its index.

    Hashes each vertex's bit pattern to one integer and sorts those, several
    times faster than ``np.unique(axis=0)``, and keeps the vertices in order of
    first appearance, so the integration kernel reads memory as the file laid it
    out. A hash collision (two different points, one hash) is detected and falls
    back to the exact ``np.unique(axis=0)``.
    """
    points = vertices + 0.0  # -0.0 becomes +0.0, so equal coordinates have equal bits
    bits = points.view(np.uint64)
    with np.errstate(over="ignore"):
        keys = (
            bits[:, 0] * np.uint64(0x9E3779B97F4A7C15)
            ^ bits[:, 1] * np.uint64(0xC2B2AE3D27D4EB4F)
            ^ bits[:, 2] * np.uint64(0x165667B19E3779F9)
        )
    unique, inverse, exact = merge_by_key(points, keys, np.argsort(keys))
    if not exact:
        unique, inverse = np.unique(points, axis=0, return_inverse=True)
    return unique, inverse.reshape(-1).astype(np.int64)


def _check_edges(faces: NDArray[np.int64], n_vertices: int, label: str) -> None:
    """Every edge in exactly two triangles, traversed once in each direction.

    One sort of integer edge keys (see :func:`tumble.core.topology.directed_edge_keys`)
    rather than trimesh's graph helpers, so the errors can count what is wrong.
    """
    keys = directed_edge_keys(faces, n_vertices)
    keys.sort()
    boundary, crowded, same_direction = (int(n) for n in edge_defects(keys))
    if boundary:
        raise MeshError(
            f"Expected {label} to be closed (watertight), got {boundary} boundary edges "
            "(edges of only one triangle): it has holes, so it bounds no solid."
        )
    if crowded:
        raise MeshError(
            f"Expected {label} to be manifold, got {crowded} edges shared by more than two "
            "triangles."
        )
    if same_direction:
        raise MeshError(
            f"Expected {label} to have consistent winding, got {same_direction} edges traversed "
            "in the same direction by both of their triangles (some triangles are flipped; "
            "trimesh.repair.fix_normals can repair it)."
        )
