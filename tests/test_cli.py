"""The command line: output equals the library's, user errors are one line and exit code 2."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
from numpy.testing import assert_allclose
from typer.testing import CliRunner

import tumble as tb
from tumble.cli import app

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
runner = CliRunner()


def run(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def test_shape_json_equals_the_library() -> None:
    code, out, _ = run(
        "inertia",
        "solid-cone",
        "--mass",
        "250 g",
        "--radius",
        "3 cm",
        "--height",
        "8 cm",
        "--about",
        "0, 0, -2 cm",
        "--json",
    )
    assert code == 0
    data = json.loads(out)
    expected = tb.shapes.solid_cone(0.25, 0.03, 0.08)
    assert data["mass"] == pytest.approx(0.25, rel=1e-15)
    assert_allclose(data["inertia"], expected.inertia, rtol=1e-15)
    assert_allclose(data["about"]["inertia"], expected.inertia_about([0, 0, -0.02]), rtol=1e-15)
    moments, axes = expected.principal()
    assert_allclose(data["principal_moments"], moments, rtol=1e-15)
    assert_allclose(data["principal_axes"], axes, rtol=1e-15)


def test_mesh_table_shows_the_products_of_inertia() -> None:
    code, out, _ = run(
        "inertia", str(EXAMPLES / "l_bracket.stl"), "--units", "mm", "--density", "2700 kg/m^3"
    )
    assert code == 0
    mp = tb.from_mesh(EXAMPLES / "l_bracket.stl", density=2700, units="mm")
    assert "Inertia tensor about the centre of mass" in out
    assert f"{mp.inertia[0, 1]:.6g}" in out  # the (non-zero, positive) product I_xy
    assert f"{mp.mass:.6g}" in out
    assert "I_xy = −Σ m x y" in out


def test_mesh_json_with_mass() -> None:
    code, out, _ = run(
        "inertia", str(EXAMPLES / "l_bracket.stl"), "--units", "mm", "--mass", "1 kg", "--json"
    )
    assert code == 0
    assert json.loads(out)["mass"] == pytest.approx(1.0, rel=1e-15)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["inertia", "cylindr", "--mass", "1"],
            r"Expected a shape to be one of box, .*, or a mesh file, got 'cylindr'\. Did you mean solid-cylinder\?",
        ),
        (
            ["inertia", "box", "--mass", "1", "--size", "1, 2 m"],
            r"Expected `size` to have shape \(3,\), got \(2,\)",
        ),
        (
            ["inertia", "box", "--mass", "1", "--size", "1,2,3", "--radius", "2"],
            r"Expected only --mass, --size for box, got --radius",
        ),
        (
            ["inertia", "box", "--size", "1,2,3"],
            r"Expected --mass for box \(it takes --mass, --size\)",
        ),
        (
            ["inertia", "solid-cylinder", "--mass", "1", "--radius", "1 kg", "--height", "1"],
            r"Expected `radius` to be a length in m, got 1 kg",
        ),
        (
            ["inertia", "solid-sphere", "--mass", "1 kg", "--radius", "3 🍕"],
            r"Expected `radius` to be a number or a quantity such as '250 g', got '3 🍕', which holds '🍕'",
        ),
        (
            ["inertia", "missing.stl", "--density", "1000"],
            r"Expected `mesh` to be a mesh file, got 'missing.stl' \(no such file\)",
        ),
        (
            ["inertia", str(EXAMPLES / "l_bracket.stl")],
            r"Expected exactly one of `density` and `mass`, got neither",
        ),
        (
            ["inertia", str(EXAMPLES / "l_bracket.stl"), "--density", "1", "--radius", "2"],
            r"Expected --density or --mass \(and --units\) for a mesh, got --radius",
        ),
        (
            ["inertia", "box", "--mass", "1", "--size", "1,2,3", "--about", "1, 2"],
            r"Expected `--about` to have shape \(3,\), got \(2,\)",
        ),
    ],
)
def test_user_errors_are_one_line_with_exit_code_2(args: list[str], message: str) -> None:
    code, out, err = run(*args)
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("error: ")
    assert re.search(message, lines[0]), lines[0]


def test_debug_shows_the_exception() -> None:
    result = runner.invoke(app, ["--debug", "inertia", "box", "--mass", "-1", "--size", "1,2,3"])
    assert isinstance(result.exception, tb.InputError)


def test_version() -> None:
    code, out, _ = run("--version")
    assert code == 0
    assert out.startswith("tumble ")


def test_python_dash_m_tumble_is_the_command() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "tumble", "--version"], capture_output=True, text=True, check=False
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("tumble ")


def script(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """The real entry point in a fresh process, as a user's shell runs it."""
    return subprocess.run(
        [sys.executable, "-c", "from tumble.cli import main; main()", *args],
        capture_output=True,
        text=True,
        check=False,
        cwd=cwd,
    )


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["inertia", "torus", "--mass", "1", "--major-radius", "1", "--minor-radius", "2"],
            r"^error: Expected `minor_radius` <= `major_radius` = 1.0 m",
        ),
        (
            ["inertia", "box", "--mass", "1", "--foo", "3"],
            r"^error: No such option: --foo \(see: tumble inertia --help\)$",
        ),
        (
            ["inertia"],
            r"^error: Missing argument 'SHAPE-or-MESH'\. \(see: tumble inertia --help\)$",
        ),
        (["frobnicate"], r"^error: No such command 'frobnicate'\.$"),
        (
            ["inertia", ".", "--density", "1"],
            r"^error: Expected `mesh` to be a mesh file, got '\.' \(a directory\)\.$",
        ),
        (["inertia", "box", "--mass", "9**9**9 g", "--size", "1,2,3"], r"runaway power"),
    ],
)
def test_script_errors_are_one_line_exit_2_without_traceback(args: list[str], message: str) -> None:
    result = script(*args)
    assert result.returncode == 2
    assert result.stdout == ""
    assert result.stderr.count("\n") == 1, result.stderr
    assert "Traceback" not in result.stderr
    assert re.search(message, result.stderr.strip()), result.stderr


def test_script_without_arguments_shows_help() -> None:
    result = script()
    assert result.returncode == 0
    assert "inertia" in result.stdout


def test_script_warnings_are_one_line(tmp_path: Path) -> None:
    import trimesh

    cube = trimesh.creation.box()
    cube.invert()  # inside out: tumble reverses it and says so
    cube.export(tmp_path / "inverted.stl")
    result = script("inertia", str(tmp_path / "inverted.stl"), "--density", "1000", "--json")
    assert result.returncode == 0
    assert json.loads(result.stdout)["mass"] == pytest.approx(1000.0, rel=1e-12)
    assert result.stderr.count("\n") == 1
    assert result.stderr.startswith("warning: mesh ") and "is inside out" in result.stderr


def test_json_names_the_shape_as_typed() -> None:
    code, out, _ = run("inertia", "solid_sphere", "--mass", "1", "--radius", "1", "--json")
    assert code == 0
    assert json.loads(out)["body"] == "solid-sphere"


def test_an_error_of_the_file_system_is_one_line_with_a_long_path_cut() -> None:
    from tumble.cli.app import one_line

    long = "/tmp/" + "x" * 5000
    message = one_line(PermissionError(13, "Permission denied", long))
    assert message.startswith("Expected to read or write '/tmp/xxx")
    assert message.endswith("'..., got: Permission denied.")
    assert len(message) < 300
