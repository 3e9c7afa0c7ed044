"""What an audit of a robot description finds: each :class:`Finding`, each link's
line (:class:`LinkSummary`), and the :class:`Audit` that holds them."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.massprops import MassProperties
from tumble.robots.model import Link, Robot

__all__ = ["CODES", "Audit", "Finding", "LinkSummary", "link_finding"]

Array = NDArray[np.float64]

#: Every finding's code and severity: ``error`` for values no body has, ``warning``
#: for values a body may have but this link's shapes say otherwise, ``info`` for
#: what could not be checked.
CODES = {
    "negative-mass": "error",
    "not-positive-definite": "error",
    "triangle-inequality": "error",
    "power-of-ten": "error",
    "swapped-attributes": "error",
    "row-major": "error",
    "unreadable-inertial": "error",
    "round-off": "warning",
    "massless-with-geometry": "warning",
    "geometry-mismatch": "warning",
    "implausible-density": "warning",
    "missing-mesh": "warning",
    "malformed-number": "warning",
    "unknown-geometry": "warning",
    "invalid-joint": "warning",
    "geometry-unavailable": "info",
}

#: The order in which a link's corrections are chosen: the smallest edit first.
_PRIORITY = (
    "negative-mass",
    "round-off",
    "power-of-ten",
    "swapped-attributes",
    "row-major",
    "massless-with-geometry",
    "geometry-mismatch",
)


@dataclass(frozen=True)
class Finding:
    """One thing wrong with a link's declared values.

    Attributes
    ----------
    link : the link's name.
    code : what is wrong (:data:`CODES`).
    severity : ``"error"``, ``"warning"`` or ``"info"``.
    message : one or two sentences: what was found, by how much, what to do.
    correction : None, or the attributes to change and their new values, named
        as the file names them (URDF: ``"mass"``, ``"ixx"`` … ``"izz"`` of the
        inertial frame, ``"xyz"`` the centre of mass as a 3-tuple).
    """

    link: str
    code: str
    severity: str
    message: str
    correction: dict[str, Any] | None = None


def link_finding(
    link: Link, code: str, message: str, correction: dict[str, Any] | None = None
) -> Finding:
    """The finding ``code`` (with its severity from :data:`CODES`) of ``link``,
    saying ``message``, with ``correction`` (see :class:`Finding`) or None."""
    return Finding(link.name, code, CODES[code], message, correction)


@dataclass(frozen=True)
class LinkSummary:
    """A link's line in the audit's table: declared mass (kg) and principal moments
    (kg·m², ascending; negative ones as they are), the geometry's mass
    properties at that mass (None where not computed) and its volume (m³)."""

    link: str
    mass: float
    moments: Array
    geometry: MassProperties | None = None
    volume: float | None = None


@dataclass(frozen=True)
class Audit:
    """The audit of one robot description.

    Attributes
    ----------
    robot : the description read.
    geometry : the shapes compared with (``"collision"``, ``"visual"`` or ``"none"``).
    findings : every finding, link by link in the file's order.
    links : each link's :class:`LinkSummary`.
    """

    robot: Robot
    geometry: str
    findings: tuple[Finding, ...]
    links: tuple[LinkSummary, ...] = field(default=())

    @property
    def errors(self) -> tuple[Finding, ...]:
        """The findings of values no body has (severity ``error``)."""
        return tuple(f for f in self.findings if f.severity == "error")

    def corrections(self) -> dict[str, dict[str, Any]]:
        """One correction a link, the smallest edit that explains its findings:
        ``{link: {attribute: value}}``."""
        chosen: dict[str, dict[str, Any]] = {}
        for code in _PRIORITY:
            for finding in self.findings:
                if finding.code == code and finding.correction and finding.link not in chosen:
                    chosen[finding.link] = finding.correction
        return chosen

    def to_dict(self) -> dict[str, Any]:
        """The audit as plain data (for ``--json``)."""
        return {
            "file": str(self.robot.path),
            "robot": self.robot.name,
            "geometry": self.geometry,
            "links": len(self.robot.links),
            "errors": len(self.errors),
            "findings": [
                {
                    "link": f.link,
                    "code": f.code,
                    "severity": f.severity,
                    "message": f.message,
                    "correction": _plain(f.correction),
                }
                for f in self.findings
            ],
        }


def _plain(correction: dict[str, Any] | None) -> dict[str, Any] | None:
    if correction is None:
        return None
    return {k: list(v) if isinstance(v, tuple) else v for k, v in correction.items()}
