"""Reading configuration files: a ``.toml`` path or the name of a built-in file,
then TOML, then a model.

Scenarios and sweeps are both given on the command line as either a file or
the name of one shipped with tumble (``tumble run gyroscope``, ``tumble sweep
flip-map``); the rules for telling them apart and the messages for a missing
file, an unreadable one, an unknown name and invalid TOML are the same for
both, so they live here once.
"""

from __future__ import annotations

import difflib
import os
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from tumble.config.errors import ConfigError, first_error

if TYPE_CHECKING:
    from pydantic import BaseModel

__all__ = ["Builtins", "Source", "parse_toml", "read_source", "validate_toml"]

Model = TypeVar("Model", bound="BaseModel")


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
    """

    kind: str
    package: str
    folder_name: str
    error: type[ConfigError]
    order: tuple[str, ...] = ()
    describe: tuple[str, ...] = ("description",)

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
            suggests the nearest.
        """
        names = self.names()
        if name not in names:
            close = difflib.get_close_matches(name, names, n=1)
            hint = f" Did you mean {close[0]}?" if close else ""
            raise self.error(
                f"Expected a built-in {self.kind} ({', '.join(names)}) or a .toml file, "
                f"got {name!r}.{hint}"
            )
        return (self.folder() / f"{name}.toml").read_text(encoding="utf-8")

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
    if path.suffix.lower() == ".toml" or path.exists():
        if not path.is_file():
            raise builtins.error(f"Expected a {builtins.kind} file, got {name!r} (no such file).")
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise builtins.error(f"Expected a readable UTF-8 file, got {name!r}: {exc}.") from None
        return Source(text, name, path.resolve().parent, path)
    return Source(builtins.text(name), f"builtin:{name}", builtins.folder(), None)


def parse_toml(text: str, source: str, error: type[ConfigError] = ConfigError) -> dict[str, Any]:
    """The data of TOML ``text``.

    Raises
    ------
    ConfigError (``error``)
        Invalid TOML, with tomllib's line and column.
    """
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{source}: Expected valid TOML, got an error: {exc}.") from None


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
