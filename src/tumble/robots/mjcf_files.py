"""An MJCF model's files read before MuJoCo reads them: the files it includes
(regular files only: a FIFO or a device would block MuJoCo's reader or never
end), every file they name (meshes, height fields, textures, skins, models),
the model's size (:data:`MAX_BODIES`, :data:`MAX_GEOMS`, and the memory budget
of :mod:`tumble.resources` for the files MuJoCo reads), and each body's
``<inertial>`` as written, for the digits of the file."""

from __future__ import annotations

import math
import os
import stat
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from xml.parsers import expat

import numpy as np

from tumble.errors import InputError, RequestTooLargeError
from tumble.files import mode_kind
from tumble.resources import check_memory
from tumble.robots.geometry import shown
from tumble.robots.ros import read_regular

__all__ = ["FULL_TO_URDF", "MAX_BODIES", "MAX_GEOMS", "WrittenModel"]

#: The most bodies an MJCF may have. MuJoCo's parser takes a time growing as the
#: square of the number of bodies (measured: 0.2 s for 1000 bodies, 1.2 s for
#: 2000, 3 to 8 s for 5000 with their joints compiled, 20 to 50 s for 10⁴, so
#: minutes for 10⁵): the bound keeps a model's reading within seconds.
MAX_BODIES = 5_000

#: The most geoms an MJCF may have (measured: 1 s for 10⁴ geoms, 2.4 s for
#: 2 × 10⁴, 19 s for 4 × 10⁴).
MAX_GEOMS = 20_000

#: The memory MuJoCo takes for each byte of the files it reads, for the memory
#: budget: its document tree of the XML, and a mesh's vertices, faces, normals
#: and convex hull (a binary STL's 50 bytes a triangle become 36 bytes of float
#: vertices before merging, faces, a hull, and tumble's float64 copy).
_MEMORY_PER_BYTE = 16

#: The elements that name files MuJoCo reads, and the attributes naming them
#: (a cube texture names one file per face).
_FILE_ATTRIBUTES = {
    "mesh": ("file",),
    "hfield": ("file",),
    "skin": ("file",),
    "model": ("file",),
    "flexcomp": ("file",),
    "texture": ("file", "fileright", "fileleft", "fileup", "filedown", "filefront", "fileback"),
}

#: The compiler's folders for the files of assets.
_FOLDERS = ("meshdir", "texturedir", "assetdir")

#: MJCF's ``fullinertia`` (ixx iyy izz ixy ixz iyz) in URDF's order (ixx ixy ixz iyy iyz izz).
FULL_TO_URDF = (0, 3, 4, 1, 5, 2)


@dataclass
class WrittenModel:
    """What an MJCF's XML says, read before MuJoCo reads it: the files it includes
    and names, its size, and the ``<inertial>`` of each body as written.

    ``folder`` is the main file's folder: MuJoCo looks for an included file
    there first, then beside the file that includes it, and for the files of
    assets in the compiler's folders (``meshdir``, ``texturedir``,
    ``assetdir``) under it."""

    folder: Path
    bodies: float = 0.0
    geoms: float = 0.0
    #: Every ``<body>`` in order: its name (None: unnamed) and its
    #: ``<inertial>``'s attributes (None: none), while ``ordered`` holds (no
    #: ``<replicate>`` copies bodies, so the order is MuJoCo's).
    written: list[tuple[str | None, dict[str, str] | None]] = field(default_factory=list)
    ordered: bool = True
    #: (element, file named, folder of the file that names it).
    references: list[tuple[str, str, Path]] = field(default_factory=list)
    folders: set[str] = field(default_factory=set)
    size: int = 0
    _read: set[Path] = field(default_factory=set)
    _copies: list[float] = field(default_factory=lambda: [1.0])
    #: The elements open: each body's index in ``written`` (None: not a body).
    _open: list[int | None] = field(default_factory=list)

    def scan(self, path: Path, data: bytes) -> None:
        """Read one file of the model (``data``: its bytes), and those it includes."""
        self._read.add(path.resolve())
        self.size += len(data)
        parser = expat.ParserCreate()
        parser.StartElementHandler = lambda name, attributes: self._start(path, name, attributes)
        parser.EndElementHandler = self._end
        try:
            parser.Parse(data, True)
        except expat.ExpatError as error:
            raise InputError(
                f"Expected an MJCF model in {shown(path)}, got: malformed XML: {error}."
            ) from None

    def _start(self, path: Path, name: str, attributes: dict[str, str]) -> None:
        copies = self._copies[-1]
        body = None
        if name == "replicate":
            copies *= max(_number(attributes.get("count"), 1.0), 1.0)
            self.ordered = False
        elif name == "body":
            self.bodies += copies
            body = len(self.written)
            self.written.append((attributes.get("name"), None))
        elif name == "inertial":
            owner = self._open[-1] if self._open else None  # a body's own child
            if owner is not None:
                self.written[owner] = (self.written[owner][0], dict(attributes))
        elif name == "geom":
            self.geoms += copies
        elif name in ("flexcomp", "composite"):
            # A body for each point of the grid, at most.
            counts = [_number(v, 1.0) for v in attributes.get("count", "10 10 10").split()]
            self.bodies += copies * math.prod(max(c, 1.0) for c in counts)
        elif name == "compiler":
            self.folders.update(attributes[key] for key in _FOLDERS if attributes.get(key))
        elif name == "include" and attributes.get("file"):
            self._include(path, attributes["file"])
        for key in _FILE_ATTRIBUTES.get(name, ()):
            if attributes.get(key):
                self.references.append((name, attributes[key], path.parent))
        self._open.append(body)
        self._copies.append(copies)

    def _end(self, name: str) -> None:
        self._open.pop()
        self._copies.pop()

    def _include(self, path: Path, name: str) -> None:
        # MuJoCo opens the first that exists: beside the main file, then beside
        # the file that includes it.
        candidates = [self.folder / name, path.parent / name]
        found = next((c for c in candidates if os.path.lexists(c)), candidates[0])
        if found.resolve() in self._read:
            return  # MuJoCo refuses a file included twice, with its own message
        what = f"the file of an <include> in {shown(path)} to be a regular file"
        self.scan(found, read_regular(found, what))

    def check(self, path: Path) -> None:
        """Refuse a model whose named files are not regular files, or that is too
        large to compile (see :data:`MAX_BODIES`, :data:`MAX_GEOMS`)."""
        if self.bodies > MAX_BODIES or self.geoms > MAX_GEOMS:
            what, count, bound = (
                ("bodies", self.bodies, MAX_BODIES)
                if self.bodies > MAX_BODIES
                else ("geoms", self.geoms, MAX_GEOMS)
            )
            raise RequestTooLargeError(
                f"Expected an MJCF model of at most {bound} {what} (MuJoCo's parser takes a "
                f"time growing as the square of their number), got {count:.0f} in {shown(path)}."
            )
        seen: set[Path] = set()
        size = self.size
        for element, name, near in self.references:
            for candidate in self._candidates(name, near):
                try:
                    status = os.stat(candidate)
                except (OSError, ValueError):
                    continue  # missing (MuJoCo says so) or not a name at all
                if not stat.S_ISREG(status.st_mode):
                    raise InputError(
                        f"Expected the file of a <{element}> in {shown(path)} to be a regular "
                        f"file, got {shown(candidate)}, which is {mode_kind(status.st_mode)}."
                    )
                if candidate.resolve() not in seen:
                    seen.add(candidate.resolve())
                    size += status.st_size
        check_memory(
            _MEMORY_PER_BYTE * size,
            f"an MJCF model of {size} bytes of files for MuJoCo to read",
            "Simplify its meshes.",
        )

    def _candidates(self, name: str, near: Path) -> list[Path]:
        """Where MuJoCo may look for an asset's file: under the main file's folder
        or beside the file naming it, in a compiler folder or not, by its name or
        its last part (``strippath``)."""
        found = []
        for base in dict.fromkeys((self.folder, near)):
            for folder in ("", *sorted(self.folders)):
                for written in dict.fromkeys((name, os.path.basename(name))):
                    found.append(base / folder / written)
        return list(dict.fromkeys(found))

    def texts(self, bodies: Any) -> dict[int, tuple[str, ...]]:
        """The six inertia texts in URDF's order of each body of the spec
        (``bodies``, the world first) whose ``<inertial>`` was read here and
        whose numbers are the spec's: matched in order where the order is
        MuJoCo's, else by unique name."""
        bodies = list(bodies)[1:]
        if self.ordered and len(self.written) == len(bodies):
            pairs = list(enumerate(self.written, start=1))
        else:
            names = [name for name, _ in self.written]
            index = {body.name: i for i, body in enumerate(bodies, start=1) if body.name}
            pairs = [
                (index[name], (name, attributes))
                for name, attributes in self.written
                if name and names.count(name) == 1 and name in index
            ]
        found = {}
        for i, (name, attributes) in pairs:
            body = bodies[i - 1]
            if attributes is None or (name or "") != body.name:
                continue
            texts = _inertia_texts(attributes, body)
            if texts is not None:
                found[i] = texts
        return found


def _number(text: str | None, default: float) -> float:
    try:
        value = float(text) if text is not None else default
    except ValueError:
        return default
    return value if math.isfinite(value) else default


def _inertia_texts(attributes: Mapping[str, str], body: Any) -> tuple[str, ...] | None:
    """An ``<inertial>``'s six inertia numbers as written, in URDF's order; None
    where they are not the numbers MuJoCo read (the texts are then unknown)."""
    if "fullinertia" in attributes:
        full = attributes["fullinertia"].split()
        if len(full) != 6:
            return None
        texts = tuple(full[k] for k in FULL_TO_URDF)
        values = np.asarray(body.fullinertia, dtype=float)[list(FULL_TO_URDF)]
    elif "diaginertia" in attributes:
        diagonal = attributes["diaginertia"].split()
        if len(diagonal) != 3:
            return None
        texts = (diagonal[0], "0", "0", diagonal[1], "0", diagonal[2])
        first, second, third = np.asarray(body.inertia, dtype=float)
        values = np.array([first, 0.0, 0.0, second, 0.0, third])
    else:
        return None
    try:
        read = np.array([float(text) for text in texts])
    except ValueError:
        return None
    return texts if np.array_equal(read, values) else None
