"""Reading a URDF file into a :class:`~tumble.robots.model.Robot`.

URDF is plain XML with a handful of elements (ROS's ``urdfdom`` is the
reference; its rules are followed here: ``rpy`` is roll, pitch, yaw about fixed
axes; a missing ``<origin>`` is the identity, a missing ``<axis>`` is x, a
missing ``<inertial>`` a massless link). It is read with the standard library's
expat parser rather than a URDF library because the audit needs what those
libraries drop or refuse: the numbers as written (an invalid tensor, the digits
given), and the byte offset of each inertial element, so that a corrected copy
changes those elements and nothing else.

Its parts: :mod:`tumble.robots.urdf_numbers` (urdfdom's and PyBullet's readings
of numbers), :mod:`tumble.robots.urdf_reader` (placements, inertials, shapes)
and :mod:`tumble.robots.urdf_joints` (the joints, and whether they make a tree).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from tumble.errors import InputError
from tumble.robots.elements import parse_elements
from tumble.robots.model import Link, Robot, shown
from tumble.robots.urdf_joints import read_joints, root_link
from tumble.robots.urdf_numbers import urdf_number
from tumble.robots.urdf_reader import Owner, Reader, resolve_mesh

__all__ = ["read_urdf", "resolve_mesh", "urdf_number"]


def read_urdf(
    path: Path,
    data: bytes | None = None,
    packages: Mapping[str, Path] | None = None,
    xacro: bool = False,
) -> Robot:
    """The robot of a URDF file (see :mod:`tumble.robots.urdf`).

    Numbers are read as urdfdom reads them. Inside an ``<inertial>``, one that
    urdfdom refuses (or a missing element or attribute) makes that link's
    inertial unreadable (a notice; :meth:`Robot.mass_properties` refuses the
    link). Elsewhere (origins, axes, sizes, scales, limits) such a number is
    read as PyBullet reads it where that is what was meant (``"0.07, 0, -0.69"``,
    a fourth number), else the default stands in, with a notice; a joint whose
    placement was not read leaves the poses beyond it unknown. Joints that do
    not make a tree (a duplicate name, a link with two parents, a cycle, mimic
    joints in a cycle) are notices too, and poses are refused.

    Parameters
    ----------
    path : the file; messages name it.
    data : the file's content where it was produced another way (a xacro
        expansion): read instead of the file.
    packages : ROS package names and their folders, where ``package://`` mesh
        names are looked up first (see :func:`resolve_mesh`).
    xacro : whether ``data`` is the xacro expansion of ``path``: messages then
        give lines of the expansion as such.

    Raises
    ------
    InputError
        A file that cannot be read, is not well-formed XML or not a URDF robot,
        a link without a name or with another link's name, no links, a joint of
        an unknown type, a joint whose parent or child is no link, a zero axis.
    """
    if data is None:
        try:
            data = path.read_bytes()
        except OSError as error:
            raise InputError(
                f"Expected a readable robot file, got {shown(path)}: {error.strerror}."
            ) from None
    top = parse_elements(path, data)
    if top.name != "robot":
        raise InputError(
            f"Expected a URDF robot (a <robot> root element) in {shown(path)}, got <{top.name}>."
        )
    reader = Reader(path, packages, xacro)
    links: dict[str, Link] = {}
    for element in top.all("link"):
        name = element.attributes.get("name")
        if not name:
            raise InputError(
                f"Expected a name on the <link> at {reader.at(element.line)} of {path.name}, got "
                "none."
            )
        if name in links:
            raise InputError(
                f"Expected one link named {name!r} in {path.name}, got two "
                f"({reader.at(element.line)})."
            )
        owner = Owner("link", name)
        inertial, unreadable = reader.inertial(element, owner)
        links[name] = Link(
            name=name,
            inertial=inertial,
            shapes={kind: reader.shapes(element, kind, owner) for kind in ("collision", "visual")},
            line=element.line,
            unreadable=unreadable,
        )
    if not links:
        raise InputError(f"Expected a robot with links in {shown(path)}, got none.")
    joints, refusals = read_joints(reader, top, links)
    root, more = root_link(reader, links, joints)
    return Robot(
        top.attributes.get("name", path.stem),
        path,
        links,
        joints,
        root,
        tuple(reader.notices),
        (refusals + more + [""])[0],
    )
