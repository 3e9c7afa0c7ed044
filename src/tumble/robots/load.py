"""Which reader a robot file takes, by its suffix."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from tumble.errors import InputError
from tumble.robots.model import Robot, shown

__all__ = ["SUFFIXES", "load"]

#: The robot files read: URDF, and MJCF through MuJoCo's own parser.
SUFFIXES = {".urdf": "URDF", ".xml": "MJCF"}


def load(path: Any) -> Robot:
    """Read a robot description: a URDF (``.urdf``) or an MJCF (``.xml``) file.

    Parameters
    ----------
    path : the file. A URDF's meshes (``package://`` names included) are looked
        up beside it, in its parent folders and in ``ROS_PACKAGE_PATH``, and read
        only when a link's geometry is asked for. An MJCF is compiled by MuJoCo
        (the ``mujoco`` extra: ``pip install 'tumble[robots]'``).

    Returns
    -------
    Robot: its links (declared values as written, valid or not) and joints.

    Raises
    ------
    InputError
        A file that cannot be read, is not XML, is not a robot, has a number
        that is not one, or links that are not a tree of joints.

    Examples
    --------
    >>> import tumble as tb
    >>> from tumble.robots import example_path
    >>> robot = tb.robots.load(example_path())
    >>> sorted(robot.links)
    ['arm', 'base', 'hand']
    >>> print(f"{robot.mass_properties().mass:.1f} kg")
    6.5 kg
    """
    path = Path(path)
    kind = SUFFIXES.get(path.suffix.lower())
    if kind is None:
        hint = " (run xacro on it first)" if path.suffix.lower() == ".xacro" else ""
        raise InputError(
            f"Expected a robot file ending in .urdf (URDF) or .xml (MJCF), got {shown(path)}{hint}."
        )
    if not path.is_file():
        raise InputError(f"Expected a robot file, got {shown(path)}: no such file.")
    if kind == "URDF":
        from tumble.robots.urdf import read_urdf

        return read_urdf(path)
    from tumble.robots.mjcf import read_mjcf

    return read_mjcf(path)
