r"""
The gimballed gyroscope and the gyrocompass
===========================================

A spinning disk is mounted in a gimbal that lets its axis tilt about one
horizontal axis, AB, and the gimbal's mount is carried round the vertical on a
turntable. The spin axis does not stay where it is put: it swings about the
direction of the turntable's rotation like a pendulum. On the rotating Earth
the same effect makes a gyroscope seek north: the gyrocompass. This page
derives the swing, simulates it with tumble's gimbal model and shows where the
small-angle formula of the lecture notes stops holding.
"""

# %%
# Theory
# ------
#
# Let the turntable turn at :math:`\Omega` about the vertical and let
# :math:`\theta` be the angle of the spin axis from the vertical, in the plane
# perpendicular to AB. The disk, of moment :math:`I_s` about its spin axis and
# :math:`I_{AB}` about AB, is pivoted at its centre of mass; in the turning
# frame its Lagrangian is
#
# .. math::
#
#    \mathcal L = \tfrac12 I_{AB}\,(\dot\theta^2 + \Omega^2\sin^2\theta)
#               + \tfrac12 I_s\,(\dot\psi + \Omega\cos\theta)^2 ,
#
# with :math:`\psi` the spin angle. :math:`\psi` is cyclic, so the spin
# :math:`\omega_s = \dot\psi + \Omega\cos\theta` and the spin angular momentum
# :math:`L_s = I_s\omega_s` are constant, and
#
# .. math::
#
#    I_{AB}\,\ddot\theta = -L_s\,\Omega\sin\theta + I_{AB}\,\Omega^2\sin\theta\cos\theta .
#
# The lecture notes (after Kleppner & Kolenkow, *An Introduction to
# Mechanics*, ch. 7) drop the last term, which is small when
# :math:`L_s \gg I_{AB}\Omega`, and write
# :math:`I_{AB}\ddot\theta + \Omega L_s\sin\theta = 0`: a pendulum. For small
# swings that starts on the vertical,
#
# .. math::
#
#    \theta(t) = \theta_0\sin\beta t, \qquad \beta = \sqrt{\frac{L_s\,\Omega}{I_{AB}}} .
#
# Keeping the :math:`\Omega^2` term, the small-angle frequency is
# :math:`\sqrt{\beta^2 - \Omega^2}`, and the vertical is stable only if
# :math:`L_s > I_{AB}\Omega`. For swings of any size, the energy integral
#
# .. math::
#
#    \dot\theta^2 = \dot\theta_0^2 - 2\beta^2(1 - \cos\theta) + \Omega^2\sin^2\theta
#
# gives the rate :math:`\dot\theta_0` at the vertical of a swing of amplitude
# :math:`\theta_0` (where :math:`\dot\theta = 0`), and the period
# :math:`T = 4\int_0^{\theta_0} d\theta/\dot\theta`, a complete elliptic integral
# that :func:`tumble.theory.gyrocompass` evaluates with Carlson's :math:`R_F`.
# Without the :math:`\Omega^2` term it is the pendulum's
# :math:`T = 4K(\sin^2\tfrac{\theta_0}{2})/\beta \approx (2\pi/\beta)(1 +
# \theta_0^2/16)`: the period grows with the amplitude.

import math

import matplotlib.pyplot as plt
import numpy as np
from scipy import special

import tumble as tb

# The disk and rates of the built-in scenario `gyrocompass`.
disk = tb.shapes.solid_cylinder("1 kg", radius="10 cm", height="1 cm")
spin = 200.0  # rad/s, ω_s
platform = 2.0  # rad/s, Ω

compass = tb.theory.gyrocompass(disk, spin, platform)
beta = compass.oscillation_frequency
print(f"I_s = {compass.axial_moment:.6g} kg·m², I_AB = {compass.gimbal_moment:.6g} kg·m²")
print(
    f"L_s = {compass.spin_angular_momentum:.6g} kg·m²/s, "
    f"L_s / (I_AB Ω) = {compass.spin_angular_momentum / (compass.gimbal_moment * platform):.1f}"
)
print(f"β = √(L_s Ω / I_AB)         = {beta:.6f} rad/s")
print(f"√(β² − Ω²), exact for small θ = {compass.small_oscillation_frequency:.6f} rad/s")

# %%
# Simulating the swing
# --------------------
#
# ``tumble.models.gyrocompass`` integrates the exact equation (with a fixed-step
# Runge–Kutta scheme) and returns :math:`\theta(t)` together with the disk's
# full attitude as a :class:`tumble.Trajectory`. Each run below starts on the
# vertical, :math:`\theta(0) = 0`, with the rate :math:`\dot\theta_0` of the
# energy integral, so that its amplitude is exactly :math:`\theta_0`.


def swing(amplitude, periods=3.5, duration=None):
    """Simulate a swing of the given amplitude (rad) for some periods (or a duration, s)."""
    rate0 = math.sqrt(
        2 * beta**2 * (1 - math.cos(amplitude)) - platform**2 * math.sin(amplitude) ** 2
    )
    if duration is None:
        duration = periods * compass.period(amplitude)
    return tb.models.gyrocompass(disk, spin, platform, 0.0, angle_rate0=rate0, duration=duration)


small, large = math.radians(10.0), math.radians(120.0)
runs = {small: swing(small, duration=1.0), large: swing(large, duration=1.0)}
print(runs[small])

fig, axes = plt.subplots(2, 1, figsize=(7.5, 6.0), sharex=True, layout="constrained")
for ax, (amplitude, run) in zip(axes, runs.items(), strict=True):
    t = run.trajectory.t
    ax.plot(t, np.degrees(run.angle), label="simulation (exact equation)")
    ax.plot(t, np.degrees(amplitude * np.sin(beta * t)), "--", label=r"$\theta_0\sin\beta t$")
    ax.set_ylabel("θ (deg)")
    ax.set_title(f"θ0 = {math.degrees(amplitude):.0f}°", fontsize="medium")
axes[1].set_xlim(0, 1.0)
fig.legend(*axes[0].get_legend_handles_labels(), loc="outside upper center", ncols=2)
axes[1].set_xlabel("time t (s)")
plt.show()

# %%
# At 10° the small-angle solution follows the simulation closely: it drifts
# ahead slowly, by the difference between :math:`\beta` and the true
# frequency. At 120° it is wrong from the first swing: the true swing is
# slower, and its shape departs from a sine.
#
# The frequency against the amplitude
# -----------------------------------
#
# For amplitudes from 5° to 170°: the frequency measured on the simulated
# :math:`\theta(t)` (:func:`tumble.analysis.oscillation_frequency`, from the
# times between maxima), the exact :math:`2\pi/T(\theta_0)` of
# ``Gyrocompass.period``, and the error of the small-angle :math:`\beta`.

amplitudes = np.radians([5, 10, 20, 30, 45, 60, 90, 120, 150, 170])
measured = []
print(" θ0 (deg)  simulated   exact 2π/T   β error   Jacobi integral change")
for amplitude in amplitudes:
    run = swing(amplitude)
    frequency = tb.analysis.oscillation_frequency(run.trajectory.t, run.angle)
    exact = 2 * math.pi / compass.period(amplitude)
    jacobi = np.ptp(run.jacobi_integral) / abs(run.jacobi_integral[0])
    measured.append(frequency)
    print(
        f"{math.degrees(amplitude):9.0f} {frequency:10.6f} {exact:12.6f} "
        f"{beta / frequency - 1:9.2%} {jacobi:12.1e}"
    )
measured = np.array(measured)
exact = np.array([2 * math.pi / compass.period(a) for a in amplitudes])

at_90 = beta * compass.period(math.pi / 2) / (2 * math.pi) - 1
print(f"β is off by {at_90:.1%} at θ0 = 90°")

# RK4 shifts an oscillator's frequency by ~(ω Δt)⁴/120: ~1e-8 at the model's
# default step (200 steps a swing). 1e-6 leaves room for the parabolic refinement
# of the maxima and is far below the smallest effect on this page, Ω²/2β².
assert np.all(np.abs(measured / exact - 1) < 1e-6)
# The small-angle β: within 1 % at 10° (Ω²/2β² plus θ0²/16 ≈ 0.4 %), off by
# more than 10 % at 90°.
assert abs(beta / measured[1] - 1) < 0.01
assert beta / measured[np.isclose(amplitudes, math.pi / 2)][0] - 1 > 0.1

# %%
# The error of :math:`\beta` grows with the amplitude as the pendulum's does,
# about :math:`\theta_0^2/16` for moderate swings; near 180° the period grows
# without bound (the axis released upside down stays there). At small
# amplitude what is left is the dropped :math:`\Omega^2` term,
# :math:`\beta/\sqrt{\beta^2 - \Omega^2} - 1 \approx \Omega^2/2\beta^2`.

dense = np.radians(np.linspace(1.0, 175.0, 200))
exact_curve = np.array([2 * math.pi / compass.period(a) for a in dense])
pendulum = 2 * math.pi * beta / (4 * special.ellipk(np.sin(dense / 2) ** 2))  # Ω² term dropped
floor = beta / compass.small_oscillation_frequency - 1

fig, ax = plt.subplots(figsize=(7.0, 4.2), layout="constrained")
ax.semilogy(np.degrees(dense), 100 * (beta / exact_curve - 1), label="exact period, Carlson $R_F$")
ax.semilogy(
    np.degrees(dense), 100 * (beta / pendulum - 1), ":", label=r"pendulum, $\Omega^2$ term dropped"
)
ax.semilogy(
    np.degrees(amplitudes), 100 * (beta / measured - 1), "o", mfc="none", label="simulation"
)
ax.axhline(100 * floor, color="0.5", lw=0.8, ls="--", label=r"$\beta/\sqrt{\beta^2-\Omega^2} - 1$")
ax.axhline(1.0, color="C3", lw=0.8)
ax.text(178, 1.1, "1 %", color="C3", ha="right", va="bottom")
ax.set_ylim(0.1, 300)
ax.set_xlabel("amplitude θ0 (deg)")
ax.set_ylabel("error of β: β / (2π/T) − 1 (%)")
ax.set_xticks(np.arange(0, 181, 30))
ax.legend(fontsize="small")
plt.show()

first = dense[np.argmax(beta / exact_curve - 1 > 0.01)]
print(f"β is off by more than 1 % above θ0 = {math.degrees(first):.0f}°")

# %%
# The built-in scenario
# ---------------------
#
# ``tumble run gyrocompass`` runs the same disk at two amplitudes, 10° and
# 100°, starting as the notes do with :math:`\dot\theta_0 = \beta\theta_0`, and
# compares the measured frequency with :math:`\beta`, with
# :math:`\sqrt{\beta^2-\Omega^2}` and with the exact frequency at the measured
# amplitude. From Python:

import tumble.scenario  # noqa: E402

result = tumble.scenario.run("gyrocompass")
for row in result.comparisons:
    print(
        f"{row['quantity']:52s} theory {row['theory']:9.4f} rad/s, "
        f"relative error {row['relative_error']:.1e}"
    )

# %%
# Classic slips
# -------------
#
# The notes' equation :math:`I_{AB}\ddot\theta + \Omega L_s\sin\theta = 0`
# is not wrong but approximate: it drops :math:`I_{AB}\Omega^2\sin\theta\cos\theta`,
# the centrifugal term of the disk's transverse rotation. Its relative size is
# :math:`\Omega^2\cos\theta/\beta^2`; with the spin slowed down it matters, and
# below :math:`\omega_s = I_{AB}\Omega/I_s` the vertical is no longer stable at
# all (:func:`tumble.theory.gyrocompass` refuses such a spin). And
# :math:`\theta(t) = \theta_0\sin\beta t` holds for small swings only: the
# error of :math:`\beta` passes 1 % at the amplitude printed above and reaches
# the printed value at 90°.

print(f"the Ω² term against the main term near θ = 0, Ω²/β²: {platform**2 / beta**2:.2%}")
print(
    f"spin below which the vertical is unstable: "
    f"{compass.gimbal_moment * platform / compass.axial_moment:.2f} rad/s"
)
for slow in (20.0, 5.0):
    c = tb.theory.gyrocompass(disk, slow, platform)
    print(
        f"at ω_s = {slow:4.0f} rad/s: β = {c.oscillation_frequency:.4f}, "
        f"exact small-angle {c.small_oscillation_frequency:.4f} rad/s "
        f"(β off by {c.oscillation_frequency / c.small_oscillation_frequency - 1:.1%})"
    )

# %%
# Where the formula stops holding
# -------------------------------
#
# :math:`\theta_0\sin\beta t` is the small-swing, fast-spin limit of the exact
# equation. It fails at large amplitude (the period grows, as a pendulum's, and
# diverges as :math:`\theta_0 \to 180^\circ`) and when :math:`L_s` is not large
# against :math:`I_{AB}\Omega` (the :math:`\Omega^2` term). The exact equation
# itself assumes a massless, frictionless gimbal and a disk spinning freely in
# its bearings; a motor that holds the spin relative to the gimbal changes the
# equation at order :math:`\Omega^2`, and friction in the gimbal bearings
# (``damping=`` of ``tumble.models.gyrocompass``) makes the swing decay so
# that the axis settles along :math:`\boldsymbol\Omega`. On the rotating Earth,
# with the spin axis held horizontal (``latitude=``), :math:`\Omega` is the
# horizontal part of the Earth's rotation, :math:`\Omega_E\cos\lambda`: the
# damped axis settles north, and the directive effect vanishes at the poles.
