"""The corrected copy of a robot file (``write_corrected``, ``tumble audit --fix``):
edits placed where the parser saw the elements, the file's own encoding kept,
MJCF's ``<inertial>`` written as MuJoCo reads it, and a copy that does not read
back with its corrections never written."""

from __future__ import annotations

import codecs
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

import tumble as tb
from tumble.cli import app
from tumble.robots import Finding, example_path, write_corrected

EXAMPLE = example_path().read_text(encoding="utf-8")
SLIPPED = EXAMPLE.replace('izz="0.0009"', 'izz="0.9"')
HAND_INERTIAL = """    <inertial>
      <mass value="0.5"/>
      <inertia ixx="0.0005" ixy="0" ixz="0" iyy="0.0005" iyz="0" izz="0.0005"/>
    </inertial>
"""


@pytest.fixture(autouse=True)
def _scratch_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """MuJoCo logs its warnings to MUJOCO_LOG.TXT in the working folder: a scratch one."""
    monkeypatch.chdir(tmp_path)


def robot_file(tmp_path: Path, text: str, name: str = "arm.urdf") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def corrected(source: Path, tmp_path: Path, name: str = "fixed.urdf") -> Path:
    return write_corrected(tb.robots.audit(source), tmp_path / name)


# ---------------------------------------------------------------- URDF: the right place


def test_a_commented_out_link_before_the_real_one_is_left_alone(tmp_path: Path) -> None:
    comment = '  <!-- <link name="hand"> was here -->\n'
    text = EXAMPLE.replace(HAND_INERTIAL, "").replace(
        '  <link name="base">', comment + '  <link name="base">'
    )
    source = robot_file(tmp_path, text)
    fixed = corrected(source, tmp_path)
    written = fixed.read_text(encoding="utf-8")
    assert comment in written
    assert written.index("<inertial>", written.index('<link name="hand">')) < written.index(
        "</link>", written.index('<link name="hand">')
    )
    assert tb.robots.audit(fixed).findings == ()


def test_a_self_closing_inertial_is_unreadable_and_a_correction_fills_it(tmp_path: Path) -> None:
    source = robot_file(tmp_path, EXAMPLE.replace(HAND_INERTIAL, "    <inertial/>\n"))
    audit = tb.robots.audit(source)
    # urdfdom and PyBullet refuse an inertial without <mass>: an error of its link,
    # which no correction of the audit's own fills.
    assert ("hand", "unreadable-inertial") in [(f.link, f.code) for f in audit.findings]
    assert "hand" not in audit.corrections()
    # A correction given for it goes inside the element, which then opens and closes:
    # the hand's sphere (radius 0.05 m) at 0.5 kg, I = 2/5 m r² = 0.0005 kg·m².
    sphere = {"mass": 0.5, "xyz": (0.0, 0.0, 0.0), "ixx": 0.0005, "ixy": 0.0, "ixz": 0.0,
              "iyy": 0.0005, "iyz": 0.0, "izz": 0.0005}  # fmt: skip
    given = replace(
        audit, findings=(Finding("hand", "massless-with-geometry", "warning", "", sphere),)
    )
    fixed = write_corrected(given, tmp_path / "fixed.urdf")
    written = fixed.read_text(encoding="utf-8")
    assert "<inertial/>" not in written
    block = written[written.index('<link name="hand">') :]
    assert block.index("<inertial>") < block.index("<mass") < block.index("</inertial>")
    assert tb.robots.audit(fixed).findings == ()
    hand = tb.robots.load(fixed).links["hand"]
    assert hand.mass == 0.5
    assert_allclose(hand.inertia, np.eye(3) * 0.4 * 0.5 * 0.05**2, rtol=1e-15)


def test_an_attribute_value_that_mentions_izz_is_left_alone(tmp_path: Path) -> None:
    note = """note=' izz="3" before' """
    text = SLIPPED.replace('<inertia ixx="0.0271167"', f'<inertia {note}ixx="0.0271167"')
    source = robot_file(tmp_path, text)
    fixed = corrected(source, tmp_path)
    assert fixed.read_text(encoding="utf-8") == text.replace('izz="0.9"', 'izz="0.0009"')


def test_an_inertial_from_an_entity_is_refused_and_nothing_written(tmp_path: Path) -> None:
    declaration = '<?xml version="1.0"?>\n'
    entity = (
        '<!DOCTYPE robot [\n<!ENTITY hand_inertial \'<inertial><mass value="0"/>'
        '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>\'>\n]>\n'
    )
    text = EXAMPLE.replace(declaration, declaration + entity).replace(
        HAND_INERTIAL, "    &hand_inertial;\n"
    )
    source = robot_file(tmp_path, text)
    audit = tb.robots.audit(source)
    assert [f.code for f in audit.findings] == ["massless-with-geometry"]
    out = tmp_path / "fixed.urdf"
    with pytest.raises(
        tb.InputError,
        match=r"^Expected link 'hand' written out in arm\.urdf to correct it, got the entity "
        r"reference &hand_inertial; inside it: correct the entity by hand\.$",
    ):
        write_corrected(audit, out)
    assert not out.exists()


def test_a_link_from_an_entity_is_refused(tmp_path: Path) -> None:
    start = EXAMPLE.index('  <link name="hand">')
    end = EXAMPLE.index("  </link>", start) + len("  </link>\n")
    hand = EXAMPLE[start:end].replace('<mass value="0.5"/>', '<mass value="0"/>')
    declaration = '<?xml version="1.0"?>\n'
    text = EXAMPLE[:start] + "  &hand;\n" + EXAMPLE[end:]
    text = text.replace(declaration, f"{declaration}<!DOCTYPE robot [<!ENTITY hand '{hand}'>]>\n")
    audit = tb.robots.audit(robot_file(tmp_path, text))
    assert [f.code for f in audit.findings] == ["massless-with-geometry"]
    with pytest.raises(
        tb.InputError,
        match=r"^Expected link 'hand' written in arm\.urdf to correct it, got none there: it "
        r"comes from an entity\.$",
    ):
        write_corrected(audit, tmp_path / "fixed.urdf")


# ---------------------------------------------------------------- the file's own encoding


def _encoded(text: str, encoding: str) -> bytes:
    """``text`` as a file in ``encoding``: a byte-order mark for UTF-16, and the
    XML declaration naming a declared encoding."""
    if encoding in ("utf-16-le", "utf-16-be"):
        mark = codecs.BOM_UTF16_LE if encoding == "utf-16-le" else codecs.BOM_UTF16_BE
        return mark + text.encode(encoding)
    if encoding == "utf-8-sig":
        return text.encode(encoding)
    declared = text.replace('<?xml version="1.0"?>', f'<?xml version="1.0" encoding="{encoding}"?>')
    return declared.encode(encoding)


@pytest.mark.parametrize(
    "encoding", ["utf-16-le", "utf-16-be", "utf-8-sig", "ISO-8859-1", "windows-1252"]
)
def test_the_copy_keeps_the_files_encoding_byte_for_byte(tmp_path: Path, encoding: str) -> None:
    # Accents in a comment and in the very tag corrected.
    accents = "<!-- Dimensions relevées à l’œil: ±1 mm, 25 €. -->\n<robot"
    note = ' note="mesuré à l’œil, 3 €"/>'
    if encoding == "ISO-8859-1":
        accents, note = (t.replace("’œ", "'o").replace(" €", " EUR") for t in (accents, note))
    text = EXAMPLE.replace("<robot", accents, 1).replace('izz="0.0009"/>', f'izz="0.0009"{note}')
    source = tmp_path / "arm.urdf"
    source.write_bytes(_encoded(text.replace('izz="0.0009"', 'izz="0.9"'), encoding))
    fixed = corrected(source, tmp_path)
    assert fixed.read_bytes() == _encoded(text, encoding)
    assert tb.robots.audit(fixed).findings == ()


def test_a_latin_1_file_is_corrected_through_the_command_line(tmp_path: Path) -> None:
    text = SLIPPED.replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="ISO-8859-1"?>')
    text = text.replace('izz="0.9"/>', 'izz="0.9" note="mesuré"/>')
    source = tmp_path / "arm.urdf"
    source.write_bytes(text.encode("latin-1"))
    out = tmp_path / "fixed.urdf"
    result = CliRunner().invoke(app, ["audit", str(source), "--fix", str(out)])
    assert result.exit_code == 1, result.output
    assert f"Corrected 1 link into {out}" in result.output
    assert out.read_bytes() == text.replace('izz="0.9"', 'izz="0.0009"').encode("latin-1")


# ---------------------------------------------------------------- refusals


def test_what_is_not_an_audit_or_a_path_is_refused(tmp_path: Path) -> None:
    with pytest.raises(
        tb.InputError,
        match=r"^Expected an Audit from tumble\.robots\.audit to correct, got str 'x'\.$",
    ):
        write_corrected("x", tmp_path / "out.urdf")  # type: ignore[arg-type]
    with pytest.raises(
        tb.InputError, match=r"^Expected the corrected file's path \(str or Path\), got int 5\.$"
    ):
        write_corrected(tb.robots.audit(example_path()), 5)


def test_a_copy_that_does_not_read_back_as_audited_is_never_written(tmp_path: Path) -> None:
    # The source changed after its audit: the copy would carry the base's new mass.
    source = robot_file(tmp_path, SLIPPED)
    audit = tb.robots.audit(source)
    source.write_text(
        SLIPPED.replace('<mass value="4.0"/>', '<mass value="5.0"/>'), encoding="utf-8"
    )
    out = tmp_path / "fixed.urdf"
    out.write_text("an earlier copy", encoding="utf-8")
    with pytest.raises(
        tb.InputError,
        match=r"^Expected link 'base' of the corrected copy of '.*arm\.urdf' to read back with its "
        r"former values, got mass 5\.0 kg for 4\.0: it cannot be corrected in place, and nothing "
        r"was written\.$",
    ):
        write_corrected(audit, out)
    assert out.read_text(encoding="utf-8") == "an earlier copy"
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_a_file_of_another_kind_is_refused(tmp_path: Path) -> None:
    audit = tb.robots.audit(robot_file(tmp_path, SLIPPED))
    moved = replace(audit, robot=replace(audit.robot, path=tmp_path / "arm.urdf.xacro"))
    with pytest.raises(
        tb.InputError,
        match=r"^Expected a URDF \(\.urdf\) or MJCF \(\.xml\) file to correct, got '.*arm\.urdf\.xacro'\.$",
    ):
        write_corrected(moved, tmp_path / "fixed.urdf")


# ---------------------------------------------------------------- MJCF

MJCF = """<mujoco model="two">
  <!-- a box base and a tilted arm; the arm's inertial frame is turned 90° about y -->
  <worldbody>
    <body name="base" pos="0 0 0.1">
      <freejoint/>
      <inertial pos="0 0 0" mass="4" diaginertia="0.0333333 0.0333333 0.06"/>
      <geom type="box" size="0.15 0.15 0.05" mass="4"/>
      <body name="arm" pos="0 0 0.1">
        <joint type="hinge" axis="0 1 0"/>
        <inertial pos="0 0 0.2" quat="0.7071068 0 0.7071068 0" mass="2" diaginertia="0.0009 0.0271167 0.0271167"/>
        <geom type="cylinder" fromto="0 0 0 0 0 0.4" size="0.03" mass="2"/>
      </body>
      <body name="hand" pos="0 0 0.5">
        <geom type="box" size="0.05 0.03 0.02" pos="0 0 0.05" euler="0 0 30" mass="0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def compiled(path: Path, body: str) -> tuple[float, np.ndarray, np.ndarray]:
    """MuJoCo's compiled mass, centre and inertia (body axes) of ``body``: the oracle."""
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_path(str(path)).body(body)
    axes = Rotation.from_quat(model.iquat, scalar_first=True).as_matrix()
    return float(model.mass[0]), np.array(model.ipos), axes @ np.diag(model.inertia) @ axes.T


def test_an_mjcf_slipped_decimal_point_is_corrected_in_its_diaginertia(tmp_path: Path) -> None:
    mujoco = pytest.importorskip("mujoco")
    text = MJCF.replace(
        'diaginertia="0.0333333 0.0333333 0.06"', 'diaginertia="0.0333333 0.0333333 6"'
    )
    source = robot_file(tmp_path, text, "two.xml")
    with pytest.raises(ValueError, match="inertia"):
        mujoco.MjModel.from_xml_path(str(source))  # MuJoCo refuses the tensor as written
    audit = tb.robots.audit(source)
    # The massless hand, welded to the base, is corrected too (as in the file
    # MuJoCo compiles): its inertial is inserted on a line of its own.
    assert audit.corrections().keys() == {"base", "hand"}
    assert audit.corrections()["base"] == {"izz": 0.06}
    fixed = write_corrected(audit, tmp_path / "fixed.xml")
    written = fixed.read_text(encoding="utf-8")
    assert written.replace(written.splitlines()[13] + "\n", "") == MJCF
    mass, _, inertia = compiled(fixed, "base")
    assert mass == 4.0
    assert_allclose(inertia, np.diag([0.0333333, 0.0333333, 0.06]), rtol=1e-12)


def test_an_mjcf_correction_off_the_diagonal_becomes_fullinertia_in_body_axes(
    tmp_path: Path,
) -> None:
    pytest.importorskip("mujoco")
    source = robot_file(tmp_path, MJCF, "two.xml")
    names = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    indices = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
    along_z = np.diag([0.0271167, 0.0271167, 0.0009])
    # The cylinder along z in body axes, in the arm's inertial frame (the quat),
    # with a product added: no longer diagonal there.
    quat = Rotation.from_quat([0.7071068, 0, 0.7071068, 0], scalar_first=True).as_matrix()
    seen = quat.T @ along_z @ quat + np.array([[0, 1e-4, 0], [1e-4, 0, 0], [0, 0, 0]])
    correction = {n: float(seen[i, j]) for n, (i, j) in zip(names, indices, strict=True)}
    finding = Finding("arm", "geometry-mismatch", "warning", "products", correction)
    audit = tb.robots.Audit(tb.robots.load(source), "none", (finding,))
    fixed = write_corrected(audit, tmp_path / "fixed.xml")
    line = next(x for x in fixed.read_text(encoding="utf-8").splitlines() if 'pos="0 0 0.2"' in x)
    assert "fullinertia=" in line and "quat=" not in line and "diaginertia=" not in line
    # MuJoCo's compiled tensor (body axes) is the correction turned by the quat.
    _, centre, inertia = compiled(fixed, "arm")
    assert_allclose(inertia, quat @ seen @ quat.T, rtol=0, atol=1e-12)
    assert_allclose(centre, [0, 0, 0.2], atol=1e-15)
    # Everything else is the source's, byte for byte.
    before, after = MJCF.splitlines(), fixed.read_text(encoding="utf-8").splitlines()
    assert [i for i, (a, b) in enumerate(zip(before, after, strict=True)) if a != b] == [9]


def test_an_mjcf_body_without_inertial_gets_one(tmp_path: Path) -> None:
    pytest.importorskip("mujoco")
    source = robot_file(tmp_path, MJCF, "two.xml")
    audit = tb.robots.audit(source)
    assert [(f.link, f.code) for f in audit.findings] == [("hand", "massless-with-geometry")]
    correction = audit.corrections()["hand"]
    fixed = write_corrected(audit, tmp_path / "fixed.xml")
    written = fixed.read_text(encoding="utf-8")
    assert written.replace(written.splitlines()[13] + "\n", "") == MJCF
    mass, centre, inertia = compiled(fixed, "hand")
    assert mass == correction["mass"]
    assert_allclose(centre, [0, 0, 0.05], atol=1e-15)
    # A box of edges 0.1, 0.06, 0.04 m turned 30° about z: the correction keeps 6
    # significant digits, hence rtol 1e-5 of the largest moment.
    box = mass / 12 * np.diag([0.06**2 + 0.04**2, 0.1**2 + 0.04**2, 0.1**2 + 0.06**2])
    turn = Rotation.from_euler("z", 30, degrees=True).as_matrix()
    assert_allclose(inertia, turn @ box @ turn.T, rtol=0, atol=1e-5 * box.max())


def test_an_mjcf_body_of_an_included_file_is_refused_naming_it(tmp_path: Path) -> None:
    pytest.importorskip("mujoco")
    (tmp_path / "parts.xml").write_text(
        '<mujoco>\n  <body name="arm" pos="0 0 0.1">\n'
        '    <inertial pos="0 0 0.2" mass="2" diaginertia="0.0271167 0.0271167 0.9"/>\n'
        '    <geom type="cylinder" fromto="0 0 0 0 0 0.4" size="0.03" mass="2"/>\n'
        "  </body>\n</mujoco>\n",
        encoding="utf-8",
    )
    source = robot_file(
        tmp_path,
        '<mujoco model="included">\n  <worldbody>\n    <body name="base">\n      <freejoint/>\n'
        '      <geom type="box" size="0.15 0.15 0.05" mass="4"/>\n'
        '      <include file="parts.xml"/>\n    </body>\n  </worldbody>\n</mujoco>\n',
        "main.xml",
    )
    audit = tb.robots.audit(source)
    assert audit.corrections()["arm"] == {"izz": 0.0009}
    with pytest.raises(
        tb.InputError,
        match=r"^Expected body 'arm' written in main\.xml to correct it, got it in the included "
        r"file 'parts\.xml': correct that file\.$",
    ):
        write_corrected(audit, tmp_path / "fixed.xml")


def test_an_mjcf_correction_a_compiler_setting_overrides_is_refused(tmp_path: Path) -> None:
    pytest.importorskip("mujoco")
    text = MJCF.replace("<worldbody>", '<compiler settotalmass="10"/>\n  <worldbody>').replace(
        'diaginertia="0.0333333 0.0333333 0.06"', 'diaginertia="0.0333333 0.0333333 6"'
    )
    audit = tb.robots.audit(robot_file(tmp_path, text, "two.xml"))
    assert "base" in audit.corrections()
    out = tmp_path / "fixed.xml"
    with pytest.raises(
        tb.InputError, match=r"^Expected .*corrected copy of '.*two\.xml'.*nothing was written\.$"
    ):
        write_corrected(audit, out)
    assert not out.exists()


# ---------------------------------------------------------------- re-audited before written


def test_a_correction_that_leaves_its_link_unphysical_is_never_written(tmp_path: Path) -> None:
    # The arm's mass is negative and its izz slipped: its correction, the
    # smallest edit, restores the mass alone, so the copy still breaks I1 + I2 >= I3.
    text = SLIPPED.replace('<mass value="2.0"/>', '<mass value="-2.0"/>')
    audit = tb.robots.audit(robot_file(tmp_path, text))
    assert audit.corrections() == {"arm": {"mass": 2.0}}
    out = tmp_path / "fixed.urdf"
    with pytest.raises(
        tb.InputError,
        match=r"^Expected link 'arm' of the corrected copy of '.*arm\.urdf' to audit without "
        r"errors, got triangle-inequality: Principal moments .* Its correction does not make it "
        r"physical, and nothing was written\.$",
    ):
        write_corrected(audit, out)
    assert not out.exists()


def test_a_link_of_infinite_inertia_leaves_the_read_back_check_of_the_others(
    tmp_path: Path,
) -> None:
    # 1.5e308 ± 1e308 turned 45° about z: an entry past float64's range.
    huge = """  <link name="huge">
    <inertial>
      <origin xyz="0 0 0" rpy="0 0 0.7853981633974483"/>
      <mass value="1.0"/>
      <inertia ixx="1.5e308" ixy="1e308" ixz="0" iyy="1.5e308" iyz="0" izz="1e308"/>
    </inertial>
  </link>
  <joint name="weld" type="fixed"><parent link="hand"/><child link="huge"/></joint>
</robot>"""
    text = EXAMPLE.replace("</robot>", huge)
    source = robot_file(tmp_path, text)
    audit = tb.robots.audit(source)
    assert not np.all(np.isfinite(audit.robot.links["huge"].inertia))
    # The base's inertia changed after the audit: the copy would carry it.
    source.write_text(text.replace('ixx="0.0333333"', 'ixx="0.05"'), encoding="utf-8")
    with pytest.raises(
        tb.InputError,
        match=r"^Expected link 'base' of the corrected copy of '.*arm\.urdf' to read back with its "
        r"former values, got inertia \[\[0\.05, .*nothing was written\.$",
    ):
        write_corrected(audit, tmp_path / "fixed.urdf")
    assert not (tmp_path / "fixed.urdf").exists()


def test_an_mjcf_correction_mujoco_refuses_for_its_body_is_never_written(tmp_path: Path) -> None:
    mujoco = pytest.importorskip("mujoco")
    text = MJCF.replace(
        'diaginertia="0.0333333 0.0333333 0.06"', 'diaginertia="0.0333333 0.0333333 6"'
    )
    source = robot_file(tmp_path, text, "two.xml")
    # A correction the audit finds nothing in (no mass, no inertia) but MuJoCo
    # refuses for the moving base: neither the source nor the copy compiles.
    correction = dict.fromkeys(("mass", "ixx", "ixy", "ixz", "iyy", "iyz", "izz"), 0.0)
    finding = Finding("base", "power-of-ten", "error", "a slipped izz", correction)
    audit = tb.robots.Audit(tb.robots.load(source), "none", (finding,))
    out = tmp_path / "fixed.xml"
    with pytest.raises(
        tb.InputError,
        match=r"^Expected body 'base' of the corrected copy of '.*two\.xml' to compile in MuJoCo, "
        r"got: mass and inertia of moving bodies must be larger than mjMINVAL; Element name "
        r"'base', id 1, line \d+\. Nothing was written\.$",
    ):
        write_corrected(audit, out)
    assert not out.exists()
    with pytest.raises(ValueError, match="inertia"):
        mujoco.MjModel.from_xml_path(str(source))


def test_an_unnamed_mjcf_body_is_refused_as_one_without_a_name(tmp_path: Path) -> None:
    pytest.importorskip("mujoco")
    source = robot_file(
        tmp_path,
        '<mujoco><worldbody><body><joint type="hinge"/><inertial pos="0 0 0" mass="1" '
        'diaginertia="0.01 0.01 0.9"/><geom type="sphere" size="0.1"/></body></worldbody>'
        "</mujoco>",
        "unnamed.xml",
    )
    audit = tb.robots.audit(source)
    assert "body 1" in audit.corrections()
    with pytest.raises(
        tb.InputError,
        match=r"^Expected body 'body 1' written in unnamed\.xml to correct it, got a body without "
        r"a name, which cannot be found in the file: name it\.$",
    ):
        write_corrected(audit, tmp_path / "fixed.xml")
