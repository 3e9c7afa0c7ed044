"""A mesh file checked before it is read: a regular file, data rather than holes,
and within the memory budget.

Reading a mesh takes memory in proportion to its file: trimesh reads a binary
STL whole and makes arrays of its triangles, and tumble's checks copy them
again. A file that declares more than the memory budget holds
(:mod:`tumble.resources`) is refused before the first byte is read, rather than
after minutes of swapping, or a kill by the operating system; so is a sparse
file (its holes read as zeros, gigabytes of them from a few real bytes) and a
FIFO or a device (reading it would wait for a writer, or never end).
"""

from __future__ import annotations

import errno
import os
import struct
from pathlib import Path

from tumble.errors import QUOTED_PATH_LENGTH, InputError, quoted
from tumble.files import check_regular_file, file_kind
from tumble.mesh.step import STEP_SUFFIXES
from tumble.resources import check_memory, format_bytes

__all__ = ["MEMORY_PER_BYTE", "check_mesh_file"]

#: Peak memory of reading and checking a mesh (:func:`tumble.mesh.from_mesh`),
#: bytes per byte of its file. Measured on a sphere of 327 680 triangles written
#: by trimesh in each format: binary STL 15, ASCII STL 7, OBJ 7.5, binary PLY 14,
#: ASCII PLY 18, GLB 13, OFF 18; rounded up.
MEMORY_PER_BYTE = 20

#: A binary STL: an 80-byte header, the number of triangles (uint32, little
#: endian), then 50 bytes per triangle.
_STL_HEADER, _STL_TRIANGLE = 84, 50

#: Holes a mesh file may have before it is refused as sparse: a file system may
#: keep a block of zeros as a hole, but not most of a file of coordinates.
_SPARSE_SLACK = 1 << 20

#: The most data segments :func:`_data_bytes` follows (each one system call):
#: a file in more pieces than this is taken to be all data.
_MOST_SEGMENTS = 10_000


def check_mesh_file(path: str | os.PathLike[str], what: str = "the mesh") -> None:
    """Refuse, before it is read, a mesh file that cannot be read safely.

    Refused: a FIFO, a device or a socket (reading it would block, or never
    end); a sparse file mostly made of holes (they read as zeros: a 2 GB file of
    84 real bytes declares 40 million triangles); a file whose reading would
    take more than the memory budget (about :data:`MEMORY_PER_BYTE` bytes of
    memory per byte of the file; a binary STL's size is its declared triangle
    count, 84 + 50 bytes per triangle, when the two agree, as trimesh then reads
    it). A missing path or a folder passes: the reader says so. STEP files,
    tessellated in a child process bounded by the budget
    (:mod:`tumble.mesh.step`), are checked as files only.

    Parameters
    ----------
    path : the mesh file.
    what : names it in messages, e.g. "the mesh" or "the mesh of link 'arm'".

    Raises
    ------
    InputError
        ``path`` is not a regular file, or is sparse.
    tumble.errors.RequestTooLargeError
        Reading it would take more than the memory budget
        (``TUMBLE_MEMORY_BUDGET``).
    """
    check_regular_file(path, what)
    if file_kind(path) != "a regular file":
        return
    shown = quoted(os.fspath(path), QUOTED_PATH_LENGTH)
    size = os.stat(path).st_size
    data = _data_bytes(path, size)
    if size - data > max(size // 2, _SPARSE_SLACK):
        raise InputError(
            f"Expected {what} to be a file of data, got {shown}, a sparse file of "
            f"{format_bytes(size)} of which {format_bytes(data)} hold data (the rest reads "
            "as zeros, no mesh)."
        )
    suffix = Path(path).suffix.lower()
    if suffix in STEP_SUFFIXES:
        return
    triangles = _binary_stl_triangles(path, size) if suffix == ".stl" else None
    description = (
        f"{what} {shown}, a binary STL of {triangles} triangles"
        if triangles is not None
        else f"{what} {shown} of {format_bytes(size)}"
    )
    check_memory(
        MEMORY_PER_BYTE * size,
        description,
        "Use a mesh of fewer triangles (simplify it), or raise TUMBLE_MEMORY_BUDGET.",
    )


def _binary_stl_triangles(path: str | os.PathLike[str], size: int) -> int | None:
    """The triangles a binary STL declares, where its size agrees with them (as
    trimesh reads it); None for a file read as text."""
    if size < _STL_HEADER:
        return None
    with open(path, "rb") as stream:
        header = stream.read(_STL_HEADER)
    (count,) = struct.unpack("<I", header[80:84])
    return count if _STL_HEADER + _STL_TRIANGLE * count == size else None


def _data_bytes(path: str | os.PathLike[str], size: int) -> int:
    """How many bytes of ``path`` hold data rather than holes (``SEEK_DATA``);
    ``size`` where the system cannot tell."""
    if not size or not hasattr(os, "SEEK_DATA"):
        return size
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError:
        return size
    try:
        data, offset = 0, 0
        for _ in range(_MOST_SEGMENTS):
            try:
                start = os.lseek(descriptor, offset, os.SEEK_DATA)
            except OSError as exc:
                return data if exc.errno == errno.ENXIO else size  # ENXIO: no data after
            offset = os.lseek(descriptor, start, os.SEEK_HOLE)
            data += offset - start
            if offset >= size:
                return data
        return size
    except OSError:
        return size
    finally:
        os.close(descriptor)
