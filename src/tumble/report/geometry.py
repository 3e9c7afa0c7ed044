"""Meshes to draw bodies with in the 3D viewer, in body coordinates.

Surfaces of revolution, spheres, boxes, tori, and the uniform ellipsoid of
equal inertia that stands in for a body known only by its mass properties.
Drawn meshes only: made with numpy here, so drawing a solid does not pay for
importing trimesh's mesh generators; nothing here enters a computation. The
bodies of scenario files are drawn by :mod:`tumble.report.scenario_geometry`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.massprops import MassProperties

__all__ = [
    "DiscDrawing",
    "Geometry",
    "Mesh",
    "box",
    "cylinder",
    "disc_mesh",
    "equal_inertia_ellipsoid",
    "revolve",
    "sphere",
    "torus",
]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Geometry:
    """A triangle mesh in body coordinates, m: ``vertices`` (n, 3), ``faces`` (m, 3);
    ``exact`` is False where it stands in for the body (an ellipsoid of equal inertia,
    spheres for point masses)."""

    vertices: Array
    faces: NDArray[np.int64]
    exact: bool = True


Mesh = tuple[Array, NDArray[np.int64]]


def revolve(profile: Any, sections: int = 48, closed: bool = False) -> Mesh:
    """The surface swept by a profile ``[(r, z), ...]`` turned about the z axis.

    Points with ``r = 0`` become single vertices on the axis (the poles of a
    sphere, the apex of a cone); ``closed`` joins the last point to the first
    (a torus, a tube's cross-section). Drawn meshes only: made with numpy here,
    so drawing a solid does not pay for importing trimesh's mesh generators.
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
    theta = np.linspace(0.0, np.pi, rings + 1)
    profile = np.column_stack((radius * np.sin(theta), -radius * np.cos(theta)))
    profile[0, 0] = profile[-1, 0] = 0.0
    return revolve(profile, sections)


def cylinder(radius: float, height: float, sections: int = 48) -> Mesh:
    h = 0.5 * height
    return revolve([(0.0, -h), (radius, -h), (radius, h), (0.0, h)], sections)


def torus(major: float, minor: float, sections: int = 48, tube: int = 16) -> Mesh:
    a = np.linspace(0.0, 2.0 * np.pi, tube, endpoint=False)
    return revolve(np.column_stack((major + minor * np.cos(a), minor * np.sin(a))), sections, True)


def box(size: Any) -> Mesh:
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


def equal_inertia_ellipsoid(mp: MassProperties) -> Geometry:
    """The uniform solid ellipsoid with the body's mass and inertia, at its centre of mass.

    Its semi-axes along the principal axes are ``a_i² = 5 (I_j + I_k − I_i) / (2 m)``.
    """
    moments, axes = mp.principal()
    squares = np.array([5.0 * (moments.sum() - 2.0 * m) / (2.0 * mp.mass) for m in moments])
    floor = 0.02 * float(np.sqrt(np.max(squares)))
    semi = np.maximum(np.sqrt(np.maximum(squares, 0.0)), floor)
    vertices, faces = sphere()
    return Geometry((vertices * semi) @ axes.T + mp.center_of_mass, faces, exact=False)


@dataclass(frozen=True)
class DiscDrawing:
    """Where to draw a part that spins as a disc (a rotor, a wheel): its centre (m)
    and unit spin axis in body coordinates, its radius and thickness (m)."""

    position: Array
    axis: Array
    radius: float
    thickness: float


def disc_drawing(drawing: Any) -> DiscDrawing | None:
    """A part's drawing (:class:`tumble.parts.PartDrawing`) as a turning disc, or
    None when it is not a disc that spins."""
    if drawing is None or drawing.shape != "disc" or drawing.spin is None:
        return None
    axis = np.asarray(drawing.axis, dtype=float)
    return DiscDrawing(
        np.asarray(drawing.position, dtype=float),
        axis / np.linalg.norm(axis),
        float(drawing.radius),
        float(drawing.thickness),
    )


def disc_mesh(drawing: DiscDrawing) -> tuple[Array, NDArray[np.int64], NDArray[np.bool_]]:
    """A disc with a stripe along one radius (to see it turn), in body coordinates at
    its place: vertices, faces, and which faces belong to the stripe."""
    from scipy.spatial.transform import Rotation

    disc, disc_faces = cylinder(drawing.radius, drawing.thickness, sections=32)
    stripe, stripe_faces = box((drawing.radius, 0.15 * drawing.radius, 1.1 * drawing.thickness))
    stripe = stripe + np.array([0.5 * drawing.radius, 0.0, 0.0])
    vertices = np.vstack([disc, stripe])
    faces = np.vstack([disc_faces, stripe_faces + len(disc)])
    marked = np.concatenate([np.zeros(len(disc_faces), bool), np.ones(len(stripe_faces), bool)])
    turn, _ = Rotation.align_vectors([drawing.axis], [[0.0, 0.0, 1.0]])
    return turn.apply(vertices) + drawing.position, faces.astype(np.int64), marked
