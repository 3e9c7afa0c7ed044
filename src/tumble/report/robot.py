"""The HTML page of a robot's audit: its links drawn in 3D as ellipsoids of equal
inertia, the declared beside the geometry's, coloured by finding, and the table
of links and findings. One self-contained file (plotly inlined, no network)."""

from __future__ import annotations

import html
import json
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.massprops import MassProperties
from tumble.report.geometry import equal_inertia_ellipsoid
from tumble.report.html import stylesheet

if TYPE_CHECKING:
    from tumble.robots import Audit, Link

__all__ = ["audit_page", "write_audit_page"]

Array = NDArray[np.float64]

#: The colour of a link's declared ellipsoid by its worst finding.
_COLOURS = {"error": "#d62728", "warning": "#ff7f0e", "info": "#1f77b4", None: "#2ca02c"}


def _worst(severities: list[str]) -> str | None:
    for severity in ("error", "warning", "info"):
        if severity in severities:
            return severity
    return None


def _declared(link: Link) -> MassProperties | None:
    """The link's declared values as mass properties, None where no body has them."""
    from tumble.errors import InputError

    if not link.mass > 0:
        return None
    try:
        return MassProperties(link.mass, link.center_of_mass, link.inertia)
    except InputError:
        return None


def _mesh_trace(
    solid: MassProperties,
    pose: tuple[Array, Array],
    name: str,
    colour: str,
    opacity: float,
    text: str,
) -> dict[str, Any]:
    """The ellipsoid of equal inertia of ``solid`` (link coordinates), placed by
    ``pose`` in the root link's frame."""
    ellipsoid = equal_inertia_ellipsoid(solid)
    rotation, translation = pose
    vertices = ellipsoid.vertices @ rotation.T + translation
    i, j, k = ellipsoid.faces.T
    return {
        "type": "mesh3d",
        "name": name,
        "x": vertices[:, 0].tolist(),
        "y": vertices[:, 1].tolist(),
        "z": vertices[:, 2].tolist(),
        "i": i.tolist(),
        "j": j.tolist(),
        "k": k.tolist(),
        "color": colour,
        "opacity": opacity,
        "hovertext": text,
        "hoverinfo": "text",
        "flatshading": True,
        "showlegend": False,
    }


def _figure(audit: Audit, joints: Mapping[str, Any] | None) -> dict[str, Any]:
    robot = audit.robot
    poses = robot.link_poses(joints)
    findings: dict[str, list[Any]] = {}
    for finding in audit.findings:
        findings.setdefault(finding.link, []).append(finding)
    geometry = {summary.link: summary.geometry for summary in audit.links}
    traces: list[dict[str, Any]] = []
    invalid: list[tuple[str, Array]] = []
    for name, link in robot.links.items():
        found = findings.get(name, [])
        worst = _worst([f.severity for f in found])
        codes = ", ".join(f.code for f in found) or "ok"
        declared = _declared(link)
        if declared is not None:
            text = f"{name}: {link.mass:.4g} kg, declared ({codes})"
            traces.append(_mesh_trace(declared, poses[name], name, _COLOURS[worst], 0.8, text))
        elif link.mass > 0:
            rotation, translation = poses[name]
            invalid.append(
                (
                    f"{name}: no body has its tensor ({codes})",
                    rotation @ link.center_of_mass + translation,
                )
            )
        shapes = geometry.get(name)
        if shapes is not None:
            text = f"{name}: its {audit.geometry} shapes at {link.mass:.4g} kg"
            traces.append(_mesh_trace(shapes, poses[name], name, "#7f7f7f", 0.25, text))
    if invalid:
        points = np.array([p for _, p in invalid])
        traces.append(
            {
                "type": "scatter3d",
                "mode": "markers",
                "name": "no body has its tensor",
                "x": points[:, 0].tolist(),
                "y": points[:, 1].tolist(),
                "z": points[:, 2].tolist(),
                "marker": {"symbol": "diamond", "size": 6, "color": _COLOURS["error"]},
                "hovertext": [t for t, _ in invalid],
                "hoverinfo": "text",
            }
        )
    return {
        "data": traces,
        "layout": {
            "margin": {"l": 0, "r": 0, "t": 10, "b": 0},
            "scene": {
                "aspectmode": "data",
                "xaxis": {"title": {"text": "x (m)"}},
                "yaxis": {"title": {"text": "y (m)"}},
                "zaxis": {"title": {"text": "z (m)"}},
            },
        },
    }


def _table(audit: Audit) -> str:
    e = html.escape
    codes: dict[str, list[str]] = {}
    for finding in audit.findings:
        codes.setdefault(finding.link, []).append(finding.code)
    rows = []
    for summary in audit.links:
        moments = " ".join(f"{v:.4g}" for v in summary.moments)
        shapes = (
            ""
            if summary.geometry is None
            else " ".join(f"{v:.4g}" for v in summary.geometry.principal()[0])
        )
        found = ", ".join(codes.get(summary.link, [])) or "ok"
        rows.append(
            f"<tr><td>{e(summary.link)}</td><td>{summary.mass:.4g}</td>"
            f"<td>{moments}</td><td>{shapes}</td><td>{e(found)}</td></tr>"
        )
    return (
        "<table><thead><tr><th>link</th><th>mass (kg)</th><th>declared moments (kg·m²)</th>"
        f"<th>{e(audit.geometry)} shapes' moments</th><th>findings</th></tr></thead>"
        f"<tbody>{''.join(rows)}</tbody></table>"
    )


def _findings(audit: Audit) -> str:
    e = html.escape
    items = []
    for f in audit.findings:
        correction = "" if not f.correction else f" <code>{e(json.dumps(f.correction))}</code>"
        items.append(
            f"<li><b>{e(f.severity)}</b> {e(f.link)} ({e(f.code)}): {e(f.message)}{correction}</li>"
        )
    return f"<ul>{''.join(items)}</ul>" if items else "<p>No findings.</p>"


def audit_page(audit: Audit, joints: Mapping[str, Any] | None = None) -> str:
    """The audit of a robot as one self-contained HTML page: the links at the pose
    ``joints`` (default: every joint at its reference) drawn as ellipsoids of equal
    inertia (a uniform ellipsoid with the link's mass and inertia), the declared
    coloured by the link's worst finding (green none, blue info, orange warning,
    red error), its shapes' in grey; links whose declared tensor no body has as
    red diamonds at their centre of mass; then the table and the findings."""
    from plotly.offline import get_plotlyjs

    robot = audit.robot
    title = f"tumble audit: {robot.name} ({robot.path.name})"
    errors = len(audit.errors)
    note = (
        f"{len(robot.links)} links; {errors} error{'s' * (errors != 1)}, "
        f"{len(audit.findings) - errors} other findings. Each link with mass is drawn as the "
        "uniform ellipsoid of its declared mass and inertia, in the root link's frame"
        + (f", beside its {audit.geometry} shapes' (grey)" if audit.geometry != "none" else "")
        + "."
    )
    figure = json.dumps(_figure(audit, joints), allow_nan=False).replace("</", "<\\/")
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{html.escape(title)}</title>\n<style>{stylesheet()}</style>\n"
        f"<script>{get_plotlyjs()}</script>\n</head>\n<body>\n"
        f'<h1>{html.escape(title)}</h1>\n<p class="note">{html.escape(note)}</p>\n'
        '<div id="robot" style="height:70vh"></div>\n'
        f'<script type="application/json" id="tumble-robot">{figure}</script>\n'
        "<script>const figure = JSON.parse(document.getElementById('tumble-robot').textContent);"
        "Plotly.newPlot('robot', figure.data, figure.layout, {responsive: true});</script>\n"
        f"<h2>Links</h2>\n{_table(audit)}\n<h2>Findings</h2>\n{_findings(audit)}\n"
        "</body>\n</html>\n"
    )


def write_audit_page(audit: Audit, path: Any, joints: Mapping[str, Any] | None = None) -> Path:
    """Write :func:`audit_page` to ``path`` (atomically)."""
    from tumble.files import write_text

    return write_text(Path(path), audit_page(audit, joints))
