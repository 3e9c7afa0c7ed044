"""What a finished sweep says: statistics of each metric, and its maps as numbers.

Everything is read back from the Zarr store one chunk at a time, so memory
stays bounded by a chunk whatever the number of bodies, and the numbers depend
only on the stored results (not on how the run was cut or resumed).

A map shows a statistic (mean, min or max, over the bodies that fall in a
cell, NaN values left out) of one metric over one or two varied parameters:
a grid parameter gives one cell per grid value, a random one ``bins`` equal
cells over its range (logarithmic for a log-uniform draw). The maps are drawn
by :mod:`tumble.report.sweep`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.sweep.plan import METRICS, GridAxis, MapSpec, Plan

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
