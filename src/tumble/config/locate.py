"""Line numbers of keys in a TOML text, for error messages.

The standard library's ``tomllib`` gives values but not where they were
written, so error messages find the line of a key path here: a small scan of
table headers (``[a.b]``, ``[[parts]]``), ``key = value`` lines and dotted keys.
Inline tables and arrays spread over lines are attributed to the line of their
key. The result is a hint for the reader, never used to interpret the file.
"""

from __future__ import annotations

import re

__all__ = ["KeyPath", "key_lines", "line_of"]

_HEADER = re.compile(r"^\s*(\[\[?)\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")
_KEY = re.compile(
    r"""^\s*((?:[A-Za-z0-9_-]+|"[^"]*"|'[^']*')(?:\s*\.\s*(?:[A-Za-z0-9_-]+|"[^"]*"|'[^']*'))*)\s*="""
)
_INLINE_KEY = re.compile(r"""[{,]\s*([A-Za-z0-9_-]+|"[^"]*"|'[^']*')\s*=""")

#: A key path: table and key names, and indices into arrays of tables.
KeyPath = tuple[str | int, ...]


def _split(dotted: str) -> list[str]:
    parts = re.findall(r"""[A-Za-z0-9_-]+|"[^"]*"|'[^']*'""", dotted)
    return [p.strip("\"'") for p in parts]


def key_lines(text: str) -> dict[KeyPath, int]:
    """Map each key path (array-of-tables entries by index) to its 1-based line."""
    lines: dict[KeyPath, int] = {}
    table: KeyPath = ()
    counts: dict[KeyPath, int] = {}
    depth = 0  # brackets and braces still open from a value spread over lines
    for number, line in enumerate(text.splitlines(), start=1):
        code = _strip_comment(line)
        if depth > 0:
            depth += _balance(code)
            continue
        header = _HEADER.match(line)
        if header:
            names = tuple(_split(header.group(2)))
            if header.group(1) == "[[":
                index = counts.get(names, -1) + 1
                counts[names] = index
                table = (*names, index)
            else:
                table = _resolve(names, counts)
            lines.setdefault(table, number)
            # The table itself also answers for its parent path.
            for k in range(1, len(table)):
                lines.setdefault(table[:k], number)
            continue
        key = _KEY.match(code)
        if key:
            path = (*table, *_split(key.group(1)))
            lines.setdefault(path, number)
            rest = code[key.end() :]
            for inner in _INLINE_KEY.finditer(rest):
                lines.setdefault((*path, inner.group(1).strip("\"'")), number)
            depth = _balance(rest)
    return lines


def _resolve(names: tuple[str, ...], counts: dict[KeyPath, int]) -> KeyPath:
    """A ``[a.b]`` header inside the last entry of an array of tables ``[[a]]``."""
    path: list[str | int] = []
    for name in names:
        path.append(name)
        key = tuple(path)
        if key in counts:
            path.append(counts[key])
    return tuple(path)


def _strip_comment(line: str) -> str:
    quote = ""
    for k, char in enumerate(line):
        if quote:
            if char == quote:
                quote = ""
        elif char in "\"'":
            quote = char
        elif char == "#":
            return line[:k]
    return line


def _balance(code: str) -> int:
    quote = ""
    depth = 0
    for char in code:
        if quote:
            if char == quote:
                quote = ""
        elif char in "\"'":
            quote = char
        elif char in "[{":
            depth += 1
        elif char in "]}":
            depth -= 1
    return depth


def line_of(lines: dict[KeyPath, int], path: KeyPath) -> int | None:
    """The line of ``path`` or of its nearest ancestor that has one."""
    for k in range(len(path), 0, -1):
        if path[:k] in lines:
            return lines[path[:k]]
    return None
