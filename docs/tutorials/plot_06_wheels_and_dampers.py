r"""
Wheels and dampers: dual spin and Explorer 1
============================================

Explorer 1, the first American satellite (1958), was a long thin cylinder
spun about its long axis, the axis of its *smallest* moment of inertia. A
free rigid body spins stably about that axis, yet within hours Explorer 1 was
tumbling end over end: its flexible antennas turned some of the kinetic
energy into heat. This page shows the same fate with an internal
energy sink, a Kane damper (:class:`tumble.KaneDamper`), and then how a wheel
spinning inside the body (:class:`tumble.Rotor`) makes the same spin stable:
the *dual-spin* principle of later spacecraft.
"""

# %%
# Theory: the energy sink
# -----------------------
#
# An internal part exerts no torque on the body as a whole, so the angular
# momentum :math:`\mathbf H` stays fixed in space, while a damper turns kinetic
# energy :math:`T` into heat. For an axisymmetric body (axial moment
# :math:`I_a`, transverse :math:`I_t`) let :math:`\theta` be the *nutation
# angle* between the symmetry axis and :math:`\mathbf H`. With
# :math:`H = |\mathbf H|` fixed, a rigid body has
#
# .. math::
#
#    T(\theta) = \frac{H^2 \sin^2\theta}{2 I_t} + \frac{H^2 \cos^2\theta}{2 I_a} .
#
# For a prolate body spun about its axis (:math:`I_a < I_t`), :math:`T` is
# largest at :math:`\theta = 0`, so losing energy *increases* :math:`\theta`,
# until the body spins about a transverse axis, :math:`\theta = 90°`, with the
# least energy compatible with :math:`H`, :math:`T = H^2 / (2 I_t)`. This is
# the *major-axis rule* (Bracewell & Garriott, *Nature* 182 (1958) 760; Hughes,
# *Spacecraft Attitude Dynamics*, on energy dissipation): a body that loses
# energy ends up spinning about its axis of largest moment.
#
# A Kane damper is a sphere of moment :math:`J` in a cavity filled with viscous
# fluid, coupled to the body by the torque :math:`D (\boldsymbol\omega -
# \boldsymbol\omega_s)`. Linearised about a spin :math:`\Omega`, the nutation
# grows or decays as :math:`e^{-\sigma t}`;
# :func:`tumble.theory.kane_damper_decay` gives :math:`\sigma` (negative here:
# growth) from the eigenvalues of the linear equations.
#
# The body
# --------
#
# A prolate satellite: a 100 kg cylinder 2 m long and 1 m across, a Kane
# damper (a 20 kg sphere of 20 cm radius, :math:`D` = 0.2 N·m·s) 0.6 m up its
# axis and a 10 kg wheel (30 cm radius, 5 cm thick) 0.6 m down it, the wheel's
# axis along the body's. Following tumble's convention, the
# :class:`tumble.MassProperties` hold every part as if locked to the body; the
# part objects add only what locking hides. In part (a) the wheel does not
# turn relative to the body, so it is simply part of the rigid body.

import matplotlib.pyplot as plt
import numpy as np

import tumble as tb

hull = tb.shapes.solid_cylinder("100 kg", radius="0.5 m", height="2 m")  # axis along body z
sphere = tb.shapes.solid_sphere("20 kg", radius="20 cm")
disc = tb.shapes.solid_cylinder("10 kg", radius="30 cm", height="5 cm")
craft = (
    hull + sphere.transformed(translation=[0, 0, 0.6]) + disc.transformed(translation=[0, 0, -0.6])
)
damper = tb.KaneDamper(sphere.inertia[0, 0], "0.2 N*m*s")
wheel_inertia = disc.inertia[2, 2]  # J of the wheel about its axis, kg·m²

i_t, i_a = craft.inertia[0, 0], craft.inertia[2, 2]
spin = 2.0  # rad/s, about body z
omega0 = [0.01, 0.0, spin]  # a small wobble, rad/s
print(craft)
print(f"I_a = {i_a:.4f} kg·m² (spin axis, the smallest), I_t = {i_t:.4f} kg·m²")
print(f"damper: J = {damper.inertia:.4f} kg·m², D = {damper.damping} N·m·s")
print(f"wheel: J = {wheel_inertia:.4f} kg·m²")

decay = tb.theory.kane_damper_decay(craft, damper.inertia, damper.damping, spin)
print(
    f"linear theory: the nutation grows at {-decay.decay_rate:.5f} 1/s "
    f"(time constant {decay.time_constant:.1f} s), nutation frequency "
    f"{decay.nutation_frequency:.4f} rad/s"
)


def nutation_angle(run):
    """The angle between the body's z axis and H, degrees, at each sample."""
    h = run.body_momentum  # H in body axes, the parts' momenta included
    return np.degrees(np.arctan2(np.hypot(h[:, 0], h[:, 1]), h[:, 2]))


# %%
# (a) The damper alone: into a flat spin
# --------------------------------------
#
# :func:`tumble.simulate` with ``internal=[damper]``; a damper is not
# conservative, so ``method="auto"`` picks the adaptive Dormand–Prince method.

flat = tb.simulate(craft, omega0, duration=3000.0, dt=0.5, internal=[damper])
theta = nutation_angle(flat)
momentum = np.linalg.norm(flat.angular_momentum, axis=1)
moments = craft.principal()[0]
final_energy = momentum[0] ** 2 / (2 * moments[2])
growth = tb.analysis.exponential_rate(flat.t, np.radians(theta), (2 * np.radians(theta[0]), 0.1))
print(flat.method, "—", flat.reason)
print(f"nutation angle: {theta[0]:.3f}° at the start, {theta[-1]:.4f}° at the end")
print(
    f"growth rate of the nutation: simulated {growth:.5f} 1/s, theory {-decay.decay_rate:.5f} 1/s"
)
print(
    f"energy: {flat.energy[0]:.4f} J at the start, {flat.energy[-1]:.6f} J at the end, "
    f"H²/(2 I_max) = {final_energy:.6f} J"
)
print(f"relative drift of |H|: {np.ptp(momentum) / momentum[0]:.1e}")

# The fit spans the nutation from twice its start to 0.1 rad, where the
# linearisation errs by ~θ² (< 1 %) and the tilt's own wobble adds a little:
# 2 % is a firm bound on their sum.
assert np.isclose(growth, -decay.decay_rate, rtol=0.02)
# After ~13 time constants of growth and the decay into the flat spin, the
# remaining nutation energy is far below 1e-6 of T (the adaptive method keeps
# |H| to ~1e-9 at its default rtol = 1e-10).
assert np.isclose(flat.energy[-1], final_energy, rtol=1e-6)
assert np.ptp(momentum) / momentum[0] < 1e-7

fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True, layout="constrained")
top.plot(flat.t, theta, color="tab:red")
top.axhline(90, color="0.5", linestyle=":")
top.set(ylabel="nutation angle (deg)", title="(a) Spin about the minor axis with a damper")
bottom.plot(flat.t, flat.energy, color="tab:blue", label="kinetic energy $T$ (J)")
bottom.plot(flat.t, final_energy * np.ones_like(flat.t), "k:", label=r"$H^2 / (2 I_{max})$ (J)")
bottom.plot(flat.t, momentum, color="tab:green", label=r"$|\mathbf{H}|$ (kg·m²/s)")
bottom.set(xlabel="time (s)", ylabel="J, or kg·m²/s")
bottom.legend()

# %%
# Explorer 1 itself
# -----------------
#
# The built-in scenario ``explorer-1`` (``tumble run explorer-1``) has
# Explorer 1's proportions: a 13 kg cylinder 2.03 m long and 15.2 cm across,
# spun at 750 rpm, here with a Kane damper of 1 kg. For a spin that starts
# almost exactly about the axis, the energy falls by the ratio
# :math:`2 T_0 I_{max} / H^2 \approx I_t / I_a`.

ball = tb.shapes.solid_sphere("1 kg", radius="6.5 cm")
explorer = tb.shapes.solid_cylinder("13 kg", radius="7.6 cm", height="2.03 m") + ball
explorer_damper = tb.KaneDamper(ball.inertia[0, 0], "3.5e-3 N*m*s")
e_moments = explorer.principal()[0]
e_run = tb.simulate(
    explorer, [0.001, 0, "750 rpm"], duration=2000.0, dt=0.5, internal=[explorer_damper]
)
e_h = np.linalg.norm(e_run.angular_momentum[0])
ratio = e_run.energy[0] / e_run.energy[-1]
print(f"Explorer 1: I_t / I_a = {e_moments[2] / e_moments[0]:.2f}")
print(
    f"energy fell {ratio:.2f}-fold; 2 T0 I_max / H² = "
    f"{2 * e_run.energy[0] * e_moments[2] / e_h**2:.2f}; "
    f"nutation at the end {nutation_angle(e_run)[-1]:.3f}°"
)

# %%
# (b) Dual spin: a wheel stabilises the spin
# ------------------------------------------
#
# Now let the wheel turn relative to the body at :math:`\Omega_r`, with
# relative momentum :math:`h = J \Omega_r` along the axis. A free wheel keeps
# its own axial momentum :math:`h_a = J (\omega_3 + \Omega_r)`, so with the
# platform's axial moment :math:`C = I_a - J`, the energy at fixed
# :math:`H` becomes
#
# .. math::
#
#    T(\theta) = \frac{H^2 \sin^2\theta}{2 I_t}
#              + \frac{(H \cos\theta - h_a)^2}{2 C} + \frac{h_a^2}{2 J},
#    \qquad
#    \frac{\mathrm dT}{\mathrm d\theta}
#      = H \sin\theta \left( \frac{H\cos\theta}{I_t} - \omega_3 \right).
#
# The bracket is the nutation frequency :math:`\lambda_p` seen from the
# platform. Energy lost in the platform shrinks :math:`\theta` when it is
# positive, which at small :math:`\theta` (:math:`H \approx I_a \Omega + h`,
# :math:`\omega_3 \approx \Omega`) is the dual-spin stability criterion for a
# damper on the platform (Iorillo, ASME Winter Annual Meeting 1965; Likins,
# *J. Spacecraft Rockets* 4 (1967) 1638):
#
# .. math::
#
#    \lambda_p = \frac{h - (I_t - I_a)\,\Omega}{I_t} > 0
#    \quad\Longleftrightarrow\quad
#    h > h^* = (I_t - I_a)\,\Omega .
#
# In other words, with the wheel the spin axis must act as the major axis,
# :math:`I_a + h/\Omega > I_t`. Without the damper, the axisymmetric gyrostat is stable for
# every :math:`h` (:func:`tumble.theory.gyrostat_stability`, whose nutation
# frequency is :math:`|\lambda_p|`): only dissipation tells the two sides of
# :math:`h^*` apart. Below :math:`h^*` the body does not go all the way to a
# flat spin: :math:`T` is least where
#
# .. math::
#
#    \cos\theta_f = \frac{h_a\, I_t}{H\, (I_t - C)}
#
# (and at :math:`\theta_f = 0` when that exceeds 1, which is again
# :math:`h > h^*`). A locked wheel is part of the platform
# (:math:`C = I_a`, :math:`h_a = 0`), and :math:`\theta_f = 90°`, as in (a).

h_star = (i_t - i_a) * spin
print(
    f"h* = (I_t − I_a) Ω = {h_star:.3f} kg·m²/s, "
    f"a wheel speed of {h_star / wheel_inertia:.1f} rad/s"
)

fractions = [0.25, 0.5, 1.5, 2.0]  # h / h*
dual, predicted = {}, {}
for fraction in fractions:
    h = fraction * h_star
    rotor = tb.Rotor([0, 0, 1], wheel_inertia, speed=h / wheel_inertia)
    run = tb.simulate(craft, omega0, duration=6000.0, dt=0.5, internal=[damper, rotor])
    big_h = np.linalg.norm(run.angular_momentum[0])
    h_axial = wheel_inertia * (omega0[2] + h / wheel_inertia)
    cos_final = h_axial * i_t / (big_h * (i_t - (i_a - wheel_inertia)))
    predicted[fraction] = np.degrees(np.arccos(min(cos_final, 1.0)))
    dual[fraction] = run
    undamped = tb.theory.gyrostat_stability(craft, spin, h)
    lam = (h - h_star) / i_t
    print(
        f"h = {fraction:.2f} h*: λ_p = {lam:+.4f} rad/s; without the damper "
        f"gyrostat_stability says stable={undamped.stable}, |λ| = "
        f"{undamped.nutation_frequency:.4f} rad/s\n"
        f"    nutation {nutation_angle(run)[0]:.3f}° → {nutation_angle(run)[-1]:.4f}°, "
        f"energy-sink θ_f = {predicted[fraction]:.4f}°; "
        f"drift of |H| {run.drift['angular_momentum_vector']:.1e}"
    )

# In every case the run lasts many times the slowest growth or decay seen, so
# the end state is the minimum of T; 0.05° covers the nutation that remains.
for fraction in fractions:
    assert abs(nutation_angle(dual[fraction])[-1] - predicted[fraction]) < 0.05

# %%
# The nutation frequency measured on :math:`\omega_1` in the first 1000 s of
# the stable run at :math:`h = 2h^*`, against :math:`|\lambda_p|`:

stable = dual[2.0]
early = stable.t < 1000.0
measured = tb.analysis.oscillation_frequency(stable.t[early], stable.omega[early, 0])
expected = tb.theory.gyrostat_stability(craft, spin, 2.0 * h_star).nutation_frequency
print(f"nutation frequency: simulated {measured:.4f} rad/s, |λ_p| = {expected:.4f} rad/s")
# The damper's sphere follows the body only partly, which shifts the effective
# transverse moment between I_t and I_t − J: a relative shift up to J/I_t.
assert np.isclose(measured, expected, rtol=2 * damper.inertia / i_t)

fig, ax = plt.subplots(figsize=(8, 4.5), layout="constrained")
ax.semilogy(flat.t, theta, color="k", label="wheel locked (a)")
colours = ["tab:orange", "tab:red", "tab:blue", "tab:green"]
for fraction, colour in zip(fractions, colours, strict=True):
    run = dual[fraction]
    ax.semilogy(run.t, nutation_angle(run), color=colour, label=f"$h = {fraction:g}\\,h^*$")
ax.set(xlabel="time (s)", ylabel="nutation angle (deg)", ylim=(1e-5, 200))
ax.set_title("(b) Dual spin: nutation angle with a wheel of relative momentum $h$")
ax.legend(ncols=3, loc="lower left")

# %%
# The end state against :math:`h / h^*`: the curve is :math:`\theta_f` from the
# energy sink, the points the simulations. At :math:`h = 0` a free wheel still
# keeps the axial momentum :math:`J\Omega` it started with, so the curve starts
# a little below the 90° of the locked wheel.

grid = np.linspace(0, 2.2, 300)
big_h0 = np.hypot(i_t * omega0[0], i_a * spin + grid * h_star)
cos_grid = (wheel_inertia * spin + grid * h_star) * i_t / (big_h0 * (i_t - i_a + wheel_inertia))
fig, ax = plt.subplots(figsize=(6.5, 4), layout="constrained")
ax.plot(
    grid, np.degrees(np.arccos(np.minimum(cos_grid, 1.0))), "k", label=r"$\theta_f$, energy sink"
)
ax.plot(
    fractions,
    [nutation_angle(dual[f])[-1] for f in fractions],
    "o",
    color="tab:orange",
    label="simulated, at the end",
)
ax.plot([0], [theta[-1]], "s", color="tab:red", label="wheel locked (a)")
ax.axvline(1.0, color="0.5", linestyle=":")
ax.set(xlabel=r"relative wheel momentum $h / h^*$", ylabel="final nutation angle (deg)")
ax.legend()

# %%
# The Poinsot construction
# ------------------------
#
# For a rigid body without torque, :func:`tumble.analysis.herpolhode` gives
# Poinsot's picture: the inertia ellipsoid rolling on the fixed invariable
# plane (``tumble run tennis-racket`` shows it in its 3D viewer). It needs
# :math:`T` and :math:`\mathbf H` both conserved, so it refuses a body with
# internal parts: with a damper the plane stays, but its distance
# :math:`2T/H` from the centre shrinks as the energy goes, and the polhode
# drifts across the separatrix to the major axis (see :ref:`tutorials`, the
# page on the tennis-racket flip, for the polhodes of the free body).
#
# Where the formulas stop holding
# -------------------------------
#
# The energy-sink argument assumes the dissipation is slow, so that the
# motion over one nutation period is nearly the rigid one; a strong damper
# changes the nutation frequency itself, and the linear rate from
# :func:`tumble.theory.kane_damper_decay` is then the one to use. The
# criterion :math:`h > h^*` is for dissipation on the platform only: real
# wheels have bearing friction and motors, and energy lost in the *rotor*
# adds a destabilising term of its own, weighted by the nutation frequency the
# rotor sees (Likins 1967). The nutation angle here is measured from the
# total :math:`\mathbf H`; it is not the same as the angle between the axis
# and :math:`\boldsymbol\omega`. And a real Explorer 1 lost energy through
# whip antennas, not a Kane damper, so its time constant differs; the end
# state, set by :math:`H` alone, does not.
