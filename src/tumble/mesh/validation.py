"""The validation and repairs that make a triangle mesh a solid before its integrals
are taken (:mod:`tumble.mesh`): merging and welding vertices, cancelling
coincident triangles, and checking that every edge closes the surface, or
splits it into closed pieces, with consistent winding.
"""

from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import NDArray

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

__all__ = [
    "DEFAULT_MERGE_FRACTION",
    "LARGEST_SUGGESTED_FRACTION",
    "ROUND_OFF_ULPS",
    "MeshRepairWarning",
    "bounds_and_centre",
    "box_diagonal",
    "check_arrays",
    "check_edges",
    "check_parts",
    "checked_topology",
    "cubic_metres",
    "drop_cancelling",
    "merge_identical_vertices",
    "scaled_inertia",
    "weld_seams",
]

#: The default ``merge_tolerance`` is the larger of this fraction of the bounding
#: box's diagonal (far above the round-off of double coordinates, ~1e-16 of
#: their size, far below any feature a mesh draws) and :data:`ROUND_OFF_ULPS`
#: units in the last place of the largest coordinate, in the precision the file
#: stores (single precision in STL files: their round-off is ~6e-8 of the size).
DEFAULT_MERGE_FRACTION = 1e-9

#: Units in the last place of the coordinates that the default tolerance allows.
ROUND_OFF_ULPS = 4

#: A gap wider than this fraction of the diagonal is a hole, not a seam: no
#: larger ``merge_tolerance`` is suggested for it.
LARGEST_SUGGESTED_FRACTION = 1e-5


class MeshRepairWarning(UserWarning):
    """A mesh was read as a closed solid after a repair it should be told of:
    vertices welded across a seam, coincident triangles of opposite winding
    removed, or closed pieces that touch along edges."""


def check_parts(
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
                f"{cubic_metres(volumes[k], size)} against {cubic_metres(volume, size)} in all: "
                "it is inside out."
            )


def bounds_and_centre(
    vertices: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The corners of the bounding box of ``vertices`` and a point near them to
    integrate about: their mean, or the box's centre when the sum of coordinates
    near 1e308 overflows."""
    low, high, reference = bounds_and_mean(vertices)
    if not np.all(np.isfinite(reference)):
        reference = low + 0.5 * (high - low)
    return low, high, reference


def scaled_inertia(
    mass: float, size: float, per_mass: NDArray[np.float64], label: str
) -> NDArray[np.float64]:
    """The inertia tensor ``mass × size² × per_mass`` (kg·m²), from the inertia per unit
    mass in units of the mesh's ``size`` (m).

    Raises
    ------
    InputError
        When it is beyond float range or below its normal numbers (a mesh
        1e200 m or 1e-200 m across): inf or a tensor rounded to zero.
    """
    scale = np.float64(size)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        # Paired so that no partial product leaves float range before the result does.
        inertia = (per_mass * scale) * (scale * mass)
    largest = float(np.max(np.abs(inertia)))  # NaN where inf met 0
    if not np.finfo(float).tiny <= largest < np.inf:
        raise InputError(
            f"Expected the inertia of {label} within float range (normal floats, 2.2e-308 to "
            f"1.8e308 kg·m²), got about {mass:.3g} kg × ({size:.3g} m)²."
        )
    return np.asarray(inertia)


def cubic_metres(volume: float, size: float, spec: str = ".6g") -> str:
    """A volume ``volume`` in units of ``size``³ (m³), formatted with ``spec``; as that
    product when m³ would overflow or underflow (a mesh 1e200 m or 1e-200 m across)."""
    scale = np.float64(size)
    with np.errstate(over="ignore", under="ignore"):
        # |volume| <= 1 in units of size³: each product moves towards the result.
        value = float(volume * scale * scale * scale)
    if np.isfinite(value) and (value != 0 or volume == 0):
        return f"{value:{spec}} m³"
    return f"{volume:{spec}} × ({size:.3g} m)³"


def check_arrays(vertices: NDArray[np.float64], faces: NDArray[np.int64], label: str) -> None:
    """Triangles (k, 3) with indices into ``vertices`` (n, 3), all finite, within a box
    whose diagonal is within float range.

    Raises
    ------
    MeshError
        Faces not of shape (k, 3) or none, vertices not (n, 3), indices out of
        range, NaN or infinite coordinates, a diagonal over 1.8e308 m.
    """
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
    low_corner, high_corner, _ = bounds_and_mean(vertices)
    if not np.isfinite(box_diagonal(low_corner, high_corner)):
        raise MeshError(
            f"Expected {label} to fit in float range (a diagonal below 1.8e308 m), got "
            f"vertices from {low_corner.tolist()} to {high_corner.tolist()}."
        )


def box_diagonal(low: NDArray[np.float64], high: NDArray[np.float64]) -> float:
    """The length of the box from corner ``low`` to ``high``, without the overflow or
    underflow of squaring its sides (a mesh 1e-300 m across has a diagonal, not 0);
    inf when it is beyond float range."""
    with np.errstate(over="ignore", invalid="ignore"):
        sides = high - low
        size = float(np.max(sides))
        if not 0 < size < np.inf:
            return size
        return float(size * np.linalg.norm(sides / size))


def checked_topology(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    label: str,
    merge_tolerance: float | None = None,
    epsilon: float = float(np.finfo(np.float64).eps),
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Merge duplicate vertices, drop zero-area triangles, weld seams, check the
    mesh is closed (or closed pieces) and oriented. ``epsilon``: the relative
    round-off of the coordinates as the file stored them (for the default
    ``merge_tolerance``)."""
    check_arrays(vertices, faces, label)
    unique, inverse = merge_identical_vertices(vertices)
    faces = renumber_faces(faces, inverse)
    if faces.shape[0] == 0:
        raise MeshError(f"Expected {label} to have triangles of non-zero area, got none.")
    keys = directed_edge_keys(faces, unique.shape[0])
    keys.sort()
    boundary, crowded, _ = (int(n) for n in edge_defects(keys))
    corner_low, corner_high, _ = bounds_and_mean(unique)
    extent = box_diagonal(corner_low, corner_high)
    tolerance = merge_tolerance
    if tolerance is None:
        largest = float(max(np.max(np.abs(corner_low)), np.max(np.abs(corner_high))))
        tolerance = max(DEFAULT_MERGE_FRACTION * extent, ROUND_OFF_ULPS * epsilon * largest)
    if boundary and tolerance > 0:
        welded_faces, count, largest, touched = weld_seams(unique, faces, keys, tolerance)
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
        faces, cancelled = drop_cancelling(faces, keys, unique.shape[0])
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
    check_edges(faces, unique.shape[0], label, keys, unique, extent, tolerance)
    return unique, faces


def weld_seams(
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


def drop_cancelling(
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


def merge_identical_vertices(
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


def check_edges(
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
                f"triangles, {open_edges} of which do not split it into closed pieces wound "
                "alike (at such an edge the triangles must pair up around it, each pair "
                "bounding one solid wedge)."
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
            "trimesh.repair.fix_normals, with networkx installed, can repair it)."
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
    sides = vertices[starts] - vertices[ends]
    scale = float(np.max(np.abs(sides)))  # > 0: the triangles of zero area were dropped
    length = scale * float(np.sum(np.linalg.norm(sides / scale, axis=1)))
    message = (
        f"Expected {label} to be closed (watertight), got {boundary} boundary edges (edges of "
        f"only one triangle, {length:.3g} m long in all, {length / diagonal:.2g} of the "
        f"mesh's diagonal) "
        + (f"after welding vertices closer than {tolerance:.3g} m" if tolerance > 0 else "")
        + ("without welding (merge_tolerance 0)" if tolerance == 0 else "")
        + ": it has holes, so it bounds no solid."
    )
    shell = (
        " For a sheet or a thin-walled part, shell_thickness gives the mass properties of "
        "its surface as a shell."
    )
    seam = np.unique(np.concatenate([starts, ends]))
    if seam.shape[0] < 2:
        return message + shell
    # The seam's near pairs: vertices with another within the largest gap
    # suggested; welding those at twice their largest distance must close it.
    distances, _ = cKDTree(vertices[seam]).query(vertices[seam], k=2)
    near = distances[:, 1][distances[:, 1] <= 0.5 * LARGEST_SUGGESTED_FRACTION * diagonal]
    if near.shape[0] == 0:
        return message + shell
    gap = float(np.max(near))
    suggestion = 2.0 * gap
    if not suggestion > tolerance:
        return message + shell
    welded_faces, _, _, _ = weld_seams(vertices, faces, keys, suggestion)
    closed = directed_edge_keys(welded_faces, vertices.shape[0])
    closed.sort()
    if edge_defects(closed)[0]:
        return message + shell
    return (
        message + f" Its vertices at the holes are at most {gap:.3g} m from one another: "
        f"merge_tolerance = {suggestion:.2g} m welds them and closes it." + shell
    )
