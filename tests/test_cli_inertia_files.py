"""`tumble inertia` with a mesh file: what is wrong with a file is one line, its name cut."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from tumble.cli import app

runner = CliRunner()


def invoke(*args: str) -> tuple[int, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stderr.strip()


@pytest.mark.parametrize("name", ["missing.step", "missing.STP", "missing.stl"])
def test_a_missing_mesh_file_is_named_as_a_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str
) -> None:
    monkeypatch.chdir(tmp_path)
    code, err = invoke("inertia", name, "--density", "2700")
    assert code == 2
    assert err == f"error: Expected `mesh` to be a mesh file, got {name!r} (no such file)."


def test_a_name_too_long_for_the_system_is_cut() -> None:
    code, err = invoke("inertia", "n" * 5000, "--mass", "1")
    assert code == 2
    assert err.startswith("error: Expected a shape to be one of box, ")
    assert err.endswith(f"or a mesh file, got {'n' * 60!r}....")


def test_a_malformed_stl_is_one_line_in_the_words_of_the_format(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("bad.stl").write_text(
        "solid bad\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0\n"
        "  endloop\n endfacet\nendsolid bad\n"
    )
    code, err = invoke("inertia", "bad.stl", "--mass", "1")
    assert code == 2
    assert err == (
        "error: Expected mesh 'bad.stl' to be a well-formed STL file (each facet has 3 `vertex` "
        "lines of 3 numbers), got one that is not."
    )
