"""One request of the catalogue of hostile requests (``bench/hostile_catalogue.py``)
and what must come of it, with the files it is given."""

from __future__ import annotations

import os
import stat
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["Case", "Files", "command", "library", "lost_inputs", "make_inputs"]

Files = dict[str, bytes | Callable[[], bytes]]


@dataclass(frozen=True)
class Case:
    """One request and what must come of it.

    ``surface``: "cli" (``call`` is the list of arguments of ``tumble``) or
    "library" (``call`` is Python source run with ``tb`` (tumble), ``np``,
    ``ureg`` (tumble's registry), ``pint``, ``Path`` and ``tmp`` (the case's
    folder) in scope, leaving its answer in ``result``). ``check`` (for
    ``expect="result"``): an expression that holds only for a right answer.
    ``files``: name → bytes, or a function that makes them (for large files,
    made only when the case runs). ``fifos``, ``devices`` (a character device
    like ``/dev/null``, made where the process may make one) and ``sparse``
    (name → (bytes written, size the file is extended to without writing))
    are inputs of other kinds. Every input must come out of the request as it
    went in: a file changed or gone, or a FIFO or device replaced, is lost data.
    """

    name: str
    surface: str
    call: str | tuple[str, ...]
    expect: str = "refusal"
    check: str = ""
    files: Files = field(default_factory=dict)
    #: Exceptions besides tumble.InputError that refuse cleanly (by Python's own rules).
    refusals: tuple[str, ...] = ()
    #: Exit codes besides 0 of a command's answer (``tumble audit``: 1, findings).
    exit_codes: tuple[int, ...] = ()
    fifos: tuple[str, ...] = ()
    devices: tuple[str, ...] = ()
    sparse: dict[str, tuple[bytes, int]] = field(default_factory=dict)


def library(
    name: str,
    code: str,
    expect: str = "refusal",
    check: str = "",
    *,
    fifos: tuple[str, ...] = (),
    sparse: dict[str, tuple[bytes, int]] | None = None,
    **files: bytes | Callable[[], bytes],
) -> Case:
    """A request through the library."""
    return Case(name, "library", code, expect, check, dict(files), fifos=fifos, sparse=sparse or {})


def command(
    name: str,
    *args: str,
    expect: str = "refusal",
    check: str = "",
    files: Files | None = None,
    exit_codes: tuple[int, ...] = (),
    fifos: tuple[str, ...] = (),
    devices: tuple[str, ...] = (),
    sparse: dict[str, tuple[bytes, int]] | None = None,
) -> Case:
    """A request through the command line."""
    return Case(
        name, "cli", tuple(args), expect, check, files or {}, (), exit_codes, fifos, devices,
        sparse or {},
    )  # fmt: skip


def make_inputs(case: Case, folder: Path) -> dict[str, bytes | str]:
    """Make the case's inputs in ``folder``; what each must still be afterwards
    (a file's bytes, or the kind of a special file)."""
    kept: dict[str, bytes | str] = {}
    for name, data in case.files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        kept[name] = data() if callable(data) else data
        path.write_bytes(kept[name])
    for name, (data, size) in case.sparse.items():
        with open(folder / name, "wb") as stream:
            stream.write(data)
            stream.truncate(size)
        kept[name] = "sparse"
    for name in case.fifos:
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        os.mkfifo(folder / name)
        kept[name] = "fifo"
    for name in case.devices:
        # A device like /dev/null (1, 3), where this process may make one (as root).
        try:
            os.mknod(folder / name, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
        except PermissionError:
            continue
        kept[name] = "device"
    return kept


def lost_inputs(folder: Path, kept: dict[str, bytes | str]) -> list[str]:
    """The inputs that did not come out of the request as they went in."""
    lost = []
    for name, was in kept.items():
        path = folder / name
        try:
            mode = path.lstat().st_mode
        except OSError:
            lost.append(f"{name} is gone")
            continue
        if was == "fifo" and not stat.S_ISFIFO(mode):
            lost.append(f"the FIFO {name} was replaced")
        elif was == "device" and not stat.S_ISCHR(mode):
            lost.append(f"the device {name} was replaced")
        elif was == "sparse" and not stat.S_ISREG(mode):
            lost.append(f"{name} was replaced")
        elif isinstance(was, bytes) and (not stat.S_ISREG(mode) or path.read_bytes() != was):
            lost.append(f"{name} was changed")
    return lost
