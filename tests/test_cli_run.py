"""`tumble run`, `tumble list`, `tumble show`: output, run folders, one-line errors."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tumble.cli import app
from tumble.scenario import builtin_names, builtin_text

runner = CliRunner()

# A fast scenario for the command line's own behaviour (the physics is tested elsewhere).
QUICK = """
[scenario]
name = "quick"
title = "A quick free top"

[body]
shape = "box"
mass = "1 kg"
size = "10, 20, 30 cm"

[initial]
omega = "3, 0.1, 0.1 rad/s"    # about x, the intermediate axis: it flips

[simulation]
duration = "5 s"

[output]
samples = 500
figures = false
viewer = false
"""
FULL = QUICK.replace("figures = false\nviewer = false", "viewer_frames = 20")


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture
def quick(tmp_path: Path) -> Path:
    path = tmp_path / "quick.toml"
    path.write_text(QUICK)
    return path


def test_list_names_every_builtin_on_one_line() -> None:
    code, out, _ = invoke("list")
    assert code == 0
    lines = out.splitlines()
    names = builtin_names()
    assert [line.split()[0] for line in lines[: len(names)]] == names
    assert lines[0].startswith("gyroscope ") and "precession" in lines[0]


def test_show_prints_the_toml_to_copy(tmp_path: Path) -> None:
    code, out, _ = invoke("show", "skew-rod")
    assert code == 0
    assert out == builtin_text("skew-rod")
    code, out, err = invoke("show", "skewrod")
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        "error: Expected a built-in scenario (gyroscope, gyrocompass, skew-rod, tennis-racket, "
        "heavy-top, free-symmetric-top, tumbling-satellite, dual-spin, explorer-1, "
        "gravity-gradient, reaction-wheel-slew) or a .toml file, got 'skewrod'. "
        "Did you mean skew-rod?"
    ]


def test_run_a_file_writes_the_folder_and_prints_the_report(quick: Path, tmp_path: Path) -> None:
    quick.write_text(FULL)
    out_dir = tmp_path / "out"
    code, out, err = invoke("run", str(quick), "-o", str(out_dir))
    assert code == 0, err
    assert "A quick free top" in out
    assert "Theory (flip-period) vs simulation" in out
    assert f"Report: {out_dir / 'report.html'}" in out.replace("\n", "")
    for name in ("trajectory.parquet", "summary.json", "report.html", "viewer.html", "omega.png"):
        assert (out_dir / name).is_file()


def test_json_prints_the_summary(quick: Path, tmp_path: Path) -> None:
    code, out, _ = invoke("run", str(quick), "-o", str(tmp_path / "j"), "--json")
    assert code == 0
    summary = json.loads(out)
    assert summary["scenario"] == "quick"
    assert summary["report"] == str(tmp_path / "j" / "report.html")
    assert summary["comparisons"][0]["quantity"] == "flip period"
    assert summary["comparisons"][0]["relative_error"] < 1e-6
    # A free body: the energy and the vector L are conserved, and only they are shown.
    assert set(summary["drift"]) == {"energy", "angular_momentum_vector"}


def test_quiet_prints_nothing(quick: Path, tmp_path: Path) -> None:
    code, out, err = invoke("run", str(quick), "-o", str(tmp_path / "q"), "--quiet")
    assert code == 0 and out == "" and err == ""


def test_rerun_into_a_folder_asks_for_force(quick: Path, tmp_path: Path) -> None:
    out_dir = tmp_path / "again"
    assert invoke("run", str(quick), "-o", str(out_dir), "-q")[0] == 0
    stamp = (out_dir / "summary.json").stat().st_mtime_ns
    code, out, err = invoke("run", str(quick), "-o", str(out_dir))
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"error: Expected an empty or new output folder, got {str(out_dir)!r}, which holds files "
        "(use --force to replace them)."
    ]
    assert (out_dir / "summary.json").stat().st_mtime_ns == stamp  # untouched
    code, _, _ = invoke("run", str(quick), "-o", str(out_dir), "--force", "-q")
    assert code == 0 and (out_dir / "summary.json").stat().st_mtime_ns != stamp


def test_default_folder_is_under_runs(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    code, out, _ = invoke("run", str(quick))
    assert code == 0
    (folder,) = (tmp_path / "runs").iterdir()
    assert folder.name.startswith("quick-")
    assert f"Report: runs/{folder.name}/report.html" in out.replace("\n", "")
    # A second run in the same second gets its own folder.
    assert invoke("run", str(quick), "-q")[0] == 0
    assert len(list((tmp_path / "runs").iterdir())) == 2


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            QUICK.replace('mass = "1 kg"', 'mass = "1 m"'),
            r"^error: .*quick\.toml, line 8, `body\.mass`: Expected `mass` to be a mass in kg, got 1 m \(dimensions \[length\]\)\.$",
        ),
        (
            QUICK.replace("[output]", "[ouptut]"),
            r"^error: .*quick\.toml, line 17, `ouptut`: Expected one of .*, got the unknown key `ouptut`\. Did you mean `output`\?$",
        ),
        (
            QUICK.replace('duration = "5 s"', 'duration = "0 s"'),
            r"^error: .*`simulation\.duration`: Expected `duration` > 0 s, got 0\.0\.$",
        ),
        (
            QUICK.replace("[body]", "[body"),
            r"^error: .*quick\.toml: Expected valid TOML, got an error: .*\(at line 6, column 6\)\.$",
        ),
    ],
)
def test_user_errors_are_one_line_and_exit_2(text: str, message: str, tmp_path: Path) -> None:
    path = tmp_path / "quick.toml"
    path.write_text(text)
    code, out, err = invoke("run", str(path), "-o", str(tmp_path / "out"))
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1
    assert re.match(message, lines[0]), lines[0]
    assert not (tmp_path / "out").exists()  # nothing written before the error


def test_missing_file_and_unknown_scenario() -> None:
    code, _, err = invoke("run", "nothere.toml")
    assert code == 2
    assert err.strip() == "error: Expected a scenario file, got 'nothere.toml' (no such file)."
    code, _, err = invoke("run", "gyroskope")
    assert code == 2 and err.strip().endswith("got 'gyroskope'. Did you mean gyroscope?")


def test_debug_shows_the_traceback(tmp_path: Path) -> None:
    from tumble.scenario import ScenarioError

    result = runner.invoke(app, ["--debug", "run", "nothere.toml"])
    assert isinstance(result.exception, ScenarioError)


def test_progress_bar_appears_for_slow_runs(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from tumble.cli.progress import LazyProgress

    shown: list[str] = []
    monkeypatch.setattr(LazyProgress, "DELAY", 0.0)
    original = LazyProgress._show

    def spy(self: LazyProgress) -> bool:
        visible = original(self)
        if visible:
            shown.append(self.description)
        return visible

    monkeypatch.setattr(LazyProgress, "_show", spy)
    assert invoke("run", str(quick), "-o", str(tmp_path / "p"))[0] == 0
    assert shown and any(d.startswith("writing") for d in shown)
    shown.clear()
    assert invoke("run", str(quick), "-o", str(tmp_path / "p2"), "--quiet")[0] == 0
    assert shown == []


def test_list_and_show_include_example_sweeps() -> None:
    sweep = pytest.importorskip("tumble.sweep")
    examples = sweep.builtin_sweeps()
    if not examples:
        pytest.skip("no example sweeps shipped")
    code, out, _ = invoke("list")
    assert code == 0
    for name in examples:
        assert any(line.split()[:2] == [name, "sweep:"] for line in out.splitlines())
    name = next(iter(examples))
    code, out, _ = invoke("show", name)
    assert code == 0 and out == sweep.show_sweep(name)
