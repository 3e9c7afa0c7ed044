"""Robot descriptions: reading, each link's geometry, the whole robot at a pose,
the audit's findings and corrections, and the corrected copy."""

from __future__ import annotations

import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import tumble as tb
from robot_files import EXAMPLE, robot_file, slipped
from tumble.robots import example_path, write_corrected
from tumble.robots.tensors import judge_tensor


def codes(audit: tb.robots.Audit) -> list[tuple[str, str]]:
    return [(f.link, f.code) for f in audit.findings]


def changed_lines(a: Path, b: Path) -> list[str]:
    diff = subprocess.run(["diff", str(a), str(b)], capture_output=True, text=True).stdout
    return [line for line in diff.splitlines() if line[:1] in "<>"]


# ------------------------------------------------------------------ the example arm
def box_inertia(m: float, a: float, b: float, c: float) -> np.ndarray:
    return m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def cylinder_inertia(m: float, r: float, h: float) -> np.ndarray:
    t = m * (3 * r * r + h * h) / 12
    return np.diag([t, t, m * r * r / 2])


def shifted(inertia: np.ndarray, m: float, d: np.ndarray) -> np.ndarray:
    """Steiner: about a point at −d from the centre of mass."""
    return inertia + m * (d @ d * np.eye(3) - np.outer(d, d))


def test_the_example_arm_reads_as_written() -> None:
    robot = tb.robots.load(example_path())
    assert list(robot.links) == ["base", "arm", "hand"]
    assert robot.root == "base"
    assert robot.joints["shoulder"].kind == "revolute"
    assert_allclose(robot.joints["shoulder"].axis, [0, 1, 0])
    arm = robot.links["arm"]
    assert arm.mass == 2.0
    assert_allclose(arm.center_of_mass, [0, 0, 0.2])
    assert_allclose(arm.inertia, np.diag([0.0271167, 0.0271167, 0.0009]))


def test_each_link_geometry_is_its_shape_at_the_declared_mass() -> None:
    # Oracle: the textbook moments of a box, a cylinder and a sphere, written here.
    links = tb.robots.load(example_path()).links
    base = links["base"].geometry()
    assert_allclose(base.inertia, box_inertia(4.0, 0.3, 0.3, 0.1), rtol=1e-14)
    assert_allclose(base.center_of_mass, [0, 0, 0.05], atol=1e-15)
    assert_allclose(links["arm"].geometry().inertia, cylinder_inertia(2.0, 0.03, 0.4), rtol=1e-14)
    assert_allclose(links["hand"].geometry().inertia, 0.4 * 0.5 * 0.05**2 * np.eye(3), rtol=1e-14)
    assert links["arm"].volume() == pytest.approx(math.pi * 0.03**2 * 0.4, rel=1e-14)
    # At another mass, in proportion.
    assert_allclose(links["arm"].geometry(mass=4.0).inertia, cylinder_inertia(4.0, 0.03, 0.4))


def test_two_shapes_share_the_mass_in_proportion_to_their_volumes(tmp_path: Path) -> None:
    # Two equal boxes side by side weigh as one box twice as long.
    text = EXAMPLE.replace(
        '<geometry><box size="0.3 0.3 0.1"/></geometry>\n    </collision>',
        '<geometry><box size="0.15 0.3 0.1"/></geometry>\n    </collision>',
    ).replace(
        '    <collision>\n      <origin xyz="0 0 0.05" rpy="0 0 0"/>',
        '    <collision>\n      <origin xyz="-0.075 0 0.05" rpy="0 0 0"/>'
        '\n      <geometry><box size="0.15 0.3 0.1"/></geometry>\n    </collision>'
        '\n    <collision>\n      <origin xyz="0.075 0 0.05" rpy="0 0 0"/>',
        1,
    )
    geometry = tb.robots.load(robot_file(tmp_path, text)).links["base"].geometry()
    assert_allclose(geometry.inertia, box_inertia(4.0, 0.3, 0.3, 0.1), rtol=1e-13)


def test_the_whole_arm_at_zero_and_at_a_pose_is_its_links_placed_by_hand() -> None:
    # Oracle: the three declared links placed by hand (shoulder 0.1 m up, hand 0.4 m
    # along the arm) with Steiner's theorem, independently of the joint code.
    robot = tb.robots.load(example_path())
    masses = [4.0, 2.0, 0.5]
    own = [np.diag([0.0333333, 0.0333333, 0.06]), np.diag([0.0271167, 0.0271167, 0.0009]),
           0.0005 * np.eye(3)]  # fmt: skip
    for angle in (0.0, 0.7, -math.pi / 2):
        c, s = math.cos(angle), math.sin(angle)
        turn = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])  # about y
        centres = [np.array([0, 0, 0.05]), np.array([0, 0, 0.1]) + turn @ [0, 0, 0.2],
                   np.array([0, 0, 0.1]) + turn @ [0, 0, 0.4]]  # fmt: skip
        tensors = [own[0], turn @ own[1] @ turn.T, own[2]]
        mass = sum(masses)
        com = sum(m * x for m, x in zip(masses, centres, strict=True)) / mass
        inertia = sum(
            shifted(t, m, x - com) for t, m, x in zip(tensors, masses, centres, strict=True)
        )
        whole = robot.mass_properties({"shoulder": angle})
        assert whole.mass == pytest.approx(mass)
        assert_allclose(whole.center_of_mass, com, atol=1e-15)
        assert_allclose(whole.inertia, inertia, rtol=1e-13, atol=1e-16)
    degrees = robot.mass_properties({"shoulder": "-90 deg"})
    assert_allclose(degrees.inertia, robot.mass_properties({"shoulder": -math.pi / 2}).inertia)


def test_a_prismatic_and_a_mimic_joint_move_their_links(tmp_path: Path) -> None:
    text = EXAMPLE.replace(
        '<joint name="wrist" type="fixed">',
        '<joint name="wrist" type="prismatic">\n    <axis xyz="0 0 1"/>\n'
        '    <mimic joint="shoulder" multiplier="0.1" offset="0.05"/>',
    )
    robot = tb.robots.load(robot_file(tmp_path, text))
    poses = robot.link_poses({"shoulder": 0.0})
    assert_allclose(poses["hand"][1], [0, 0, 0.1 + 0.4 + 0.05])
    poses = robot.link_poses({"shoulder": 1.0})
    # The hand slides 0.15 m along the turned arm.
    turn = np.array([[math.cos(1), 0, math.sin(1)], [0, 1, 0], [-math.sin(1), 0, math.cos(1)]])
    assert_allclose(poses["hand"][1], [0, 0, 0.1] + turn @ [0, 0, 0.55], atol=1e-15)
    with pytest.raises(tb.InputError, match=r"got 'wrist', a mimic joint\.$"):
        robot.mass_properties({"wrist": 0.1})


# ------------------------------------------------------------------ the audit
def test_the_example_arm_audits_clean() -> None:
    for geometry in ("collision", "visual", "none"):
        audit = tb.robots.audit(example_path(), geometry=geometry)
        assert audit.findings == ()
    assert [s.link for s in tb.robots.audit(example_path()).links] == ["base", "arm", "hand"]


def judged(*texts: str) -> tuple[str, float] | None:
    return judge_tensor(tuple(float(t) for t in texts), texts)


def test_a_written_valid_tensor_is_not_flagged_for_its_rounding() -> None:
    # A thin disk (I1 + I2 = I3) printed to three digits: 0.0104, 0.0104, 0.0209
    # may be 0.01044, 0.01044, 0.02088 rounded, a valid tensor.
    assert judged("0.0104", "0", "0", "0.0104", "0", "0.0209") is None
    # Written with more digits the same shortfall (0.5 %) is beyond their rounding.
    code, shortfall = judged("0.010400", "0", "0", "0.010400", "0", "0.020900")  # type: ignore[misc]
    assert code == "triangle-inequality" and shortfall == pytest.approx(0.0001 / 0.0209)
    # One or two digits are taken as chosen, within 0.5 %: a 5 % shortfall is found.
    code, shortfall = judged("0.01", "0", "0", "0.01", "0", "0.021")  # type: ignore[misc]
    assert code == "triangle-inequality" and shortfall == pytest.approx(1 / 21)
    # A placeholder of six equal entries is a rank-one tensor (0, 0, 3e-6): no body.
    assert judged("1e-6", "1e-6", "1e-6", "1e-6", "1e-6", "1e-6")[0] == "triangle-inequality"  # type: ignore[index]
    assert judged("1", "0", "0", "-1", "0", "1")[0] == "not-positive-definite"  # type: ignore[index]
    # A thin rod along (0, 1, 1) (moments 0, 0.6, 0.6) with its product printed one
    # unit too large in the sixth decimal: a negative moment (−1e-6) as written,
    # within the rounding of what was written.
    assert judged("0.6", "0", "0", "0.3", "-0.300001", "0.3") is None
    assert judged("0.6", "0", "0", "0.3", "-0.31", "0.3")[0] == "not-positive-definite"  # type: ignore[index]


def test_a_slipped_decimal_point_is_found_and_corrected(tmp_path: Path) -> None:
    source = slipped(tmp_path, 'izz="0.0009"', 'izz="0.9"')
    audit = tb.robots.audit(source)
    assert codes(audit) == [("arm", "triangle-inequality"), ("arm", "power-of-ten")]
    assert audit.findings[0].severity == "error"
    assert "94 % of I3" in audit.findings[0].message
    assert audit.findings[1].correction == {"izz": 0.0009}
    fixed = write_corrected(audit, tmp_path / "fixed.urdf")
    assert changed_lines(source, fixed) == [
        '<       <inertia ixx="0.0271167" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.9"/>',
        '>       <inertia ixx="0.0271167" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.0009"/>',
    ]
    assert tb.robots.audit(fixed).findings == ()
    assert source.read_text(encoding="utf-8") == EXAMPLE.replace('izz="0.0009"', 'izz="0.9"')


def test_a_slip_that_leaves_one_physical_power_needs_no_geometry(tmp_path: Path) -> None:
    # ixx of the base 100 times too small: only ×100 makes it physical again.
    source = slipped(tmp_path, 'ixx="0.0333333"', 'ixx="0.000333333"')
    audit = tb.robots.audit(source, geometry="none")
    assert codes(audit) == [("base", "triangle-inequality"), ("base", "power-of-ten")]
    assert audit.findings[1].correction == {"ixx": 0.0333333}


def test_several_physical_powers_without_geometry_give_no_correction(tmp_path: Path) -> None:
    source = slipped(tmp_path, 'izz="0.0009"', 'izz="0.9"')
    audit = tb.robots.audit(source, geometry="none")
    assert codes(audit) == [("arm", "triangle-inequality"), ("arm", "power-of-ten")]
    assert audit.findings[1].correction is None
    assert "in 5 ways" in audit.findings[1].message


def test_a_tensor_in_kg_mm2_is_found_against_its_shapes(tmp_path: Path) -> None:
    text = EXAMPLE.replace(
        'ixx="0.0271167" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.0009"',
        'ixx="27116.7" ixy="0" ixz="0" iyy="27116.7" iyz="0" izz="900"',
    )
    source = robot_file(tmp_path, text)
    audit = tb.robots.audit(source)
    assert codes(audit) == [("arm", "geometry-mismatch")]
    assert "kg·mm² for kg·m²" in audit.findings[0].message
    assert audit.findings[0].correction == {"ixx": 0.0271167, "iyy": 0.0271167, "izz": 0.0009}
    fixed = write_corrected(audit, tmp_path / "fixed.urdf")
    assert len(changed_lines(source, fixed)) == 2
    assert tb.robots.audit(fixed).findings == ()


def test_a_massless_link_with_shapes_gets_the_robots_density(tmp_path: Path) -> None:
    source = slipped(tmp_path, '<mass value="0.5"/>', '<mass value="0"/>')
    audit = tb.robots.audit(source)
    assert codes(audit) == [("hand", "massless-with-geometry")]
    finding = audit.findings[0]
    assert finding.severity == "warning"
    # The robot's density: the other links' 6 kg over their shapes' volume.
    density = 6.0 / (0.3 * 0.3 * 0.1 + math.pi * 0.03**2 * 0.4)
    mass = density * 4 / 3 * math.pi * 0.05**3
    assert finding.correction["mass"] == pytest.approx(mass, rel=1e-5)  # type: ignore[index]
    assert finding.correction["izz"] == pytest.approx(0.4 * mass * 0.05**2, rel=1e-5)  # type: ignore[index]
    fixed = write_corrected(audit, tmp_path / "fixed.urdf")
    assert tb.robots.audit(fixed).findings == ()
    assert all("mass" in line or "inertia" in line or "origin" in line
               for line in changed_lines(source, fixed))  # fmt: skip


def test_a_link_without_inertial_gets_one_inserted(tmp_path: Path) -> None:
    start = EXAMPLE.index('  <link name="hand">')
    end = EXAMPLE.index("    <collision>", start)
    source = robot_file(tmp_path, EXAMPLE[:start] + '  <link name="hand">\n' + EXAMPLE[end:])
    audit = tb.robots.audit(source)
    assert codes(audit) == [("hand", "massless-with-geometry")]
    fixed = write_corrected(audit, tmp_path / "fixed.urdf")
    assert tb.robots.audit(fixed).findings == ()
    added = changed_lines(source, fixed)
    assert added[0] == ">     <inertial>" and added[-1] == ">     </inertial>"


def test_a_negative_mass_and_a_negative_moment_are_errors(tmp_path: Path) -> None:
    audit = tb.robots.audit(slipped(tmp_path, '<mass value="0.5"/>', '<mass value="-0.5"/>'))
    assert codes(audit) == [("hand", "negative-mass")]
    assert audit.findings[0].correction == {"mass": 0.5}
    audit = tb.robots.audit(slipped(tmp_path, 'iyy="0.0005"', 'iyy="-0.0005"'))
    assert ("hand", "not-positive-definite") in codes(audit)
    assert audit.errors


def test_exchanged_attributes_are_found(tmp_path: Path) -> None:
    # A product written where a moment belongs, and the moment as a product.
    source = slipped(tmp_path, 'ixx="0.0333333" ixy="0"', 'ixx="0" ixy="0.0333333"')
    audit = tb.robots.audit(source, geometry="none")
    assert ("base", "swapped-attributes") in codes(audit)
    swap = next(f for f in audit.findings if f.code == "swapped-attributes")
    assert swap.correction == {"ixx": 0.0333333, "ixy": 0.0}


def test_a_row_major_walk_is_recognised(tmp_path: Path) -> None:
    # The 3 × 3 matrix [[a, b, 0], [b, c, d], [0, d, e]] written row by row into
    # ixx ixy ixz iyy iyz izz: a, b, 0, b, c, d; e is lost.
    text = EXAMPLE.replace(
        'ixx="0.0333333" ixy="0" ixz="0" iyy="0.0333333" iyz="0" izz="0.06"',
        'ixx="0.0333333" ixy="0.02" ixz="0" iyy="0.02" iyz="0.0333333" izz="0.001"',
    )
    audit = tb.robots.audit(robot_file(tmp_path, text), geometry="none")
    assert ("base", "row-major") in codes(audit)


def test_a_centre_of_mass_outside_the_shapes_is_found(tmp_path: Path) -> None:
    source = slipped(tmp_path, '<origin xyz="0 0 0.2" rpy="0 0 0"/>\n      <mass value="2.0"/>',
                     '<origin xyz="0 0 2" rpy="0 0 0"/>\n      <mass value="2.0"/>')  # fmt: skip
    audit = tb.robots.audit(source)
    assert codes(audit) == [("arm", "geometry-mismatch")]
    assert audit.findings[0].correction == {"xyz": (0.0, 0.0, 0.2)}
    fixed = write_corrected(audit, tmp_path / "fixed.urdf")
    assert tb.robots.audit(fixed).findings == ()


def test_a_mesh_in_millimetres_has_an_implausible_density(tmp_path: Path) -> None:
    import trimesh

    trimesh.creation.box(extents=[300, 300, 100]).export(tmp_path / "base.stl")
    source = slipped(tmp_path, '<geometry><box size="0.3 0.3 0.1"/></geometry>',
                     '<geometry><mesh filename="base.stl"/></geometry>')  # fmt: skip
    audit = tb.robots.audit(source)
    assert codes(audit) == [("base", "implausible-density")]
    assert "millimetres read as metres" in audit.findings[0].message
    scaled = slipped(tmp_path, '<geometry><box size="0.3 0.3 0.1"/></geometry>',
                     '<geometry><mesh filename="base.stl" scale="0.001 0.001 0.001"/></geometry>',
                     "scaled.urdf")  # fmt: skip
    assert tb.robots.audit(scaled).findings == ()
    assert_allclose(tb.robots.load(scaled).links["base"].geometry().inertia,
                    box_inertia(4.0, 0.3, 0.3, 0.1), rtol=1e-6, atol=1e-15)  # fmt: skip


def test_a_missing_mesh_is_a_finding_and_a_clear_error(tmp_path: Path) -> None:
    source = slipped(tmp_path, '<geometry><box size="0.3 0.3 0.1"/></geometry>',
                     '<geometry><mesh filename="package://arm/meshes/base.stl"/></geometry>')  # fmt: skip
    audit = tb.robots.audit(source)
    assert codes(audit) == [("base", "missing-mesh")]
    assert "base.stl" in audit.findings[0].message
    with pytest.raises(tb.InputError, match=r"Expected the mesh file '.*base\.stl' to exist"):
        tb.robots.load(source).links["base"].geometry()


def test_package_names_resolve_through_parent_folders(tmp_path: Path) -> None:
    import trimesh

    package = tmp_path / "arm_description"
    (package / "meshes").mkdir(parents=True)
    (package / "urdf").mkdir()
    trimesh.creation.box(extents=[0.3, 0.3, 0.1]).export(package / "meshes" / "base.stl")
    text = EXAMPLE.replace('<geometry><box size="0.3 0.3 0.1"/></geometry>',
                           '<geometry><mesh filename="package://arm_description/meshes/base.stl"/>'
                           "</geometry>")  # fmt: skip
    source = robot_file(package / "urdf", text)
    assert tb.robots.audit(source).findings == ()


# ------------------------------------------------------------------ refusals
@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("not xml <", r"^Expected '.*arm\.urdf' to be well-formed XML, got syntax error at line 1"),
        ("<sdf/>", r"^Expected a URDF robot \(a <robot> root element\) in '.*', got <sdf>\.$"),
        (EXAMPLE.replace('<child link="hand"/>', '<child link="hind"/>'),
         r"^Expected the child of joint 'wrist' \(arm\.urdf line \d+\) to be a link of the robot, "
         r"got 'hind'\.$"),
        (EXAMPLE.replace('type="fixed"', 'type="welded"'),
         r"^Expected the type of joint 'wrist' .* to be one of revolute, continuous, prismatic, "
         r"fixed, floating, planar, spherical, got 'welded'\.$"),
    ],
)  # fmt: skip
def test_bad_robot_files_are_refused_with_one_clear_line(
    tmp_path: Path, text: str, message: str
) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.robots.load(robot_file(tmp_path, text))


# What urdfdom refuses in a file whose every inertial can still be read: the file
# loads, so that the audit judges them, and the poses that need it are refused.
@pytest.mark.parametrize(
    ("text", "message"),
    [
        (EXAMPLE.replace('izz="0.0009"', 'izz="1.2.3"'),
         r"^Expected a finite number for `izz` of <inertia> of link 'arm' \(arm\.urdf line 20\), "
         r"got '1\.2\.3'\.$"),
        (EXAMPLE.replace('<child link="hand"/>', '<child link="arm"/>'),
         r"^Expected a tree of links in arm\.urdf, got link 'arm' as the child of two joints\.$"),
        (EXAMPLE.replace('<parent link="arm"/>', '<parent link="hand"/>')
         .replace('<child link="arm"/>\n    <origin xyz="0 0 0.1"', '<child link="hand"/>\n    <origin xyz="0 0 0.1"'),
         r"^Expected a tree of links"),
        (EXAMPLE.replace("</robot>", '  <joint name="back" type="fixed">\n    <parent link="hand"/>\n'
                         '    <child link="base"/>\n  </joint>\n</robot>'),
         r"^Expected a tree of links in arm\.urdf, got a cycle"),
    ],
)  # fmt: skip
def test_what_urdfdom_refuses_loads_and_its_poses_are_refused(
    tmp_path: Path, text: str, message: str
) -> None:
    robot = tb.robots.load(robot_file(tmp_path, text))
    assert {notice.code for notice in robot.notices} <= {"unreadable-inertial", "invalid-joint"}
    assert robot.notices
    with pytest.raises(tb.InputError, match=message):
        robot.mass_properties()


def test_a_file_that_cannot_be_read_and_a_cut_start_tag_are_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The superuser reads any file: the refusal of the operating system is mocked.
    path = robot_file(tmp_path, EXAMPLE, "arm.urdf")

    opened = os.open

    def refuse(name: object, *args: object) -> int:
        if str(name) == str(path):
            raise PermissionError(13, "Permission denied")
        return opened(name, *args)  # type: ignore[arg-type]

    with monkeypatch.context() as patch:
        patch.setattr(os, "open", refuse)
        with pytest.raises(
            tb.InputError,
            match=r"^Expected a robot file, got '.*arm\.urdf': Permission denied\.$",
        ):
            tb.robots.load(path)


def test_other_refusals(tmp_path: Path) -> None:
    # A xacro file is expanded by xacro: plain URDF expands to itself.
    assert sorted(tb.robots.load(robot_file(tmp_path, EXAMPLE, "arm.xacro")).links) == [
        "arm",
        "base",
        "hand",
    ]
    with pytest.raises(
        tb.InputError, match=r"\.xacro \(xacro\) or \.xml \(MJCF\), got '.*arm\.txt'\.$"
    ):
        tb.robots.load(robot_file(tmp_path, EXAMPLE, "arm.txt"))
    with pytest.raises(tb.InputError, match=r"got '.*nothing\.urdf': no such file\.$"):
        tb.robots.load(tmp_path / "nothing.urdf")
    robot = tb.robots.load(example_path())
    with pytest.raises(
        tb.InputError, match=r"^Expected a joint of the robot to be one of .*'elbow'"
    ):
        robot.mass_properties({"elbow": 1.0})
    with pytest.raises(tb.InputError, match=r"got 'wrist', a fixed joint\.$"):
        robot.mass_properties({"wrist": 1.0})
    with pytest.raises(tb.InputError, match=r"`joints\['shoulder'\]`"):
        robot.mass_properties({"shoulder": "3 kg"})
    with pytest.raises(
        tb.InputError, match=r"^Expected `geometry` to be one of collision, visual, none"
    ):
        tb.robots.audit(example_path(), geometry="both")
    with pytest.raises(
        tb.InputError, match=r"^Expected link 'arm' to have visual shapes, got none\.$"
    ):
        robot.links["arm"].geometry("visual")
    source = robot_file(tmp_path, EXAMPLE)
    with pytest.raises(tb.InputError, match=r"^Expected --fix to name a new file, got the audited"):
        write_corrected(tb.robots.audit(source), source)
    invalid = slipped(tmp_path, 'izz="0.0009"', 'izz="0.9"', "invalid.urdf")
    with pytest.raises(tb.InputError, match=r"^Expected link 'arm' of '.*invalid\.urdf' to declare "
                       r"physical mass properties, got: .*\(`tumble audit` finds the correction\)$"):  # fmt: skip
        tb.robots.load(invalid).mass_properties()


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('<link name="hand">', "<link>", r"^Expected a name on the <link> at line \d+ of arm\.urdf, got none\.$"),
        ('<link name="hand">', '<link name="arm">', r"^Expected one link named 'arm' in arm\.urdf, got two \(line \d+\)\.$"),
        ('<box size="0.3 0.3 0.1"/>', "<box/>", r"^Expected a `size` attribute on <box> of link 'base' \(arm\.urdf line \d+\), got none\.$"),
        ('<axis xyz="0 1 0"/>', '<axis xyz="0 0 0"/>', r"^Expected a non-zero axis for joint 'shoulder' \(arm\.urdf line \d+\), got \[0\.0, 0\.0, 0\.0\]\.$"),
    ],
)  # fmt: skip
def test_more_refusals_of_bad_files(tmp_path: Path, old: str, new: str, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.robots.load(slipped(tmp_path, old, new))


def test_a_joint_whose_origin_cannot_be_read_refuses_the_poses_beyond_it(tmp_path: Path) -> None:
    robot = tb.robots.load(
        slipped(tmp_path, '<origin xyz="0 0 0.4" rpy="0 0 0"/>',
                '<origin xyz="$(arg x) 0 0.4" rpy="0 0 0"/>')
    )  # fmt: skip
    assert [notice.code for notice in robot.notices] == ["malformed-number"]
    with pytest.raises(
        tb.InputError,
        match=r"got '\$\(arg x\) 0 0\.4' \(a xacro expression: run xacro on the file first\); "
        r"link 'hand' beyond it has mass, so its pose is unknown\.$",
    ):
        robot.mass_properties()


def test_refusals_of_geometry_and_poses(tmp_path: Path) -> None:
    robot = tb.robots.load(example_path())
    with pytest.raises(
        tb.InputError, match=r"^Expected a mass > 0 kg to give link 'arm'.s geometry, got -1\.0\.$"
    ):
        robot.links["arm"].geometry(mass=-1.0)
    (tmp_path / "broken.stl").write_text("solid nothing\nthis is not a mesh\n", encoding="utf-8")
    broken = slipped(tmp_path, '<box size="0.3 0.3 0.1"/>', '<mesh filename="broken.stl"/>')
    with pytest.raises(tb.InputError, match=r"broken\.stl"):
        tb.robots.load(broken).links["base"].geometry()
    assert [f.code for f in tb.robots.audit(broken).findings] == ["geometry-unavailable"]
    massless = EXAMPLE.replace('<mass value="4.0"/>', '<mass value="0"/>').replace(
        '<mass value="2.0"/>', '<mass value="0"/>').replace('<mass value="0.5"/>', '<mass value="0"/>')  # fmt: skip
    with pytest.raises(
        tb.InputError, match=r"^Expected a robot with mass, got no link with mass in "
    ):
        tb.robots.load(robot_file(tmp_path, massless, "massless.urdf")).mass_properties()
    mimic = EXAMPLE.replace('<joint name="wrist" type="fixed">',
                            '<joint name="wrist" type="revolute">\n    <mimic joint="elbow"/>')  # fmt: skip
    robot = tb.robots.load(robot_file(tmp_path, mimic, "mimic.urdf"))  # an audit needs no pose
    assert tb.robots.audit(robot).findings == ()
    with pytest.raises(
        tb.InputError,
        match=r"^Expected joint 'wrist' to mimic a joint of the robot, got 'elbow'\.$",
    ):
        robot.mass_properties()


def test_an_mjcf_file_is_read_through_mujoco_and_a_clean_one_corrected_is_itself(
    tmp_path: Path,
) -> None:
    pytest.importorskip("mujoco")
    source = tmp_path / "box.xml"
    source.write_text(
        '<mujoco><worldbody><body name="b"><freejoint/>'
        '<geom type="box" size="0.15 0.15 0.05" mass="4"/></body></worldbody></mujoco>',
        encoding="utf-8",
    )
    robot = tb.robots.load(source)
    assert list(robot.links) == ["world", "b"]
    assert_allclose(
        robot.links["b"].geometry().inertia, box_inertia(4.0, 0.3, 0.3, 0.1), rtol=1e-12
    )
    assert_allclose(robot.links["b"].inertia, box_inertia(4.0, 0.3, 0.3, 0.1), rtol=1e-12)
    audit = tb.robots.audit(source)
    assert audit.findings == ()
    assert write_corrected(audit, tmp_path / "out.xml").read_bytes() == source.read_bytes()
    (tmp_path / "bad.xml").write_text(
        "<mujoco><worldbody><body><geom type='sphere'/>", encoding="utf-8"
    )
    with pytest.raises(tb.InputError, match=r"^Expected an MJCF model in '.*bad\.xml', got: "):
        tb.robots.load(tmp_path / "bad.xml")


def test_a_collada_mesh_in_centimetres_is_read_in_metres(tmp_path: Path) -> None:
    # A COLLADA file declares its unit (<unit meter="0.01"/>): a 30 × 30 × 10 cm box
    # written in centimetres is the base's box, in metres.
    import trimesh

    box = trimesh.creation.box(extents=[30, 30, 10])
    text = trimesh.exchange.dae.export_collada(box).decode()
    text = text.replace(
        "<up_axis>Y_UP</up_axis>", '<unit meter="0.01" name="centimeter"/><up_axis>Z_UP</up_axis>'
    )
    (tmp_path / "base.dae").write_text(text, encoding="utf-8")
    source = slipped(tmp_path, '<geometry><box size="0.3 0.3 0.1"/></geometry>',
                     '<geometry><mesh filename="base.dae"/></geometry>')  # fmt: skip
    base = tb.robots.load(source).links["base"]
    assert_allclose(base.geometry().inertia, box_inertia(4.0, 0.3, 0.3, 0.1), rtol=1e-9, atol=1e-15)
    assert tb.robots.audit(source).findings == ()


def test_refusals_of_shapes_and_readers(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from tumble.robots.model import LinkShape

    with pytest.raises(
        tb.InputError, match=r"^Expected a mesh shape to name its file, got none\.$"
    ):
        LinkShape("mesh").unit_density()
    with pytest.raises(
        tb.InputError, match=r"^Expected a shape's kind to be one of box, .*got 'cone'\."
    ):
        LinkShape("cone").unit_density()
    with pytest.raises(
        tb.InputError, match=r"^Expected `kind` to be one of collision, visual, got 'inertial'\."
    ):
        tb.robots.load(example_path()).links["arm"].geometry("inertial")
    (tmp_path / "garbage.glb").write_bytes(b"glTF\x02\x00\x00\x00garbage")
    with pytest.raises(
        tb.InputError, match=r"^Expected a readable mesh file, got '.*garbage\.glb': "
    ):
        LinkShape("mesh", mesh=tmp_path / "garbage.glb").unit_density()
    with pytest.raises(
        tb.InputError, match=r"^Expected a robot with links in '.*empty\.urdf', got none\.$"
    ):
        tb.robots.load(robot_file(tmp_path, '<robot name="empty"/>', "empty.urdf"))
    source = tmp_path / "m.xml"
    source.write_text("<mujoco><worldbody><body name='b'><geom type='sphere' size='0.1'/></body>"
                      "</worldbody></mujoco>", encoding="utf-8")  # fmt: skip
    monkeypatch.setitem(__import__("sys").modules, "mujoco", None)
    with pytest.raises(tb.InputError, match=r"^Expected the mujoco package to read the MJCF file "
                       r"'.*m\.xml', got none installed: pip install 'tumble\[robots\]'\.$"):  # fmt: skip
        tb.robots.load(source)


def test_refusals_of_mjcf_models(tmp_path: Path) -> None:
    pytest.importorskip("mujoco")
    massless = tmp_path / "massless.xml"
    massless.write_text(
        "<mujoco><worldbody><body name='b' pos='0 0 1'><inertial pos='0 0 0' mass='1' "
        "diaginertia='1 1 1'/><geom type='sphere' size='0.1' mass='0'/></body></worldbody></mujoco>",
        encoding="utf-8",
    )
    with pytest.raises(tb.InputError, match=r"^Expected link 'b' to have collision shapes with mass, "
                       r"got only massless ones\.$"):  # fmt: skip
        tb.robots.load(massless).links["b"].geometry()
    broken = tmp_path / "broken.xml"
    broken.write_text("<mujoco><worldbody><body name='b'><joint type='hinge'/></body></worldbody>"
                      "</mujoco>", encoding="utf-8")  # fmt: skip
    with pytest.raises(
        tb.InputError, match=r"^Expected an MJCF model MuJoCo compiles, got broken\.xml: "
    ):
        tb.robots.load(broken)


def test_the_old_name_of_a_link_s_shape_still_works_with_a_warning() -> None:
    import tumble.robots

    with pytest.warns(
        DeprecationWarning,
        match=r"tumble\.robots\.Shape is deprecated: use tumble\.robots\.LinkShape",
    ):
        old = tumble.robots.Shape
    assert old is tumble.robots.LinkShape
    with pytest.raises(AttributeError, match="has no attribute 'Shap'"):
        tumble.robots.Shap  # noqa: B018
