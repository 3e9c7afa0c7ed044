"""Reading URDF files as users have them: numbers as urdfdom reads them inside the
inertials and as PyBullet reads them elsewhere, joints that make no tree, mimic
joints in any order, joint limits, and values that overflow float64."""

from __future__ import annotations

import math
import os
import warnings
from collections import Counter
from pathlib import Path

import numpy as np
import pybullet_data
import pytest
from numpy.testing import assert_allclose

import tumble as tb
from robot_files import EXAMPLE, robot_file, slipped
from tumble.errors import JointLimitWarning
from tumble.robots import example_path
from tumble.robots.model import rotation_about, rotation_from_rpy
from tumble.robots.urdf import read_urdf, resolve_mesh, urdf_number

PYBULLET = Path(pybullet_data.getDataPath())


def codes(audit: tb.robots.Audit) -> Counter[str]:
    return Counter(finding.code for finding in audit.findings)


# ------------------------------------------------------------------ real files PyBullet reads
@pytest.mark.parametrize(
    ("name", "links", "inertials", "lines"),
    [
        ("bicycle/bike.urdf", 4, 4, [103, 136]),
        ("quadruped/microtaur/microtaur.urdf", 26, 26, [300, 336, 372, 409, 552, 717, 885, 1050]),
        ("racecar/racecar_differential.urdf", 21, 21, [16, 23]),
        ("husky/husky.urdf", 11, 5, [97, 97]),
    ],
)
def test_pybullet_files_with_malformed_numbers_have_every_inertial_judged(
    name: str, links: int, inertials: int, lines: list[int]
) -> None:
    audit = tb.robots.audit(PYBULLET / name, geometry="none")
    assert len(audit.robot.links) == links
    assert sum(link.inertial is not None for link in audit.robot.links.values()) == inertials
    assert len(audit.links) == links
    malformed = [f for f in audit.findings if f.code == "malformed-number"]
    assert "unreadable-inertial" not in codes(audit)
    assert sorted(int(f.message.split(":")[0].removeprefix("Line ")) for f in malformed) == lines
    assert all("urdfdom refuses" in f.message and "PyBullet" in f.message for f in malformed)


def test_the_numbers_pybullet_reads_are_read_as_pybullet_reads_them() -> None:
    bike = read_urdf(PYBULLET / "bicycle/bike.urdf")
    (message,) = [n.message for n in bike.notices if n.line == 103]
    assert (
        "'0.07, 0, -0.69'" in message
        and "PyBullet reads 0.07 0 -0.69, and so does tumble" in message
    )
    assert_allclose(bike.joints["handlebar_to_frontwheel"].translation, [0.07, 0, -0.69])
    microtaur = read_urdf(PYBULLET / "quadruped/microtaur/microtaur.urdf")
    # PyBullet takes the first three of four numbers: R = Rz(0) Ry(1.57079) Rx(-3.14159).
    assert_allclose(
        microtaur.joints["dynamixel7_chassis_left"].rotation,
        rotation_from_rpy((-3.14159, 1.57079, 0.0)),
    )
    racecar = read_urdf(PYBULLET / "racecar/racecar_differential.urdf")
    assert racecar.links["chassis"].shapes["visual"][0].scale == (1.0, 1.0, 1.0)


@pytest.mark.parametrize("name", ["bicycle/bike.urdf", "quadruped/microtaur/microtaur.urdf"])
def test_the_whole_robot_matches_pybullet_on_the_same_file(name: str) -> None:
    pybullet = pytest.importorskip("pybullet")
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(PYBULLET / name), flags=pybullet.URDF_USE_INERTIA_FROM_FILE)
        masses = [pybullet.getDynamicsInfo(body, -1)[0]]
        centres = [pybullet.getBasePositionAndOrientation(body)[0]]
        for index in range(pybullet.getNumJoints(body)):
            masses.append(pybullet.getDynamicsInfo(body, index)[0])
            centres.append(pybullet.getLinkState(body, index, computeForwardKinematics=True)[0])
    finally:
        pybullet.disconnect(client)
    mass = np.array(masses)
    centre = mass @ np.array(centres) / mass.sum()
    whole = tb.robots.load(PYBULLET / name).mass_properties()
    assert whole.mass == pytest.approx(mass.sum(), rel=1e-12)
    # PyBullet keeps the numbers of origins in float32: 1e-7 of the 1 m size.
    assert_allclose(whole.center_of_mass, centre, atol=1e-6)


def test_a_joint_whose_placement_means_nothing_is_refused_only_where_needed(
    tmp_path: Path,
) -> None:
    husky = tb.robots.load(PYBULLET / "husky/husky.urdf")
    assert husky.joints["imu_joint"].unread
    assert husky.mass_properties().mass > 0  # nothing with mass beyond the IMU joint
    text = EXAMPLE.replace('<origin xyz="0 0 0.4" rpy="0 0 0"/>', '<origin xyz="$(arg x) 0 0.4"/>')
    robot = tb.robots.load(robot_file(tmp_path, text))
    (notice,) = robot.notices
    assert notice.code == "malformed-number" and notice.link == "wrist"
    assert "tumble reads the default 0 0 0" in notice.message
    with pytest.raises(
        tb.InputError,
        match=r"^Expected 3 finite numbers for `xyz` of <origin> of joint 'wrist' \(arm\.urdf line "
        r"\d+\), got '\$\(arg x\) 0 0\.4' \(a xacro expression: run xacro on the file first\); "
        r"link 'hand' beyond it has mass, so its pose is unknown\.$",
    ):
        robot.mass_properties()


def test_a_malformed_shape_size_leaves_the_shape_out(tmp_path: Path) -> None:
    path = slipped(tmp_path, '<box size="0.3 0.3 0.1"/>', '<box size="0.3 0.3"/>')
    audit = tb.robots.audit(path)
    assert codes(audit)["malformed-number"] == 1
    assert "PyBullet refuses it; tumble leaves the shape out" in audit.findings[0].message
    assert audit.robot.links["base"].shapes["collision"] == ()


# ------------------------------------------------------------------ numbers as urdfdom reads them
@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("1e-3", 1e-3),
        ("-.5", -0.5),
        ("2.", 2.0),
        (" 1", 1.0),  # the stream skips leading spaces
        ("1_0e-3", None),  # Python's float() takes underscores
        ("١e-2", None),  # and digits of other scripts
        ("1 ", None),  # the whole text must be a number
        ("inf", None),
        ("nan", None),
        ("0x10", None),
        ("1e", None),
        ("1e400", None),
        ("", None),
    ],
)
def test_numbers_are_read_as_urdfdom_reads_them(text: str, value: float | None) -> None:
    assert urdf_number(text) == value


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('izz="0.0009"', 'izz="1_0e-3"', r"got '1_0e-3'"),
        ('izz="0.0009"', 'izz="١e-2"', r"got '١e-2'"),
        ('izz="0.0009"', "", r"^Expected a `izz` attribute on <inertia> of link 'arm'"),
        ('<mass value="2.0"/>', "", r"^Expected a <mass> in the <inertial> of link 'arm'"),
        ('<origin xyz="0 0 0.2" rpy="0 0 0"/>\n      <mass', '<origin xyz="0,0,0.2"/>\n      <mass',
         r"`xyz` of <origin> of link 'arm'"),
    ],
)  # fmt: skip
def test_an_inertial_urdfdom_refuses_is_an_error_and_not_judged(
    tmp_path: Path, old: str, new: str, message: str
) -> None:
    path = slipped(tmp_path, old, new)
    audit = tb.robots.audit(path, geometry="none")
    assert [(f.link, f.code, f.severity) for f in audit.findings] == [
        ("arm", "unreadable-inertial", "error")
    ]
    assert "urdfdom refuses the file, and the inertial is not judged" in audit.findings[0].message
    robot = audit.robot
    assert robot.links["arm"].inertial is None
    with pytest.raises(tb.InputError, match=message):
        robot.mass_properties()


def test_an_unknown_shape_is_a_notice(tmp_path: Path) -> None:
    path = slipped(tmp_path, '<sphere radius="0.05"/>', '<cone radius="0.05" length="0.1"/>')
    robot = tb.robots.load(path)
    (notice,) = robot.notices
    assert (notice.link, notice.code) == ("hand", "unknown-geometry")
    assert "<cone>" in notice.message and "left out of its geometry" in notice.message
    assert robot.links["hand"].shapes["collision"] == ()


# ------------------------------------------------------------------ joints
CHAIN = """<robot name="chain">
  <link name="base"><inertial><mass value="1"/>
    <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial></link>
  <link name="a"><inertial><mass value="1"/>
    <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial></link>
  <link name="b"><inertial><mass value="1"/>
    <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial></link>
  <link name="c"><inertial><origin xyz="1 0 0"/><mass value="1"/>
    <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial></link>
{joints}
</robot>
"""
JOINTS = {
    "ja": '<joint name="ja" type="continuous"><parent link="base"/><child link="a"/>'
    '<origin xyz="1 0 0"/><axis xyz="0 0 1"/></joint>',
    "jb": '<joint name="jb" type="continuous"><parent link="a"/><child link="b"/>'
    '<origin xyz="1 0 0"/><axis xyz="0 0 1"/><mimic joint="ja" multiplier="2"/></joint>',
    "jc": '<joint name="jc" type="continuous"><parent link="b"/><child link="c"/>'
    '<origin xyz="1 0 0"/><axis xyz="0 0 1"/>'
    '<mimic joint="jb" multiplier="0.5" offset="0.1"/></joint>',
}


def chain(tmp_path: Path, order: str, name: str = "chain.urdf", **changed: str) -> Path:
    joints = {**JOINTS, **changed}
    text = CHAIN.format(joints="\n".join(joints[n] for n in order.split()))
    return robot_file(tmp_path, text, name)


def test_mimic_joints_follow_their_sources_whatever_the_file_order(tmp_path: Path) -> None:
    angle = 0.3
    backwards = tb.robots.load(chain(tmp_path, "jc jb ja")).mass_properties({"ja": angle})
    forwards = tb.robots.load(chain(tmp_path, "ja jb jc", "f.urdf")).mass_properties({"ja": angle})

    # By hand: ja = t, jb = 2t, jc = 0.5 jb + 0.1; each joint 1 m along x of its
    # parent, turning about z; each link's mass at its frame's origin but c's,
    # 1 m along x of c's frame: where it lies depends on jc, and so on the order
    # in which the mimic joints are computed (jc before jb would read jb as 0).
    def turned(theta: float) -> np.ndarray:
        return np.array([math.cos(theta), math.sin(theta), 0.0])

    a = np.array([1.0, 0, 0])
    b = a + turned(angle)
    c = b + turned(angle + 2 * angle)
    jc = 0.5 * (2 * angle) + 0.1
    c_mass = c + turned(angle + 2 * angle + jc)
    expected = (np.zeros(3) + a + b + c_mass) / 4
    # Sums of four unit-size terms: round-off near 1e-16.
    assert_allclose(backwards.center_of_mass, expected, atol=1e-12)
    assert_allclose(backwards.center_of_mass, forwards.center_of_mass, atol=1e-12)
    assert_allclose(backwards.inertia, forwards.inertia, atol=1e-12)


@pytest.mark.parametrize(
    ("changed", "cycle"),
    [
        ({"ja": JOINTS["ja"].replace("</joint>", '<mimic joint="jc"/></joint>')},
         "'ja' -> 'jc' -> 'jb' -> 'ja'"),
        ({"jb": JOINTS["jb"].replace('joint="ja"', 'joint="jb"')}, "'jb' -> 'jb'"),
    ],
)  # fmt: skip
def test_mimic_cycles_are_notices_and_refused_in_poses(
    tmp_path: Path, changed: dict[str, str], cycle: str
) -> None:
    robot = tb.robots.load(chain(tmp_path, "ja jb jc", **changed))
    notices = [n for n in robot.notices if n.code == "invalid-joint"]
    assert len(notices) == 1 and cycle.split(" -> ")[0] in notices[0].message
    with pytest.raises(
        tb.InputError,
        match=rf"^Expected mimic joints that follow a joint that moves, got a cycle: {cycle}\.$",
    ):
        robot.mass_properties()


def test_a_duplicate_joint_name_and_a_link_with_two_parents_are_notices(tmp_path: Path) -> None:
    twice = JOINTS["jb"] + JOINTS["jc"].replace('name="jc"', 'name="jb"')
    # The second 'jb' is left out (urdfdom refuses the file): link 'c' hangs on nothing.
    robot = tb.robots.load(chain(tmp_path, "ja jb", jb=twice))
    assert [n.code for n in robot.notices] == ["invalid-joint", "invalid-joint"]
    assert "got two (lines" in robot.notices[0].message
    with pytest.raises(tb.InputError, match=r"^Expected one joint named 'jb' in chain\.urdf"):
        robot.mass_properties()
    # An invalid inertia is still judged.
    two_parents = EXAMPLE.replace('<child link="hand"/>', '<child link="arm"/>').replace(
        'izz="0.0009"', 'izz="0.09"'
    )
    audit = tb.robots.audit(robot_file(tmp_path, two_parents, "two.urdf"), geometry="none")
    assert codes(audit)["invalid-joint"] == 2  # 'arm' twice a child; 'hand' joined to nothing
    assert ("arm", "triangle-inequality") in [(f.link, f.code) for f in audit.findings]
    with pytest.raises(
        tb.InputError,
        match=r"^Expected a tree of links in two\.urdf, got link 'arm' as the child of two joints",
    ):
        audit.robot.mass_properties()


def test_a_cycle_of_joints_is_a_notice(tmp_path: Path) -> None:
    text = EXAMPLE.replace(
        "</robot>",
        '  <joint name="back" type="fixed">\n    <parent link="hand"/>\n'
        '    <child link="base"/>\n  </joint>\n</robot>',
    )
    robot = tb.robots.load(robot_file(tmp_path, text))
    assert {n.code for n in robot.notices} == {"invalid-joint"}
    with pytest.raises(tb.InputError, match=r"^Expected a tree of links in arm\.urdf, got a cycle"):
        robot.mass_properties()


def test_a_joint_value_outside_its_limits_is_used_with_a_warning() -> None:
    robot = tb.robots.load(example_path())
    assert robot.joints["shoulder"].limits == (-1.57, 1.57)
    with pytest.warns(
        JointLimitWarning,
        match=r"^Joint 'shoulder' at 2 rad is outside its limits \[-1\.57, 1\.57\] rad: used",
    ):
        beyond = robot.mass_properties({"shoulder": 2.0})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        within = robot.mass_properties({"shoulder": 1.0})
        # 1.57 as written is π/2 to its three digits: 90° is within it.
        robot.mass_properties({"shoulder": "90 deg"})
    with pytest.warns(JointLimitWarning, match=r"at 1\.576 rad is outside"):
        robot.mass_properties({"shoulder": 1.576})
    assert not np.allclose(beyond.center_of_mass, within.center_of_mass)


def test_a_mimic_joint_outside_its_limits_names_its_source_and_the_unit(tmp_path: Path) -> None:
    limited = (
        JOINTS["jb"]
        .replace('type="continuous"', 'type="revolute"')
        .replace("</joint>", '<limit lower="-0.5" upper="0.5" effort="1" velocity="1"/></joint>')
    )
    sliding = (
        JOINTS["jc"]
        .replace('type="continuous"', 'type="prismatic"')
        .replace("</joint>", '<limit lower="0" upper="0.2" effort="1" velocity="1"/></joint>')
    )
    robot = tb.robots.load(chain(tmp_path, "ja jb jc", jb=limited, jc=sliding))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot.mass_properties({"ja": 0.3})  # jb = 0.6 rad, jc = 0.5 × 0.6 + 0.1 = 0.4 m
    assert [str(w.message) for w in caught] == [
        "Joint 'jb' (mimicking 'ja') at 0.6 rad is outside its limits [-0.5, 0.5] rad: "
        "used as given.",
        "Joint 'jc' (mimicking 'jb') at 0.4 m is outside its limits [0, 0.2] m: used as given.",
    ]


def test_names_with_quotes_and_spaces_are_kept_whole_in_notices(tmp_path: Path) -> None:
    # Notices name their link or joint; a name is never recovered from a message.
    text = (
        EXAMPLE.replace('"hand"', '"o\'clock hand"')
        .replace('name="wrist"', 'name="wrist &quot;2&quot;"')
        .replace('<sphere radius="0.05"/>', '<cone radius="0.05"/>')
        .replace('<origin xyz="0 0 0.4"', '<origin xyz="0 0 x"')
    )
    robot = tb.robots.load(robot_file(tmp_path, text))
    assert sorted((notice.link, notice.code) for notice in robot.notices) == [
        ("o'clock hand", "unknown-geometry"),
        ('wrist "2"', "malformed-number"),
    ]


# ------------------------------------------------------------------ library errors
def test_joints_not_a_mapping_and_a_mass_with_units(tmp_path: Path) -> None:
    robot = tb.robots.load(example_path())
    with pytest.raises(tb.InputError, match=r"^Expected `joints` to be a mapping of joint names"):
        robot.mass_properties([1.0])  # type: ignore[arg-type]
    arm = robot.links["arm"]
    assert_allclose(arm.geometry(mass="2 kg").inertia, arm.geometry(mass=2.0).inertia, rtol=1e-15)
    with pytest.raises(tb.InputError, match=r"^Expected `mass` to be a mass in kg, got 2 m"):
        arm.geometry(mass="2 m")


def test_shapes_and_tensors_beyond_float64_do_not_raise_overflow(tmp_path: Path) -> None:
    path = slipped(tmp_path, '<sphere radius="0.05"/>', '<sphere radius="1e200"/>')
    robot = tb.robots.load(path)
    with pytest.raises(
        tb.InputError,
        match=r"^Expected a sphere small enough for its volume and inertia to be finite in "
        r"float64, got size 1e\+200 m\.$",
    ):
        robot.links["hand"].geometry()
    huge = slipped(
        tmp_path,
        '<inertia ixx="0.0005" ixy="0" ixz="0" iyy="0.0005" iyz="0" izz="0.0005"/>',
        '<origin rpy="0.3 0.2 0.1"/><inertia ixx="1.7e308" ixy="1.7e308" ixz="0" '
        'iyy="1.7e308" iyz="0" izz="1.7e308"/>',
        "huge.urdf",
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inertia = tb.robots.load(huge).links["hand"].inertia
    assert not np.all(np.isfinite(inertia))


# ------------------------------------------------------------------ rotations
def test_rpy_is_fixed_axis_roll_pitch_yaw() -> None:
    def by_hand(roll: float, pitch: float, yaw: float) -> np.ndarray:
        # R = Rz(yaw) Ry(pitch) Rx(roll), multiplied out (the URDF specification).
        cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
        cy, sy = math.cos(yaw), math.sin(yaw)
        return np.array(
            [
                [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                [-sp, cp * sr, cp * cr],
            ]
        )

    for rpy in np.random.default_rng(44).uniform(-4, 4, (50, 3)):
        # Products of unit sines and cosines: round-off near 1e-16.
        assert_allclose(rotation_from_rpy(tuple(rpy)), by_hand(*rpy), atol=1e-14)
    axis, angle = np.array([1.0, 2.0, 2.0]) / 3, 0.7
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rodrigues = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
    assert_allclose(rotation_about(axis, angle), rodrigues, atol=1e-14)


# ------------------------------------------------------------------ the reader's arguments
def test_the_content_and_the_packages_can_be_given(tmp_path: Path) -> None:
    folder = tmp_path / "renamed_description"
    (folder / "meshes").mkdir(parents=True)
    (folder / "meshes" / "hand.stl").write_bytes(b"")
    text = EXAMPLE.replace(
        '<sphere radius="0.05"/>', '<mesh filename="package://hand_support/meshes/hand.stl"/>'
    )
    robot = read_urdf(
        tmp_path / "virtual.urdf",
        data=text.encode(),
        packages={"hand_support": folder},
    )
    assert robot.path == tmp_path / "virtual.urdf"
    assert robot.links["hand"].shapes["collision"][0].mesh == folder / "meshes" / "hand.stl"
    assert (
        resolve_mesh("package://other/x.stl", tmp_path / "a.urdf", {"hand_support": folder}).name
        == "x.stl"
    )


def test_a_package_mesh_is_never_taken_from_another_package(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # ROS_PACKAGE_PATH lists the folders of packages a and b; only b has the
    # mesh. package://a/... is a's file, missing, never b's.
    for package in ("a", "b"):
        (tmp_path / "workspace" / package / "meshes").mkdir(parents=True)
    (tmp_path / "workspace" / "b" / "meshes" / "base.stl").write_bytes(b"")
    monkeypatch.setenv(
        "ROS_PACKAGE_PATH",
        os.pathsep.join(str(tmp_path / "workspace" / p) for p in ("a", "b")),
    )
    urdf = tmp_path / "robot" / "r.urdf"
    found = resolve_mesh("package://a/meshes/base.stl", urdf)
    assert found == tmp_path / "workspace" / "a" / "meshes" / "base.stl"
    assert resolve_mesh("package://b/meshes/base.stl", urdf).is_file()


def test_a_mesh_of_no_package_is_found_under_a_parent_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # example-robot-data's layout: share/example-robot-data/robots/x_data/robots/x.urdf
    # names its meshes package:///example-robot-data/robots/x_data/meshes/m.stl.
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    data = tmp_path / "share" / "example-robot-data" / "robots" / "x_data"
    (data / "meshes").mkdir(parents=True)
    (data / "robots").mkdir()
    (data / "meshes" / "m.stl").write_bytes(b"")
    urdf = data / "robots" / "x.urdf"
    found = resolve_mesh("package:///example-robot-data/robots/x_data/meshes/m.stl", urdf)
    assert found == data / "meshes" / "m.stl"
    # Found nowhere: beside the URDF, for the error to name.
    assert resolve_mesh("package:///gone/m.stl", urdf) == data / "robots" / "gone" / "m.stl"
