"""A corrected copy of a robot file that differs from it only where corrected.

The file is parsed again with expat, whose start-tag positions place every
edit (a comment, a CDATA section or an attribute's value is never taken for a
tag), and decoded in its own encoding: a byte-order mark, else the encoding its
XML declaration names, else UTF-8. For each corrected link only the values of
the attributes the correction names are rewritten, in the start tags of its
inertial elements; an element it lacks is inserted after its parent's start
tag. The text is encoded back in the file's encoding, so everything else
(comments, spacing, the order of attributes, other links) is byte for byte the
source's and a diff of the two files shows the corrections alone.

* URDF: the link's ``<inertial>``: ``<mass value>``, ``<origin xyz>`` and
  ``<inertia ixx … izz>`` (the inertial frame's axes, as the audit gives them).
* MJCF: the body's ``<inertial>``: ``mass``, ``pos``, and ``diaginertia`` (the
  orientation kept) where the corrected tensor is diagonal in the element's
  frame and the element had ``diaginertia``; else ``fullinertia`` in body axes,
  with ``diaginertia`` and the orientation removed, as MuJoCo allows none of
  them beside it.

A link written through an entity reference, or in another file (an MJCF
``<include>``), is refused: an edit there would land elsewhere. Before the copy
is put in place it is read back and audited: every corrected link must carry
its corrected values and every other link its former ones, and an MJCF must
compile in MuJoCo with them; otherwise nothing is written.

The file's text and the edits of it are :mod:`tumble.robots.fix_text`'s, the
edits of an MJCF body :mod:`tumble.robots.fix_mjcf`'s.
"""

from __future__ import annotations

import os
import re
import tempfile
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, quoted
from tumble.robots.findings import Audit
from tumble.robots.fix_mjcf import SAME, declared_inertia, inertia_tensor, mjcf_edits
from tumble.robots.fix_text import Document, empty_element, written_number, written_numbers
from tumble.robots.mjcf import one_line
from tumble.robots.model import INERTIA_ATTRIBUTES, Link, shown

__all__ = ["check_corrected_path", "write_corrected"]

Array = NDArray[np.float64]

#: The robot files a corrected copy is written of, by suffix.
_KINDS = {".urdf": "URDF", ".xml": "MJCF"}


def write_corrected(audit: Audit, out: Any) -> Path:
    """Write the audited file with each link's correction (:meth:`Audit.corrections`)
    to ``out``, never over the source; returns ``out``.

    Parameters
    ----------
    audit : the :class:`~tumble.robots.Audit` of a URDF (``.urdf``) or MJCF
        (``.xml``) file, from :func:`tumble.robots.audit`.
    out : the path of the corrected copy (str or path-like).

    Raises
    ------
    InputError
        ``audit`` is not an audit, ``out`` is the audited file itself, the file
        is neither URDF nor MJCF, a corrected link is not written out in the
        file (an entity, an included file), or the copy does not read back with
        the corrections (nothing is written then).
    OutputError
        ``out`` cannot be written (nothing is left half-written).
    """
    from tumble.files import output_error

    if not isinstance(audit, Audit):
        raise InputError(
            f"Expected an Audit from tumble.robots.audit to correct, got "
            f"{type(audit).__name__} {quoted(audit)}."
        )
    if not isinstance(out, (str, os.PathLike)):
        raise InputError(
            f"Expected the corrected file's path (str or Path), got "
            f"{type(out).__name__} {quoted(out)}."
        )
    source = audit.robot.path
    target = Path(out)
    check_corrected_path(source, target)
    kind = _KINDS[source.suffix.lower()]
    try:
        data = source.read_bytes()
    except OSError as error:
        raise InputError(
            f"Expected a readable robot file, got {shown(source)}: {error.strerror}."
        ) from None
    document = Document.parse(source, data)
    corrections = audit.corrections()
    edits: list[tuple[int, int, str]] = []
    for name, correction in corrections.items():
        link = audit.robot.links.get(name)
        if link is None:
            raise InputError(
                f"Expected a correction of a link of {shown(source)}, got one of {name!r}."
            )
        _check_attributes(name, correction)
        if kind == "URDF":
            edits += _urdf_edits(document, link, correction)
        else:
            edits += mjcf_edits(document, link, correction)
    written = document.edited(edits)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise output_error(error, target.parent, "the folder") from None
    _staged(target, written, lambda copy: _verify(audit, kind, copy, corrections))
    return target


def _staged(target: Path, data: bytes, check: Callable[[Path], None]) -> None:
    """Write ``data`` under a temporary name beside ``target`` that keeps its suffix
    (MuJoCo reads a file by its suffix), ``check`` it, then move it into place;
    removed if anything fails, so ``target`` is never half-written or wrong."""
    from tumble.files import output_error, permissions

    try:
        handle, name = tempfile.mkstemp(
            prefix=f".{target.name}.", suffix=target.suffix, dir=target.parent
        )
    except OSError as error:
        raise output_error(error, target, "the corrected file") from None
    os.close(handle)
    staged = Path(name)
    try:
        staged.write_bytes(data)
        check(staged)
        os.chmod(staged, permissions())
        os.replace(staged, target)
    except OSError as error:
        raise output_error(error, target, "the corrected file") from None
    finally:
        staged.unlink(missing_ok=True)


def check_corrected_path(source: Path, out: Path) -> None:
    """Refuse, before any work, a corrected copy over its source, of a file that
    is neither a URDF (``.urdf``) nor an MJCF (``.xml``), or where it cannot be
    written."""
    from tumble.files import check_output

    if out.resolve() == source.resolve():
        raise InputError(
            f"Expected --fix to name a new file, got the audited file itself, "
            f"{shown(source)}: the source is never changed."
        )
    if source.suffix.lower() not in _KINDS:
        raise InputError(
            f"Expected a URDF (.urdf) or MJCF (.xml) file to correct, got {shown(source)}."
        )
    check_output(out, "the corrected file", folder=False)


def _check_attributes(name: str, correction: Mapping[str, Any]) -> None:
    known = ("mass", "xyz", *INERTIA_ATTRIBUTES)
    unknown = [k for k in correction if k not in known]
    if unknown:
        raise InputError(
            f"Expected the correction of link {name!r} to name {', '.join(known)}, "
            f"got {unknown[0]!r}."
        )


# ---------------------------------------------------------------- URDF


def _urdf_edits(
    document: Document, link: Link, correction: Mapping[str, Any]
) -> list[tuple[int, int, str]]:
    owner = f"link {link.name!r}"
    element = next(
        (
            e
            for e in document.root.children
            if e.name == "link" and e.attributes.get("name") == link.name
        ),
        None,
    )
    if element is None:
        raise InputError(
            f"Expected {owner} written in {document.path.name} to correct it, got none "
            "there: it comes from an entity."
        )
    document.check_written_out(element, owner)
    values: dict[str, dict[str, str]] = {"origin": {}, "mass": {}, "inertia": {}}
    for name, value in correction.items():
        if name == "mass":
            values["mass"]["value"] = written_number(value)
        elif name == "xyz":
            values["origin"]["xyz"] = written_numbers(value)
        else:
            values["inertia"][name] = written_number(value)
    inertial = element.child("inertial")
    if inertial is None:
        full = {"origin": {"xyz": "0 0 0"}, "mass": {"value": "0"}}
        full["inertia"] = dict.fromkeys(INERTIA_ATTRIBUTES, "0")
        for name, attributes in values.items():
            full[name].update(attributes)
        children = [empty_element(e, a) for e, a in full.items()]
        block = document.newline.join(["<inertial>", *("  " + c for c in children), "</inertial>"])
        indent = document.indent(element) + "  "
        return [document.children_inserted(element, owner, [block.replace("\n", "\n" + indent)])]
    edits = []
    missing = []
    for name, attributes in values.items():
        child = inertial.child(name)
        if child is not None:
            edits += document.tag(child, owner).edits(attributes)
        elif attributes:
            if name == "inertia":
                attributes = {a: attributes.get(a, "0") for a in INERTIA_ATTRIBUTES}
            missing.append(empty_element(name, attributes))
    if missing:
        edits.append(document.children_inserted(inertial, owner, missing))
    return edits


# ---------------------------------------------------------------- read back


def _expected(link: Link, correction: Mapping[str, Any] | None) -> tuple[float, Array, Array]:
    """A link's mass, centre of mass and inertia (link axes) once corrected."""
    if not correction:
        return link.mass, link.center_of_mass, link.inertia
    rotation = np.eye(3) if link.inertial is None else link.inertial.rotation
    tensor = inertia_tensor({**declared_inertia(link), **correction})
    centre = np.array(correction.get("xyz", link.center_of_mass), dtype=float)
    return float(correction.get("mass", link.mass)), centre, rotation @ tensor @ rotation.T


def _differs(got: Any, expected: Any, floor: float) -> bool:
    """Whether two values differ by more than :data:`SAME` of the larger, or of
    ``floor`` (the robot's largest such value: a reader's bound, 1e-12 kg for a
    massless body, is no difference)."""
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    scale = max(np.abs(expected).max(initial=0.0), np.abs(got).max(initial=0.0), floor)
    return not np.all(np.abs(got - expected) <= SAME * scale)


def _floors(links: Mapping[str, Link]) -> tuple[float, float, float]:
    """The largest finite mass, centre-of-mass coordinate and inertia entry of the links."""
    rows = np.array(
        [
            (abs(link.mass), np.abs(link.center_of_mass).max(), np.abs(link.inertia).max())
            for link in links.values()
        ]
    ).reshape(-1, 3)
    # Only finite values: one link's infinite entry (1e308 turned by its rpy)
    # would make every difference vanish beside it.
    finite = np.where(np.isfinite(rows), rows, 0.0)
    mass, centre, inertia = finite.max(axis=0, initial=0.0)
    return float(mass), float(centre), float(inertia)


def _verify(
    audit: Audit, kind: str, written: Path, corrections: Mapping[str, Mapping[str, Any]]
) -> None:
    """Refuse a copy that does not read back with every correction made and every
    other link as it was (``written``: the copy, not yet in place)."""
    from tumble.robots.auditing import audit_robot

    source = audit.robot.path
    try:
        if kind == "URDF":
            from tumble.robots.urdf import read_urdf

            robot = read_urdf(written)
        else:
            from tumble.robots.mjcf import read_mjcf

            robot = read_mjcf(written)
        again = audit_robot(robot, audit.geometry)
    except InputError as error:
        raise InputError(
            f"Expected the corrected copy of {shown(source)} to read back, got: {error} "
            "Nothing was written."
        ) from None
    floors = _floors(audit.robot.links)
    for name, link in audit.robot.links.items():
        mass, centre, inertia = _expected(link, corrections.get(name))
        new = again.robot.links.get(name)
        what = "corrected" if name in corrections else "former"
        if new is None:
            wrong = "no such link"
        elif _differs(new.mass, mass, floors[0]):
            wrong = f"mass {new.mass!r} kg for {mass!r}"
        elif _differs(new.center_of_mass, centre, floors[1]):
            wrong = f"centre of mass {new.center_of_mass.tolist()} m for {centre.tolist()}"
        elif _differs(new.inertia, inertia, floors[2]):
            wrong = f"inertia {_shown(new.inertia)} kg·m² for {_shown(inertia)}"
        else:
            continue
        raise InputError(
            f"Expected link {name!r} of the corrected copy of {shown(source)} to read back "
            f"with its {what} values, got {wrong}: it cannot be corrected in place, and "
            "nothing was written."
        )
    for finding in again.findings:
        if finding.link in corrections and (
            finding.severity == "error" or finding.code == "round-off"
        ):
            raise InputError(
                f"Expected link {finding.link!r} of the corrected copy of {shown(source)} to "
                f"audit without errors, got {finding.code}: {finding.message} Its correction "
                "does not make it physical, and nothing was written."
            )
    if kind == "MJCF":
        _compiled(source, written, audit.robot.links, corrections, floors)


def _shown(tensor: Array) -> str:
    return str([[float(f"{v:.6g}") for v in row] for row in tensor])


def _compiled(
    source: Path,
    written: Path,
    links: Mapping[str, Link],
    corrections: Mapping[str, Mapping[str, Any]],
    floors: tuple[float, float, float],
) -> None:
    """Refuse an MJCF copy that MuJoCo compiles no longer, or refuses for a
    corrected body, or whose compiled model lacks a correction (a compiler
    setting that overrides it: ``inertiafromgeom``, ``settotalmass``)."""
    import mujoco
    from scipy.spatial.transform import Rotation

    try:
        model = mujoco.MjModel.from_xml_path(str(written))
    except Exception as error:  # MuJoCo raises ValueError with its compiler's message
        blamed = re.search(r"^Element name '(.*)', id \d+", str(error), re.MULTILINE)
        if blamed is not None and blamed.group(1) in corrections:
            raise InputError(
                f"Expected body {blamed.group(1)!r} of the corrected copy of {shown(source)} to "
                f"compile in MuJoCo, got: {one_line(error)} Nothing was written."
            ) from None
        try:
            mujoco.MjModel.from_xml_path(str(source))
        except Exception:
            # The source does not compile either, for a body left as it was:
            # the read-back checked the values.
            return
        raise InputError(
            f"Expected the corrected copy of {shown(source)} to compile in MuJoCo as the "
            f"source does, got: {one_line(error)} Nothing was written."
        ) from None
    for name, correction in corrections.items():
        body = model.body(name)
        mass, centre, inertia = _expected(links[name], correction)
        axes = Rotation.from_quat(body.iquat, scalar_first=True).as_matrix()
        compiled = axes @ np.diag(body.inertia) @ axes.T
        if (
            _differs(body.mass[0], mass, floors[0])
            or _differs(body.ipos, centre, floors[1])
            or _differs(compiled, inertia, floors[2])
        ):
            raise InputError(
                f"Expected MuJoCo's model of the corrected copy of {shown(source)} to give "
                f"body {name!r} its corrected values, got mass {float(body.mass[0])!r} kg, "
                f"inertia {_shown(compiled)} kg·m² (a compiler setting overrides them): "
                "nothing was written."
            )
