"""``tumble audit`` on ROS files as users have them: a folder of robot files,
xacro files with ``--package`` and ``--xacro-arg``, outputs that must never
replace an input, and robot files that are not regular files."""

from __future__ import annotations

import json
import os
import struct
from importlib import metadata
from pathlib import Path

import pytest
from typer.testing import CliRunner

import tumble as tb
from tumble.cli import app
from tumble.robots import NotARobot, example_path

runner = CliRunner()

EXAMPLE = example_path().read_text(encoding="utf-8")
BAD = EXAMPLE.replace('izz="0.0009"', 'izz="0.9"')  # a slipped decimal point: 1 error
MACROS = (
    '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="arm" params="">'
    '<link name="a"/></xacro:macro></robot>'
)
MODEL = """<mujoco model="m"><worldbody><body name="b"><freejoint/>
<geom type="box" size="0.1 0.2 0.3" mass="2"/></body></worldbody></mujoco>"""


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def one_error_line(result: object) -> str:
    lines = result.output.strip().splitlines()  # type: ignore[attr-defined]
    assert result.exit_code == 2 and len(lines) == 1, result.output  # type: ignore[attr-defined]
    return lines[0]


def json_lines(output: str) -> list[dict[str, object]]:
    return [json.loads(line) for line in output.splitlines() if line.startswith("{")]


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    """Five robot files (a clean URDF, one with an error, a clean xacro robot, a
    MuJoCo model and a file of xacro macros), one that cannot be read, and files
    that are no robots."""
    write(tmp_path, "arm.urdf", EXAMPLE)
    write(tmp_path, "bad/arm.urdf", BAD)
    write(tmp_path, "ros/urdf/arm.urdf.xacro", EXAMPLE)
    write(tmp_path, "ros/urdf/arm_macro.xacro", MACROS)
    write(tmp_path, "ros/package.xml", "<package><name>ros</name></package>")
    write(tmp_path, "mjcf/model.xml", MODEL)
    write(tmp_path, "broken.urdf", EXAMPLE[:200])
    write(tmp_path, "notes.txt", "no robot here")
    return tmp_path


def test_a_folder_is_audited_file_by_file_with_a_summary(folder: Path) -> None:
    pytest.importorskip("mujoco")
    pytest.importorskip("xacro")
    result = runner.invoke(app, ["audit", str(folder), "--geometry", "none"])
    assert result.exit_code == 1, result.output  # an error, and a file that cannot be read
    output = " ".join(result.output.split())
    assert "files audited │ 4" in output
    assert "links │ 11" in output  # 3 + 3 + 3, and the model's world and body
    assert "files with errors │ 1" in output
    assert "error triangle-inequality │ 1" in output and "error power-of-ten │ 1" in output
    assert "skipped (no robot: xacro macros) │ 1" in output
    assert "could not be read │ 1" in output
    assert "bad/arm.urdf │ 2 │ power-of-ten, triangle-inequality" in output
    assert "broken.urdf │ Expected" in output and "to be well-formed XML" in output
    assert output.endswith("4 files audited: 2 errors in 1 file; 1 could not be read, 1 skipped"), (
        output
    )


def test_a_folder_with_json_gives_one_object_per_line_per_file(folder: Path) -> None:
    pytest.importorskip("mujoco")
    result = runner.invoke(app, ["audit", str(folder), "--geometry", "none", "--json"])
    assert result.exit_code == 1, result.output
    records = {Path(str(r["file"])).relative_to(folder).as_posix(): r
               for r in json_lines(result.output)}  # fmt: skip
    assert sorted(records) == [
        "arm.urdf", "bad/arm.urdf", "broken.urdf", "mjcf/model.xml",
        "ros/urdf/arm.urdf.xacro", "ros/urdf/arm_macro.xacro",
    ]  # fmt: skip
    status = {name: r["status"] for name, r in records.items()}
    assert status == {
        "arm.urdf": "audited", "bad/arm.urdf": "audited", "broken.urdf": "unreadable",
        "mjcf/model.xml": "audited", "ros/urdf/arm.urdf.xacro": "audited",
        "ros/urdf/arm_macro.xacro": "skipped",
    }  # fmt: skip
    assert records["bad/arm.urdf"]["errors"] == 2 and records["arm.urdf"]["errors"] == 0
    assert "\n" not in str(records["broken.urdf"]["reason"])


def test_a_clean_folder_exits_0(tmp_path: Path) -> None:
    write(tmp_path, "a/arm.urdf", EXAMPLE)
    write(tmp_path, "b/arm.urdf", EXAMPLE)
    result = runner.invoke(app, ["audit", str(tmp_path), "--geometry", "none"])
    assert result.exit_code == 0, result.output
    assert "2 files audited: 0 errors in 0 files; 0 could not be read, 0 skipped" in result.output


def test_a_fifo_in_a_folder_is_listed_as_unreadable_without_waiting(tmp_path: Path) -> None:
    write(tmp_path, "arm.urdf", EXAMPLE)
    os.mkfifo(tmp_path / "pipe.urdf")
    result = runner.invoke(app, ["audit", str(tmp_path), "--geometry", "none", "--json"])
    assert result.exit_code == 1, result.output
    records = json_lines(result.output)
    assert [r["status"] for r in records] == ["audited", "unreadable"]
    assert "which is not a regular file (a FIFO)." in str(records[1]["reason"])


@pytest.mark.parametrize("option", ["--fix", "--report"])
def test_fix_and_report_are_for_one_file(folder: Path, option: str) -> None:
    line = one_error_line(
        runner.invoke(app, ["audit", str(folder), option, str(folder / "out.html")])
    )
    assert line == (
        f"error: Expected {option} only with a robot file, got the folder {str(folder)!r}: "
        "audit a file alone to correct it or draw it."
    )
    assert not (folder / "out.html").exists()


def package_corpus(name: str) -> Path:
    if name == "pybullet_data":
        pybullet_data = pytest.importorskip("pybullet_data")
        return Path(pybullet_data.getDataPath())
    try:
        distribution = metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:
        pytest.skip("example-robot-data is not installed (the robot-files extra)")
    return Path(str(distribution.locate_file("cmeel.prefix/share/example-robot-data/robots")))


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:xacro, expanding")  # xacro's own remarks on a file
@pytest.mark.parametrize("name", ["pybullet_data", "example-robot-data"])
def test_a_test_package_audited_whole_counts_as_each_file_alone(
    name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A check that the folder's per-file results equal those of auditing each
    # file alone through the library (the same audit code: what is checked is
    # the folder's walk, counting and exit code, not the audit itself).
    pytest.importorskip("mujoco")
    monkeypatch.chdir(tmp_path)  # MuJoCo logs its errors to MUJOCO_LOG.TXT here
    folder = package_corpus(name)
    alone = {}
    for path in tb.robots.robot_files(folder):
        try:
            audit = tb.robots.audit(path, geometry="none")
            alone[str(path)] = ("audited", len(audit.links), len(audit.errors))
        except NotARobot:
            alone[str(path)] = ("skipped", 0, 0)
        except tb.InputError:
            alone[str(path)] = ("unreadable", 0, 0)
    result = runner.invoke(app, ["audit", str(folder), "--geometry", "none", "--json"])
    records = json_lines(result.output)
    whole = {str(r["file"]): (r["status"], r.get("links", 0), r.get("errors", 0)) for r in records}
    assert whole == alone
    assert len(whole) > (1000 if name == "pybullet_data" else 60)
    failing = any(status == "unreadable" or errors for status, _, errors in alone.values())
    assert result.exit_code == (1 if failing else 0)


# ------------------------------------------------------------------ ROS options
def test_package_and_xacro_arg_reach_the_xacro_file(tmp_path: Path) -> None:
    pytest.importorskip("xacro")
    write(tmp_path, "elsewhere/parts/arm.xacro", EXAMPLE.replace('<?xml version="1.0"?>', ""))
    top = write(
        tmp_path, "robot/top.urdf.xacro",
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:arg name="part" default="none"/>'
        '<xacro:include filename="$(find my_parts)/parts/$(arg part).xacro"/></robot>',
    )  # fmt: skip
    arguments = ["audit", str(top), "--geometry", "none"]
    line = one_error_line(runner.invoke(app, arguments))
    assert line.startswith("error: Expected ROS package 'my_parts', which ")
    given = [*arguments, "--package", f"my_parts={tmp_path / 'elsewhere'}"]
    result = runner.invoke(app, [*given, "--xacro-arg", "part:=arm"])
    assert result.exit_code == 0, result.output
    assert "r: 3 links (top.urdf.xacro)" in " ".join(result.output.split())
    result = runner.invoke(app, [*given, "--xacro-arg", "part=arm", "--xacro-arg", "part=arm"])
    assert result.exit_code == 0, result.output  # the same value twice says one thing


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--package", "my_parts"],
         "error: Expected --package NAME=DIR, e.g. 'kuka_kr16_support=kuka_kr16', got 'my_parts'."),
        (["--package", "=here"],
         "error: Expected --package NAME=DIR, e.g. 'kuka_kr16_support=kuka_kr16', got '=here'."),
        (["--package", "my_parts="],
         "error: Expected --package NAME=DIR, e.g. 'kuka_kr16_support=kuka_kr16', got 'my_parts='."),
        (["--package", "a={tmp}", "--package", "a={tmp}/robot"],
         "error: Expected one value for --package a, got two: '{tmp}' and '{tmp}/robot'."),
        (["--package", "a={tmp}/robot/top.urdf.xacro"],
         "error: Expected the folder of ROS package 'a', got '{tmp}/robot/top.urdf.xacro': not a "
         "folder."),
        (["--package", "a={tmp}/gone"],
         "error: Expected the folder of ROS package 'a', got '{tmp}/gone': no such folder."),
        (["--xacro-arg", "part"],
         "error: Expected --xacro-arg NAME=VALUE, e.g. 'prefix=left_', got 'part'."),
        (["--xacro-arg", "part=a", "--xacro-arg", "part=b"],
         "error: Expected one value for --xacro-arg part, got two: 'a' and 'b'."),
    ],
)  # fmt: skip
def test_bad_ros_options_are_one_line(tmp_path: Path, arguments: list[str], message: str) -> None:
    top = write(tmp_path, "robot/top.urdf.xacro", EXAMPLE)
    given = [a.format(tmp=tmp_path) for a in arguments]
    line = one_error_line(runner.invoke(app, ["audit", str(top), *given]))
    assert line == message.format(tmp=tmp_path)


def test_a_xacro_arg_for_a_urdf_is_refused(tmp_path: Path) -> None:
    source = write(tmp_path, "arm.urdf", EXAMPLE)
    line = one_error_line(runner.invoke(app, ["audit", str(source), "--xacro-arg", "a=1"]))
    assert line == (
        f"error: Expected xacro arguments only for a xacro file, got {str(source)!r}, a URDF file."
    )


# ------------------------------------------------- outputs that alias inputs
def test_a_report_over_the_robot_file_is_refused_and_the_file_kept(tmp_path: Path) -> None:
    source = write(tmp_path, "arm.urdf", EXAMPLE)
    line = one_error_line(runner.invoke(app, ["audit", str(source), "--report", str(source)]))
    assert line == (
        f"error: Expected --report to name a new file, got the audited file itself, "
        f"{str(source)!r}: the robot's files are never changed."
    )
    assert source.read_text(encoding="utf-8") == EXAMPLE


def test_an_output_spelled_another_way_or_linked_is_still_the_robot_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    source = write(tmp_path, "arm.urdf", EXAMPLE)
    os.link(source, tmp_path / "hard.urdf")
    (tmp_path / "soft.html").symlink_to(source)
    monkeypatch.chdir(tmp_path)
    for output in ("./arm.urdf", "sub/../arm.urdf", "hard.urdf", "soft.html"):
        (tmp_path / "sub").mkdir(exist_ok=True)
        line = one_error_line(runner.invoke(app, ["audit", "arm.urdf", "--report", output]))
        assert "got the audited file itself" in line, output
    assert source.read_text(encoding="utf-8") == EXAMPLE


def test_a_report_over_an_mjcf_model_is_refused(tmp_path: Path) -> None:
    model = write(tmp_path, "model.xml", MODEL)
    line = one_error_line(runner.invoke(app, ["audit", str(model), "--report", str(model)]))
    assert "Expected --report to name a new file, got the audited file itself" in line
    assert model.read_text(encoding="utf-8") == MODEL


def test_report_and_fix_on_one_path_are_refused_before_any_work(tmp_path: Path) -> None:
    source = write(tmp_path, "arm.urdf", BAD)
    out = tmp_path / "out.urdf"
    line = one_error_line(
        runner.invoke(app, ["audit", str(source), "--report", str(out), "--fix", str(out)])
    )
    assert line == (
        f"error: Expected --report and --fix to name two files, got {str(out)!r} for both: "
        "one would replace the other."
    )
    assert not out.exists()


def test_a_report_over_a_file_the_xacro_file_includes_is_refused(tmp_path: Path) -> None:
    pytest.importorskip("xacro")
    part = write(tmp_path, "parts/arm.xacro", EXAMPLE.replace('<?xml version="1.0"?>', ""))
    top = write(
        tmp_path, "top.urdf.xacro",
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="parts/arm.xacro"/></robot>',
    )  # fmt: skip
    line = one_error_line(runner.invoke(app, ["audit", str(top), "--report", str(part)]))
    assert line.startswith(
        f"error: Expected --report to name a new file, got a file that {str(top)!r} includes, "
    )
    assert part.read_text(encoding="utf-8") == EXAMPLE.replace('<?xml version="1.0"?>', "")


# ------------------------------------------------- robot files that are no files
def test_dev_zero_and_a_fifo_are_named_for_what_they_are(tmp_path: Path) -> None:
    line = one_error_line(runner.invoke(app, ["audit", "/dev/zero"]))
    assert line == (
        "error: Expected a robot file, got '/dev/zero', which is not a regular file "
        "(a character device)."
    )
    os.mkfifo(tmp_path / "robot.urdf")
    line = one_error_line(runner.invoke(app, ["audit", str(tmp_path / "robot.urdf")]))
    assert line.endswith("which is not a regular file (a FIFO).")


def test_an_mjcf_including_a_fifo_is_refused_without_waiting(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    write(tmp_path, "m.xml", '<mujoco><include file="f.xml"/></mujoco>')
    os.mkfifo(tmp_path / "f.xml")
    line = one_error_line(runner.invoke(app, ["audit", "m.xml"]))
    assert line == (
        "error: Expected a file for 'm.xml' to include, got 'f.xml', which is not a regular "
        "file (a FIFO)."
    )


def test_a_report_over_a_file_an_mjcf_includes_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("mujoco")
    monkeypatch.chdir(tmp_path)
    body = MODEL.replace('<mujoco model="m">', "<mujoco>")
    write(tmp_path, "m.xml", '<mujoco model="m"><include file="body.xml"/></mujoco>')
    write(tmp_path, "body.xml", body)
    line = one_error_line(runner.invoke(app, ["audit", "m.xml", "--report", "body.xml"]))
    assert line == (
        "error: Expected --report to name a new file, got a file that 'm.xml' includes, "
        "'body.xml': the robot's files are never changed."
    )
    assert (tmp_path / "body.xml").read_text(encoding="utf-8") == body


def cube_stl(side: float) -> bytes:
    """A binary STL of a closed cube of edge ``side`` (m), centred on the origin."""
    corners = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
             (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]  # fmt: skip
    data = bytearray(80) + struct.pack("<I", len(faces))
    for face in faces:
        data += struct.pack("<3f", 0, 0, 0)
        for k in face:
            data += struct.pack("<3f", *(side / 2 * c for c in corners[k]))
        data += struct.pack("<H", 0)
    return bytes(data)


def test_a_report_over_a_mesh_of_a_urdf_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    mesh = tmp_path / "hand_support" / "meshes" / "hand.stl"
    mesh.parent.mkdir(parents=True)
    mesh.write_bytes(cube_stl(0.1))
    text = EXAMPLE.replace(
        '<sphere radius="0.05"/>', '<mesh filename="package://hand_support/meshes/hand.stl"/>'
    )
    write(tmp_path, "robot/arm.urdf", text)
    arguments = ["audit", "robot/arm.urdf", "--package", "hand_support=hand_support"]
    line = one_error_line(
        runner.invoke(app, [*arguments, "--report", "robot/../hand_support/meshes/hand.stl"])
    )
    assert line.startswith(
        "error: Expected --report to name a new file, got a file that 'robot/arm.urdf' reads "
        "(a mesh...), "
    )
    assert line.endswith("hand.stl': the robot's files are never changed.")
    assert mesh.read_bytes() == cube_stl(0.1)


def test_a_report_over_a_mesh_of_an_mjcf_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("mujoco")
    monkeypatch.chdir(tmp_path)
    mesh = tmp_path / "assets" / "cube.stl"
    mesh.parent.mkdir()
    mesh.write_bytes(cube_stl(0.1))
    write(
        tmp_path, "m.xml",
        '<mujoco model="m"><compiler meshdir="assets"/><asset><mesh file="cube.stl"/></asset>'
        '<worldbody><body name="b"><freejoint/><geom type="mesh" mesh="cube"/></body>'
        "</worldbody></mujoco>",
    )  # fmt: skip
    line = one_error_line(runner.invoke(app, ["audit", "m.xml", "--report", "assets/cube.stl"]))
    assert line == (
        "error: Expected --report to name a new file, got a file that 'm.xml' reads "
        "(a mesh...), 'assets/cube.stl': the robot's files are never changed."
    )
    assert mesh.read_bytes() == cube_stl(0.1)
    # The model is audited, and its report written, where the report is a new file.
    result = runner.invoke(app, ["audit", "m.xml", "--report", "page.html"])
    assert result.exit_code == 0 and (tmp_path / "page.html").is_file(), result.output
