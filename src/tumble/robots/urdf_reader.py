"""Reading the parts of a URDF's elements: numbers, placements, inertials, shapes.

A :class:`Reader` reads one file's elements (:mod:`tumble.robots.elements`),
naming the file, line and element in every error, and gathers the notices of
what it read another way than urdfdom does (see :mod:`tumble.robots.urdf`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tumble.errors import InputError, quoted
from tumble.robots.elements import Element
from tumble.robots.model import INERTIA_ATTRIBUTES, Inertial, LinkShape, Notice, rotation_from_rpy
from tumble.robots.ros import find_package
from tumble.robots.urdf_numbers import atof, pybullet_numbers, shown_numbers, urdf_numbers

__all__ = ["SHAPE_SIZES", "Owner", "Reader", "resolve_mesh"]


@dataclass(frozen=True)
class Owner:
    """The link or joint an element belongs to, named in messages as ``link 'name'``."""

    kind: str
    name: str

    def __str__(self) -> str:
        return f"{self.kind} {self.name!r}"


class Reader:
    """Reads one file's elements, naming the file, line and element in every error,
    and gathers the notices of what it read another way.

    ``xacro``: the elements are those of the file's xacro expansion, whose lines
    are not the file's: messages say so."""

    def __init__(
        self, path: Path, packages: Mapping[str, Path] | None = None, xacro: bool = False
    ) -> None:
        self.path = path
        self.packages = packages
        self.xacro = xacro
        self.notices: list[Notice] = []

    def at(self, line: int | str) -> str:
        """Where ``line`` is (a number, or "lines 3 and 9"), for a message: in the
        file, or in its xacro expansion (the file's own lines are not known there)."""
        what = str(line) if isinstance(line, str) else f"line {line}"
        return f"{what} of the xacro expansion" if self.xacro else what

    def where(self, element: Element, owner: Owner) -> str:
        return f"{owner} ({self.path.name} {self.at(element.line)})"

    def opening(self, line: int) -> str:
        """A notice's opening, "Line 14" or "Line 14 of the xacro expansion"."""
        return self.at(line).capitalize()

    def expected(self, element: Element, attribute: str, count: int, owner: Owner) -> str:
        """The message for an attribute that is not ``count`` numbers as urdfdom reads them."""
        text = element.attributes.get(attribute, "")
        what = "a finite number" if count == 1 else f"{count} finite numbers"
        hint = " (a xacro expression: run xacro on the file first)" if "$" in text else ""
        return (
            f"Expected {what} for `{attribute}` of <{element.name}> of "
            f"{self.where(element, owner)}, got {quoted(text)}{hint}."
        )

    def missing(self, element: Element, attribute: str, owner: Owner) -> str:
        return (
            f"Expected a `{attribute}` attribute on <{element.name}> of "
            f"{self.where(element, owner)}, got none."
        )

    def numbers(
        self,
        element: Element,
        attribute: str,
        count: int,
        owner: Owner,
        default: tuple[float, ...] | None = None,
    ) -> tuple[float, ...]:
        """``count`` numbers as urdfdom reads them; refuses anything else."""
        text = element.attributes.get(attribute)
        if text is None:
            if default is None:
                raise InputError(self.missing(element, attribute, owner))
            return default
        values = urdf_numbers(text, count)
        if values is None:
            raise InputError(self.expected(element, attribute, count, owner))
        return values

    def lenient(
        self,
        element: Element,
        attribute: str,
        count: int,
        owner: Owner,
        default: tuple[float, ...] | None,
    ) -> tuple[tuple[float, ...] | None, str]:
        """``count`` numbers outside an inertial: as urdfdom reads them, or else as
        PyBullet reads them where that reading is what was meant (commas, more
        numbers than needed), or else ``default`` (None: nothing). Each reading
        other than urdfdom's is a notice. Returns the numbers and, where they are
        not the file's, why (an error message), else ""."""
        text = element.attributes.get(attribute)
        if text is None:
            if default is None:
                raise InputError(self.missing(element, attribute, owner))
            return default, ""
        values = urdf_numbers(text, count)
        if values is not None:
            return values, ""
        reading, meant = pybullet_numbers(text, count)
        if attribute == "scale" and reading is None:
            # PyBullet's fallback for a mesh scale of one number: the same on every axis.
            value, meant = atof(text.strip())
            reading = (value, value, value) if value else (0.0, 0.0, 0.0)
        what = "a number" if count == 1 else f"{count} numbers"
        pybullet = (
            "PyBullet refuses it" if reading is None else f"PyBullet reads {shown_numbers(reading)}"
        )
        if reading is not None and meant:
            how, values, unread = f"{pybullet}, and so does tumble", reading, ""
        elif default is not None:
            how = f"{pybullet}{'' if reading is None else ', not what was written'}; tumble reads "
            how += f"the default {shown_numbers(default)}"
            if owner.kind == "joint" and element.name in ("origin", "axis"):
                how += " and refuses the poses of links with mass beyond the joint"
            values, unread = default, self.expected(element, attribute, count, owner)
        else:
            how = f"{pybullet}{'' if reading is None else ', not what was written'}; tumble "
            how += "leaves the shape out"
            values, unread = None, self.expected(element, attribute, count, owner)
        hint = " (a xacro expression: run xacro on the file first)" if "$" in text else ""
        self.notices.append(
            Notice(
                owner.name,
                "malformed-number",
                f"{self.opening(element.line)}: `{attribute}` of <{element.name}> of {owner} is "
                f"{quoted(text)}{hint}, not {what} as URDF writes them (urdfdom refuses "
                f"the file); {how}.",
                element.line,
            )
        )
        return values, unread

    def placement(
        self, element: Element | None, owner: Owner
    ) -> tuple[tuple[float, ...], tuple[float, ...], str]:
        """The ``<origin>`` of a joint, visual or collision, read leniently: xyz, rpy
        and why they are not the file's ("" where they are)."""
        origin = None if element is None else element.child("origin")
        if origin is None:
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), ""
        xyz, unread_xyz = self.lenient(origin, "xyz", 3, owner, (0.0, 0.0, 0.0))
        rpy, unread_rpy = self.lenient(origin, "rpy", 3, owner, (0.0, 0.0, 0.0))
        return xyz, rpy, unread_xyz or unread_rpy  # type: ignore[return-value]

    def inertial(self, link: Element, owner: Owner) -> tuple[Inertial | None, str]:
        """The link's ``<inertial>`` as urdfdom reads it, or None and why it cannot
        be read (a missing element or attribute, a number urdfdom refuses)."""
        element = link.child("inertial")
        if element is None:
            return None, ""
        try:
            origin = element.child("origin")
            xyz, rpy = (
                ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
                if origin is None
                else (
                    self.numbers(origin, "xyz", 3, owner, (0.0, 0.0, 0.0)),
                    self.numbers(origin, "rpy", 3, owner, (0.0, 0.0, 0.0)),
                )
            )
            mass, inertia = element.child("mass"), element.child("inertia")
            for name, child in (("mass", mass), ("inertia", inertia)):
                if child is None:
                    raise InputError(
                        f"Expected a <{name}> in the <inertial> of "
                        f"{self.where(element, owner)}, got none."
                    )
            assert mass is not None and inertia is not None
            values = tuple(self.numbers(inertia, name, 1, owner)[0] for name in INERTIA_ATTRIBUTES)
            weight = self.numbers(mass, "value", 1, owner)[0]
        except InputError as error:
            reason = str(error)
            self.notices.append(
                Notice(
                    owner.name,
                    "unreadable-inertial",
                    f"{reason[:-1]}: urdfdom refuses the file, and the inertial is not judged.",
                    element.line,
                )
            )
            return None, reason
        offsets = {"inertial": element.offset}
        for name in ("origin", "mass", "inertia"):
            child = element.child(name)
            if child is not None:
                offsets[name] = child.offset
        return (
            Inertial(
                mass=weight,
                xyz=xyz,
                rpy=rpy,
                values=values,
                texts=tuple(inertia.attributes[name] for name in INERTIA_ATTRIBUTES),
                offsets=offsets,
            ),
            "",
        )

    def shapes(self, link: Element, kind: str, owner: Owner) -> tuple[LinkShape, ...]:
        found = []
        for element in link.all(kind):
            geometry = element.child("geometry")
            if geometry is None or not geometry.children:
                continue
            xyz, rpy, _ = self.placement(element, owner)
            rotation, translation = rotation_from_rpy(rpy), np.array(xyz)
            shape = geometry.children[0]
            if shape.name not in SHAPE_SIZES:
                self.notices.append(
                    Notice(
                        owner.name,
                        "unknown-geometry",
                        f"{self.opening(shape.line)}: <{shape.name}> in a <{kind}> of {owner} "
                        f"is no shape of URDF ({', '.join(SHAPE_SIZES)}): left out of its "
                        "geometry.",
                        shape.line,
                    )
                )
                continue
            size: tuple[float, ...] = ()
            for attribute, count in SHAPE_SIZES[shape.name]:
                values, _ = self.lenient(shape, attribute, count, owner, None)
                if values is None:
                    break
                size += values
            else:
                if shape.name != "mesh":
                    found.append(LinkShape(shape.name, size, rotation, translation))
                    continue
                scale, _ = self.lenient(shape, "scale", 3, owner, (1.0, 1.0, 1.0))
                mesh = resolve_mesh(shape.attributes.get("filename", ""), self.path, self.packages)
                found.append(LinkShape("mesh", (), rotation, translation, mesh, scale))  # type: ignore[arg-type]
        return tuple(found)


#: URDF's shapes (and PyBullet's capsule) and the numbers that size each.
SHAPE_SIZES = {
    "box": (("size", 3),),
    "cylinder": (("radius", 1), ("length", 1)),
    "capsule": (("radius", 1), ("length", 1)),
    "sphere": (("radius", 1),),
    "mesh": (),
}


def resolve_mesh(name: str, urdf: Path, packages: Mapping[str, Path] | None = None) -> Path:
    """The file a URDF's mesh ``filename`` names: ``package://pkg/rest`` is ``rest``
    in the folder of package ``pkg`` (:func:`tumble.robots.ros.find_package`:
    ``packages``, then the URDF's parent folders, then ``ROS_PACKAGE_PATH``);
    ``package:///rest`` (no package) is ``rest`` under the nearest of those
    folders that holds it; ``file://`` paths as they are; others relative to
    the URDF's folder. A package found nowhere gives ``rest`` in a folder
    ``pkg`` beside the URDF, for the error to name."""
    if name.startswith("file://"):
        return Path(name[len("file://") :])
    if not name.startswith("package://"):
        return urdf.parent / name
    package, _, rest = name[len("package://") :].partition("/")
    if not package:
        # ``package:///rest`` names no package: ``rest`` under the folder that holds
        # it, as the URDF's parent folders and ROS_PACKAGE_PATH are searched for it
        # (example-robot-data writes its meshes so).
        roots = [*Path(os.path.abspath(urdf)).parents]
        roots += [
            Path(entry)
            for entry in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep)
            if entry
        ]
        return next((root / rest for root in roots if (root / rest).is_file()), urdf.parent / rest)
    folder = find_package(package, urdf, packages)
    return (urdf.parent / package if folder is None else folder) / rest
