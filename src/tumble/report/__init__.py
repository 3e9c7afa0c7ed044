"""Reports of runs: figures (matplotlib), the 3D viewer (plotly), HTML pages, run folders.

* :func:`write_run` — a scenario's run folder: ``trajectory.parquet``,
  ``summary.json``, ``report.html``, PNG figures and ``viewer.html``.
* :func:`figures` — matplotlib figures of a trajectory (``Trajectory.plot``).
* :func:`view` — the interactive viewer (``Trajectory.view``).
* :func:`write_sweep_report` — the ``report.html`` of a finished sweep.

Everything written is self-contained and works offline; every file is written
to a temporary name and renamed, and a run folder is filled beside its final
place and moved there whole, so a reader never sees half a run. One writer
at a time: a run folder is claimed (:class:`tumble.locks.OutputLock`) before
it is checked and written.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from tumble.errors import InputError, OutputError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from tumble.report.charts import FigureWorkers
    from tumble.report.geometry import Geometry
    from tumble.report.viewer import Viewer
    from tumble.scenario.execute import RunResult
    from tumble.sweep.engine import SweepSummary
    from tumble.trajectory import Trajectory

__all__ = ["RunFolderExistsError", "figures", "view", "write_run", "write_sweep_report"]

#: The files of a run folder, whatever the scenario (PNG figures come besides).
RUN_FILES = ("trajectory.parquet", "summary.json", "report.html", "viewer.html")


class RunFolderExistsError(InputError):
    """The output folder already holds files and ``force`` was not given."""


def figures(traj: Trajectory) -> dict[str, Figure]:
    """Matplotlib figures of a trajectory by name: omega, angular_momentum, drift, polhode."""
    from tumble.report.plots import trajectory_figures

    return trajectory_figures(traj)


def view(traj: Trajectory, geometry: Geometry | None = None, frames: int = 300) -> Viewer:
    """The interactive 3D viewer of a trajectory (an ellipsoid of equal inertia
    unless ``geometry`` gives the body's mesh)."""
    from tumble.report.viewer import Viewer, viewer_html

    return Viewer(viewer_html(traj, geometry, frames=frames))


def write_sweep_report(summary: SweepSummary) -> Path:
    """Write the ``report.html`` of a finished sweep (statistics, maps, the sweep
    file) into its folder and return its path (see :mod:`tumble.report.sweep`)."""
    from tumble.report.sweep import write_sweep_report as write

    return write(summary)


def _write_parquet(traj: Trajectory, path: Path, scenario: str, label: str) -> None:
    """The trajectory's Parquet file, its metadata extended with the scenario."""
    import pyarrow.parquet as pq

    from tumble.files import write_bytes

    staging = path.with_name(f".{path.name}.staging")
    traj.to_parquet(staging)
    table = pq.read_table(staging)
    staging.unlink()
    meta = dict(table.schema.metadata or {})
    tumble_meta = json.loads(meta.get(b"tumble", b"{}"))
    tumble_meta["scenario"] = scenario
    tumble_meta["run"] = label
    meta[b"tumble"] = json.dumps(tumble_meta).encode()
    meta[b"scenario"] = scenario.encode()
    import pyarrow as pa

    sink = pa.BufferOutputStream()
    pq.write_table(table.replace_schema_metadata(meta), sink)
    write_bytes(path, sink.getvalue().to_pybytes())


def check_folder(
    folder: Path | str | os.PathLike[str],
    force: bool,
    *,
    kind: str = "run",
    marker: str = "summary.json",
    whole: bool = True,
) -> None:
    """Refuse, before any work, a ``kind`` folder (a run's, a fit's) that cannot
    be written (see :func:`tumble.files.check_output`) or, if it is to be
    replaced ``whole``, replaced whole (the current folder or one above it, a
    mount point), or that holds files unless ``force``; with ``force``, a folder
    that holds files but is not such a folder (no ``marker`` file) is refused
    too, so that no other work is deleted, and so is one holding a file its
    ``marker`` does not list (:func:`tumble.files.check_replaceable`)."""
    from tumble.files import check_output, check_replaceable

    check_output(folder, f"the {kind} folder", folder=True)
    target = Path(os.path.abspath(folder))
    if target.is_dir() and whole:
        here = Path.cwd()
        if target == here or target in here.parents or os.path.ismount(target):
            where = "a mount point" if os.path.ismount(target) else "the current folder or above it"
            raise OutputError(
                f"Expected a {kind} folder that can be replaced whole, got {str(folder)!r}, "
                f"{where}: name a new folder inside it.",
                str(folder),
            )
    if target.is_dir() and any(target.iterdir()):
        if not force:
            raise RunFolderExistsError(
                f"Expected an empty or new output folder, got {str(folder)!r}, which "
                "holds files (use --force to replace them)."
            )
        if not (target / marker).is_file():
            raise RunFolderExistsError(
                f"Expected a {kind} folder to replace with --force (one holding "
                f"{marker}), got {str(folder)!r}, which holds other files: name "
                "another folder."
            )
        if whole:
            check_replaceable(folder, f"the {kind} folder", listed_in=marker)


def write_run(
    result: RunResult,
    folder: str | os.PathLike[str],
    *,
    force: bool = False,
    progress: Callable[[str], object] | None = None,
    figure_workers: FigureWorkers | None = None,
) -> Path:
    """Write a run folder for ``result``.

    The folder gets ``trajectory.parquet`` (one more ``trajectory-LABEL.parquet``
    per extra run), ``summary.json``, ``report.html``, one PNG per figure and
    ``viewer.html`` (unless the scenario's ``[output]`` turns figures or the
    viewer off). It is filled under a temporary name beside ``folder`` and then
    renamed (:func:`tumble.locks.staged_folder`); with ``force`` an existing
    folder is replaced whole. The folder is claimed first
    (:class:`tumble.locks.OutputLock`): another process writing it is refused,
    and what a killed writer left beside it is removed. The figures are drawn
    by ``figure_workers`` (:class:`~tumble.report.charts.FigureWorkers`) while
    the other files are written, if given, else here.

    Raises
    ------
    RunFolderExistsError
        If ``folder`` holds files and ``force`` is false.
    tumble.OutputInUseError
        If another process (or thread) is writing ``folder``.
    tumble.errors.OutputError
        If the folder cannot be written (checked first), or the file system
        fails while writing (a full disk): no partial folder is left, and an
        existing folder is unchanged.
    """
    from tumble.files import output_error
    from tumble.locks import OutputLock, staged_folder

    target = Path(folder)
    try:
        with OutputLock(target, "the run folder"):
            check_folder(target, force)  # claimed: no other writer changes it now
            with staged_folder(target) as staging:
                _fill(result, staging, progress or (lambda _: None), figure_workers)
    except OSError as exc:
        raise output_error(exc, target, "the run folder") from exc
    except OutputError as exc:
        if not isinstance(exc.cause, OSError):
            raise
        raise output_error(exc.cause, target, "the run folder") from exc.cause
    return target


def _fill(
    result: RunResult,
    staging: Path,
    step: Callable[[str], object],
    workers: FigureWorkers | None,
) -> None:
    """Write the run folder's files into ``staging``."""
    from tumble.files import write_bytes, write_text
    from tumble.report.html import report_html

    spec = result.scenario.spec
    name = spec.scenario.name
    sheets = {}
    if spec.output.figures:
        from tumble.report.plots import trajectory_sheets

        sheets = trajectory_sheets(result.trajectory, result.panels)
    # Workers draw the figures while the other files are written.
    drawings = workers.submit(sheets) if workers is not None and sheets else None
    step("trajectory.parquet")
    for label, traj in result.runs.items():
        file = "trajectory.parquet" if label == "main" else f"trajectory-{label}.parquet"
        _write_parquet(traj, staging / file, name, label)
    viewer = None
    if spec.output.viewer:
        step("viewer.html")
        from tumble.report.scenario_geometry import body_geometry, part_drawings
        from tumble.report.viewer import viewer_html
        from tumble.scenario.build import at_key, file_parts

        title = spec.scenario.title or name
        with at_key(result.scenario, "body"):
            geometry = body_geometry(spec.body, result.scenario.folder)
        centre = result.trajectory.mass_properties.center_of_mass
        drawn, rotors = part_drawings(file_parts(spec), centre, geometry)
        page = viewer_html(
            result.trajectory,
            drawn,
            frames=spec.output.viewer_frames,
            title=title,
            rotors=rotors,
        )
        write_text(staging / "viewer.html", page)
        viewer = "viewer.html"
    pngs: dict[str, bytes] = {}
    if sheets:
        step("figures")
        from tumble.report.charts import draw, png

        pngs = (
            drawings.result()
            if drawings is not None
            else {key: png(draw(sheet)) for key, sheet in sheets.items()}
        )
    for figure_name, image in pngs.items():
        write_bytes(staging / f"{figure_name}.png", image)
    step("report.html")
    write_text(staging / "report.html", report_html(result, pngs, viewer))
    summary = result.summary()
    summary["files"] = sorted([*(p.name for p in staging.iterdir()), "summary.json"])
    write_text(staging / "summary.json", json.dumps(summary, indent=2, allow_nan=False) + "\n")
