r"""
Angular momentum and the rotating skew rod
==========================================

A rod fixed at its centre to a vertical shaft, at an angle to it, and turned at
a constant rate: the classic example of a body whose angular momentum is not
parallel to its angular velocity. The angular momentum turns with the rod, so
the shaft must push on the rod through its bearings even though nothing speeds
up or slows down. This page derives that torque, computes it with tumble in
closed form and by simulation, and finds the bearing loads.
"""

# %%
# Theory
# ------
#
# The angular momentum of a rigid body about its centre of mass is
# :math:`\mathbf L = \mathsf I\,\boldsymbol\omega`, with the inertia tensor
#
# .. math::
#
#    I_{ij} = \sum m\,(r^2\delta_{ij} - r_i r_j),
#
# so that, written out,
#
# .. math::
#
#    L_x = \omega_x \sum m\,(y^2 + z^2) - \omega_y \sum m\,x y - \omega_z \sum m\,x z,
#
# and cyclically. The products of inertia enter the tensor with a minus sign,
# :math:`I_{xy} = -\sum m\,x y`, which is what makes :math:`\mathbf L =
# \mathsf I\boldsymbol\omega` a plain matrix product (Kleppner & Kolenkow,
# *An Introduction to Mechanics*, ch. 7; Goldstein, *Classical Mechanics*, §5.1).
#
# A thin uniform rod of mass :math:`m` and length :math:`\ell` along the unit
# vector :math:`\hat{\mathbf u}` has :math:`\mathsf I = \tfrac{m\ell^2}{12}
# (\mathbb 1 - \hat{\mathbf u}\hat{\mathbf u}^{\mathsf T})`. Fix its centre on a
# vertical shaft at an angle :math:`\alpha` from the shaft and turn the shaft
# at :math:`\boldsymbol\omega = \Omega\hat{\mathbf z}`. Then
#
# .. math::
#
#    \mathbf L = \frac{m\ell^2}{12}\,\Omega\,(\hat{\mathbf z} - \cos\alpha\,\hat{\mathbf u}),
#    \qquad |\mathbf L| = \frac{m\ell^2}{12}\,\Omega\sin\alpha .
#
# :math:`\mathbf L` is perpendicular to the rod, not along the shaft. Its
# horizontal part, of magnitude :math:`L_\perp = \tfrac{m\ell^2}{12}\Omega\sin\alpha
# \cos\alpha`, points opposite to the horizontal projection of the rod's upper
# half and turns with it,
# so :math:`\mathbf L` changes although :math:`\Omega` is constant. The shaft must
# supply
#
# .. math::
#
#    \boldsymbol\tau = \frac{d\mathbf L}{dt} = \boldsymbol\omega\times\mathbf L,
#    \qquad |\boldsymbol\tau| = \Omega L_\perp
#    = \frac{m\ell^2}{12}\,\Omega^2\sin\alpha\cos\alpha ,
#
# a horizontal torque that turns with the rod. In body axes this is Euler's
# equation :math:`\boldsymbol\tau = \mathsf I\dot{\boldsymbol\omega} +
# \boldsymbol\omega\times(\mathsf I\boldsymbol\omega)` with
# :math:`\dot{\boldsymbol\omega} = 0`. The torque is largest at
# :math:`\alpha = 45^\circ` and vanishes when the rod is along the shaft or
# perpendicular to it, the two positions in which the shaft is a principal axis.
#
# Two bearings on the shaft at :math:`z = \pm d/2` supply it as a couple: the
# centre of mass does not move, so the two forces are equal and opposite,
# horizontal, of magnitude :math:`|\boldsymbol\tau|/d`, and turn with the rod.
#
# A rod of finite thickness, a cylinder of radius :math:`r` with moments
# :math:`I_\perp = m(3r^2 + \ell^2)/12` and :math:`I_\parallel = m r^2/2` about
# its centre, needs :math:`|\boldsymbol\tau| = (I_\perp - I_\parallel)\,\Omega^2
# \sin\alpha\cos\alpha`: the thickness lowers the torque, and a cylinder with
# :math:`\ell = \sqrt 3\,r` has equal moments and needs none.

import matplotlib.pyplot as plt
import numpy as np
from scipy.spatial.transform import Rotation

import tumble as tb

m = 0.5  # kg, the rod's mass
ell = 0.4  # m, its length
alpha = np.radians(30.0)  # the rod's angle from the shaft
big_omega = 20.0  # rad/s, the shaft's rate
d = 0.2  # m, the distance between the two bearings

# tumble's thin rod lies along body z; turning it by α about y puts it at α from
# the shaft (space z), along u = (sin α, 0, cos α), at t = 0.
turn = Rotation.from_euler("y", alpha)
rod = tb.shapes.thin_rod(m, ell).transformed(rotation=turn)
u = turn.apply([0.0, 0.0, 1.0])
omega = np.array([0.0, 0.0, big_omega])

# %%
# L and the torque, by tumble and in closed form
# ----------------------------------------------
#
# :func:`tumble.angular_momentum` computes :math:`\mathsf I\boldsymbol\omega`
# and :func:`tumble.required_torque` the right-hand side of Euler's equation,
# both in body axes (which coincide with space axes at :math:`t = 0`).

L = tb.angular_momentum(rod, omega)
tau = tb.required_torque(rod, omega, [0.0, 0.0, 0.0])

k = m * ell**2 / 12  # kg·m², the rod's transverse moment
L_closed = k * big_omega * (np.array([0.0, 0.0, 1.0]) - np.cos(alpha) * u)
tau_closed = k * big_omega**2 * np.sin(alpha) * np.cos(alpha)

print(f"L (tumble)        = {L} kg·m²/s")
print(f"L (closed form)   = {L_closed} kg·m²/s")
print(f"L · u             = {L @ u:.2e} kg·m²/s (L is perpendicular to the rod)")
angle = np.degrees(np.arccos(L @ omega / (np.linalg.norm(L) * big_omega)))
print(f"angle between L and ω: {angle:.2f}°")
print(f"τ (tumble)        = {tau} N·m")
print(f"|τ| closed form   = {tau_closed:.6f} N·m")

# %%
# The bearing loads
# -----------------
#
# :func:`tumble.theory.rotor_loads` solves the statics of any body spun about a
# fixed axis between two bearings: here at :math:`z = -d/2` and :math:`+d/2`
# (the two rows of the printed array).
# :func:`tumble.theory.skew_rod` is the classic model of the lecture notes, two
# point masses on a massless rod, with its angle measured from the plane
# perpendicular to the shaft. Two masses :math:`m/2` at
# :math:`\pm\ell/(2\sqrt3)` have exactly the inertia of the uniform rod
# (two-point Gauss quadrature), so that model with the angle
# :math:`90^\circ - \alpha` gives the same torque and bearing forces.

loads = tb.theory.rotor_loads(rod, big_omega, axis=[0, 0, 1], bearings=(-d / 2, d / 2))
classic = tb.theory.skew_rod(
    m / 2, ell / (2 * np.sqrt(3)), np.pi / 2 - alpha, big_omega, bearing_separation=d
)
print(f"forces the two bearings exert on the shaft (rotor_loads), N:\n{loads.bearing_forces}")
print(f"net force (the centre of mass stays on the axis): {loads.force} N")
print(
    f"|F| each: rotor_loads {np.linalg.norm(loads.bearing_forces[0]):.6f} N, "
    f"skew_rod {classic.bearing_force:.6f} N, |τ|/d = {tau_closed / d:.6f} N"
)
print(f"|τ|: skew_rod {classic.torque:.6f} N·m")

assert np.allclose(L, L_closed, rtol=1e-12, atol=1e-15)
# Closed forms on both sides: they agree to round-off (1e-12 of |τ| leaves room
# for the last digits of the products, nothing for a physical difference).
for value in (np.linalg.norm(tau), np.linalg.norm(loads.torque), classic.torque):
    assert abs(value - tau_closed) < 1e-12 * tau_closed
assert abs(classic.bearing_force - tau_closed / d) < 1e-12 * tau_closed / d

# %%
# Classic slips
# -------------
#
# Lecture notes sometimes write the last term of :math:`L_x` as
# :math:`-\omega_z\sum m\,x y` instead of :math:`-\omega_z\sum m\,x z`. For the
# rod in the :math:`x`-:math:`z` plane, :math:`\sum m\,x y = 0`: the slip would
# give :math:`L_x = 0`, :math:`\mathbf L` along the shaft and no torque at all.
# With the two point masses of the same inertia:

r = ell / (2 * np.sqrt(3)) * np.array([u, -u])  # positions of the two masses, m
masses = np.array([m / 2, m / 2])
x, y, z = r.T
right = -big_omega * np.sum(masses * x * z)  # −ω_z Σ m x z, kg·m²/s
slip = -big_omega * np.sum(masses * x * y)  # −ω_z Σ m x y
pair = tb.point_masses(masses, r)
print(f"L_x = −ω_z Σ m x z = {right:.6f} kg·m²/s, tumble {tb.angular_momentum(pair, omega)[0]:.6f}")
print(f"L_x = −ω_z Σ m x y = {slip + 0.0:.6f} kg·m²/s (the slip)")
print(f"I_xz = {pair.inertia[0, 2]:.6f} kg·m² = −Σ m x z = {-np.sum(masses * x * z):.6f} kg·m²")

# %%
# The sign matters for the same reason: with :math:`I_{xz} = +\sum m\,x z` the
# product :math:`\mathsf I\boldsymbol\omega` would tilt :math:`\mathbf L` to
# the wrong side of the shaft. Last, the axes about which no such torque is
# needed are the *principal* axes (sometimes misprinted "primordial"), the
# eigenvectors of :math:`\mathsf I`: for the rod, its own direction and any
# direction perpendicular to it. The shaft is neither.

moments, axes = rod.principal()
print(f"principal moments {moments.round(12) + 0.0} kg·m²")
print(f"axis of the smallest moment {axes[:, 0].round(12) + 0.0}, the rod u = {u}")
print(f"I ẑ = {rod.inertia @ [0.0, 0.0, 1.0]} kg·m²: not along ẑ")

# %%
# Simulation: a rod of finite thickness driven at a steady rate
# -------------------------------------------------------------
#
# A real rod has a thickness; take a cylinder of radius 2 cm (a thin rod has
# no moment about its axis and cannot be simulated). The torque model
# :class:`tumble.torques.HoldRotation` is the body-fixed torque
# :math:`\boldsymbol\omega_0\times(\mathsf I\boldsymbol\omega_0)` that the motor
# and bearings supply. :func:`tumble.simulate` follows Euler's equations under
# it for one turn; if that torque is right, :math:`\boldsymbol\omega` stays on
# the shaft and :math:`\mathbf L` turns rigidly about it. Its rate of change,
# by five-point differences on the samples, is the torque the shaft supplies.

radius = 0.02  # m
cylinder = tb.shapes.solid_cylinder(m, radius, ell).transformed(rotation=turn)
turn_time = 2 * np.pi / big_omega
run = tb.simulate(
    cylinder,
    omega,
    duration=turn_time,
    dt=turn_time / 400,
    torque=tb.torques.HoldRotation(),
)
print(run)

i_perp = m * (3 * radius**2 + ell**2) / 12
i_axial = m * radius**2 / 2
tau_cylinder = (i_perp - i_axial) * big_omega**2 * np.sin(alpha) * np.cos(alpha)

L_space = run.angular_momentum  # (n, 3), space axes, kg·m²/s
step = run.t[1] - run.t[0]  # the samples are evenly spaced
# Five-point central differences for dL/dt at the inner samples.
dL_dt = (L_space[:-4] - 8 * L_space[1:-3] + 8 * L_space[3:-1] - L_space[4:]) / (12 * step)
inner = slice(2, -2)
omega_cross_L = np.cross(run.omega_space[inner], L_space[inner])
worst_rate = np.max(np.linalg.norm(dL_dt - omega_cross_L, axis=1)) / tau_cylinder
worst_omega = np.max(np.abs(run.omega_space - omega)) / big_omega
print(f"ω stays on the shaft: largest |ω − Ω ẑ| / Ω = {worst_omega:.1e}")
print(
    f"|dL/dt| over the turn: {np.linalg.norm(dL_dt, axis=1).min():.6f} to "
    f"{np.linalg.norm(dL_dt, axis=1).max():.6f} N·m"
)
print(f"(I⊥ − I∥) Ω² sin α cos α = {tau_cylinder:.6f} N·m (thin rod: {tau_closed:.6f} N·m)")
print(f"largest |dL/dt − ω × L| / |τ| = {worst_rate:.1e}")

# The five-point difference errs by (Ω Δt)⁴/30 of |dL/dt|, with Ω Δt = 2π/400:
# 2e-9. 1e-7 bounds it with room; a wrong torque model would miss by O(1).
assert worst_rate < 1e-7
assert worst_omega < 1e-9  # the adaptive integrator's tolerance (rtol 1e-10)
assert np.allclose(np.linalg.norm(dL_dt, axis=1), tau_cylinder, rtol=1e-7), (
    "|dL/dt| is the closed form"
)

# %%
# :math:`\mathbf L` over one turn: its vertical part stays, its horizontal part
# turns with the rod (left; the dotted lines are the thin rod's closed form,
# which differs slightly). Seen from above (right), the
# horizontal part of :math:`\mathbf L` points opposite to the horizontal
# projection of the rod's upper half at every instant.

phase = big_omega * run.t
closed_L = tb.theory.skew_rod(
    m / 2, ell / (2 * np.sqrt(3)), np.pi / 2 - alpha, big_omega
).angular_momentum_at(run.t)  # the thin rod's L(t), space axes
fig, (left, right_ax) = plt.subplots(1, 2, figsize=(10, 4.2), layout="constrained")
for j, name in enumerate("xyz"):
    left.plot(np.degrees(phase), L_space[:, j], label=f"$L_{name}$, simulated cylinder")
    left.plot(np.degrees(phase), closed_L[:, j], "k:", lw=1)
left.plot([], [], "k:", lw=1, label="thin rod, closed form")
left.set_xlabel("shaft angle Ωt (deg)")
left.set_ylabel("L, space axes (kg·m²/s)")
left.set_xticks(np.arange(0, 361, 90))
left.set_ylim(-0.105, 0.07)
left.legend(fontsize="small", loc="lower center", ncols=2)

rod_dir = run.rotation.apply(u)  # the rod's upper half: body axes = space axes at t = 0
for colour, degrees in zip(("C0", "C1", "C2"), (0, 120, 240), strict=True):
    n = np.argmin(np.abs(np.degrees(phase) - degrees))
    right_ax.plot([0, rod_dir[n, 0]], [0, rod_dir[n, 1]], color=colour, lw=5, alpha=0.4)
    h = L_space[n, :2] / np.hypot(*L_space[n, :2])
    right_ax.annotate(
        "", xy=h, xytext=(0, 0), arrowprops={"arrowstyle": "->", "color": colour, "lw": 1.5}
    )
    right_ax.text(*(1.25 * h), f"Ωt = {degrees}°", color=colour, ha="center", va="center")
right_ax.plot([], [], color="0.5", lw=5, alpha=0.4, label="rod's upper half (projection)")
right_ax.plot([], [], color="0.5", label="horizontal part of L (direction)")
right_ax.set_aspect("equal")
right_ax.set_xlim(-1.6, 1.6)
right_ax.set_ylim(-1.35, 1.6)
right_ax.set_xlabel("x (space, unit length)")
right_ax.set_ylabel("y (space, unit length)")
right_ax.legend(fontsize="small", loc="upper center")
fig.suptitle(f"Rod at α = {np.degrees(alpha):.0f}° from the shaft, Ω = {big_omega:.0f} rad/s")
plt.show()

# %%
# The torque against the angle
# ----------------------------
#
# The closed form :math:`(I_\perp - I_\parallel)\,\Omega^2\sin\alpha\cos\alpha`
# against :func:`tumble.required_torque`, for rods of the same mass and length
# at angles from 0° to 90°: thin, and cylinders of three radii. All peak at
# 45°; the thicker the rod, the smaller the torque, and the cylinder with
# :math:`r = \ell/\sqrt 3` (equal moments: every axis through its centre is
# principal) needs none.

angles = np.radians(np.linspace(0.0, 90.0, 91))
marks = np.radians(np.arange(0.0, 91.0, 7.5))


def torque_of(body, a):
    """|τ| that keeps `body`, turned by `a` about y, spinning at Ω about z, N·m."""
    turned = body.transformed(rotation=Rotation.from_euler("y", a))
    return np.linalg.norm(tb.required_torque(turned, omega, [0.0, 0.0, 0.0]))


fig, ax = plt.subplots(figsize=(6.4, 4.2), layout="constrained")
bodies = {
    "thin rod": tb.shapes.thin_rod(m, ell),
    "cylinder, r = 2 cm": tb.shapes.solid_cylinder(m, radius, ell),
    "cylinder, r = 10 cm": tb.shapes.solid_cylinder(m, 0.1, ell),
    "cylinder, r = ℓ/√3": tb.shapes.solid_cylinder(m, ell / np.sqrt(3), ell),
}
worst = 0.0
for colour, (name, body) in zip(("C0", "C1", "C2", "C3"), bodies.items(), strict=True):
    i_par = body.inertia[2, 2]  # about the cylinder's own axis, body z before turning
    i_tr = body.inertia[0, 0]
    curve = (i_tr - i_par) * big_omega**2 * np.sin(angles) * np.cos(angles)
    computed = np.array([torque_of(body, a) for a in marks])
    expected = (i_tr - i_par) * big_omega**2 * np.sin(marks) * np.cos(marks)
    worst = max(worst, np.max(np.abs(computed - expected)) / tau_closed)
    ax.plot(np.degrees(angles), curve, color=colour, label=name)
    ax.plot(np.degrees(marks), computed, "o", color=colour, mfc="none")
    print(f"{name:20s} I⊥ − I∥ = {i_tr - i_par:.3e} kg·m², largest |τ| {curve.max():.4f} N·m")
ax.plot([], [], "o", color="0.4", mfc="none", label="tumble.required_torque")
print(f"largest difference, required_torque vs (I⊥ − I∥) Ω² sin α cos α: {worst:.1e} of |τ|")
ax.set_xlabel("angle α of the rod from the shaft (deg)")
ax.set_ylabel("torque |τ| (N·m)")
ax.set_xticks(np.arange(0, 91, 15))
ax.legend(fontsize="small")
plt.show()

# %%
# The built-in scenario
# ---------------------
#
# ``tumble run skew-rod`` runs the same experiment on a rod with a ball at each
# end (``tumble show skew-rod`` prints the scenario file): the body is
# simulated under the steady-rate torque and its :math:`|\mathbf L|`, the angle
# between :math:`\mathbf L` and :math:`\boldsymbol\omega`, :math:`|d\mathbf L/dt|`
# and the bearing forces are compared with :func:`tumble.theory.rotor_loads`.
# From Python, ``tumble.scenario.run`` returns the same comparison:

import tumble.scenario  # noqa: E402

result = tumble.scenario.run("skew-rod")
for row in result.comparisons:
    print(
        f"{row['quantity']:24s} theory {row['theory']:.6g} {row['unit']:8s} "
        f"relative error {row['relative_error']:.1e}"
    )

# %%
# Where the formula stops holding
# -------------------------------
#
# The formula assumes a rigid rod turned at a constant rate by a shaft held
# in rigid bearings. If :math:`\Omega` changes, Euler's equation adds
# :math:`\mathsf I\dot{\boldsymbol\omega}`, which has a part along the shaft
# (the motor's torque) and, because :math:`\mathsf I\hat{\mathbf z}` is not
# along :math:`\hat{\mathbf z}`, a horizontal part too. The loads above are the
# dynamic ones only: the rod's weight adds a constant load along the shaft,
# and a centre of mass off the shaft adds the rotating force
# :math:`m\Omega^2 r_\perp` of a statically unbalanced rotor (which
# :func:`tumble.theory.rotor_loads` includes). At high rates a real rod bends under the
# centrifugal loads, which changes its inertia tensor; and a rod released from
# its shaft does not keep turning about it: without the torque, its angular
# velocity leaves the shaft and the rod tumbles, since the shaft is not a
# principal axis. The same torque appears in every rotor whose axis of
# rotation is not a principal axis (dynamic imbalance); balancing a rotor means
# making the shaft a principal axis through the centre of mass.
