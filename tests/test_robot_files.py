"""Real robot descriptions, against oracles nobody here wrote.

* Every declared ``<inertial>`` tensor of the URDFs shipped with pybullet_data
  and example-robot-data, parsed here with ElementTree and judged from numpy's
  eigenvalues: the clearly invalid ones are found, with the right code, and no
  clearly valid one is flagged.
* The whole-robot mass properties of six robots at their zero pose and at random
  poses equal yourdfpy's link transforms composed with the parallel-axis theorem.
* The bodies of Gymnasium's MuJoCo models, their geometry computed by tumble from
  the geoms, equal MuJoCo's compiled masses, centres and inertias; the whole
  robot at random joint values equals MuJoCo's own forward kinematics.

The files come from the ``robot-files`` extra (``make setup`` installs it).
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from functools import cache
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import tumble as tb

pybullet_data = pytest.importorskip("pybullet_data")


@pytest.fixture(autouse=True)
def _scratch_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """MuJoCo's own loader (an oracle here) logs its warnings to MUJOCO_LOG.TXT in
    the working folder: a scratch one."""
    monkeypatch.chdir(tmp_path)


@cache
def corpus() -> tuple[Path, ...]:
    """Every URDF of both packages."""
    folders = [Path(pybullet_data.getDataPath()), example_robot_folder()]
    return tuple(sorted(p for folder in folders for p in folder.rglob("*.urdf")))


@cache
def example_robot_folder() -> Path:
    """example-robot-data's robots: files of the distribution (a cmeel wheel, no
    Python module)."""
    try:
        distribution = metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:
        pytest.skip("example-robot-data is not installed (the robot-files extra)")
    return Path(str(distribution.locate_file("cmeel.prefix/share/example-robot-data/robots")))


def declared_tensors(path: Path) -> list[tuple[str, np.ndarray]]:
    """Each link's ``<inertia>`` as ElementTree reads it (links whose numbers do
    not parse are left out: tumble refuses the whole file for them)."""
    found = []
    for link in ElementTree.parse(path).getroot().findall("link"):
        inertia = link.find("inertial/inertia")
        if inertia is None:
            continue
        try:
            v = {k: float(inertia.get(k, "0")) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        except ValueError:
            continue
        tensor = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]],
                           [v["ixz"], v["iyz"], v["izz"]]])  # fmt: skip
        found.append((link.get("name", ""), tensor))
    return found


def test_the_corpus_is_there() -> None:
    assert len(corpus()) > 1100


@pytest.mark.slow  # every robot file of the corpus audited: 10 s and more
def test_every_clearly_invalid_tensor_is_found_and_no_valid_one() -> None:
    # Clearly invalid: a principal moment below −1 % of the largest, or I1 + I2
    # short of I3 by more than 1 % of I3: far beyond any rounding of the written
    # digits (tumble's own threshold is the rounding itself, so it may find more,
    # within that 1 %: those are not asserted). Clearly valid: every moment ≥ 0
    # and I1 + I2 ≥ I3 as numpy computes them from the numbers as written.
    invalid = valid = refused = 0
    for path in corpus():
        try:
            audit = tb.robots.audit(path, geometry="none")
        except tb.InputError:
            refused += 1
            continue
        flagged = {(f.link, f.code) for f in audit.findings if f.severity == "error"}
        for name, tensor in declared_tensors(path):
            moments = np.sort(np.linalg.eigvals(tensor).real)
            size = np.abs(moments).max()
            if size < 1e-15:  # a zero written with noise (1e-35 kg·m²): no body is judged
                continue
            if moments[0] < -0.01 * size:
                invalid += 1
                assert (name, "not-positive-definite") in flagged, (path, name, moments)
            elif moments[2] - moments[0] - moments[1] > 0.01 * moments[2]:
                invalid += 1
                assert (name, "triangle-inequality") in flagged, (path, name, moments)
            elif moments[0] >= 0 and moments[0] + moments[1] >= moments[2]:
                valid += 1
                assert not any(link == name for link, _ in flagged), (path, name, flagged)
    assert invalid > 30 and valid > 2000
    assert refused < 10


ROBOTS = {
    "kuka_iiwa": ("pybullet", "kuka_iiwa/model.urdf"),
    "panda": ("pybullet", "franka_panda/panda.urdf"),
    "ur5": ("example", "ur_description/urdf/ur5_robot.urdf"),
    "talos": ("example", "talos_data/robots/talos_reduced.urdf"),
    "solo12": ("example", "solo_description/robots/solo12.urdf"),
    "go2": ("example", "go2_description/urdf/go2.urdf"),
}


def robot_path(name: str) -> Path:
    where, relative = ROBOTS[name]
    folder = Path(pybullet_data.getDataPath()) if where == "pybullet" else example_robot_folder()
    return folder / relative


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_whole_robot_mass_properties_equal_yourdfpys_kinematics(name: str) -> None:
    # Oracle: yourdfpy's transform of every link into the root's frame (its own
    # URDF parser and kinematics), then each link's declared inertia rotated and
    # moved by the parallel-axis theorem, summed here.
    yourdfpy = pytest.importorskip("yourdfpy")
    path = robot_path(name)
    reference = yourdfpy.URDF.load(str(path), load_meshes=False, build_collision_scene_graph=False,
                                   load_collision_meshes=False)  # fmt: skip
    robot = tb.robots.load(path)
    moving = [j for j, joint in robot.joints.items()
              if joint.kind in ("revolute", "continuous", "prismatic") and joint.mimic is None]  # fmt: skip
    rng = np.random.default_rng(len(name))
    for trial in range(4):
        values = {} if trial == 0 else {j: float(rng.uniform(-1.5, 1.5)) for j in moving}
        configuration = np.array([values.get(j, 0.0) for j in reference.actuated_joint_names])
        reference.update_cfg(configuration)
        mass, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
        for link in reference.robot.links:
            inertial = link.inertial
            if inertial is None or inertial.mass == 0:
                continue
            pose = reference.get_transform(frame_to=link.name, frame_from=reference.base_link)
            origin = pose @ (inertial.origin if inertial.origin is not None else np.eye(4))
            rotation, centre = origin[:3, :3], origin[:3, 3]
            m = inertial.mass
            mass += m
            first += m * centre
            second += rotation @ inertial.inertia @ rotation.T + m * (
                centre @ centre * np.eye(3) - np.outer(centre, centre)
            )
        com = first / mass
        inertia = second - mass * (com @ com * np.eye(3) - np.outer(com, com))
        ours = robot.mass_properties(values)
        assert ours.mass == pytest.approx(mass, rel=1e-12)
        scale = np.abs(inertia).max()
        # 1e-9 of the largest entry: both sum the same few dozen terms of
        # products of rotations, each to a few ε.
        assert_allclose(ours.center_of_mass, com, atol=1e-9 * max(1.0, np.abs(com).max()))
        assert_allclose(ours.inertia, inertia, atol=1e-9 * scale)


GYMNASIUM_MODELS = ("humanoid", "ant", "half_cheetah", "walker2d", "hopper")


def gymnasium_model(name: str) -> Path:
    gymnasium = pytest.importorskip("gymnasium")
    return Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / f"{name}.xml"


@pytest.mark.parametrize("name", GYMNASIUM_MODELS)
def test_mjcf_body_geometry_equals_mujocos_compiled_inertia(name: str) -> None:
    # Oracle: MuJoCo 's compiler (inertiafromgeom), its body_mass, body_ipos and
    # body_inertia in the frame of body_iquat.
    mujoco = pytest.importorskip("mujoco")
    path = gymnasium_model(name)
    model = mujoco.MjModel.from_xml_path(str(path))
    robot = tb.robots.load(path)
    names = [model.body(i).name or f"body {i}" for i in range(1, model.nbody)]
    assert list(robot.links)[1:] == names
    checked = 0
    for i, link in enumerate(robot.links.values()):
        if i == 0 or model.body_mass[i] == 0:
            continue
        geometry = link.geometry()
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, model.body_iquat[i])
        rotation = rotation.reshape(3, 3)
        inertia = rotation @ np.diag(model.body_inertia[i]) @ rotation.T
        # 1e-9 relative: both evaluate the same closed forms of the primitives,
        # summed and shifted in another order.
        assert geometry.mass == pytest.approx(model.body_mass[i], rel=1e-9)
        assert_allclose(geometry.center_of_mass, model.body_ipos[i], atol=1e-9)
        assert_allclose(geometry.inertia, inertia, atol=1e-9 * np.abs(inertia).max())
        checked += 1
    assert checked >= 3


@pytest.mark.parametrize("name", GYMNASIUM_MODELS)
def test_mjcf_whole_robot_equals_mujocos_kinematics(name: str) -> None:
    # Oracle: mj_kinematics at random hinge and slide values: xipos, ximat and
    # body_inertia of every body, composed here.
    mujoco = pytest.importorskip("mujoco")
    path = gymnasium_model(name)
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    robot = tb.robots.load(path)
    rng = np.random.default_rng(3)
    values = {}
    for j in range(model.njnt):
        if model.jnt_type[j] in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE):
            value = float(rng.uniform(-0.8, 0.8))
            values[model.joint(j).name] = value
            data.qpos[model.jnt_qposadr[j]] = value
        elif model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
            data.qpos[model.jnt_qposadr[j] : model.jnt_qposadr[j] + 7] = model.qpos0[
                model.jnt_qposadr[j] : model.jnt_qposadr[j] + 7
            ]
    mujoco.mj_kinematics(model, data)
    masses = model.body_mass[1:]
    mass = masses.sum()
    com = (masses[:, None] * data.xipos[1:]).sum(axis=0) / mass
    inertia = np.zeros((3, 3))
    for i in range(1, model.nbody):
        rotation = data.ximat[i].reshape(3, 3)
        d = data.xipos[i] - com
        inertia += rotation @ np.diag(model.body_inertia[i]) @ rotation.T + model.body_mass[i] * (
            d @ d * np.eye(3) - np.outer(d, d)
        )
    ours = robot.mass_properties(values)
    assert ours.mass == pytest.approx(mass, rel=1e-12)
    assert_allclose(ours.center_of_mass, com, atol=1e-9)
    assert_allclose(ours.inertia, inertia, atol=1e-9 * np.abs(inertia).max())


def test_auditing_gymnasium_models_finds_no_error() -> None:
    pytest.importorskip("mujoco")
    for name in GYMNASIUM_MODELS:
        assert tb.robots.audit(gymnasium_model(name)).errors == ()


def test_a_seeded_slip_in_a_real_robot_is_found_and_fixed(tmp_path: Path) -> None:
    # kuka_iiwa's link 3 declares (0.08, 0.075, 0.01) kg·m²; its ixx written 1000
    # times too large is made physical again by one power of ten alone (0.008 and
    # 0.8 are not), so the audit corrects it without the geometry (its meshes
    # have holes, so they give no solid: an info finding each).
    source = robot_path("kuka_iiwa")
    text = source.read_text(encoding="utf-8").replace(
        'filename="meshes/', f'filename="{source.parent}/meshes/'
    )
    link = "lbr_iiwa_link_3"
    start = text.index(f'<link name="{link}">')
    ixx = text.index('ixx="', start) + len('ixx="')
    value = text[ixx : text.index('"', ixx)]
    assert value == "0.08"
    path = tmp_path / "iiwa.urdf"
    path.write_text(text[:ixx] + "80" + text[ixx + len(value) :], encoding="utf-8")
    audit = tb.robots.audit(path)
    found = {(f.link, f.code): f for f in audit.findings}
    assert (link, "triangle-inequality") in found
    assert found[(link, "power-of-ten")].correction == {"ixx": 0.08}
    assert all(f.severity == "info" for f in audit.findings if f.link != link)
    fixed = tb.robots.write_corrected(audit, tmp_path / "fixed.urdf")
    assert fixed.read_text(encoding="utf-8") == text
