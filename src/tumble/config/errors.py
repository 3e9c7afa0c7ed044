"""Errors of configuration files, as one line: ``SOURCE, line N, `dotted.path`: message``.

pydantic reports where a value failed as a location inside the validated data
(``("body", "shape", "radius")``, with the names of union branches mixed in)
and in its own words ("Input should be ..."). A user editing a TOML file needs
the file, the line, the key path as written and a message in tumble's template
("Expected X, got Y."): :func:`first_error` makes that line from the first
problem, :func:`where` makes its prefix for checks done after validation.

Models raise two kinds of custom errors that carry a key below the place where
they were raised, so that the message points at the key rather than at its
table: :func:`unknown_key` (a key that is not in the schema) and
:func:`key_error` (a problem with one key found by a model-wide check).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from tumble.config.locate import key_lines, line_of
from tumble.errors import QUOTED_LENGTH, InputError, quoted, unknown_choice

if TYPE_CHECKING:
    # Imported where used: listing and showing built-in files needs no pydantic.
    from pydantic import ValidationError
    from pydantic_core import PydanticCustomError

__all__ = [
    "ConfigError",
    "dotted",
    "first_error",
    "key_error",
    "key_text",
    "shown",
    "unknown_key",
    "where",
]

#: pydantic's prefixes of messages from validators that raise ValueError or assert.
_PREFIXES = ("Value error, ", "Assertion failed, ")


class ConfigError(InputError):
    """A configuration file or a built-in name is invalid; the message names the file,
    the line and the key."""


def unknown_key(key: str, known: Sequence[str]) -> PydanticCustomError:
    """The error for a key that the schema does not have, suggesting the nearest one
    (:func:`tumble.errors.unknown_choice`: ``Expected the key to be one of a, b, got
    'x'. Did you mean a?``); :func:`first_error` adds the key to the path, so the
    line is the key's own.
    """
    from pydantic_core import PydanticCustomError

    message = str(unknown_choice(key, known, "the key"))
    return PydanticCustomError("unknown_key", "{message}", {"key": key, "message": message})


def key_text(key: str) -> str:
    """A key as messages write it: as it is, or with its line breaks and other
    unprintable characters escaped (``a\\nb``), so that a message stays one line;
    cut after :data:`~tumble.errors.QUOTED_LENGTH` characters."""
    text = key if key.isprintable() else repr(key)[1:-1]
    return text if len(text) <= QUOTED_LENGTH else f"{text[:QUOTED_LENGTH]}..."


def key_error(key: str | tuple[str | int, ...], message: str) -> PydanticCustomError:
    """An error found by a model-wide check that is about ``key`` (a name, or a key path
    below the model raising it): the message is located at that key, not at the model."""
    from pydantic_core import PydanticCustomError

    path = (key,) if isinstance(key, str) else tuple(key)
    return PydanticCustomError("key_error", "{message}", {"message": message, "key": path})


def dotted(path: Sequence[Any]) -> str:
    """A key path as written in messages: ``body.parts[0].radius``."""
    text = ""
    for part in path:
        if isinstance(part, int):
            text += f"[{part}]"
        else:
            name = key_text(str(part))
            text += f".{name}" if text else name
    return text


def where(text: str, source: str, path: Sequence[Any]) -> str:
    """``SOURCE, line N, `dotted.path``` for a key path of the TOML ``text``.

    The line is the key's, or its nearest table's; without one (or without a
    path) the prefix is shorter: ``SOURCE, `path``` or ``SOURCE``.
    """
    path = tuple(path)
    line = line_of(key_lines(text), path) if path else None
    place = f"{source}, line {line}" if line is not None else source
    return f"{place}, `{dotted(path)}`" if path else place


def first_error(
    exc: ValidationError,
    text: str,
    source: str,
    *,
    key_path: Callable[[tuple[Any, ...]], list[Any]] = list,
    name_input: bool = False,
    count_others: bool = False,
) -> str:
    """The first problem of a validation, as one line ``SOURCE, line N, `path`: message``.

    An unknown key comes first when there are several problems: with a union,
    pydantic also reports the branches that were not meant, and a typo
    explains them all.

    Parameters
    ----------
    exc : the error of validating the TOML ``text`` read from ``source``.
    key_path : turns pydantic's location into the key path of the file (drops
        the tags of union branches); default: the location as it is.
    name_input : reword pydantic's own messages as ``Expected ..., got VALUE.``
        (otherwise ``Expected a valid value: input should be ...``).
    count_others : end with ``(N more problems)`` when there are others.
    """
    errors = exc.errors(include_url=False)
    errors.sort(key=lambda e: 0 if e["type"] == "unknown_key" else 1)
    error = errors[0]
    path = key_path(tuple(error["loc"]))
    if error["type"] == "unknown_key":
        path.append(error["ctx"]["key"])
    elif error["type"] == "key_error":
        path.extend(error["ctx"]["key"])
    message = str(error["msg"])
    for prefix in _PREFIXES:
        message = message.removeprefix(prefix)
    if error["type"] == "missing":
        message = (
            f"Expected the table [{path[-1]}], which is missing."
            if len(path) == 1
            else f"Expected the key `{path[-1]}`, which is missing."
        )
    elif not message.startswith("Expected"):
        message = _reworded(message, error["input"]) if name_input else _plain(message)
    more = len(errors) - 1
    tail = f" ({more} more problem{'s' if more > 1 else ''})" if count_others and more else ""
    return f"{where(text, source, path)}: {message}{tail}"


def _plain(message: str) -> str:
    return f"Expected a valid value: {message[0].lower()}{message[1:]}."


def _reworded(message: str, given: Any) -> str:
    """pydantic's "Input should be ..." and "String should ..." in tumble's template."""
    if message.startswith("Input should be "):
        rest = message.removeprefix("Input should be ")
        if rest.startswith(("greater", "less")):
            rest = f"a value {rest}"
        return f"Expected {rest}, got {shown(given)}."
    if message.startswith("String should "):
        rest = message.removeprefix("String should ")
        return f"Expected a string that should {rest}, got {shown(given)}."
    return f"Expected a valid value ({message}), got {shown(given)}."


def shown(value: Any) -> str:
    """A TOML value as messages show it: ``true``, ``a table``, ``an array``, ``'x'``, ``2``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, list):
        return "an array"
    return quoted(value)
