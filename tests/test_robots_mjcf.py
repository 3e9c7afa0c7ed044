"""The MJCF reader: MuJoCo's compiled mass properties, the digits written, files
that are not regular files, models too large to compile, one-line messages."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import tumble as tb
from robot_files import mujocos_inertia
from tumble.errors import RequestTooLargeError
from tumble.robots.mjcf import MAX_BODIES, MAX_GEOMS
from tumble.robots.model import Inertial, Robot

mujoco = pytest.importorskip("mujoco")


def mjcf(folder: Path, body: str, name: str = "robot.xml", head: str = "") -> Path:
    path = folder / name
    path.write_text(f"<mujoco>{head}<worldbody>{body}</worldbody></mujoco>", encoding="utf-8")
    return path


def declared(robot: Robot, name: str) -> Inertial:
    inertial = robot.links[name].inertial
    assert inertial is not None
    return inertial


def mujocos_whole_robot(
    path: Path, values: dict[str, float]
) -> tuple[float, np.ndarray, np.ndarray]:
    """Oracle: MuJoCo's compiled model at ``values`` (hinge and slide joints by name):
    mj_kinematics, then the total of body_mass, the world body's subtree_com and
    the inertia about it (:func:`robot_files.mujocos_inertia`)."""
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    for name, value in values.items():
        data.qpos[model.jnt_qposadr[model.joint(name).id]] = value
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    mass = float(model.body_mass.sum())
    centre = np.array(data.subtree_com[0])
    return mass, centre, mujocos_inertia(model, data, centre)


def assert_as_mujoco(path: Path, values: dict[str, float]) -> None:
    mass, centre, inertia = mujocos_whole_robot(path, values)
    ours = tb.robots.load(path).mass_properties(values)
    # 1e-12 relative: both sum the same float64 masses; 1e-9 of the largest
    # entry for the centre and the tensor: the same few products of rotations,
    # composed in another order, each to a few ε.
    assert ours.mass == pytest.approx(mass, rel=1e-12)
    assert_allclose(ours.center_of_mass, centre, atol=1e-9 * max(1.0, np.abs(centre).max()))
    assert_allclose(ours.inertia, inertia, atol=1e-9 * np.abs(inertia).max())


ARM = """
<body name="base" pos="0 0 0.1">
  <inertial pos="0.01 0 0" quat="0.9 0.1 0.2 0.3" mass="5" diaginertia="0.05 0.04 0.03"/>
  <geom type="box" size="0.1 0.1 0.05" mass="1"/>
  <body name="arm" pos="0 0 0.2">
    <joint name="shoulder" type="hinge" axis="0 1 0"/>
    <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/>
    <body name="hand" pos="0.3 0 0">
      <joint name="slide" type="slide" axis="1 0 0"/>
      <inertial pos="0.02 0.01 0" mass="0.5"
                fullinertia="0.002 0.003 0.004 0.0001 -0.0002 0.0003"/>
    </body>
  </body>
</body>
"""

POSE = {"shoulder": 0.7, "slide": 0.05}


SETTOTALMASS = "ignore:compiler attribute 'settotalmass' is deprecated"


@pytest.mark.filterwarnings(SETTOTALMASS)
@pytest.mark.parametrize(
    ("compiler", "total"),
    [
        # MuJoCo takes the geoms instead of the <inertial> of the bodies that
        # have geoms: 1 + 1 kg, and the hand's 0.5 kg (it has no geoms).
        ('<compiler inertiafromgeom="true"/>', 2.5),
        # Every body's mass and inertia scaled to sum to 10 kg.
        ('<compiler settotalmass="10"/>', 10.0),
        ('<compiler boundmass="2" boundinertia="0.01"/>', None),
        ('<compiler fusestatic="true"/>', None),
        ("", 6.5),
    ],
)
def test_whole_robot_is_mujocos_compiled_model_at_a_pose(
    tmp_path: Path, compiler: str, total: float | None
) -> None:
    path = mjcf(tmp_path, ARM, head=compiler)
    assert_as_mujoco(path, POSE)
    if total is not None:
        assert tb.robots.load(path).mass_properties(POSE).mass == pytest.approx(total, rel=1e-12)


#: Two 1 kg boxes of geoms, the first declaring 5 kg: MuJoCo's model has 2 kg
#: with inertiafromgeom (the geoms alone) and 10 kg with settotalmass="10".
REPORTED = """
<body name="a" pos="0 0 1">
  <joint name="j1" type="hinge" axis="0 1 0"/>
  <inertial pos="0 0 0" mass="5" diaginertia="0.1 0.1 0.1"/>
  <geom type="box" size="0.1 0.1 0.1" mass="1"/>
  <body name="b" pos="0.5 0 0">
    <joint name="j2" type="hinge" axis="0 1 0"/>
    <geom type="box" size="0.1 0.1 0.1" mass="1"/>
  </body>
</body>
"""


@pytest.mark.filterwarnings(SETTOTALMASS)
@pytest.mark.parametrize(
    ("compiler", "total"),
    [('<compiler inertiafromgeom="true"/>', 2.0), ('<compiler settotalmass="10"/>', 10.0)],
)
def test_the_reported_files_are_mujocos_compiled_model(
    tmp_path: Path, compiler: str, total: float
) -> None:
    path = mjcf(tmp_path, REPORTED, head=compiler)
    pose = {"j1": -0.4, "j2": 1.1}
    assert_as_mujoco(path, pose)
    assert tb.robots.load(path).mass_properties(pose).mass == pytest.approx(total, rel=1e-12)


@pytest.mark.filterwarnings(SETTOTALMASS)
def test_each_body_keeps_its_declared_inertial_beside_mujocos_compiled_one(tmp_path: Path) -> None:
    path = mjcf(tmp_path, REPORTED, head='<compiler settotalmass="10"/>')
    robot = tb.robots.load(path)
    links = robot.links
    model = mujoco.MjModel.from_xml_path(str(path))
    # The audit judges the 5 kg written; the whole robot sums MuJoCo's 10 × 5/6 kg.
    assert declared(robot, "a").mass == 5.0
    for i, name in ((1, "a"), (2, "b")):
        compiled = links[name].compiled
        assert compiled is not None
        # Exactly: both are MuJoCo's float64 values, copied.
        assert compiled.mass == model.body_mass[i]
        assert_allclose(np.diag(compiled.tensor), model.body_inertia[i], rtol=0, atol=0)
        assert links[name].counted().inertial is compiled
    # A URDF's links are counted as declared.
    arm = tb.robots.load(tb.robots.example_path()).links["arm"]
    assert arm.compiled is None and arm.counted() is arm


GYMNASIUM_MODELS = ("humanoid", "ant", "half_cheetah", "walker2d", "hopper", "swimmer", "reacher")


@pytest.mark.filterwarnings(SETTOTALMASS)  # half_cheetah's
@pytest.mark.parametrize("name", GYMNASIUM_MODELS)
def test_gymnasium_models_are_mujocos_compiled_model_at_a_pose(name: str) -> None:
    gymnasium = pytest.importorskip("gymnasium")
    path = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / f"{name}.xml"
    model = mujoco.MjModel.from_xml_path(str(path))
    rng = np.random.default_rng(7)
    values = {
        model.joint(j).name: float(rng.uniform(-0.8, 0.8))
        for j in range(model.njnt)
        if model.jnt_type[j] in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE)
    }
    assert_as_mujoco(path, values)


@pytest.mark.filterwarnings(SETTOTALMASS)
def test_declared_values_stay_as_written_where_the_compiler_changes_them(tmp_path: Path) -> None:
    # settotalmass scales the base's 5 kg, but the audit judges the digits of
    # the file: the link keeps them, and its shapes keep their own masses.
    robot = tb.robots.load(mjcf(tmp_path, ARM, head='<compiler settotalmass="10"/>'))
    base = robot.links["base"]
    assert base.mass == 5.0
    assert base.inertial is not None
    assert base.inertial.texts == ("0.05", "0", "0", "0.04", "0", "0.03")
    assert base.geometry().mass == pytest.approx(1.0)
    # The arm's values are MuJoCo's (from its geom), scaled as MuJoCo scales
    # them, and so is its geometry: they agree.
    arm = robot.links["arm"]
    assert arm.geometry().mass == pytest.approx(arm.mass, rel=1e-12)
    assert arm.mass == pytest.approx(10.0 / 6.5, rel=1e-12)


def test_inertia_texts_are_the_digits_written(tmp_path: Path) -> None:
    # MuJoCo refuses this tensor (0.010 + 0.010 < 0.0201); the audit judges
    # the digits as written, so they are kept, in URDF's order.
    (tmp_path / "part.xml").write_text(
        '<mujoco><body name="c" pos="0 0 1"><joint type="hinge"/><inertial pos="0 0 0" '
        'mass="1" fullinertia="3.0e-2 2.50E-2 0.0200 1e-3 -0.0 +2e-3"/></body></mujoco>',
        encoding="utf-8",
    )
    body = (
        '<body name="a"><joint type="hinge"/>'
        '<inertial pos="0 0 0" mass="1" diaginertia="0.010  0.010 0.0201"/></body>'
        '<body name="b"><joint type="hinge"/><geom type="sphere" size="0.1"/></body>'
        '<include file="part.xml"/>'
    )
    robot = tb.robots.load(mjcf(tmp_path, body))
    assert declared(robot, "a").texts == ("0.010", "0", "0", "0.010", "0", "0.0201")
    assert declared(robot, "c").texts == (
        "3.0e-2",
        "1e-3",
        "-0.0",
        "2.50E-2",
        "+2e-3",
        "0.0200",
    )
    assert declared(robot, "c").values == (0.03, 0.001, -0.0, 0.025, 0.002, 0.02)
    # Computed by MuJoCo from a geom: no digits written, its float64 values.
    texts = declared(robot, "b").texts
    assert [float(t) for t in texts] == list(declared(robot, "b").values)
    # Judged on those digits: a shortfall the rounding of 0.010 may explain
    # (0.0095 + 0.0105 >= 0.0201 for digits that round to them).
    codes = {f.code for f in tb.robots.audit(robot.path).findings if f.link == "a"}
    assert codes == {"round-off"}


def test_unnamed_bodies_keep_their_own_declared_values(tmp_path: Path) -> None:
    body = "".join(
        f'<body><joint type="hinge"/><inertial pos="0 0 0" mass="{m}" diaginertia="1 1 1"/></body>'
        for m in (1, 2, 3)
    )
    robot = tb.robots.load(mjcf(tmp_path, body))
    assert [link.mass for link in robot.links.values()] == [0.0, 1.0, 2.0, 3.0]


def load_in_a_child(path: Path) -> subprocess.CompletedProcess[str]:
    # A FIFO without a writer blocks whoever opens it: the load runs in a child
    # so that a reader that opens it makes the test fail, not hang.
    code = textwrap.dedent(f"""
        import tumble as tb
        from tumble.robots.mjcf import read_mjcf
        try:
            read_mjcf({str(path)!r})
        except tb.InputError as error:
            print(type(error).__name__, error)
    """)
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=False
    )


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are POSIX's")
def test_an_included_fifo_is_refused_before_mujoco_opens_it(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "fifo.xml")
    path = mjcf(tmp_path, '<include file="fifo.xml"/><body name="b"><geom size="0.1"/></body>')
    result = load_in_a_child(path)
    assert result.stdout.splitlines() == [
        f"InputError Expected the file of an <include> in '{path}' to be a regular file, "
        f"got '{tmp_path / 'fifo.xml'}', which is not a regular file (a FIFO)."
    ]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are POSIX's")
@pytest.mark.parametrize(
    ("head", "file"),
    [
        ('<asset><mesh name="m" file="fifo.stl"/></asset>', "fifo.stl"),
        ('<compiler meshdir="meshes"/><asset><mesh name="m" file="fifo.stl"/></asset>',
         "meshes/fifo.stl"),
        ('<asset><texture name="t" type="2d" file="fifo.png"/></asset>', "fifo.png"),
        ('<asset><hfield name="h" file="fifo.png" size="1 1 1 1"/></asset>', "fifo.png"),
    ],
)  # fmt: skip
def test_an_asset_file_that_is_a_fifo_is_refused(tmp_path: Path, head: str, file: str) -> None:
    (tmp_path / "meshes").mkdir()
    os.mkfifo(tmp_path / file)
    path = mjcf(tmp_path, '<body name="b"><geom size="0.1"/></body>', head=head)
    element = head.split("<")[-2].split()[0]
    result = load_in_a_child(path)
    assert result.stdout.splitlines() == [
        f"InputError Expected the file of a <{element}> in '{path}' to be a regular file, "
        f"got '{tmp_path / file}', which is a FIFO."
    ]


def test_a_device_as_a_mesh_is_refused(tmp_path: Path) -> None:
    path = mjcf(
        tmp_path,
        '<body name="b"><geom type="mesh" mesh="m"/></body>',
        head='<asset><mesh name="m" file="/dev/zero"/></asset>',
    )
    with pytest.raises(
        tb.InputError,
        match=r"^Expected the file of a <mesh> in '.*robot\.xml' to be a regular file, got "
        r"'/dev/zero', which is a character device\.$",
    ):
        tb.robots.load(path)


@pytest.mark.parametrize(
    ("body", "what", "count"),
    [
        # 10⁵ bodies, 8 MB: minutes in MuJoCo's parser.
        ('<body pos="0 0 1"><geom type="sphere" size="0.1"/></body>' * 100_000, "bodies", 100000),
        ('<replicate count="1000" offset="1 0 0"><body><geom size="0.1"/></body>'
         '<body><geom size="0.1"/></body></replicate>' * 5, "bodies", 10000),
        ('<body><geom size="0.1"/></body>' + '<geom size="0.1"/>' * 30_000, "geoms", 30001),
    ],
)  # fmt: skip
def test_a_model_too_large_to_compile_is_refused_before_mujoco_reads_it(
    tmp_path: Path, body: str, what: str, count: int
) -> None:
    path = mjcf(tmp_path, body)
    bound = MAX_BODIES if what == "bodies" else MAX_GEOMS
    with pytest.raises(
        RequestTooLargeError,
        match=rf"^Expected an MJCF model of at most {bound} {what} \(MuJoCo's parser takes a time "
        rf"growing as the square of their number\), got {count} in '.*robot\.xml'\.$",
    ):
        tb.robots.load(path)


def test_a_model_at_the_bound_is_read(tmp_path: Path) -> None:
    body = '<body><joint type="hinge"/><geom type="sphere" size="0.1" mass="1"/></body>'
    robot = tb.robots.load(mjcf(tmp_path, body * 1000))
    assert robot.mass_properties().mass == pytest.approx(1000.0)


def test_mesh_files_beyond_the_memory_budget_are_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A sparse file: 1 GiB declared, nothing written.
    with open(tmp_path / "huge.stl", "wb") as file:
        file.truncate(2**30)
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "1 GiB")
    path = mjcf(
        tmp_path,
        '<body name="b"><geom type="mesh" mesh="m"/></body>',
        head='<asset><mesh name="m" file="huge.stl"/></asset>',
    )
    with pytest.raises(
        RequestTooLargeError,
        match=r"^Expected a request that fits in the memory budget of 1 GiB .*, got an MJCF model "
        r"of \d+ bytes of files for MuJoCo to read: about 16 GiB\. Simplify its meshes\.$",
    ):
        tb.robots.load(path)


@pytest.mark.parametrize(
    ("body", "message"),
    [
        # Parsed: MuJoCo's message names the element and its line on a second line.
        ('<body name="b"><inertial mass="1" diaginertia="1 1 1"/></body>',
         r"^Expected an MJCF model in '.*robot\.xml', got: XML Error: required attribute "
         r"missing: 'pos'; Element 'inertial', line 1\.$"),
        # Compiled: the same.
        ('<body name="b"><joint type="hinge"/></body>',
         r"^Expected an MJCF model MuJoCo compiles, got robot\.xml: mass and inertia of "
         r"moving bodies must be larger than mjMINVAL; Element name 'b', id 1, line 1\.$"),
        ('<body name="b"><geom size="0.1"/></body><body name="b"/>',
         r"^Expected an MJCF model in '.*robot\.xml', got: XML Error: repeated name 'b' "
         r"in body; Element 'body', line 1\.$"),
        # Not XML: expat's message, with its line and column.
        ('<body name="b"><geom size="0.1"/>',
         r"^Expected an MJCF model in '.*robot\.xml', got: malformed XML: mismatched tag: "
         r"line 1, column \d+\.$"),
    ],
)  # fmt: skip
def test_messages_are_one_line_naming_the_file(tmp_path: Path, body: str, message: str) -> None:
    with pytest.raises(tb.InputError, match=message) as caught:
        tb.robots.load(mjcf(tmp_path, body))
    assert "\n" not in str(caught.value)


@pytest.mark.parametrize(
    "body",
    [
        '<body name="b"><joint type="hinge"/><geom type="sphere" size="0.1" mass="1e308"/></body>',
        '<body name="b"><joint type="hinge"/><geom type="box" size="1e200 1 1"/></body>',
    ],
)
def test_geoms_whose_mass_overflows_are_refused(tmp_path: Path, body: str) -> None:
    with pytest.raises(
        tb.InputError,
        match=r"^Expected body 'b' of '.*robot\.xml' to have mass properties MuJoCo computes as "
        r"finite numbers from its geoms, got mass .* kg and moments .* kg·m² \(its geoms' masses "
        r"or densities are near float64's limit\)\.$",
    ):
        tb.robots.load(mjcf(tmp_path, body))


def test_a_declared_mass_of_1e308_is_read_as_written(tmp_path: Path) -> None:
    path = mjcf(
        tmp_path,
        '<body name="b"><joint type="hinge"/><inertial pos="0 0 0" mass="1e308" '
        'diaginertia="1e308 1e308 1e308"/><geom type="sphere" size="0.1"/></body>',
    )
    robot = tb.robots.load(path)
    assert robot.links["b"].mass == 1e308
    assert declared(robot, "b").texts == ("1e308", "0", "0", "1e308", "0", "1e308")


def test_every_joint_type_of_mujoco_is_known() -> None:
    from tumble.robots.mjcf import _JOINT_KINDS

    assert set(_JOINT_KINDS) == set(mujoco.mjtJoint.__members__)


FUSESTATIC = '<compiler fusestatic="true"/>'

#: A moving body with a static child that fusestatic merges into it, and a
#: moving sibling declaring 2 kg after it.
FUSED = """
<body name="a" pos="0 0 1">
  <joint name="j1" type="hinge" axis="0 1 0"/>
  <geom type="box" size="0.1 0.1 0.1" mass="1"/>
  <body name="s" pos="0.2 0 0" euler="0 0 90">
    <inertial pos="0.05 0 0" mass="7" diaginertia="{inertia}"/>
  </body>
  <body name="b" pos="0 0 -0.5">
    <joint name="j2" type="hinge" axis="1 0 0"/>
    <inertial pos="0 0 0" mass="2" diaginertia="0.1 0.1 0.1"/>
  </body>
</body>
"""


def test_a_body_merged_by_fusestatic_is_judged(tmp_path: Path) -> None:
    # MuJoCo refuses the file (0.010 + 0.010 < 0.0201, element 's'): the audit
    # must still judge s, a shortfall the rounding of 0.010 explains.
    path = mjcf(tmp_path, FUSED.format(inertia="0.010 0.010 0.0201"), head=FUSESTATIC)
    with pytest.raises(ValueError, match="A \\+ B >= C"):
        mujoco.MjModel.from_xml_path(str(path))
    findings = tb.robots.audit(path).findings
    assert {(f.link, f.code) for f in findings} == {("s", "round-off")}


def test_a_body_merged_by_fusestatic_keeps_its_declared_values_counted_once(
    tmp_path: Path,
) -> None:
    path = mjcf(tmp_path, FUSED.format(inertia="0.01 0.01 0.019"), head=FUSESTATIC)
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.nbody == 3  # s is merged into a
    robot = tb.robots.load(path)
    assert list(robot.links) == ["world", "a", "s", "b"]
    # Each body its own declared values (b's 2 kg, not s's 7 kg).
    assert declared(robot, "s").mass == 7.0
    assert declared(robot, "b").mass == 2.0
    # s's place in a: 0.2 m along a's x, turned 90° about z.
    pose = robot.link_poses({"j1": 0.0})["s"]
    assert_allclose(pose[1], [0.2, 0.0, 1.0], atol=1e-15)
    assert_allclose(pose[0], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)
    # The whole robot is MuJoCo's: s's 7 kg counted once, in a's compiled body.
    assert_as_mujoco(path, {"j1": 0.3, "j2": -0.6})
    assert robot.mass_properties().mass == pytest.approx(1.0 + 7.0 + 2.0, rel=1e-12)


@pytest.mark.parametrize(
    ("inertial", "code", "refusal"),
    [
        ('mass="1" diaginertia="-0.01 0.01 0.01"', "not-positive-definite",
         "Expected the principal moments of `inertia` to be >= 0"),
        ('mass="-1" diaginertia="0.01 0.01 0.01"', "negative-mass", "Expected `mass` > 0 kg"),
    ],
)  # fmt: skip
def test_a_moving_body_mujoco_refuses_is_a_finding_not_a_refusal_of_the_file(
    tmp_path: Path, inertial: str, code: str, refusal: str
) -> None:
    body = (
        f'<body name="a"><joint type="hinge"/><inertial pos="0 0 0" {inertial}/></body>'
        '<body name="b" pos="1 0 0"><joint type="hinge"/><geom size="0.1" mass="1"/></body>'
    )
    path = mjcf(tmp_path, body)
    with pytest.raises(ValueError, match=r"inertia"):
        mujoco.MjModel.from_xml_path(str(path))
    audit = tb.robots.audit(path)
    assert {(f.link, f.code) for f in audit.findings} == {("a", code)}
    # The whole robot is refused, as for a URDF, naming the body.
    with pytest.raises(
        tb.InputError,
        match=rf"^Expected link 'a' of '.*robot\.xml' to declare physical mass properties, "
        rf"got: {refusal}",
    ):
        audit.robot.mass_properties()


def test_the_error_that_stops_the_compile_is_the_one_reported(tmp_path: Path) -> None:
    # a's inertia stops MuJoCo first; b, moving and massless, stops it even
    # without a's: b's error is the one to name.
    body = (
        '<body name="a"><joint type="hinge"/>'
        '<inertial pos="0 0 0" mass="1" diaginertia="-0.01 0.01 0.01"/></body>'
        '<body name="b"><joint type="hinge"/></body>'
    )
    with pytest.raises(
        tb.InputError,
        match=r"^Expected an MJCF model MuJoCo compiles, got robot\.xml: mass and inertia of "
        r"moving bodies must be larger than mjMINVAL; Element name 'b', id 2, line 1\.$",
    ):
        tb.robots.load(mjcf(tmp_path, body))
