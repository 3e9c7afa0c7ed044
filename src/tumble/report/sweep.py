"""The page of a finished sweep: its statistics, its maps as images, its file.

The numbers come from :func:`tumble.sweep.summary.summarize` (in the sweep's
:class:`~tumble.sweep.SweepSummary`); this module draws them (matplotlib) and
writes ``report.html`` beside ``results.zarr`` and ``summary.json``.
"""

from __future__ import annotations

import base64
import html
import io
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.files import write_text
from tumble.report.html import stylesheet
from tumble.sweep.plan import METRICS, PARAMETERS
from tumble.sweep.summary import MapData

if TYPE_CHECKING:
    from tumble.sweep.engine import SweepSummary

__all__ = ["coarsened", "map_png", "report_html", "write_sweep_report"]

Array = NDArray[np.float64]


def write_sweep_report(summary: SweepSummary) -> Path:
    """Write ``report.html`` of a finished sweep into its folder (written whole or
    not at all) and return its path."""
    page = report_html(summary.to_dict(), list(summary.maps), summary.text)
    write_text(summary.report, page)
    return summary.report


def _label(name: str) -> str:
    from tumble.units import SI_UNITS

    kind = PARAMETERS[name][0]
    unit = "deg" if kind == "angle" else SI_UNITS.get(kind, "")
    return f"{name} [{unit}]" if unit else name


def _shown(name: str, values: Array) -> Array:
    """Angles are shown in degrees."""
    return np.degrees(values) if PARAMETERS.get(name, ("",))[0] == "angle" else values


#: Cells per axis drawn at most: a finer map is merged into blocks first (the
#: image is some 500 pixels wide, and a million quadrilaterals would cost
#: matplotlib seconds and hundreds of MB).
MAX_CELLS = 250


def coarsened(data: MapData, limit: int = MAX_CELLS) -> MapData:
    """The map merged into blocks of k × k cells so no axis has more than
    ``limit``: means weighted by the bodies in each cell, minima and maxima
    of the cells."""
    ny, nx = data.values.shape
    kx = -(-nx // limit)
    ky = -(-ny // limit) if data.edges_y is not None else 1
    if kx == 1 and ky == 1:
        return data
    rows, cols = -(-ny // ky), -(-nx // kx)
    values = np.full((rows * ky, cols * kx), np.nan)
    counts = np.zeros((rows * ky, cols * kx), dtype=np.int64)
    values[:ny, :nx] = data.values
    counts[:ny, :nx] = data.counts
    blocks = values.reshape(rows, ky, cols, kx)
    weights = counts.reshape(rows, ky, cols, kx)
    total = weights.sum(axis=(1, 3))
    with warnings.catch_warnings(), np.errstate(invalid="ignore", divide="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN blocks
        if data.spec.statistic == "mean":
            merged = np.nansum(blocks * weights, axis=(1, 3)) / total
        elif data.spec.statistic == "min":
            merged = np.nanmin(blocks, axis=(1, 3))
        else:
            merged = np.nanmax(blocks, axis=(1, 3))
    merged[total == 0] = np.nan
    edges_x = np.append(data.edges_x[:-1:kx], data.edges_x[-1])
    edges_y = None if data.edges_y is None else np.append(data.edges_y[:-1:ky], data.edges_y[-1])
    return MapData(data.spec, merged, total, edges_x, edges_y, data.log_x, data.log_y)


def map_png(data: MapData) -> bytes:
    """The map as a PNG image."""
    from matplotlib.figure import Figure

    data = coarsened(data)
    spec = data.spec
    unit = METRICS[spec.metric][0]
    metric_label = f"{spec.statistic} {spec.metric}" + (f" [{unit}]" if unit else "")
    if spec.metric == "max_nutation":
        metric_label = f"{spec.statistic} max_nutation [deg]"
    values = np.degrees(data.values) if spec.metric == "max_nutation" else data.values
    figure = Figure(figsize=(7.0, 5.0))  # fixed margins: a layout engine costs ~0.2 s a map
    figure.subplots_adjust(left=0.11, right=0.97 if spec.y is None else 0.8, bottom=0.1, top=0.93)
    axes = figure.add_subplot()
    x = _shown(spec.x, data.edges_x)
    if data.edges_y is None or spec.y is None:
        centres = 0.5 * (x[1:] + x[:-1]) if not data.log_x else np.sqrt(x[1:] * x[:-1])
        axes.plot(centres, values[0], marker=".", linewidth=1)
        axes.set_ylabel(metric_label)
    else:
        y = _shown(spec.y, data.edges_y)
        mesh = axes.pcolormesh(x, y, np.ma.masked_invalid(values), cmap="viridis", shading="flat")
        figure.colorbar(mesh, cax=figure.add_axes((0.83, 0.1, 0.025, 0.83)), label=metric_label)
        axes.set_ylabel(_label(spec.y))
        if data.log_y:
            axes.set_yscale("log")
    if data.log_x:
        axes.set_xscale("log")
    axes.set_xlabel(_label(spec.x))
    axes.set_title(f"{spec.metric} over {spec.x}" + (f" × {spec.y}" if spec.y else ""))
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=100)
    return buffer.getvalue()


def _number(value: Any) -> str:
    if value is None:
        return "—"
    if isinstance(value, int):
        return f"{value:,}"
    return f"{float(value):.6g}"


def report_html(summary: dict[str, Any], maps: list[MapData], text: str) -> str:
    """A self-contained page: the run, the statistics, the maps, the sweep file."""
    e = html.escape
    run_rows = [
        ("sweep", summary["name"]),
        ("bodies", _number(summary["bodies"])),
        ("chunks", f"{summary['chunks']} of {_number(summary['chunk_size'])} bodies"),
        ("method", f"{summary['method']}, dt = {summary['dt']:.6g} s, {summary['steps']} steps"),
        ("backend", summary["backend"]),
        ("this run", f"{summary['chunks_run']} chunks computed, {summary['chunks_reused']} reused"),
    ]
    if summary.get("body_steps_per_second"):
        run_rows.append(("speed", f"{summary['body_steps_per_second']:.3g} body-steps/s"))
    rows = "".join(f"<tr><th>{e(k)}</th><td>{e(str(v))}</td></tr>" for k, v in run_rows)
    metric_rows = []
    for name, s in summary["metrics"].items():
        extra = ""
        if "fraction_flipped" in s:
            extra = f"{100 * s['fraction_flipped']:.3g} % of bodies flipped"
        metric_rows.append(
            f"<tr><td>{e(name)}</td><td>{e(s['unit'] or '1')}</td>"
            + "".join(
                f'<td class="num">{_number(s[k])}</td>' for k in ("mean", "min", "max", "nan")
            )
            + f"<td>{e(extra)}</td></tr>"
        )
    images = "".join(
        f"<h2>{e(m.spec.metric)}: {e(m.spec.statistic)} over {e(m.spec.x)}"
        + (f" × {e(m.spec.y)}" if m.spec.y else "")
        + "</h2>"
        + f'<img alt="map" src="data:image/png;base64,{base64.b64encode(map_png(m)).decode()}">'
        for m in maps
    )
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{e(summary["name"])} — tumble sweep</title>
<style>{stylesheet()}</style></head><body>
<h1>Sweep {e(summary["name"])}</h1>
<p>{e(summary.get("description", ""))}</p>
<table>{rows}</table>
<h2>Metrics per body</h2>
<table><thead><tr><th>metric</th><th>unit</th><th>mean</th><th>min</th><th>max</th>
<th>NaN</th><th></th></tr></thead><tbody>{"".join(metric_rows)}</tbody></table>
<p>Angles in the maps are in degrees; the results are in results.zarr (SI units).</p>
{images}
<h2>Sweep file</h2>
<pre>{e(text)}</pre>
</body></html>
"""
