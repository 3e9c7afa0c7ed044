"""A robot file's text as written, and edits of it in place.

A :class:`Document` is the file decoded in its own encoding (a byte-order mark,
else the encoding its XML declaration names, else UTF-8) with its elements at
their offsets in the decoded text; :meth:`Document.tag` finds where each
attribute of a start tag is written (:meth:`Tag.edits` rewrites them), and
:meth:`Document.edited` makes edits (start, stop, new text) and encodes the
text back as it was.
"""

from __future__ import annotations

import codecs
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tumble.errors import InputError, quoted
from tumble.robots.elements import Element, parse_elements
from tumble.robots.model import shown

__all__ = [
    "Document",
    "Tag",
    "empty_element",
    "written_number",
    "written_numbers",
]


_ATTRIBUTE = re.compile(r"""\s+([^\s=/>]+)\s*=\s*("[^"]*"|'[^']*')""")
_CLOSING = re.compile(r"\s*(/?)>")


@dataclass(frozen=True)
class Tag:
    """Where the parts of a start tag lie in the text: each attribute's value
    (within the quotes) and whole span (with the space before it), the end of
    the last attribute, the ``/>`` of an empty element (or ``>``), and the end."""

    values: dict[str, tuple[int, int]]
    spans: dict[str, tuple[int, int]]
    last: int
    closing: int
    end: int
    empty: bool

    def edits(self, values: Mapping[str, str]) -> list[tuple[int, int, str]]:
        """The edits that give the attributes ``values`` (as written): each value
        replaced where the attribute is written, the others added after the
        tag's last attribute."""
        edits = [(*self.values[k], v) for k, v in values.items() if k in self.values]
        added = "".join(f' {k}="{v}"' for k, v in values.items() if k not in self.values)
        if added:
            edits.append((self.last, self.last, added))
        return edits


@dataclass(frozen=True)
class Document:
    """A robot file decoded in its own encoding, with its elements as written."""

    path: Path
    codec: str
    text: str
    root: Element

    @classmethod
    def parse(cls, path: Path, data: bytes) -> Document:
        """The document of the file at ``path`` whose content is ``data``.

        Raises
        ------
        InputError
            An encoding Python does not know, bytes that do not decode in the
            file's encoding and encode back unchanged, XML that is not
            well-formed.
        """
        codec = _encoding(path, data)
        try:
            text = data.decode(codec)
        except UnicodeDecodeError:
            text = ""
        if not text or text.encode(codec) != data:
            raise InputError(
                f"Expected {shown(path)} to be text in its encoding, {codec}, got bytes "
                "that do not decode and encode back unchanged."
            )
        root = _elements(path, data, codec)
        return cls(path, codec, text, root)

    @property
    def newline(self) -> str:
        """The file's line ending: ``"\\r\\n"`` where it has one, else ``"\\n"``."""
        return "\r\n" if "\r\n" in self.text else "\n"

    def tag(self, element: Element, owner: str) -> Tag:
        """The start tag of ``element``, checked to be written where expat saw it."""
        text = self.text
        head = "<" + element.name
        at = element.offset + len(head)
        if not text.startswith(head, element.offset) or not re.match(r"[\s/>]", text[at : at + 1]):
            raise InputError(
                f"Expected the <{element.name}> of {owner} written in {self.path.name} at line "
                f"{element.line}, got other text there: it cannot be corrected in place."
            )
        values, spans = {}, {}
        while (match := _ATTRIBUTE.match(text, at)) is not None:
            values[match.group(1)] = (match.start(2) + 1, match.end(2) - 1)
            spans[match.group(1)] = (match.start(), match.end())
            at = match.end()
        closing = _CLOSING.match(text, at)
        if closing is None:  # expat parsed it: only a reader's bug gets here
            raise InputError(
                f"Expected a complete start tag <{element.name}> at line {element.line} of "
                f"{self.path.name}, got {quoted(text[element.offset : at + 20])}."
            )
        empty = closing.group(1) == "/"
        return Tag(values, spans, at, closing.start(1), closing.end(), empty)

    def check_written_out(self, element: Element, owner: str) -> None:
        """Refuse a link whose content holds an entity reference: what it brings may
        be the very element to correct, written elsewhere."""
        if element.references:
            raise InputError(
                f"Expected {owner} written out in {self.path.name} to correct it, got the "
                f"entity reference {element.references[0]} inside it: correct the entity "
                "by hand."
            )

    def indent(self, element: Element) -> str:
        """The spaces before ``element``'s start tag on its line ("" if not alone)."""
        line = self.text.rfind("\n", 0, element.offset) + 1
        head = self.text[line : element.offset]
        return head if head.strip() == "" else ""

    def children_inserted(
        self, element: Element, owner: str, blocks: list[str]
    ) -> tuple[int, int, str]:
        """The edit that puts ``blocks`` (one element each) first in ``element``,
        one a line, indented one step further; an empty element gets its end tag."""
        tag = self.tag(element, owner)
        indent = self.indent(element)
        inner = "".join(self.newline + indent + "  " + block for block in blocks)
        if tag.empty:
            closing = f">{inner}{self.newline}{indent}</{element.name}>"
            return tag.closing, tag.end, closing
        return tag.end, tag.end, inner

    def edited(self, edits: list[tuple[int, int, str]]) -> bytes:
        """The file with ``edits`` ((start, stop, text) in the decoded text) made,
        encoded as it was."""
        text = self.text
        bound = len(text)
        for start, stop, new in sorted(edits, reverse=True):
            if stop > bound:  # two edits of one span: a reader's bug, never a wrong file
                raise InputError(
                    f"Expected separate places to correct in {self.path.name}, got two edits "
                    f"overlapping at character {start}."
                )
            text = text[:start] + new + text[stop:]
            bound = start
        return text.encode(self.codec)


def _encoding(path: Path, data: bytes) -> str:
    """The codec of a file, as XML finds it: a byte-order mark (kept in the decoded
    text, so that it is written back), UTF-16's ``<`` without one, the XML
    declaration's ``encoding``, else UTF-8."""
    if data.startswith((b"\xff\xfe", b"<\x00")):
        return "utf-16-le"
    if data.startswith((b"\xfe\xff", b"\x00<")):
        return "utf-16-be"
    if data.startswith(codecs.BOM_UTF8):
        return "utf-8"
    declared = re.match(rb"""<\?xml\s[^>]*?encoding\s*=\s*["']([A-Za-z][\w.\-]*)["']""", data)
    if declared is None:
        return "utf-8"
    name = declared.group(1).decode("ascii")
    try:
        codec = codecs.lookup(name).name
    except LookupError:
        raise InputError(
            f"Expected an encoding Python knows in the XML declaration of {shown(path)}, "
            f"got {name!r}."
        ) from None
    # A declared UTF-16 without a mark: expat reads it big-endian.
    return "utf-16-be" if codec == "utf-16" else codec


def _elements(path: Path, data: bytes, codec: str) -> Element:
    """The elements written in the file with their offsets in the decoded text.
    Internal entities are not expanded, so no element is taken from an entity's
    text; a reference to one is kept on the elements around it."""
    root = parse_elements(path, data, keep_entities=True)
    # Byte offsets to offsets in the decoded text, one piece at a time (in
    # document order, the offsets only grow).
    byte = character = 0
    for element in (root, *root.walk()):
        character += len(data[byte : element.offset].decode(codec))
        byte = element.offset
        element.offset = character
    return root


def written_number(value: float) -> str:
    """``value`` as a corrected copy writes it: the shortest text that reads back
    as the same float64."""
    return repr(float(value))


def written_numbers(values: Any) -> str:
    """``values`` (an iterable of numbers) written as :func:`written_number`, one
    space apart."""
    return " ".join(written_number(v) for v in values)


def empty_element(name: str, attributes: Mapping[str, str]) -> str:
    """An empty element ``<name a="v" …/>`` with ``attributes`` (values as written)."""
    text = " ".join(f'{k}="{v}"' for k, v in attributes.items())
    return f"<{name} {text}/>"
