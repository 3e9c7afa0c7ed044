"""ROS robot files: packages found by name, and ``.xacro`` files expanded into URDF.

ROS names files by package: ``$(find pkg)`` in a xacro file and
``package://pkg/...`` in a mesh name (:func:`tumble.robots.urdf.resolve_mesh`).
Without ROS installed, a package is looked up (:func:`find_package`): in
the folders given by name (``packages``), then in the file's parent folders (a
folder named ``pkg``, or one holding a folder ``pkg``), then in each folder of
``ROS_PACKAGE_PATH`` (a folder ``pkg`` in it, or the folder itself when it is
named ``pkg``). Packaged copies often rename package folders (rtb-data's
``kuka_kr16_support`` lives in ``kuka_kr16/``): ``packages`` says where.

A xacro file is expanded by the ``xacro`` package (pure Python, the ``robots``
extra), the same code ROS runs, with its ``$(find pkg)`` answered as above and
every file it reads (the file and what it includes) read only when it is a
regular file, so that a FIFO or a device never blocks the expansion. Doing so
replaces some of xacro's private names (:data:`XACRO_INTERNALS`): the ``robots``
extra pins the xacro versions that have them.
"""

from __future__ import annotations

import contextlib
import io
import os
import stat
import threading
import warnings
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tumble.errors import InputError, cut, quoted
from tumble.files import mode_kind
from tumble.robots.model import shown

__all__ = [
    "XACRO_INTERNALS",
    "XACRO_SUFFIXES",
    "Expansion",
    "NotARobot",
    "expand_xacro",
    "find_package",
    "missing_xacro_internals",
    "package_folders",
    "read_regular",
    "xacro_arguments",
]

#: The suffixes of xacro files (``.urdf.xacro`` ends in ``.xacro`` too).
XACRO_SUFFIXES = (".xacro",)

#: The private names of xacro's modules (``xacro``, ``xacro.substitution_args``)
#: that an expansion reads or replaces: xacro has no public way to answer
#: ``$(find)`` or to read the files it includes.
XACRO_INTERNALS = {
    "xacro": ("parse", "filestack", "root_dir", "all_includes", "init_stacks", "process_doc"),
    "xacro.substitution_args": ("_eval_find", "_eval_dict"),
}

#: xacro keeps the state of an expansion in module globals: one at a time.
_XACRO_LOCK = threading.Lock()


class NotARobot(InputError):
    """A file that expands to no robot: a xacro file of macros or properties,
    meant to be included by others."""


@dataclass(frozen=True)
class Expansion:
    """A xacro file expanded: the URDF text, and every file that was read for it.

    Attributes
    ----------
    data : the expanded document, UTF-8 XML, one element a line as the ``xacro``
        command prints it (after its four lines of banner): the lines of
        messages about it are lines of this text, not of the xacro file.
    sources : the xacro file and the files it included (included ones as xacro
        named them), in the order read.
    """

    data: bytes
    sources: tuple[Path, ...]


def read_regular(path: Path, what: str = "a robot file") -> bytes:
    """The bytes of ``path``, read only when it is a regular file.

    The file is opened without blocking and checked on the open descriptor, so
    that a FIFO, a device or a socket is refused rather than read (a FIFO with no
    writer would block ``open`` for ever, ``/dev/zero`` never ends).

    Raises
    ------
    InputError
        "Expected <what>, got '<path>', which is not a regular file (a
        FIFO)." and the like; "no such file"; the system's reason for a file
        that cannot be read.
    """
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise InputError(f"Expected {what}, got {shown(path)}: no such file.") from None
    except OSError as error:
        if os.path.isdir(path):
            raise InputError(
                f"Expected {what}, got {shown(path)}, which is not a regular file (a folder)."
            ) from None
        raise InputError(f"Expected {what}, got {shown(path)}: {error.strerror}.") from None
    with os.fdopen(descriptor, "rb") as file:
        mode = os.fstat(descriptor).st_mode
        if not stat.S_ISREG(mode):
            raise InputError(
                f"Expected {what}, got {shown(path)}, which is not a regular file "
                f"({mode_kind(mode)})."
            )
        try:
            return file.read()
        except OSError as error:
            raise InputError(f"Expected {what}, got {shown(path)}: {error.strerror}.") from None


def package_folders(packages: Mapping[str, Any] | None) -> dict[str, Path]:
    """``packages`` checked: ROS package names, each to an existing folder.

    Raises
    ------
    InputError
        A mapping that is not one, a name that is no package name, a folder that
        is not one.
    """
    if packages is None:
        return {}
    if not isinstance(packages, Mapping):
        raise InputError(
            f"Expected packages as a mapping of ROS package names to folders, got "
            f"{quoted(packages)}."
        )
    folders = {}
    for name, folder in packages.items():
        if not isinstance(name, str) or not name or "/" in name or name != name.strip():
            raise InputError(f"Expected a ROS package name, got {quoted(name)}.")
        if not isinstance(folder, str | os.PathLike):
            raise InputError(
                f"Expected the folder of ROS package {name!r} as a path, got {quoted(folder)}."
            )
        path = Path(folder)
        if not path.is_dir():
            what = "no such folder" if not os.path.lexists(path) else "not a folder"
            raise InputError(
                f"Expected the folder of ROS package {name!r}, got {shown(path)}: {what}."
            )
        folders[name] = path
    return folders


def xacro_arguments(arguments: Mapping[str, Any] | None) -> dict[str, str]:
    """xacro's ``<xacro:arg>`` values, checked: names to texts.

    Raises
    ------
    InputError
        A mapping that is not one, an empty name or a value that is not text.
    """
    if arguments is None:
        return {}
    if not isinstance(arguments, Mapping):
        raise InputError(
            f"Expected xacro arguments as a mapping of names to values, got {quoted(arguments)}."
        )
    checked = {}
    for name, value in arguments.items():
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"Expected a xacro argument name, got {quoted(name)}.")
        if not isinstance(value, str | int | float) or isinstance(value, bool):
            raise InputError(
                f"Expected a text value for xacro argument {name!r}, got {quoted(value)}."
            )
        checked[name] = str(value)
    return checked


def find_package(name: str, near: Path, packages: Mapping[str, Path] | None = None) -> Path | None:
    """The folder of ROS package ``name`` (see :mod:`tumble.robots.ros`), or None.

    Parameters
    ----------
    name : the package's name.
    near : the file that names it; its parent folders are searched.
    packages : package names and their folders, searched first.
    """
    if packages and name in packages:
        return Path(packages[name])
    for folder in Path(os.path.abspath(near)).parents:
        if folder.name == name:
            return folder
        if (folder / name).is_dir():
            return folder / name
    for entry in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep):
        if not entry:
            continue
        if Path(entry).name == name and Path(entry).is_dir():
            return Path(entry)
        if (Path(entry) / name).is_dir():
            return Path(entry) / name
    return None


def expand_xacro(
    path: Path,
    *,
    packages: Mapping[str, Path] | None = None,
    arguments: Mapping[str, str] | None = None,
) -> Expansion:
    """Expand a xacro file into URDF, as ROS's ``xacro`` command does.

    Parameters
    ----------
    path : the ``.xacro`` file.
    packages : ROS package names and their folders, for ``$(find pkg)``
        (see :func:`find_package`).
    arguments : values of the file's ``<xacro:arg>`` (``$(arg name)``), by name.

    Returns
    -------
    Expansion: the URDF text and the files read.

    Raises
    ------
    InputError
        One line naming the file: xacro not installed, a package found nowhere,
        an argument with no value, an expression xacro cannot evaluate, XML that
        is not well-formed, an included file that cannot be read.
    """
    import xml.dom.minidom
    from xml.parsers import expat

    xacro, substitution_args = _installed_xacro(path)
    data = read_regular(path)
    files = _XacroFiles(xacro, path, packages)
    missing = files.missing
    problems = io.StringIO()
    with (
        _XACRO_LOCK,
        _patched(substitution_args, xacro, files.find, files.parse),
        contextlib.redirect_stderr(problems),
    ):
        try:
            xacro.init_stacks(str(path))
            xacro.all_includes = []
            doc = xml.dom.minidom.parseString(data)
            xacro.process_doc(doc, mappings=dict(arguments or {}))
            # One element a line, so that a line number names something.
            expanded = doc.toprettyxml(indent="  ", encoding="utf-8")
        except InputError:
            if not missing:
                raise
            raise _missing_package(path, missing[0]) from None
        except expat.ExpatError as error:
            raise InputError(
                f"Expected {shown(path)} to be well-formed XML, got {error}."
            ) from None
        except Exception as error:  # xacro raises its own and Python's errors
            if missing:
                raise _missing_package(path, missing[0]) from None
            raise _xacro_error(path, error) from None
        finally:
            xacro.init_stacks(None)
    said = " ".join(problems.getvalue().split())
    if said:
        warnings.warn(f"xacro, expanding {path.name}: {cut(said, 300)}", stacklevel=2)
    return Expansion(expanded, tuple(files.sources))


def _installed_xacro(path: Path) -> tuple[Any, Any]:
    """The xacro module and its ``substitution_args``, of a version tumble supports.

    Raises
    ------
    InputError
        xacro not installed, or a version without the internals tumble patches.
    """
    try:
        import xacro  # type: ignore[import-untyped]
        from xacro import substitution_args
    except ImportError:
        raise InputError(
            f"Expected the xacro package to expand {shown(path)}, got none installed: "
            "pip install 'tumble[robots]'."
        ) from None
    missing_names = missing_xacro_internals()
    if missing_names:
        raise InputError(
            f"Expected a xacro version that tumble supports (the `robots` extra's pin) to "
            f"expand {shown(path)}, got xacro {_version()} without {', '.join(missing_names)}: "
            "pip install 'tumble[robots]'."
        )
    return xacro, substitution_args


class _XacroFiles:
    """What xacro reads while it expands ``path``, in tumble's hands: ``$(find pkg)``
    looked up in ``packages`` (the names found nowhere kept in ``missing``), and each
    included file read as tumble reads files (kept in ``sources``)."""

    def __init__(self, xacro: Any, path: Path, packages: Mapping[str, Path] | None) -> None:
        self.xacro = xacro
        self.path = path
        self.packages = packages
        self.missing: list[str] = []
        self.sources = [path]
        self.original_parse = xacro.parse

    def find(self, name: str) -> str:
        folder = find_package(name, Path(self.xacro.filestack[-1] or self.path), self.packages)
        if folder is None:
            self.missing.append(name)
            raise InputError(f"ROS package {name!r} not found")
        return str(folder)

    def parse(self, inp: Any, filename: str | None = None) -> Any:
        import xml.dom.minidom
        from xml.parsers import expat

        if inp is not None:
            return self.original_parse(inp, filename)
        path = self.path
        included = Path(os.path.join(self.xacro.root_dir, filename or ""))
        try:
            text = read_regular(included, "a file to include")
        except InputError as error:
            if not os.path.lexists(included):
                # as xacro's own parse: an optional include may be missing
                raise self.xacro.XacroException(
                    f"No such file to include: {included}", exc=FileNotFoundError()
                ) from None
            raise InputError(f"Expected {shown(path)} to expand with xacro, got: {error}") from None
        self.sources.append(included)
        try:
            return xml.dom.minidom.parseString(text)
        except expat.ExpatError as error:
            raise InputError(
                f"Expected {shown(included)}, which {shown(path)} includes, to be well-formed "
                f"XML, got {error}."
            ) from None


def missing_xacro_internals() -> list[str]:
    """The names of :data:`XACRO_INTERNALS` that the installed xacro lacks (none
    where it has them all, as the versions the ``robots`` extra allows do)."""
    import importlib

    missing = []
    for module_name, names in XACRO_INTERNALS.items():
        module = importlib.import_module(module_name)
        missing += [f"{module_name}.{name}" for name in names if not hasattr(module, name)]
    evaluators = getattr(importlib.import_module("xacro.substitution_args"), "_eval_dict", None)
    if isinstance(evaluators, dict) and "find" not in evaluators:
        missing.append("xacro.substitution_args._eval_dict['find']")
    return missing


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("xacro")
    except PackageNotFoundError:
        return "(version unknown)"


@contextlib.contextmanager
def _patched(substitution_args: Any, xacro: Any, find: Any, parse: Any) -> Iterator[None]:
    """xacro's ``$(find)`` and its file reader replaced for one expansion: its
    own ``$(find)`` asks ROS 2's ament index, which a plain Python has not."""
    saved = (substitution_args._eval_find, substitution_args._eval_dict["find"], xacro.parse)
    substitution_args._eval_find = find
    substitution_args._eval_dict["find"] = find
    xacro.parse = parse
    try:
        yield
    finally:
        (substitution_args._eval_find, substitution_args._eval_dict["find"], xacro.parse) = saved


def _missing_package(path: Path, name: str) -> InputError:
    return InputError(
        f"Expected ROS package {name!r}, which {shown(path)} names in $(find {name}), to be "
        f"found, got none beside the file or in ROS_PACKAGE_PATH (give its folder: "
        f"--package {name}=DIR, or packages={{{name!r}: DIR}})."
    )


def _xacro_error(path: Path, error: BaseException) -> InputError:
    """xacro's error as one line naming the file."""
    from xacro import XacroException
    from xacro.substitution_args import ArgException  # type: ignore[import-untyped]

    cause = error.exc if isinstance(error, XacroException) else None
    if isinstance(cause, ArgException):
        name = str(cause)
        return InputError(
            f"Expected a value for xacro argument {name!r} of {shown(path)} (--xacro-arg "
            f"{name}=VALUE), got none."
        )
    if isinstance(cause, InputError):
        return cause
    text = " ".join(str(error).split()) or type(error).__name__
    return InputError(f"Expected {shown(path)} to expand with xacro, got: {text}.")
