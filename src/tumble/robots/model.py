"""A robot description as tumble reads it: links, joints and the shapes of each link.

The declared values of a link are kept as written (``mass``, ``center_of_mass``,
``inertia``): an invalid tensor is a value the audit must be able to hold, so a
:class:`Link` is not a :class:`~tumble.massprops.MassProperties`. Frames: every
link has its own coordinates (URDF's link frame, MJCF's body frame); a joint
places its child's frame in its parent's; the whole robot is given in the root
link's frame.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import QUOTED_PATH_LENGTH, InputError, quoted, unknown_choice
from tumble.massprops import MassProperties

__all__ = [
    "GEOMETRY_KINDS",
    "Inertial",
    "Joint",
    "Link",
    "Robot",
    "Shape",
    "at_own_mass",
    "rotation_about",
    "shown",
]

Array = NDArray[np.float64]

#: The sets of shapes a link has: those it collides with and those it is drawn with.
GEOMETRY_KINDS = ("collision", "visual")

#: The attributes of URDF's ``<inertia>``, in the order of :attr:`Inertial.values`.
INERTIA_ATTRIBUTES = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


@dataclass(frozen=True)
class Shape:
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
        in the link's coordinates."""
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


def _unit_density(shape: Shape) -> MassProperties:
    from tumble import shapes

    kind, size = shape.kind, shape.size
    if kind == "box":
        return shapes.box(size[0] * size[1] * size[2], size)
    if kind == "cylinder":
        radius, length = size
        return shapes.solid_cylinder(math.pi * radius * radius * length, radius, length)
    if kind == "sphere":
        return shapes.solid_sphere(4.0 / 3.0 * math.pi * size[0] ** 3, size[0])
    if kind == "capsule":
        radius, length = size
        volume = math.pi * radius * radius * (length + 4.0 * radius / 3.0)
        return shapes.capsule(volume, radius, length)
    if kind == "ellipsoid":
        return shapes.ellipsoid(4.0 / 3.0 * math.pi * size[0] * size[1] * size[2], size)
    if kind == "mesh" and shape.vertices is not None and shape.faces is not None:
        return _inline_mesh(shape)[0]
    if kind == "mesh":
        if shape.mesh is None:
            raise InputError("Expected a mesh shape to name its file, got none.")
        return _mesh_solid(shape.mesh, shape.scale)[0]
    raise unknown_choice(
        kind, ("box", "cylinder", "sphere", "capsule", "ellipsoid", "mesh"), "a shape's kind"
    )


def _half_extents(shape: Shape) -> Array:
    """Half the edges of the box around a primitive shape, in its own frame."""
    size = shape.size
    if shape.kind == "box":
        return np.array(size) / 2
    if shape.kind == "cylinder":
        return np.array([size[0], size[0], size[1] / 2])
    if shape.kind == "capsule":
        return np.array([size[0], size[0], size[1] / 2 + size[0]])
    if shape.kind == "sphere":
        return np.full(3, size[0])
    if shape.kind == "ellipsoid":
        return np.array(size)
    return np.zeros(3)


_MESHES: dict[tuple[str, int, tuple[float, ...]], tuple[MassProperties, Array, Array]] = {}


def _inline_mesh(shape: Shape) -> tuple[MassProperties, Array, Array]:
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

        from tumble.mesh import MeshOrientationWarning, declared_scale, from_mesh

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


@dataclass(frozen=True)
class Inertial:
    """A link's ``<inertial>`` as written: the six numbers of ``<inertia>`` in URDF's
    order (ixx, ixy, ixz, iyy, iyz, izz; kg·m², about the centre of mass, in the
    inertial frame), their text, the mass (kg), the origin (``xyz`` m, ``rpy``
    rad, or ``axes`` where the file gives a rotation) and where each element
    starts in the file (byte offsets, for a corrected copy that changes nothing
    else)."""

    mass: float
    xyz: tuple[float, ...]
    rpy: tuple[float, ...]
    values: tuple[float, ...]
    texts: tuple[str, ...] = ()
    offsets: Mapping[str, int] = field(default_factory=dict)
    axes: Array | None = None

    @property
    def rotation(self) -> Array:
        """The inertial frame's axes in the link's (columns): ``axes`` where the
        file gives them as a rotation (MJCF's quaternions), else from ``rpy``."""
        return rotation_from_rpy(self.rpy) if self.axes is None else self.axes

    @property
    def tensor(self) -> Array:
        """The (3, 3) tensor in the inertial frame's axes."""
        xx, xy, xz, yy, yz, zz = self.values
        return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]], dtype=float)


@dataclass(frozen=True)
class Link:
    """A link (URDF) or body (MJCF) with its declared inertial values, raw.

    ``mass`` (kg), ``center_of_mass`` (m, link coordinates) and ``inertia``
    (kg·m², about the centre of mass, link axes) are as the file declares them,
    valid or not; a link that declares nothing has mass 0. ``shapes`` maps
    ``"collision"`` and ``"visual"`` to the link's shapes."""

    name: str
    inertial: Inertial | None
    shapes: Mapping[str, tuple[Shape, ...]]
    line: int = 0

    @property
    def mass(self) -> float:
        """The declared mass, kg (0 where the link declares none)."""
        return 0.0 if self.inertial is None else self.inertial.mass

    @property
    def center_of_mass(self) -> Array:
        """The declared centre of mass, m, link coordinates."""
        return np.zeros(3) if self.inertial is None else np.array(self.inertial.xyz, dtype=float)

    @property
    def inertia(self) -> Array:
        """The declared inertia about the centre of mass, kg·m², link axes."""
        if self.inertial is None:
            return np.zeros((3, 3))
        rotation = self.inertial.rotation
        return rotation @ self.inertial.tensor @ rotation.T

    def geometry(self, kind: str = "collision", mass: Any = None) -> MassProperties:
        """The link's ``kind`` shapes (``"collision"`` or ``"visual"``) as one uniform
        solid, in link coordinates: at ``mass`` (kg; default the declared mass),
        shared among the shapes in proportion to their volumes. Shapes that
        carry their own mass or density (MJCF's geoms) keep it, as MuJoCo counts
        them, and ``mass`` is then ignored. Overlapping shapes count twice.

        Raises
        ------
        InputError
            No shapes of that kind, a shape whose file is missing or unreadable,
            or a mass that is not positive.
        """
        shapes = self._shapes(kind)
        if any(shape.mass is not None or shape.density is not None for shape in shapes):
            parts = [part for part in map(at_own_mass, shapes) if part is not None]
            if not parts:
                raise InputError(
                    f"Expected link {self.name!r} to have {kind} shapes with mass, got only "
                    "massless ones."
                )
            return sum(parts[1:], start=parts[0])
        solids = [shape.unit_density() for shape in shapes]
        volume = sum(solid.mass for solid in solids)
        total = self.mass if mass is None else float(mass)
        if not total > 0:
            raise InputError(
                f"Expected a mass > 0 kg to give link {self.name!r}'s geometry, got {total!r}."
            )
        scaled = [_scaled(solid, total / volume) for solid in solids]
        return sum(scaled[1:], start=scaled[0])

    def volume(self, kind: str = "collision") -> float:
        """The summed volume of the link's ``kind`` shapes, m³."""
        return float(sum(shape.unit_density().mass for shape in self._shapes(kind)))

    def _shapes(self, kind: str) -> tuple[Shape, ...]:
        if kind not in GEOMETRY_KINDS:
            raise unknown_choice(kind, GEOMETRY_KINDS, "`kind`")
        shapes = self.shapes.get(kind, ())
        if not shapes:
            raise InputError(f"Expected link {self.name!r} to have {kind} shapes, got none.")
        return shapes


def _scaled(solid: MassProperties, factor: float) -> MassProperties:
    return MassProperties(solid.mass * factor, solid.center_of_mass, solid.inertia * factor)


def at_own_mass(shape: Shape) -> MassProperties | None:
    """A shape at its own mass, or its density times its volume (MJCF's geoms);
    None for a massless one."""
    solid = shape.unit_density()
    mass = shape.mass if shape.mass is not None else (shape.density or 0.0) * solid.mass
    return _scaled(solid, mass / solid.mass) if mass > 0 else None


@dataclass(frozen=True)
class Joint:
    """A joint: it places ``child``'s frame in ``parent``'s at ``rotation`` and
    ``translation`` (x_parent = R x + t), then moves it by its value about or
    along ``axis`` (a unit vector of that frame). ``kind``: ``"revolute"``,
    ``"continuous"`` (rad), ``"prismatic"`` (m), ``"fixed"``, ``"floating"`` or
    ``"planar"`` (held at their origin). ``mimic``: (joint, multiplier, offset),
    whose value is multiplier × that joint's + offset."""

    name: str
    kind: str
    parent: str
    child: str
    rotation: Array
    translation: Array
    axis: Array
    mimic: tuple[str, float, float] | None = None
    anchor: Array = field(default_factory=lambda: np.zeros(3))
    reference: float = 0.0

    def motion(self, value: float) -> tuple[Array, Array]:
        """The child frame's move at ``value`` (rad or m) in the frame the joint
        places, as (R, t): a turn by ``value − reference`` about the axis through
        ``anchor``, or a slide along it; none for a joint held at its origin."""
        if self.kind in ("revolute", "continuous"):
            turn = rotation_about(self.axis, value - self.reference)
            return turn, self.anchor - turn @ self.anchor
        if self.kind == "prismatic":
            return np.eye(3), self.axis * (value - self.reference)
        return np.eye(3), np.zeros(3)


#: The joint kinds a configuration sets, and what their values are.
MOVING = {"revolute": "angle", "continuous": "angle", "prismatic": "length"}


@dataclass(frozen=True)
class Robot:
    """A robot description: its links and joints by name, in the file's order.

    Attributes
    ----------
    name : the robot's name in the file.
    path : the file read.
    links : ``{name: Link}``.
    joints : ``{name: Joint}``.
    root : the name of the root link (the child of no joint).
    """

    name: str
    path: Path
    links: Mapping[str, Link]
    joints: Mapping[str, Joint]
    root: str

    @cached_property
    def _tree(self) -> tuple[dict[str, list[str]], dict[str, list[Joint]]]:
        """Each link's children in order, and the joints between each child and its
        parent, in the order they move it (MJCF bodies may have several)."""
        children: dict[str, list[str]] = {name: [] for name in self.links}
        joints: dict[str, list[Joint]] = {}
        for joint in self.joints.values():
            if joint.child not in joints:
                children[joint.parent].append(joint.child)
            joints.setdefault(joint.child, []).append(joint)
        return children, joints

    def link_poses(self, joints: Mapping[str, Any] | None = None) -> dict[str, tuple[Array, Array]]:
        """Every link's frame in the root link's, ``{name: (R, t)}`` (x_root = R x + t),
        at the configuration ``joints`` (see :meth:`mass_properties`)."""
        values = self._configuration(joints or {})
        children, between = self._tree
        poses = {self.root: (np.eye(3), np.zeros(3))}
        stack = [self.root]
        while stack:
            parent = stack.pop()
            for child in children[parent]:
                rotation, translation = poses[parent]
                for joint in between[child]:
                    translation = rotation @ joint.translation + translation
                    rotation = rotation @ joint.rotation
                    turn, shift = joint.motion(values.get(joint.name, joint.reference))
                    translation = rotation @ shift + translation
                    rotation = rotation @ turn
                poses[child] = (rotation, translation)
                stack.append(child)
        return poses

    def mass_properties(self, joints: Mapping[str, Any] | None = None) -> MassProperties:
        """The whole robot's mass properties in the root link's frame at a joint
        configuration: ``joints`` maps joint names to values (rad for revolute
        and continuous joints, m for prismatic ones; numbers or strings such as
        ``"30 deg"``); joints not given are at their reference (0; an MJCF joint's
        ``ref``), mimic joints follow theirs.

        Raises
        ------
        InputError
            An unknown joint, a value for a fixed or mimic joint, a link whose
            declared mass or inertia is not physical (``tumble audit`` says
            which and how to correct it), or a robot without mass.
        """
        total: MassProperties | None = None
        for name, (rotation, translation) in self.link_poses(joints).items():
            link = self.links[name]
            if link.mass == 0.0:
                continue
            try:
                own = MassProperties(link.mass, link.center_of_mass, link.inertia)
            except InputError as error:
                raise InputError(
                    f"Expected link {name!r} of {shown(self.path)} to declare physical "
                    f"mass properties, got: {error} (`tumble audit` finds the correction)"
                ) from None
            placed = own.transformed(rotation, translation)
            total = placed if total is None else total + placed
        if total is None:
            raise InputError(f"Expected a robot with mass, got no link with mass in {self.path}.")
        return total

    def _configuration(self, given: Mapping[str, Any]) -> dict[str, float]:
        from tumble.units import to_si

        values: dict[str, float] = {}
        for name, value in given.items():
            joint = self.joints.get(name)
            if joint is None:
                raise unknown_choice(name, self.joints, "a joint of the robot")
            if joint.kind not in MOVING or joint.mimic is not None:
                what = "a mimic joint" if joint.mimic is not None else f"a {joint.kind} joint"
                raise InputError(
                    f"Expected joints that take a value (revolute, continuous, prismatic), "
                    f"got {name!r}, {what}."
                )
            values[name] = to_si(value, MOVING[joint.kind], f"joints[{name!r}]")
        for joint in self.joints.values():
            if joint.mimic is not None and joint.kind in MOVING:
                source, multiplier, offset = joint.mimic
                if source not in self.joints:
                    raise InputError(
                        f"Expected joint {joint.name!r} to mimic a joint of the robot, got "
                        f"{source!r}."
                    )
                values[joint.name] = multiplier * values.get(source, 0.0) + offset
        return values


def shown(path: Any) -> str:
    """A file's path as a message shows it."""
    return quoted(str(path), QUOTED_PATH_LENGTH)


def rotation_from_rpy(rpy: tuple[float, ...]) -> Array:
    """URDF's fixed-axis roll, pitch, yaw (rad): R = Rz(yaw) Ry(pitch) Rx(roll)."""
    roll, pitch, yaw = rpy
    cr, sr, cp, sp, cy, sy = (
        math.cos(roll),
        math.sin(roll),
        math.cos(pitch),
        math.sin(pitch),
        math.cos(yaw),
        math.sin(yaw),
    )
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def rotation_about(axis: Array, angle: float) -> Array:
    """The rotation by ``angle`` (rad) about the unit vector ``axis`` (Rodrigues)."""
    x, y, z = axis
    c, s = math.cos(angle), math.sin(angle)
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)
