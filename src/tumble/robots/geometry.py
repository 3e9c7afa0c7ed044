"""A robot link's shapes, and each shape as a uniform solid: the collision and
visual shapes of URDF's links and MJCF's geoms, in the link's coordinates, with
the mesh files they name read once a process."""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble import shapes as primitives
from tumble.errors import QUOTED_PATH_LENGTH, InputError, quoted, unknown_choice
from tumble.massprops import MassProperties

__all__ = ["GEOMETRY_KINDS", "LinkShape", "at_own_mass", "scaled", "shown"]

Array = NDArray[np.float64]

#: The sets of shapes a link has: those it collides with and those it is drawn with.
GEOMETRY_KINDS = ("collision", "visual")


@dataclass(frozen=True)
class LinkShape:
    """One collision or visual shape of a link, in the link's coordinates.

    ``kind`` is ``"box"`` (``size`` its three edges, m), ``"cylinder"`` (radius,
    length; axis z), ``"sphere"`` (radius), ``"capsule"`` (radius, length of the
    cylinder between the caps; axis z), ``"ellipsoid"`` (semi-axes) or ``"mesh"``
    (``mesh`` the file, ``scale`` its three factors). ``rotation`` and
    ``translation`` place the shape's frame in the link's (x_link = R x + t).
    ``mass`` and ``density`` are the shape's own where the file gives them
    (MJCF's geoms); a URDF's shapes share their link's declared mass in
    proportion to their volumes."""

    kind: str
    size: tuple[float, ...] = ()
    rotation: Array = field(default_factory=lambda: np.eye(3))
    translation: Array = field(default_factory=lambda: np.zeros(3))
    mesh: Path | None = None
    scale: tuple[float, ...] = (1.0, 1.0, 1.0)
    mass: float | None = None
    density: float | None = None
    vertices: Array | None = None
    faces: NDArray[np.int64] | None = None

    def unit_density(self) -> MassProperties:
        """The shape as a solid of density 1 kg/m³ (its mass is its volume in m³),
        in the link's coordinates.

        Raises
        ------
        InputError
            A shape so large that its volume or inertia overflows float64, or
            whose mesh file is missing or unreadable.
        """
        if self.kind != "mesh":
            edges = 2.0 * _half_extents(self)
            with np.errstate(over="ignore", invalid="ignore"):
                # Volume ~ edge³ and inertia ~ volume × edge² at density 1.
                largest = float(np.max(np.abs(edges))) if edges.size else 0.0
                bound = float(np.prod(np.abs(edges))) * largest * largest
            if not math.isfinite(bound):
                sizes = " ".join(f"{value:g}" for value in self.size)
                raise InputError(
                    f"Expected a {self.kind} small enough for its volume and inertia to be "
                    f"finite in float64, got size {sizes} m."
                )
        return _unit_density(self).transformed(self.rotation, self.translation)

    def corners(self) -> Array:
        """Points (n, 3) whose box holds the shape, in the link's coordinates: the
        corners of the box around it in its own frame, placed."""
        half = _half_extents(self)
        if self.kind == "mesh" and self.vertices is not None:
            low, high = _inline_mesh(self)[1:]
        elif self.kind == "mesh":
            low, high = _mesh_solid(self.mesh, self.scale)[1:]  # type: ignore[arg-type]
        else:
            low, high = -half, half
        signs = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)])
        own = np.where(signs == 0, low, high)
        return own @ self.rotation.T + self.translation

    @property
    def label(self) -> str:
        """How a message names the shape: its kind, or its mesh file."""
        return f"mesh {self.mesh}" if self.mesh is not None else self.kind


#: The primitives of robot files, by the files' words, as the catalogue's
#: (:data:`tumble.shapes.SHAPE_KINDS`): its name and its dimensions from the file's
#: sizes (a cylinder's and a capsule's ``length`` is the catalogue's ``height`` and
#: ``cylinder_height``).
PRIMITIVES: dict[str, tuple[str, Callable[[tuple[float, ...]], dict[str, Any]]]] = {
    "box": ("box", lambda size: {"size": tuple(size)}),
    "cylinder": ("solid-cylinder", lambda size: {"radius": size[0], "height": size[1]}),
    "sphere": ("solid-sphere", lambda size: {"radius": size[0]}),
    "capsule": ("capsule", lambda size: {"radius": size[0], "cylinder_height": size[1]}),
    "ellipsoid": ("ellipsoid", lambda size: {"semi_axes": tuple(size)}),
}


def _primitive(shape: LinkShape) -> primitives.Shape:
    """A primitive shape as the catalogue's :class:`tumble.shapes.Shape` (its sizes
    not checked: its closed form checks them when it is used)."""
    name, dimensions = PRIMITIVES[shape.kind]
    return primitives.Shape(primitives.SHAPE_KINDS[name], dimensions(shape.size))


def _unit_density(shape: LinkShape) -> MassProperties:
    kind = shape.kind
    if kind in PRIMITIVES:
        return _primitive(shape).at_density(1.0)
    if kind == "mesh" and shape.vertices is not None and shape.faces is not None:
        return _inline_mesh(shape)[0]
    if kind == "mesh":
        if shape.mesh is None:
            raise InputError("Expected a mesh shape to name its file, got none.")
        return _mesh_solid(shape.mesh, shape.scale)[0]
    raise unknown_choice(kind, (*PRIMITIVES, "mesh"), "a shape's kind")


def _half_extents(shape: LinkShape) -> Array:
    """Half the edges of the box around a primitive shape, in its own frame (the
    primitives of robot files are centred on their origin)."""
    if shape.kind not in PRIMITIVES:
        return np.zeros(3)
    return _primitive(shape).bounding_box[1]


_MESHES: dict[tuple[str, int, tuple[float, ...]], tuple[MassProperties, Array, Array]] = {}


def _inline_mesh(shape: LinkShape) -> tuple[MassProperties, Array, Array]:
    """A mesh given by its arrays (MJCF's compiled meshes) at density 1, and its box."""
    from tumble.mesh import mesh_mass_properties

    vertices = np.asarray(shape.vertices, dtype=float) * np.asarray(shape.scale)
    solid = mesh_mass_properties(
        vertices, np.asarray(shape.faces), density=1.0, label="a mesh geom"
    )
    return solid, vertices.min(axis=0), vertices.max(axis=0)


def _mesh_solid(path: Path, scale: tuple[float, ...]) -> tuple[MassProperties, Array, Array]:
    """A mesh file's solid at density 1, its vertices scaled by ``scale``, and the
    corners of the box around them; read once a process for each file (as last
    modified) and scale: a robot's legs share their meshes."""
    try:
        stamp = path.stat().st_mtime_ns
    except OSError as error:
        raise InputError(
            f"Expected the mesh file {shown(path)} to exist, got {error.strerror}."
        ) from error
    key = (str(path), stamp, scale)
    if key not in _MESHES:
        import trimesh

        from tumble.mesh import (
            MeshOrientationWarning,
            check_mesh_file,
            declared_scale,
            from_mesh,
        )

        # Before a byte is read: a FIFO, a sparse file, a file beyond the memory budget.
        check_mesh_file(path, "the mesh file")
        try:
            loaded = trimesh.load(path, force="mesh", process=False)
        except Exception as error:  # trimesh raises many kinds for unreadable files
            raise InputError(
                f"Expected a readable mesh file, got {shown(path)}: {error}"
            ) from error
        matrix = np.eye(4)
        matrix[:3, :3] = np.diag(scale)
        loaded.apply_transform(matrix)
        with warnings.catch_warnings():
            # A mirrored mesh (a negative scale) is inside out: reversed, as meant.
            warnings.simplefilter("ignore", MeshOrientationWarning)
            try:
                solid = from_mesh(loaded, density=1.0)
            except InputError as error:
                # Read from a loaded mesh, its messages say "mesh": name the file.
                text = str(error).replace("mesh", f"the mesh {shown(path)}", 1)
                raise type(error)(text) from None
        # The box in metres: from_mesh scales by the unit the file declares (COLLADA's).
        unit = declared_scale(loaded) or 1.0
        low, high = unit * np.asarray(loaded.bounds, dtype=float)
        _MESHES[key] = (solid, low, high)
    return _MESHES[key]


def scaled(solid: MassProperties, factor: float) -> MassProperties:
    """``solid`` with its mass and inertia times ``factor`` (its centre of mass kept)."""
    return MassProperties(solid.mass * factor, solid.center_of_mass, solid.inertia * factor)


def at_own_mass(shape: LinkShape) -> MassProperties | None:
    """A shape at its own mass, or its density times its volume (MJCF's geoms);
    None for a massless one."""
    solid = shape.unit_density()
    mass = shape.mass if shape.mass is not None else (shape.density or 0.0) * solid.mass
    return scaled(solid, mass / solid.mass) if mass > 0 else None


def shown(path: Any) -> str:
    """A file's path as a message shows it."""
    return quoted(str(path), QUOTED_PATH_LENGTH)
