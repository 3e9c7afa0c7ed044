"""`tumble sweep`: a run, a resume, JSON, and one-line errors with exit code 2."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from test_sweep import SMALL
from tumble.cli import app

runner = CliRunner()


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def test_a_sweep_runs_then_resumes_from_its_folder(tmp_path: Path) -> None:
    source = tmp_path / "small.toml"
    source.write_text(SMALL, encoding="utf-8")
    folder = tmp_path / "out"
    code, out, _ = invoke("sweep", str(source), "-o", str(folder), "--quiet")
    assert code == 0 and out == ""
    assert (folder / "summary.json").exists() and (folder / "report.html").exists()
    code, out, _ = invoke("sweep", str(source), "-o", str(folder), "--json")
    summary = json.loads(out)
    assert code == 0
    # Everything was already there: every chunk is reused, none recomputed.
    assert summary["chunks_run"] == 0 and summary["chunks_reused"] == summary["chunks"]
    code, out, _ = invoke("sweep", str(source), "-o", str(folder))
    assert code == 0 and "reused" in out and "report.html" in out


def test_sweep_errors_are_one_line_with_exit_code_2(tmp_path: Path) -> None:
    source = tmp_path / "small.toml"
    source.write_text(SMALL.replace("seed = 3", "seeds = 3"), encoding="utf-8")
    code, _, err = invoke("sweep", str(source), "-o", str(tmp_path / "out"))
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("error: ") and "seeds" in err
    code, _, err = invoke("sweep", "no-such-sweep", "-o", str(tmp_path / "x"))
    assert code == 2 and err.count("\n") == 1 and "no-such-sweep" in err


def test_a_sweep_folder_under_a_file_is_one_line_before_any_chunk(tmp_path: Path) -> None:
    source = tmp_path / "small.toml"
    source.write_text(SMALL, encoding="utf-8")
    folder = tmp_path / "small.toml" / "out"
    code, out, err = invoke("sweep", str(source), "-o", str(folder))
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"error: Expected the sweep's output folder in a folder, got {str(folder)!r}, which is "
        f"under the file {str(source)!r}."
    ]


def test_a_sweep_beyond_the_memory_budget_is_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    source = tmp_path / "small.toml"
    source.write_text(SMALL, encoding="utf-8")
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "1 kB")
    code, _, err = invoke("sweep", str(source), "-o", str(tmp_path / "out"))
    assert code == 2
    (line,) = err.strip().splitlines()
    assert line.startswith(
        "error: Expected a request that fits in the memory budget of 1000 B "
        "(TUMBLE_MEMORY_BUDGET = 1 kB), got chunks of 18 bodies: about "
    )
    assert not (tmp_path / "out").exists()
