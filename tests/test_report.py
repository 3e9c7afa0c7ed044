"""Run folders, the HTML report, the viewer page and the notebook helpers."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import tumble as tb
from tumble.errors import OutputError
from tumble.report import RUN_FILES, RunFolderExistsError, write_run
from tumble.scenario import run


@pytest.fixture(scope="module")
def gyroscope() -> object:
    return run("gyroscope")


@pytest.fixture(scope="module")
def folder(gyroscope: object, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_run(gyroscope, tmp_path_factory.mktemp("runs") / "gyro")  # type: ignore[arg-type]


def test_run_folder_holds_every_file(folder: Path) -> None:
    names = {p.name for p in folder.iterdir()}
    assert set(RUN_FILES) <= names
    pngs = {
        "omega.png",
        "angular_momentum.png",
        "drift.png",
        "polhode.png",
        "nutation.png",
        "precession.png",
    }
    assert pngs <= names
    for png in pngs:
        assert (folder / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # Nothing half-written or staged is left behind, in the folder or beside it.
    assert not [n for n in os.listdir(folder.parent) if n.startswith(".")]
    assert not [n for n in names if n.startswith(".")]


def test_summary_json(folder: Path, gyroscope: object) -> None:
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["scenario"] == "gyroscope"
    assert summary["tumble_version"] == tb.__version__
    assert summary["method"] == "exact"
    assert summary["comparisons"], "the gyroscope has a theory"
    for row in summary["comparisons"]:
        assert {"quantity", "theory", "measured", "relative_error", "unit"} <= set(row)
        assert row["relative_error"] == pytest.approx(
            abs(row["measured"] - row["theory"]) / abs(row["theory"]), rel=1e-12
        )
    drift = summary["drift"]
    # A symmetric top on a pivot under gravity conserves exactly these three; the
    # splitting keeps each to round-off over the run.
    assert set(drift) == {"energy", "angular_momentum_vertical", "angular_momentum_axial"}
    assert max(drift.values()) < 1e-10
    assert "report.html" in summary["files"] and "summary.json" in summary["files"]


def test_parquet_round_trip_with_scenario_metadata(folder: Path, gyroscope: object) -> None:
    import pyarrow.parquet as pq

    read = tb.Trajectory.read_parquet(folder / "trajectory.parquet")
    traj = gyroscope.trajectory  # type: ignore[attr-defined]
    assert_allclose(read.t, traj.t, rtol=0, atol=0)
    assert_allclose(read.omega, traj.omega, rtol=0, atol=0)
    assert read.method == "exact"
    meta = json.loads(pq.read_schema(folder / "trajectory.parquet").metadata[b"tumble"])
    assert meta["scenario"] == "gyroscope"
    assert meta["tumble_version"] == tb.__version__
    assert meta["method"] == "exact"


def test_report_is_self_contained(folder: Path, gyroscope: object) -> None:
    page = (folder / "report.html").read_text()
    # Nothing is fetched: no external scripts, styles or images.
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert "<link" not in page
    images = re.findall(r'<img [^>]*src="([^"]+)"', page)
    assert len(images) == 6 and all(src.startswith("data:image/png;base64,") for src in images)
    for row in gyroscope.comparisons:  # type: ignore[attr-defined]
        assert row["quantity"] in page
    assert 'href="viewer.html"' in page
    assert "pivot = &quot;0, 0, -10 cm&quot;" in page  # the scenario itself, escaped
    # The stylesheet shipped with the package, inlined.
    from tumble.report.html import stylesheet

    assert "td.num {" in stylesheet() and f"<style>{stylesheet()}</style>" in page


def test_viewer_is_self_contained_and_small(folder: Path) -> None:
    page = (folder / "viewer.html").read_text()
    assert len(page.encode()) < 10e6
    assert not re.search(r"""<script[^>]+src=""", page)
    assert "Plotly" in page and "newPlot" in page
    data = json.loads(re.search(r'id="tumble-data">(.*?)</script>', page, re.S).group(1))  # type: ignore[union-attr]
    assert len(data["t"]) == len(data["q"]) == 300  # [output] viewer_frames
    assert data["t"][0] == 0 and data["t"][-1] == pytest.approx(5.0)
    assert data["exact_shape"] and data["fixed_point"] == "pivot"
    for q in data["q"]:
        assert np.linalg.norm(q) == pytest.approx(1.0, abs=1e-4)  # 5 digits kept


def test_an_existing_folder_needs_force(folder: Path, gyroscope: object, tmp_path: Path) -> None:
    target = tmp_path / "out"
    target.mkdir()
    (target / "old.txt").write_text("from another run")
    with pytest.raises(
        RunFolderExistsError,
        match=r"Expected an empty or new output folder, got '.*out', which holds files \(use --force to replace them\)\.",
    ):
        write_run(gyroscope, target)  # type: ignore[arg-type]
    # --force replaces run folders only: a folder of other files is never deleted.
    with pytest.raises(
        RunFolderExistsError,
        match=r"Expected a run folder to replace with --force \(one holding summary\.json\), got "
        r"'.*out', which holds other files: name another folder\.",
    ):
        write_run(gyroscope, target, force=True)  # type: ignore[arg-type]
    assert (target / "old.txt").exists()
    # Nor is a run folder holding a file its summary does not list as the run's.
    (target / "summary.json").write_text('{"files": ["summary.json", "old.txt"]}')
    (target / "notes.txt").write_text("mine")
    with pytest.raises(
        OutputError,
        match=r"^Expected the run folder to hold only the files its summary\.json lists to "
        r"replace it whole, got '.*out', which holds 'notes\.txt' too: move it away",
    ):
        write_run(gyroscope, target, force=True)  # type: ignore[arg-type]
    assert (target / "notes.txt").read_text() == "mine"
    (target / "notes.txt").unlink()
    write_run(gyroscope, target, force=True)  # type: ignore[arg-type]
    assert not (target / "old.txt").exists()  # replaced whole, never mixed
    assert (target / "report.html").exists()
    assert sorted(os.listdir(tmp_path)) == ["out"]


def test_a_failed_write_leaves_nothing(
    gyroscope: object, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import tumble.report.html

    def broken(*args: object, **kwargs: object) -> str:
        raise RuntimeError("disk full")

    monkeypatch.setattr(tumble.report.html, "report_html", broken)
    with pytest.raises(RuntimeError, match="disk full"):
        write_run(gyroscope, tmp_path / "out")  # type: ignore[arg-type]
    assert os.listdir(tmp_path) == []


def test_a_file_in_the_way_is_refused(gyroscope: object, tmp_path: Path) -> None:
    (tmp_path / "out").write_text("x")
    with pytest.raises(
        tb.OutputError,
        match=r"Expected the run folder to be a folder, got '.*out', which is a file\.",
    ):
        write_run(gyroscope, tmp_path / "out")  # type: ignore[arg-type]


def test_gyrocompass_folder_has_both_runs(tmp_path: Path) -> None:
    from tumble.scenario import builtin_text, parse

    spec = builtin_text("gyrocompass") + "\n[output]\nfigures = false\nviewer = false\n"
    result = run(parse(spec))
    out = write_run(result, tmp_path / "gc")
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "report.html",
        "summary.json",
        "trajectory-amplitude-100deg.parquet",
        "trajectory.parquet",
    ]
    summary = json.loads((out / "summary.json").read_text())
    # The platform does work on the disk: only the Jacobi integral is conserved, and
    # RK4 at the scenario's step keeps it to ~1e-10 of its size.
    assert set(summary["drift"]) == {"jacobi_integral"}
    assert summary["drift"]["jacobi_integral"] < 1e-8
    assert {row["run"] for row in summary["comparisons"]} == {"main", "amplitude-100deg"}


# ------------------------------------------------------------------ notebooks
def test_notebook_html() -> None:
    mp = tb.shapes.solid_cone("250 g", "3 cm", "8 cm")
    page = mp._repr_html_()
    assert "0.25 kg" in page and "9.375e-05" in page and "<table>" in page
    traj = tb.simulate(tb.shapes.box(1, [1, 2, 3]), [0.1, 1, 0.1], duration=1.0)
    summary = traj._repr_html_()
    assert f"{len(traj.t)} over 1 s" in summary and "relative drift" in summary


def test_plot_and_view(tmp_path: Path) -> None:
    from matplotlib.figure import Figure

    traj = tb.simulate(tb.shapes.box(1, [1, 2, 3]), [0.1, 1, 0.1], duration=3.0, dt=1e-2)
    figures = traj.plot()
    assert set(figures) == {"omega", "angular_momentum", "drift", "polhode"}
    assert all(isinstance(f, Figure) for f in figures.values())
    # The ω figure shows the three body components (and |ω|).
    lines = figures["omega"].axes[0].get_lines()
    assert_allclose(lines[1].get_ydata(), traj.omega[:, 1])
    # Torque-free: the herpolhode beside the polhode, the curve ω draws on the
    # invariable plane (tumble.analysis.herpolhode); under a torque, the polhode alone.
    polhode_axes = figures["polhode"].axes
    assert len(polhode_axes) == 2
    plane = tb.analysis.herpolhode(traj)
    drawn = polhode_axes[1].get_lines()[0]
    assert_allclose(drawn.get_xdata(), plane.in_plane[:, 0])
    assert_allclose(drawn.get_ydata(), plane.in_plane[:, 1])
    damped = tb.simulate(tb.shapes.box(1, [1, 2, 3]), [0.1, 1, 0.1], duration=1.0, dt=1e-2,
                         torque=tb.torques.LinearDamping(0.01))  # fmt: skip
    assert len(damped.plot()["polhode"].axes) == 1
    viewer = traj.view(frames=50)
    assert "srcdoc=" in viewer._repr_html_()
    saved = viewer.save(tmp_path / "v.html")
    page = saved.read_text()
    data = json.loads(re.search(r'id="tumble-data">(.*?)</script>', page, re.S).group(1))  # type: ignore[union-attr]
    assert len(data["t"]) == 50
    assert not data["exact_shape"]  # an ellipsoid of equal inertia
    assert data["fixed_point"] == "centre of mass"


def test_equal_inertia_ellipsoid() -> None:
    from tumble.report.geometry import equal_inertia_ellipsoid

    body = tb.shapes.box(2.0, [0.3, 0.2, 0.1]).transformed(translation=[1, 2, 3])
    geometry = equal_inertia_ellipsoid(body)
    # Semi-axes a_i² = 5 (I_j + I_k − I_i) / (2 m): for a box of edges e, a = √(5/12) e.
    semi = np.sqrt(5 / 12) * np.array([0.3, 0.2, 0.1])
    local = geometry.vertices - [1, 2, 3]
    assert_allclose(np.sum((local / semi) ** 2, axis=1), 1.0, rtol=1e-12)
    assert not geometry.exact


def test_drift_figure_shows_only_what_is_conserved(gyroscope: object) -> None:
    from tumble.report.plots import drift_figure

    traj = gyroscope.trajectory  # type: ignore[attr-defined]
    # Under gravity |L| about the pivot is not conserved: the energy and the
    # vertical and axial components of L are drawn, nothing else.
    energy_line, vertical_line, axial_line = drift_figure(traj).axes[0].get_lines()
    energy = traj.energy
    assert_allclose(energy_line.get_ydata(), (energy - energy[0]) / np.max(np.abs(energy)))
    # Independently: L in space dotted with the upward vertical (gravity is −z here),
    # and L in body axes dotted with the symmetry axis z, relative to the largest |L|
    # of the run.
    momentum = traj.angular_momentum
    size = np.max(np.linalg.norm(momentum, axis=1))
    assert_allclose(vertical_line.get_ydata(), (momentum[:, 2] - momentum[0, 2]) / size)
    inertia = traj.mass_properties.inertia_about(traj.pivot)
    axial = traj.omega @ inertia[2]
    assert_allclose(axial_line.get_ydata(), (axial - axial[0]) / size, atol=1e-15)


def test_a_scenario_solid_is_drawn_as_its_shape_s_surface() -> None:
    from tumble.report.scenario_geometry import shape_mesh
    from tumble.scenario.bodies import ShapeBody
    from tumble.shapes import Shape

    vertices, faces = shape_mesh(ShapeBody(mass=1, shape="capsule", radius=0.5, cylinder_height=1))
    expected = Shape.of("capsule", radius=0.5, cylinder_height=1).surface()
    assert_allclose(vertices, expected[0], rtol=0, atol=0)
    assert np.array_equal(faces, expected[1])


def test_the_viewer_draws_the_poinsot_construction_of_a_torque_free_body(
    gyroscope: object,
) -> None:
    from scipy.spatial.transform import Rotation

    from tumble.report.viewer import viewer_data

    # Under gravity about a pivot there is no fixed plane: no Poinsot panel.
    assert viewer_data(gyroscope.trajectory)["poinsot"] is None  # type: ignore[attr-defined]
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    traj = tb.simulate(body, [0.4, 2.0, 0.3], duration=10.0, dt=0.01, method="exact")
    data = viewer_data(traj)
    poinsot = data["poinsot"]
    assert poinsot is not None
    polhode, herpolhode = np.array(poinsot["polhode"]), np.array(poinsot["herpolhode"])
    scale = float(np.max(np.linalg.norm(herpolhode, axis=1)))
    # The page keeps 5 significant digits of each array (q to 1e-5, ω to 1e-4 of
    # its largest value): the relations hold to a few 1e-4 of |ω|.
    turned = Rotation.from_quat(np.array(data["q"]), scalar_first=True).apply(polhode)
    assert np.max(np.abs(turned - herpolhode)) < 5e-4 * scale  # the contact point is ω
    height = herpolhode @ np.array(poinsot["normal"])
    assert np.max(np.abs(height - poinsot["height"])) < 5e-4 * scale  # on the plane
    energy = 0.5 * np.einsum("ni,ij,nj->n", polhode, body.inertia, polhode)
    assert np.max(np.abs(energy / traj.energy[0] - 1)) < 1e-3  # on the ellipsoid ω·Jω = 2T
    # The mesh is that ellipsoid: its points satisfy ω·Jω = 2T.
    mesh = np.array(poinsot["ellipsoid"])
    on = np.einsum("ni,ij,nj->n", mesh, body.inertia, mesh) / (2 * traj.energy[0])
    assert np.max(np.abs(on - 1)) < 1e-3


def test_the_current_folder_and_mount_points_are_not_run_folders(
    gyroscope: object, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Replacing a run folder moves it aside: the current folder, one above it
    # or a mount point cannot be moved, so they are refused before any work.
    inside = tmp_path / "work"
    inside.mkdir()
    monkeypatch.chdir(inside)
    for target in (".", "", "..", str(tmp_path)):
        with pytest.raises(
            tb.OutputError,
            match=r"Expected a run folder that can be replaced whole, got '.*', the current "
            r"folder or above it: name a new folder inside it\.",
        ):
            write_run(gyroscope, target, force=True)  # type: ignore[arg-type]
    monkeypatch.setattr(os.path, "ismount", lambda p: Path(p) == inside)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(tb.OutputError, match=r"got '.*work', a mount point: name a new folder"):
        write_run(gyroscope, inside, force=True)  # type: ignore[arg-type]
    assert sorted(os.listdir(tmp_path)) == ["work"]


def test_figure_workers_draw_the_very_png_drawn_here(gyroscope: object, tmp_path: Path) -> None:
    # The oracle is drawing in this process: workers must give the same bytes, in
    # the same order, and a run folder written with them the same PNG files.
    from tumble.report.charts import FigureWorkers, draw, png
    from tumble.report.plots import trajectory_sheets

    sheets = trajectory_sheets(gyroscope.trajectory, gyroscope.panels)  # type: ignore[attr-defined]
    here = {name: png(draw(sheet)) for name, sheet in sheets.items()}
    with FigureWorkers(2) as workers:
        drawn = workers.submit(sheets).result()
        folder = write_run(gyroscope, tmp_path / "with-workers", figure_workers=workers)  # type: ignore[arg-type]
    assert list(drawn) == list(here)
    assert drawn == here
    for name, image in here.items():
        assert (folder / f"{name}.png").read_bytes() == image


def test_the_sheets_of_dead_figure_workers_are_drawn_here(gyroscope: object) -> None:
    # A worker that dies (here: made to exit) breaks the pool; the sheets are then
    # drawn in this process, the same bytes, and no error reaches the user.
    from tumble.report.charts import FigureWorkers, draw, png
    from tumble.report.plots import omega_sheet

    sheet = omega_sheet(gyroscope.trajectory)  # type: ignore[attr-defined]
    with FigureWorkers(1) as workers:
        assert workers._pool is not None
        workers._pool.submit(os._exit, 1)
        drawings = workers.submit({"omega": sheet, "again": sheet})
        assert drawings.result() == {"omega": png(draw(sheet)), "again": png(draw(sheet))}
        assert workers.submit({"omega": sheet}).result() == {"omega": png(draw(sheet))}


def test_a_drawing_error_in_a_figure_worker_reaches_the_caller(gyroscope: object) -> None:
    # Not a dead worker but a sheet that cannot be drawn: the same error as here.
    from tumble.report.charts import Chart, FigureWorkers, Sheet

    bad = Sheet((Chart("t", "x", "y", legend="nowhere in particular"),))
    with FigureWorkers(1) as workers, pytest.raises(ValueError, match="nowhere in particular"):
        workers.submit({"bad": bad}).result()
