"""ROS robot files as users have them: xacro files expanded, packages found by
name (given folders, parent folders, ROS_PACKAGE_PATH), and robot files that
are not regular files or not paths refused with one line.

The real files come from rtb-data (the ``robot-files`` extra): the Robotics
Toolbox's copies of ROS packages, whose folders are renamed (``kuka_kr16/`` holds
the package ``kuka_kr16_support``), and which also ship each KUKA robot already
expanded (``kr16_2.urdf``): the oracle of the expansion.
"""

from __future__ import annotations

import os
import re
import threading
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import tumble as tb
from tumble.robots import NotARobot, example_path

rtbdata = pytest.importorskip("rtbdata")
pytest.importorskip("xacro")

PACKAGES = Path(rtbdata.__file__).parent / "xacro"
KR16 = PACKAGES / "kuka_description" / "kuka_kr16"
EXAMPLE = example_path().read_text(encoding="utf-8")

#: A xacro robot of one box link whose mass is an argument.
ARGUMENT_ROBOT = """<?xml version="1.0"?>
<robot name="box" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="mass" default="1.5"/>
  <link name="box">
    <inertial>
      <mass value="$(arg mass)"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>
    </inertial>
    <collision><geometry><box size="$(arg side) 1 1"/></geometry></collision>
  </link>
</robot>
"""


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def test_a_renamed_package_is_found_through_packages_and_its_meshes_resolve() -> None:
    # kr16_2.xacro includes $(find kuka_kr16_support)/urdf/kr16_2_macro.xacro and
    # names its meshes package://kuka_kr16_support/..., a package whose folder is
    # kuka_kr16/ in rtb-data.
    robot = tb.robots.load(KR16 / "urdf" / "kr16_2.xacro", packages={"kuka_kr16_support": KR16})
    meshes = [s.mesh for link in robot.links.values() for s in link.shapes["collision"]]
    assert len(meshes) == 7 and all(mesh is not None and mesh.is_file() for mesh in meshes)
    audit = tb.robots.audit(robot)
    assert not [f for f in audit.findings if f.code == "missing-mesh"], audit.findings
    assert len(audit.links) == 9


def test_the_expansion_equals_the_expanded_file_the_package_ships() -> None:
    # Oracle: rtb-data's own kr16_2.urdf, expanded by ROS's xacro when the package
    # was made, read here with ElementTree for the declared inertials, and by
    # tumble for the whole robot at a pose (the same reader on both sides: what
    # is compared is the expansion, exact text for exact text).
    expanded = tb.robots.load(KR16 / "urdf" / "kr16_2.xacro", packages={"kuka_kr16_support": KR16})
    shipped = KR16 / "urdf" / "kr16_2.urdf"
    declared: dict[str, list[float]] = {}
    for link in ElementTree.parse(shipped).getroot().findall("link"):
        inertia = link.find("inertial/inertia")
        if inertia is not None:
            declared[link.get("name", "")] = [float(inertia.get(k, "0")) for k in
                                          ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]  # fmt: skip
    assert len(declared) == 7
    for name, values in declared.items():
        inertial = expanded.links[name].inertial
        assert inertial is not None and list(inertial.values) == values
    reference = tb.robots.load(shipped)
    pose = {name: 0.08 * (k + 1) for k, name in enumerate(sorted(reference.joints))
            if reference.joints[name].kind == "revolute"}  # fmt: skip
    a, b = expanded.mass_properties(pose), reference.mass_properties(pose)
    # the same numbers through the same arithmetic: equal to the last bits
    assert_allclose(a.center_of_mass, b.center_of_mass, rtol=0, atol=1e-15)
    assert_allclose(a.inertia, b.inertia, rtol=0, atol=1e-15)


def test_without_the_package_the_error_names_it() -> None:
    with pytest.raises(
        tb.InputError,
        match=r"^Expected ROS package 'kuka_kr16_support', which '.*kr16_2\.xacro' names in "
        r"\$\(find kuka_kr16_support\), to be found, got none beside the file or in "
        r"ROS_PACKAGE_PATH \(give its folder: --package kuka_kr16_support=DIR",
    ):
        tb.robots.load(KR16 / "urdf" / "kr16_2.xacro")


def test_ros_package_path_finds_packages_for_find_and_meshes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "kuka_kr16_support").symlink_to(KR16, target_is_directory=True)
    monkeypatch.setenv(
        "ROS_PACKAGE_PATH", os.pathsep.join(["", str(tmp_path / "none"), str(tmp_path)])
    )
    robot = tb.robots.load(KR16 / "urdf" / "kr16_2.xacro")
    meshes = [s.mesh for link in robot.links.values() for s in link.shapes["collision"]]
    assert len(meshes) == 7 and all(mesh is not None and mesh.is_file() for mesh in meshes)


def test_a_package_named_by_its_parent_folder_needs_no_mapping() -> None:
    # px100.urdf.xacro lives in trossen_descriptions/urdf/ and names
    # $(find trossen_descriptions): the parent folder of that name.
    robot = tb.robots.load(PACKAGES / "trossen_descriptions" / "urdf" / "px100.urdf.xacro")
    assert len(robot.links) == 12
    assert all(link.inertial is not None for link in robot.links.values())


def test_xacro_arguments_take_their_values_and_defaults(tmp_path: Path) -> None:
    path = write(tmp_path, "box.urdf.xacro", ARGUMENT_ROBOT)
    robot = tb.robots.load(path, xacro_args={"mass": "2.5", "side": 2})
    assert robot.links["box"].inertial.mass == 2.5  # type: ignore[union-attr]
    assert robot.links["box"].shapes["collision"][0].size == (2.0, 1.0, 1.0)
    assert tb.robots.load(path, xacro_args={"side": "1"}).links["box"].inertial.mass == 1.5  # type: ignore[union-attr]
    with pytest.raises(
        tb.InputError,
        match=r"^Expected a value for xacro argument 'side' of '.*box\.urdf\.xacro' "
        r"\(--xacro-arg side=VALUE\), got none\.$",
    ):
        tb.robots.load(path)


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ("mass=1", r"^Expected xacro arguments as a mapping of names to values, got 'mass=1'\.$"),
        ({"": "1"}, r"^Expected a xacro argument name, got ''\.$"),
        ({"mass": None}, r"^Expected a text value for xacro argument 'mass', got None\.$"),
    ],
)
def test_bad_xacro_arguments_are_refused(tmp_path: Path, arguments: object, message: str) -> None:
    path = write(tmp_path, "box.urdf.xacro", ARGUMENT_ROBOT)
    with pytest.raises(tb.InputError, match=message):
        tb.robots.load(path, xacro_args=arguments)  # type: ignore[arg-type]


def test_xacro_arguments_and_packages_only_where_they_mean_something(tmp_path: Path) -> None:
    with pytest.raises(
        tb.InputError,
        match=r"^Expected xacro arguments only for a xacro file, got '.*arm\.urdf', a URDF file\.$",
    ):
        tb.robots.load(example_path(), xacro_args={"x": "1"})
    model = write(tmp_path, "model.xml", "<mujoco/>")
    with pytest.raises(tb.InputError, match=r"^Expected ROS packages only for a URDF or xacro"):
        tb.robots.load(model, packages={"p": tmp_path})
    with pytest.raises(
        tb.InputError, match=r"^Expected the folder of ROS package 'p', got '.*gone': no such"
    ):
        tb.robots.load(example_path(), packages={"p": tmp_path / "gone"})
    with pytest.raises(
        tb.InputError, match=r"^Expected the folder of ROS package 'p', got '.*model\.xml': not a"
    ):
        tb.robots.load(example_path(), packages={"p": model})
    with pytest.raises(tb.InputError, match=r"^Expected a ROS package name, got 'a/b'\.$"):
        tb.robots.load(example_path(), packages={"a/b": tmp_path})


def test_errors_of_xacro_are_one_line_naming_the_file(tmp_path: Path) -> None:
    bad = write(tmp_path, "bad.urdf.xacro", EXAMPLE.replace('izz="0.0009"', 'izz="${0.9*deg}"'))
    with pytest.raises(
        tb.InputError,
        match=r"^Expected '.*bad\.urdf\.xacro' to expand with xacro, got: name 'deg' is not "
        r"defined when evaluating expression '0\.9\*deg'\.$",
    ):
        tb.robots.load(bad)
    cut = write(tmp_path, "cut.xacro", EXAMPLE[:300])
    with pytest.raises(tb.InputError, match=r"^Expected '.*cut\.xacro' to be well-formed XML, got"):
        tb.robots.load(cut)
    including = write(
        tmp_path, "top.urdf.xacro",
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="part.xacro"/></robot>',
    )  # fmt: skip
    write(tmp_path, "part.xacro", "<robot><link name='a'></robot>")
    with pytest.raises(
        tb.InputError,
        match=r"^Expected '.*part\.xacro', which '.*top\.urdf\.xacro' includes, to be "
        r"well-formed XML, got mismatched tag",
    ):
        tb.robots.load(including)
    (tmp_path / "part.xacro").unlink()
    with pytest.raises(
        tb.InputError,
        match=r"^Expected '.*top\.urdf\.xacro' to expand with xacro, got: No such file to "
        r"include: .*part\.xacro\.$",
    ):
        tb.robots.load(including)
    for error in (bad, cut, including):
        with pytest.raises(tb.InputError) as caught:
            tb.robots.load(error)
        assert "\n" not in str(caught.value)


def test_an_included_fifo_is_refused_without_waiting(tmp_path: Path) -> None:
    including = write(
        tmp_path, "top.urdf.xacro",
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="part.xacro"/></robot>',
    )  # fmt: skip
    os.mkfifo(tmp_path / "part.xacro")
    with pytest.raises(
        tb.InputError,
        match=r"^Expected '.*top\.urdf\.xacro' to expand with xacro, got: Expected a file to "
        r"include, got '.*part\.xacro', which is not a regular file \(a FIFO\)\.$",
    ):
        tb.robots.load(including)


def test_a_file_of_macros_is_no_robot(tmp_path: Path) -> None:
    macros = write(
        tmp_path, "arm_macro.xacro",
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="arm" params="">'
        '<link name="a"/></xacro:macro></robot>',
    )  # fmt: skip
    with pytest.raises(
        NotARobot, match=r"^Expected a robot with links in '.*arm_macro\.xacro' after xacro, got "
        r"a robot of no link \(a file of macros, meant to be included by others\)\.$",
    ):  # fmt: skip
        tb.robots.load(macros)
    assert issubclass(NotARobot, tb.InputError)


def test_a_plain_urdf_named_xacro_expands_to_itself(tmp_path: Path) -> None:
    path = write(tmp_path, "arm.urdf.xacro", EXAMPLE)
    expanded, plain = tb.robots.load(path), tb.robots.load(example_path())
    assert sorted(expanded.links) == sorted(plain.links)
    assert_allclose(expanded.mass_properties().inertia, plain.mass_properties().inertia, atol=0)


def test_expansions_in_threads_do_not_mix(tmp_path: Path) -> None:
    # xacro keeps an expansion's state in module globals: expansions take turns.
    path = write(tmp_path, "box.urdf.xacro", ARGUMENT_ROBOT)
    masses: dict[int, float] = {}

    def expand(k: int) -> None:
        robot = tb.robots.load(path, xacro_args={"mass": str(k + 1), "side": "1"})
        masses[k] = robot.links["box"].inertial.mass  # type: ignore[union-attr]

    threads = [threading.Thread(target=expand, args=(k,)) for k in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert masses == {k: float(k + 1) for k in range(8)}
    from xacro import substitution_args  # type: ignore[import-untyped]

    assert substitution_args._eval_find.__module__ == "xacro.substitution_args"


@pytest.mark.parametrize(
    ("given", "message"),
    [
        (None, r"^Expected a robot file's path \(str or os\.PathLike\), got None\.$"),
        (3, r"^Expected a robot file's path \(str or os\.PathLike\), got 3 \(int\)\.$"),
        (b"<robot/>", r"^Expected a robot file's path \(str or os\.PathLike\), got bytes "
                      r"b'<robot/>' \(write the robot to a file and pass its path\)\.$"),
        ("/dev/zero", r"^Expected a robot file, got '/dev/zero', which is not a regular file "
                      r"\(a character device\)\.$"),
    ],
)  # fmt: skip
def test_what_is_no_robot_file_is_named(given: object, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.robots.load(given)


def test_a_fifo_and_a_folder_are_named_for_what_they_are(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "robot.urdf")
    with pytest.raises(
        tb.InputError,
        match=r"^Expected a robot file, got '.*robot\.urdf', which is not a regular file "
        r"\(a FIFO\)\.$",
    ):
        tb.robots.load(tmp_path / "robot.urdf")
    (tmp_path / "folder.urdf").mkdir()
    with pytest.raises(tb.InputError, match=r"which is not a regular file \(a folder\)\.$"):
        tb.robots.load(tmp_path / "folder.urdf")


def test_robot_files_lists_robots_and_mujoco_models_only(tmp_path: Path) -> None:
    write(tmp_path, "b/arm.urdf", EXAMPLE)
    write(tmp_path, "a/arm.urdf.xacro", EXAMPLE)
    write(tmp_path, "a/model.xml", "<!-- a model -->\n<mujoco model='m'/>")
    write(tmp_path, "a/package.xml", "<package><name>a</name></package>")
    write(tmp_path, "a/notes.txt", "no robot")
    found = [p.relative_to(tmp_path).as_posix() for p in tb.robots.robot_files(tmp_path)]
    assert found == ["a/arm.urdf.xacro", "a/model.xml", "b/arm.urdf"]
    with pytest.raises(
        tb.InputError, match=r"^Expected a folder of robot files, got '.*arm\.urdf'"
    ):
        list(tb.robots.robot_files(tmp_path / "b" / "arm.urdf"))


def test_the_sources_of_a_xacro_file_are_it_and_its_includes(tmp_path: Path) -> None:
    from tumble.robots.load import read_robot

    write(tmp_path, "parts/arm.xacro", EXAMPLE.replace('<?xml version="1.0"?>', ""))
    top = write(
        tmp_path, "top.urdf.xacro",
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="parts/arm.xacro"/></robot>',
    )  # fmt: skip
    loaded = read_robot(top)
    assert [p.resolve() for p in loaded.sources] == [top, (tmp_path / "parts" / "arm.xacro")]
    assert np.isclose(loaded.robot.mass_properties().mass, 6.5)


def test_lines_named_in_a_xacro_file_are_lines_of_its_expansion(tmp_path: Path) -> None:
    from tumble.robots.ros import expand_xacro

    malformed = EXAMPLE.replace('<origin xyz="0 0 0.4"', '<origin xyz="0 0 x"')
    path = write(tmp_path, "t.urdf.xacro", malformed)
    (notice,) = tb.robots.load(path).notices
    found = re.match(
        r"^Line (\d+) of the xacro expansion: `xyz` of <origin> of joint 'wrist'", notice.message
    )
    assert found, notice.message
    # The line named is the expansion's line that holds the element, and the
    # expansion has one element a line: the number names one element.
    lines = expand_xacro(path).data.decode().splitlines()
    assert "<origin" in lines[int(found.group(1)) - 1]
    assert 'xyz="0 0 x"' in lines[int(found.group(1)) - 1]
    assert sum("<" in line for line in lines[2:]) >= 40
    # A URDF file's own lines are named as they are.
    (plain,) = tb.robots.load(write(tmp_path, "t.urdf", malformed)).notices
    line = malformed[: malformed.index("0 0 x")].count("\n") + 1
    assert plain.message.startswith(f"Line {line}: ")


def test_the_xacro_internals_replaced_are_there(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import xacro

    from tumble.robots.ros import missing_xacro_internals

    missing = missing_xacro_internals()
    assert not missing, (
        f"the installed xacro lacks {missing}, which tumble.robots.ros reads or replaces to "
        "expand files: adapt ros.py to this xacro version, or pin the robots extra below it"
    )
    monkeypatch.delattr(xacro, "filestack")
    with pytest.raises(
        tb.InputError,
        match=r"^Expected a xacro version that tumble supports \(the `robots` extra's pin\) to "
        r"expand '.*arm\.urdf\.xacro', got xacro \S+ without xacro\.filestack: pip install",
    ):
        tb.robots.load(write(tmp_path, "arm.urdf.xacro", EXAMPLE))
