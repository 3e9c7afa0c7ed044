"""The report of engines against the exact motion: figures, the HTML page and the folder."""

from __future__ import annotations

import html
import io
import json
import math
import re
from pathlib import Path
from typing import ClassVar

import numpy as np
import pandas as pd
import pytest

import tumble.conformance as conformance
from tumble.conformance import ENGINES, ConformanceResult, Engine, Scenario, register_engine
from tumble.report import RunFolderExistsError
from tumble.report.conformance import conformance_figures, conformance_html, write_conformance
from tumble.report.conformance_figures import circulation_axis, exact_polhode

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

#: Short runs: the report's work does not depend on the horizon, only on the samples.
ENGINES_USED = ["tumble/rk4", "scipy/rk45"]


class _Absent(Engine):
    """An engine whose module is not installed: the suite skips it with a reason."""

    name: ClassVar[str] = "absent-report-test"
    variants: ClassVar[dict[str, str]] = {"": "an engine that is never installed"}
    modules: ClassVar[tuple[str, ...]] = ("tumble_no_such_engine_module",)


@pytest.fixture(scope="module")
def single() -> ConformanceResult:
    """A run at one dt of a free body, with one engine skipped as not installed."""
    register_engine(_Absent)
    try:
        return conformance.run(
            [*ENGINES_USED, "absent-report-test"], "intermediate-fast", dt=1e-2, duration=1.0
        )
    finally:
        del ENGINES[_Absent.name]


@pytest.fixture(scope="module")
def swept() -> ConformanceResult:
    return conformance.sweep(ENGINES_USED, "intermediate-slow", [2e-2, 1e-2], duration=2.0)


@pytest.fixture(scope="module")
def pivoted() -> ConformanceResult:
    # 5e-3 s: the top turns at up to 34 rad/s, and tumble's integrators ask for 20
    # steps a turn at least.
    return conformance.run(ENGINES_USED, "heavy-top", dt=5e-3, duration=1.0)


def _image(data: bytes) -> np.ndarray:
    import matplotlib.image

    assert data.startswith(PNG_SIGNATURE)
    return np.asarray(matplotlib.image.imread(io.BytesIO(data), format="png"))


def _check_pngs(figures: dict[str, bytes]) -> None:
    for name, data in figures.items():
        image = _image(data)
        assert image.ndim == 3 and min(image.shape[:2]) > 200, name
        # Something is drawn: not one flat colour.
        assert float(np.ptp(image[..., :3])) > 0.5, name


def test_a_run_of_a_free_body_has_energy_attitude_and_momentum_sphere_figures(
    single: ConformanceResult,
) -> None:
    figures = conformance_figures(single)
    assert list(figures) == ["energy", "attitude", "momentum-sphere"]
    _check_pngs(figures)


def test_a_sweep_adds_the_convergence_figure(swept: ConformanceResult) -> None:
    figures = conformance_figures(swept)
    assert list(figures) == ["energy", "attitude", "convergence", "momentum-sphere"]
    _check_pngs(figures)


def test_a_sweep_of_one_dt_has_no_convergence_figure() -> None:
    result = conformance.sweep(["tumble/rk4"], "major-spin", [1e-2], duration=1.0)
    assert "convergence" not in conformance_figures(result)


def test_a_body_on_a_pivot_has_no_momentum_sphere(pivoted: ConformanceResult) -> None:
    figures = conformance_figures(pivoted)
    assert list(figures) == ["energy", "attitude"]
    _check_pngs(figures)


def test_a_user_body_on_a_pivot_has_no_momentum_sphere() -> None:
    top = Scenario(
        (0.05, 0.05, 0.08),
        (0.0, 0.0, 20.0),
        duration=1.0,
        pivot=(0.0, 0.0, -0.1),
        gravity=9.81,
        attitude0=(np.cos(0.1), np.sin(0.1), 0.0, 0.0),
    )
    result = conformance.run(["tumble/rk4"], top, dt=1e-2)
    assert "momentum-sphere" not in conformance_figures(result)


def test_no_figures_when_no_engine_ran() -> None:
    register_engine(_Absent)
    try:
        result = conformance.run(["absent-report-test"], "major-spin", dt=1e-2, duration=1.0)
    finally:
        del ENGINES[_Absent.name]
    assert conformance_figures(result) == {}
    page = conformance_html(result, {})
    assert "No engine ran." in page
    assert "tumble_no_such_engine_module" in page


@pytest.mark.parametrize("name", ["major-spin", "minor-spin", "intermediate-fast", "symmetric-top"])
def test_the_momentum_sphere_is_seen_along_the_axis_the_polhode_circles(name: str) -> None:
    # Oracle (Landau & Lifshitz, Mechanics §37): L circles the major axis when
    # L² > 2 E I_intermediate, the minor axis when L² < 2 E I_intermediate.
    scenario = conformance.get_scenario(name)
    moments, omega = scenario.moments, scenario.initial_state[1]
    momentum = moments * omega
    energy = 0.5 * float(omega @ momentum)
    middle = float(np.sort(moments)[1])
    expected = int(
        np.argmax(moments) if momentum @ momentum > 2 * energy * middle else np.argmin(moments)
    )
    polhode = exact_polhode(scenario, 20.0)
    assert circulation_axis(polhode, moments) == expected
    # The polhode lies on the unit sphere (L/|L(0)|, |L| conserved): to round-off of
    # the elliptic functions, far below 1e-9.
    np.testing.assert_allclose(np.linalg.norm(polhode, axis=1), 1.0, atol=1e-9)


def test_the_page_names_every_engine_and_why_one_was_skipped(single: ConformanceResult) -> None:
    page = conformance_html(single, conformance_figures(single))
    assert page.startswith("<!DOCTYPE html>")
    assert "intermediate-fast" in page
    assert html.escape(single.scenario.description) in page
    for engine in ENGINES_USED:
        assert f"<td>{engine}</td>" in page
    reason = single.skipped["absent-report-test"]
    assert reason.startswith("not installed: tumble_no_such_engine_module")
    assert "absent-report-test" in page
    assert html.escape(reason) in page
    # Every figure is inline, as a PNG data URI: the page loads nothing.
    assert page.count('src="data:image/png;base64,') == 3
    assert "http://" not in page and "https://" not in page


def test_the_page_shows_the_table_to_three_significant_digits(swept: ConformanceResult) -> None:
    page = conformance_html(swept, {})
    for _, row in swept.table.iterrows():
        assert f'<td class="num">{row["energy_drift_max"]:.3g}</td>' in page
        assert f'<td class="num">{row["attitude_error_max"]:.3g}</td>' in page
    assert "<th>order</th>" in page and "<th>safe dt (s)</th>" in page
    # tumble/rk4's step of 1e-2 s keeps within 1e-6 on this slow tumble: a safe dt shown.
    assert swept.table["safe_dt"].notna().any()
    cost = re.search(r"The exact reference took ([0-9.e+-]+) s", page)
    assert cost is not None and float(cost.group(1)) == pytest.approx(
        swept.reference_seconds, rel=0.01
    )


def test_a_single_run_has_no_order_column(single: ConformanceResult) -> None:
    page = conformance_html(single, {})
    assert "<th>order</th>" not in page and "<th>safe dt (s)</th>" not in page


def test_a_failed_run_shows_its_failure() -> None:
    pytest.importorskip("mujoco")
    # MuJoCo's default Euler gains energy on this fast tumble until it blows up (about
    # 8.6 s at dt = 1e-2 s): the failure is in the table and the figures still draw.
    result = conformance.run(["mujoco/euler"], "intermediate-fast", dt=1e-2, duration=12.0)
    (row,) = result.table.to_dict(orient="records")
    assert math.isfinite(row["failed_at"]) and row["failure"]
    figures = conformance_figures(result)
    _check_pngs(figures)
    page = conformance_html(result, figures)
    assert f'<td class="poor">{html.escape(row["failure"])}</td>' in page


def test_the_folder_holds_the_table_the_page_and_the_summary(
    pivoted: ConformanceResult, tmp_path: Path
) -> None:
    folder = write_conformance(pivoted, tmp_path / "conform")
    files = sorted(path.name for path in folder.iterdir())
    assert files == ["conformance.json", "report.html", "table.json", "table.parquet"]
    summary = json.loads((folder / "conformance.json").read_text())
    assert summary["files"] == files
    assert summary["scenario"]["name"] == "heavy-top"
    np.testing.assert_array_equal(summary["scenario"]["moments"], [0.05, 0.05, 0.08])
    assert summary["scenario"]["duration"] == pytest.approx(1.0)
    assert summary["reference_seconds"] == pivoted.reference_seconds
    pd.testing.assert_frame_equal(pd.read_parquet(folder / "table.parquet"), pivoted.table)
    assert "<td>tumble/rk4</td>" in (folder / "report.html").read_text()


def test_table_json_has_null_for_nan(pivoted: ConformanceResult, tmp_path: Path) -> None:
    folder = write_conformance(pivoted, tmp_path / "conform")
    text = (folder / "table.json").read_text()
    assert "NaN" not in text and "Infinity" not in text
    records = json.loads(text)
    assert [record["engine"] for record in records] == ENGINES_USED
    for record, (_, row) in zip(records, pivoted.table.iterrows(), strict=True):
        # About a pivot L's direction is not conserved (NaN), and no run failed (NaN).
        assert math.isnan(row["direction_drift_max"]) and record["direction_drift_max"] is None
        assert math.isnan(row["failed_at"]) and record["failed_at"] is None
        assert record["energy_drift_max"] == row["energy_drift_max"]
        assert record["flips"] == row["flips"]


def test_an_existing_folder_is_refused_without_force_and_replaced_with_it(
    single: ConformanceResult, pivoted: ConformanceResult, tmp_path: Path
) -> None:
    folder = tmp_path / "conform"
    write_conformance(single, folder)
    message = (
        f"Expected an empty or new output folder, got '{folder}', which holds files "
        "(use --force to replace them)."
    )
    with pytest.raises(RunFolderExistsError, match=re.escape(message)):
        write_conformance(pivoted, folder)
    assert json.loads((folder / "conformance.json").read_text())["scenario"]["name"] == (
        "intermediate-fast"
    )
    write_conformance(pivoted, folder, force=True)
    assert json.loads((folder / "conformance.json").read_text())["scenario"]["name"] == (
        "heavy-top"
    )


def test_force_does_not_replace_a_folder_of_other_work(
    pivoted: ConformanceResult, tmp_path: Path
) -> None:
    folder = tmp_path / "notes"
    folder.mkdir()
    (folder / "mine.txt").write_text("keep me")
    message = (
        "Expected a conformance folder to replace with --force (one holding "
        f"conformance.json), got '{folder}', which holds other files: name another folder."
    )
    with pytest.raises(RunFolderExistsError, match=re.escape(message)):
        write_conformance(pivoted, folder, force=True)
    assert (folder / "mine.txt").read_text() == "keep me"
