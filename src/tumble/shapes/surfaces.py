"""Triangle meshes of the surfaces of the catalogue's solids, to draw them with.

Each is centred like its closed form in ``tumble.shapes.closed_forms`` (on its
centre of mass, its symmetry axis along z), in metres. An idealised thin body (a
rod, a disk, a ring) is given a small thickness so it can be seen. Made with numpy
here, so drawing a solid does not pay for importing trimesh's mesh generators;
nothing here enters a computation of mass properties.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "Mesh",
    "box",
    "capsule",
    "cone",
    "cylinder",
    "ellipsoid",
    "hollow_sphere",
    "revolve",
    "sphere",
    "tetrahedron",
    "torus",
    "tube",
]

Array = NDArray[np.float64]
#: A triangle mesh: vertices (n, 3), m, and faces (m, 3), indices of vertices.
Mesh = tuple[Array, NDArray[np.int64]]


def revolve(profile: Any, sections: int = 48, closed: bool = False) -> Mesh:
    """The surface swept by a profile ``[(r, z), ...]`` turned about the z axis.

    Points with ``r = 0`` become single vertices on the axis (the poles of a
    sphere, the apex of a cone); ``closed`` joins the last point to the first
    (a torus, a tube's cross-section).
    """
    points = np.asarray(profile, dtype=float)
    angles = np.linspace(0.0, 2.0 * np.pi, sections, endpoint=False)
    circle = np.column_stack((np.cos(angles), np.sin(angles)))
    vertices: list[Array] = []
    rings: list[NDArray[np.int64]] = []
    count = 0
    for r, z in points:
        if r == 0.0:
            vertices.append(np.array([[0.0, 0.0, z]]))
            rings.append(np.full(sections, count, dtype=np.int64))
            count += 1
        else:
            vertices.append(np.column_stack((r * circle, np.full(sections, z))))
            rings.append(np.arange(count, count + sections, dtype=np.int64))
            count += sections
    faces: list[NDArray[np.int64]] = []
    pairs = list(zip(range(len(rings) - 1), range(1, len(rings)), strict=True))
    if closed:
        pairs.append((len(rings) - 1, 0))
    for i, j in pairs:
        a, b = rings[i], rings[j]
        a1, b1 = np.roll(a, -1), np.roll(b, -1)
        for triangle in (np.column_stack((a, a1, b1)), np.column_stack((a, b1, b))):
            keep = (triangle[:, 0] != triangle[:, 1]) & (triangle[:, 1] != triangle[:, 2])
            keep &= triangle[:, 0] != triangle[:, 2]
            faces.append(triangle[keep])
    return np.vstack(vertices), np.vstack(faces)


def sphere(radius: float = 1.0, rings: int = 16, sections: int = 32) -> Mesh:
    """A sphere of ``radius`` (m) about the origin."""
    theta = np.linspace(0.0, np.pi, rings + 1)
    profile = np.column_stack((radius * np.sin(theta), -radius * np.cos(theta)))
    profile[0, 0] = profile[-1, 0] = 0.0
    return revolve(profile, sections)


def hollow_sphere(inner_radius: float, outer_radius: float) -> Mesh:
    """A spherical shell of solid wall (m) about the origin: the outer sphere and the
    inner one turned inside out."""
    outer, faces = sphere(outer_radius)
    inner = outer * (inner_radius / outer_radius)
    return np.vstack([outer, inner]), np.vstack([faces, faces[:, ::-1] + len(outer)])


def cylinder(radius: float, height: float, sections: int = 48) -> Mesh:
    """A closed cylinder of ``radius`` and ``height`` (m) along z, centred."""
    h = 0.5 * height
    return revolve([(0.0, -h), (radius, -h), (radius, h), (0.0, h)], sections)


def tube(inner_radius: float, outer_radius: float, height: float) -> Mesh:
    """A hollow cylinder (m) along z, centred: its ends are rings."""
    h = 0.5 * height
    profile = [(inner_radius, -h), (outer_radius, -h), (outer_radius, h), (inner_radius, h)]
    return revolve(profile, closed=True)


def cone(radius: float, height: float) -> Mesh:
    """A solid cone (m), apex at +z, its centre of mass (a quarter of the height
    above the base) at the origin."""
    return revolve([(0.0, -0.25 * height), (radius, -0.25 * height), (0.0, 0.75 * height)])


def torus(
    major_radius: float, minor_radius: float, sections: int = 48, tube_sections: int = 16
) -> Mesh:
    """A torus about z, ``major_radius`` to the tube's centre, ``minor_radius`` of the
    tube (m), centred."""
    a = np.linspace(0.0, 2.0 * np.pi, tube_sections, endpoint=False)
    profile = np.column_stack((major_radius + minor_radius * np.cos(a), minor_radius * np.sin(a)))
    return revolve(profile, sections, closed=True)


def capsule(radius: float, cylinder_height: float) -> Mesh:
    """A cylinder of ``radius`` and ``cylinder_height`` (m) along z capped by two
    hemispheres, centred."""
    h = 0.5 * cylinder_height
    theta = np.linspace(0.0, 0.5 * np.pi, 9)
    bottom = [(radius * np.sin(t), -h - radius * np.cos(t)) for t in theta]
    top = [(radius * np.cos(t), h + radius * np.sin(t)) for t in theta]
    profile = np.array(bottom + top)
    profile[0, 0] = profile[-1, 0] = 0.0
    return revolve(profile)


def ellipsoid(semi_axes: Any) -> Mesh:
    """An ellipsoid of ``semi_axes`` (a, b, c) (m) along x, y, z."""
    vertices, faces = sphere()
    return vertices * np.asarray(semi_axes, dtype=float), faces


def box(size: Any) -> Mesh:
    """A box of full edges ``size`` (a, b, c) (m) along x, y, z, centred."""
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    faces = np.array(
        [
            [0, 1, 3],
            [0, 3, 2],
            [4, 6, 7],
            [4, 7, 5],
            [0, 4, 5],
            [0, 5, 1],
            [2, 3, 7],
            [2, 7, 6],
            [0, 2, 6],
            [0, 6, 4],
            [1, 5, 7],
            [1, 7, 3],
        ],
        dtype=np.int64,
    )
    return corners * (0.5 * np.asarray(size, dtype=float)), faces


def tetrahedron(edge: float) -> Mesh:
    """A regular tetrahedron of ``edge`` (m): vertices (a / √8)(±1, ±1, ±1) with an even
    number of minus signs, its centre of mass at the origin."""
    a = edge / np.sqrt(8.0)
    vertices = a * np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    return vertices, np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]], dtype=np.int64)
