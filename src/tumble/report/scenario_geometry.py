"""Meshes of the bodies of scenario files, to draw them in the 3D viewer.

Solids of :mod:`tumble.shapes` are drawn as they are (turned profiles, boxes),
mesh files as read, point masses as small spheres, and a body given by its
mass properties as the uniform ellipsoid of equal inertia
(:func:`tumble.report.geometry.equal_inertia_ellipsoid`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.massprops import MassProperties
from tumble.report.geometry import (
    DiscDrawing,
    Geometry,
    disc_drawing,
    equal_inertia_ellipsoid,
)
from tumble.scenario.bodies import InertiaBody, MeshBody, PartsBody, PointsBody, ShapeBody
from tumble.scenario.build import mesh_path, rotation
from tumble.shapes import SHAPE_KINDS
from tumble.shapes.surfaces import Mesh, sphere

__all__ = ["body_geometry", "part_drawings", "shape_mesh"]

Array = NDArray[np.float64]


def shape_mesh(spec: ShapeBody) -> Mesh:
    """A drawing of a solid of :mod:`tumble.shapes`, centred like it (on its centre of
    mass): its kind's surface (:attr:`tumble.shapes.ShapeKind.surface`)."""
    return SHAPE_KINDS[spec.shape].surface(**spec.dimensions())


def body_geometry(spec: Any, folder: Path) -> Geometry:
    """A mesh of the body in body coordinates, for the 3D viewer.

    Solids and mesh files are drawn as they are; point masses as small spheres;
    a body given by its inertia as the ellipsoid of equal inertia.
    """
    pieces: list[tuple[Array, NDArray[np.int64]]] = []
    exact = True
    if isinstance(spec, PartsBody):
        for part in spec.parts:
            child = body_geometry(part, folder)
            pieces.append((child.vertices, child.faces))
            exact = exact and child.exact
    elif isinstance(spec, ShapeBody):
        pieces.append(shape_mesh(spec))
    elif isinstance(spec, MeshBody):
        import trimesh

        mesh_file: Any = trimesh.load(mesh_path(spec, folder), force="mesh", process=False)
        scale = 1.0
        if spec.units is not None:
            from tumble.units import length_scale

            scale = length_scale(spec.units)
        pieces.append(
            (np.asarray(mesh_file.vertices, float) * scale, np.asarray(mesh_file.faces, np.int64))
        )
    elif isinstance(spec, PointsBody):
        positions = np.asarray(spec.positions, dtype=float)
        extent = float(np.ptp(positions, axis=0).max()) if len(positions) > 1 else 0.1
        radius = max(extent, 1e-6) / 20.0
        ball, ball_faces = sphere(radius, rings=8, sections=12)
        for point in positions:
            pieces.append((ball + point, ball_faces))
        exact = False
    else:
        assert isinstance(spec, InertiaBody)
        unplaced = MassProperties(spec.mass, spec.center_of_mass, spec.inertia)
        ellipsoid = equal_inertia_ellipsoid(unplaced)
        pieces.append((ellipsoid.vertices, ellipsoid.faces))
        exact = False
    vertices, faces = _concatenate(pieces)
    if spec.rotation is not None:
        vertices = rotation(spec.rotation).apply(vertices)
    if spec.translation is not None:
        vertices = vertices + np.asarray(spec.translation)
    return Geometry(vertices, faces, exact)


def _concatenate(pieces: list[tuple[Array, NDArray[np.int64]]]) -> tuple[Array, NDArray[np.int64]]:
    vertices, faces, offset = [], [], 0
    for v, f in pieces:
        vertices.append(v)
        faces.append(f + offset)
        offset += len(v)
    return np.vstack(vertices), np.vstack(faces).astype(np.int64)


def part_drawings(
    parts: Any, centre: Array, geometry: Geometry
) -> tuple[Geometry, list[DiscDrawing | None]]:
    """The body's mesh with the parts drawn as balls added to it, and the discs of
    the parts that spin, one per column of the rotors' speeds (None for one not
    drawn as a disc), from each part's :meth:`~tumble.parts.InternalPart.drawing`.
    ``parts`` are parts as read from a file (:class:`tumble.parts.FilePart`) or
    bare parts; ``centre`` the body's centre of mass (body coordinates, m)."""
    vertices = geometry.vertices
    reach = float(np.max(np.ptp(vertices, axis=0))) if len(vertices) else 1.0
    pieces = [(geometry.vertices, geometry.faces)]
    rotors: list[DiscDrawing | None] = []
    for entry in parts:
        part = getattr(entry, "part", entry)
        drawing = part.drawing(
            reach,
            centre,
            getattr(entry, "position", None),
            getattr(entry, "radius", None),
            getattr(entry, "thickness", None),
        )
        if part.spin is not None:
            rotors.append(disc_drawing(drawing))
        elif drawing is not None and drawing.shape == "ball":
            ball, faces = sphere(drawing.radius, rings=8, sections=12)
            pieces.append((ball + drawing.position, faces))
    if len(pieces) > 1:
        vertices, faces = _concatenate(pieces)
        geometry = Geometry(vertices, faces, geometry.exact)
    return geometry, rotors
