"""Reading a URDF file into a :class:`~tumble.robots.model.Robot`.

URDF is plain XML with a handful of elements (ROS's ``urdfdom`` is the
reference; its rules are followed here: ``rpy`` is roll, pitch, yaw about fixed
axes; a missing ``<origin>`` is the identity, a missing ``<axis>`` is x, a
missing ``<inertial>`` a massless link). It is read with the standard library's
expat parser rather than a URDF library because the audit needs what those
libraries drop or refuse: the numbers as written (an invalid tensor, the digits
given), and the byte offset of each inertial element, so that a corrected copy
changes those elements and nothing else.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from xml.parsers import expat

import numpy as np

from tumble.errors import InputError, quoted
from tumble.robots.model import (
    INERTIA_ATTRIBUTES,
    Inertial,
    Joint,
    Link,
    Robot,
    Shape,
    rotation_from_rpy,
    shown,
)

__all__ = ["read_urdf", "resolve_mesh"]

#: The joint kinds of URDF, and PyBullet's ``spherical`` (held at its origin, as
#: ``floating`` and ``planar`` are).
JOINT_KINDS = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar", "spherical")


class _Element:
    """An element being read: its name, attributes, line and byte offset."""

    __slots__ = ("attributes", "children", "line", "name", "offset")

    def __init__(self, name: str, attributes: dict[str, str], line: int, offset: int) -> None:
        self.name = name
        self.attributes = attributes
        self.line = line
        self.offset = offset
        self.children: list[_Element] = []

    def child(self, name: str) -> _Element | None:
        return next((c for c in self.children if c.name == name), None)

    def all(self, name: str) -> list[_Element]:
        return [c for c in self.children if c.name == name]


def _tree(path: Path, data: bytes) -> _Element:
    parser = expat.ParserCreate()
    root = _Element("", {}, 0, 0)
    stack = [root]

    def start(name: str, attributes: dict[str, str]) -> None:
        element = _Element(name, attributes, parser.CurrentLineNumber, parser.CurrentByteIndex)
        stack[-1].children.append(element)
        stack.append(element)

    def end(name: str) -> None:
        stack.pop()

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    try:
        parser.Parse(data, True)
    except expat.ExpatError as error:
        raise InputError(
            f"Expected {shown(path)} to be well-formed XML, got "
            f"{expat.errors.messages[error.code]} at line {error.lineno}, "
            f"column {error.offset + 1}."
        ) from None
    return root.children[0]


class _Reader:
    """Reads one file's elements, naming the file, line and element in every error."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def where(self, element: _Element, owner: str) -> str:
        return f"{owner} ({self.path.name} line {element.line})"

    def numbers(
        self,
        element: _Element,
        attribute: str,
        count: int,
        owner: str,
        default: tuple[float, ...] | None = None,
    ) -> tuple[float, ...]:
        text = element.attributes.get(attribute)
        if text is None:
            if default is None:
                raise InputError(
                    f"Expected a `{attribute}` attribute on <{element.name}> of "
                    f"{self.where(element, owner)}, got none."
                )
            return default
        parts = text.split()
        try:
            values = tuple(float(part) for part in parts)
        except ValueError:
            values = ()
        if len(values) != count or not all(np.isfinite(values)):
            what = "a finite number" if count == 1 else f"{count} finite numbers"
            hint = " (a xacro expression: run xacro on the file first)" if "$(" in text else ""
            raise InputError(
                f"Expected {what} for `{attribute}` of <{element.name}> of "
                f"{self.where(element, owner)}, got {quoted(text)}{hint}."
            )
        return values

    def origin(
        self, element: _Element | None, owner: str
    ) -> tuple[tuple[float, ...], tuple[float, ...]]:
        origin = None if element is None else element.child("origin")
        if origin is None:
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        return (
            self.numbers(origin, "xyz", 3, owner, (0.0, 0.0, 0.0)),
            self.numbers(origin, "rpy", 3, owner, (0.0, 0.0, 0.0)),
        )

    def inertial(self, link: _Element, owner: str) -> Inertial | None:
        element = link.child("inertial")
        if element is None:
            return None
        xyz, rpy = self.origin(element, owner)
        mass = element.child("mass")
        inertia = element.child("inertia")
        values = tuple(
            self.numbers(inertia, name, 1, owner, (0.0,))[0] if inertia is not None else 0.0
            for name in INERTIA_ATTRIBUTES
        )
        texts = tuple(
            inertia.attributes.get(name, "0") if inertia is not None else "0"
            for name in INERTIA_ATTRIBUTES
        )
        offsets = {"inertial": element.offset}
        for name in ("origin", "mass", "inertia"):
            child = element.child(name)
            if child is not None:
                offsets[name] = child.offset
        return Inertial(
            mass=self.numbers(mass, "value", 1, owner, (0.0,))[0] if mass is not None else 0.0,
            xyz=xyz,
            rpy=rpy,
            values=values,
            texts=texts,
            offsets=offsets,
        )

    def shapes(self, link: _Element, kind: str, owner: str) -> tuple[Shape, ...]:
        found = []
        for element in link.all(kind):
            geometry = element.child("geometry")
            if geometry is None or not geometry.children:
                continue
            xyz, rpy = self.origin(element, owner)
            rotation, translation = rotation_from_rpy(rpy), np.array(xyz)
            shape = geometry.children[0]
            if shape.name == "box":
                size = self.numbers(shape, "size", 3, owner)
                found.append(Shape("box", size, rotation, translation))
            elif shape.name in ("cylinder", "capsule"):
                radius = self.numbers(shape, "radius", 1, owner)[0]
                length = self.numbers(shape, "length", 1, owner)[0]
                found.append(Shape(shape.name, (radius, length), rotation, translation))
            elif shape.name == "sphere":
                found.append(
                    Shape("sphere", self.numbers(shape, "radius", 1, owner), rotation, translation)
                )
            elif shape.name == "mesh":
                name = shape.attributes.get("filename", "")
                scale = self.numbers(shape, "scale", 3, owner, (1.0, 1.0, 1.0))
                found.append(
                    Shape("mesh", (), rotation, translation, resolve_mesh(name, self.path), scale)
                )
        return tuple(found)


def read_urdf(path: Path) -> Robot:
    """The robot of a URDF file (see :mod:`tumble.robots.urdf`)."""
    try:
        data = path.read_bytes()
    except OSError as error:
        raise InputError(
            f"Expected a readable robot file, got {shown(path)}: {error.strerror}."
        ) from None
    top = _tree(path, data)
    if top.name != "robot":
        raise InputError(
            f"Expected a URDF robot (a <robot> root element) in {shown(path)}, got <{top.name}>."
        )
    reader = _Reader(path)
    links: dict[str, Link] = {}
    for element in top.all("link"):
        name = element.attributes.get("name")
        if not name:
            raise InputError(
                f"Expected a name on the <link> at line {element.line} of {path.name}, got none."
            )
        if name in links:
            raise InputError(
                f"Expected one link named {name!r} in {path.name}, got two (line {element.line})."
            )
        owner = f"link {name!r}"
        links[name] = Link(
            name=name,
            inertial=reader.inertial(element, owner),
            shapes={kind: reader.shapes(element, kind, owner) for kind in ("collision", "visual")},
            line=element.line,
        )
    if not links:
        raise InputError(f"Expected a robot with links in {shown(path)}, got none.")
    joints = _joints(reader, top, links)
    return Robot(
        top.attributes.get("name", path.stem), path, links, joints, _root(path, links, joints)
    )


def _joints(reader: _Reader, top: _Element, links: Mapping[str, Link]) -> dict[str, Joint]:
    joints: dict[str, Joint] = {}
    for element in top.all("joint"):
        name = element.attributes.get("name", "")
        owner = f"joint {name!r}"
        kind = element.attributes.get("type", "")
        if kind not in JOINT_KINDS:
            raise InputError(
                f"Expected the type of {reader.where(element, owner)} to be one of "
                f"{', '.join(JOINT_KINDS)}, got {quoted(kind)}."
            )
        ends = []
        for end in ("parent", "child"):
            child = element.child(end)
            link = None if child is None else child.attributes.get("link")
            if link not in links:
                raise InputError(
                    f"Expected the {end} of {reader.where(element, owner)} to be a link of the "
                    f"robot, got {quoted(link) if link else 'none'}."
                )
            ends.append(link)
        xyz, rpy = reader.origin(element, owner)
        axis_element = element.child("axis")
        axis = np.array(
            reader.numbers(axis_element, "xyz", 3, owner, (1.0, 0.0, 0.0))
            if axis_element is not None
            else (1.0, 0.0, 0.0)
        )
        size = float(np.linalg.norm(axis))
        if kind in ("revolute", "continuous", "prismatic") and not size > 0:
            raise InputError(
                f"Expected a non-zero axis for {reader.where(element, owner)}, got {axis.tolist()}."
            )
        mimic_element = element.child("mimic")
        mimic = None
        if mimic_element is not None:
            mimic = (
                mimic_element.attributes.get("joint", ""),
                reader.numbers(mimic_element, "multiplier", 1, owner, (1.0,))[0],
                reader.numbers(mimic_element, "offset", 1, owner, (0.0,))[0],
            )
        parent_link, child_link = str(ends[0]), str(ends[1])
        direction = axis / size if size > 0 else axis
        placement = rotation_from_rpy(rpy), np.array(xyz)
        joints[name] = Joint(name, kind, parent_link, child_link, *placement, direction, mimic)
    return joints


def _root(path: Path, links: Mapping[str, Link], joints: Mapping[str, Joint]) -> str:
    """The one link that is no joint's child; refuses a link with two parents, a
    cycle and links joined to nothing."""
    parent: dict[str, str] = {}
    for joint in joints.values():
        if joint.child in parent:
            raise InputError(
                f"Expected a tree of links in {path.name}, got link {joint.child!r} as the child "
                f"of two joints."
            )
        parent[joint.child] = joint.name
    roots = [name for name in links if name not in parent]
    if not roots:
        raise InputError(
            f"Expected a tree of links in {path.name}, got a cycle of joints (no root link)."
        )
    reached = {roots[0]}
    children: dict[str, list[str]] = {}
    for joint in joints.values():
        children.setdefault(joint.parent, []).append(joint.child)
    stack = [roots[0]]
    while stack:
        for child in children.get(stack.pop(), []):
            if child not in reached:
                reached.add(child)
                stack.append(child)
    if len(roots) > 1 or len(reached) < len(links):
        unjoined = [name for name in links if name not in reached]
        what = "a cycle of joints among" if len(roots) == 1 else "no joint to"
        raise InputError(
            f"Expected a tree of links joined to root link {roots[0]!r} in {path.name}, got "
            f"{what} {', '.join(repr(n) for n in unjoined[:5])}"
            + (f" and {len(unjoined) - 5} more" if len(unjoined) > 5 else "")
            + "."
        )
    return roots[0]


def resolve_mesh(name: str, urdf: Path) -> Path:
    """The file a URDF's mesh ``filename`` names: ``package://pkg/rest`` looked up in
    the URDF's parent folders (a folder named ``pkg``, or one holding it) and in
    ``ROS_PACKAGE_PATH``; ``file://`` paths as they are; others relative to the
    URDF's folder. A file that is found nowhere comes back as the first place
    looked, for the error to name."""
    if name.startswith("file://"):
        return Path(name[len("file://") :])
    if not name.startswith("package://"):
        return urdf.parent / name
    package, _, rest = name[len("package://") :].partition("/")
    places = []
    for folder in urdf.resolve().parents:
        places += [folder / rest] if folder.name == package else []
        places.append(folder / package / rest)
    for entry in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep):
        if entry:
            places += [Path(entry) / package / rest, Path(entry) / rest]
    return next((place for place in places if place.is_file()), places[0])
