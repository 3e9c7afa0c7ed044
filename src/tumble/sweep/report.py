"""What a finished sweep says: statistics of each metric, maps, summary.json, report.html.

Everything is read back from the Zarr store one chunk at a time, so memory
stays bounded by a chunk whatever the number of bodies, and the numbers depend
only on the stored results (not on how the run was cut or resumed).

A map shows a statistic (mean, min or max, over the bodies that fall in a
cell, NaN values left out) of one metric over one or two varied parameters:
a grid parameter gives one cell per grid value, a random one ``bins`` equal
cells over its range (logarithmic for a log-uniform draw).
"""

from __future__ import annotations

import base64
import html
import io
import math
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.report.html import stylesheet
from tumble.sweep.plan import METRICS, PARAMETERS, GridAxis, MapSpec, Plan

if TYPE_CHECKING:
    from tumble.sweep.store import SweepStore

__all__ = ["MapData", "summarize"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class MapData:
    """A computed map: ``values`` (ny, nx) (one row for a curve) at cell
    ``edges_x``/``edges_y``; ``log_x``/``log_y`` for logarithmic axes."""

    spec: MapSpec
    values: Array
    counts: NDArray[np.int64]
    edges_x: Array
    edges_y: Array | None
    log_x: bool
    log_y: bool


class _Axis:
    """How bodies fall into the cells of one map axis."""

    def __init__(self, plan: Plan, name: str, bins: int) -> None:
        self.name = name
        grid = {a.name: (k, a) for k, a in enumerate(plan.grid)}
        if name in grid:
            self.grid_index: int | None = grid[name][0]
            axis: GridAxis = grid[name][1]
            values = axis.values
            unique, self.rank = np.unique(values, return_inverse=True)  # cell of each grid value
            self.size = len(unique)
            self.log = bool(len(unique) > 2 and np.all(unique > 0) and _geometric(unique))
            self.edges = _edges(unique, self.log)
        else:
            self.grid_index = None
            draw = next(a for a in plan.random if a.name == name)
            self.size = bins
            self.log = draw.distribution == "loguniform"
            low, high = draw.low, draw.high
            if high == low:
                high = low + (abs(low) or 1.0) * 1e-9
            self.edges = (
                np.geomspace(low, high, bins + 1) if self.log else np.linspace(low, high, bins + 1)
            )
            self.low, self.high = low, high

    def cells(self, store: SweepStore, index: int, grid: tuple[NDArray[np.int64], ...]) -> Any:
        if self.grid_index is not None:
            return self.rank[grid[self.grid_index]]
        values = store.read(f"parameters/{self.name}", index).astype(float)
        if self.log:
            position = np.log(values / self.low) / math.log(self.high / self.low)
        else:
            position = (values - self.low) / (self.high - self.low)
        return np.clip((position * self.size).astype(np.int64), 0, self.size - 1)


def _geometric(values: Array) -> bool:
    ratios = values[1:] / values[:-1]
    linear = np.diff(values)
    return bool(
        np.ptp(ratios) < 1e-9 * ratios.mean() and np.ptp(linear) > 1e-6 * abs(linear.mean())
    )


def _edges(centres: Array, log: bool) -> Array:
    if len(centres) == 1:
        c = centres[0]
        return np.array([c * 0.9, c * 1.1]) if log else np.array([c - 0.5, c + 0.5])
    points = np.log(centres) if log else centres
    middle = 0.5 * (points[1:] + points[:-1])
    edges = np.concatenate(
        [[points[0] - (middle[0] - points[0])], middle, [points[-1] + (points[-1] - middle[-1])]]
    )
    return np.exp(edges) if log else edges


def summarize(store: SweepStore) -> tuple[dict[str, Any], list[MapData]]:
    """Statistics of every metric and the maps, streamed chunk by chunk."""
    plan = store.plan
    stats = {
        name: {"count": 0, "sum": 0.0, "min": math.inf, "max": -math.inf, "nan": 0}
        for name in plan.metrics
    }
    flipped = 0
    axes = []
    accumulators = []
    for spec in plan.maps:
        ax = _Axis(plan, spec.x, spec.bins)
        ay = _Axis(plan, spec.y, spec.bins) if spec.y is not None else None
        axes.append((ax, ay))
        size = ax.size * (ay.size if ay is not None else 1)
        initial = {"mean": 0.0, "min": math.inf, "max": -math.inf}[spec.statistic]
        accumulators.append((np.full(size, initial), np.zeros(size, dtype=np.int64)))
    for index in range(plan.n_chunks):
        start, stop = plan.chunk_range(index)
        grid = plan.grid_indices(start, stop)
        values = {name: store.read(f"metrics/{name}", index).astype(float) for name in plan.metrics}
        for name, v in values.items():
            finite = np.isfinite(v)
            s = stats[name]
            s["nan"] += int(v.size - finite.sum())
            if finite.any():
                s["count"] += int(finite.sum())
                s["sum"] += float(v[finite].sum())
                s["min"] = min(s["min"], float(v[finite].min()))
                s["max"] = max(s["max"], float(v[finite].max()))
        if "flips" in values:
            flipped += int(np.count_nonzero(values["flips"] > 0))
        for (ax, ay), spec, (acc, counts) in zip(axes, plan.maps, accumulators, strict=True):
            cell = ax.cells(store, index, grid)
            if ay is not None:
                cell = ay.cells(store, index, grid) * ax.size + cell
            v = values[spec.metric]
            keep = np.isfinite(v)
            cell, v = cell[keep], v[keep]
            counts += np.bincount(cell, minlength=counts.size)
            if spec.statistic == "mean":
                acc += np.bincount(cell, weights=v, minlength=acc.size)
            elif spec.statistic == "min":
                np.minimum.at(acc, cell, v)
            else:
                np.maximum.at(acc, cell, v)
    metrics: dict[str, Any] = {}
    for name, s in stats.items():
        count = s["count"]
        metrics[name] = {
            "unit": METRICS[name][0],
            "bodies": count,
            "nan": s["nan"],
            "mean": s["sum"] / count if count else None,
            "min": s["min"] if count else None,
            "max": s["max"] if count else None,
        }
    if "flips" in stats:
        metrics["flips"]["fraction_flipped"] = flipped / plan.n_bodies
    maps = []
    for (ax, ay), spec, (acc, counts) in zip(axes, plan.maps, accumulators, strict=True):
        with np.errstate(invalid="ignore", divide="ignore"):
            result = acc / counts if spec.statistic == "mean" else acc.copy()
        result[counts == 0] = np.nan
        shape = (ay.size if ay is not None else 1, ax.size)
        maps.append(
            MapData(
                spec,
                result.reshape(shape),
                counts.reshape(shape),
                ax.edges,
                ay.edges if ay is not None else None,
                ax.log,
                ay.log if ay is not None else False,
            )
        )
    return metrics, maps


# ---------------------------------------------------------------- figures
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
