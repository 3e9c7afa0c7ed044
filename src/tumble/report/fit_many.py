"""The folder of a fit of one body to many throws in a recording (``tumble fit --windows``
or ``--all``).

* :func:`joint_summary` — the joint fit of the throws with its uncertainties, or why
  there is none, as JSON-ready data (``joint.json``).
* :func:`throw_sheets`, :func:`ratios_sheet`, :func:`residuals_sheet` — the figures:
  each throw's measured and fitted rates with the forecast past its held-out cut, the
  ratios of every throw beside the joint ones, the residuals under the joint body.
* :func:`many_report_html` — ``report.html``: the joint fit, the throws, the figures.
* :func:`write_many` — the folder with all of them: ``throws.csv`` and
  ``throws.parquet`` (:attr:`tumble.identification.ThrowFits.table`), ``joint.json``,
  the joint body's ``fitted-scenario.toml``, ``report.html``, ``ratios.png`` and
  ``residuals.png``, and ``fit.json`` (last: it lists what was written, as a single
  fit's does, so ``--force`` replaces either kind of fit folder alike).
"""

from __future__ import annotations

import html
import json
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.report.charts import COLOURS, Chart, Line, Points, Sheet

if TYPE_CHECKING:
    from tumble.identification import BodyFit, JointFit, ThrowFits
    from tumble.identification.recordings import Recording

__all__ = [
    "THROWS_PER_ROW",
    "joint_summary",
    "many_report_html",
    "ratios_sheet",
    "residuals_sheet",
    "throw_sheets",
    "write_many",
]

Array = NDArray[np.float64]

#: Throws side by side in one row of the report's figure of the throws.
THROWS_PER_ROW = 3

#: The margins of a sheet of a row of throws, and of a pair of charts.
ROW_MARGINS = {"left": 0.08, "right": 0.98, "top": 0.9, "bottom": 0.15, "wspace": 0.25}
PAIR_MARGINS = {"left": 0.1, "right": 0.98, "top": 0.9, "bottom": 0.13, "wspace": 0.3}

#: The share of a window's length drawn before and after it (the throw and the catch).
MARGIN = 0.15


def _finite(value: Any) -> float | None:
    """A float for JSON: None where it is not finite (JSON has no NaN)."""
    number = float(value)
    return number if math.isfinite(number) else None


def _median(values: Array) -> float:
    """The median of the finite values; nan when there is none."""
    finite = values[np.isfinite(values)]
    return float(np.median(finite)) if finite.size else math.nan


def joint_summary(many: ThrowFits, source: str) -> dict[str, Any]:
    """The joint fit as JSON-ready data: the shared ratios, axes, bias and torque with
    their standard errors, the residual against the noise, the choice of torque, the
    throws in it and the outliers left out (numbers from 1, as in ``throws.csv``), and
    the medians of the forecast errors of the held-out parts; ``"joint": null`` and
    ``"joint_refusal"`` when there is no joint fit."""
    joint = many.joint
    summary: dict[str, Any] = {
        "recording": source,
        "throws_found": len(many.windows),
        "throws_fitted": len(many.fitted),
        "throws_joined": [i + 1 for i in many.joined],
        "hold_out": many.hold_out,
        "forecast_error_median": _finite(_median(many.forecast_errors)),
        "single_forecast_error_median": _finite(_median(many.single_forecast_errors)),
        "joint_refusal": many.joint_refusal,
        "joint": None if joint is None else _joint_values(joint),
        "units": {"time": "s", "rates": "rad/s", "moment_ratios": "1", "forecast_error": "1"},
        "conventions": (
            "principal moments ascending, as ratios to I3; principal_axes: the principal "
            "axes as columns in the sensor's axes; bias in the sensor's axes; throws and "
            "outliers: numbers from 1, the rows of throws.csv; throws_joined: refused alone, "
            "fitted under the joint body (their omega0 alone) and so in it; omega0: per "
            "joint throw, in the principal axes; forecast errors: the rms of the forecast "
            "less the measured rates over a throw's held-out last part, over the rms of "
            "|omega| there (forecast_error_median: the joint body of the throws' first parts; "
            "single_forecast_error_median: each throw's first part alone)"
        ),
    }
    return summary


def _joint_values(joint: JointFit) -> dict[str, Any]:
    return {
        "moment_ratios": joint.moment_ratios.tolist(),
        "moment_ratios_standard_error": joint.uncertainty.tolist(),
        "principal_axes": joint.axes.tolist(),
        "bias": joint.bias.tolist(),
        "bias_fitted": joint.bias_fitted,
        "torque": joint.torque,
        "torque_parameters": joint.torque_parameters.tolist(),
        "torque_parameters_standard_error": joint.torque_uncertainty.tolist(),
        "torque_units": joint.torque_units,
        "residual_rms": float(joint.residual_rms),
        "noise": float(joint.noise),
        "noise_ratio": float(joint.noise_ratio),
        "choice": joint.choice,
        "throws": [i + 1 for i in joint.throws],
        "outliers": [i + 1 for i in joint.outliers],
        "outlier_count": len(joint.outliers),
        "omega0": joint.omega0.tolist(),
        "parameters": list(joint.parameter_names),
        "covariance": joint.covariance.tolist(),
    }


# ------------------------------------------------------------------ figures
def _shown_fit(many: ThrowFits, i: int) -> tuple[BodyFit | None, str]:
    """The fit drawn over throw ``i``: the joint body's, or an outlier's own; its label."""
    fit = many.fits[i]
    joint = many.joint
    if joint is not None and i in joint.throws:
        return joint.throw_fit(i), "joint body"
    if isinstance(fit, str):
        return None, ""
    return fit, "own fit (outlier)" if joint is not None and i in joint.outliers else "own fit"


def throw_chart(many: ThrowFits, recording: Recording, i: int, legend: bool) -> Chart:
    """Throw ``i``'s measured rates (sensor axes) around its window, the fit of it,
    and the forecast of the joint body of the first parts past the held-out cut."""
    start, end = many.windows[i]
    margin = MARGIN * (end - start)
    near = (recording.t >= start - margin) & (recording.t <= end + margin)
    t = recording.t[near]
    lines = [
        Line(
            t - start,
            recording.omega[near, k],
            label=f"ω_{axis}" if legend else None,
            colour=COLOURS[k],
            width=0.8,
        )
        for k, axis in enumerate("xyz")
    ]
    fit, how = _shown_fit(many, i)
    note = None
    if fit is None:
        note = "refused: " + str(many.fits[i])[:48] + "…"
    else:
        lines += _three(fit.t - start, fit.predicted(fit.t), how if legend else None, "k", "--")
    held = many.held_out_joint
    if held is not None and i in held.throws:
        cut = many.cut(i)
        later = t[(t > cut) & (t <= end)]
        forecast = held.throw_fit(i).forecast(later)
        label = "forecast past the cut" if legend else None
        lines += _three(later - start, forecast, label, "#ff7f0e", ":", width=1.6)
        span = np.array([np.min(recording.omega[near]), np.max(recording.omega[near])])
        lines.append(Line(np.full(2, cut - start), span, colour="0.4", width=0.8, dash="-."))
    outlier = many.joint is not None and i in many.joint.outliers
    title = f"throw {i + 1}: {start:.4g}–{end:.4g} s" + (" (outlier)" if outlier else "")
    return Chart(
        title,
        "t − start (s)",
        "ω (rad/s)",
        lines=tuple(lines),
        note=note,
        legend="best" if legend else None,
        title_size="small",
    )


def _three(
    x: Array, values: Array, label: str | None, colour: str, dash: str, width: float = 1.0
) -> list[Line]:
    """The three components of ``values`` (n, 3) against ``x``, one style, one label."""
    return [
        Line(
            x, values[:, k], label=label if k == 0 else None, colour=colour, width=width, dash=dash
        )
        for k in range(3)
    ]


def _level(
    edges: Array, value: float, label: str | None, dash: str = "--", width: float = 0.8
) -> Line:
    """A level line across ``edges`` (x at both ends)."""
    return Line(edges, np.full(2, value), label=label, colour="0.2", width=width, dash=dash)


def throw_sheets(many: ThrowFits, recording: Recording, count: int | None = None) -> list[Sheet]:
    """The figures of the first ``count`` throws (all when None), :data:`THROWS_PER_ROW`
    to a sheet (:func:`throw_chart`); the legend on each row's first."""
    shown = range(len(many.windows) if count is None else min(count, len(many.windows)))
    sheets = []
    for first in shown[::THROWS_PER_ROW]:
        row = [i for i in shown if first <= i < first + THROWS_PER_ROW]
        charts = tuple(throw_chart(many, recording, i, legend=i == first) for i in row)
        sheets.append(Sheet(charts, size=(4.0 * len(charts), 3.2), margins=ROW_MARGINS))
    return sheets


def _bars(x: Array, values: Array, errors: Array) -> Line:
    """Error bars ±1 standard error as one line broken by NaNs."""
    xs = np.column_stack([x, x, np.full(x.size, np.nan)]).ravel()
    ys = np.column_stack([values - errors, values + errors, np.full(x.size, np.nan)]).ravel()
    return Line(xs, ys, colour="0.3", width=1.0)


def ratios_sheet(many: ThrowFits) -> Sheet:
    """I1/I3 and I2/I3 of every fitted throw with ±1 standard error, the outliers
    marked, beside the joint values and their ±1 standard error band."""
    table = many.table
    fitted = table[table["fitted"]]
    charts = []
    for k, name in enumerate(("I1/I3", "I2/I3")):
        column = f"r{k + 1}"
        x = fitted["throw"].to_numpy(float)
        values = fitted[column].to_numpy(float)
        errors = fitted[f"{column}_error"].to_numpy(float)
        outlier = fitted["outlier"].to_numpy(bool)
        lines = [_bars(x, values, errors)]
        points = [
            Points(x[~outlier], values[~outlier], label="throw ± σ", colour=COLOURS[0]),
            Points(
                x[outlier],
                values[outlier],
                label="outlier",
                colour=COLOURS[1],
                marker="x",
                size=30.0,
            ),
        ]
        joint = many.joint
        if joint is not None:
            edges = np.array([0.5, len(many.windows) + 0.5])
            value, error = joint.moment_ratios[k], joint.uncertainty[k]
            lines.append(_level(edges, value, "joint", dash="-", width=1.2))
            lines += [_level(edges, value + error, "joint ± σ"), _level(edges, value - error, None)]
        charts.append(
            Chart(
                f"{name} of each throw",
                "throw",
                name,
                lines=tuple(lines),
                points=tuple(points),
                title_size="medium",
            )
        )
    return Sheet(tuple(charts), size=(11.0, 4.0), margins=PAIR_MARGINS)


def residuals_sheet(many: ThrowFits) -> Sheet:
    """The residuals of each joint throw under the joint body, against the time since
    its window's start, with ± the noise σ; and each throw's residual rms under the
    joint body beside its own fit's."""
    joint = many.joint
    lines, numbers, under_joint, own = [], [], [], []
    noise = math.nan
    if joint is not None:
        noise = joint.noise
        for n, i in enumerate(joint.throws):
            fit = joint.throw_fit(i)
            residuals = fit.residuals
            lines += [
                Line(
                    fit.t - fit.window[0],
                    residuals[:, k],
                    colour=COLOURS[k],
                    width=0.5,
                    alpha=0.6,
                    label=f"ω_{axis}" if n == 0 else None,
                )
                for k, axis in enumerate("xyz")
            ]
            numbers.append(i + 1)
            under_joint.append(fit.residual_rms)
            single = many.fits[i]
            own.append(single.residual_rms if not isinstance(single, str) else math.nan)
        longest = max(fit.window[1] - fit.window[0] for fit in joint.fits)
        edges = np.array([0.0, longest])
        lines += [_level(edges, noise, "± noise σ"), _level(edges, -noise, None)]
    left = Chart(
        "Residuals under the joint body, sensor axes",
        "t − start (s)",
        "residual (rad/s)",
        lines=tuple(lines),
        note=None if joint is not None else "no joint fit",
        title_size="medium",
    )
    x = np.array(numbers, dtype=float)
    rms_lines: tuple[Line, ...] = ()
    if joint is not None:
        edges = np.array([0.5, len(many.windows) + 0.5])
        rms_lines = (Line(edges, np.full(2, noise), colour="0.3", dash="--", label="noise σ"),)
    right = Chart(
        "Residual rms of each throw",
        "throw",
        "rms (rad/s)",
        lines=rms_lines,
        points=(
            Points(x, np.array(under_joint), label="joint body", colour=COLOURS[0]),
            Points(x, np.array(own), label="own fit", colour=COLOURS[4], marker="s", size=10.0),
        ),
        title_size="medium",
    )
    return Sheet(
        (left, right),
        size=(11.0, 4.0),
        margins={"left": 0.08, "right": 0.98, "top": 0.9, "bottom": 0.13, "wspace": 0.3},
    )


# ------------------------------------------------------------------ the page
def _table(header: list[str], rows: list[list[str]]) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(cell)}</td>" for cell in row) + "</tr>" for row in rows
    )
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _error(value: float, error: float) -> str:
    return f"{value:.5g} ± {error:.2g}" if math.isfinite(value) else "—"


def _percent(value: float) -> str:
    return f"{100 * value:.2g} %" if math.isfinite(value) else "—"


def many_report_html(
    many: ThrowFits, source: str, figures: dict[str, bytes], throws: list[bytes]
) -> str:
    """``report.html``: the joint fit, the table of the throws, and the figures (the
    ratios, the residuals, then every throw's figure rows ``throws``), self-contained."""
    from tumble.report.html import png_data_uri, stylesheet

    title = f"Many-throw fit of {source}"
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{html.escape(title)} — tumble</title><style>{stylesheet()}</style></head><body>",
        f"<h1>{html.escape(title)}</h1>",
        f"<p>{len(many.fitted)} of {len(many.windows)} throws fitted; "
        f"{_percent(many.hold_out)} of each window held out for the forecast.</p>",
        "<h2>Joint fit</h2>",
    ]
    joint = many.joint
    if joint is None:
        parts.append(f"<p>No joint fit: {html.escape(many.joint_refusal)}</p>")
    else:
        rows = [
            [name, _error(joint.moment_ratios[k], joint.uncertainty[k]), ""]
            for k, name in enumerate(("I1/I3", "I2/I3"))
        ]
        drag = zip(joint.torque_parameters, joint.torque_uncertainty, strict=True)
        rows += [
            [f"c{k}/I3 ({joint.torque})", _error(value, error), joint.torque_units]
            for k, (value, error) in enumerate(drag, start=1)
        ]
        rows += [
            ["residual rms", f"{joint.residual_rms:.3g}", "rad/s"],
            ["noise σ", f"{joint.noise:.3g}", "rad/s"],
            ["throws in it", ", ".join(str(i + 1) for i in joint.throws), ""],
            ["outliers", ", ".join(str(i + 1) for i in joint.outliers) or "none", ""],
        ]
        parts.append(_table(["quantity", "value ± std. error", "unit"], rows))
        parts.append(f"<p>Torque: {html.escape(joint.choice)}</p>")
    parts.append(
        f"<p>Forecast error of the held-out parts, median: "
        f"{_percent(_median(many.forecast_errors))} (joint body), "
        f"{_percent(_median(many.single_forecast_errors))} (each throw alone).</p>"
    )
    parts.append("<h2>Throws</h2>")
    rows = [
        [
            str(row.throw),
            f"{row.start:.4g}–{row.end:.4g}",
            "yes" if row.fitted else row.reason,
            row.torque,
            _error(row.r1, row.r1_error),
            _error(row.r2, row.r2_error),
            f"{row.noise_ratio:.3g}" if math.isfinite(row.noise_ratio) else "—",
            _percent(row.forecast_error),
            "yes" if row.outlier else "",
        ]
        for row in many.table.itertuples()
    ]
    header = "throw,window (s),fitted,torque,I1/I3,I2/I3,residual/noise,forecast error,outlier"
    parts.append(_table(header.split(","), rows))
    captions = {
        "ratios": "The ratios of each throw fitted alone (±1 standard error), outliers "
        "marked, beside the joint fit's and its ±1 standard error.",
        "residuals": "Measured − fitted under the joint body for each throw in it; beside, "
        "each throw's residual rms under the joint body and under its own fit.",
    }
    if figures or throws:
        parts.append("<h2>Figures</h2>")
    for name, image in figures.items():
        parts.append(
            f'<figure><img alt="{name}" src="{png_data_uri(image)}"><figcaption class="small">'
            f"{html.escape(captions[name])} ({name}.png)</figcaption></figure>"
        )
    if throws:
        parts.append(
            '<h3>Each throw</h3><p class="small">Measured rates (sensor axes) around each '
            "window, the joint body's fit of it (dashed), and, past the held-out cut "
            "(dash-dotted), the forecast of the joint body fitted to the throws' first "
            "parts (dotted).</p>"
        )
    for image in throws:
        parts.append(f'<figure><img alt="throws" src="{png_data_uri(image)}"></figure>')
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


# ------------------------------------------------------------------ the folder
def write_many(
    many: ThrowFits,
    recording: Recording,
    folder: str | os.PathLike[str],
    *,
    source: str,
    settings: dict[str, Any],
    figures: bool = True,
    force: bool = False,
) -> Path:
    """Write the folder of a many-throw fit (see the module's description), staged
    beside ``folder`` and renamed, claimed first, as :func:`tumble.report.fit.write_fit`
    does. ``settings`` (what was asked: loss, torque, windows found or given) go into
    ``fit.json``. Raises as :func:`tumble.report.fit.write_fit`."""
    from tumble.files import write_bytes, write_text
    from tumble.report.charts import draw, png
    from tumble.report.fit import check_fit_folder, fit_folder, fit_name, fitted_scenario

    target = Path(folder)
    check_fit_folder(target, force)
    joint = many.joint
    scenario = None
    if joint is not None:
        scenario = fitted_scenario(joint.throw_fit(joint.throws[0]), fit_name(source), source)
    images: dict[str, bytes] = {}
    rows: list[bytes] = []
    if figures:
        images = {
            "ratios": png(draw(ratios_sheet(many))),
            "residuals": png(draw(residuals_sheet(many))),
        }
        rows = [png(draw(sheet)) for sheet in throw_sheets(many, recording)]
    page = many_report_html(many, source, images, rows)
    table = many.table
    files = ["throws.csv", "throws.parquet", "joint.json", "report.html", "fit.json"]
    files += [f"{name}.png" for name in images] + (["fitted-scenario.toml"] if scenario else [])
    listing = {
        "kind": "many throws",
        "recording": source,
        "columns": list(recording.columns),
        "note": recording.note,
        "samples": int(recording.t.size),
        "windows": [list(window) for window in many.windows],
        **settings,
        "hold_out": many.hold_out,
        "files": sorted(files),
    }
    with fit_folder(target, force) as staging:
        write_text(staging / "throws.csv", table.to_csv(index=False))
        table.to_parquet(staging / "throws.parquet", index=False)
        summary = joint_summary(many, source)
        write_text(staging / "joint.json", json.dumps(summary, indent=2, allow_nan=False) + "\n")
        if scenario is not None:
            write_text(staging / "fitted-scenario.toml", scenario)
        for name, image in images.items():
            write_bytes(staging / f"{name}.png", image)
        write_text(staging / "report.html", page)
        write_text(staging / "fit.json", json.dumps(listing, indent=2, allow_nan=False) + "\n")
    return target
