"""Sweeps: millions of free bodies at once, in this process or on a Dask cluster.

A sweep file (TOML; see :mod:`tumble.sweep.schema`) gives a base scenario and
the parameters to vary, on grids or drawn at random; each body is stepped by
the batched compiled kernels and measured as it goes (flips, time of the first
flip, largest nutation, conservation drift), and the results go to a Zarr store
chunked by bodies, with ``summary.json``; the maps of the report page are
computed here and drawn by :func:`tumble.report.write_sweep_report`.

* :func:`run_sweep` — run (or resume) a sweep into a folder: a :class:`SweepSummary`.
* :func:`load_sweep` — validate a sweep file or built-in into a :class:`Plan`.
* :func:`builtin_sweeps`, :func:`show_sweep` — the sweeps shipped with tumble.
* :func:`open_results` — the Zarr group of a sweep's results; an interrupted
  sweep's warns (:class:`IncompleteSweepWarning`) and marks its bodies computed.
"""

from __future__ import annotations

from tumble.sweep.engine import SweepSummary, builtin_sweeps, load_sweep, run_sweep, show_sweep
from tumble.sweep.plan import METRICS, PARAMETERS, Plan
from tumble.sweep.schema import SweepError
from tumble.sweep.store import IncompleteSweepWarning, open_results

__all__ = [
    "METRICS",
    "PARAMETERS",
    "IncompleteSweepWarning",
    "Plan",
    "SweepError",
    "SweepSummary",
    "builtin_sweeps",
    "load_sweep",
    "open_results",
    "run_sweep",
    "show_sweep",
]
