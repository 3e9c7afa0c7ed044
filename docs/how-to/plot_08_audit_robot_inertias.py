"""
Audit a robot's inertias
========================

Robot descriptions carry an inertia tensor for every link, most often written
by hand or exported by a CAD tool, and they are often wrong: a decimal point
slipped in one attribute, a tensor in kg·mm² where kg·m² was meant, a massless
link with collision shapes. Simulators react badly: some refuse the file with a
terse message, others integrate a body that cannot exist. ``tumble audit``
finds such links, says by how much they are wrong, compares them with what
their shapes give, and writes a corrected copy in which only the corrected
lines change.

In a shell:

.. code-block:: console

   $ tumble audit robot.urdf                        # a table of the links, then the findings
   $ tumble audit robot.urdf --geometry none        # the declared values alone (fast)
   $ tumble audit robot.urdf --json                 # for scripts
   $ tumble audit robot.urdf --fix robot-fixed.urdf # a corrected copy; the source is untouched
   $ tumble audit robot.urdf --report audit.html    # the links in 3D, coloured by finding
   $ tumble inertia robot.urdf --joints "shoulder=30 deg"   # the whole robot at a pose
   $ tumble audit robot.urdf.xacro --package my_arm_support=my_arm --xacro-arg prefix=left_
   $ tumble audit robots/ --geometry none           # every robot file under a folder

The exit code is 0 when no link has an error, 1 when some has, 2 for a file
that cannot be read. MJCF files (``.xml``) are read through MuJoCo's own parser
(``pip install 'tumble[robots]'``); a link is then a body, and its geometry the
geoms MuJoCo counts in its inertia. A robot file is read only when it is a
regular file (a FIFO or a device is refused, never read), and an output
(``--report``, ``--fix``) is refused when it is the robot file, a file it
includes, or the other output.
"""

# %%
# A robot with a slipped decimal point
# ------------------------------------
#
# tumble ships a small arm (a box base, a cylindrical arm, a spherical hand).
# Here its arm's ``izz`` is written 1000 times too large, as a missing "0.00"
# would make it:

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import tumble as tb
from tumble.robots import example_path

folder = Path(tempfile.mkdtemp())
source = folder / "arm.urdf"
source.write_text(example_path().read_text().replace('izz="0.0009"', 'izz="0.9"'))

audit = tb.robots.audit(source)
for finding in audit.findings:
    print(f"{finding.severity} {finding.link} {finding.code}: {finding.message}")
    print("    correction:", finding.correction)

# %%
# The tensor is not one any body has: its largest principal moment exceeds the
# sum of the other two (the triangle inequality I₁ + I₂ ≥ I₃ that every mass
# distribution obeys). Five moves of the decimal point in ``izz`` would make it
# physical, and the arm's collision cylinder at the declared 2 kg says which:
# 0.0009 kg·m², the one within a factor √10 of the shape's own ``izz``. Without
# geometry (``geometry="none"``) the audit lists the five and corrects nothing.
#
# What counts as wrong
# --------------------
#
# A tensor is judged with the digits it was written with: ``0.01`` may be any
# number from 0.005 to 0.015, so a principal moment is negative, or the
# triangle inequality broken, only beyond what the rounding of the written
# digits can explain (Weyl's inequality bounds how far the eigenvalues move).
# Against the geometry, the sum of the principal moments must lie within a
# factor 2 of the shapes' (a hollow or motor-heavy link stays within it), the
# centre of mass within the box around the shapes, and the density (mass over
# the shapes' volume) within 10–25 000 kg/m³.
#
# The corrected copy
# ------------------
#
# ``--fix`` writes the file again with each link's correction; the diff shows
# the corrected attribute alone:

fixed = folder / "arm-fixed.urdf"
done = subprocess.run(
    [sys.executable, "-m", "tumble", "audit", str(source), "--fix", str(fixed)],
    capture_output=True, text=True, env={**os.environ, "COLUMNS": "100"},
)  # fmt: skip
print(done.stdout + done.stderr)
print("exit code", done.returncode)
print(subprocess.run(["diff", str(source), str(fixed)], capture_output=True, text=True).stdout)

# %%
# The corrected file audits clean:

print(tb.robots.audit(fixed).findings)

# %%
# The whole robot at a pose
# -------------------------
#
# ``Robot.mass_properties`` composes every link's declared values through the
# joints, in the root link's frame; joints not given stay at 0:

robot = tb.robots.load(fixed)
straight = robot.mass_properties()
bent = robot.mass_properties({"shoulder": "90 deg"})
print("centre of mass, straight:", straight.center_of_mass.round(4), "m")
print("centre of mass, bent:    ", bent.center_of_mass.round(4), "m")
print("principal moments, bent: ", bent.principal()[0].round(5), "kg·m²")

# %%
# ROS packages and xacro files
# ----------------------------
#
# ROS packages ship ``.urdf.xacro`` files: macros that ``xacro`` expands into
# URDF. ``tumble audit`` expands them through the ``xacro`` package (pure
# Python, no ROS needed), with ``--xacro-arg NAME=VALUE`` for the file's
# ``<xacro:arg>``. ``$(find pkg)`` and ``package://pkg/`` mesh names are looked
# up in the folders given with ``--package NAME=DIR`` (``packages=`` in Python),
# then in the file's parent folders (a folder named ``pkg``, or one holding it),
# then in ``ROS_PACKAGE_PATH``. Copies of packages often rename their folders
# (rtb-data's ``kuka_kr16_support`` is its folder ``kuka_kr16/``): a package
# found nowhere is an error that names it.
#
# Here a robot file includes the arm from a package ``arm_parts`` kept in a
# folder of another name:

parts = folder / "parts-v2" / "urdf"
parts.mkdir(parents=True)
(parts / "arm.xacro").write_text(fixed.read_text().replace('<?xml version="1.0"?>', ""))
robot_xacro = folder / "robot.urdf.xacro"
robot_xacro.write_text(
    '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
    '  <xacro:include filename="$(find arm_parts)/urdf/arm.xacro"/>\n'
    "</robot>\n"
)
try:
    tb.robots.load(robot_xacro)
except tb.InputError as error:
    print(error)
audit = tb.robots.audit(robot_xacro, packages={"arm_parts": folder / "parts-v2"})
print(len(audit.links), "links,", len(audit.errors), "errors")

# %%
# A folder of robot files
# -----------------------
#
# ``tumble audit FOLDER`` audits every robot file under a folder: ``.urdf``,
# xacro files, and ``.xml`` files that are MuJoCo models (their root element is
# ``<mujoco>``). A xacro file that expands to no robot (a file of macros, meant
# to be included by others) is skipped and counted. A progress bar runs on
# stderr, then a summary table gives the files audited, their links, the errors
# by code, the files with errors and the files that could not be read, each
# with its reason. ``--json`` prints one JSON object per line per file instead
# (``"status"``: ``audited``, ``skipped`` or ``unreadable``). The exit code is 1
# when a file has an error or could not be read, 0 when every robot file was
# read and has none, 2 for bad arguments. ``--fix`` and ``--report`` take one
# robot file, not a folder.

done = subprocess.run(
    [sys.executable, "-m", "tumble", "audit", str(folder), "--geometry", "none",
     "--package", f"arm_parts={folder / 'parts-v2'}"],
    capture_output=True, text=True, env={**os.environ, "COLUMNS": "100"},
)  # fmt: skip
print(done.stdout + done.stderr)
print("exit code", done.returncode)
