"""``tumble audit`` and ``tumble inertia ROBOT``: exit codes, JSON, the corrected copy."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import tumble as tb
from tumble.cli import app
from tumble.robots import example_path

runner = CliRunner()

EXAMPLE = example_path().read_text(encoding="utf-8")


def write(tmp_path: Path, text: str = EXAMPLE, name: str = "arm.urdf") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_a_clean_robot_exits_0_with_a_table() -> None:
    result = runner.invoke(app, ["audit", str(example_path())])
    assert result.exit_code == 0, result.output
    assert "arm: 3 links (arm.urdf)" in result.output
    assert "0 errors, 0 other findings" in result.output


def test_a_robot_with_an_error_exits_1_and_fix_writes_the_corrected_copy(tmp_path: Path) -> None:
    source = write(tmp_path, EXAMPLE.replace('izz="0.0009"', 'izz="0.9"'))
    out = tmp_path / "fixed" / "arm.urdf"
    result = runner.invoke(app, ["audit", str(source), "--fix", str(out)])
    assert result.exit_code == 1, result.output
    assert "error arm (triangle-inequality)" in result.output
    assert "power-of-ten): Writing izz = 0.0009 (for 0.9)" in result.output
    assert f"Corrected 1 link into {out}" in result.output
    assert out.read_text(encoding="utf-8") == EXAMPLE
    assert runner.invoke(app, ["audit", str(out)]).exit_code == 0


def test_json_lists_the_findings(tmp_path: Path) -> None:
    source = write(tmp_path, EXAMPLE.replace('<mass value="0.5"/>', '<mass value="0"/>'))
    result = runner.invoke(app, ["audit", str(source), "--json"])
    assert result.exit_code == 0, result.output  # a warning is no error
    data = json.loads(result.output)
    assert data["errors"] == 0 and data["links"] == 3
    (finding,) = data["findings"]
    assert finding["code"] == "massless-with-geometry" and finding["link"] == "hand"
    assert len(finding["correction"]["xyz"]) == 3


def test_geometry_none_reads_no_shape(tmp_path: Path) -> None:
    source = write(
        tmp_path, EXAMPLE.replace('<box size="0.3 0.3 0.1"/>', '<mesh filename="gone.stl"/>')
    )
    assert runner.invoke(app, ["audit", str(source), "--geometry", "none"]).exit_code == 0
    result = runner.invoke(app, ["audit", str(source), "--json"])
    assert json.loads(result.output)["findings"][0]["code"] == "missing-mesh"


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["audit", "nothing.urdf"], "error: Expected a robot file, got 'nothing.urdf': no such file."),
        (["audit", "{example}", "--geometry", "both"],
         "error: Expected --geometry to be one of collision, visual, none, got 'both'."),
        (["inertia", "{bad}"], "error: Expected a finite number for `izz` of <inertia> of link 'arm'"),
        (["audit", "{example}", "--fix", "{example}"],
         "error: Expected --fix to name a new file, got the audited file itself"),
        (["audit", "{example}", "--fix", "{file}/out.urdf"], "error: Expected "),
        (["inertia", "{example}", "--joints", "elbow=1"],
         "error: Expected a joint of the robot to be one of shoulder, wrist, got 'elbow'."),
        (["inertia", "{example}", "--joints", "shoulder"],
         "error: Expected --joints NAME=VALUE, e.g. 'elbow=30 deg', got 'shoulder'."),
        (["inertia", "{example}", "--mass", "1 kg"],
         "error: Expected no --mass for a robot file, got one: its links declare their masses."),
        (["inertia", "box", "--mass", "1", "--size", "1,1,1", "--joints", "a=1"],
         "error: Expected --joints only with a robot file (.urdf, .xacro, .xml), got 'box'."),
    ],
)  # fmt: skip
def test_bad_input_is_one_line_and_exit_2(
    tmp_path: Path, arguments: list[str], message: str
) -> None:
    example = write(tmp_path)
    bad = write(tmp_path, EXAMPLE.replace('izz="0.0009"', 'izz="1.2.3"'), "bad.urdf")
    blocker = tmp_path / "blocker"
    blocker.write_text("a file", encoding="utf-8")
    values = {"example": str(example), "bad": str(bad), "file": str(blocker)}
    result = runner.invoke(app, [a.format(**values) for a in arguments])
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message.format(**values)), result.output
    assert example.read_text(encoding="utf-8") == EXAMPLE


def test_inertia_of_a_robot_at_a_pose() -> None:
    result = runner.invoke(
        app, ["inertia", str(example_path()), "--joints", "shoulder=90 deg", "--json"]
    )
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    expected = tb.robots.load(example_path()).mass_properties({"shoulder": np.pi / 2})
    assert data["mass"] == pytest.approx(6.5)
    np.testing.assert_allclose(data["center_of_mass"], expected.center_of_mass, atol=1e-15)
    np.testing.assert_allclose(data["inertia"], expected.inertia, atol=1e-15)
    assert "root link 'base'" in data["body"]


def test_inertia_of_a_xacro_robot_is_that_of_its_expansion(tmp_path: Path) -> None:
    # A xacro macro places the hand: expanded, the file is the example arm.
    macro = (
        '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:property name="reach" value="0.4"/>\n'
    )
    text = EXAMPLE.split('<robot name="arm">', 1)[1].replace(
        '<origin xyz="0 0 0.4" rpy="0 0 0"/>', '<origin xyz="0 0 ${reach}" rpy="0 0 0"/>'
    )
    assert "${reach}" in text
    source = tmp_path / "arm.urdf.xacro"
    source.write_text(macro + text, encoding="utf-8")
    result = runner.invoke(app, ["inertia", str(source), "--joints", "shoulder=90 deg", "--json"])
    assert result.exit_code == 0, result.output
    expected = tb.robots.load(example_path()).mass_properties({"shoulder": np.pi / 2})
    np.testing.assert_allclose(
        json.loads(result.output)["inertia"], expected.inertia, rtol=0, atol=1e-15
    )


def test_the_report_draws_every_link_and_lists_the_findings(tmp_path: Path) -> None:
    source = write(tmp_path, EXAMPLE.replace('izz="0.0009"', 'izz="0.9"'))
    page = tmp_path / "audit.html"
    result = runner.invoke(app, ["audit", str(source), "--report", str(page)])
    assert result.exit_code == 1, result.output
    assert f"Report: {page}" in result.output
    text = page.read_text(encoding="utf-8")
    figure = json.loads(text.split('id="tumble-robot">')[1].split("</script>")[0])
    meshes = [t for t in figure["data"] if t["type"] == "mesh3d"]
    # base and hand declared and their shapes; the arm's shapes; the arm itself a marker.
    assert len(meshes) == 5
    (marker,) = [t for t in figure["data"] if t["type"] == "scatter3d"]
    assert marker["hovertext"] == [
        "arm: no body has its tensor (triangle-inequality, power-of-ten)"
    ]
    np.testing.assert_allclose([marker["x"][0], marker["y"][0], marker["z"][0]], [0, 0, 0.3])
    assert "power-of-ten" in text and "https://" not in text.split("<script>")[0]
