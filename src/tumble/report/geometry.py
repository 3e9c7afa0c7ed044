"""Meshes to draw bodies with in the 3D viewer, in body coordinates.

The uniform ellipsoid of equal inertia that stands in for a body known only by
its mass properties, and the turning discs of parts; the solids' surfaces
(surfaces of revolution, spheres, boxes, tori) are
``tumble.shapes.surfaces``'. The bodies of scenario files are drawn by
:mod:`tumble.report.scenario_geometry`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.massprops import MassProperties
from tumble.shapes.surfaces import box, cylinder, sphere

__all__ = [
    "DiscDrawing",
    "Geometry",
    "disc_mesh",
    "equal_inertia_ellipsoid",
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
