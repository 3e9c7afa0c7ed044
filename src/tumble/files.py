"""Files written whole or not at all, and output locations checked before any work.

A reader (another process, a crash, an interrupted run) never sees half a file:
each file is written to a temporary name in its folder and renamed
(``os.replace`` within one folder is atomic), and a failed write leaves no
temporary file behind. :func:`check_output` refuses, before any work, a place
that cannot be written; an error of the file system while writing (a full
disk, a lost permission) becomes an :class:`~tumble.errors.OutputError` that
names the path and the cause. Only a regular file (or a new path) is ever
replaced, and only a folder (or a new path) filled: the rename would replace
a FIFO, a device or a socket with a file. Files to read are checked to be
regular files before they are opened (:func:`check_regular_file`): a FIFO or
a device would block the reader, or never end.

A folder replaced whole (``--force``) is checked first to hold only what its
earlier writer wrote (:func:`check_replaceable`): never an input of the
command, nor a user's file.

Outputs written by one process at a time, and folders filled beside their
output and moved into place, are in :mod:`tumble.locks`.
"""

from __future__ import annotations

import errno
import json
import os
import stat
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from tumble.errors import QUOTED_PATH_LENGTH, InputError, OutputError, quoted

__all__ = [
    "check_output",
    "check_regular_file",
    "check_replaceable",
    "file_kind",
    "mode_kind",
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


#: Words for the kinds of files by the test of :mod:`stat` that tells them.
_KINDS = (
    (stat.S_ISREG, "a regular file"),
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
    (stat.S_ISLNK, "a symbolic link"),
)


def file_kind(path: str | os.PathLike[str]) -> str | None:
    """What ``path`` is, in words ("a regular file", "a folder", "a FIFO", "a
    character device", ...), following symbolic links; None where nothing is
    there (or the system cannot look: a name too long, a path through a file)."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return None
    return mode_kind(mode)


def mode_kind(mode: int) -> str:
    """What a file of ``st_mode`` ``mode`` is, in words (see :func:`file_kind`)."""
    return next((words for test, words in _KINDS if test(mode)), "a special file")


def check_regular_file(path: str | os.PathLike[str], what: str) -> None:
    """Refuse, before it is opened, a file to read that exists but is not a
    regular file or a folder: reading a FIFO waits for a writer that may never
    come, reading a device may never end. A missing path or a folder is left
    to the caller's own message.

    ``what`` names the file in the message (e.g. "the recording").

    Raises
    ------
    InputError
        ``Expected the recording to be a regular file, got 'x', a FIFO.``
    """
    kind = file_kind(path)
    if kind is not None and kind not in ("a regular file", "a folder"):
        raise InputError(
            f"Expected {what} to be a regular file, got {quoted(path, QUOTED_PATH_LENGTH)}, {kind}."
        )


def _check_replaceable(path: Path, shown: str, what: str, *, folder: bool) -> None:
    """Refuse an existing ``path`` that writing ``what`` there would destroy: a
    FIFO, a device or a socket (a rename replaces whatever is there; the
    superuser's ``--report /dev/null`` would replace the system's null device
    with a file)."""
    kind = file_kind(path)
    if kind is None or kind in ("a regular file", "a folder"):
        return
    wanted = "a folder" if folder else "a regular file"
    raise OutputError(
        f"Expected {what} to be {wanted} or a new path, got {shown!r}, {kind}.", shown
    )


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
    output folder can be written; that an existing path is a regular file (a
    folder with ``folder``), not a FIFO, a device or a socket that writing
    would replace.

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
        _check_replaceable(target, shown, what, folder=folder)
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


def check_replaceable(
    path: str | os.PathLike[str],
    what: str,
    *,
    listed_in: str,
    inputs: Iterable[str | os.PathLike[str]] = (),
) -> None:
    """Refuse, before any work, to replace the folder ``path`` whole where that
    would delete files its earlier writer did not write.

    Refused: a folder that holds one of ``inputs`` (the files the command reads:
    a scenario, a recording, a mesh; links followed), or that holds a file or
    folder that its ``listed_in`` file (``summary.json`` of a run, ``fit.json``
    of a fit: its ``"files"`` lists what the writer wrote) does not list. A
    path that is not an existing folder passes, and so does, but for the
    inputs, a folder without a ``listed_in`` file (no earlier writer's: the
    caller refuses it).

    Parameters
    ----------
    path : the output folder, to be replaced whole (``--force``).
    what : names it in messages, e.g. "the run folder".
    listed_in : the name of the earlier writer's record in the folder.
    inputs : the files the command reads.

    Raises
    ------
    OutputError
        Naming the folder and the first file in the way.
    """
    shown = quoted(str(path), QUOTED_PATH_LENGTH)
    target = os.path.realpath(path)
    if not os.path.isdir(target):
        return
    for given in inputs:
        source = os.path.realpath(given)
        if os.path.commonpath([source, target]) == target:
            raise OutputError(
                f"Expected {what} to hold none of the files read, got {shown}, which holds "
                f"{quoted(os.fspath(given), QUOTED_PATH_LENGTH)}: name another folder.",
                str(path),
            )
    if not os.path.lexists(Path(target) / listed_in):
        # No earlier writer's folder: the caller's check of the folder says what it holds.
        return
    listed = {listed_in, *_listed(Path(target) / listed_in)}
    extra = sorted(name for name in _names(target) if name not in listed)
    if extra:
        raise OutputError(
            f"Expected {what} to hold only the files its {listed_in} lists to replace it "
            f"whole, got {shown}, which holds "
            f"{quoted(extra[0], QUOTED_PATH_LENGTH)} too: move it away, or name another folder.",
            str(path),
        )


def _listed(record: Path) -> list[str]:
    """The names the ``"files"`` of a writer's JSON record lists; none where it
    cannot be read (or is too large to be one: 1 MB), or is no regular file (a
    FIFO would never end)."""
    if file_kind(record) != "a regular file":
        return []
    try:
        with open(record, "rb") as stream:
            data = json.loads(stream.read(1 << 20).decode("utf-8"))
    except (OSError, ValueError):
        return []
    files = data.get("files") if isinstance(data, dict) else None
    if not isinstance(files, list):
        return []
    return [name for name in files if isinstance(name, str)]


def _names(folder: str) -> list[str]:
    """The names in ``folder``; none where it cannot be read."""
    try:
        return os.listdir(folder)
    except OSError:
        return []


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
        renaming the file; ``path`` is then unchanged. ``path`` is not a
        regular file or a new path (a FIFO, a device, a socket: checked
        before and again just before the rename, which would replace it).
    """
    target = Path(path)
    _check_replaceable(target, str(path), "the file", folder=False)
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
        _check_replaceable(target, str(path), "the file", folder=False)
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
