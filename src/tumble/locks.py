"""One writer at a time for each output, and folders filled beside their output.

An output is written by one process at a time: :class:`OutputLock` claims it
(a lock file beside a folder replaced whole, inside a folder written into) and
refuses a second writer with one line naming the first (its pid, host and
start). The claim is a ``flock`` on the lock file, which the kernel releases
when its process ends, however it ends: a lock left by a killed process is
taken over, and the temporary folders and files that process left (their
names end in ``.partial``) are removed by the next writer; those of a writer
still alive are never touched. :func:`staged_folder` fills a new folder
beside its output and moves it into place whole
(:func:`tumble.files.check_replaceable` says first whether it may).
"""

from __future__ import annotations

import errno
import json
import os
import re
import shutil
import socket
import sys
import tempfile
import threading
import time
import warnings
from collections.abc import Iterable, Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tumble.errors import QUOTED_PATH_LENGTH, OutputError, OutputInUseError, cut, quoted
from tumble.files import check_output, output_error, path_exists, permissions

__all__ = ["LOCK_INSIDE", "OutputLock", "staged_folder"]

#: The lock file of a folder written into (a sweep's), inside it.
LOCK_INSIDE = ".tumble.lock"

#: The temporary folders beside an output, as :func:`staged_folder` names them:
#: ``.NAME.XXXXXXXX.tumble.partial`` (being filled) and ``.NAME.XXXXXXXX.tumble.old``
#: (the folder it replaces, moved aside), XXXXXXXX as :func:`tempfile.mkdtemp`
#: draws it. "tumble" in the name: only such a folder is ever removed as a dead
#: writer's leftover, never a folder of another program's or a user's.
_PARTIAL, _OLD = ".tumble.partial", ".tumble.old"
_STAGED = re.compile(r"\.(?P<name>.+)\.[a-z0-9_]{8}\.tumble\.(?P<kind>partial|old)", re.DOTALL)
#: The lock file beside an output called NAME.
_LOCK_BESIDE = re.compile(r"\.(?P<name>.+)\.lock", re.DOTALL)
#: The keys a lock file's record holds at least (it has "since" and "command"
#: too): only a file holding them is taken as a lock of tumble's.
_RECORD_KEYS = frozenset({"pid", "host"})


class _Foreign(Exception):
    """The lock file's name holds a file that is not a lock of tumble's."""


class _Busy(Exception):
    """The lock file is held; ``record`` is what its owner wrote in it (None if unreadable)."""

    def __init__(self, record: dict[str, Any] | None) -> None:
        super().__init__()
        self.record = record


@dataclass
class _Claim:
    """A lock this process holds: its open lock file, the thread that took it, how
    many times (a writer may call another that claims the same output)."""

    descriptor: int
    thread: int
    depth: int = 1


_CLAIMS: dict[str, _Claim] = {}
_GUARD = [threading.Lock()]  # in a list: a forked child replaces it


def _forget_claims() -> None:
    """In a forked child (figure workers, a pool's processes): close the lock
    files inherited from the parent, so that the parent's locks end with the
    parent alone, and forget them (closing does not release the parent's lock;
    unlocking would)."""
    for claim in _CLAIMS.values():
        with suppress(OSError):
            os.close(claim.descriptor)
    _CLAIMS.clear()
    _GUARD[0] = threading.Lock()  # another thread may have held it at the fork


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_claims)


class OutputLock:
    """An exclusive claim on an output: one writer at a time, across processes.

    A second writer is refused with one line that names the first: its pid,
    host, and since when it writes. The claim is a ``flock`` on a lock file,
    which the kernel releases when the process ends, however it ends; the file
    holds the owner's record (JSON: pid, host, since, command) for the message,
    and is removed on release. A lock file left by a killed process is taken
    over, and what that process left half-made is removed: beside a folder
    replaced whole, the temporary folders of :func:`staged_folder` whose
    output no live process claims (a folder moved aside by a writer killed in
    the middle of a replacement is moved back, as it was before); inside a
    folder written into, the temporary files (``*.partial``) under the names
    in ``own``. On a file system without locks, the record decides: a live pid
    on this host holds it.

    The claim is re-entrant in its thread (a command claims its output at once,
    then calls a library writer that claims it again) and refused to other
    threads. Use it as a context manager, or call :meth:`acquire` and
    :meth:`release`.

    Parameters
    ----------
    path : the output folder: one replaced whole (a run's, a fit's; the lock
        file is ``.NAME.lock`` beside it), or, with ``inside``, one written
        into (a sweep's; the lock file is ``PATH/.tumble.lock``).
    what : names the output in messages, e.g. "the run folder".
    inside : see ``path``.
    own : with ``inside``, the names of the files and folders that the writer
        keeps in the folder: the temporary files left under them are removed.

    Raises
    ------
    OutputInUseError
        (:meth:`acquire`) Another writer holds the output.
    tumble.errors.OutputError
        (:meth:`acquire`) The output cannot be written there
        (:func:`check_output`); the folders made for the lock file are removed.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        what: str,
        *,
        inside: bool = False,
        own: Iterable[str] = (),
    ) -> None:
        self.shown = str(path)
        self.target = Path(os.path.abspath(path))
        self.what = what
        self.inside = inside
        self.own = tuple(own)
        self.file = self.target / LOCK_INSIDE if inside else _beside_lock(self.target)
        # As messages show them: quoted, a long path cut.
        self._named = quoted(self.shown, QUOTED_PATH_LENGTH)
        self._file_named = quoted(str(self.file), QUOTED_PATH_LENGTH)
        self._made: list[Path] = []
        self._held = False

    def __enter__(self) -> OutputLock:
        self.acquire()
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()

    def acquire(self) -> None:
        """Claim the output (see the class). Raises OutputInUseError or OutputError."""
        key = str(self.file)
        with _GUARD[0]:
            claim = _CLAIMS.get(key)
            if claim is not None and claim.thread == threading.get_ident():
                claim.depth += 1
                self._held = True
                return
        if claim is not None:
            raise self._in_use({"pid": os.getpid()})
        check_output(self.target, self.what, folder=True, staged=not self.inside)
        folder = self.file.parent
        self._made = [p for p in [folder, *folder.parents] if not path_exists(p)]  # deepest first
        try:
            folder.mkdir(parents=True, exist_ok=True)
            descriptor, previous = _take(self.file)
        except _Busy as busy:
            self._remove_made()
            raise self._in_use(busy.record) from None
        except _Foreign:
            self._remove_made()
            raise OutputError(
                f"Expected the lock file {self._file_named} of {self.what} "
                f"{self._named} to be tumble's or absent, got a file of another kind "
                "(move it away, or write elsewhere).",
                self.shown,
            ) from None
        except OSError as exc:
            self._remove_made()
            raise output_error(exc, self.shown, self.what) from exc
        with _GUARD[0]:
            _CLAIMS[key] = _Claim(descriptor, threading.get_ident())
        self._held = True
        if previous is not None and previous.get("host") != socket.gethostname():
            warnings.warn(
                f"Took over the lock of {self.what} {self._named} that pid "
                f"{previous.get('pid')} on {previous.get('host')} left (since "
                f"{previous.get('since')}): no process holds it any more.",
                UserWarning,
                stacklevel=2,
            )
        with suppress(OSError):  # what cannot be removed stays: it harms no one
            if self.inside:
                self._clean_inside()
            else:
                self._clean_beside()

    def release(self) -> None:
        """End the claim (the outermost one of its thread removes the lock file)."""
        if not self._held:
            return
        self._held = False
        key = str(self.file)
        with _GUARD[0]:
            claim = _CLAIMS.get(key)
            if claim is None:  # forgotten in a forked child
                return
            claim.depth -= 1
            if claim.depth:
                return
            del _CLAIMS[key]
        _drop(claim.descriptor, self.file)
        self._remove_made()

    def _remove_made(self) -> None:
        """Remove the folders made for the lock file that are still empty."""
        for folder in self._made:
            try:
                folder.rmdir()
            except OSError:  # holds the output now, or another writer's files
                break
        self._made = []

    def _in_use(self, record: dict[str, Any] | None) -> OutputInUseError:
        if record is None:
            who = f"another process (its lock file {self._file_named} does not say which)"
        elif record.get("pid") == os.getpid():
            who = f"another thread of this process (pid {os.getpid()})"
        else:
            who = f"pid {record.get('pid')} on {record.get('host')} since {record.get('since')}"
        return OutputInUseError(
            f"Expected {self.what} {self._named} to be free to write, got one being "
            f"written by {who}: wait for it to end, or write elsewhere.",
            self.shown,
        )

    def _clean_beside(self) -> None:
        """Remove the temporary folders beside the output that no live writer
        claims: this output's (it is claimed here), and those of other outputs
        whose lock file is free, with that lock file. (A temporary folder with
        no lock file beside it has no writer that can be asked: it is kept.)"""
        folder = self.target.parent
        others = set()
        for entry in _entries(folder):
            staged = _STAGED.fullmatch(entry.name)
            if staged is not None and staged["name"] == self.target.name:
                _remove_staged(Path(entry.path), self.target)
            elif staged is None and (lock := _LOCK_BESIDE.fullmatch(entry.name)) is not None:
                others.add(lock["name"])
        others.discard(self.target.name)
        for name in sorted(n for n in others if _holds_record(_beside_lock(folder / n))):
            with _free(folder / name) as free:
                if free:  # listed again: a writer killed since the first look left its own
                    for entry in _entries(folder):
                        staged = _STAGED.fullmatch(entry.name)
                        if staged is not None and staged["name"] == name:
                            _remove_staged(Path(entry.path), folder / name)

    def _clean_inside(self) -> None:
        """Remove the temporary files (``*.partial``) left in the folder under
        the names in ``own``: claimed here, no live writer is making them."""
        for entry in _entries(self.target):
            name = entry.name
            mine = any(name == f"{own}.partial" or name.startswith(f".{own}.") for own in self.own)
            if mine and name.endswith(".partial"):
                _remove(Path(entry.path))
            elif name in self.own and entry.is_dir(follow_symlinks=False):
                for root, folders, files in os.walk(entry.path):
                    for leftover in [*folders, *files]:
                        if leftover.endswith(".partial"):
                            _remove(Path(root) / leftover)
                    folders[:] = [f for f in folders if not f.endswith(".partial")]


def _beside_lock(target: Path) -> Path:
    """The lock file of an output replaced whole: ``.NAME.lock`` beside it."""
    return target.parent / f".{target.name}.lock"


def _entries(folder: Path) -> list[os.DirEntry[str]]:
    """The entries of ``folder``; none where it cannot be read."""
    try:
        with os.scandir(folder) as found:
            return list(found)
    except OSError:
        return []


def _remove(path: Path) -> None:
    """Remove a file or a folder, whichever ``path`` is; gone already is fine."""
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        path.unlink(missing_ok=True)


def _remove_staged(entry: Path, target: Path) -> None:
    """Remove a temporary folder of :func:`staged_folder` whose writer is gone; a
    folder it had moved aside to replace, and not replaced, is moved back."""
    if not entry.is_dir() or entry.is_symlink():
        return  # not a folder of staged_folder: a file written beside, say
    old = entry / target.name
    if entry.name.endswith(_OLD) and old.is_dir() and not os.path.lexists(target):
        with suppress(OSError):
            os.replace(old, target)
    shutil.rmtree(entry, ignore_errors=True)


@contextmanager
def _free(target: Path) -> Iterator[bool]:
    """Claim the output ``target`` (beside lock) for the block if no one holds it:
    whether it was free. The block may remove what a dead writer of it left."""
    file = _beside_lock(target)
    if str(file) in _CLAIMS:
        yield False
        return
    try:
        descriptor, _ = _take(file, create=False)
    except (_Busy, _Foreign, OSError):
        yield False
        return
    try:
        yield True
    finally:
        _drop(descriptor, file)


def _holds_record(file: Path) -> bool:
    """Whether ``file`` holds a lock record of tumble's (read only: a file of
    another program's is never written)."""
    try:
        with open(file, "rb") as stream:
            record = json.loads(stream.read(4096).decode("utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(record, dict) and record.keys() >= _RECORD_KEYS


def _take(file: Path, *, create: bool = True) -> tuple[int, dict[str, Any] | None]:
    """Lock ``file`` (created if missing, unless not ``create``) and write this
    process's record in it: its descriptor, and the record of a previous owner
    that left it (None if none).

    Raises
    ------
    _Busy
        Another process holds it.
    OSError
        It cannot be created or written.
    """
    flags = os.O_RDWR | (os.O_CREAT if create else 0)
    for _ in range(100):  # another round only when its owner removed it meanwhile
        descriptor = os.open(file, flags, 0o666)  # the umask applies
        try:
            locked = _flock(descriptor)
            if locked is None:  # no locks on this file system: the record decides
                record = _read(descriptor)
                if record is not None and _running(record):
                    raise _Busy(record)
            elif not locked:
                raise _Busy(_read(descriptor, wait=True))
            try:
                same = os.path.samestat(os.fstat(descriptor), os.stat(file))
            except FileNotFoundError:
                same = False
            if not same:  # removed by its owner between our opening and locking it
                if not create:
                    raise FileNotFoundError(errno.ENOENT, os.strerror(errno.ENOENT), str(file))
                os.close(descriptor)
                continue
            if os.fstat(descriptor).st_size and not _holds_record(file):
                raise _Foreign()
            previous = _read(descriptor)
            record = {
                "pid": os.getpid(),
                "host": socket.gethostname(),
                "since": time.strftime("%Y-%m-%d %H:%M:%S %z"),
                "command": cut(" ".join(sys.argv), QUOTED_PATH_LENGTH),
            }
            os.ftruncate(descriptor, 0)
            os.lseek(descriptor, 0, os.SEEK_SET)
            os.write(descriptor, (json.dumps(record) + "\n").encode("utf-8"))
            return descriptor, previous
        except BaseException:
            os.close(descriptor)
            raise
    raise _Busy(None)


def _flock(descriptor: int) -> bool | None:
    """Lock the open file without waiting: True if locked, False if another
    process holds it, None where the system or file system has no such locks."""
    if sys.platform == "win32":
        return None
    import fcntl

    try:
        fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    except OSError as exc:
        if exc.errno in (errno.ENOLCK, errno.EOPNOTSUPP, errno.ENOSYS, errno.EINVAL):
            return None
        raise
    return True


def _read(descriptor: int, *, wait: bool = False) -> dict[str, Any] | None:
    """The owner's record in an open lock file; None if empty or unreadable.
    ``wait``: a little, for an owner that has locked the file but not yet
    written its record."""
    for _ in range(50 if wait else 1):
        try:
            os.lseek(descriptor, 0, os.SEEK_SET)
            record = json.loads(os.read(descriptor, 4096).decode("utf-8"))
        except (OSError, ValueError):
            record = None
        if isinstance(record, dict):
            return record
        if wait:
            time.sleep(0.01)
    return None


def _running(record: dict[str, Any]) -> bool:
    """Whether the owner of a record runs: a live pid on this host (another
    host's cannot be seen: taken as running)."""
    if record.get("host") != socket.gethostname():
        return True
    pid = record.get("pid")
    if not isinstance(pid, int) or pid == os.getpid() or pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, but another user's
        return True
    return True


def _drop(descriptor: int, file: Path) -> None:
    """Remove a held lock file (if it is still this one), then close it, which
    releases the lock: a writer that opened it meanwhile sees it removed and
    opens a new one."""
    try:
        if os.path.samestat(os.fstat(descriptor), os.stat(file)):
            file.unlink()
    except OSError:
        pass
    os.close(descriptor)


@contextmanager
def staged_folder(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A new, empty folder beside ``path`` to fill, named ``.NAME.XXXXXXXX.tumble.partial``:
    it replaces ``path`` whole when the block ends normally (a folder there is
    moved aside first, then removed; should the move fail, it is put back),
    and is removed when the block raises. Hold the output's
    :class:`OutputLock` around it: the next writer removes what a killed one
    left.

    Raises
    ------
    OSError
        An error of the file system while making, filling or moving the folder.
    """
    target = Path(path)
    staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=_PARTIAL, dir=target.parent))
    try:
        os.chmod(staging, permissions(directory=True))
        yield staging
        _replace_folder(staging, target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def _replace_folder(staging: Path, target: Path) -> None:
    """Move the finished folder into place; an old one is moved aside first, then
    removed. Anything but a folder at ``target`` (a file, a FIFO, a device) is
    left as it is, and the move fails."""
    if target.is_dir():
        aside = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=_OLD, dir=target.parent))
        try:
            os.replace(target, aside / target.name)
        except OSError:
            shutil.rmtree(aside, ignore_errors=True)
            raise
        try:
            os.replace(staging, target)
        except OSError:
            os.replace(aside / target.name, target)  # the old folder back, unchanged
            shutil.rmtree(aside, ignore_errors=True)
            raise
        shutil.rmtree(aside, ignore_errors=True)
    else:
        os.replace(staging, target)
