"""The joints of a URDF and whether they make a tree of links.

urdfdom refuses a file whose joints make no tree (a duplicate joint name, a
link with two parents, a cycle, links joined to nothing, mimic joints that
follow each other in a cycle); here each is a notice, every link is still
judged, and poses are refused.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from tumble.errors import InputError, quoted
from tumble.robots.elements import Element
from tumble.robots.model import (
    JOINT_KINDS,
    Joint,
    Link,
    Notice,
    mimic_order,
    rotation_from_rpy,
    shown_cycle,
)
from tumble.robots.urdf_numbers import last_digit
from tumble.robots.urdf_reader import Owner, Reader

__all__ = ["JOINT_KINDS", "read_joints", "root_link"]


def read_joints(
    reader: Reader, top: Element, links: Mapping[str, Link]
) -> tuple[dict[str, Joint], list[str]]:
    """The joints by name (the first of two with one name) and why they make no
    tree, as error messages (each also a notice)."""
    joints: dict[str, Joint] = {}
    lines: dict[str, int] = {}
    refusals: list[str] = []
    for element in top.all("joint"):
        name = element.attributes.get("name", "")
        owner = Owner("joint", name)
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
        if name in joints:
            both = reader.at(f"lines {lines[name]} and {element.line}")
            message = f"Expected one joint named {name!r} in {reader.path.name}, got two ({both})."
            reader.notices.append(
                Notice(
                    name,
                    "invalid-joint",
                    f"{message[:-1]}: urdfdom refuses the file; the second is left out and "
                    "poses are refused.",
                    element.line,
                )
            )
            refusals.append(message)
            continue
        xyz, rpy, unread = reader.placement(element, owner)
        axis_element = element.child("axis")
        read, unread_axis = (
            reader.lenient(axis_element, "xyz", 3, owner, (1.0, 0.0, 0.0))
            if axis_element is not None
            else ((1.0, 0.0, 0.0), "")
        )
        axis = np.array(read)
        size = float(np.linalg.norm(axis))
        if kind in ("revolute", "continuous", "prismatic") and not size > 0:
            raise InputError(
                f"Expected a non-zero axis for {reader.where(element, owner)}, got {axis.tolist()}."
            )
        mimic_element = element.child("mimic")
        mimic = None
        if mimic_element is not None:
            multiplier, _ = reader.lenient(mimic_element, "multiplier", 1, owner, (1.0,))
            offset, _ = reader.lenient(mimic_element, "offset", 1, owner, (0.0,))
            mimic = (mimic_element.attributes.get("joint", ""), multiplier[0], offset[0])  # type: ignore[index]
        parent_link, child_link = str(ends[0]), str(ends[1])
        direction = axis / size if size > 0 else axis
        placement = rotation_from_rpy(rpy), np.array(xyz)
        joints[name] = Joint(
            name,
            kind,
            parent_link,
            child_link,
            *placement,
            direction,
            mimic,
            **_limits(reader, element, kind, owner),
            unread=unread or unread_axis,
        )
        lines[name] = element.line
    _mimic_cycles(reader, joints, lines)
    return joints, refusals


def _limits(reader: Reader, element: Element, kind: str, owner: Owner) -> dict[str, Any]:
    """A revolute or prismatic joint's ``limits`` (lower, upper) where its
    ``<limit>`` gives either (urdfdom's default for the other: 0), and their
    ``slack`` (half a unit of the last digit written), as :class:`Joint`'s fields."""
    limit = element.child("limit")
    if kind not in ("revolute", "prismatic") or limit is None:
        return {}
    if "lower" not in limit.attributes and "upper" not in limit.attributes:
        return {}
    lower, _ = reader.lenient(limit, "lower", 1, owner, (0.0,))
    upper, _ = reader.lenient(limit, "upper", 1, owner, (0.0,))
    low, high = lower[0], upper[0]  # type: ignore[index]
    if not low <= high:
        return {}
    slack = tuple(last_digit(limit.attributes.get(name, "0")) / 2 for name in ("lower", "upper"))
    return {"limits": (low, high), "slack": slack}


def _mimic_cycles(reader: Reader, joints: Mapping[str, Joint], lines: Mapping[str, int]) -> None:
    """A notice for each cycle of mimic joints (a joint that mimics itself too)."""
    for cycle in mimic_order(joints)[1]:
        reader.notices.append(
            Notice(
                cycle[0],
                "invalid-joint",
                f"{reader.opening(lines[cycle[0]])}: mimic joints follow each other in a cycle "
                f"({shown_cycle(cycle)}): no joint moves them; poses are refused.",
                lines[cycle[0]],
            )
        )


def root_link(
    reader: Reader, links: Mapping[str, Link], joints: Mapping[str, Joint]
) -> tuple[str, list[str]]:
    """The one link that is no joint's child, and why the joints make no tree (a
    link with two parents, a cycle, links joined to nothing) as error messages,
    each also a notice: the links are still judged, poses are refused."""
    name = reader.path.name
    parent: dict[str, str] = {}
    problems: list[tuple[str, str]] = []
    for joint in joints.values():
        if joint.child in parent:
            problems.append(
                (
                    joint.name,
                    f"Expected a tree of links in {name}, got link {joint.child!r} as the child "
                    f"of two joints.",
                )
            )
        parent.setdefault(joint.child, joint.name)
    roots = [link for link in links if link not in parent]
    if not roots:
        problems.append(
            ("", f"Expected a tree of links in {name}, got a cycle of joints (no root link).")
        )
    root = roots[0] if roots else next(iter(links))
    reached = {root}
    children: dict[str, list[str]] = {}
    for joint in joints.values():
        children.setdefault(joint.parent, []).append(joint.child)
    stack = [root]
    while stack:
        for child in children.get(stack.pop(), []):
            if child not in reached:
                reached.add(child)
                stack.append(child)
    if roots and (len(roots) > 1 or len(reached) < len(links)):
        unjoined = [link for link in links if link not in reached]
        what = "a cycle of joints among" if len(roots) == 1 else "no joint to"
        problems.append(
            (
                "",
                f"Expected a tree of links joined to root link {root!r} in {name}, got "
                f"{what} {', '.join(repr(n) for n in unjoined[:5])}"
                + (f" and {len(unjoined) - 5} more" if len(unjoined) > 5 else "")
                + ".",
            )
        )
    for owner, message in problems:
        reader.notices.append(
            Notice(
                owner or root,
                "invalid-joint",
                f"{message[:-1]}: urdfdom refuses the file; every link is still judged, "
                "poses are refused.",
                0,
            )
        )
    return root, [message for _, message in problems]
