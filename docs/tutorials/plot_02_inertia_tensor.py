r"""
The inertia tensor
==================

The inertia tensor turns an angular velocity into an angular momentum,
:math:`\mathbf L = \mathsf I \boldsymbol\omega`. This page builds it by hand
from point masses and checks :func:`tumble.point_masses` against the sum,
moves it to another point with the parallel-axis theorem, finds the principal
axes, and then computes the tensor of a solid from ``tumble.shapes`` and of
a CAD part, an aluminium L-bracket given as a triangle mesh, with
:func:`tumble.from_mesh`. The mesh result is checked against the same bracket
assembled from two boxes.
"""

# %%
# Theory
# ------
#
# For rigid point masses :math:`m_k` at positions :math:`\mathbf r_k` (a solid
# replaces the sum by an integral over :math:`\mathrm dm`) the angular momentum
# about the origin is
# :math:`\mathbf L = \sum_k m_k\, \mathbf r_k \times (\boldsymbol\omega \times \mathbf r_k)`.
# Expanding the double cross product gives :math:`\mathbf L = \mathsf I \boldsymbol\omega`
# with the inertia tensor
#
# .. math::
#
#    I_{ij} = \sum_k m_k \left( r_k^2\, \delta_{ij} - r_{k,i}\, r_{k,j} \right),
#    \qquad
#    \mathsf I = \begin{pmatrix}
#      \sum m (y^2 + z^2) & -\sum m x y & -\sum m x z \\
#      -\sum m x y & \sum m (x^2 + z^2) & -\sum m y z \\
#      -\sum m x z & -\sum m y z & \sum m (x^2 + y^2)
#    \end{pmatrix}.
#
# The diagonal entries are the *moments* of inertia, the off-diagonal ones the
# *products* of inertia. The products enter with a **minus sign**,
# :math:`I_{xy} = -\sum m x y`: only then is :math:`\mathbf L = \mathsf I \boldsymbol\omega`
# a plain matrix product. Written out, the first component is
#
# .. math::
#
#    L_x = \omega_x \sum m (y^2 + z^2) - \omega_y \sum m x y - \omega_z \sum m x z .
#
# Two slips are common in lecture notes: a product of inertia written without
# its minus sign, and the third term of :math:`L_x` written with
# :math:`\sum m x y` in place of :math:`\sum m x z`. tumble uses the forms above
# (Goldstein, *Classical Mechanics*, §5.3; Kleppner & Kolenkow, *An
# Introduction to Mechanics*, ch. 7). ``MassProperties.inertia`` is
# always about the **centre of mass**, in body axes (:doc:`/explanation/conventions`).
#
# Point masses, by hand and by tumble
# -----------------------------------
#
# Four masses in the :math:`xy` plane and one above it. The hand formula is
# evaluated about their centre of mass, where tumble reports the tensor.

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import trimesh
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

import tumble as tb

masses = np.array([1.0, 2.0, 1.5, 0.5, 1.0])  # kg
positions = np.array(  # m, body axes
    [
        [0.3, 0.1, 0.0],
        [-0.2, 0.25, 0.0],
        [0.1, -0.3, 0.0],
        [-0.15, -0.1, 0.0],
        [0.05, 0.05, 0.2],
    ]
)
body = tb.point_masses(masses, positions)

com = masses @ positions / masses.sum()
x, y, z = (positions - com).T  # coordinates relative to the centre of mass
by_hand = np.array(
    [
        [np.sum(masses * (y**2 + z**2)), -np.sum(masses * x * y), -np.sum(masses * x * z)],
        [-np.sum(masses * x * y), np.sum(masses * (x**2 + z**2)), -np.sum(masses * y * z)],
        [-np.sum(masses * x * z), -np.sum(masses * y * z), np.sum(masses * (x**2 + y**2))],
    ]
)
np.set_printoptions(precision=6)
print("centre of mass (m):", body.center_of_mass)
print("inertia from tumble (kg·m²):\n", body.inertia)
print("inertia by hand (kg·m²):\n", by_hand)
print(f"Σ m x y = {np.sum(masses * x * y):+.6f} kg·m², I_xy = {body.inertia[0, 1]:+.6f} kg·m²")

# Sums of five products of order 0.1 kg·m²: they agree to a few units in the
# last place of float64, so 1e-12 of the largest entry leaves a wide margin.
assert np.allclose(body.inertia, by_hand, rtol=0, atol=1e-12 * np.abs(by_hand).max())

# %%
# The angular momentum of a spin :math:`\boldsymbol\omega` about the centre of
# mass three ways: the definition
# :math:`\sum m\, \mathbf r \times (\boldsymbol\omega \times \mathbf r)`, the
# component formula for :math:`L_x` above, and :func:`tumble.angular_momentum`
# (which is :math:`\mathsf I \boldsymbol\omega`). The last line shows what the
# slip :math:`\sum m x y` in the third term of :math:`L_x` would give.

omega = np.array([1.0, -2.0, 3.0])  # rad/s, body axes
relative = positions - com
by_definition = np.sum(masses[:, None] * np.cross(relative, np.cross(omega, relative)), axis=0)
lx = (
    omega[0] * np.sum(masses * (y**2 + z**2))
    - omega[1] * np.sum(masses * x * y)
    - omega[2] * np.sum(masses * x * z)
)
lx_slip = (
    omega[0] * np.sum(masses * (y**2 + z**2))
    - omega[1] * np.sum(masses * x * y)
    - omega[2] * np.sum(masses * x * y)
)
print("L by definition (kg·m²/s):     ", by_definition)
print("L = I ω, tumble (kg·m²/s):     ", tb.angular_momentum(body, omega))
print(f"L_x from the component formula: {lx:.6f} kg·m²/s")
print(f"L_x with Σ m x y as third term: {lx_slip:.6f} kg·m²/s (wrong)")

# %%
# The parallel-axis theorem
# -------------------------
#
# About a point :math:`P` at :math:`\mathbf d = \mathbf r_P - \mathbf r_G` from
# the centre of mass :math:`G` (Steiner's theorem, in tensor form),
#
# .. math::
#
#    \mathsf I_P = \mathsf I_G
#      + m \left( |\mathbf d|^2 \mathsf E - \mathbf d\, \mathbf d^{\mathsf T} \right).
#
# ``MassProperties.inertia_about(point)`` applies it. About the body origin it
# must equal the hand formula with the raw positions, the origin being the
# reference of the coordinates.

x0, y0, z0 = positions.T
about_origin_by_hand = np.array(
    [
        [np.sum(masses * (y0**2 + z0**2)), -np.sum(masses * x0 * y0), -np.sum(masses * x0 * z0)],
        [-np.sum(masses * x0 * y0), np.sum(masses * (x0**2 + z0**2)), -np.sum(masses * y0 * z0)],
        [-np.sum(masses * x0 * z0), -np.sum(masses * y0 * z0), np.sum(masses * (x0**2 + y0**2))],
    ]
)
about_origin = body.inertia_about([0.0, 0.0, 0.0])
print("inertia about the origin, tumble (kg·m²):\n", about_origin)
print(
    "largest difference from the hand formula:",
    f"{np.abs(about_origin - about_origin_by_hand).max():.2e} kg·m²",
)
# Same sums, moved by the theorem: round-off of float64 only.
assert np.allclose(about_origin, about_origin_by_hand, rtol=0, atol=1e-12)

# %%
# The same theorem for a solid cone (mass :math:`m`, base radius :math:`r`,
# height :math:`h`). :func:`tumble.shapes.solid_cone` puts its centre of mass at
# the origin and its apex at :math:`z = 3h/4`. About the centre of mass a
# transverse moment is :math:`\tfrac{3}{20} m r^2 + \tfrac{3}{80} m h^2`; about
# the apex the textbook value is :math:`\tfrac{3}{20} m r^2 + \tfrac{3}{5} m h^2`.

m, r, h = 0.25, 0.03, 0.08  # kg, m, m
cone = tb.shapes.solid_cone(m, radius=r, height=h)
apex = [0.0, 0.0, 0.75 * h]
transverse_apex = cone.inertia_about(apex)[0, 0]
textbook = 3 / 20 * m * r**2 + 3 / 5 * m * h**2
print(f"cone: I_xx about the centre of mass {cone.inertia[0, 0]:.6e} kg·m²")
print(f"      I_xx about the apex {transverse_apex:.6e} kg·m², textbook {textbook:.6e} kg·m²")
assert np.isclose(transverse_apex, textbook, rtol=1e-12)

# %%
# Principal axes
# --------------
#
# :math:`\mathsf I` is real and symmetric, so it has three real, non-negative
# eigenvalues, the *principal moments*, and three orthogonal eigenvectors, the
# *principal axes* (some notes call them "primordial axes"; the name is
# *principal*):
#
# .. math::
#
#    \mathsf I = \mathsf R \operatorname{diag}(I_1, I_2, I_3) \mathsf R^{\mathsf T},
#    \qquad I_1 \le I_2 \le I_3 .
#
# Spun about a principal axis, a body has :math:`\mathbf L \parallel \boldsymbol\omega`.
# ``MassProperties.principal()`` returns the moments in ascending order and the
# axes as the columns of :math:`\mathsf R`, a proper rotation
# (:math:`\det \mathsf R = +1`), so the axes form a right-handed frame.
# The moments also obey the triangle inequality :math:`I_1 + I_2 \ge I_3`,
# which every distribution of mass satisfies.

moments, axes = body.principal()
print("principal moments (kg·m²):", moments)
print("principal axes (columns):\n", axes)
print(f"det R = {np.linalg.det(axes):+.15f}")
print(
    "largest |R diag(I) Rᵀ − I|:",
    f"{np.abs(axes @ np.diag(moments) @ axes.T - body.inertia).max():.2e} kg·m²",
)
for k in range(3):
    spin = axes[:, k]
    momentum = tb.angular_momentum(body, spin)
    angle = np.degrees(np.arctan2(np.linalg.norm(np.cross(momentum, spin)), momentum @ spin))
    print(f"ω along axis {k + 1}: angle between L and ω = {angle:.2e} deg")
# A proper rotation, and the eigen-decomposition reproduces the tensor to round-off.
assert np.isclose(np.linalg.det(axes), 1.0, atol=1e-12)
assert np.all(np.diff(moments) >= 0) and moments[0] + moments[1] >= moments[2]
assert np.allclose(axes @ np.diag(moments) @ axes.T, body.inertia, rtol=0, atol=1e-12)

# %%
# A CAD part: the L-bracket
# -------------------------
#
# ``examples/l_bracket.stl`` is an L-shaped bracket in millimetres: a leg of
# 60 mm along :math:`x` and one of 40 mm along :math:`y`, both 8 mm thick,
# extruded 30 mm along :math:`z`. Made of aluminium (2700 kg/m³), its mass
# properties come from the exact volume integrals of the polyhedron. The
# command line gives the same numbers with
# ``tumble inertia examples/l_bracket.stl --units mm --density "2700 kg/m^3"``.
#
# The page runs in ``docs/tutorials``, so the file is two folders up.

stl = Path("../../examples/l_bracket.stl")
assert stl.exists(), f"run this page from docs/tutorials: {stl.resolve()} is missing"
bracket = tb.from_mesh(stl, density="2700 kg/m^3", units="mm")
print(bracket)

# %%
# The same bracket is two boxes: the leg along :math:`x`, 60 × 8 × 30 mm,
# centred at (30, 4, 15) mm, and the rest of the leg along :math:`y`,
# 8 × 32 × 30 mm, centred at (4, 24, 15) mm. :func:`tumble.shapes.box` gives
# each about its own centre; ``transformed`` moves it and ``+`` adds the parts
# about their common centre of mass (the parallel-axis theorem again).

density = 2700.0  # kg/m³
leg_x = tb.shapes.box(density * 0.060 * 0.008 * 0.030, "60, 8, 30 mm")
leg_y = tb.shapes.box(density * 0.008 * 0.032 * 0.030, "8, 32, 30 mm")
assembly = leg_x.transformed(translation="30, 4, 15 mm") + leg_y.transformed(
    translation="4, 24, 15 mm"
)
scale = np.abs(bracket.inertia).max()
print(f"mass: mesh {bracket.mass:.9g} kg, two boxes {assembly.mass:.9g} kg")
print("centre of mass difference (m):", assembly.center_of_mass - bracket.center_of_mass)
print(
    "largest inertia difference / largest entry:",
    f"{np.abs(assembly.inertia - bracket.inertia).max() / scale:.1e}",
)
print(
    f"I_xy = {bracket.inertia[0, 1]:+.6e} kg·m², "
    f"so Σ m (x − x_G)(y − y_G) = {-bracket.inertia[0, 1]:+.6e} kg·m²"
)

# The vertices are whole millimetres, exact in the file's single precision, and
# both computations are exact formulas: they differ by float64 round-off only
# (~1e-16 relative); 1e-12 allows for the summation order of any platform.
assert np.isclose(assembly.mass, bracket.mass, rtol=1e-12)
assert np.allclose(assembly.center_of_mass, bracket.center_of_mass, rtol=0, atol=1e-14)
assert np.allclose(assembly.inertia, bracket.inertia, rtol=0, atol=1e-12 * scale)

# %%
# Seen from its centre of mass, most of the bracket lies where
# :math:`x - x_G` and :math:`y - y_G` have opposite signs (the end of the
# :math:`x` leg lies right of and below :math:`G`, the end of the :math:`y` leg
# left of and above it), so :math:`\sum m x y < 0` and :math:`I_{xy} > 0`. The
# bracket has a symmetry plane :math:`z = 15` mm, so :math:`z` is a principal
# axis; the other two lie in the :math:`xy` plane. There the eigenvectors of
# the :math:`2 \times 2` block give the axis of the smallest moment at the angle
# :math:`\theta_1 = \tfrac12 \operatorname{atan2}(-2 I_{xy},\, I_{yy} - I_{xx})`
# from :math:`x` (with :math:`I_{xy}` the tensor's entry, sign included).

b_moments, b_axes = bracket.principal()
ixx, iyy, ixy = bracket.inertia[0, 0], bracket.inertia[1, 1], bracket.inertia[0, 1]
theta = 0.5 * np.arctan2(-2 * ixy, iyy - ixx)
axis_1_angle = np.arctan2(b_axes[1, 0], b_axes[0, 0])
print("principal moments (kg·m²):", b_moments)
print("principal axes (columns):\n", b_axes)
print(
    f"axis 1 at {np.degrees(axis_1_angle):.4f} deg from x; "
    f"(1/2) atan2(−2 I_xy, I_yy − I_xx) = {np.degrees(theta):.4f} deg"
)

# %%
# The figure shows the bracket with its principal axes drawn from the centre
# of mass, each labelled with its moment.

mesh = trimesh.load(stl)  # coordinates in mm
fig = plt.figure(figsize=(7, 6))
ax = fig.add_subplot(projection="3d")
ax.add_collection3d(
    Poly3DCollection(
        mesh.vertices[mesh.faces], facecolor="0.75", edgecolor="0.4", linewidth=0.4, alpha=0.35
    )
)
centre = bracket.center_of_mass * 1000  # mm
for k, colour in enumerate(["tab:red", "tab:green", "tab:blue"]):
    tip = 35.0 * b_axes[:, k]
    ax.quiver(*centre, *tip, color=colour, linewidth=2, arrow_length_ratio=0.12)
    ax.text(*(centre + 1.1 * tip), f"$I_{k + 1}$", color=colour)
    ax.plot([], [], color=colour, label=f"axis {k + 1}: $I_{k + 1}$ = {b_moments[k]:.4e} kg·m²")
ax.scatter(*centre, color="k", s=20, label="centre of mass")
ax.set(xlabel="x (mm)", ylabel="y (mm)", zlabel="z (mm)")
ax.set(xlim=(-5, 65), ylim=(-15, 55), zlim=(-20, 50))
ax.set_box_aspect((1, 1, 1))
ax.view_init(elev=55, azim=-70)
ax.set_title("Aluminium L-bracket and its principal axes")
ax.legend(loc="upper left", fontsize="small")

# %%
# Where the formulas stop holding
# -------------------------------
#
# The tensor describes a *rigid* body: a part that flexes or carries fluid has
# no single tensor. The mesh integrals are exact for the polyhedron only if it
# bounds a solid, and a curved CAD surface is replaced by its triangles, so a
# cylinder's mesh has a little less volume than the cylinder; tumble refuses
# open meshes rather than return a number (a thin wall is computed with
# ``shell_thickness``). A uniform density is assumed: a part of several
# materials is an assembly of parts, added with ``+`` as above. Finally, when
# two principal moments are nearly equal, as :math:`I_2` and :math:`I_3` of
# this bracket are, their axes are well defined mathematically but turn a long
# way for a small change of shape; only the plane they span is robust.
