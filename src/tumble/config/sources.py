"""Reading configuration files: a ``.toml`` path or the name of a built-in file,
then TOML, then a model.

Scenarios and sweeps are both given on the command line as either a file or
the name of one shipped with tumble (``tumble run gyroscope``, ``tumble sweep
flip-map``); the rules for telling them apart and the messages for a missing
file, an unreadable one, an unknown name and invalid TOML are the same for
both, so they live here once.

Files are read as people save them: a UTF-8 byte order mark (which Windows
editors write, and TOML does not allow) is dropped, and a file nested deeper
than Python's TOML parser can follow is one line that gives its depth.
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from tumble.config.errors import ConfigError, first_error
from tumble.errors import QUOTED_PATH_LENGTH, quoted, unknown_choice
from tumble.files import file_kind

if TYPE_CHECKING:
    from pydantic import BaseModel

__all__ = ["Builtins", "Source", "parse_toml", "read_source", "validate_toml"]

Model = TypeVar("Model", bound="BaseModel")

#: Every kind of built-in file by its ``kind``, as each is defined; a name unknown
#: to one kind is looked up in the others, to say which command runs it.
_KINDS: dict[str, Builtins] = {}

#: The modules that define the kinds of built-in files, imported when a name is
#: unknown (a command that reads scenarios has not imported the sweeps).
_DEFINED_IN = ("tumble.scenario.loaded", "tumble.sweep.engine")

#: The byte order mark some editors begin a UTF-8 file with.
_BYTE_ORDER_MARK = "\ufeff"


@dataclass(frozen=True)
class Builtins:
    """The built-in files of one kind: the ``*.toml`` files of a folder in a package.

    Attributes
    ----------
    kind : what they are (``"scenario"``, ``"sweep"``): names them in messages,
        and names the table that describes each file.
    package, folder_name : where they are (``"tumble.scenario"``, ``"builtin"``).
    error : the exception for an unknown name, a missing file and the like.
    order : the names listed first, in this order; the others follow sorted.
    describe : the keys of the ``[kind]`` table whose first non-empty value
        describes a file (its first line).
    command : the command that runs a file of this kind; default ``tumble KIND``.
    """

    kind: str
    package: str
    folder_name: str
    error: type[ConfigError]
    order: tuple[str, ...] = ()
    describe: tuple[str, ...] = ("description",)
    command: str = ""

    def __post_init__(self) -> None:
        _KINDS[self.kind] = self

    @property
    def runs_with(self) -> str:
        """The command that runs a file of this kind (``tumble run``)."""
        return self.command or f"tumble {self.kind}"

    def folder(self) -> Path:
        """The folder of the files (also where the files they name are looked up)."""
        return Path(str(resources.files(self.package) / self.folder_name))

    def names(self) -> list[str]:
        """The names of the files (without ``.toml``): those of ``order``, then the rest sorted."""
        found = {p.stem for p in self.folder().glob("*.toml")}
        return [n for n in self.order if n in found] + sorted(found - set(self.order))

    def text(self, name: str) -> str:
        """The TOML text of the built-in file ``name``.

        Raises
        ------
        ConfigError (``error``)
            If there is none of that name; the message lists the names and
            suggests the nearest, or says how to run a built-in of the other kind.
        """
        names = self.names()
        if name not in names:
            other = self._other_kind(name)
            hint = None
            if other is not None:
                hint = f"That is a built-in {other.kind}: run it with `{other.runs_with} {name}`."
            error = unknown_choice(
                name, names, f"a built-in {self.kind}", alternative="a .toml file", hint=hint
            )
            raise self.error(str(error))
        return (self.folder() / f"{name}.toml").read_text(encoding="utf-8")

    def _other_kind(self, name: str) -> Builtins | None:
        """The other kind of built-in file that has one named ``name``, if any."""
        import importlib

        for module in _DEFINED_IN:
            try:
                importlib.import_module(module)
            except ImportError:  # an optional part that is not installed
                continue
        for kind in _KINDS.values():
            try:
                if kind is not self and name in kind.names():
                    return kind
            except (ImportError, OSError):  # its package is gone (one made for a test)
                continue
        return None

    def description(self, name: str) -> str:
        """One line that describes the built-in file ``name`` (empty if it has none)."""
        table = tomllib.loads(self.text(name)).get(self.kind, {})
        text = next((table[key] for key in self.describe if table.get(key)), "")
        return str(text).split("\n")[0]


@dataclass(frozen=True)
class Source:
    """The text of a configuration file and where it came from.

    Attributes
    ----------
    text : the TOML text as written.
    name : its name in messages: the path as given, or ``builtin:NAME``.
    folder : where relative paths written in it are looked up.
    file : the file read, or None for a built-in.
    """

    text: str
    name: str
    folder: Path
    file: Path | None


def read_source(given: str | os.PathLike[str], builtins: Builtins) -> Source:
    """A file (a path ending in ``.toml``, or any that exists) or a built-in file by name.

    Raises
    ------
    ConfigError (``builtins.error``)
        No such file, an unreadable or non-UTF-8 file, or an unknown name.
    """
    name = str(given)
    path = Path(name)
    shown = quoted(name, QUOTED_PATH_LENGTH)
    try:
        exists = path.exists()
    except OSError as exc:  # a name too long for the system, a folder that cannot be read
        raise builtins.error(
            f"Expected a {builtins.kind} file or a built-in name, got {quoted(name)}: "
            f"{exc.strerror or exc}."
        ) from None
    if path.suffix.lower() == ".toml" or exists:
        kind = file_kind(path)
        if kind != "a regular file":  # a FIFO or a device would block the reader
            why = {None: "no such file", "a folder": "a folder"}.get(kind, kind)
            raise builtins.error(f"Expected a {builtins.kind} file, got {shown} ({why}).")
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise builtins.error(f"Expected a readable UTF-8 file, got {shown}: {exc}.") from None
        return Source(text, name, path.resolve().parent, path)
    return Source(builtins.text(name), f"builtin:{name}", builtins.folder(), None)


def parse_toml(text: str, source: str, error: type[ConfigError] = ConfigError) -> dict[str, Any]:
    """The data of TOML ``text``.

    A byte order mark at the start is dropped.

    Raises
    ------
    ConfigError (``error``)
        Invalid TOML, with tomllib's line and column; arrays and inline tables
        nested deeper than tomllib can follow (about 500 levels), with the depth.
    """
    text = text.removeprefix(_BYTE_ORDER_MARK)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{source}: Expected valid TOML, got an error: {exc}.") from None
    except RecursionError:  # tomllib recurses once per level of nesting
        raise error(
            f"{source}: Expected arrays and inline tables nested at most a few hundred levels "
            f"deep, got {_depth(text)} levels."
        ) from None


def _depth(text: str) -> int:
    """The deepest nesting of arrays and inline tables in TOML ``text`` (brackets
    outside strings and comments; a table header counts as one level)."""
    deepest = depth = 0
    position, end = 0, len(text)
    while position < end:
        char = text[position]
        if char in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif char in "]}":
            depth = max(depth - 1, 0)
        elif char == "#":
            newline = text.find("\n", position)
            position = end if newline < 0 else newline
            continue
        elif char in "\"'":
            position = _string_end(text, position)
            continue
        position += 1
    return deepest


def _string_end(text: str, start: int) -> int:
    """The position after the TOML string that starts at ``start`` (basic or literal,
    on one line or several; backslash escapes in basic strings)."""
    quote = text[start]
    delimiter = quote * 3 if text.startswith(quote * 3, start) else quote
    position = start + len(delimiter)
    while position < len(text):
        if quote == '"' and text[position] == "\\":
            position += 2
            continue
        if text.startswith(delimiter, position):
            return position + len(delimiter)
        if delimiter == quote and text[position] == "\n":  # unterminated: tomllib says so
            return position
        position += 1
    return position


def validate_toml(
    model: type[Model],
    text: str,
    source: str,
    *,
    error: type[ConfigError] = ConfigError,
    key_path: Callable[[tuple[Any, ...]], list[Any]] = list,
    name_input: bool = False,
    count_others: bool = False,
) -> Model:
    """TOML ``text`` validated into ``model``.

    ``key_path``, ``name_input`` and ``count_others`` shape the message, as in
    :func:`~tumble.config.errors.first_error`.

    Raises
    ------
    ConfigError (``error``)
        Invalid TOML, or the first problem of the validation as one line
        ``SOURCE, line N, `key.path`: message``.
    """
    from pydantic import ValidationError

    data = parse_toml(text, source, error)
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        message = first_error(
            exc,
            text,
            source,
            key_path=key_path,
            name_input=name_input,
            count_others=count_others,
        )
        raise error(message) from None
