"""Families of the catalogue of hostile requests (``bench/hostile_catalogue.py``):
robot files as users have them, rotors on elastic bearings, and outputs that
alias inputs or name something that is not a regular file."""

from __future__ import annotations

import importlib.util
from pathlib import Path

from hostile_case import Case, command, library

__all__ = ["outputs", "robot_files", "rotors"]

#: A two-link arm: a box base, a cylindrical arm on a revolute joint with limits.
ARM = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base">
    <inertial>
      <origin xyz="0 0 0.05" rpy="0 0 0"/>
      <mass value="4.0"/>
      <inertia ixx="0.0333333" ixy="0" ixz="0" iyy="0.0333333" iyz="0" izz="0.06"/>
    </inertial>
    <collision>
      <origin xyz="0 0 0.05" rpy="0 0 0"/>
      <geometry><box size="0.3 0.3 0.1"/></geometry>
    </collision>
  </link>
  <link name="arm">
    <inertial>
      <origin xyz="0 0 0.2" rpy="0 0 0"/>
      <mass value="2.0"/>
      <inertia ixx="0.0271167" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.0009"/>
    </inertial>
    <collision>
      <origin xyz="0 0 0.2" rpy="0 0 0"/>
      <geometry><cylinder radius="0.03" length="0.4"/></geometry>
    </collision>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/>
    <child link="arm"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 1 0"/>
    <limit lower="-1.57" upper="1.57" effort="50" velocity="2"/>
  </joint>
</robot>
"""

#: The arm's tensor, and one MuJoCo refuses as written (0.010 + 0.010 < 0.0201)
#: that the rounding of its digits explains.
ARM_TENSOR = 'ixx="0.0271167" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.0009"'
ROUNDED_TENSOR = 'ixx="0.010" ixy="0" ixz="0" iyy="0.010" iyz="0" izz="0.0201"'

#: The arm's cylinder inertia with a decimal point slipped (0.0009 written 0.9).
SLIPPED = ARM.replace('izz="0.0009"', 'izz="0.9"')


def _arm(old: str, new: str) -> bytes:
    if old not in ARM:
        raise ValueError(f"{old!r} is not in the arm")
    return ARM.replace(old, new, 1).encode()


def _chain(order: tuple[str, ...]) -> bytes:
    """Four links in a row on three revolute joints about z: jb mimics ja (×2), jc
    mimics jb (×3), declared in ``order``; each link 1 kg at its frame's x = 1."""
    link = (
        '<link name="{0}"><inertial><origin xyz="1 0 0"/><mass value="1"/>'
        '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>'
    )
    joints = {
        "ja": '<joint name="ja" type="revolute"><parent link="l0"/><child link="l1"/>'
        '<origin xyz="1 0 0"/><axis xyz="0 0 1"/></joint>',
        "jb": '<joint name="jb" type="revolute"><parent link="l1"/><child link="l2"/>'
        '<origin xyz="1 0 0"/><axis xyz="0 0 1"/><mimic joint="ja" multiplier="2"/></joint>',
        "jc": '<joint name="jc" type="revolute"><parent link="l2"/><child link="l3"/>'
        '<origin xyz="1 0 0"/><axis xyz="0 0 1"/><mimic joint="jb" multiplier="3"/></joint>',
    }
    body = "".join(link.format(f"l{k}") for k in range(4)) + "".join(joints[j] for j in order)
    return f'<robot name="chain">{body}</robot>'.encode()


#: MJCF: two 1 kg boxes of geoms; the compiler's settings decide their masses.
MJCF = """<mujoco model="m">
  <compiler {compiler}/>
  <worldbody>
    <body name="a" pos="0 0 1">
      <joint type="hinge" axis="0 1 0"/>
      <inertial pos="0 0 0" mass="{mass}" diaginertia="{inertia}"/>
      <geom type="box" size="0.1 0.1 0.1" mass="1"/>
      <body name="b" pos="0.5 0 0">
        <joint type="hinge" axis="0 1 0"/>
        <geom type="box" size="0.1 0.1 0.1" mass="1"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def _mjcf(compiler: str = "", mass: str = "5", inertia: str = "0.1 0.1 0.1") -> bytes:
    return MJCF.format(compiler=compiler, mass=mass, inertia=inertia).encode()


def _package_file(module: str, *parts: str) -> str | None:
    """A file of an installed package of robot files (None where it is not installed)."""
    spec = importlib.util.find_spec(module)
    if spec is None or spec.origin is None:
        return None
    path = Path(spec.origin).parent.joinpath(*parts)
    return str(path) if path.is_file() else None


#: pybullet_data's files with numbers PyBullet reads in a form URDF does not
#: allow, and their links (every one with a valid inertial).
MALFORMED = {
    "bike": ("bicycle/bike.urdf",),
    "microtaur": ("quadruped/microtaur/microtaur.urdf",),
    "racecar-differential": ("racecar/racecar_differential.urdf",),
    "husky": ("husky/husky.urdf",),
}


def _xacro() -> list[Case]:
    """ROS's xacro files: includes, packages found by name, arguments."""
    top = (
        b'<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        b'<xacro:include filename="part.xacro"/></robot>'
    )
    find = top.replace(b'"part.xacro"', b'"$(find parts)/part.xacro"')
    part = ARM.replace('<?xml version="1.0"?>', "").encode()
    robot = {"r.urdf": ARM.encode()}
    return [
        command(
            "robot/xacro-include-fifo",
            "audit",
            "r.urdf.xacro",
            files={"r.urdf.xacro": top},
            fifos=("part.xacro",),
        ),
        command(
            "robot/xacro-missing-package",
            "audit",
            "r.urdf.xacro",
            files={"r.urdf.xacro": find, "p/part.xacro": part},
        ),
        command(
            "robot/xacro-renamed-package",
            "audit",
            "r.urdf.xacro",
            "--package",
            "parts=p",
            "--geometry",
            "none",
            "--json",
            expect="result",
            check="json.loads(run.stdout)['links'] == 2 and json.loads(run.stdout)['errors'] == 0",
            files={"r.urdf.xacro": find, "p/part.xacro": part},
        ),
        command(
            "robot/xacro-missing-arg",
            "audit",
            "r.urdf.xacro",
            files={"r.urdf.xacro": _arm('izz="0.0009"', 'izz="$(arg izz)"')},
        ),
        command(
            "robot/xacro-bad-expression",
            "audit",
            "r.urdf.xacro",
            files={"r.urdf.xacro": _arm('izz="0.0009"', 'izz="${0.9*deg}"')},
        ),
        command("robot/xacro-arg-for-urdf", "audit", "r.urdf", "--xacro-arg", "a=1", files=robot),
        command("robot/package-malformed", "audit", "r.urdf", "--package", "p", files=robot),
        command(
            "robot/package-not-a-folder", "audit", "r.urdf", "--package", "p=r.urdf", files=robot
        ),
        command(
            "robot/package-twice",
            "audit",
            "r.urdf",
            "--package",
            "p=.",
            "--package",
            "p=..",
            files=robot,
        ),
        command(
            "robot/folder-with-fifo",
            "audit",
            ".",
            "--geometry",
            "none",
            "--json",
            expect="result",
            exit_codes=(1,),
            files={"a.urdf": ARM.encode()},
            fifos=("b.urdf",),
            check="[json.loads(line)['status'] for line in run.stdout.splitlines()] "
            "== ['audited', 'unreadable']",
        ),
        command("output/folder-fix", "audit", ".", "--fix", "out.urdf", files=robot),
        command(
            "output/report-is-robot-spelled",
            "audit",
            "r.urdf",
            "--report",
            "sub/../r.urdf",
            files={**robot, "sub/keep": b""},
        ),
        command(
            "output/report-is-xacro-include",
            "audit",
            "r.urdf.xacro",
            "--report",
            "part.xacro",
            files={"r.urdf.xacro": top, "part.xacro": part},
        ),
        library("robot/load-int", "tb.robots.load(3)"),
        library(
            "robot/load-xacro-args-text",
            "tb.robots.load(tmp / 'r.urdf.xacro', xacro_args='m=1')",
            **{"r.urdf.xacro": ARM.encode()},
        ),
        library(
            "robot/load-packages-missing-folder",
            "tb.robots.load(tmp / 'r.urdf', packages={'p': tmp / 'gone'})",
            **{"r.urdf": ARM.encode()},
        ),
    ]


_ARM_INERTIAL = """    <inertial>
      <origin xyz="0 0 0.2" rpy="0 0 0"/>
      <mass value="2.0"/>
      <inertia ixx="0.0271167" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.0009"/>
    </inertial>
"""
_ENTITY = (
    '<!DOCTYPE robot [<!ENTITY arm_inertial \'<inertial><mass value="0"/>'
    '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>\'>]>\n'
)
#: MJCF: a base whose izz slipped (6 for 0.06) and a massless hand with a shape.
_TWO = """<mujoco model="two">
  <worldbody>
    <body name="base">
      <freejoint/>
      <inertial pos="0 0 0" mass="4" diaginertia="0.0333333 0.0333333 6"/>
      <geom type="box" size="0.15 0.15 0.05" mass="4"/>
      <body name="hand" pos="0 0 0.3">
        <geom type="box" size="0.05 0.03 0.02" pos="0 0 0.05" euler="0 0 30" mass="0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
_PARTS = """<mujoco>
  <body name="arm" pos="0 0 0.1">
    <inertial pos="0 0 0.2" mass="2" diaginertia="0.0271167 0.0271167 0.9"/>
    <geom type="cylinder" fromto="0 0 0 0 0 0.4" size="0.03" mass="2"/>
  </body>
</mujoco>
"""


def _corrected_copies() -> list[Case]:
    """Corrected copies: the slipped value corrected where the file has it, in
    the file's encoding, never in a comment, an attribute's text or an entity."""
    windows = SLIPPED.replace('version="1.0"', 'version="1.0" encoding="windows-1252"')
    return [
        command(
            "robot/fix-self-closing-inertial",
            "audit",
            "r.urdf",
            "--fix",
            "out.urdf",
            expect="result",
            exit_codes=(1,),
            # urdfdom and PyBullet refuse an inertial without <mass>: an error of its
            # link, for which the audit has no correction; the copy is the source.
            check="'unreadable-inertial' in run.stdout "
            "and (folder / 'out.urdf').read_bytes() == (folder / 'r.urdf').read_bytes()",
            files={"r.urdf": ARM.replace(_ARM_INERTIAL, "    <inertial/>\n").encode()},
        ),
        command(
            "robot/fix-attribute-mentions-izz",
            "audit",
            "r.urdf",
            "--fix",
            "out.urdf",
            expect="result",
            exit_codes=(1,),
            check="(folder / 'out.urdf').read_text() == "
            + repr(ARM.replace('izz="0.0009"', 'note=\' izz="3"\' izz="0.0009"')),
            files={"r.urdf": SLIPPED.replace('izz="0.9"', 'note=\' izz="3"\' izz="0.9"').encode()},
        ),
        command(
            "robot/fix-inertial-from-entity",
            "audit",
            "r.urdf",
            "--fix",
            "out.urdf",
            files={
                "r.urdf": ARM.replace(
                    '<?xml version="1.0"?>\n', '<?xml version="1.0"?>\n' + _ENTITY
                )
                .replace(_ARM_INERTIAL, "    &arm_inertial;\n")
                .encode()
            },
        ),
        command(
            "robot/fix-utf-16-be",
            "audit",
            "r.urdf",
            "--fix",
            "out.urdf",
            expect="result",
            exit_codes=(1,),
            check="(folder / 'out.urdf').read_bytes() == b'\\xfe\\xff' + "
            + repr(ARM)
            + ".encode('utf-16-be')",
            files={"r.urdf": b"\xfe\xff" + SLIPPED.encode("utf-16-be")},
        ),
        command(
            "robot/fix-windows-1252-in-tag",
            "audit",
            "r.urdf",
            "--fix",
            "out.urdf",
            expect="result",
            exit_codes=(1,),
            check="(folder / 'out.urdf').read_bytes() == "
            + repr(
                ARM.replace('version="1.0"', 'version="1.0" encoding="windows-1252"')
                .replace('izz="0.0009"', 'izz="0.0009" note="25 €"')
                .encode("cp1252")
            ),
            files={
                "r.urdf": windows.replace('izz="0.9"', 'izz="0.9" note="25 €"').encode("cp1252")
            },
        ),
        # Only the negative mass corrected, the slipped izz left: the copy is never written.
        library(
            "robot/fix-correction-leaves-link-unphysical",
            "tb.robots.write_corrected(tb.robots.audit(tmp / 'r.urdf'), tmp / 'f.urdf')",
            **{"r.urdf": SLIPPED.replace('<mass value="2.0"/>', '<mass value="-2.0"/>').encode()},
        ),
        library(
            "robot/write-corrected-out-number",
            "tb.robots.write_corrected(tb.robots.audit(tmp / 'r.urdf'), 5)",
            **{"r.urdf": SLIPPED.encode()},
        ),
        library(
            "robot/fix-mjcf-diaginertia",
            "import mujoco\n"
            "out = tb.robots.write_corrected(tb.robots.audit(tmp / 'm.xml'), tmp / 'out.xml')\n"
            "result = mujoco.MjModel.from_xml_path(str(out)).body('base').inertia",
            "result",
            "np.allclose(result, [0.0333333, 0.0333333, 0.06], rtol=1e-12, atol=0)",
            **{"m.xml": _TWO.encode()},
        ),
        library(
            "robot/fix-mjcf-inserts-inertial",
            "import mujoco\n"
            "audit = tb.robots.audit(tmp / 'm.xml')\n"
            "out = tb.robots.write_corrected(audit, tmp / 'out.xml')\n"
            "body = mujoco.MjModel.from_xml_path(str(out)).body('hand')\n"
            "result = (float(body.mass[0]), audit.corrections()['hand']['mass'])",
            "result",
            # The massless hand gets the robot's density: MuJoCo compiles the correction's mass.
            "result[0] == result[1] > 0",
            **{"m.xml": _TWO.replace('6"/>', '0.06"/>').encode()},
        ),
        command(
            "robot/fix-mjcf-included-body",
            "audit",
            "m.xml",
            "--fix",
            "out.xml",
            files={
                "m.xml": b'<mujoco><worldbody><body name="base"><freejoint/>'
                b'<geom type="box" size="0.15 0.15 0.05" mass="4"/><include file="parts.xml"/>'
                b"</body></worldbody></mujoco>",
                "parts.xml": _PARTS.encode(),
            },
        ),
        # A body of an included file (here in ISO-8859-1) is corrected in that file, by hand.
        library(
            "robot/fix-body-in-latin-1-include",
            "tb.robots.write_corrected(tb.robots.audit(tmp / 'm.xml'), tmp / 'fixed.xml')",
            **{
                "m.xml": b'<mujoco model="m">\n  <worldbody>\n    <include file="parts.xml"/>\n'
                b"  </worldbody>\n</mujoco>\n",
                "parts.xml": (
                    '<?xml version="1.0" encoding="ISO-8859-1"?>\n<mujoco>\n'
                    "  <!-- bras \xe9paule -->\n" + _PARTS.split("\n", 1)[1]
                ).encode("latin-1"),
            },
        ),
        library(
            "robot/malformed-xml",
            "tb.robots.load(tmp / 'bad.urdf')",
            **{"bad.urdf": b'<robot name="r">\n  <link name="a">\n</robot>\n'},
        ),
        command(
            "robot/fix-mjcf-settotalmass",
            "audit",
            "m.xml",
            "--fix",
            "out.xml",
            files={
                "m.xml": _TWO.replace(
                    "<worldbody>", '<compiler settotalmass="10"/><worldbody>'
                ).encode()
            },
        ),
    ]


def robot_files() -> list[Case]:
    """Robot descriptions: malformed numbers, slips that must not audit clean,
    mimic joints, compiler settings of MJCF, huge values, files that are not
    regular files, and corrected copies in every encoding."""
    audit_json = ("audit", "r.urdf", "--geometry", "none", "--json")
    findings = "[f['code'] for f in json.loads(run.stdout)['findings']]"
    cases = [
        # Numbers urdfdom refuses in an inertial: never judged as if they were read.
        command(
            "robot/underscore-number",
            *audit_json,
            expect="result",
            exit_codes=(1,),
            check=f"'unreadable-inertial' in {findings}",
            files={"r.urdf": _arm('izz="0.0009"', 'izz="1_0e-3"')},
        ),
        command(
            "robot/arabic-digit",
            *audit_json,
            expect="result",
            exit_codes=(1,),
            check=f"'unreadable-inertial' in {findings}",
            files={"r.urdf": _arm('izz="0.0009"', 'izz="١e-2"')},
        ),
        command(
            "robot/missing-izz",
            *audit_json,
            expect="result",
            exit_codes=(1,),
            check=f"'unreadable-inertial' in {findings}",
            files={"r.urdf": _arm('iyz="0" izz="0.0009"', 'iyz="0"')},
        ),
        command(
            "robot/cone-geometry",
            "audit",
            "r.urdf",
            "--json",
            expect="result",
            exit_codes=(1,),
            check=f"'unknown-geometry' in {findings}",
            files={"r.urdf": _arm('<box size="0.3 0.3 0.1"/>', '<cone radius="1" length="1"/>')},
        ),
        # A tensor MuJoCo refuses as written (I1 + I2 < I3) never audits clean; the
        # rounding of its digits explains it: a warning, corrected to one MuJoCo takes.
        command(
            "robot/round-off",
            *audit_json,
            expect="result",
            check=f"{findings} == ['round-off']",
            files={"r.urdf": _arm(ARM_TENSOR, ROUNDED_TENSOR)},
        ),
        library(
            "robot/round-off-correction-accepted",
            "c = tb.robots.audit(tmp / 'r.urdf', geometry='none').corrections()['arm']\n"
            "result = tb.MassProperties(2.0, [0, 0, 0], "
            "[[c['ixx'], 0, 0], [0, c['iyy'], 0], [0, 0, c['izz']]])",
            "result",
            "result.inertia[0, 0] + result.inertia[1, 1] >= result.inertia[2, 2]",
            **{"r.urdf": _arm(ARM_TENSOR, ROUNDED_TENSOR)},
        ),
        # The base's box written in centimetres, read as metres: its density 1e-6 of a solid's.
        command(
            "robot/mesh-in-centimetres",
            "audit",
            "r.urdf",
            "--json",
            expect="result",
            check="any('centimetres' in f['message'] for f in json.loads(run.stdout)['findings'])",
            files={
                "r.urdf": _arm('<box size="0.3 0.3 0.1"/>', '<mesh filename="b.stl"/>'),
                "b.stl": lambda: (
                    __import__("trimesh").creation.box((30, 30, 10)).export(file_type="stl")
                ),
            },
        ),
        # A tensor of round-off zeros that the engines still refuse.
        command(
            "robot/tiny-tensor-refused",
            *audit_json,
            expect="result",
            check=f"{findings} == ['round-off']",
            files={
                "r.urdf": _arm(
                    ARM_TENSOR, 'ixx="1e-14" ixy="0" ixz="0" iyy="1e-14" iyz="0" izz="5e-14"'
                )
            },
        ),
        # The one move of a decimal point (0.301 for 0.0301) is still refused by MuJoCo:
        # the correction goes on to one it accepts, and the copy audits clean.
        library(
            "robot/decimal-correction-accepted",
            "a = tb.robots.audit(tmp / 'r.urdf', geometry='none')\n"
            "result = tb.robots.audit(tb.robots.write_corrected(a, tmp / 'f.urdf'), geometry='none')",
            "result",
            "result.findings == ()",
            **{
                "r.urdf": _arm(
                    ARM_TENSOR, 'ixx="0.010" ixy="0" ixz="0" iyy="0.020" iyz="0" izz="0.301"'
                )
            },
        ),
        library(
            "robot/no-refused-correction",
            "from tumble.robots.tensors import nearest_accepted\n"
            "result = nearest_accepted([1.5e308, 0.0, 1.5e308, 1e308, 1.5e308, 1.5e308])",
            "result",
            "result is None",
        ),
        # A box of three different sides declared with its x and z exchanged.
        library(
            "robot/box-of-three-sides-turned",
            "result = [(f.link, f.code) for f in tb.robots.audit(tmp / 'r.urdf').findings]",
            "result",
            "result == [('base', 'geometry-mismatch')]",
            **{
                "r.urdf": _arm('<box size="0.3 0.3 0.1"/>', '<box size="0.38 0.27 0.18"/>').replace(
                    b'ixx="0.0333333" ixy="0" ixz="0" iyy="0.0333333" iyz="0" izz="0.06"',
                    b'ixx="0.0724333" ixy="0" ixz="0" iyy="0.0589333" iyz="0" izz="0.0351"',
                )
            },
        ),
        # A cylinder declared along x (its small moment about x) whose shape lies along z.
        command(
            "robot/axes-mismatch",
            "audit",
            "r.urdf",
            "--json",
            expect="result",
            exit_codes=(0, 1),
            check=f"'geometry-mismatch' in {findings}",
            files={
                "r.urdf": _arm(
                    'ixx="0.0271167" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.0009"',
                    'ixx="0.0009" ixy="0" ixz="0" iyy="0.0271167" iyz="0" izz="0.0271167"',
                )
            },
        ),
    ]
    # Overflow: no traceback, a finding or a refusal.
    for label, (old, new) in {
        "inertia-1e308": ('izz="0.06"', 'izz="1e308"'),
        "products-1e308": (
            'ixy="0" ixz="0" iyy="0.0333333"',
            'ixy="1e308" ixz="1e308" iyy="0.0333333"',
        ),
        "mass-1e308": ('<mass value="4.0"/>', '<mass value="1e308"/>'),
        "sphere-1e200": ('<box size="0.3 0.3 0.1"/>', '<sphere radius="1e200"/>'),
    }.items():
        cases.append(
            command(
                f"robot/{label}",
                "audit",
                "r.urdf",
                "--json",
                expect="result",
                exit_codes=(1,),
                check="json.loads(run.stdout)['errors'] >= 1 or run.returncode == 0",
                files={"r.urdf": _arm(old, new)},
            )
        )
    # Mimic chains in any order; cycles, self-mimic and duplicate joints refused.
    in_order = "tb.robots.load(tmp / 'a.urdf').mass_properties({'ja': 0.3}).center_of_mass"
    cases += [
        library(
            "robot/mimic-chain-order",
            "result = tb.robots.load(tmp / 'r.urdf').mass_properties({'ja': 0.3}).center_of_mass",
            "result",
            f"np.allclose(result, {in_order}, rtol=0, atol=1e-12)",
            **{"r.urdf": _chain(("jc", "jb", "ja")), "a.urdf": _chain(("ja", "jb", "jc"))},
        ),
        library(
            "robot/mimic-cycle",
            "tb.robots.load(tmp / 'r.urdf').mass_properties({'ja': 0.3})",
            **{
                "r.urdf": _chain(("ja", "jb", "jc")).replace(
                    b'<origin xyz="1 0 0"/><axis xyz="0 0 1"/></joint>',
                    b'<origin xyz="1 0 0"/><axis xyz="0 0 1"/><mimic joint="jc"/></joint>',
                ),
            },
        ),
        library(
            "robot/self-mimic",
            "tb.robots.load(tmp / 'r.urdf').mass_properties()",
            **{
                "r.urdf": _chain(("ja", "jb", "jc")).replace(
                    b'joint="jb" multiplier="3"', b'joint="jc"'
                )
            },
        ),
        library(
            "robot/duplicate-joint",
            "tb.robots.load(tmp / 'r.urdf').mass_properties()",
            **{"r.urdf": _chain(("ja", "jb", "jc")).replace(b'name="jc"', b'name="jb"')},
        ),
        # Library arguments of the wrong kind.
        library("robot/load-none", "tb.robots.load(None)"),
        library("robot/load-bytes", "tb.robots.load(b'<robot/>')"),
        library(
            "robot/joints-list",
            "tb.robots.load(tmp / 'r.urdf').mass_properties(['shoulder'])",
            **{"r.urdf": ARM.encode()},
        ),
        library("robot/write-corrected-text", "tb.robots.write_corrected('x', tmp / 'out.urdf')"),
        library(
            "robot/geometry-mass-units",
            "result = tb.robots.load(tmp / 'r.urdf').links['arm'].geometry(mass='2 kg')",
            "result",
            # The arm's cylinder at 2 kg: m (3 r² + h²) / 12 about a transverse axis.
            "abs(result.mass - 2) < 1e-12 and abs(result.inertia[0, 0] - 2 * (3 * 0.03**2 + 0.4**2) / 12) < 1e-12",
            **{"r.urdf": ARM.encode()},
        ),
        library(
            "robot/geometry-mass-length",
            "tb.robots.load(tmp / 'r.urdf').links['arm'].geometry(mass='2 m')",
            **{"r.urdf": ARM.encode()},
        ),
        command(
            "robot/joints-twice",
            "inertia",
            "r.urdf",
            "--joints",
            "shoulder=1",
            "--joints",
            "shoulder=-1",
            files={"r.urdf": ARM.encode()},
        ),
        # MJCF: the compiler's settings decide the masses (2 kg of geoms; 10 kg in all).
        library(
            "robot/mjcf-inertiafromgeom",
            "result = tb.robots.load(tmp / 'm.xml').mass_properties()",
            "result",
            "abs(result.mass - 2) < 1e-9",
            **{"m.xml": _mjcf('inertiafromgeom="true"')},
        ),
        library(
            "robot/mjcf-settotalmass",
            "result = tb.robots.load(tmp / 'm.xml').mass_properties()",
            "result",
            "abs(result.mass - 10) < 1e-9",
            **{"m.xml": _mjcf('settotalmass="10"')},
        ),
        command(
            "robot/mjcf-mass-1e308",
            "audit",
            "m.xml",
            "--json",
            expect="result",
            exit_codes=(1,),
            check="json.loads(run.stdout)['errors'] >= 1 or run.returncode == 0",
            files={"m.xml": _mjcf(mass="1e308", inertia="1e308 1e308 1e308")},
        ),
        command(
            "robot/mjcf-bodies-1e5",
            "audit",
            "m.xml",
            "--geometry",
            "none",
            files={
                "m.xml": lambda: (
                    "<mujoco><worldbody>"
                    + "".join(
                        f'<body name="b{k}"><geom size="0.1"/></body>' for k in range(100_000)
                    )
                    + "</worldbody></mujoco>"
                ).encode()
            },
        ),
        # The declared 5 kg kept for the audit; MuJoCo scales 5 + 1 kg to 10 kg, body a to 10 · 5/6.
        library(
            "robot/mjcf-declared-beside-compiled",
            "robot = tb.robots.load(tmp / 'm.xml')\na = robot.links['a']\n"
            "result = (a.mass, a.compiled.mass, robot.mass_properties().mass)",
            "result",
            "result[0] == 5 and abs(result[1] - 50 / 6) < 1e-9 and abs(result[2] - 10) < 1e-9",
            **{"m.xml": _mjcf('settotalmass="10"')},
        ),
        # Both bodies raised to boundmass, 7 kg each, whatever is declared.
        library(
            "robot/mjcf-boundmass-counts-compiled",
            "robot = tb.robots.load(tmp / 'm.xml')\n"
            "result = (robot.links['a'].mass, robot.mass_properties().mass)",
            "result",
            "result[0] == 5 and abs(result[1] - 14) < 1e-9",
            **{"m.xml": _mjcf('boundmass="7"')},
        ),
        # The triangle inequality broken: MuJoCo compiles nothing, the pose is refused.
        library(
            "robot/mjcf-unphysical-pose",
            "tb.robots.load(tmp / 'm.xml').mass_properties()",
            **{"m.xml": _mjcf(inertia="0.1 0.1 0.5")},
        ),
        # A static body merged into its parent by the compiler is judged as written.
        library(
            "robot/mjcf-fusestatic-body-judged",
            "result = {(f.link, f.code) for f in tb.robots.audit(tmp / 'm.xml').findings}",
            "result",
            "result == {('s', 'round-off')}",
            **{
                "m.xml": b'<mujoco><compiler fusestatic="true"/><worldbody><body name="a">'
                b'<joint type="hinge"/><geom size="0.1"/><body name="s" pos="0.1 0 0">'
                b'<inertial pos="0 0 0" mass="1" diaginertia="0.010 0.010 0.0201"/></body></body>'
                b"</worldbody></mujoco>"
            },
        ),
        command(
            "robot/mjcf-negative-moment",
            "audit",
            "m.xml",
            "--json",
            expect="result",
            exit_codes=(1,),
            check=f"'not-positive-definite' in {findings}",
            files={
                "m.xml": b'<mujoco><worldbody><body name="a"><joint type="hinge"/>'
                b'<inertial pos="0 0 0" mass="1" diaginertia="-0.01 0.01 0.01"/></body>'
                b"</worldbody></mujoco>"
            },
        ),
        command(
            "robot/mjcf-replicate-bodies",
            "audit",
            "m.xml",
            files={
                "m.xml": b'<mujoco><worldbody><replicate count="100000" offset="1 0 0"><body>'
                b'<geom size="0.1"/></body></replicate></worldbody></mujoco>'
            },
        ),
        command(
            "robot/mjcf-geoms-3e4",
            "audit",
            "m.xml",
            files={
                "m.xml": lambda: (
                    "<mujoco><worldbody><body>"
                    + '<geom size="0.1"/>' * 30_000
                    + "</body></worldbody></mujoco>"
                ).encode()
            },
        ),
        command(
            "robot/mjcf-geom-mass-1e308",
            "audit",
            "m.xml",
            files={
                "m.xml": b'<mujoco><worldbody><body name="b"><joint type="hinge"/>'
                b'<geom size="0.1" mass="1e308"/></body></worldbody></mujoco>'
            },
        ),
        library(
            "robot/mjcf-digits-written",
            "result = tb.robots.load(tmp / 'm.xml').links['a'].inertial.texts",
            "result",
            "result == ('0.010', '0', '0', '0.010', '0', '0.0201')",
            **{
                "m.xml": b'<mujoco><worldbody><body name="a"><joint type="hinge"/>'
                b'<inertial pos="0 0 0" mass="1" diaginertia="0.010 0.010 0.0201"/>'
                b"</body></worldbody></mujoco>"
            },
        ),
        # MuJoCo raises each 1 kg body to boundmass, 2 kg.
        library(
            "robot/mjcf-boundmass-at-pose",
            "result = tb.robots.load(tmp / 'm.xml').mass_properties({'h': 0.7})",
            "result",
            "abs(result.mass - 4) < 1e-9",
            **{
                "m.xml": b'<mujoco><compiler boundmass="2"/><worldbody><body name="a">'
                b'<joint name="h" type="hinge"/><geom size="0.1" mass="1"/><body pos="0.5 0 0">'
                b'<joint type="hinge"/><geom size="0.1" mass="1"/></body></body></worldbody>'
                b"</mujoco>"
            },
        ),
        command(
            "robot/mjcf-texture-fifo",
            "audit",
            "m.xml",
            files={
                "m.xml": b'<mujoco><asset><texture name="t" type="2d" file="t.png"/></asset>'
                b'<worldbody><body><geom size="0.1"/></body></worldbody></mujoco>'
            },
            fifos=("t.png",),
        ),
        command(
            "robot/mjcf-meshdir-fifo",
            "audit",
            "m.xml",
            files={
                "m.xml": b'<mujoco><compiler meshdir="meshes"/><asset><mesh name="s" file="s.stl"/>'
                b'</asset><worldbody><body><geom type="mesh" mesh="s"/></body></worldbody></mujoco>'
            },
            fifos=("meshes/s.stl",),
        ),
        command(
            "robot/mjcf-mesh-dev-zero",
            "audit",
            "m.xml",
            files={
                "m.xml": b'<mujoco><asset><mesh name="s" file="/dev/zero"/></asset><worldbody>'
                b'<body><geom type="mesh" mesh="s"/></body></worldbody></mujoco>'
            },
        ),
        # Files that are not regular files: refused before anything opens them.
        command("robot/fifo", "audit", "r.urdf", fifos=("r.urdf",)),
        command("robot/dev-zero", "audit", "/dev/zero"),
        command(
            "robot/mjcf-include-fifo",
            "audit",
            "m.xml",
            files={"m.xml": b'<mujoco><include file="f.xml"/></mujoco>'},
            fifos=("f.xml",),
        ),
        command(
            "robot/mjcf-mesh-fifo",
            "audit",
            "m.xml",
            files={
                "m.xml": b'<mujoco><asset><mesh name="s" file="s.stl"/></asset><worldbody>'
                b'<body><geom type="mesh" mesh="s"/></body></worldbody></mujoco>'
            },
            fifos=("s.stl",),
        ),
        # A sparse mesh file (2 GiB of holes) is never read: the link's geometry is unavailable.
        command(
            "robot/sparse-mesh",
            "audit",
            "r.urdf",
            "--json",
            expect="result",
            check="any(f['code'] == 'geometry-unavailable' and 'sparse' in f['message'] "
            "for f in json.loads(run.stdout)['findings'])",
            files={"r.urdf": _arm('<box size="0.3 0.3 0.1"/>', '<mesh filename="s.stl"/>')},
            sparse={"s.stl": (b"\0" * 80 + (40_000_000).to_bytes(4, "little"), 2 * 2**30)},
        ),
        # Corrected copies: the slipped decimal point corrected wherever the file puts it.
        command(
            "robot/fix-latin-1",
            "audit",
            "r.urdf",
            "--fix",
            "out.urdf",
            expect="result",
            exit_codes=(1,),
            check="'izz=\"0.0009\"' in (folder / 'out.urdf').read_text('latin-1')",
            files={
                "r.urdf": SLIPPED.replace(
                    '<?xml version="1.0"?>', '<?xml version="1.0" encoding="ISO-8859-1"?>'
                )
                .replace('<robot name="arm">', '<robot name="bras articulé">')
                .encode("latin-1")
            },
        ),
        command(
            "robot/fix-utf-16",
            "audit",
            "r.urdf",
            "--fix",
            "out.urdf",
            expect="result",
            exit_codes=(1,),
            check="'izz=\"0.0009\"' in (folder / 'out.urdf').read_text('utf-16')",
            files={
                "r.urdf": SLIPPED.replace(
                    'version="1.0"', 'version="1.0" encoding="UTF-16"'
                ).encode("utf-16")
            },
        ),
        command(
            "robot/fix-commented-link",
            "audit",
            "r.urdf",
            "--fix",
            "out.urdf",
            expect="result",
            exit_codes=(1,),
            check="(folder / 'out.urdf').read_text().count('izz=\"0.9\"') == 1 "
            "and 'izz=\"0.0009\"' in (folder / 'out.urdf').read_text()",
            files={
                "r.urdf": SLIPPED.replace(
                    '  <link name="arm">',
                    '  <!-- <link name="arm"><inertial><mass value="1"/>'
                    '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="0.9"/></inertial></link> -->\n'
                    '  <link name="arm">',
                ).encode()
            },
        ),
    ]
    # Numbers in a form URDF does not allow, outside the inertials: read as PyBullet
    # reads them, and said; the kinematics refuse only a pose they cannot place.
    shoulder = '<origin xyz="0 0 0.1" rpy="0 0 0"/>'
    cases += [
        command(
            "robot/comma-origin",
            *audit_json,
            expect="result",
            check=f"{findings} == ['malformed-number']",
            files={"r.urdf": _arm(shoulder, '<origin xyz="0, 0, 0.1"/>')},
        ),
        library(
            "robot/four-number-rpy",
            "result = tb.robots.load(tmp / 'r.urdf').joints['shoulder'].rotation",
            "result",
            "np.allclose(result, __import__('scipy.spatial.transform', fromlist=['Rotation'])"
            ".Rotation.from_euler('xyz', (0.1, 0.2, 0.3)).as_matrix(), rtol=0, atol=1e-15)",
            **{"r.urdf": _arm(shoulder, '<origin xyz="0 0 0.1" rpy="0.1 0.2 0.3 0"/>')},
        ),
        library(
            "robot/xacro-joint-origin-pose",
            "tb.robots.load(tmp / 'r.urdf').mass_properties()",
            **{"r.urdf": _arm(shoulder, '<origin xyz="$(arg x) 0 0.1"/>')},
        ),
        library(
            "robot/joint-beyond-limit",
            "import warnings\nwith warnings.catch_warnings(record=True) as caught:\n"
            "    warnings.simplefilter('always')\n"
            "    tb.robots.load(tmp / 'r.urdf').mass_properties({'shoulder': 3.0})\n"
            "result = [type(w.message).__name__ for w in caught]",
            "result",
            "'JointLimitWarning' in result",
            **{"r.urdf": ARM.encode()},
        ),
    ]
    cases += _xacro() + _corrected_copies()
    for label, parts in MALFORMED.items():
        path = _package_file("pybullet_data", *parts)
        if path is None:
            continue
        cases.append(
            command(
                f"robot/pybullet-{label}",
                "audit",
                path,
                "--geometry",
                "none",
                "--json",
                expect="result",
                exit_codes=(1,),
                check=f"'malformed-number' in {findings} and 'unreadable-inertial' not in {findings}",
            )
        )
    return cases


#: A 10 kg disk between two bearings of 1 MN/m at ±0.2 m (RigidRotor's example).
ROTOR = (
    "rotor = tb.theory.RigidRotor(tb.shapes.thin_disk(10.0, 0.1), "
    "[tb.theory.Bearing(-0.2, 1e6), tb.theory.Bearing(0.2, 1e6)])\n"
)


#: The built-in rotor scenario: a shaft on two bearings, run up.
SHAFT = (
    Path(__file__).resolve().parents[1]
    / "src"
    / "tumble"
    / "scenario"
    / "builtin"
    / "rotor-on-bearings.toml"
).read_text()


def rotors() -> list[Case]:
    """Rigid rotors on elastic bearings: flags that are not flags, requests too
    large or too long, values that overflow, and whirl at negative speeds."""
    return [
        library("rotor/backward-text", ROTOR + "rotor.critical_speeds(backward='no')"),
        library("rotor/bearings-number", "tb.theory.RigidRotor(tb.shapes.thin_disk(10.0, 0.1), 5)"),
        library(
            "rotor/stiffness-1e308",
            ROTOR.replace("Bearing(0.2, 1e6)", "Bearing(0.2, 1e308)") + "rotor.frequencies(0.0)",
        ),
        library(
            "rotor/position-1e200",
            ROTOR.replace("Bearing(0.2, 1e6)", "Bearing('1e200 m', 1e6)")
            + "rotor.frequencies(0.0)",
        ),
        # 5e7 speeds: 1.6 GB of frequencies alone, beyond the budget of 1 GiB.
        library("rotor/frequencies-5e7", ROTOR + "rotor.frequencies(np.zeros(50_000_000))"),
        library(
            "rotor/run-up-tiny-step",
            ROTOR + "tb.models.run_up(rotor, 1e-4, duration=1.0, speed=100.0, dt=1e-12)",
        ),
        library(
            "rotor/run-up-long",
            ROTOR + "tb.models.run_up(rotor, 1e-4, duration=1e9, speed=100.0)",
        ),
        library(
            "rotor/bearings-none", "tb.theory.RigidRotor(tb.shapes.thin_disk(10.0, 0.1), None)"
        ),
        library(
            "rotor/bearings-one-object",
            "tb.theory.RigidRotor(tb.shapes.thin_disk(10.0, 0.1), tb.theory.Bearing(0.2, 1e6))",
        ),
        library(
            "rotor/point-mass",
            "tb.theory.RigidRotor(tb.MassProperties(1.0, [0, 0, 0], np.zeros((3, 3))), "
            "[tb.theory.Bearing(-0.2, 1e6), tb.theory.Bearing(0.2, 1e6)])",
        ),
        library(
            "rotor/damping-1e308",
            ROTOR.replace("Bearing(0.2, 1e6)", "Bearing(0.2, 1e6, 1e308)") + "rotor.whirl(100.0)",
        ),
        # The tilt stiffness Σ k a² underflows to 0.
        library(
            "rotor/bearings-coincident",
            ROTOR.replace("-0.2, 1e6", "-1e-200, 1e6").replace("(0.2, 1e6", "(1e-200, 1e6")
            + "rotor.unbalance_response(100.0, 1e-4)",
        ),
        library("rotor/backward-int", ROTOR + "rotor.critical_speeds(backward=1)"),
        library("rotor/response-speed-overflow", ROTOR + "rotor.unbalance_response(1e200, 1e-4)"),
        library("rotor/orbits-unbalance-overflow", ROTOR + "rotor.unbalance_orbits(100.0, 1e308)"),
        library("rotor/frequencies-speed-overflow", ROTOR + "rotor.frequencies(1e308)"),
        # 1.3 GB of modes, and 4e7 orbits: beyond the budget of 1 GiB.
        library("rotor/whirl-4e6", ROTOR + "rotor.whirl(np.zeros(4_000_000))"),
        library("rotor/orbits-4e7", ROTOR + "rotor.unbalance_orbits(np.zeros(40_000_000), 1e-4)"),
        library(
            "rotor/run-up-max-steps-float",
            ROTOR + "tb.models.run_up(rotor, 1e-4, duration=1.0, max_steps=1e6)",
        ),
        library(
            "rotor/run-up-end-speed-overflow",
            ROTOR + "tb.models.run_up(rotor, 1e-4, duration=10.0, speed=1e300, acceleration=1e308)",
        ),
        library(
            "rotor/run-up-max-steps-bool",
            ROTOR + "tb.models.run_up(rotor, 1e-4, duration=1.0, max_steps=True)",
        ),
        library(
            "rotor/run-up-max-steps-fraction",
            ROTOR + "tb.models.run_up(rotor, 1e-4, duration=1.0, max_steps=2.5)",
        ),
        library(
            "simulate/max-steps-bool",
            "tb.simulate(tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0])), [1, 2, 3], "
            "duration=1.0, max_steps=True)",
        ),
        library(
            "rotor/bearings-one-position",
            "tb.theory.RigidRotor(tb.shapes.thin_disk(10.0, 0.1), "
            "[tb.theory.Bearing(0.2, 1e6), tb.theory.Bearing(0.2, 1e6)])",
        ),
        library(
            "rotor/bearings-round-off-apart",
            "tb.theory.RigidRotor(tb.shapes.thin_disk(10.0, 0.1), "
            "[tb.theory.Bearing(0.2, 1e6), tb.theory.Bearing(0.2 + 1e-9, 1e6)])",
        ),
        library(
            "rotor/centre-off-axis",
            "tb.theory.RigidRotor(tb.shapes.thin_disk(10.0, 0.1), "
            "[tb.theory.Bearing(-0.2, 1e6), tb.theory.Bearing(0.2, 1e6)], point=[0.01, 0, 0])",
        ),
        library("rotor/bearing-negative-stiffness-pair", "tb.theory.Bearing(0.2, [1e6, -1])"),
        # Below the critical speed on isotropic bearings, the undamped cylindrical
        # response: U Ω² / |Σ k − m Ω²|.
        library(
            "rotor/unbalance-response-oracle",
            ROTOR + "result = rotor.unbalance_response(300.0, 1e-4)",
            "result",
            "np.allclose(result, 1e-4 * 300.0**2 / abs(2e6 - 10.0 * 300.0**2), rtol=1e-9)",
        ),
        # At −Ω the forward conical mode is (I_p |Ω| + √(I_p² Ω² + 4 I_t K_θ)) / (2 I_t)
        # (Friswell et al. §3.5), with K_θ = Σ k a² = 2 · 1e6 · 0.2².
        library(
            "rotor/whirl-negative-forward-conical",
            ROTOR + "result = rotor.whirl(-3000.0)",
            "result",
            "bool(result.forward[0, np.argmin(abs(result.frequencies[0] - (0.05 * 3000 + "
            "(0.05**2 * 3000**2 + 4 * 0.025 * 2e6 * 0.04) ** 0.5) / 0.05))])",
        ),
        # Speeds solved in blocks: the same frequencies as one at a time, across a block's edge.
        library(
            "rotor/frequencies-chunked",
            ROTOR + "s = np.linspace(0, 3000, 10000)\nresult = rotor.frequencies(s)",
            "result",
            "np.allclose(result[[0, 4095, 4096, 9999]], "
            "[rotor.frequencies(v) for v in s[[0, 4095, 4096, 9999]]], rtol=1e-12, atol=0)",
        ),
        command(
            "rotor/scenario-stiffness-1e308",
            "run",
            "r.toml",
            "-o",
            "out",
            "-q",
            files={
                "r.toml": SHAFT.replace('"2e6 N/m"', "1e308").replace('"3e6 N/m"', "1e308").encode()
            },
        ),
        command(
            "rotor/scenario-position-1e200",
            "run",
            "r.toml",
            "-o",
            "out",
            "-q",
            files={"r.toml": SHAFT.replace('position = "-25 cm"', 'position = "1e200 m"').encode()},
        ),
        command(
            "rotor/scenario-duration-1e9",
            "run",
            "r.toml",
            "-o",
            "out",
            "-q",
            files={"r.toml": SHAFT.replace('duration = "2 s"', 'duration = "1e9 s"').encode()},
        ),
        # Reversing the spin mirrors the rotor: the forward whirl at −Ω has the
        # frequencies of the forward whirl at +Ω.
        library(
            "rotor/whirl-negative-speed",
            ROTOR + "result = (rotor.whirl(-300.0), rotor.whirl(300.0))",
            "result",
            "np.allclose(np.sort(result[0].frequencies[result[0].forward]), "
            "np.sort(result[1].frequencies[result[1].forward]), rtol=1e-9)",
        ),
    ]


#: A valid scenario: a box spun near its intermediate axis for a second.
SCENARIO = """[scenario]
name = "s"
[body]
shape = "box"
mass = "0.5 kg"
size = "20, 10, 4 cm"
[initial]
omega = "0.05, 10, 0.05 rad/s"
[simulation]
duration = "1 s"
method = "exact"
"""

#: The phone recording tumble ships (a valid recording to fit).
RECORDING = (
    Path(__file__).resolve().parents[1]
    / "src"
    / "tumble"
    / "identification"
    / "data"
    / "phone-flip.csv"
)


#: A quick scenario that writes neither figures nor viewer.
QUICK = b"""[scenario]
name = "quick"
[body]
shape = "box"
mass = "1 kg"
size = "10, 20, 30 cm"
[initial]
omega = "3, 0.1, 0.1 rad/s"
[simulation]
duration = "1 s"
[output]
samples = 50
figures = false
viewer = false
"""
#: What an earlier run and an earlier fit list as theirs.
EARLIER_RUN = b'{"files": ["summary.json", "report.html"]}'
EARLIER_FIT = b'{"files": ["fit.json", "fitted-scenario.toml"]}'


def _box_stl() -> bytes:
    """The base's box, 0.3 × 0.3 × 0.1 m, as a binary STL."""
    import trimesh

    return bytes(trimesh.creation.box((0.3, 0.3, 0.1)).export(file_type="stl"))


def _dense_stl(triangles: int) -> bytes:
    """A binary STL whose header's count of triangles matches its size."""
    return b"dense".ljust(80) + triangles.to_bytes(4, "little") + b"\x01" * 50 * triangles


def outputs() -> list[Case]:
    """Outputs that are an input, another output, or not a regular file; run
    folders that hold an input or files no run wrote."""
    robot = {"r.urdf": SLIPPED.encode()}
    return [
        command("output/report-is-robot", "audit", "r.urdf", "--report", "r.urdf", files=robot),
        command(
            "output/report-is-fix",
            "audit",
            "r.urdf",
            "--report",
            "x.html",
            "--fix",
            "x.html",
            files=robot,
        ),
        command(
            "output/report-is-mjcf",
            "audit",
            "m.xml",
            "--report",
            "m.xml",
            files={"m.xml": _mjcf()},
        ),
        # An output over a mesh the robot reads.
        command(
            "output/report-over-urdf-mesh",
            "audit",
            "r.urdf",
            "--report",
            "meshes/../b.stl",
            files={
                "r.urdf": _arm('<box size="0.3 0.3 0.1"/>', '<mesh filename="b.stl"/>'),
                "b.stl": _box_stl,
                "meshes/keep": b"",
            },
        ),
        command(
            "output/report-over-mjcf-mesh",
            "audit",
            "m.xml",
            "--report",
            "assets/cube.stl",
            files={
                "m.xml": b'<mujoco model="m"><compiler meshdir="assets"/><asset>'
                b'<mesh file="cube.stl"/></asset><worldbody><body name="b"><freejoint/>'
                b'<geom type="mesh" mesh="cube"/></body></worldbody></mujoco>',
                "assets/cube.stl": _box_stl,
            },
        ),
        command("output/fix-fifo", "audit", "r.urdf", "--fix", "f", files=robot, fifos=("f",)),
        command(
            "output/report-fifo", "audit", "r.urdf", "--report", "f", files=robot, fifos=("f",)
        ),
        command(
            "output/report-device",
            "audit",
            "r.urdf",
            "--report",
            "null",
            files=robot,
            devices=("null",),
        ),
        command(
            "output/run-into-its-folder",
            "run",
            "s.toml",
            "-o",
            ".",
            "--force",
            files={"s.toml": SCENARIO.encode()},
        ),
        command(
            "output/run-over-other-files",
            "run",
            "s.toml",
            "-o",
            "out",
            "--force",
            files={"s.toml": SCENARIO.encode(), "out/notes.txt": b"mine\n"},
        ),
        command(
            "output/fit-into-its-folder",
            "fit",
            "r.csv",
            "-o",
            ".",
            "--force",
            files={"r.csv": RECORDING.read_bytes},
        ),
        command("output/fit-fifo", "fit", "r.csv", fifos=("r.csv",)),
        command("output/run-fifo", "run", "s.toml", fifos=("s.toml",)),
        command("output/inertia-fifo", "inertia", "m.stl", "--density", "1000", fifos=("m.stl",)),
        command(
            "output/run-force-over-its-scenario",
            "run",
            "R/s.toml",
            "-o",
            "R",
            "--force",
            files={"R/s.toml": QUICK, "R/summary.json": EARLIER_RUN},
        ),
        command(
            "output/run-force-over-a-users-file",
            "run",
            "s.toml",
            "-o",
            "R",
            "--force",
            files={"s.toml": QUICK, "R/summary.json": EARLIER_RUN, "R/notes.txt": b"mine\n"},
        ),
        command(
            "output/fit-force-over-its-recording",
            "fit",
            "F/r.csv",
            "-o",
            "F",
            "--force",
            files={"F/r.csv": RECORDING.read_bytes, "F/fit.json": EARLIER_FIT},
        ),
        command(
            "output/fit-force-recording-named-as-its-output",
            "fit",
            "F/fitted-scenario.toml",
            "--columns",
            "0,1,2,3",
            "-o",
            "F",
            "--force",
            files={"F/fitted-scenario.toml": RECORDING.read_bytes, "F/fit.json": EARLIER_FIT},
        ),
        command(
            "output/run-folder-fifo",
            "run",
            "s.toml",
            "-o",
            "out",
            files={"s.toml": QUICK},
            fifos=("out",),
        ),
        command(
            "output/fit-folder-device",
            "fit",
            "r.csv",
            "-o",
            "out",
            files={"r.csv": RECORDING.read_bytes},
            devices=("out",),
        ),
        command("output/sweep-folder-fifo", "sweep", "flip-map", "-o", "out", fifos=("out",)),
        command(
            "output/inertia-sparse-obj",
            "inertia",
            "m.obj",
            "--density",
            "1000",
            sparse={"m.obj": (b"v 0 0 0\n", 2 * 2**30)},
        ),
        library(
            "output/library-write-text-fifo",
            "from tumble.files import write_text\nwrite_text(tmp / 'f', 'x')",
            fifos=("f",),
        ),
        library(
            "output/library-recording-fifo",
            "from tumble.identification.recordings import read_recording\n"
            "result = read_recording(tmp / 'r.csv')",
            fifos=("r.csv",),
        ),
        library(
            "output/library-mesh-sparse",
            "result = tb.from_mesh(tmp / 'm.stl', density=1.0)",
            sparse={
                "m.stl": (b"\0" * 80 + (40_000_000).to_bytes(4, "little"), 84 + 50 * 40_000_000)
            },
        ),
        # 1.2 million triangles, 60 MB: about 1.1 GiB to read, beyond the budget of 1 GiB.
        library(
            "output/library-mesh-beyond-budget",
            "result = tb.from_mesh(tmp / 'big.stl', density=1.0)",
            **{"big.stl": lambda: _dense_stl(1_200_000)},
        ),
        library(
            "output/library-mesh-within-budget",
            "import trimesh\n(tmp / 'b.stl').write_bytes(trimesh.exchange.stl.export_stl("
            "trimesh.creation.box(extents=(1, 2, 3))))\n"
            "result = tb.from_mesh(tmp / 'b.stl', density=1.0)",
            "result",
            "abs(result.mass - 6.0) < 1e-12",
        ),
        command(
            "output/inertia-sparse-stl",
            "inertia",
            "m.stl",
            "--density",
            "1000",
            sparse={"m.stl": (b"\0" * 80 + (40_000_000).to_bytes(4, "little"), 2 * 2**30)},
        ),
    ]
