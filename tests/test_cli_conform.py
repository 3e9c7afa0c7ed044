"""``tumble conform``: the table, JSON, the report folder, and one line for each refusal."""

from __future__ import annotations

import json
from pathlib import Path
from typing import ClassVar

import pytest
from typer.testing import CliRunner

from tumble.cli import app
from tumble.conformance import ENGINES, Engine, register_engine

runner = CliRunner()

QUICK = ["--engines", "tumble/rk4,scipy/rk45", "--duration", "1", "--dt", "0.01"]


def test_the_table_names_each_engine_and_the_exact_flip_count() -> None:
    result = runner.invoke(app, ["conform", *QUICK, "--scenario", "major-spin"])
    assert result.exit_code == 0, result.output
    assert "major-spin: I = (1, 2, 3) kg·m², ω0 = (0.1, 0, 20) rad/s" in result.output
    assert "tumble/rk4" in result.output and "scipy/rk45" in result.output
    assert "exact flips: " in result.output
    assert "of the engines'" in result.output


def test_json_prints_one_record_per_engine_with_the_contract_s_columns() -> None:
    result = runner.invoke(app, ["conform", *QUICK, "--json"])
    assert result.exit_code == 0, result.output
    records = [json.loads(line) for line in result.output.splitlines()]
    assert [record["engine"] for record in records] == ["tumble/rk4", "scipy/rk45"]
    for key in (
        "dt",
        "energy_drift_max",
        "energy_drift_final",
        "momentum_drift_max",
        "direction_drift_max",
        "attitude_error_max",
        "omega_error_max",
        "flips",
        "flips_exact",
        "failed_at",
        "steps_per_second",
    ):
        assert key in records[0]
    assert records[0]["failed_at"] is None  # NaN in the table, null in JSON


def test_several_steps_make_a_sweep_with_orders() -> None:
    result = runner.invoke(
        app,
        [
            "conform",
            "--engines",
            "tumble/rk4",
            "--scenario",
            "intermediate-slow",
            "--duration",
            "5",
            "--dt",
            "0.04,0.02",
            "--dt",
            "0.01",
            "--json",
        ],
    )
    assert result.exit_code == 0, result.output
    records = [json.loads(line) for line in result.output.splitlines()]
    assert [record["dt"] for record in records] == [0.04, 0.02, 0.01]
    assert records[0]["order"] == pytest.approx(4.0, abs=0.3)  # RK4


def test_a_body_of_one_s_own() -> None:
    result = runner.invoke(
        app, ["conform", *QUICK, "--inertia", "2, 3, 4 kg*m^2", "--omega", "0, 5, 0.1", "--json"]
    )
    assert result.exit_code == 0, result.output
    assert len(result.output.splitlines()) == 2


def test_list_shows_engines_and_scenarios() -> None:
    result = runner.invoke(app, ["conform", "--list"])
    assert result.exit_code == 0, result.output
    for name in ("mujoco/rk4", "pybullet/undamped", "drake/continuous", "rapier", "heavy-top"):
        assert name in result.output


class _Missing(Engine):
    name = "absent-test"
    variants: ClassVar[dict[str, str]] = {"": "needs a module nobody has"}
    modules = ("no_such_engine_module",)


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (
            ["--scenario", "spin"],
            "Expected the scenario to be one of intermediate-slow, intermediate-fast, major-spin, minor-spin, symmetric-top, heavy-top, or a Scenario, got 'spin'.",
        ),
        (["--engines", "mujoco/rk5"], "Did you mean mujoco/rk4?"),
        (
            ["--engines", "absent-test"],
            "Expected an installed engine, got absent-test: not installed: no_such_engine_module (pip install 'tumble[engines]').",
        ),
        (["--dt", "0"], "Expected dt > 0 s, got 0.0."),
        (
            ["--dt", "0.01,,0.02"],
            "Expected --dt to be values separated by commas, got '0.01,,0.02'.",
        ),
        (["--dt", "2 kg"], "Expected `dt` to be a time in s, got 2 kg"),
        (["--duration", "-1"], "Expected a duration > 0 s, got '-1'."),
        (["--dt", "5", "--duration", "1"], "Expected dt no longer than the duration 1 s, got 5 s."),
        (["--dt", "1e-9", "--duration", "100"], "Expected at most 20,000,000 steps"),
        (["--inertia", "1, 1, 3"], "triangle"),
        (
            ["--scenario", "heavy-top", "--omega", "0, 0, 1"],
            "Expected --inertia and --omega with a free body's scenario, got --scenario heavy-top",
        ),
    ],
)
def test_requests_that_cannot_work_exit_2_with_one_line(arguments: list[str], message: str) -> None:
    register_engine(_Missing)
    try:
        result = runner.invoke(app, ["conform", "--engines", "tumble/rk4", *arguments])
    finally:
        del ENGINES["absent-test"]
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1, result.output
    assert message in lines[0]


def test_the_report_folder(tmp_path: Path) -> None:
    folder = tmp_path / "conformance"
    result = runner.invoke(app, ["conform", *QUICK, "-o", str(folder)])
    assert result.exit_code == 0, result.output
    assert {path.name for path in folder.iterdir()} >= {
        "table.parquet",
        "table.json",
        "report.html",
        "conformance.json",
    }
    again = runner.invoke(app, ["conform", *QUICK, "-o", str(folder)])
    assert again.exit_code == 2
    assert "--force" in again.output or "force" in again.output
    forced = runner.invoke(app, ["conform", *QUICK, "-o", str(folder), "--force"])
    assert forced.exit_code == 0, forced.output


def test_an_output_that_is_a_file_is_refused_before_any_run(tmp_path: Path) -> None:
    path = tmp_path / "table.txt"
    path.write_text("keep me", encoding="utf-8")
    result = runner.invoke(app, ["conform", *QUICK, "-o", str(path)])
    assert result.exit_code == 2, result.output
    assert path.read_text(encoding="utf-8") == "keep me"
    assert len(result.output.strip().splitlines()) == 1
