"""A corrected copy of a robot file that differs from it only where corrected.

The source's bytes are copied and, for each corrected link, only the values of
the attributes named by the correction are rewritten, inside the start tags of
its ``<inertial>``'s ``<mass>``, ``<origin>`` and ``<inertia>`` elements
(found by the byte offsets the reader kept). A link without those elements gets
them, inserted after its start tag. Everything else (comments, spacing, the
order of attributes, other links) is byte for byte the source's, so a diff of
the two shows the corrections alone.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from tumble.errors import InputError
from tumble.robots.findings import Audit
from tumble.robots.model import INERTIA_ATTRIBUTES, Link, shown

__all__ = ["check_corrected_path", "write_corrected"]


def write_corrected(audit: Audit, out: Any) -> Path:
    """Write the audited file with each link's correction (:meth:`Audit.corrections`)
    to ``out``, never over the source; returns ``out``.

    Raises
    ------
    InputError
        ``out`` is the audited file itself, or the file is not a URDF.
    OutputError
        ``out`` cannot be written (nothing is left half-written).
    """
    from tumble.files import output_error, write_bytes

    source = audit.robot.path
    target = Path(out)
    check_corrected_path(source, target)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise output_error(error, target.parent, "the folder") from None
    data = source.read_bytes()
    edits: list[tuple[int, int, bytes]] = []
    for name, correction in audit.corrections().items():
        edits += _link_edits(data, audit.robot.links[name], correction)
    for start, stop, text in sorted(edits, reverse=True):
        data = data[:start] + text + data[stop:]
    return write_bytes(target, data)


def check_corrected_path(source: Path, out: Path) -> None:
    """Refuse, before any work, a corrected copy over its source, of a file that
    is not a URDF, or where it cannot be written."""
    from tumble.files import check_output

    if out.resolve() == source.resolve():
        raise InputError(
            f"Expected --fix to name a new file, got the audited file itself, "
            f"{shown(source)}: the source is never changed."
        )
    if source.suffix.lower() != ".urdf":
        raise InputError(f"Expected a URDF file to correct, got {shown(source)}.")
    check_output(out, "the corrected file", folder=False)


def _number(value: float) -> str:
    return repr(float(value))


def _values(correction: dict[str, Any]) -> dict[str, dict[str, str]]:
    """The correction as new attribute texts, by element."""
    elements: dict[str, dict[str, str]] = {"mass": {}, "origin": {}, "inertia": {}}
    for name, value in correction.items():
        if name == "mass":
            elements["mass"]["value"] = _number(value)
        elif name == "xyz":
            elements["origin"]["xyz"] = " ".join(_number(v) for v in value)
        elif name in INERTIA_ATTRIBUTES:
            elements["inertia"][name] = _number(value)
    return {k: v for k, v in elements.items() if v}


def _link_edits(
    data: bytes, link: Link, correction: dict[str, Any]
) -> list[tuple[int, int, bytes]]:
    elements = _values(correction)
    inertial = link.inertial
    offsets = {} if inertial is None else dict(inertial.offsets)
    edits = []
    missing = []
    for element, attributes in elements.items():
        if element in offsets:
            edits.append(_tag_edit(data, offsets[element], attributes))
        else:
            missing.append((element, attributes))
    if not missing:
        return edits
    if "inertial" in offsets:
        # Insert the missing children after <inertial ...>.
        end = _tag_end(data, offsets["inertial"])
        indent = _indent(data, offsets["inertial"]) + b"  "
        text = b"".join(b"\n" + indent + _element(e, a) for e, a in missing)
        return [*edits, (end, end, text)]
    start = _link_offset(data, link)
    end = _tag_end(data, start)
    indent = _indent(data, start) + b"  "
    inner = indent + b"  "
    full = {"origin": {"xyz": "0 0 0"}, "mass": {"value": "0"}, "inertia": {}}
    for element, attributes in missing:
        full[element] = {**full[element], **attributes}
    children = b"".join(b"\n" + inner + _element(e, full[e]) for e in ("origin", "mass", "inertia"))
    block = b"\n" + indent + b"<inertial>" + children + b"\n" + indent + b"</inertial>"
    return [*edits, (end, end, block)]


def _element(name: str, attributes: dict[str, str]) -> bytes:
    if name == "inertia":
        attributes = {a: attributes.get(a, "0") for a in INERTIA_ATTRIBUTES}
    text = " ".join(f'{k}="{v}"' for k, v in attributes.items())
    return f"<{name} {text}/>".encode()


def _tag_end(data: bytes, start: int) -> int:
    """The offset just past the ``>`` that ends the start tag at ``start`` (quotes
    respected: ``>`` may appear inside an attribute's value)."""
    quote = None
    for i in range(start, len(data)):
        c = data[i : i + 1]
        if quote is not None:
            quote = None if c == quote else quote
        elif c in (b'"', b"'"):
            quote = c
        elif c == b">":
            return i + 1
    raise InputError("Expected a complete start tag in the robot file, got the end of the file.")


def _indent(data: bytes, start: int) -> bytes:
    line = data.rfind(b"\n", 0, start) + 1
    head = data[line:start]
    return head if head.strip() == b"" else b""


def _tag_edit(data: bytes, start: int, attributes: dict[str, str]) -> tuple[int, int, bytes]:
    """The start tag at ``start`` with ``attributes``' values replaced (or added)."""
    end = _tag_end(data, start)
    tag = data[start:end].decode("utf-8")
    for name, value in attributes.items():
        pattern = re.compile(rf"(\s{re.escape(name)}\s*=\s*)([\"'])(.*?)\2", re.DOTALL)
        match = pattern.search(tag)
        if match is not None:
            quote = match.group(2)
            tag = f"{tag[: match.start()]}{match.group(1)}{quote}{value}{quote}{tag[match.end() :]}"
        else:
            closing = 2 if tag.endswith("/>") else 1
            tag = f'{tag[:-closing].rstrip()} {name}="{value}"{tag[-closing:]}'
    return start, end, tag.encode("utf-8")


def _link_offset(data: bytes, link: Link) -> int:
    """The offset of the link's start tag, found by its name (the reader keeps the
    offsets of inertial elements only)."""
    pattern = re.compile(
        rb"<link\s[^>]*name\s*=\s*[\"']" + re.escape(link.name.encode()) + rb"[\"']"
    )
    match = pattern.search(data)
    if match is None:
        raise InputError(f"Expected link {link.name!r} in the robot file, got none.")
    return match.start()
