"""Figures as data, and their drawing with matplotlib (Agg: no display needed).

A :class:`Sheet` describes a figure completely (its charts, their lines, points
and labels) in numpy arrays and strings, with no matplotlib object in it, so it
can be made where the data are and drawn elsewhere: :func:`draw` makes the
``matplotlib.figure.Figure``, :func:`png` the PNG bytes, and
:class:`FigureWorkers` draws sheets in worker processes started before they
are needed (``tumble run`` starts them as it starts, so that importing
matplotlib and drawing overlap with the simulation and the writing of files).

This module imports numpy only: matplotlib is imported when a sheet is drawn.
"""

from __future__ import annotations

import gc
import io
import multiprocessing
import os
import signal
import sys
from collections.abc import Mapping
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "COLOURS",
    "Chart",
    "Drawings",
    "FigureWorkers",
    "Line",
    "Points",
    "Series",
    "Sheet",
    "Wireframe",
    "draw",
    "png",
]

Array = NDArray[np.float64]

#: Line colours, in the order the series of a chart take them.
COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")


@dataclass(frozen=True)
class Series:
    """Points (x, y), or (x, y, z) in a 3-D chart, with their legend label."""

    x: Array
    y: Array
    z: Array | None = None
    label: str | None = None
    colour: str = COLOURS[0]


@dataclass(frozen=True)
class Line(Series):
    """A line through the points."""

    width: float = 1.0
    dash: str = "-"
    alpha: float = 1.0


@dataclass(frozen=True)
class Points(Series):
    """Markers at the points."""

    colour: str = "k"
    size: float = 12.0
    marker: str = "o"
    on_top: bool = False


@dataclass(frozen=True)
class Wireframe:
    """A surface drawn as a grid of lines in a 3-D chart, (x, y, z) each (rows, columns)."""

    x: Array
    y: Array
    z: Array
    colour: str = "0.75"
    width: float = 0.4


@dataclass(frozen=True)
class Chart:
    """One set of axes: its lines, points and wireframes, labels and scales.
    A chart with a ``zlabel`` is three-dimensional."""

    title: str
    xlabel: str
    ylabel: str
    zlabel: str | None = None
    lines: tuple[Line, ...] = ()
    points: tuple[Points, ...] = ()
    wireframes: tuple[Wireframe, ...] = ()
    legend: str | None = "upper right"  # its place, or None for no legend
    note: str | None = None  # a text in the middle of the axes
    log_y: bool = False
    x_range: tuple[float, float] | None = None
    scientific_y: bool = False  # tick labels as ×10ⁿ outside 1e-3 … 1e3
    equal_aspect: bool = False
    box_aspect: tuple[float, float, float] | None = None  # of a 3-D chart
    title_size: str | None = None
    grid: bool = True


@dataclass(frozen=True)
class Sheet:
    """A figure: its charts side by side, its size (inches) and its margins
    (fractions of the figure: left, right, top, bottom, and the space between
    charts). Fixed margins: a layout engine would double the time to draw."""

    charts: tuple[Chart, ...]
    size: tuple[float, float] = (8.0, 4.0)
    margins: Mapping[str, float] = field(
        default_factory=lambda: {"left": 0.1, "right": 0.97, "top": 0.91, "bottom": 0.13}
    )


def draw(sheet: Sheet) -> Figure:
    """The matplotlib figure of a sheet, made without pyplot (no global registry,
    no window)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    figure = Figure(figsize=sheet.size)
    figure.subplots_adjust(**sheet.margins)
    for k, chart in enumerate(sheet.charts):
        three_d = chart.zlabel is not None
        axes = figure.add_subplot(1, len(sheet.charts), k + 1, projection="3d" if three_d else None)
        _fill(axes, chart, three_d)
    return figure


def _fill(axes: Any, chart: Chart, three_d: bool) -> None:
    """Draw a chart's content and labels into matplotlib axes."""
    for mesh in chart.wireframes:
        axes.plot_wireframe(mesh.x, mesh.y, mesh.z, color=mesh.colour, lw=mesh.width)
    for line in chart.lines:
        coordinates = (line.x, line.y, line.z) if three_d else (line.x, line.y)
        axes.plot(
            *coordinates,
            color=line.colour,
            lw=line.width,
            ls=line.dash,
            alpha=line.alpha,
            label=line.label,
        )
    for points in chart.points:
        coordinates = (points.x, points.y, points.z) if three_d else (points.x, points.y)
        axes.scatter(
            *coordinates,
            color=points.colour,
            s=points.size,
            marker=points.marker,
            label=points.label,
            zorder=3 if points.on_top else None,
        )
    if chart.note is not None:
        axes.text(0.5, 0.5, chart.note, ha="center", transform=axes.transAxes)
    axes.set(xlabel=chart.xlabel, ylabel=chart.ylabel)
    if three_d:
        axes.set(zlabel=chart.zlabel)
        if chart.box_aspect is not None:
            axes.set_box_aspect(chart.box_aspect)
    axes.set_title(chart.title, fontsize=chart.title_size)
    if chart.x_range is not None:
        axes.set_xlim(*chart.x_range)
    if chart.log_y:
        axes.set_yscale("log")
    if chart.scientific_y:
        axes.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
    if chart.equal_aspect:
        axes.set_aspect("equal", adjustable="datalim")
    if chart.legend is not None:
        axes.legend(loc=chart.legend, fontsize="small", framealpha=0.8)
    if chart.grid and not three_d:
        axes.grid(alpha=0.3)


def png(figure: Figure, dpi: int = 100) -> bytes:
    """The figure as PNG bytes."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=dpi, pil_kwargs={"compress_level": 3})
    return buffer.getvalue()


def _png_of(sheet: Sheet) -> bytes:
    """A sheet drawn as PNG bytes (the task of a worker)."""
    return png(draw(sheet))


#: A small sheet with text and a line, drawn once by each worker as it starts:
#: it imports matplotlib and loads the fonts before the first real sheet.
_WARM_UP = Sheet(
    (Chart("t", "x", "y", lines=(Line(np.arange(3.0), np.arange(3.0), label="ω₁ L²"),)),),
    size=(2.0, 1.5),
)


def _warm_up(parent: int) -> None:
    """A worker's start: bound to end with its ``parent`` process, then
    matplotlib imported and its fonts loaded, and what that made moved out of
    the cyclic collector's sight, so that its passes while sheets are drawn do
    not search it again."""
    _end_with(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is for the parent to handle
    _png_of(_WARM_UP)
    gc.freeze()


#: prctl's request for a signal when the parent ends (linux/prctl.h).
_PR_SET_PDEATHSIG = 1


def _end_with(parent: int) -> None:
    """Make this worker end when its ``parent`` ends, however it ends: a parent
    killed (SIGKILL) cannot stop its workers, and they would live on, orphans.
    On Linux the kernel kills the worker when the thread that started it ends
    (``prctl(PR_SET_PDEATHSIG)``; FigureWorkers are made and used by one
    thread); elsewhere a thread of the worker watches for its parent to change
    (the orphan's new parent), twice a second."""
    if sys.platform.startswith("linux"):
        import ctypes

        try:
            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0:
                if os.getppid() != parent:  # it ended before the request
                    os._exit(1)
                return
        except (OSError, AttributeError):  # no prctl in this C library: watch instead
            pass
    import threading

    threading.Thread(target=_watch, args=(parent,), name="watch-parent", daemon=True).start()


def _watch(parent: int) -> None:
    """End this process once its parent is no longer ``parent``."""
    import time

    while os.getppid() == parent:
        time.sleep(0.5)
    os._exit(1)


class FigureWorkers:
    """Worker processes that draw sheets into PNG bytes while this process goes on.

    They start at once and import matplotlib and load its fonts as they start,
    so that work overlaps with whatever this process does until
    :meth:`submit`. Should a worker fail to start or die, the sheets are drawn
    in this process instead: the result is the same PNG bytes. Use as a
    context manager, or call :meth:`close`.

    ``workers``: how many; by default the cores this process leaves, up to two
    (one on two cores: more would slow this process down more than they help).
    On Linux they are forked: create them before this process starts threads.
    They end with this process, even when it is killed (SIGKILL): see
    :func:`_end_with`.
    """

    def __init__(self, workers: int | None = None) -> None:
        self._pool: ProcessPoolExecutor | None = None
        if workers is None:  # the cores this process leaves, up to two
            workers = min(2, max(1, (os.cpu_count() or 1) - 1))
        try:
            # Forked on Linux: a fresh interpreter (spawn) would import again
            # what this process has, and fork is safe here, before any thread.
            method = "fork" if sys.platform.startswith("linux") else "spawn"
            self._pool = ProcessPoolExecutor(
                max_workers=workers,
                mp_context=multiprocessing.get_context(method),
                initializer=_warm_up,
                initargs=(os.getpid(),),
            )
            for _ in range(workers):  # the pool starts its workers on demand
                self._pool.submit(int)
        except (OSError, ImportError, NotImplementedError):  # no processes (or no
            self._pool = None  # semaphores, which the pool's queues need): draw here

    def submit(self, sheets: Mapping[str, Sheet]) -> Drawings:
        """Start drawing the sheets; :meth:`Drawings.result` gives their PNG bytes."""
        futures: dict[str, Future[bytes] | None] = {}
        for name, sheet in sheets.items():
            try:
                futures[name] = None if self._pool is None else self._pool.submit(_png_of, sheet)
            except RuntimeError:  # a broken or shut pool: drawn here
                futures[name] = None
        return Drawings(dict(sheets), futures)

    def close(self) -> None:
        """Stop the workers, dropping the sheets not yet begun, and wait for them
        to end (without waiting, the interpreter's exit may write to the pool's
        closed pipe)."""
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def __enter__(self) -> FigureWorkers:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


@dataclass
class Drawings:
    """Sheets being drawn by :class:`FigureWorkers`."""

    sheets: dict[str, Sheet]
    futures: dict[str, Future[bytes] | None]

    def result(self) -> dict[str, bytes]:
        """The PNG bytes of each sheet by name, in order; a sheet whose worker
        failed (or that had none) is drawn here: the same bytes."""
        done: dict[str, bytes] = {}
        for name, sheet in self.sheets.items():
            future = self.futures[name]
            try:
                done[name] = _png_of(sheet) if future is None else future.result()
            except BrokenProcessPool:  # the worker died: drawn here
                done[name] = _png_of(sheet)
        return done
