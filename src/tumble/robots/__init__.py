"""Robot descriptions: every link's declared inertia, what its shapes say it
should be, the whole robot at a pose, and the audit that finds and corrects
inertias no body has.

* :func:`load` reads a URDF, a xacro or an MJCF file into a :class:`Robot`
  (:func:`robot_files` lists those of a folder);
* :func:`audit` judges every link's declared values (:class:`Audit`,
  :class:`Finding`), and :func:`write_corrected` writes a copy with the
  corrections in which nothing else changes.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from tumble.errors import JointLimitWarning
from tumble.robots.findings import CODES, Audit, Finding, LinkSummary
from tumble.robots.fix import write_corrected
from tumble.robots.load import load, robot_files
from tumble.robots.model import Joint, Link, LinkShape, Notice, Robot
from tumble.robots.ros import NotARobot

__all__ = [
    "CODES",
    "Audit",
    "Finding",
    "Joint",
    "JointLimitWarning",
    "Link",
    "LinkShape",
    "LinkSummary",
    "NotARobot",
    "Notice",
    "Robot",
    "audit",
    "example_path",
    "load",
    "robot_files",
    "write_corrected",
]


def __getattr__(name: str) -> Any:
    # `Shape` was the name of a link's shape until it was told apart from the
    # catalogue's solids (`tumble.shapes.Shape`): kept for one release, with a warning.
    if name == "Shape":
        warnings.warn(
            "tumble.robots.Shape is deprecated: use tumble.robots.LinkShape (a link's "
            "collision or visual shape; tumble.shapes.Shape is a solid of the catalogue).",
            DeprecationWarning,
            stacklevel=2,
        )
        return LinkShape
    raise AttributeError(f"module 'tumble.robots' has no attribute {name!r}")


def audit(
    path: Any,
    geometry: str = "collision",
    *,
    packages: Mapping[str, Any] | None = None,
    xacro_args: Mapping[str, Any] | None = None,
) -> Audit:
    """Audit the declared inertias of every link of a robot file.

    Parameters
    ----------
    path : a URDF (``.urdf``), xacro (``.urdf.xacro``) or MJCF (``.xml``) file,
        or a :class:`Robot`.
    geometry : the shapes the declared values are compared with,
        ``"collision"`` (default), ``"visual"``, or ``"none"`` (the declared
        values judged alone: fast, no mesh read).
    packages, xacro_args : as for :func:`load` (a file only).

    Returns
    -------
    Audit, whose ``findings`` are :class:`Finding` (link, code, severity,
    message, correction); ``audit.errors`` are those of values no body has.

    Examples
    --------
    A decimal point slipped in one attribute of the example arm's inertia:

    >>> import tumble as tb
    >>> from tumble.robots import example_path
    >>> text = example_path().read_text().replace('izz="0.0009"', 'izz="0.9"')
    >>> import tempfile, pathlib
    >>> slipped = pathlib.Path(tempfile.mkdtemp()) / "arm.urdf"
    >>> _ = slipped.write_text(text)
    >>> for finding in tb.robots.audit(slipped).findings:
    ...     print(finding.code, finding.correction)
    triangle-inequality None
    power-of-ten {'izz': 0.0009}
    """
    from tumble.robots.auditing import audit_robot

    if isinstance(path, Robot):
        robot = path
    else:
        robot = load(path, packages=packages, xacro_args=xacro_args)
    return audit_robot(robot, geometry)


def example_path() -> Path:
    """The example arm shipped with tumble: a URDF of three links."""
    return Path(__file__).parent / "examples" / "arm.urdf"
