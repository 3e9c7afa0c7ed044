"""Which reader a robot file takes, by its suffix, and the robot files of a folder."""

from __future__ import annotations

import contextlib
import os
import stat
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tumble.errors import InputError, quoted
from tumble.files import mode_kind
from tumble.robots.model import Robot, shown
from tumble.robots.ros import (
    NotARobot,
    expand_xacro,
    package_folders,
    read_regular,
    xacro_arguments,
)

__all__ = ["SUFFIXES", "Loaded", "NotARobot", "load", "read_robot", "robot_files", "robot_kind"]

#: The robot files read: URDF, xacro files expanded into URDF, and MJCF through
#: MuJoCo's own parser.
SUFFIXES = {".urdf": "URDF", ".xacro": "xacro", ".xml": "MJCF"}

#: How much of an ``.xml`` file is read to find its root element (a MuJoCo
#: model's ``<mujoco>`` comes after at most a declaration and comments).
_HEAD = 1 << 16


@dataclass(frozen=True)
class Loaded:
    """A robot and the files it was read from.

    Attributes
    ----------
    robot : the robot.
    sources : the file itself, then the files it includes (a xacro file's
        ``<xacro:include>``, an MJCF's ``<include>``): what an output must never
        overwrite.
    references : the files the robot names and reads on demand (a URDF's
        meshes where they resolve; every place MuJoCo may look for an MJCF's
        meshes, height fields, textures...): what an output must never
        overwrite either.
    """

    robot: Robot
    sources: tuple[Path, ...]
    references: tuple[Path, ...] = ()


def load(
    path: Any,
    *,
    packages: Mapping[str, Any] | None = None,
    xacro_args: Mapping[str, Any] | None = None,
) -> Robot:
    """Read a robot description: a URDF (``.urdf``), a xacro file (``.urdf.xacro``,
    ``.xacro``) or an MJCF (``.xml``) file.

    Parameters
    ----------
    path : the file (a ``str`` or ``os.PathLike``): a regular file. A URDF's meshes
        (``package://`` names included) are looked up in ``packages``, beside it, in
        its parent folders and in ``ROS_PACKAGE_PATH``, and read only when a link's
        geometry is asked for. A xacro file is expanded by the ``xacro`` package
        first (see :mod:`tumble.robots.ros`). An MJCF is compiled by MuJoCo. Both
        need the ``robots`` extra: ``pip install 'tumble[robots]'``.
    packages : ROS package names and their folders (for example
        ``{"kuka_kr16_support": "kuka_kr16"}``), for ``$(find pkg)`` and
        ``package://pkg/...``: packaged copies often rename package folders.
        URDF and xacro files only.
    xacro_args : values of a xacro file's ``<xacro:arg>``, by name (as
        ``xacro file.urdf.xacro name:=value`` gives them). xacro files only.

    Returns
    -------
    Robot: its links (declared values as written, valid or not) and joints.

    Raises
    ------
    InputError
        A path that is not one, a file that does not exist or is not a regular
        file (a folder, a FIFO, a device), a file that cannot be read, is not XML,
        is not a robot, has a number that is not one, or links that are not a
        tree of joints; a xacro file that xacro cannot expand (a package found
        nowhere, an argument with no value, a bad expression), or that expands to
        no robot (:class:`NotARobot`, a file meant to be included).

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
    return read_robot(path, packages=packages, xacro_args=xacro_args).robot


def read_robot(
    path: Any,
    *,
    packages: Mapping[str, Any] | None = None,
    xacro_args: Mapping[str, Any] | None = None,
) -> Loaded:
    """A robot file read (as :func:`load`), with the files it was read from."""
    path = _robot_path(path)
    kind = robot_kind(path)
    folders = package_folders(packages)
    arguments = xacro_arguments(xacro_args)
    if arguments and kind != "xacro":
        raise InputError(
            f"Expected xacro arguments only for a xacro file, got {shown(path)}, "
            f"{'an' if kind == 'MJCF' else 'a'} {kind} file."
        )
    if folders and kind == "MJCF":
        raise InputError(
            f"Expected ROS packages only for a URDF or xacro file, got {shown(path)}, an MJCF file."
        )
    if kind == "MJCF":
        from tumble.robots.mjcf import read_mjcf

        # the includes first: MuJoCo would wait for ever on a FIFO
        includes = _mjcf_includes(path, read_regular(path))
        return Loaded(read_mjcf(path), (path, *includes), _mjcf_references(path))
    from tumble.robots.urdf import read_urdf

    if kind == "URDF":
        robot = read_urdf(path, data=read_regular(path), packages=folders)
        return Loaded(robot, (path,), _meshes(robot))
    expansion = expand_xacro(path, packages=folders, arguments=arguments)
    _check_expansion(path, expansion.data)
    robot = read_urdf(path, data=expansion.data, packages=folders, xacro=True)
    return Loaded(robot, expansion.sources, _meshes(robot))


def _meshes(robot: Robot) -> tuple[Path, ...]:
    """The mesh files the robot's shapes name, each once."""
    named = (
        shape.mesh
        for link in robot.links.values()
        for shapes in link.shapes.values()
        for shape in shapes
        if shape.mesh is not None
    )
    return tuple(dict.fromkeys(named))


def _mjcf_references(path: Path) -> tuple[Path, ...]:
    """Every place MuJoCo may look for the files an MJCF (and what it includes)
    names: beside the main file or the file naming it, in a compiler folder
    (``meshdir``...) or not, by the name written or by its last part."""
    from tumble.robots.mjcf_files import WrittenModel

    written = WrittenModel(path.parent)
    written.scan(path, read_regular(path))
    places = []
    for _, name, near in written.references:
        for base in (written.folder, near):
            for folder in ("", *sorted(written.folders)):
                places += [base / folder / name, base / folder / os.path.basename(name)]
    return tuple(dict.fromkeys(places))


def robot_kind(path: Path) -> str:
    """The kind of robot file ``path`` is by its suffix: "URDF", "xacro" or "MJCF".

    Raises
    ------
    InputError
        Another suffix.
    """
    kind = SUFFIXES.get(path.suffix.lower())
    if kind is None:
        raise InputError(
            "Expected a robot file ending in .urdf (URDF), .urdf.xacro or .xacro (xacro) or "
            f".xml (MJCF), got {shown(path)}."
        )
    return kind


def robot_files(folder: Path) -> Iterator[Path]:
    """The robot files under ``folder``, in sorted order, its sub-folders included:
    ``.urdf`` and xacro files, and ``.xml`` files whose root element is
    ``<mujoco>`` (a MuJoCo model; other XML such as ROS's ``package.xml`` is not a
    robot). Links to folders are not followed (no loop). A file that is not a
    regular file is listed, for its reading to say what it is.

    Raises
    ------
    InputError
        ``folder`` is not a folder.
    """
    if not os.path.isdir(folder):
        raise InputError(f"Expected a folder of robot files, got {shown(folder)}: not a folder.")
    for top, folders, names in os.walk(folder):
        folders.sort()
        for name in sorted(names):
            path = Path(top) / name
            kind = SUFFIXES.get(path.suffix.lower())
            if kind is not None and (kind != "MJCF" or _is_mujoco(path)):
                yield path


def _robot_path(path: Any) -> Path:
    """``path`` as a regular file's path, or an InputError naming what it is."""
    if isinstance(path, bytes | bytearray):
        raise InputError(
            f"Expected a robot file's path (str or os.PathLike), got bytes {quoted(bytes(path))} "
            "(write the robot to a file and pass its path)."
        )
    if not isinstance(path, str | os.PathLike):
        kind = "" if path is None else f" ({type(path).__name__})"
        raise InputError(
            f"Expected a robot file's path (str or os.PathLike), got {quoted(path)}{kind}."
        )
    path = Path(path)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise InputError(f"Expected a robot file, got {shown(path)}: no such file.") from None
    except OSError as error:
        raise InputError(f"Expected a robot file, got {shown(path)}: {error.strerror}.") from None
    if not stat.S_ISREG(mode):
        raise InputError(
            f"Expected a robot file, got {shown(path)}, which is not a regular file "
            f"({mode_kind(mode)})."
        )
    return path


def _check_expansion(path: Path, data: bytes) -> None:
    """Refuse, as :class:`NotARobot`, a xacro expansion with no ``<robot>`` of links."""
    import xml.etree.ElementTree as ElementTree

    top = ElementTree.fromstring(data)
    if top.tag != "robot" or top.find("link") is None:
        what = "no <robot> root" if top.tag != "robot" else "a robot of no link"
        raise NotARobot(
            f"Expected a robot with links in {shown(path)} after xacro, got {what} "
            "(a file of macros, meant to be included by others)."
        )


def _is_mujoco(path: Path) -> bool:
    """Whether an ``.xml`` file's root element is ``<mujoco>``; True for a file that
    is not a regular one (its reading says what it is)."""
    from xml.parsers import expat

    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    if not stat.S_ISREG(mode):
        return True
    with open(path, "rb") as file:
        head = file.read(_HEAD)
    roots: list[str] = []
    parser = expat.ParserCreate()

    def start(name: str, attributes: dict[str, str]) -> None:
        roots.append(name)
        parser.StartElementHandler = None

    parser.StartElementHandler = start
    with contextlib.suppress(expat.ExpatError):  # a root read before the error counts
        parser.Parse(head, False)
    return roots[:1] == ["mujoco"]


def _mjcf_includes(path: Path, data: bytes, depth: int = 0) -> list[Path]:
    """The files an MJCF's ``<include file=...>`` elements name (relative to the
    model's folder, as MuJoCo resolves them), and theirs. One that does not exist
    is left for MuJoCo to name; one that is not a regular file is refused."""
    from xml.parsers import expat

    found: list[Path] = []
    parser = expat.ParserCreate()

    def start(name: str, attributes: dict[str, str]) -> None:
        if name == "include" and attributes.get("file"):
            found.append(path.parent / attributes["file"])

    parser.StartElementHandler = start
    try:
        parser.Parse(data, True)
    except expat.ExpatError:
        return found
    nested = []
    for include in found if depth < 8 else []:
        if os.path.lexists(include):
            text = read_regular(include, f"a file for {shown(path)} to include")
            nested += _mjcf_includes(path, text, depth + 1)
    return found + nested
