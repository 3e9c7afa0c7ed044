"""HTML: the run report (one self-contained page) and the notebook summaries of
:class:`~tumble.MassProperties` and :class:`~tumble.Trajectory`.

Nothing here loads from the network: figures are PNG data URIs, styles inline.
"""

from __future__ import annotations

import base64
import functools
import html
import math
from collections.abc import Mapping, Sequence
from importlib import resources
from typing import TYPE_CHECKING, Any

import numpy as np

from tumble._version import __version__

if TYPE_CHECKING:
    from tumble.massprops import MassProperties
    from tumble.scenario.execute import RunResult
    from tumble.trajectory import Trajectory

__all__ = ["mass_properties_html", "report_html", "stylesheet", "trajectory_html"]


@functools.cache
def stylesheet() -> str:
    """The CSS of tumble's HTML pages (``style.css``, shared by the run and sweep
    reports), to inline in a page."""
    return resources.files("tumble.report").joinpath("style.css").read_text(encoding="utf-8")


def _e(value: Any) -> str:
    return html.escape(str(value))


def _number(value: Any) -> str:
    if value is None:
        return "—"
    number = float(value)
    if math.isinf(number):
        return "∞" if number > 0 else "−∞"
    if math.isnan(number):
        return "NaN"
    return f"{number:.9g}"


def _grade(error: Any) -> str:
    if error is None or not math.isfinite(float(error)):
        return "poor"
    return "good" if error < 1e-3 else ("fair" if error < 5e-2 else "poor")


def _table(header: Sequence[str], rows: Sequence[Sequence[str]], numeric: Sequence[bool]) -> str:
    head = "".join(f"<th>{_e(h)}</th>" for h in header) if any(header) else ""
    body = []
    for row in rows:
        cells = []
        for cell, is_number in zip(row, numeric, strict=True):
            cells.append(f'<td class="num">{cell}</td>' if is_number else f"<td>{cell}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    thead = f"<thead><tr>{head}</tr></thead>" if head else ""
    return f"<table>{thead}<tbody>{''.join(body)}</tbody></table>"


def comparisons_html(rows: Sequence[Mapping[str, Any]]) -> str:
    """The theory-vs-simulation rows as an HTML table."""
    if not rows:
        return "<p>No closed form applies to this scenario; see the drift below.</p>"
    out = []
    for row in rows:
        error = row.get("relative_error")
        grade = _grade(error)
        shown = (
            "—"
            if error is None
            else (f"{float(error):.2e}" if math.isfinite(float(error)) else "∞")
        )
        out.append(
            [
                _e(row["quantity"]),
                _number(row["theory"]),
                _number(row["measured"]),
                f'<span class="{grade}">{shown}</span>',
                _e(row.get("unit", "")),
            ]
        )
    return _table(
        ("quantity", "theory", "simulation", "relative error", "unit"),
        out,
        (False, True, True, True, False),
    )


def drift_html(drift: Mapping[str, Any]) -> str:
    """The drift of the quantities the motion conserves as an HTML table."""
    from tumble.invariants import INVARIANTS, label

    if not drift:
        return "<p>Nothing is conserved in this motion (it is driven or damped).</p>"
    rows = []
    for key, value in drift.items():
        meaning = INVARIANTS[key].description if key in INVARIANTS else ""
        rows.append(
            [
                _e(label(key)),
                "—" if value is None else f"{float(value):.3e}",
                _e(meaning),
            ]
        )
    return _table(
        ("conserved quantity", "largest relative drift", "what it is"), rows, (False, True, False)
    )


def png_data_uri(png: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


_CAPTIONS = {
    "omega": "Angular velocity ω(t) in body axes.",
    "angular_momentum": "Angular momentum L(t) in space axes.",
    "drift": "Drift of the quantities the motion conserves: the numerical error.",
    "polhode": (
        "The polhode: L in principal axes on the energy ellipsoid; for a torque-free "
        "body, beside it the herpolhode: ω on the invariable plane (Poinsot)."
    ),
}


def report_html(result: RunResult, figures: Mapping[str, bytes], viewer: str | None = None) -> str:
    """The run's report: the scenario, theory vs simulation, drift, figures, the TOML."""
    spec = result.scenario.spec
    traj = result.trajectory
    info = spec.scenario
    title = info.title or info.name
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{_e(title)} — tumble</title><style>{stylesheet()}</style></head><body>",
        f"<h1>{_e(title)}</h1>",
        f'<p class="small">Scenario <b>{_e(info.name)}</b> ({_e(result.scenario.source)}), '
        f"tumble {_e(__version__)}.</p>",
    ]
    if info.description:
        parts.append(f"<p>{_e(info.description.strip())}</p>")
    if viewer:
        parts.append(
            f'<p><a href="{_e(viewer)}">Open the 3D viewer</a> (the body, its principal axes, '
            "ω and L, play / pause and a time slider).</p>"
        )
    parts.append("<h2>Theory vs simulation</h2>")
    if result.theory:
        parts.append(
            f'<p class="small">Closed form: <b>{_e(result.theory)}</b> (tumble.theory); '
            "measured on the trajectory with tumble.analysis.</p>"
        )
    parts.append(comparisons_html(result.comparisons))
    parts.append("<h2>Run</h2>")
    run_rows = [
        ["method", _e(f"{traj.method} — {traj.reason}")],
        ["time step", _e(f"{traj.dt:.4g} s, {traj.steps} steps")],
        ["duration, samples", _e(f"{traj.t[-1]:.6g} s, {len(traj.t)} samples")],
        [
            "body",
            _e(
                f"mass {traj.mass_properties.mass:.6g} kg, principal moments "
                + ", ".join(f"{m:.6g}" for m in traj.mass_properties.principal()[0])
                + " kg·m²"
            ),
        ],
        [
            "fixed point",
            _e(
                "none (free body)"
                if traj.pivot is None
                else f"pivot at {np.round(traj.pivot, 9).tolist()} m"
            ),
        ],
        ["wall time", _e(f"{result.elapsed:.2f} s to simulate and measure")],
    ]
    parts.append(_table(("", ""), run_rows, (False, False)))
    parts.append("<h3>Drift</h3>")
    parts.append(drift_html(result.drift))
    for note in result.notes:
        parts.append(f'<p class="small">{_e(note)}</p>')
    parts.append("<h2>Figures</h2>")
    panel_titles = {panel.name: panel.title for panel in result.panels}
    for name, png in figures.items():
        caption = _CAPTIONS.get(name) or panel_titles.get(name, name)
        parts.append(
            f'<figure><img alt="{_e(name)}" src="{png_data_uri(png)}">'
            f'<figcaption class="small">{_e(caption)} ({_e(name)}.png)</figcaption></figure>'
        )
    parts.append("<h2>Scenario</h2>")
    parts.append(f"<pre>{_e(result.scenario.text)}</pre>")
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


# ------------------------------------------------------------------ notebooks
def _matrix(values: Any) -> str:
    rows = "".join(
        "<tr>" + "".join(f'<td class="num">{float(v):.6g}</td>' for v in row) + "</tr>"
        for row in np.asarray(values)
    )
    return f"<table>{rows}</table>"


def mass_properties_html(mp: MassProperties) -> str:
    """A small HTML table of mass properties (notebooks)."""
    moments, axes = mp.principal()
    rows = [
        ["mass", f"{mp.mass:.6g} kg"],
        ["centre of mass", "[" + ", ".join(f"{v:.6g}" for v in mp.center_of_mass) + "] m (body)"],
        ["inertia about the centre of mass, body axes (kg·m²)", _matrix(mp.inertia)],
        ["principal moments", ", ".join(f"{v:.6g}" for v in moments) + " kg·m²"],
        ["principal axes (columns)", _matrix(axes)],
    ]
    body = "".join(f"<tr><th>{_e(k)}</th><td>{v}</td></tr>" for k, v in rows)
    return f"<table><caption>MassProperties</caption>{body}</table>"


def trajectory_html(traj: Trajectory) -> str:
    """A small HTML summary of a trajectory (notebooks)."""
    from tumble.invariants import label

    drift = traj.drift
    kind = "free body" if traj.pivot is None else f"pivot at {np.round(traj.pivot, 9).tolist()} m"
    rows = [
        ["samples", f"{len(traj.t)} over {traj.t[-1]:.6g} s"],
        ["body", f"{traj.mass_properties.mass:.6g} kg, {kind}"],
        ["method", f"{traj.method} (dt = {traj.dt:.3g} s, {traj.steps} steps): {traj.reason}"],
        [
            "relative drift",
            ", ".join(f"{label(k)} {v:.2e}" for k, v in drift.items()) or "nothing conserved",
        ],
        ["ω at the end (body)", "[" + ", ".join(f"{v:.6g}" for v in traj.omega[-1]) + "] rad/s"],
    ]
    body = "".join(f"<tr><th>{_e(k)}</th><td>{_e(v)}</td></tr>" for k, v in rows)
    return (
        f"<table><caption>Trajectory</caption>{body}</table>"
        '<p style="font-size:0.85em">.plot() for figures, .view() for the 3D viewer</p>'
    )
