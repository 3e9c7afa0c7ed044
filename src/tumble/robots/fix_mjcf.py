"""The edits that write a corrected inertia into an MJCF body's ``<inertial>``.

``mass``, ``pos``, and ``diaginertia`` (the orientation kept) where the
corrected tensor is diagonal in the element's frame and the element had
``diaginertia``; else ``fullinertia`` in body axes, with ``diaginertia`` and the
orientation removed, as MuJoCo allows none of them beside it.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.robots.elements import parse_elements
from tumble.robots.fix_text import Document, empty_element, written_number, written_numbers
from tumble.robots.model import INERTIA_ATTRIBUTES, Link

__all__ = ["SAME", "declared_inertia", "inertia_tensor", "mjcf_edits"]

Array = NDArray[np.float64]

#: MJCF's ways of orienting an ``<inertial>`` (at most one, and none beside
#: ``fullinertia``).
_ORIENTATIONS = ("quat", "axisangle", "xyaxes", "zaxis", "euler")

#: Two values are the same read back when they differ by less than this fraction
#: of the largest entry: far above the rounding of 17 significant digits and of
#: one change of axes (1e-15), far below any correction the audit proposes.
SAME = 1e-9


def mjcf_edits(
    document: Document, link: Link, correction: Mapping[str, Any]
) -> list[tuple[int, int, str]]:
    """The edits (start, stop, new text) of ``document`` that give body ``link``
    its ``correction`` (attribute names of URDF: ``mass``, ``xyz``, ``ixx`` …
    ``izz`` in the inertial frame's axes; kg, m, kg·m²).

    Raises
    ------
    InputError
        The body is not written in the file (an include, an entity, a
        ``<replicate>``) or has no name, or its content holds an entity
        reference.
    """
    owner = f"body {link.name!r}"
    body = next(
        (e for e in document.root.descendants("body") if e.attributes.get("name") == link.name),
        None,
    )
    if body is None:
        raise InputError(
            f"Expected {owner} written in {document.path.name} to correct it, got "
            f"{_elsewhere(document, link.name)}."
        )
    document.check_written_out(body, owner)
    old = link.inertial
    rotation = np.eye(3) if old is None else old.rotation
    tensor = inertia_tensor({**declared_inertia(link), **correction})
    mass = float(correction.get("mass", link.mass))
    centre = correction.get("xyz", tuple(link.center_of_mass))
    inertial = body.child("inertial")
    changed = any(k in correction for k in INERTIA_ATTRIBUTES)
    if inertial is None:
        attributes = {"pos": written_numbers(centre), "mass": written_number(mass)}
        attributes.update(_inertia_attributes(tensor, rotation, diagonal_allowed=True))
        block = empty_element("inertial", attributes)
        return [document.children_inserted(body, owner, [block])]
    tag = document.tag(inertial, owner)
    attributes = {}
    if "mass" in correction:
        attributes["mass"] = written_number(mass)
    if "xyz" in correction:
        attributes["pos"] = written_numbers(centre)
    removed: list[str] = []
    if changed:
        diagonal = "diaginertia" in tag.values and "fullinertia" not in tag.values
        new = _inertia_attributes(tensor, rotation, diagonal_allowed=diagonal, orient=False)
        attributes.update(new)
        if "fullinertia" in new:
            removed = [a for a in ("diaginertia", *_ORIENTATIONS) if a in tag.spans]
    return [*tag.edits(attributes), *((*tag.spans[a], "") for a in removed)]


def declared_inertia(link: Link) -> dict[str, float]:
    """The link's declared ``ixx`` … ``izz`` (kg·m², inertial frame axes); zeros
    where it declares no inertial."""
    values = (0.0,) * 6 if link.inertial is None else link.inertial.values
    return dict(zip(INERTIA_ATTRIBUTES, (float(v) for v in values), strict=True))


def inertia_tensor(values: Mapping[str, Any]) -> Array:
    """The symmetric 3×3 tensor of ``ixx`` … ``izz`` (kg·m²) in ``values``."""
    xx, xy, xz, yy, yz, zz = (float(values[a]) for a in INERTIA_ATTRIBUTES)
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def _inertia_attributes(
    tensor: Array, rotation: Array, *, diagonal_allowed: bool, orient: bool = True
) -> dict[str, str]:
    """MJCF's attributes for ``tensor`` (inertial frame ``rotation``, columns in body
    axes): ``diaginertia`` (and, with ``orient``, the frame's ``quat`` unless it is
    the body's) where it is diagonal and allowed, else ``fullinertia`` in body axes
    (M11 M22 M33 M12 M13 M23)."""
    off = np.abs(tensor[np.triu_indices(3, 1)])
    if diagonal_allowed and np.all(off <= SAME * np.abs(np.diag(tensor)).max(initial=0.0)):
        attributes = {"diaginertia": written_numbers(np.diag(tensor))}
        if orient and not np.allclose(rotation, np.eye(3), rtol=0.0, atol=1e-15):
            from scipy.spatial.transform import Rotation

            quaternion = Rotation.from_matrix(rotation).as_quat(scalar_first=True)
            attributes["quat"] = written_numbers(quaternion)
        return attributes
    body = rotation @ tensor @ rotation.T
    order = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
    return {"fullinertia": written_numbers(body[i, j] for i, j in order)}


def _elsewhere(document: Document, name: str) -> str:
    """Where a body missing from the main file is: the included file that defines
    it, nowhere (a body without a name), or what may hide it."""
    base = document.path.parent
    for include in document.root.descendants("include"):
        file = include.attributes.get("file", "")
        path = base / file
        # Only a regular file is read: a FIFO or a device would hang or never end.
        if not file or not path.is_file():
            continue
        try:
            root = parse_elements(path, path.read_bytes(), keep_entities=True)
        except (InputError, OSError):
            continue
        if any(b.attributes.get("name") == name for b in root.descendants("body")):
            return f"it in the included file {file!r}: correct that file"
    if re.fullmatch(r"body \d+", name):  # the reader's name of a body that has none
        return "a body without a name, which cannot be found in the file: name it"
    return "none there: it comes from an included file, an entity or a <replicate>"
