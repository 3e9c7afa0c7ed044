r"""
Why a spinning rotor's frequencies split: gyroscopic whirl
==========================================================

A rotor on two elastic bearings, at rest, has its natural frequencies in
pairs: it bounces or rocks equally well in any plane through its axis. Spin
it, and the rocking pairs split in two, one frequency rising with the speed
and the other falling, while the bouncing pairs stay where they are. The cause
is the gyroscopic moment of the spin's angular momentum, the same moment that
turns a gyroscope's axis. This page derives the split, computes it with
:class:`tumble.theory.RigidRotor` for a long rotor and a disk-like one, finds
their critical speeds, and follows an unbalanced rotor up through the first of
them.
"""

# %%
# Theory
# ------
#
# A rigid rotor of mass :math:`m`, with polar moment :math:`I_p` about its axis
# and transverse moment :math:`I_t` about a diameter through its centre of
# mass, spins at :math:`\Omega` about :math:`z`. Bearings at axial positions
# :math:`a_i` from the centre of mass act as springs of stiffness :math:`k_i`
# perpendicular to the axis. Small motions have four coordinates: the centre
# of mass's displacement :math:`(x, y)` and the axis's tilts :math:`\alpha`
# about :math:`x` and :math:`\beta` about :math:`y`, so that the shaft at
# :math:`a_i` is at :math:`(x + a_i\beta,\ y - a_i\alpha)`. Where
# :math:`\sum k_i a_i = 0` (bearings placed symmetrically about the centre of
# mass, for instance) the displacement and the tilt decouple. The displacement
# obeys
#
# .. math::
#
#    m\ddot x + \Big(\sum k_i\Big) x = 0, \qquad
#    \omega_{\mathrm{cyl}} = \sqrt{\frac{\sum k_i}{m}} ,
#
# the *cylindrical* mode, in which the axis moves parallel to itself, and the
# same in :math:`y`. The tilt does not, because the tilted axis carries the
# angular momentum :math:`I_p\Omega` with it: with
# :math:`\mathbf H \approx (I_t\dot\alpha + I_p\Omega\beta,\ I_t\dot\beta -
# I_p\Omega\alpha,\ I_p\Omega)` and the bearings' moment
# :math:`-K_\theta(\alpha, \beta)`, :math:`K_\theta = \sum k_i a_i^2`,
#
# .. math::
#
#    I_t\ddot\alpha + I_p\Omega\,\dot\beta + K_\theta\,\alpha = 0, \qquad
#    I_t\ddot\beta - I_p\Omega\,\dot\alpha + K_\theta\,\beta = 0 .
#
# At rest these are two copies of the *conical* mode, the axis rocking about
# the centre of mass at :math:`\sqrt{K_\theta / I_t}`. Spinning, the
# gyroscopic terms :math:`\pm I_p\Omega\dot\theta` couple them. A circular
# whirl :math:`\alpha + i\beta \propto e^{\pm i\omega t}`, the axis tracing a
# cone at :math:`\omega`, solves them when
# :math:`I_t\omega^2 \mp I_p\Omega\,\omega - K_\theta = 0`:
#
# .. math::
#
#    \omega_{f,b} = \frac{\pm I_p\Omega + \sqrt{I_p^2\Omega^2 + 4 I_t K_\theta}}{2 I_t} .
#
# The upper sign is the *forward* whirl, the cone traced in the sense of the
# spin: the gyroscopic moment pushes the tilted axis back towards the centre,
# as an added stiffness, and :math:`\omega_f` rises with :math:`\Omega`. The
# lower sign is the *backward* whirl, softened, and :math:`\omega_b` falls. In
# matrix form, for :math:`q = (x, y, \alpha, \beta)`,
# :math:`\mathsf M\ddot q + (\mathsf C + \Omega\mathsf G)\dot q + \mathsf K q
# = f`, with :math:`\mathsf G` antisymmetric (Friswell, Penny, Garvey & Lees,
# *Dynamics of Rotating Machines*, 2010, ch. 3; Genta, *Dynamics of Rotating
# Systems*, 2005, ch. 3). :meth:`tumble.theory.RigidRotor.whirl` solves this
# eigenproblem at every speed and tells forward from backward by the sense of
# each mode's orbit.
#
# The rotors
# ----------
#
# Two steel rotors (7850 kg/m³) on bearings of 2 MN/m each: a long one, a
# cylinder 50 cm long and 10 cm across between bearings 40 cm apart; and a
# disk-like one, a flywheel 40 cm across and 4 cm thick between bearings 30 cm
# apart (its short shaft's mass neglected). The positions of the bearings are
# measured from the centre of mass, the origin of both bodies.

import matplotlib.pyplot as plt
import numpy as np

import tumble as tb

steel = 7850.0  # kg/m³
rpm = np.pi / 30  # rad/s in one rpm
k = 2e6  # N/m, each bearing

long_body = tb.shapes.solid_cylinder(steel * np.pi * 0.05**2 * 0.5, "5 cm", "50 cm")  # 30.8 kg
disk_body = tb.shapes.solid_cylinder(steel * np.pi * 0.2**2 * 0.04, "20 cm", "4 cm")  # 39.5 kg
long_rotor = tb.theory.RigidRotor(
    long_body, [tb.theory.Bearing("-20 cm", k), tb.theory.Bearing("20 cm", k)]
)
disk_rotor = tb.theory.RigidRotor(
    disk_body, [tb.theory.Bearing("-15 cm", k), tb.theory.Bearing("15 cm", k)]
)
rotors = {
    "long rotor": (long_body, long_rotor, 0.2),
    "disk-like rotor": (disk_body, disk_rotor, 0.15),
}


def constants(body, arm):
    """m, I_p, I_t (about the centre of mass), Σk and K_θ for bearings k at ±arm."""
    return body.mass, body.inertia[2, 2], body.inertia[0, 0], 2 * k, 2 * k * arm**2


for name, (body, _, arm) in rotors.items():
    m, i_p, i_t, k_sum, k_theta = constants(body, arm)
    print(
        f"{name}: m = {m:.2f} kg, I_p = {i_p:.4f} kg·m², I_t = {i_t:.4f} kg·m² "
        f"(I_p / I_t = {i_p / i_t:.3f}), Σk = {k_sum:.1e} N/m, K_θ = {k_theta:.3g} N·m/rad"
    )

# %%
# At rest: bouncing and rocking
# -----------------------------
#
# :meth:`~tumble.theory.RigidRotor.whirl` at :math:`\Omega = 0` gives the
# modes of the long rotor: two pairs of frequencies, against
# :math:`\sqrt{\sum k / m}` and :math:`\sqrt{K_\theta / I_t}`:

m, i_p, i_t, k_sum, k_theta = constants(long_body, 0.2)
at_rest = long_rotor.whirl(0.0)
cylindrical, conical = np.sqrt(k_sum / m), np.sqrt(k_theta / i_t)
print("frequencies at rest:", at_rest.frequencies[0].round(3), "rad/s")
print(f"√(Σk/m) = {cylindrical:.3f} rad/s, √(K_θ/I_t) = {conical:.3f} rad/s")
# Eigenvalues of an 8 × 8 matrix whose entries span ~1e7: ~1e-13 relative.
assert np.allclose(at_rest.frequencies[0], [cylindrical] * 2 + [conical] * 2, rtol=1e-10)

# %%
# Each mode's shape is its :math:`(x, y, \alpha, \beta)`; the shaft at axial
# position :math:`z` moves by :math:`x + z\beta` in the :math:`x` direction and
# :math:`y - z\alpha` in the :math:`y` direction. At rest each pair can
# vibrate in any plane through the axis; the figure shows one mode of each pair
# in its plane, at two instants half a period apart, the displacement
# exaggerated: the cylindrical mode moves the whole rotor sideways, the conical
# mode rocks it about its centre of mass.

z = np.linspace(-0.25, 0.25, 2)  # the rotor's ends, m
fig, axes = plt.subplots(1, 2, figsize=(8, 3), sharey=True, layout="constrained")
for ax, mode, title in zip(axes, (0, 2), ("cylindrical", "conical"), strict=True):
    x, y, alpha, beta = at_rest.shapes[0, mode]
    in_x = abs(x) + abs(beta) > abs(y) + abs(alpha)  # the mode's plane: x, or else y
    plane = np.real(x + z * beta) if in_x else np.real(y - z * alpha)
    shift = 0.03 * plane / np.abs(plane).max()  # m, exaggerated
    for sign, shade in ((1, "tab:blue"), (-1, "tab:orange")):
        ax.fill_between(z, sign * shift - 0.05, sign * shift + 0.05, color=shade, alpha=0.4)
    ax.fill_between(z, -0.05, 0.05, facecolor="none", edgecolor="0.4", linestyle=":")
    ax.plot([-0.2, 0.2], [-0.09, -0.09], "k^", markersize=10, label="bearings")
    ax.set_title(f"{title}, {at_rest.frequencies[0, mode]:.1f} rad/s", fontsize="medium")
    ax.set(xlabel="axial position z (m)", aspect="equal", ylim=(-0.11, 0.11))
axes[0].set_ylabel("displacement (m)")
axes[0].legend(loc="upper left", fontsize="small")
plt.show()

# %%
# Spinning: the Campbell diagram
# ------------------------------
#
# The natural frequencies against the spin speed, for speeds up to 8000 rpm:
# forward whirls solid, backward dashed, each computed by
# :meth:`~tumble.theory.RigidRotor.whirl` (one eigenproblem a speed), with the
# closed form :math:`\omega_{f,b}` on top as circles and the *1× line*
# :math:`\omega = \Omega`. This is the *Campbell diagram* of rotor dynamics,
# drawn here in the engineer's units, Hz against rpm.

speeds = np.linspace(0.0, 8000.0, 401) * rpm  # rad/s
marks = slice(None, None, 25)
worst = 0.0
fig, axes = plt.subplots(1, 2, figsize=(9, 4), layout="constrained")
for ax, (name, (body, rotor, arm)) in zip(axes, rotors.items(), strict=True):
    m, i_p, i_t, k_sum, k_theta = constants(body, arm)
    whirl = rotor.whirl(speeds)
    root = np.sqrt(i_p**2 * speeds**2 + 4 * i_t * k_theta)
    forward, backward = (i_p * speeds + root) / (2 * i_t), (-i_p * speeds + root) / (2 * i_t)
    cylinder = np.full_like(speeds, np.sqrt(k_sum / m))
    # Each closed form against the nearest of whirl's frequencies with the same label.
    pairs = ((forward, True), (backward, False), (cylinder, True), (cylinder, False))
    for expected, sense in pairs:
        gap = np.abs(whirl.frequencies / expected[:, None] - 1)
        gap[whirl.forward != sense] = np.inf
        worst = max(worst, gap.min(axis=1).max())
    for sense, style in ((True, "-"), (False, "--")):
        # The two modes whirling each way, by frequency (where the backward
        # conical crosses the cylindrical mode the two lines swap, unseen).
        picked = np.sort(np.where(whirl.forward == sense, whirl.frequencies, np.inf), axis=1)
        ax.plot(speeds / rpm, picked[:, :2] / (2 * np.pi), style, color="tab:blue")
    for closed in (forward, backward):
        ax.plot(speeds[marks] / rpm, closed[marks] / (2 * np.pi), "o", mfc="none", color="tab:red")
    ax.plot(speeds / rpm, speeds / (2 * np.pi), color="0.4", lw=0.8)
    ax.text(7900, 7900 / 60, "1×", ha="right", va="bottom", color="0.4")
    ax.set(xlabel="spin speed Ω (rpm)", title=f"{name}, I_p / I_t = {i_p / i_t:.2f}")
    ax.set_ylim(0, None)
axes[0].set_ylabel("natural frequency (Hz)")
axes[0].plot([], [], "-", color="tab:blue", label="forward whirl")
axes[0].plot([], [], "--", color="tab:blue", label="backward whirl")
axes[0].plot([], [], "o", mfc="none", color="tab:red", label=r"closed form $\omega_{f,b}$")
axes[0].legend(loc="upper left", fontsize="small")
plt.show()
print(f"largest relative difference, whirl vs the closed forms: {worst:.1e}")
# As at rest: the eigenvalues to ~1e-13, and every frequency carries the right label.
assert worst < 1e-10

# %%
# The cylindrical pair, one forward and one backward whirl at the same
# frequency, stays at :math:`\sqrt{\sum k / m}` whatever the speed: a rotor
# moving parallel to itself does not tilt its angular momentum.
# The long rotor's conical pair splits a little (:math:`I_p` is small); the
# disk's splits wide, its forward whirl rising almost twice as fast as the
# spin. At one speed, given as a string with its unit:

print("long rotor at 3000 rpm:", long_rotor.frequencies("3000 rpm").round(2), "rad/s")
print("disk-like rotor at 3000 rpm:", disk_rotor.frequencies("3000 rpm").round(2), "rad/s")

# %%
# Critical speeds
# ---------------
#
# An unbalance is a force that turns with the rotor, at :math:`\Omega`: it
# drives a forward whirl synchronous with the spin, and the rotor resonates
# where a forward frequency meets the 1× line, at a *critical speed*. For the
# cylindrical mode that is :math:`\sqrt{\sum k / m}`. For the conical mode,
# :math:`\omega_f = \Omega` in :math:`I_t\omega^2 - I_p\Omega\omega - K_\theta
# = 0` gives
#
# .. math::
#
#    \Omega_c = \sqrt{\frac{K_\theta}{I_t - I_p}} ,
#
# which exists only if :math:`I_t > I_p`. The reason is the asymptote: at high
# speed :math:`\omega_f \to I_p\Omega / I_t`, so for a disk-like rotor
# (:math:`I_p > I_t`) the forward conical frequency runs away from the 1× line
# faster than the spin and never meets it, while for a long rotor it falls
# behind the spin and must cross. A thin disk, :math:`I_p = 2 I_t`, whirls
# forward at nearly twice its spin when fast. :meth:`~tumble.theory.RigidRotor.critical_speeds`
# finds the crossings from the synchronous eigenproblem
# :math:`\mathsf K v = \Omega^2(\mathsf M - i\mathsf G) v`:

for name, (body, rotor, arm) in rotors.items():
    m, i_p, i_t, k_sum, k_theta = constants(body, arm)
    critical = rotor.critical_speeds()
    expected = [np.sqrt(k_sum / m)]
    if i_t > i_p:
        expected.append(np.sqrt(k_theta / (i_t - i_p)))
    print(
        f"{name}: critical speeds {critical.round(2)} rad/s = {(critical / rpm).round(0)} rpm; "
        f"√(Σk/m), √(K_θ/(I_t − I_p)) = {np.round(expected, 2)} rad/s"
    )
    assert np.allclose(critical, expected, rtol=1e-10)

# %%
# The ratio :math:`\omega_f / \Omega` of the forward conical whirl makes the
# difference plain: it starts at infinity and falls to :math:`I_p / I_t`, so it
# crosses 1 only if :math:`I_p / I_t < 1` (the speeds go far beyond any real
# machine's, to show the limit).

fast = np.geomspace(100.0, 1e5, 300) * rpm  # rad/s
fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
for (name, (body, rotor, arm)), colour in zip(
    rotors.items(), ("tab:blue", "tab:green"), strict=True
):
    m, i_p, i_t, k_sum, k_theta = constants(body, arm)
    forward_conical = rotor.frequencies(fast)[:, -1]  # the highest: forward conical
    ax.loglog(fast / rpm, forward_conical / fast, color=colour, label=name)
    ax.axhline(i_p / i_t, color=colour, linestyle=":", label=f"$I_p / I_t$ = {i_p / i_t:.2f}")
    for speed in rotor.critical_speeds():
        if speed > np.sqrt(k_sum / m) * (1 + 1e-9):  # the conical one
            ax.plot(speed / rpm, 1.0, "o", color=colour, label=f"critical, {speed / rpm:.0f} rpm")
ax.axhline(1.0, color="0.4", lw=0.8)
ax.set(xlabel="spin speed Ω (rpm)", ylabel=r"forward conical whirl $\omega_f / \Omega$")
ax.legend(fontsize="small")
plt.show()

# %%
# The unbalance response
# ----------------------
#
# Now the long rotor with dampers of 500 N·s/m in its bearings and an
# unbalance :math:`U` of 20 g·cm (20 g at 1 cm from the axis: the centre of
# mass :math:`U / m` = 6.5 µm off the axis, which meets balance grade G 2.5,
# :math:`e\Omega` ≤ 2.5 mm/s, up to about 3700 rpm). The steady orbit at each
# bearing is a circle, its radius from
# :meth:`~tumble.theory.RigidRotor.unbalance_response`. Two cases: the
# unbalance in the centre plane, and the same unbalance at one end of the
# rotor, 25 cm from the centre.
#
# Far above the criticals the rotor turns about its own centre of mass and
# principal axis, wherever those are: it is *self-centring* (Jeffcott,
# *Phil. Mag.* 37, 1919). An unbalance :math:`U` moves the centre of mass
# :math:`U / m` off the shaft's axis, and, at an axial arm :math:`a_u`, adds a
# product of inertia :math:`U a_u` that tilts the principal axis by
# :math:`U a_u / (I_t - I_p)`. So the shaft at a bearing at :math:`a` orbits
# at
#
# .. math::
#
#    r \to U\left|\frac{1}{m} + \frac{a\,a_u}{I_t - I_p}\right| ,
#
# which is :math:`U / m` at both bearings for an unbalance in the centre plane.

damped = tb.theory.RigidRotor(
    long_body,
    [tb.theory.Bearing("-20 cm", k, "500 N*s/m"), tb.theory.Bearing("20 cm", k, "500 N*s/m")],
)
unbalance = 2e-4  # kg·m, 20 g·cm
m, i_p, i_t, k_sum, k_theta = constants(long_body, 0.2)
arms = np.array([-0.2, 0.2])  # the bearings, m
sweep = np.geomspace(300.0, 30000.0, 3000) * rpm  # rad/s
critical = damped.critical_speeds()

fig, ax = plt.subplots(figsize=(8, 4.5), layout="constrained")
cases = (("centre plane", 0.0, "tab:blue"), ("end plane, 25 cm", 0.25, "tab:red"))
for label, position, colour in cases:
    response = damped.unbalance_response(sweep, unbalance, position)
    limit = unbalance * np.abs(1 / m + arms * position / (i_t - i_p))
    for bearing, style in ((0, "-"), (1, "--")):
        where = f"{label}, bearing at {arms[bearing] * 100:+.0f} cm"
        ax.loglog(sweep / rpm, response[:, bearing] * 1e6, style, color=colour, label=where)
        ax.axhline(limit[bearing] * 1e6, color=colour, linestyle=":", lw=0.8)
    peaks = sweep[np.argmax(response, axis=0)]
    print(
        f"unbalance in the {label}: largest orbit {response.max() * 1e6:.1f} µm at "
        f"{(peaks / rpm).round(0)} rpm; at {sweep[-1] / rpm:.0f} rpm "
        f"{(response[-1] * 1e6).round(3)} µm, self-centred limit {(limit * 1e6).round(3)} µm"
    )
    # Undamped, each of the two terms of the limit is reached within a factor
    # 1/(1 − (Ω_c/Ω)²) of its critical Ω_c, here 2.7 % at most; the light
    # damping changes that by ~ζ² (0.2 %).
    ratio = (critical[-1] / sweep[-1]) ** 2
    bound = 1.1 * ratio / (1 - ratio) * unbalance * (1 / m + np.abs(arms * position) / (i_t - i_p))
    assert np.all(np.abs(response[-1] - limit) < bound)
for speed in critical:
    ax.axvline(speed / rpm, color="0.5", lw=0.8)
ax.set(xlabel="spin speed Ω (rpm)", ylabel="orbit radius at the bearing (µm)")
ax.legend(fontsize="small")
plt.show()

# %%
# The grey lines are the critical speeds of
# :meth:`~tumble.theory.RigidRotor.critical_speeds`, the dotted ones the
# self-centred limits. The centre-plane unbalance excites only the cylindrical
# mode, by symmetry, and its orbit is the same at both bearings. The one at the
# end of the rotor excites both modes, and its orbits differ between the
# bearings; below the criticals, at the bearing far from the unbalance, the
# shift and the tilt cancel at one speed (the dip). Above the criticals each
# orbit falls to its limit.
#
# A run-up through the first critical
# -----------------------------------
#
# A machine does not sit at a critical speed: it is run up through it.
# ``tumble.models.run_up`` integrates the equations with the speed rising at a
# constant rate, here 3000 rpm per second from 2000 rpm, for one second, with
# the centre-plane unbalance. The rotor starts at rest on the axis, so it first
# vibrates freely at its natural frequencies, which the dampers soon take out.
# Through the critical it has too little time for the resonance to build up:
# the peak comes later and lower than the steady one (Lewis, *Trans. ASME* 54,
# 1932). Past it, the free whirl that the passage leaves behind, at the
# natural frequency, beats against the forced one at :math:`\Omega` and dies
# away.

run = tb.models.run_up(
    damped, unbalance, duration=1.0, speed="2000 rpm", acceleration="3000 rpm/s", samples=4001
)
steady = damped.unbalance_response(run.speed, unbalance)[:, 0]
top, top_steady = np.argmax(run.amplitude[:, 0]), np.argmax(steady)
print(
    f"steady: peak {steady[top_steady] * 1e6:.1f} µm at {run.speed[top_steady] / rpm:.0f} rpm; "
    f"run-up: peak {run.amplitude[top, 0] * 1e6:.1f} µm at {run.speed[top] / rpm:.0f} rpm"
)
assert run.speed[top] > run.speed[top_steady] and run.amplitude[top, 0] < steady[top_steady]

fig, ax = plt.subplots(figsize=(8, 4), layout="constrained")
ax.plot(run.speed / rpm, run.amplitude[:, 0] * 1e6, color="tab:blue", label="run-up, 3000 rpm/s")
ax.plot(run.speed / rpm, steady * 1e6, "k--", label="steady response")
ax.axvline(critical[0] / rpm, color="0.5", lw=0.8)
ax.set(xlabel="spin speed Ω (rpm)", ylabel="orbit radius at the bearing (µm)")
ax.legend()
plt.show()

# %%
# Where the formulas stop holding
# -------------------------------
#
# The model is a rigid rotor: it holds while the shaft's own bending
# frequencies lie far above the speeds of interest, and a flexible rotor adds
# a bending critical for each of them. The closed forms above need
# :math:`\sum k_i a_i = 0`; otherwise the cylindrical and conical modes
# couple, and the frequencies are those of the full 4 × 4 problem, which
# :meth:`~tumble.theory.RigidRotor.whirl` solves in any case.
# Bearings of different stiffness in :math:`x` and :math:`y` split every pair
# even at rest and make the orbits ellipses; an unbalance then excites
# backward whirl too, and :meth:`~tumble.theory.RigidRotor.critical_speeds`
# lists those speeds as well. Real bearings are not simple springs: oil-film bearings have
# stiffness and damping that change with the speed, and cross-coupled terms
# that can make a forward whirl unstable (oil whirl). And the damped peaks sit
# a little away from the undamped critical speeds, by an amount of the order
# of the damping ratio squared.
