"""Files written whole or not at all, and output locations checked before any work.

A reader (another process, a crash, an interrupted run) never sees half a file:
each file is written to a temporary name in its folder and renamed
(``os.replace`` within one folder is atomic), and a failed write leaves no
temporary file behind. :func:`check_output` refuses, before any work, a place
that cannot be written; an error of the file system while writing (a full
disk, a lost permission) becomes an :class:`~tumble.errors.OutputError` that
names the path and the cause.

Outputs written by one process at a time, and folders filled beside their
output and moved into place, are in :mod:`tumble.locks`.
"""

from __future__ import annotations

import errno
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from tumble.errors import OutputError

__all__ = [
    "check_output",
    "output_error",
    "path_exists",
    "permissions",
    "replaced",
    "write_bytes",
    "write_text",
]

#: What to do about the usual causes of a failed write, by errno.
_ADVICE = {
    errno.ENOSPC: "free some space or write elsewhere",
    errno.EDQUOT: "free some space or write elsewhere",
    errno.EACCES: "choose a folder you can write to",
    errno.EPERM: "choose a folder you can write to",
    errno.EROFS: "the file system is read-only: write elsewhere",
    errno.ENAMETOOLONG: "use a shorter name",
    errno.ENOTDIR: "a part of the path is a file, not a folder",
    errno.EISDIR: "a folder is in the way",
}


def output_error(cause: OSError, path: str | os.PathLike[str], what: str) -> OutputError:
    """The one-line :class:`~tumble.errors.OutputError` for an operating-system
    error ``cause`` met while writing ``what`` (e.g. "the run folder") at ``path``."""
    reason = cause.strerror or str(cause) or type(cause).__name__
    advice = _ADVICE.get(cause.errno or 0)
    message = f"Expected to write {what} {str(path)!r}, got: {reason}"
    if advice:
        message += f" ({advice})"
    return OutputError(message + ".", str(path), cause)


def check_output(
    path: str | os.PathLike[str], what: str, *, folder: bool, staged: bool = True
) -> None:
    """Refuse, before any work, an output location that cannot be written.

    ``path`` is a file (``folder`` false) or a folder (true) to be created or
    replaced; ``what`` names it in messages (e.g. "the run folder");
    ``staged``: it is written under a temporary name beside it (a prefix and a
    suffix of up to 24 bytes) and moved into place, as files and run folders
    are; a sweep's folder is written into instead. The
    folders above it that do not exist yet will be created. Checked: that no
    name is longer than the file system allows; that the path is not a broken
    symbolic link; that a folder is not a file and a file not a folder; that
    the nearest existing folder above it is a folder (not a file) in which
    this process can create a folder (tried, and removed: permissions, a
    read-only or virtual file system, whoever runs it); that an existing
    output folder can be written.

    Raises
    ------
    OutputError
        Naming the path and what stands in the way.
    """
    target = Path(os.path.abspath(path))
    shown = str(path)
    above = target.parent
    missing = [target.name]
    while not (path_exists(above) or os.path.lexists(above)) and above != above.parent:
        missing.append(above.name)
        above = above.parent
    try:
        longest = os.pathconf(above, "PC_NAME_MAX") if above.is_dir() else 255
    except (OSError, ValueError):
        longest = 255
    for k, name in enumerate(missing):
        room = longest - 24 if staged and k == 0 else longest
        if len(os.fsencode(name)) > room:
            raise OutputError(
                f"Expected {what} with names of at most {room} bytes, got {shown[:60]!r}..., "
                f"whose name {name[:40]!r}... has {len(os.fsencode(name))} bytes "
                "(use a shorter name).",
                shown,
            )
    if os.path.lexists(target) and not path_exists(target):
        raise OutputError(
            f"Expected {what} at a path that exists or can be made, got {shown!r}, a broken "
            "symbolic link (remove it or write elsewhere).",
            shown,
        )
    if path_exists(target):
        if folder and not target.is_dir():
            raise OutputError(
                f"Expected {what} to be a folder, got {shown!r}, which is a file.", shown
            )
        if not folder and target.is_dir():
            raise OutputError(
                f"Expected {what} to be a file, got {shown!r}, which is a folder.", shown
            )
        if folder and not _can_create_in(target):
            raise OutputError(
                f"Expected {what} to be a folder that can be written, got {shown!r} "
                "(permission denied, or a read-only file system).",
                shown,
            )
    if not above.is_dir():
        # A path "through" a file, or a broken link: find what is in the way.
        blocker = next((p for p in [above, *above.parents] if os.path.lexists(p)), above)
        kind = "the broken link" if not path_exists(blocker) else "the file"
        raise OutputError(
            f"Expected {what} in a folder, got {shown!r}, which is under {kind} {str(blocker)!r}.",
            shown,
        )
    if not _can_create_in(above):
        raise OutputError(
            f"Expected {what} in a folder that can be written, got {shown!r}: "
            f"{str(above)!r} cannot be written (permission denied, or a read-only file system).",
            shown,
        )


def path_exists(path: Path) -> bool:
    """Whether ``path`` exists; False where the system cannot even look (a name
    too long, a path through a file, a loop of links)."""
    try:
        return path.exists()
    except OSError:
        return False


def _can_create_in(folder: Path) -> bool:
    """Whether this process can create (and remove) a folder in ``folder``: tried,
    since permissions alone do not tell (the superuser, read-only mounts, /proc)."""
    if not os.access(folder, os.W_OK | os.X_OK):
        return False
    try:
        probe = tempfile.mkdtemp(prefix=".tumble-probe.", dir=folder)
    except OSError:
        return False
    os.rmdir(probe)
    return True


def permissions(directory: bool = False) -> int:
    """The mode a new file (or folder) gets from the process's umask: temporary
    files are created private, and are opened up to this before the rename."""
    mask = os.umask(0)
    os.umask(mask)
    return (0o777 if directory else 0o666) & ~mask


@contextmanager
def replaced(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A temporary path beside ``path`` to write to: renamed to ``path`` when the
    block ends normally, removed when it raises.

    Raises
    ------
    OutputError
        An error of the file system while creating, writing (in the block) or
        renaming the file; ``path`` is then unchanged.
    """
    target = Path(path)
    try:
        handle, name = tempfile.mkstemp(
            prefix=f".{target.name}.", suffix=".partial", dir=target.parent
        )
    except OSError as exc:
        raise output_error(exc, target, "the file") from exc
    os.close(handle)
    temporary = Path(name)
    try:
        yield temporary
        os.chmod(temporary, permissions())
        os.replace(temporary, target)
    except OSError as exc:
        raise output_error(exc, target, "the file") from exc
    finally:
        temporary.unlink(missing_ok=True)


def write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (errors as :func:`replaced`)."""
    with replaced(path) as temporary:
        temporary.write_bytes(data)
    return Path(path)


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write UTF-8 ``text`` to ``path`` atomically (errors as :func:`replaced`)."""
    return write_bytes(path, text.encode("utf-8"))
