"""The audit's judgement of declared inertias: tensors the engines refuse as
written (round-off), a mesh's unit from its density, the form and axes of a
tensor against its shapes, and numbers at the edge of float64."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

import tumble as tb
from robot_files import slipped
from tumble.robots import example_path, write_corrected
from tumble.robots.tensors import nearest_accepted, principal_moments, refusals

EXAMPLE = example_path().read_text(encoding="utf-8")
HAND = 'ixx="0.0005" ixy="0" ixz="0" iyy="0.0005" iyz="0" izz="0.0005"'
ARM = 'ixx="0.0271167" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.0009"'
ATTRIBUTES = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def robot_file(tmp_path: Path, text: str, name: str = "arm.urdf") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def codes(audit: tb.robots.Audit) -> list[tuple[str, str]]:
    return [(f.link, f.code) for f in audit.findings]


def mujoco_refusal(values: dict[str, float] | tuple[str, ...]) -> str:
    """MuJoCo's own compiler on a free body with this full inertia: its error's
    first line, or "" where it loads the body."""
    mujoco = pytest.importorskip("mujoco")
    texts = values if isinstance(values, tuple) else tuple(repr(values[a]) for a in ATTRIBUTES)
    xx, xy, xz, yy, yz, zz = texts
    xml = (
        '<mujoco><worldbody><body><freejoint/><inertial pos="0 0 0" mass="1" '
        f'fullinertia="{xx} {yy} {zz} {xy} {xz} {yz}"/></body></worldbody></mujoco>'
    )
    try:
        mujoco.MjModel.from_xml_string(xml)
    except ValueError as error:
        return str(error).splitlines()[0]
    return ""


def chain(tensors: list[tuple[str, ...]]) -> str:
    """A URDF of one link per tensor (written texts), joined by fixed joints."""
    links = "".join(
        f'<link name="l{i}"><inertial><mass value="1"/><inertia '
        + " ".join(f'{a}="{t}"' for a, t in zip(ATTRIBUTES, texts, strict=True))
        + "/></inertial></link>"
        for i, texts in enumerate(tensors)
    )
    joints = "".join(
        f'<joint name="j{i}" type="fixed"><parent link="l{i - 1}"/><child link="l{i}"/></joint>'
        for i in range(1, len(tensors))
    )
    return f'<?xml version="1.0"?><robot name="many">{links}{joints}</robot>'


# ------------------------------------------------------------------ round-off
def test_a_tensor_the_engines_refuse_as_written_is_a_round_off_warning(tmp_path: Path) -> None:
    written = 'ixx="0.010" ixy="0" ixz="0" iyy="0.010" iyz="0" izz="0.0201"'
    source = robot_file(tmp_path, EXAMPLE.replace(HAND, written))
    # Oracles: MuJoCo's compiler and tumble's MassProperties refuse it as written.
    assert "A + B >= C" in mujoco_refusal(("0.010", "0", "0", "0.010", "0", "0.0201"))
    with pytest.raises(tb.InputError, match="triangle inequality"):
        tb.MassProperties(0.5, [0, 0, 0], np.diag([0.010, 0.010, 0.0201]))
    audit = tb.robots.audit(source, geometry="none")
    assert codes(audit) == [("hand", "round-off")]
    (finding,) = audit.findings
    assert finding.severity == "warning" and audit.errors == ()
    assert "falls short of I3 by 0.0001" in finding.message
    assert "MuJoCo" in finding.message and "MassProperties" in finding.message
    correction = finding.correction
    assert correction is not None and set(correction) == set(ATTRIBUTES)
    # The nearest accepted tensor keeps the axes and moves each moment by a third
    # of the shortfall (1e-4 / 3), far within the written digits' 5e-5 each.
    assert_allclose([correction[a] for a in ("ixx", "iyy", "izz")],
                    [0.010 + 1e-4 / 3, 0.010 + 1e-4 / 3, 0.0201 - 1e-4 / 3], atol=1e-11)  # fmt: skip
    assert correction["ixy"] == correction["ixz"] == correction["iyz"] == 0.0
    assert mujoco_refusal(correction) == ""
    tb.MassProperties(0.5, [0, 0, 0], np.diag([correction[a] for a in ("ixx", "iyy", "izz")]))
    # The corrected copy audits clean, and the corrections choose this one.
    assert audit.corrections() == {"hand": correction}
    fixed = write_corrected(audit, tmp_path / "fixed.urdf")
    assert tb.robots.audit(fixed, geometry="none").findings == ()


def test_a_round_off_beyond_the_written_digits_stays_an_error(tmp_path: Path) -> None:
    written = 'ixx="0.010000" ixy="0" ixz="0" iyy="0.010000" iyz="0" izz="0.020100"'
    audit = tb.robots.audit(robot_file(tmp_path, EXAMPLE.replace(HAND, written)), geometry="none")
    assert codes(audit)[0] == ("hand", "triangle-inequality")
    assert "round-off" not in [c for _, c in codes(audit)]


def test_no_tensor_mujoco_or_massproperties_refuses_audits_clean(tmp_path: Path) -> None:
    # Random bodies near the boundary I1 + I2 = I3 (thin plates, off by a few
    # digits), turned at random and written with 3 to 8 significant digits.
    # Oracles: MuJoCo's compiler on each tensor as written, and MassProperties.
    rng = np.random.default_rng(7)
    tensors = []
    for k in range(60):
        a, b = rng.uniform(0.2, 1.0, 2) * 10.0 ** rng.integers(-6, 1)
        c = (a + b) * (1 + rng.uniform(-3e-3, 3e-3))
        turn = Rotation.random(random_state=k).as_matrix() if k % 2 else np.eye(3)
        tensor = turn @ np.diag([a, b, c]) @ turn.T
        digits = int(rng.integers(3, 9))
        tensors.append(tuple(f"{tensor[i, j]:.{digits}g}" for i, j in
                             ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))))  # fmt: skip
    audit = tb.robots.audit(robot_file(tmp_path, chain(tensors)), geometry="none")
    flagged = {f.link for f in audit.findings}
    refused = accepted = 0
    for i, texts in enumerate(tensors):
        by_mujoco = mujoco_refusal(texts) != ""
        values = [float(t) for t in texts]
        matrix = np.array(
            [values[0:3], [values[1], *values[3:5]], [values[2], values[4], values[5]]]
        )
        try:
            tb.MassProperties(1.0, [0, 0, 0], matrix)
            by_tumble = False
        except tb.InputError:
            by_tumble = True
        if by_mujoco or by_tumble:
            refused += 1
            assert f"l{i}" in flagged, (texts, mujoco_refusal(texts))
        else:  # both load it: no round-off warning, no finding at all
            accepted += 1
            assert f"l{i}" not in flagged, (texts, audit.findings)
        if by_tumble:  # the audit and `tumble inertia` agree on what is physical
            assert refusals(values), texts
    assert refused > 15 and accepted > 15  # the sample straddles the boundary


def test_every_correction_is_accepted_by_mujoco_and_massproperties() -> None:
    rng = np.random.default_rng(3)
    for k in range(40):
        a, b = rng.uniform(0.1, 1.0, 2)
        turn = Rotation.random(random_state=k).as_matrix()
        tensor = turn @ np.diag([a, b, (a + b) * (1 + 1e-4)]) @ turn.T
        values = [tensor[i, j] for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))]
        correction = nearest_accepted(values)
        assert correction is not None
        assert mujoco_refusal(correction) == ""
        assert refusals(list(correction.values())) == ()
        fixed = np.array([[correction[n] for n in row] for row in
                          (("ixx", "ixy", "ixz"), ("ixy", "iyy", "iyz"), ("ixz", "iyz", "izz"))])  # fmt: skip
        # Nearest: the moments move by a third of the shortfall, 1e-4 (a + b) / 3,
        # plus the margin and the twelve digits (1e-9 of the trace).
        assert np.linalg.norm(fixed - tensor) == pytest.approx(
            math.sqrt(3) * 1e-4 * (a + b) / 3, rel=1e-4
        )


def test_a_tiny_tensor_the_engines_refuse_is_not_taken_for_a_clean_zero(tmp_path: Path) -> None:
    # Entries of 5e-14 beside the base's 0.06 kg·m² are below the zero floor
    # (1e-12 of it: a zero written with round-off, not judged as a body's), yet
    # MuJoCo loads it as written and refuses it: 1e-14 + 1e-14 < 5e-14.
    texts = ("1e-14", "0", "0", "1e-14", "0", "5e-14")
    assert "A + B >= C" in mujoco_refusal(texts)
    with pytest.raises(tb.InputError, match="triangle inequality"):
        tb.MassProperties(0.5, [0, 0, 0], np.diag([1e-14, 1e-14, 5e-14]))
    written = " ".join(f'{a}="{t}"' for a, t in zip(ATTRIBUTES, texts, strict=True))
    audit = tb.robots.audit(slipped(tmp_path, HAND, written), geometry="none")
    assert codes(audit) == [("hand", "round-off")]
    (finding,) = audit.findings
    assert finding.severity == "warning" and "zero written with round-off" in finding.message
    correction = finding.correction
    assert correction is not None and mujoco_refusal(correction) == ""
    fixed = write_corrected(audit, tmp_path / "fixed.urdf")
    assert tb.robots.audit(fixed, geometry="none").findings == ()
    # A zero as tiny that every engine loads stays unsaid.
    accepted = 'ixx="2e-14" ixy="0" ixz="0" iyy="2e-14" iyz="0" izz="2e-14"'
    assert mujoco_refusal(("2e-14", "0", "0", "2e-14", "0", "2e-14")) == ""
    audit = tb.robots.audit(slipped(tmp_path, HAND, accepted, "ball.urdf"), geometry="none")
    assert audit.findings == ()


def test_a_decimal_point_correction_the_engines_refuse_is_carried_to_one_they_accept(
    tmp_path: Path,
) -> None:
    # izz = 0.301 for 0.0301: moved back, 0.010 + 0.020 falls 1e-4 short of
    # 0.0301, physical only within the written digits' rounding, and MuJoCo
    # refuses it as written. The one move of a decimal point is still named, but
    # the correction must be one the engines load.
    written = 'ixx="0.010" ixy="0" ixz="0" iyy="0.020" iyz="0" izz="0.301"'
    assert "A + B >= C" in mujoco_refusal(("0.010", "0", "0", "0.020", "0", "0.0301"))
    audit = tb.robots.audit(slipped(tmp_path, HAND, written), geometry="none")
    assert codes(audit) == [("hand", "triangle-inequality"), ("hand", "power-of-ten")]
    finding = audit.findings[1]
    assert "Writing izz = 0.0301" in finding.message and "refuse" in finding.message
    correction = finding.correction
    assert correction is not None and mujoco_refusal(correction) == ""
    # Oracle: the nearest accepted tensor to (0.010, 0.020, 0.0301) moves each
    # moment by a third of the 1e-4 shortfall.
    assert_allclose([correction[a] for a in ("ixx", "iyy", "izz")],
                    [0.010 + 1e-4 / 3, 0.020 + 1e-4 / 3, 0.0301 - 1e-4 / 3], atol=1e-11)  # fmt: skip
    fixed = write_corrected(audit, tmp_path / "fixed.urdf")
    assert tb.robots.audit(fixed, geometry="none").findings == ()


def test_no_correction_is_offered_that_the_engines_still_refuse() -> None:
    # Entries of 1.5e308: the nearest tensor with I1 + I2 >= I3 has entries past
    # float64's largest, which no engine loads. No correction, not a refused one.
    values = [1.5e308, 0.0, 1.5e308, 1e308, 1.5e308, 1.5e308]
    assert refusals(values)
    assert nearest_accepted(values) is None


# ------------------------------------------------------------------ units of a mesh
def test_a_mesh_in_centimetres_is_said_to_be_in_centimetres(tmp_path: Path) -> None:
    import trimesh

    trimesh.creation.box(extents=[30, 30, 10]).export(tmp_path / "base.stl")
    source = robot_file(
        tmp_path,
        EXAMPLE.replace(
            '<geometry><box size="0.3 0.3 0.1"/></geometry>',
            '<geometry><mesh filename="base.stl"/></geometry>',
        ),
    )
    audit = tb.robots.audit(source)
    assert codes(audit) == [("base", "implausible-density")]
    # Oracle: 4 kg in a 0.3 x 0.3 x 0.1 m box is 444 kg/m³; read in metres the
    # volume is 1e6 times too large.
    assert "centimetres read as metres" in audit.findings[0].message
    assert "density is 444.4 kg/m³" in audit.findings[0].message


# ------------------------------------------------------------------ form and axes
def test_a_cylinder_declared_along_x_whose_shape_lies_along_z_is_found(tmp_path: Path) -> None:
    # The arm's cylinder lies along z; its tensor written about x instead.
    turned = 'ixx="0.0009" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.0271167"'
    audit = tb.robots.audit(robot_file(tmp_path, EXAMPLE.replace(ARM, turned)))
    assert codes(audit) == [("arm", "geometry-mismatch")]
    (finding,) = audit.findings
    assert "smallest moment ((1, 0, 0), link axes) lies 90° from its shapes' ((0, 0, 1))" in (
        finding.message
    )
    # The correction is the shapes' tensor: the cylinder's textbook moments.
    assert finding.correction is not None
    m, r, h = 2.0, 0.03, 0.4
    assert finding.correction["izz"] == pytest.approx(m * r * r / 2, rel=1e-5)
    assert finding.correction["ixx"] == pytest.approx(m * (3 * r * r + h * h) / 12, rel=1e-5)
    # Turned by the inertial frame to where the shape lies, the same numbers match.
    aligned = EXAMPLE.replace(ARM, turned).replace(
        '<origin xyz="0 0 0.2" rpy="0 0 0"/>\n      <mass value="2.0"/>',
        '<origin xyz="0 0 0.2" rpy="0 1.5707963267948966 0"/>\n      <mass value="2.0"/>',
    )
    assert tb.robots.audit(robot_file(tmp_path, aligned, "aligned.urdf")).findings == ()


def test_a_disc_declared_for_a_rod_is_another_form(tmp_path: Path) -> None:
    # Same sum of moments as the arm's cylinder (0.0551 kg·m²), shares of a disc.
    disc = 'ixx="0.0137833" ixy="0" ixz="0" iyy="0.0137833" iyz="0" izz="0.0275666"'
    audit = tb.robots.audit(robot_file(tmp_path, EXAMPLE.replace(ARM, disc)))
    assert codes(audit) == [("arm", "geometry-mismatch")]
    assert "shares of their sum, (0.25, 0.25, 0.5)" in audit.findings[0].message


def turned_base(axis: str, angle: float) -> str:
    """The base's declared tensor turned by ``angle`` (rad) about ``axis``, written
    with nine digits."""
    turn = Rotation.from_euler(axis, angle).as_matrix()
    tensor = turn @ np.diag([0.0333333, 0.0333333, 0.06]) @ turn.T
    return " ".join(f'{a}="{tensor[i, j]:.9g}"' for a, (i, j) in
                    zip(ATTRIBUTES, ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)), strict=True))  # fmt: skip


def test_axes_of_near_equal_moments_are_not_compared(tmp_path: Path) -> None:
    # The base's box (0.3 x 0.3 x 0.1) has two equal moments: turned about z, the
    # axis of the third, its tensor is the same, so a declared tensor turned so
    # matches its shapes.
    base = 'ixx="0.0333333" ixy="0" ixz="0" iyy="0.0333333" iyz="0" izz="0.06"'
    audit = tb.robots.audit(slipped(tmp_path, base, turned_base("z", 0.7)))
    assert audit.findings == ()
    # Turned about x, the turn mixes unequal moments (shares 0.263 and 0.474 of
    # the sum): the tensors over their traces then differ by 0.211 sin(angle),
    # beyond 0.18 at 1.2 rad (0.196), within it at 0.7 rad (0.136).
    audit = tb.robots.audit(slipped(tmp_path, base, turned_base("x", 1.2), "x.urdf"))
    assert codes(audit) == [("base", "geometry-mismatch")]
    assert "largest moment" in audit.findings[0].message
    assert "69° from its shapes'" in audit.findings[0].message
    assert tb.robots.audit(slipped(tmp_path, base, turned_base("x", 0.7), "y.urdf")).findings == ()


def test_a_box_of_three_sides_declared_turned_is_found_though_no_moment_stands_far_apart(
    tmp_path: Path,
) -> None:
    # A 0.38 x 0.27 x 0.18 m box of 4 kg: moments m (b² + c²) / 12 and so on,
    # shares of their sum (0.211, 0.354, 0.435), none more than 0.15 from
    # another. Declared with x and z exchanged (a 90° turn about y), the tensors
    # over their traces differ by 0.435 - 0.211 = 0.224 (spectral norm).
    box = '<geometry><box size="0.38 0.27 0.18"/></geometry>'
    shaped = EXAMPLE.replace('<geometry><box size="0.3 0.3 0.1"/></geometry>', box)
    assert box in shaped
    base = 'ixx="0.0333333" ixy="0" ixz="0" iyy="0.0333333" iyz="0" izz="0.06"'
    right = 'ixx="0.0351" ixy="0" ixz="0" iyy="0.0589333" iyz="0" izz="0.0724333"'
    assert tb.robots.audit(robot_file(tmp_path, shaped.replace(base, right))).findings == ()
    turned = 'ixx="0.0724333" ixy="0" ixz="0" iyy="0.0589333" iyz="0" izz="0.0351"'
    audit = tb.robots.audit(robot_file(tmp_path, shaped.replace(base, turned), "turned.urdf"))
    assert codes(audit) == [("base", "geometry-mismatch")]
    message = audit.findings[0].message
    assert "smallest moment ((0, 0, 1), link axes) lies 90° from its shapes' ((1, 0, 0))" in message
    assert "differ by 0.22 (spectral norm" in message
    assert audit.findings[0].correction is not None
    assert audit.findings[0].correction["ixx"] == pytest.approx(0.0351, rel=1e-4)


# ------------------------------------------------------------------ float64's edge
HUGE = 'ixx="1e308" ixy="1e308" ixz="0" iyy="1e308" iyz="1e308" izz="1e308"'


def test_huge_inertias_are_judged_without_a_traceback(tmp_path: Path) -> None:
    audit = tb.robots.audit(robot_file(tmp_path, EXAMPLE.replace(HAND, HUGE)))
    # Moments (1 − √2, 1, 1 + √2) × 1e308: a negative one, no body.
    assert ("hand", "not-positive-definite") in codes(audit)
    assert_allclose(principal_moments([1e308, 1e308, 0, 1e308, 1e308, 1e308])[:2],
                    [(1 - math.sqrt(2)) * 1e308, 1e308], rtol=1e-12)  # fmt: skip
    # A valid tensor of 1e308 on a link of 1 kg: far from its shapes, not a crash.
    huge = 'ixx="1e308" ixy="0" ixz="0" iyy="1e308" iyz="0" izz="1e308"'
    audit = tb.robots.audit(robot_file(tmp_path, EXAMPLE.replace(HAND, huge), "valid.urdf"))
    assert codes(audit) == [("hand", "geometry-mismatch")]
    assert audit.links[2].moments[0] == 1e308
    # Declared values turned by an inertial frame, beyond float64 in link axes.
    turned = EXAMPLE.replace(HAND, huge.replace('ixy="0"', 'ixy="1e307"')).replace(
        '<inertial>\n      <mass value="0.5"/>',
        '<inertial>\n      <origin xyz="0 0 0" rpy="0.3 0.2 0.1"/>\n      <mass value="0.5"/>',
    )
    assert 'rpy="0.3 0.2 0.1"' in turned
    audit = tb.robots.audit(robot_file(tmp_path, turned, "turned.urdf"))
    assert [c for _, c in codes(audit)] == ["geometry-mismatch"]


def test_huge_inertias_on_the_command_line_give_findings_not_a_traceback(
    tmp_path: Path,
) -> None:
    from tumble.cli import app

    source = robot_file(tmp_path, EXAMPLE.replace(HAND, HUGE))
    result = CliRunner().invoke(app, ["audit", str(source)])
    assert result.exit_code == 1, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert "not-positive-definite" in result.output and "Traceback" not in result.output
    mass = EXAMPLE.replace('<mass value="0.5"/>', '<mass value="1e308"/>')
    result = CliRunner().invoke(app, ["audit", str(robot_file(tmp_path, mass, "mass.urdf"))])
    assert result.exit_code == 0, result.output
    assert "geometry-unavailable" in result.output and "Traceback" not in result.output


def test_an_unreadable_inertial_is_not_compared_with_its_shapes(tmp_path: Path) -> None:
    # Its mass is unknown, not 0: no "massless" warning beside the reader's error.
    source = robot_file(tmp_path, EXAMPLE.replace('izz="0.0009"', 'izz="1.2.3"'))
    audit = tb.robots.audit(source)
    assert [c for link, c in codes(audit) if link == "arm"] == ["unreadable-inertial"]
