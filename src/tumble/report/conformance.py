"""The report of physics engines measured against the exact motion (``tumble conform``).

* :func:`conformance_figures` — the figures as PNG bytes: the energy and attitude
  errors against time, the error against dt of a sweep, and the paths of L on the
  momentum sphere beside the exact polhode (:mod:`tumble.report.conformance_figures`).
* :func:`conformance_html` — the report, one self-contained page: the table, the
  engines skipped and why, what each adapter noted, the figures, and the cost of
  the exact reference against the engines' time.
* :func:`write_conformance` — the folder: ``table.parquet``, ``table.json``,
  ``report.html`` and ``conformance.json`` (last: a folder holding it is complete).
"""

from __future__ import annotations

import html
import io
import json
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from tumble.report.conformance_figures import CONFORMANCE_FIGURES, conformance_figures

if TYPE_CHECKING:
    from tumble.conformance import ConformanceResult

__all__ = [
    "check_conformance_folder",
    "conformance_figures",
    "conformance_html",
    "write_conformance",
]

#: The marker of a conformance folder, written last.
MARKER = "conformance.json"

#: The columns of the report's table: the table's column, its heading, and how a
#: value is shown ("number": 3 significant digits, "count": an integer, "text").
COLUMNS = (
    ("engine", "engine", "text"),
    ("dt", "dt (s)", "number"),
    ("energy_drift_max", "energy drift, max", "number"),
    ("energy_drift_final", "energy drift, final", "number"),
    ("momentum_drift_max", "|L| drift, max", "number"),
    ("direction_drift_max", "L direction drift (rad)", "number"),
    ("attitude_error_max", "attitude error (rad)", "number"),
    ("omega_error_max", "ω error / |ω₀|", "number"),
    ("flips", "flips", "count"),
    ("flips_exact", "exact flips", "count"),
    ("failed_at", "failed at (s)", "number"),
    ("steps_per_second", "steps / s", "number"),
    ("order", "order", "number"),
    ("safe_dt", "safe dt (s)", "number"),
    ("failure", "failure", "text"),
)

#: What each figure shows, under it in the report.
CAPTIONS = {
    "energy": (
        "Relative energy error (E − E₀)/E₀ against time, on a symmetric log scale (linear "
        "near zero): above zero the engine gains energy, below it loses energy. A cross "
        "marks a run's failure."
    ),
    "attitude": (
        "Angle of the rotation from the exact attitude to the engine's, rad, on a log scale."
    ),
    "convergence": (
        "The largest ω error relative to |ω₀| against the step, log-log, with the lines of "
        "slope 1, 2 and 4; each engine's observed order (the fitted slope over the errors "
        "between 1e-10 and 0.1) is in the legend."
    ),
    "momentum-sphere": (
        "The angular momentum in body axes, L = Iω, over |L(0)|: each engine's path on the "
        "unit sphere and the exact polhode, seen along the axis L turns about. A path that "
        "leaves the polhode drifted in energy or |L|; outside the circle, |L| grew."
    ),
}

#: How the meanings of the table's columns read under it.
LEGEND = (
    "Drifts are relative and signed, (x(t) − x(0))/x(0), the value of largest magnitude "
    "over the run ('max') or at its end ('final'). About a pivot, the |L| drift is that of "
    "L's vertical component over |L(0)|, and L's direction is not conserved (—). Flips are "
    "the sign changes of ω's intermediate-axis component in body axes. "
    "A run that did not fail has — under 'failed at'."
)


def _e(value: Any) -> str:
    return html.escape(str(value))


def _shown(value: Any, kind: str) -> str:
    """A table cell's text: numbers to 3 significant digits, missing values as —."""
    if kind == "text":
        return "" if value is None else str(value)
    if value is None:
        return "—"
    number = float(value)
    if math.isnan(number):
        return "—"
    if math.isinf(number):
        return "∞" if number > 0 else "−∞"
    if kind == "count":
        return str(int(number))
    return f"{number:.3g}"


def _table_html(result: ConformanceResult) -> str:
    table = result.table
    columns = [column for column in COLUMNS if column[0] in table.columns]
    head = "".join(f"<th>{_e(heading)}</th>" for _, heading, _ in columns)
    rows = []
    for record in table.to_dict(orient="records"):
        cells = []
        for key, _, kind in columns:
            text = _e(_shown(record.get(key), kind))
            if kind == "text":
                failed = key == "failure" and text
                cells.append(f'<td class="poor">{text}</td>' if failed else f"<td>{text}</td>")
            else:
                cells.append(f'<td class="num">{text}</td>')
        rows.append("<tr>" + "".join(cells) + "</tr>")
    return (
        '<div style="overflow-x:auto"><table>'
        f"<thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table></div>"
    )


def _numbers(values: Any, unit: str) -> str:
    return "(" + ", ".join(f"{float(v):.6g}" for v in np.asarray(values)) + f") {unit}"


def _scenario_html(result: ConformanceResult) -> str:
    scenario = result.scenario
    body = scenario.body
    omega = scenario.initial_state[1]
    rows = [
        ("body", f"mass {body.mass:.6g} kg, principal moments {_numbers(body.moments, 'kg·m²')}"),
        ("ω₀ (principal axes)", _numbers(omega, "rad/s")),
        ("horizon", f"{_horizon(result):.6g} s"),
        (
            "fixed point",
            "none (a free body, no gravity)"
            if body.pivot is None
            else f"a ball joint at {_numbers(body.pivot, 'm')} from the centre of mass "
            f"(body axes), gravity {scenario.gravity:.6g} m/s²",
        ),
        ("reference", "the closed-form motion (tumble.theory), not an integration"),
    ]
    body_rows = "".join(f"<tr><th>{_e(k)}</th><td>{_e(v)}</td></tr>" for k, v in rows)
    return f"<table><tbody>{body_rows}</tbody></table>"


def _horizon(result: ConformanceResult) -> float:
    """The runs' horizon, s: where the runs that did not fail end (the scenario's
    duration when every run failed or none ran)."""
    ends = [
        float(one.samples.t[-1])
        for one in result.runs
        if one.samples.t.size and not math.isfinite(one.samples.failed_at)
    ]
    return max(ends) if ends else float(result.scenario.duration)


def _cost_html(result: ConformanceResult) -> str:
    reference, engines = result.reference_seconds, result.engine_seconds
    share = f" ({100.0 * reference / engines:.2g} % of the engines' time)" if engines > 0 else ""
    return (
        f"<p>The exact reference took {reference:.3g} s of wall time{share}; the engines "
        f"stepped for {engines:.3g} s.</p>"
    )


def _listing(entries: Mapping[str, Sequence[str] | str]) -> str:
    items = []
    for name, text in entries.items():
        lines = [text] if isinstance(text, str) else list(text)
        inner = "; ".join(_e(line) for line in lines)
        items.append(f"<li><b>{_e(name)}</b>: {inner}</li>")
    return "<ul>" + "".join(items) + "</ul>"


def conformance_html(result: ConformanceResult, figures: Mapping[str, bytes]) -> str:
    """The report of a conformance result as one self-contained HTML page (styles
    inline, figures as PNG data URIs): the scenario, the table (one row per engine and
    dt, numbers to 3 significant digits; ``order`` and ``safe_dt`` for a sweep), the
    engines skipped with the reason, the adapters' notes, the ``figures`` (PNG bytes by
    name, as :func:`conformance_figures` makes them) and the reference's cost."""
    from tumble._version import __version__
    from tumble.report.html import png_data_uri, stylesheet

    scenario = result.scenario
    title = f"Engines against the exact motion: {scenario.name}"
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{_e(title)} — tumble</title><style>{stylesheet()}</style></head><body>",
        f"<h1>{_e(title)}</h1>",
        f'<p class="small">tumble {_e(__version__)}, tumble.conformance.</p>',
    ]
    if scenario.description:
        parts.append(f"<p>{_e(scenario.description)}</p>")
    parts.append(_scenario_html(result))
    parts.append("<h2>Results</h2>")
    if result.runs:
        parts.append(_table_html(result))
        parts.append(f'<p class="small">{_e(LEGEND)}</p>')
        if "safe_dt" in result.table.columns:
            parts.append(
                '<p class="small">Order: the slope of log(ω error) against log(dt). Safe dt: '
                "the largest step whose run, and every run at a smaller step, did not fail "
                "and kept the energy drift and the attitude error within the tolerance "
                "(— if none).</p>"
            )
    else:
        parts.append("<p>No engine ran.</p>")
    if result.skipped:
        parts.append("<h2>Engines skipped</h2>")
        parts.append(_listing(result.skipped))
    if result.notes:
        parts.append("<h2>What the adapters changed or saw</h2>")
        parts.append(_listing(result.notes))
    if figures:
        parts.append("<h2>Figures</h2>")
        order = [n for n in CONFORMANCE_FIGURES if n in figures]
        for name in order + [n for n in figures if n not in order]:
            parts.append(
                f'<figure><img alt="{_e(name)}" src="{png_data_uri(figures[name])}">'
                f'<figcaption class="small">{_e(CAPTIONS.get(name, name))}</figcaption>'
                "</figure>"
            )
    parts.append("<h2>Cost</h2>")
    parts.append(_cost_html(result))
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


# ------------------------------------------------------------------ the folder
def _plain(value: Any) -> Any:
    """A JSON value: numpy scalars as Python's, NaN and ±inf as None."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def table_records(result: ConformanceResult) -> list[dict[str, Any]]:
    """The table as JSON-ready records, one per row: NaN and ±inf as None."""
    return [
        {str(key): _plain(value) for key, value in record.items()}
        for record in result.table.to_dict(orient="records")
    ]


def conformance_summary(result: ConformanceResult) -> dict[str, Any]:
    """The result's scenario, skipped engines, notes and costs, as JSON-ready data."""
    scenario = result.scenario
    body = scenario.body
    return {
        "scenario": {
            "name": scenario.name,
            "description": scenario.description,
            "mass": float(body.mass),
            "moments": [float(v) for v in body.moments],
            "omega0": [float(v) for v in scenario.initial_state[1]],
            "pivot": None if body.pivot is None else [float(v) for v in body.pivot],
            "gravity": float(scenario.gravity) if body.pivot is not None else 0.0,
            "duration": _horizon(result),
        },
        "engines": list(dict.fromkeys(one.engine for one in result.runs)),
        "dts": sorted({float(one.dt) for one in result.runs}),
        "skipped": dict(result.skipped),
        "notes": {name: list(lines) for name, lines in result.notes.items()},
        "reference_seconds": float(result.reference_seconds),
        "engine_seconds": float(result.engine_seconds),
        "units": {"time": "s", "moments": "kg·m²", "omega0": "rad/s", "pivot": "m"},
        "conventions": (
            "moments: the principal moments about the centre of mass; omega0: the initial "
            "angular velocity in the same principal axes; pivot: the body point held fixed "
            "(principal axes, from the centre of mass), null for a free body; duration: "
            "the horizon of the runs"
        ),
    }


def check_conformance_folder(folder: str | os.PathLike[str], force: bool) -> None:
    """Refuse, before any work, a conformance folder that cannot be written (or
    replaced whole), or that holds files unless ``force``; with ``force``, one that
    holds files but no ``conformance.json`` (other work) too
    (:func:`tumble.report.check_folder`)."""
    from tumble.report import check_folder

    check_folder(folder, force, kind="conformance", marker=MARKER)


def write_conformance(
    result: ConformanceResult, folder: str | os.PathLike[str], *, force: bool = False
) -> Path:
    """Write the conformance folder of ``result``: ``table.parquet``, ``table.json``
    (records; NaN as null), ``report.html`` and ``conformance.json`` (the scenario,
    skipped engines, notes, costs and the files; last: a folder that holds it is
    complete). The folder is filled under a temporary name beside ``folder`` and
    renamed (:func:`tumble.locks.staged_folder`); with ``force`` an earlier one there
    is replaced whole. The folder is claimed first (:class:`tumble.locks.OutputLock`).

    Raises
    ------
    tumble.report.RunFolderExistsError
        The folder holds files and ``force`` is false, or holds other files than a
        conformance folder's.
    tumble.OutputInUseError
        Another process (or thread) is writing ``folder``.
    tumble.errors.OutputError
        The folder cannot be written (checked first), or the file system fails while
        writing: an earlier folder there is then unchanged.
    """
    from tumble.errors import OutputError
    from tumble.files import output_error, write_bytes, write_text
    from tumble.locks import OutputLock, staged_folder

    target = Path(folder)
    check_conformance_folder(target, force)
    page = conformance_html(result, conformance_figures(result))
    buffer = io.BytesIO()
    result.table.to_parquet(buffer, index=False)
    records = json.dumps(table_records(result), indent=2, allow_nan=False) + "\n"
    summary = conformance_summary(result)
    summary["files"] = sorted(["table.parquet", "table.json", "report.html", MARKER])
    try:
        with OutputLock(target, "the conformance folder"):
            check_conformance_folder(target, force)  # claimed: no other writer changes it now
            with staged_folder(target) as staging:
                write_bytes(staging / "table.parquet", buffer.getvalue())
                write_text(staging / "table.json", records)
                write_text(staging / "report.html", page)
                text = json.dumps(summary, indent=2, allow_nan=False) + "\n"
                write_text(staging / MARKER, text)
    except OSError as exc:
        raise output_error(exc, target, "the conformance folder") from exc
    except OutputError as exc:
        if not isinstance(exc.cause, OSError):
            raise
        raise output_error(exc.cause, target, "the conformance folder") from exc.cause
    return target
