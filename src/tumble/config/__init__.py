"""The configuration layer shared by scenario files and sweep files.

Both are TOML files validated by strict pydantic models, given as a path or as
the name of a file shipped with tumble, and both report a problem as one line
that names the file, the line, the key path and what was expected::

    spin.toml, line 7, `body.radius`: Expected `radius` to be a length in m, got 3 kg ...

* :class:`StrictModel` — the base of every table: frozen, unknown keys refused
  (:func:`unknown_key`), with the nearest known key suggested.
* :class:`Builtins`, :func:`read_source` — a ``.toml`` path or a built-in name
  to a :class:`Source` (text, name for messages, folder).
* :func:`parse_toml`, :func:`validate_toml` — TOML text to data, and to a model.
* :func:`first_error` — a pydantic ``ValidationError`` as that one line;
  :func:`where` — its ``SOURCE, line N, `key.path``` prefix, for checks made
  after validation; :func:`key_error` — a model-wide check's error about one key.
* :func:`key_lines`, :func:`line_of` — the lines of the keys of a TOML text.
* :class:`ConfigError` — the base of :class:`~tumble.scenario.ScenarioError`
  and :class:`~tumble.sweep.SweepError` (an :class:`~tumble.InputError`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from tumble.config.errors import (
    ConfigError,
    dotted,
    first_error,
    key_error,
    key_text,
    shown,
    unknown_key,
    where,
)
from tumble.config.locate import KeyPath, key_lines, line_of
from tumble.config.sources import Builtins, Source, parse_toml, read_source, validate_toml

if TYPE_CHECKING:
    from tumble.config.model import StrictModel

__all__ = [
    "Builtins",
    "ConfigError",
    "KeyPath",
    "Source",
    "StrictModel",
    "dotted",
    "first_error",
    "key_error",
    "key_lines",
    "key_text",
    "line_of",
    "parse_toml",
    "read_source",
    "shown",
    "unknown_key",
    "validate_toml",
    "where",
]


def __getattr__(name: str) -> Any:
    # Defining a pydantic model imports most of pydantic; listing and showing
    # the built-in files, which import this package, need none of it.
    if name == "StrictModel":
        from tumble.config.model import StrictModel

        return StrictModel
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
