"""From a validated scenario to the library's objects: the body's mass properties,
a triangle mesh to draw it, the initial state and the torque model.

Errors raised by the library while building (a mesh with holes, a part whose
inertia breaks the triangle inequality) are re-raised as
:class:`~tumble.scenario.ScenarioError` naming the key path of the part.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.config import dotted
from tumble.errors import InputError
from tumble.massprops import MassProperties
from tumble.scenario.files import BUILTINS, ScenarioError, where
from tumble.scenario.schema import (
    Attitude,
    InertiaBody,
    MeshBody,
    PartsBody,
    PointsBody,
    Scenario,
    ShapeBody,
)

if TYPE_CHECKING:
    from tumble.scenario.files import LoadedScenario

__all__ = [
    "Geometry",
    "InitialState",
    "body_geometry",
    "initial_state",
    "mass_properties",
    "torque_model",
]

Array = NDArray[np.float64]


@contextmanager
def at_key(loaded: LoadedScenario | None, *path: str | int) -> Iterator[None]:
    """Re-raise the library's InputError as a ScenarioError naming the key ``path``
    (and its line in the scenario's text)."""
    try:
        yield
    except ScenarioError:
        raise
    except InputError as exc:
        place = where(loaded, path) if loaded is not None else f"`{dotted(path)}`"
        raise ScenarioError(f"{place}: {exc}") from None


@dataclass(frozen=True)
class Geometry:
    """A triangle mesh in body coordinates, m: ``vertices`` (n, 3), ``faces`` (m, 3);
    ``exact`` is False where it stands in for the body (an ellipsoid of equal inertia,
    spheres for point masses)."""

    vertices: Array
    faces: NDArray[np.int64]
    exact: bool = True


def _rotation(attitude: Attitude | None) -> Any:
    from scipy.spatial.transform import Rotation

    if attitude is None:
        return Rotation.identity()
    return Rotation.from_quat(attitude.quaternion_wxyz(), scalar_first=True)


def _mesh_path(body: MeshBody, folder: Path) -> Path:
    """The mesh file: relative to the scenario's folder, else one shipped with tumble."""
    path = Path(body.mesh)
    if not path.is_absolute():
        for base in (folder, BUILTINS.folder()):
            if (base / path).is_file():
                return base / path
        raise InputError(f"Expected a mesh file, got {body.mesh!r} (not found in {folder}).")
    if not path.is_file():
        raise InputError(f"Expected a mesh file, got {body.mesh!r} (no such file).")
    return path


def mass_properties(
    spec: Any,
    folder: Path,
    loaded: LoadedScenario | None = None,
    path: tuple[str | int, ...] = ("body",),
) -> MassProperties:
    """The mass properties of a body of the schema (parts added in the same coordinates)."""
    from tumble import shapes
    from tumble.massprops import point_masses

    with at_key(loaded, *path):
        if isinstance(spec, PartsBody):
            parts = [
                mass_properties(part, folder, loaded, (*path, "parts", k))
                for k, part in enumerate(spec.parts)
            ]
            result: MassProperties = sum(parts[1:], parts[0])
        elif isinstance(spec, ShapeBody):
            function = getattr(shapes, spec.shape.replace("-", "_"))
            result = function(spec.mass, **spec.dimensions())
        elif isinstance(spec, MeshBody):
            from tumble.mesh import from_mesh  # numba kernels: load only for meshes

            result = from_mesh(
                _mesh_path(spec, folder), density=spec.density, mass=spec.mass, units=spec.units
            )
        elif isinstance(spec, PointsBody):
            result = point_masses(list(spec.masses), [list(p) for p in spec.positions])
        elif isinstance(spec, InertiaBody):
            result = MassProperties(spec.mass, spec.center_of_mass, spec.inertia)
        else:  # pragma: no cover - the schema admits no other body
            raise InputError(f"Expected a body, got {type(spec).__name__}.")
        if spec.rotation is not None or spec.translation is not None:
            result = result.transformed(_rotation(spec.rotation), spec.translation)
        return result


# ------------------------------------------------------------------ drawing
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


def _sphere(radius: float = 1.0, rings: int = 16, sections: int = 32) -> Mesh:
    theta = np.linspace(0.0, np.pi, rings + 1)
    profile = np.column_stack((radius * np.sin(theta), -radius * np.cos(theta)))
    profile[0, 0] = profile[-1, 0] = 0.0
    return revolve(profile, sections)


def _cylinder(radius: float, height: float, sections: int = 48) -> Mesh:
    h = 0.5 * height
    return revolve([(0.0, -h), (radius, -h), (radius, h), (0.0, h)], sections)


def _torus(major: float, minor: float, sections: int = 48, tube: int = 16) -> Mesh:
    a = np.linspace(0.0, 2.0 * np.pi, tube, endpoint=False)
    return revolve(np.column_stack((major + minor * np.cos(a), minor * np.sin(a))), sections, True)


def _box(size: Any) -> Mesh:
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    faces = np.array(
        [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
         [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]],
        dtype=np.int64,
    )  # fmt: skip
    return corners * (0.5 * np.asarray(size, dtype=float)), faces


def equal_inertia_ellipsoid(mp: MassProperties) -> Geometry:
    """The uniform solid ellipsoid with the body's mass and inertia, at its centre of mass.

    Its semi-axes along the principal axes are ``a_i² = 5 (I_j + I_k − I_i) / (2 m)``.
    """
    moments, axes = mp.principal()
    squares = np.array([5.0 * (moments.sum() - 2.0 * m) / (2.0 * mp.mass) for m in moments])
    floor = 0.02 * float(np.sqrt(np.max(squares)))
    semi = np.maximum(np.sqrt(np.maximum(squares, 0.0)), floor)
    vertices, faces = _sphere()
    return Geometry((vertices * semi) @ axes.T + mp.center_of_mass, faces, exact=False)


def _shape_mesh(spec: ShapeBody) -> Mesh:
    """A drawing of a solid of :mod:`tumble.shapes`, centred like it (on its centre of mass)."""
    d = spec.dimensions()
    name = spec.shape
    if name == "box":
        return _box(d["size"])
    if name == "solid-cylinder":
        return _cylinder(d["radius"], d["height"])
    if name == "hollow-cylinder":
        h = 0.5 * d["height"]
        inner, outer = d["inner_radius"], d["outer_radius"]
        return revolve([(inner, -h), (outer, -h), (outer, h), (inner, h)], closed=True)
    if name in ("solid-sphere", "spherical-shell"):
        return _sphere(d["radius"])
    if name == "hollow-sphere":
        return _sphere(d["outer_radius"])
    if name == "solid-cone":
        # Apex at +z, centre of mass (a quarter of the height above the base) at the origin.
        h = d["height"]
        return revolve([(0.0, -0.25 * h), (d["radius"], -0.25 * h), (0.0, 0.75 * h)])
    if name == "thin-rod":
        return _cylinder(d["length"] / 80.0, d["length"], sections=12)
    if name == "thin-disk":
        return _cylinder(d["radius"], d["radius"] / 40.0)
    if name == "thin-ring":
        return _torus(d["radius"], d["radius"] / 30.0, tube=8)
    if name == "ellipsoid":
        vertices, faces = _sphere()
        return vertices * np.asarray(d["semi_axes"]), faces
    if name == "torus":
        return _torus(d["major_radius"], d["minor_radius"])
    if name == "capsule":
        r, h = d["radius"], 0.5 * d["cylinder_height"]
        theta = np.linspace(0.0, 0.5 * np.pi, 9)
        bottom = [(r * np.sin(t), -h - r * np.cos(t)) for t in theta]
        top = [(r * np.cos(t), h + r * np.sin(t)) for t in theta]
        profile = np.array(bottom + top)
        profile[0, 0] = profile[-1, 0] = 0.0
        return revolve(profile)
    # A regular tetrahedron: vertices (a / √8)(±1, ±1, ±1) with an even number of minus signs.
    a = d["edge"] / np.sqrt(8.0)
    vertices = a * np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
    return vertices, np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]], dtype=np.int64)


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
        pieces.append(_shape_mesh(spec))
    elif isinstance(spec, MeshBody):
        import trimesh

        mesh_file: Any = trimesh.load(_mesh_path(spec, folder), force="mesh", process=False)
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
        ball, ball_faces = _sphere(radius, rings=8, sections=12)
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
        vertices = _rotation(spec.rotation).apply(vertices)
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


# ------------------------------------------------------------------ state, torques
@dataclass(frozen=True)
class InitialState:
    """ω0 in body axes (rad/s) and the attitude quaternion ``[w, x, y, z]``, body → space."""

    omega: Array
    attitude: Array


def initial_state(scenario: Scenario) -> InitialState:
    """The initial ω (body axes) and attitude of a scenario."""
    from scipy.spatial.transform import Rotation

    attitude = scenario.initial.attitude
    q = np.array(attitude.quaternion_wxyz() if attitude is not None else (1.0, 0.0, 0.0, 0.0))
    omega = np.asarray(scenario.initial.omega, dtype=float)
    if scenario.initial.omega_frame == "space":
        omega = Rotation.from_quat(q, scalar_first=True).inv().apply(omega)
    return InitialState(omega, q)


def torque_model(scenario: Scenario, loaded: LoadedScenario | None = None) -> Any:
    """The sum of the scenario's ``[[torques]]`` (models of the registry,
    :data:`tumble.torques.TORQUES`), or None."""
    from tumble.torques import TORQUES

    terms = []
    for k, torque in enumerate(scenario.torques):
        with at_key(loaded, "torques", k):
            terms.append(TORQUES[torque.type](**torque.values))
    return sum(terms[1:], terms[0]) if terms else None
