"""
Mass properties of a CAD mesh
=============================

Load a triangle mesh (an STL file from CAD, or a mesh built in code with
trimesh), give its length unit and its density or its mass, and read the mass,
the centre of mass, the inertia tensor about the centre of mass and about any
other point, and the principal moments and axes. Then see what tumble says about
meshes that bound no solid, and how to fix each of them.

The integrals are exact for the polyhedron (Tonon 2004; Mirtich 1996): a mesh is
not an approximation of itself, so the only error is the one the CAD export made
when it tessellated curved faces.
"""

# %%
# Load a mesh file
# ----------------
#
# :func:`tumble.from_mesh` reads anything trimesh reads (STL, OBJ, PLY, GLB, STEP).
# CAD files are usually in millimetres and STL files do not say so: give
# ``units="mm"``. The density of aluminium, 2700 kg/m³, fixes the mass; every
# result is in SI units (kg, m, kg·m²), in the axes of the file.

import json
import subprocess
import sys
import warnings

import numpy as np
import trimesh

import tumble as tb

np.set_printoptions(precision=4)

bracket = tb.from_mesh("../../examples/l_bracket.stl", density="2700 kg/m^3", units="mm")
print(f"mass            {bracket.mass:.6f} kg")
print(f"centre of mass  {bracket.center_of_mass * 1e3} mm")
print("inertia about the centre of mass, kg·m²:")
print(bracket.inertia)

# %%
# The bracket is an L profile, a 60 × 8 mm leg along x and a 40 × 8 mm leg along y
# that share an 8 × 8 mm corner, extruded 30 mm along z. Its volume is simple enough
# to check the mass by hand:

volume = (60 * 8 + 32 * 8) * 30 * 1e-9  # m³
print(f"ρ V = {2700 * volume:.6f} kg")
# Both are exact for this polyhedron: they agree to round-off.
assert np.isclose(bracket.mass, 2700 * volume, rtol=1e-12)

# %%
# The off-diagonal entries are the products of inertia with their minus sign,
# :math:`I_{xy} = -\sum m\,x\,y` (:doc:`/explanation/conventions`). The bracket's
# mass lies mostly where :math:`x` and :math:`y` have opposite signs relative to the
# centre of mass, so its :math:`I_{xy}` is positive.
#
# About another point
# -------------------
#
# ``inertia_about`` applies the parallel-axis theorem
#
# .. math::
#
#    \mathsf I_P = \mathsf I_G + m\,(|\mathbf d|^2 \mathsf E - \mathbf d\,\mathbf d^{\mathsf T}),
#    \qquad \mathbf d = P - G,
#
# with :math:`\mathsf E` the identity. Here, about the corner at the origin of the file
# (points are lengths; strings carry their unit):

print(bracket.inertia_about("0, 0, 0 mm"))

# %%
# Principal moments and axes
# --------------------------
#
# ``principal()`` returns the moments in ascending order and the axes as the
# columns of a rotation matrix (det +1), so that
# :math:`\mathsf I = \mathsf R\,\mathrm{diag}(I_1, I_2, I_3)\,\mathsf R^{\mathsf T}`.

moments, axes = bracket.principal()
print("principal moments, kg·m²:", moments)
print("principal axes (columns):")
print(axes)
assert np.allclose(axes @ np.diag(moments) @ axes.T, bracket.inertia, atol=1e-20)

# %%
# The axis of :math:`I_2` is the extrusion axis z: the plane z = 15 mm is a plane of
# symmetry. The other two lie in the plane of the profile, turned from x and y by
# an angle:

angle = np.degrees(np.arctan2(axes[1, 0], axes[0, 0]))
print(f"axis of I1: {angle:.2f}° from x, in the plane of the profile")
assert np.allclose(np.abs(axes[:, 1]), [0, 0, 1], atol=1e-12)

# %%
# A mesh made in code, with a total mass
# --------------------------------------
#
# A ``trimesh.Trimesh`` is accepted as it is. Giving ``mass`` instead of
# ``density`` sets the total mass; the density follows from the volume. A box is a
# polyhedron, so the mesh's result equals the closed form of
# :func:`tumble.shapes.box` (its coordinates here are metres, the default unit).

mesh = trimesh.creation.box(extents=[0.1, 0.2, 0.3])
from_mesh = tb.from_mesh(mesh, mass="2 kg")
closed_form = tb.shapes.box("2 kg", "10, 20, 30 cm")
print(from_mesh.inertia.diagonal(), closed_form.inertia.diagonal())
# The same polyhedron both ways: equal to round-off.
assert np.allclose(from_mesh.inertia, closed_form.inertia, rtol=1e-12, atol=1e-15)

# %%
# Meshes that bound no solid
# --------------------------
#
# The volume integrals of a surface that does not close are meaningless rather
# than approximately right, so tumble checks the mesh first and raises
# :class:`tumble.MeshError` (a kind of :class:`tumble.InputError`) with what is wrong.
# Each case below catches the error and prints its message.
#
# **An open mesh.** One triangle removed leaves a hole:

open_box = trimesh.Trimesh(mesh.vertices, mesh.faces[1:], process=False)
try:
    tb.from_mesh(open_box, density="1000 kg/m^3")
except tb.MeshError as error:
    print(error)

# %%
# Repair the export (close the surface in the CAD tool or a mesh editor). If the
# part really is a sheet, a thin wall or an open surface, ask for its surface as a
# thin shell: ``shell_thickness`` is the wall thickness, ``density`` that of the
# wall's material.

print(tb.from_mesh(open_box, density="7850 kg/m^3", shell_thickness="1 mm"))

# %%
# **A seam.** CAD exports write each triangle's corners separately; where the two
# sides of a seam differ by round-off tumble welds them, with a
# :class:`tumble.MeshRepairWarning`. A gap wider than round-off, here one corner
# moved by 1 µm, is refused, and the message gives the ``merge_tolerance`` that
# closes it:

corners = mesh.vertices[mesh.faces].reshape(-1, 3)  # every triangle's own corners
corners[0, 2] += 1e-6
seamed = trimesh.Trimesh(corners, np.arange(len(corners)).reshape(-1, 3), process=False)
try:
    tb.from_mesh(seamed, density="1000 kg/m^3")
except tb.MeshError as error:
    print(error)

# %%
# Pass it, after checking that a gap of that size is a seam and not a feature of
# the part; the weld is reported as a warning:

with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    welded = tb.from_mesh(seamed, density="1000 kg/m^3", merge_tolerance="2 um")
for warning in caught:
    print(f"{warning.category.__name__}: {warning.message}")
print(f"mass {welded.mass:.6f} kg")

# %%
# **Inverted normals.** A mesh wound inside out (every normal pointing inward)
# has a negative signed volume. tumble reverses it and says so with a
# :class:`tumble.MeshOrientationWarning`; the result is that of the solid:

inside_out = mesh.copy()
inside_out.invert()
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    reversed_box = tb.from_mesh(inside_out, mass="2 kg")
for warning in caught:
    print(f"{warning.category.__name__}: {warning.message}")
assert np.allclose(reversed_box.inertia, from_mesh.inertia, rtol=1e-12, atol=1e-15)

# %%
# To turn the warning into an error in a pipeline, use
# ``warnings.simplefilter("error", tumble.MeshOrientationWarning)``.
#
# **Inconsistent winding.** Some triangles flipped and others not cannot be read
# as a solid:

flipped = trimesh.Trimesh(mesh.vertices, mesh.faces.copy(), process=False)
flipped.faces[3] = flipped.faces[3][::-1]
try:
    tb.from_mesh(flipped, density="1000 kg/m^3")
except tb.MeshError as error:
    print(error)

# %%
# ``trimesh.repair.fix_normals`` rewinds the triangles consistently (it needs the
# ``networkx`` package); so does re-exporting from CAD.
#
# **Degenerate meshes.** A surface that encloses nothing (the two sides of one
# triangle) and a file without triangles:

flat = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 1]], process=False)
empty = trimesh.Trimesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=int), process=False)
for bad in (flat, empty):
    try:
        tb.from_mesh(bad, density="1000 kg/m^3")
    except tb.MeshError as error:
        print(error)

# %%
# **Bad values** are :class:`tumble.InputError`: the message names the argument,
# what was expected and what was received.

for kwargs in ({"density": "2700 kg/m^3", "mass": "1 kg"}, {"density": "2 kg"}):
    try:
        tb.from_mesh(mesh, **kwargs)
    except tb.InputError as error:
        print(f"{type(error).__name__}: {error}")

# %%
# The command line
# ----------------
#
# ``tumble inertia`` does the same from a shell, with the same options
# (``--merge-tolerance``, ``--shell-thickness``, ``--mass``) and ``--about`` for
# another point:
#
# .. code-block:: console
#
#    $ tumble inertia examples/l_bracket.stl --units mm --density "2700 kg/m^3"
#    $ tumble inertia examples/l_bracket.stl --units mm --density "2700 kg/m^3" \
#          --about "0, 0, 0 mm" --json
#
# Run here (as ``python -m tumble``, the same command), ``--json`` gives numbers
# to read back; they are those of the library:

command = [
    sys.executable, "-m", "tumble", "inertia", "../../examples/l_bracket.stl", "--units", "mm",
    "--density", "2700 kg/m^3", "--about", "0, 0, 0 mm", "--json",
]  # fmt: skip
result = json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)
print(f"mass {result['mass']:.6f} kg, principal moments {result['principal_moments']} kg·m²")
assert np.allclose(result["about"]["inertia"], bracket.inertia_about([0, 0, 0]), rtol=1e-12)

# %%
# A mistake is one line on stderr and exit code 2:

command[command.index("mm")] = "kg"
failed = subprocess.run(command, capture_output=True, text=True)
print(f"exit code {failed.returncode}: {failed.stderr.strip()}")

# %%
# :doc:`/reference/cli` lists every option of ``tumble inertia``.
