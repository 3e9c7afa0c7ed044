"""Mass properties of a solid bounded by a closed triangle mesh.

Files are read with trimesh (STL, OBJ, PLY, GLB/glTF, OFF, ...); the volume
integrals are tumble's own compiled kernel, :func:`tumble.core.polyhedron.mesh_integrals`,
which is exact for the polyhedron (Tonon 2004, via the divergence theorem).

Before integrating, the mesh is checked, because the integrals of a mesh that
does not bound a solid are meaningless rather than approximately right:

* vertices with bit-identical coordinates are merged (STL files repeat them)
  and triangles that then have a repeated corner (zero area) are dropped;
* where edges are left with one triangle (a seam whose two sides differ by
  round-off, as CAD exports write them), the vertices of those edges closer
  than ``merge_tolerance`` are welded (:func:`tumble.core.topology.weld`:
  deterministic, whatever the vertex order), with a :class:`MeshRepairWarning`;
* every edge must be shared by exactly two triangles (watertight), or split
  the mesh into closed pieces: coincident triangles of opposite winding (two
  solids sharing a face) cancel and are removed, and closed pieces that touch
  along edges or at vertices (a convex decomposition) are accepted;
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
    boundary_vertices,
    bounds_and_mean,
    count_nonfinite_rows,
    crowded_edges,
    defects_after_renumbering,
    directed_edge_keys,
    edge_defects,
    face_components,
    faces_at_edges,
    index_range,
    merge_by_key,
    part_volumes_and_boxes,
    renumber_faces,
    unpaired_edges,
    weld,
)
from tumble.errors import InputError, MeshError
from tumble.massprops import MassProperties
from tumble.units import length_scale, to_si

__all__ = ["MeshOrientationWarning", "MeshRepairWarning", "from_mesh"]

#: A mesh whose |volume| is below this fraction of (surface area × largest
#: extent) encloses nothing: the volume of a flat or self-cancelling surface is
#: round-off, at most about 1e-16 · √n_triangles of that product. A plate of
#: thickness t has a ratio t / (2 · length), so only plates thinner than
#: 2e-9 of their length are refused.
ZERO_VOLUME_FRACTION = 1e-9


#: The default ``merge_tolerance``, as a fraction of the bounding box's diagonal:
#: far above the round-off of coordinates (~1e-16 of their size), far below any
#: feature a mesh draws.
DEFAULT_MERGE_FRACTION = 1e-9

#: A gap wider than this fraction of the diagonal is a hole, not a seam: no
#: larger ``merge_tolerance`` is suggested for it.
LARGEST_SUGGESTED_FRACTION = 1e-5


class MeshOrientationWarning(UserWarning):
    """An inside-out mesh (inward normals) was reversed before integrating."""


class MeshRepairWarning(UserWarning):
    """A mesh was read as a closed solid after a repair it should be told of:
    vertices welded across a seam, coincident triangles of opposite winding
    removed, or closed pieces that touch along edges."""


def from_mesh(
    mesh: Any,
    density: Any = None,
    mass: Any = None,
    units: Any = None,
    *,
    merge_tolerance: Any = None,
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
    merge_tolerance : the largest distance at which the vertices of edges with
        one triangle are welded, a length (m, or e.g. ``"0.01 mm"``; after
        ``units``). Default :data:`DEFAULT_MERGE_FRACTION` of the bounding
        box's diagonal (round-off only); 0 welds nothing.

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
        boundary edges, gives their length, and suggests the
        ``merge_tolerance`` that closes a seam), edges shared by more than two
        triangles that do not split the mesh into closed pieces, inconsistent
        winding, or zero volume.

    Warns
    -----
    MeshOrientationWarning
        If the mesh is inside out; its winding is reversed (never a silent abs()).
    MeshRepairWarning
        If vertices were welded (how many, and the largest distance moved),
        coincident triangles removed, or the mesh is closed pieces touching
        along edges (how many).
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
    tolerance = None
    if merge_tolerance is not None:
        tolerance = to_si(merge_tolerance, "length", "merge_tolerance")
        if not tolerance >= 0:
            raise InputError(f"Expected `merge_tolerance` >= 0 m, got {tolerance!r}.")
    if density is not None:
        rho = to_si(density, "density", "density")
        if rho <= 0:
            raise InputError(f"Expected `density` > 0 kg/m^3, got {rho!r}.")
        return mesh_mass_properties(
            vertices, faces, density=rho, label=label, merge_tolerance=tolerance
        )
    total = to_si(mass, "mass", "mass")
    if total <= 0:
        raise InputError(f"Expected `mass` > 0 kg, got {total!r}.")
    return mesh_mass_properties(vertices, faces, mass=total, label=label, merge_tolerance=tolerance)


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
    merge_tolerance: float | None = None,
) -> MassProperties:
    """Mass properties from SI arrays (``vertices`` (n, 3) m, ``faces`` (k, 3));
    exactly one of ``density`` (kg/m³) and ``mass`` (kg); ``merge_tolerance``
    in m (None: the default). See :func:`from_mesh`."""
    vertices, faces = _checked_topology(vertices, faces, label, merge_tolerance)
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
    # The points are about the mesh's mean and in units of its size, so the
    # sum about the origin does not cancel.
    volumes, boxes = part_volumes_and_boxes(scaled, faces, labels, n_parts)
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
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    label: str,
    merge_tolerance: float | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Merge duplicate vertices, drop zero-area triangles, weld seams, check the
    mesh is closed (or closed pieces) and oriented."""
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
    keys = directed_edge_keys(faces, unique.shape[0])
    keys.sort()
    boundary, crowded, _ = (int(n) for n in edge_defects(keys))
    corner_low, corner_high, _ = bounds_and_mean(unique)
    diagonal = float(np.linalg.norm(corner_high - corner_low))
    tolerance = DEFAULT_MERGE_FRACTION * diagonal if merge_tolerance is None else merge_tolerance
    if boundary and tolerance > 0:
        welded_faces, count, largest, touched = _weld_seams(unique, faces, keys, tolerance)
        if count:
            mask = np.zeros(unique.shape[0], dtype=bool)
            mask[touched] = True
            defects = defects_after_renumbering(keys, welded_faces, mask, unique.shape[0])
            faces = welded_faces
            warnings.warn(
                f"{label}: welded {count} vertices of its seams, moved by at most "
                f"{largest:.3g} m (merge_tolerance {tolerance:.3g} m).",
                MeshRepairWarning,
                stacklevel=4,
            )
            boundary, crowded, same_direction = (int(n) for n in defects)
            if boundary or crowded or same_direction:  # the errors count from all keys
                keys = directed_edge_keys(faces, unique.shape[0])
                keys.sort()
            else:
                return unique, faces
    if crowded:
        faces, cancelled = _drop_cancelling(faces, keys, unique.shape[0])
        if cancelled:
            warnings.warn(
                f"{label}: removed {cancelled} pairs of coincident triangles of opposite "
                "winding (solids sharing a face; their integrals cancel).",
                MeshRepairWarning,
                stacklevel=4,
            )
            if faces.shape[0] == 0:
                raise MeshError(f"Expected {label} to enclose a volume, got triangles that cancel.")
            keys = directed_edge_keys(faces, unique.shape[0])
            keys.sort()
    _check_edges(faces, unique.shape[0], label, keys, unique, diagonal, tolerance)
    return unique, faces


def _weld_seams(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    sorted_keys: NDArray[np.int64],
    tolerance: float,
) -> tuple[NDArray[np.int64], int, float, NDArray[np.int64]]:
    """Weld the vertices of the edges used once that lie within ``tolerance`` of
    each other; other vertices are kept as they are (welding a closed fan to
    another would make the mesh non-manifold). Each group of welded vertices
    becomes its lexicographically smallest member, so no coordinate changes and
    the vertex array is kept (the others are simply no longer used). Returns the
    faces (zero-area triangles dropped), how many vertices were welded away, the
    largest distance one moved (m), and the welded groups' vertices (to recount
    only the edges at them)."""
    seam = boundary_vertices(sorted_keys, vertices.shape[0])
    merged, groups, chosen, largest = weld(np.ascontiguousarray(vertices[seam]), tolerance)
    count = seam.shape[0] - merged.shape[0]
    if count == 0:
        return faces, 0, 0.0, seam[:0]
    target = np.arange(vertices.shape[0])
    target[seam] = seam[chosen[groups]]
    moved = seam[target[seam] != seam]
    touched = np.unique(np.concatenate([moved, target[moved]]))
    return renumber_faces(faces, target), count, float(largest), touched


def _drop_cancelling(
    faces: NDArray[np.int64], sorted_keys: NDArray[np.int64], n_vertices: int
) -> tuple[NDArray[np.int64], int]:
    """Remove pairs of triangles on the same three vertices wound opposite ways
    (their contributions to every integral cancel), among the triangles at edges
    of more than two triangles (a coincident pair elsewhere is a closed piece of
    no volume, harmless): the faces left and the number of pairs removed."""
    edges = crowded_edges(sorted_keys)
    _, uses = faces_at_edges(faces, n_vertices, edges)
    candidates = np.unique(uses[:, 0])
    near = faces[candidates]
    ordered = np.sort(near, axis=1)
    # +1 when the triangle runs (low, middle, high) cyclically, −1 the other way.
    start = np.argmin(near, axis=1)
    after = near[np.arange(near.shape[0]), (start + 1) % 3]
    sense = np.where(after == ordered[:, 1], 1, -1)
    order = np.lexsort((sense, ordered[:, 2], ordered[:, 1], ordered[:, 0]))
    same = np.all(ordered[order][1:] == ordered[order][:-1], axis=1)
    if not same.any():
        return faces, 0
    drop = np.zeros(faces.shape[0], dtype=bool)
    pairs = 0
    for run in np.split(order, np.flatnonzero(~same) + 1):
        if len(run) < 2:
            continue
        plus = candidates[run[sense[run] > 0]]
        minus = candidates[run[sense[run] < 0]]
        n = min(len(plus), len(minus))
        drop[plus[:n]] = True
        drop[minus[:n]] = True
        pairs += n
    return np.ascontiguousarray(faces[~drop]), pairs


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


def _check_edges(
    faces: NDArray[np.int64],
    n_vertices: int,
    label: str,
    keys: NDArray[np.int64],
    vertices: NDArray[np.float64],
    diagonal: float,
    tolerance: float,
) -> None:
    """Every edge in exactly two triangles, traversed once in each direction, or
    in closed pieces that touch along edges.

    ``keys``: the sorted directed edge keys (:func:`tumble.core.topology.directed_edge_keys`)
    of ``faces``, so the errors can count what is wrong.
    """
    boundary, crowded, same_direction = (int(n) for n in edge_defects(keys))
    if boundary:
        raise MeshError(_holes_message(faces, vertices, keys, label, boundary, diagonal, tolerance))
    if crowded:
        edges = crowded_edges(keys)
        starts, uses = faces_at_edges(faces, n_vertices, edges)
        open_edges = unpaired_edges(vertices, faces, edges, starts, uses)
        if open_edges:
            raise MeshError(
                f"Expected {label} to be manifold, got {crowded} edges shared by more than two "
                f"triangles, {open_edges} of which do not split it into closed pieces."
            )
        warnings.warn(
            f"{label}: {crowded} edges are shared by more than two triangles; read as closed "
            "pieces touching there (solids sharing edges or faces; pieces that overlap in "
            "volume would count twice).",
            MeshRepairWarning,
            stacklevel=5,
        )
    if same_direction:
        raise MeshError(
            f"Expected {label} to have consistent winding, got {same_direction} edges traversed "
            "in the same direction by both of their triangles (some triangles are flipped; "
            "trimesh.repair.fix_normals can repair it)."
        )


def _holes_message(
    faces: NDArray[np.int64],
    vertices: NDArray[np.float64],
    keys: NDArray[np.int64],
    label: str,
    boundary: int,
    diagonal: float,
    tolerance: float,
) -> str:
    """What is open, how much, and the ``merge_tolerance`` that would close it
    if a seam narrower than :data:`LARGEST_SUGGESTED_FRACTION` of the mesh is all
    that is open."""
    from scipy.spatial import cKDTree

    n = vertices.shape[0]
    edges, uses = np.unique(keys >> 1, return_counts=True)
    edges = edges[uses == 1]
    starts, ends = edges // n, edges % n
    length = float(np.sum(np.linalg.norm(vertices[starts] - vertices[ends], axis=1)))
    message = (
        f"Expected {label} to be closed (watertight), got {boundary} boundary edges (edges of "
        f"only one triangle, {length:.3g} m long in all, {length / diagonal:.2g} of the "
        f"mesh's diagonal) "
        + (f"after welding vertices closer than {tolerance:.3g} m" if tolerance > 0 else "")
        + ("without welding (merge_tolerance 0)" if tolerance == 0 else "")
        + ": it has holes, so it bounds no solid."
    )
    seam = np.unique(np.concatenate([starts, ends]))
    if seam.shape[0] < 2:
        return message
    # The seam's near pairs: vertices with another within the largest gap
    # suggested; welding those at twice their largest distance must close it.
    distances, _ = cKDTree(vertices[seam]).query(vertices[seam], k=2)
    near = distances[:, 1][distances[:, 1] <= 0.5 * LARGEST_SUGGESTED_FRACTION * diagonal]
    if near.shape[0] == 0:
        return message
    gap = float(np.max(near))
    suggestion = 2.0 * gap
    if not suggestion > tolerance:
        return message
    welded_faces, _, _, _ = _weld_seams(vertices, faces, keys, suggestion)
    closed = directed_edge_keys(welded_faces, vertices.shape[0])
    closed.sort()
    if edge_defects(closed)[0]:
        return message
    return (
        message + f" Its vertices at the holes are at most {gap:.3g} m from one another: "
        f"merge_tolerance = {suggestion:.2g} m welds them and closes it."
    )
