"""The elements of an XML robot file as written, read with expat.

A tree of :class:`Element` (name, attributes, line, byte offset of the start
tag) is what both the URDF reader and the corrected copy need: the byte offset
places an edit in the file, which a DOM library does not give.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from xml.parsers import expat

from tumble.errors import InputError
from tumble.robots.model import shown

__all__ = ["Element", "parse_elements"]

#: The entity references XML defines; any other in an element's content is the
#: document's own and may carry elements.
PREDEFINED = ("&amp;", "&lt;", "&gt;", "&quot;", "&apos;")


class Element:
    """An element as written: its name, attributes, line, the byte offset of its
    start tag, its children, and the entity references in its content
    (its descendants' included) where they are kept unexpanded."""

    __slots__ = ("attributes", "children", "line", "name", "offset", "references")

    def __init__(self, name: str, attributes: dict[str, str], line: int, offset: int) -> None:
        self.name = name
        self.attributes = attributes
        self.line = line
        self.offset = offset
        self.children: list[Element] = []
        self.references: list[str] = []

    def child(self, name: str) -> Element | None:
        """The first child of that name, the one the readers take."""
        return next((c for c in self.children if c.name == name), None)

    def all(self, name: str) -> list[Element]:
        """Every child of that name, in document order."""
        return [c for c in self.children if c.name == name]

    def walk(self) -> Iterator[Element]:
        """Every element below this one, in document order (a loop, not recursion:
        MJCF bodies may nest thousands deep)."""
        stack = list(reversed(self.children))
        while stack:
            element = stack.pop()
            yield element
            stack += reversed(element.children)

    def descendants(self, name: str) -> list[Element]:
        """Every element of that name below this one, in document order."""
        return [element for element in self.walk() if element.name == name]


def parse_elements(path: Path, data: bytes, *, keep_entities: bool = False) -> Element:
    """The root element of an XML file, each element with its line and byte offset.

    Parameters
    ----------
    path : the file; messages name it.
    data : its content.
    keep_entities : leave the document's own internal entities unexpanded (no
        element is taken from an entity's text) and list each reference on the
        elements around it (:attr:`Element.references`).

    Raises
    ------
    InputError
        ``data`` is not well-formed XML.
    """
    parser = expat.ParserCreate()
    top = Element("", {}, 0, 0)
    stack = [top]

    def start(name: str, attributes: dict[str, str]) -> None:
        element = Element(name, attributes, parser.CurrentLineNumber, parser.CurrentByteIndex)
        stack[-1].children.append(element)
        stack.append(element)

    def end(name: str) -> None:
        stack.pop()

    def other(text: str) -> None:
        # Setting this handler stops expat expanding internal entities in content.
        if text.startswith("&") and not text.startswith("&#") and text not in PREDEFINED:
            for element in stack[1:]:
                element.references.append(text)

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    if keep_entities:
        parser.DefaultHandler = other
    try:
        parser.Parse(data, True)
    except expat.ExpatError as error:
        raise InputError(
            f"Expected {shown(path)} to be well-formed XML, got "
            f"{expat.errors.messages[error.code]} at line {error.lineno}, "
            f"column {error.offset + 1}."
        ) from None
    if not top.children:  # expat refuses a document without one: a guard, not a case
        raise InputError(f"Expected an XML element in {shown(path)}, got none.")
    return top.children[0]
