"""A robot description as tumble reads it: links and joints (each link's shapes are in
:mod:`tumble.robots.geometry`).

The declared values of a link are kept as written (``mass``, ``center_of_mass``,
``inertia``): an invalid tensor is a value the audit must be able to hold, so a
:class:`Link` is not a :class:`~tumble.massprops.MassProperties`. Frames: every
link has its own coordinates (URDF's link frame, MJCF's body frame); a joint
places its child's frame in its parent's; the whole robot is given in the root
link's frame.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, quoted, unknown_choice
from tumble.massprops import MassProperties
from tumble.robots.geometry import GEOMETRY_KINDS, LinkShape, at_own_mass, scaled, shown

__all__ = [
    "GEOMETRY_KINDS",
    "JOINT_KINDS",
    "Inertial",
    "Joint",
    "Link",
    "LinkShape",
    "Notice",
    "Robot",
    "at_own_mass",
    "mimic_order",
    "rotation_about",
    "shown",
]

Array = NDArray[np.float64]

#: The attributes of URDF's ``<inertia>``, in the order of :attr:`Inertial.values`.
INERTIA_ATTRIBUTES = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


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
    ``"collision"`` and ``"visual"`` to the link's shapes. ``unreadable``: why
    the file's ``<inertial>`` could not be read (its values are then unknown:
    ``inertial`` is None and :meth:`Robot.mass_properties` refuses the link),
    empty where it was read. ``compiled``: the link's mass properties as the
    engine that reads the file compiles them, where they differ from those
    declared (MuJoCo's compiler scales, bounds and balances); None where the
    declared ones are what the engine uses."""

    name: str
    inertial: Inertial | None
    shapes: Mapping[str, tuple[LinkShape, ...]]
    line: int = 0
    unreadable: str = ""
    compiled: Inertial | None = None

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
        """The declared inertia about the centre of mass, kg·m², link axes (entries
        beyond float64 turned by the rotation are infinite, for the audit to refuse)."""
        if self.inertial is None:
            return np.zeros((3, 3))
        rotation = self.inertial.rotation
        with np.errstate(over="ignore", invalid="ignore"):
            return np.asarray(rotation @ self.inertial.tensor @ rotation.T, dtype=float)

    def counted(self) -> Link:
        """The link as :meth:`Robot.mass_properties` counts it: with its
        ``compiled`` values where the engine gives them, else as declared."""
        return (
            self if self.compiled is None else replace(self, inertial=self.compiled, compiled=None)
        )

    def geometry(self, kind: str = "collision", mass: Any = None) -> MassProperties:
        """The link's ``kind`` shapes (``"collision"`` or ``"visual"``) as one uniform
        solid, in link coordinates: at ``mass`` (kg, or a string with units such as
        ``"2 kg"``; default the declared mass),
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
        from tumble.units import to_si

        total = self.mass if mass is None else to_si(mass, "mass", "mass")
        if not total > 0:
            raise InputError(
                f"Expected a mass > 0 kg to give link {self.name!r}'s geometry, got {total!r}."
            )
        scaled_solids = [scaled(solid, total / volume) for solid in solids]
        return sum(scaled_solids[1:], start=scaled_solids[0])

    def volume(self, kind: str = "collision") -> float:
        """The summed volume of the link's ``kind`` shapes, m³."""
        return float(sum(shape.unit_density().mass for shape in self._shapes(kind)))

    def _shapes(self, kind: str) -> tuple[LinkShape, ...]:
        if kind not in GEOMETRY_KINDS:
            raise unknown_choice(kind, GEOMETRY_KINDS, "`kind`")
        shapes = self.shapes.get(kind, ())
        if not shapes:
            raise InputError(f"Expected link {self.name!r} to have {kind} shapes, got none.")
        return shapes


@dataclass(frozen=True)
class Notice:
    """Something in a robot file that its reader could not take as written and read
    another way, or left out (a malformed number outside the inertials, a shape of
    an unknown kind): the audit reports each as a :class:`~tumble.robots.Finding`.

    Attributes
    ----------
    link : the link (or joint) it belongs to, by name.
    code : what it is, a key of :data:`tumble.robots.CODES`.
    message : one sentence: the file's line, what was written, and how it was read.
    line : the line in the file, or in its xacro expansion for a xacro file (0
        where unknown).
    """

    link: str
    code: str
    message: str
    line: int = 0


@dataclass(frozen=True)
class Joint:
    """A joint: it places ``child``'s frame in ``parent``'s at ``rotation`` and
    ``translation`` (x_parent = R x + t), then moves it by its value about or
    along ``axis`` (a unit vector of that frame).

    ``kind``, one of ``JOINT_KINDS``:

    - ``"revolute"``: turns about ``axis``, value in rad, between ``limits``
      (URDF's revolute, MJCF's hinge);
    - ``"continuous"``: turns about ``axis`` without limits, rad (URDF);
    - ``"prismatic"``: slides along ``axis``, value in m (URDF's prismatic,
      MJCF's slide);
    - ``"fixed"``: never moves (URDF);
    - ``"floating"``: free in all six degrees of freedom (URDF's floating,
      MJCF's free joint);
    - ``"planar"``: moves in the plane normal to ``axis`` (URDF);
    - ``"spherical"``: turns about any axis through its origin (PyBullet's
      URDF extension ``spherical``, MJCF's ball joint).

    A configuration gives values only to the kinds in ``MOVING``; the
    others are held at their origin. ``mimic``: (joint, multiplier, offset),
    whose value is multiplier × that joint's + offset. ``limits``: the (lower,
    upper) values the file allows, where it gives them; ``slack``: how far beyond
    each a value still rounds to the digits written (half a unit of the last
    digit: ``1.57`` allows π/2). ``unread``: why the
    file's placement or axis of the joint could not be read (a default stands
    in; poses through the joint are refused), empty where it was read."""

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
    limits: tuple[float, float] | None = None
    slack: tuple[float, float] = (0.0, 0.0)
    unread: str = ""

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


#: Every kind of :class:`Joint`, whatever the file's own word for it.
JOINT_KINDS = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar", "spherical")

#: The joint kinds a configuration sets, and what their values are.
MOVING = {"revolute": "angle", "continuous": "angle", "prismatic": "length"}

#: The SI unit of each kind of joint value in ``MOVING``.
UNITS = {"angle": "rad", "length": "m"}


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
    notices : what the reader could not take as written (:class:`Notice`).
    refusal : why the joints do not make a tree of links that poses can be
        computed on (a link with two parents, a cycle, a duplicate joint name),
        as an error message; empty where they do.
    """

    name: str
    path: Path
    links: Mapping[str, Link]
    joints: Mapping[str, Joint]
    root: str
    notices: tuple[Notice, ...] = ()
    refusal: str = ""

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
        if self.refusal:
            raise InputError(self.refusal)
        values = self._configuration({} if joints is None else joints)
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
        ``ref``), mimic joints follow theirs. Each link counts with its
        ``Link.compiled`` values where it has them, else as declared.

        A value outside a joint's limits (URDF's ``<limit lower upper>``) is
        used, with a :class:`~tumble.errors.JointLimitWarning`.

        Raises
        ------
        InputError
            ``joints`` not a mapping, an unknown joint, a value for a fixed or
            mimic joint, mimic joints that follow each other in a cycle, joints
            that do not make a tree (``refusal``), a link whose inertial
            could not be read or whose declared mass or inertia is not physical
            (``tumble audit`` says which and how to correct it), a joint whose
            placement could not be read with a link of mass beyond it, or a
            robot without mass.
        """
        poses = self.link_poses(joints)
        self._refuse_unread()
        total: MassProperties | None = None
        for name, (rotation, translation) in poses.items():
            link = self.links[name].counted()
            if link.unreadable:
                raise InputError(link.unreadable)
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

    def _refuse_unread(self) -> None:
        """Refuses a joint whose placement could not be read when a link with mass
        (or with an unread inertial) lies beyond it: the pose of that link is unknown."""
        children = self._tree[0]
        for joint in self.joints.values():
            if not joint.unread:
                continue
            stack = [joint.child]
            while stack:
                link = self.links[stack.pop()].counted()
                if link.mass != 0.0 or link.unreadable:
                    raise InputError(
                        f"{joint.unread[:-1]}; link {link.name!r} beyond it has mass, so its "
                        "pose is unknown."
                    )
                stack += children[link.name]

    def _configuration(self, given: Mapping[str, Any]) -> dict[str, float]:
        from tumble.errors import JointLimitWarning
        from tumble.units import to_si

        if not isinstance(given, Mapping):
            raise InputError(
                "Expected `joints` to be a mapping of joint names to values, e.g. "
                f"{{'elbow': '30 deg'}}, got {quoted(given)}."
            )
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
        for name in self._mimic_order:
            source, multiplier, offset = self.joints[name].mimic  # type: ignore[misc]
            values[name] = multiplier * values.get(source, 0.0) + offset
        for name, value in values.items():
            joint = self.joints[name]
            limits, slack = joint.limits, joint.slack
            if limits is not None and not limits[0] - slack[0] <= value <= limits[1] + slack[1]:
                unit = UNITS[MOVING[joint.kind]]
                mimicking = "" if joint.mimic is None else f" (mimicking {joint.mimic[0]!r})"
                warnings.warn(
                    f"Joint {name!r}{mimicking} at {value:g} {unit} is outside its limits "
                    f"[{limits[0]:g}, {limits[1]:g}] {unit}: used as given.",
                    JointLimitWarning,
                    stacklevel=4,
                )
        return values

    @cached_property
    def _mimic_order(self) -> tuple[str, ...]:
        """The moving mimic joints in the order their values are computed (see
        :func:`mimic_order`); refuses a mimic of an unknown joint and mimic
        joints that follow each other in a cycle."""
        for joint in self.joints.values():
            source = None if joint.mimic is None else joint.mimic[0]
            if joint.kind in MOVING and source is not None and source not in self.joints:
                raise InputError(
                    f"Expected joint {joint.name!r} to mimic a joint of the robot, got {source!r}."
                )
        order, cycles = mimic_order(self.joints)
        if cycles:
            raise InputError(
                "Expected mimic joints that follow a joint that moves, got a cycle: "
                f"{shown_cycle(cycles[0])}."
            )
        return order


def mimic_order(
    joints: Mapping[str, Joint],
) -> tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]:
    """The moving mimic joints in an order in which each comes after the mimic
    joint it follows, whatever their order in ``joints``, and the cycles of
    mimic joints that follow each other (a joint that mimics itself is one).

    Returns
    -------
    order : the mimic joints whose values can be computed, sources first.
    cycles : each cycle's joints in the order they follow each other, starting
        from the first met in ``joints``; the joints of a cycle, and those that
        follow one, are in no ``order``.
    """
    follows = {
        name: joint.mimic[0]
        for name, joint in joints.items()
        if joint.mimic is not None and joint.kind in MOVING
    }
    order: list[str] = []
    cycles: list[tuple[str, ...]] = []
    done: set[str] = set()
    broken: set[str] = set()
    for start in follows:
        chain: list[str] = []
        name = start
        while name in follows and name not in done and name not in chain:
            chain.append(name)
            name = follows[name]
        done.update(chain)
        if name in chain:
            cycles.append(tuple(chain[chain.index(name) :]))
            broken.update(chain)
        elif name in broken:
            broken.update(chain)
        else:
            # The chain runs from follower to source: its sources come first.
            order.extend(reversed(chain))
    return tuple(order), tuple(cycles)


def shown_cycle(cycle: tuple[str, ...]) -> str:
    """A cycle of mimic joints as ``'a' -> 'b' -> 'a'``."""
    return " -> ".join(repr(name) for name in (*cycle, cycle[0]))


def rotation_from_rpy(rpy: tuple[float, ...]) -> Array:
    """URDF's fixed-axis roll, pitch, yaw (rad) as a matrix: R = Rz(yaw) Ry(pitch)
    Rx(roll), scipy's extrinsic ``"xyz"`` Euler angles."""
    from scipy.spatial.transform import Rotation

    return np.asarray(Rotation.from_euler("xyz", rpy).as_matrix(), dtype=float)


def rotation_about(axis: Array, angle: float) -> Array:
    """The rotation by ``angle`` (rad) about the unit vector ``axis``."""
    from scipy.spatial.transform import Rotation

    vector = np.asarray(axis, dtype=float) * angle
    return np.asarray(Rotation.from_rotvec(vector).as_matrix(), dtype=float)
