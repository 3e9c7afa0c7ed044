r"""
Where the classic gyroscope formulas hold
=========================================

The textbook results for a heavy gyroscope and for the gyrocompass are limits:
the fast-top formulas (Goldstein §5.7, Kleppner & Kolenkow ch. 7) hold when the
spin's angular momentum dwarfs what gravity can change in a nutation, and the
gyrocompass's frequency :math:`\beta = \sqrt{L_s \Omega / I_{AB}}` holds for small
swings. :mod:`tumble.theory` gives both each approximation and the exact value
(the steady-precession quadratic, the turning points and period of the Lagrange
top, the gyrocompass's large-amplitude period), so their ratio measures how far
each approximation can be trusted. This page draws the errors over spin rate and
amplitude; :doc:`/approximations` tabulates them.
"""

# %%
# The body
# --------
#
# A thin disk of 1 kg and radius 10 cm. As a gyroscope it sits on a pivot on its
# axis 10 cm from its centre and is released from rest at a tilt :math:`\theta_0`
# from the upward vertical; as a gyrocompass it is held at its centre in a gimbal
# on a platform turning at :math:`\Omega` = 0.5 rad/s. The fast-top formulas need
# :math:`I_s \omega_s \gg \sqrt{m g l I_\perp}`: the printed spin scale is where
# the two are equal.

import math
import runpy

import matplotlib.pyplot as plt
import numpy as np

import tumble as tb

disk = tb.shapes.thin_disk("1 kg", "10 cm")
pivot = [0.0, 0.0, -0.1]  # m, body axes: 10 cm below the centre along the axis
platform = 0.5  # rad/s, the gyrocompass's platform rate

spin_moment = disk.inertia[2, 2]  # I_s, kg·m²
transverse = disk.inertia_about(pivot)[0, 0]  # I⊥ about the pivot, kg·m²
weight_lever = disk.mass * 9.81 * 0.1  # m g l, N·m
spin_scale = math.sqrt(weight_lever * transverse) / spin_moment
print(f"I_s = {spin_moment:.4g} kg·m², I⊥ = {transverse:.4g} kg·m², m g l = {weight_lever:.4g} N·m")
print(f"spin scale √(m g l I⊥) / I_s = {spin_scale:.3g} rad/s")

# %%
# The heavy gyroscope
# -------------------
#
# The three fast-top formulas are the precession rate, the nutation frequency and
# the nutation half-amplitude of a top released from rest,
#
# .. math::
#
#    \Omega_p \approx \frac{m g l}{I_s \omega_s}, \qquad
#    \omega_n \approx \frac{I_s \omega_s}{I_\perp}, \qquad
#    \frac{\theta_\max - \theta_0}{2} \approx
#    \frac{m g l\, I_\perp \sin\theta_0}{(I_s \omega_s)^2}.
#
# :func:`tumble.theory.gyroscope` gives them with the exact values beside them:
# the slow root of the steady-precession quadratic
# :math:`I_\perp \cos\theta\, \Omega^2 - I_s \omega_s \Omega + m g l = 0`, and the
# period and turning points of the tilt from the cubic in :math:`\cos\theta`. The
# errors below are the same as those of ``examples/approximation_table.py``.


# The errors come from the script that writes the tables of :doc:`/approximations`
# (``examples/approximation_table.py``, the same disk and pivot), loaded here:

table = runpy.run_path("../../examples/approximation_table.py")
gyroscope_errors = table["gyroscope_errors"]


spins = np.geomspace(20.0, 2000.0, 41)  # rad/s
tilts = (10.0, 30.0, 60.0, 120.0)  # degrees from the upward vertical
errors = {tilt: np.array([gyroscope_errors(s, tilt) for s in spins]) for tilt in tilts}

titles = ("precession rate", "nutation frequency", "nutation half-amplitude")
fig, axes = plt.subplots(1, 3, figsize=(12, 4), sharey=True)
for k, (ax, title) in enumerate(zip(axes, titles, strict=True)):
    for tilt in tilts:
        ax.loglog(spins, 100 * errors[tilt][:, k], label=f"θ0 = {tilt:.0f}°")
    ax.axhline(1.0, color="0.5", lw=0.8, ls="--")
    ax.axvline(spin_scale, color="0.5", lw=0.8, ls=":")
    ax.set_title(title)
    ax.set_xlabel("spin ω_s (rad/s)")
axes[0].set_ylabel("error of the fast-top formula (%)")
axes[0].legend()
fig.suptitle("Fast-top formulas against the exact top (dashed: 1 %, dotted: the spin scale)")
fig.tight_layout()

# %%
# Below the spin scale no formula is good, and near the vertical there is no
# steady precession at all (the gaps of the first panel). Above it the errors fall
# as :math:`1/\omega_s^2`. At exactly 90° the quadratic loses its
# :math:`\cos\theta` term and the fast-top rate is the slow root itself, so
# 90° is left out of the logarithmic plot; its errors are printed:

for spin in (100.0, 500.0):
    errs = gyroscope_errors(spin, 90.0)
    print(f"θ0 = 90°, ω_s = {spin:.0f} rad/s: " + ", ".join(f"{e:.1e}" for e in errs))

# %%
# The slow root of the quadratic expands as
#
# .. math::
#
#    \Omega = \frac{m g l}{I_s\omega_s}
#    \left(1 + \frac{m g l\, I_\perp\cos\theta}{(I_s\omega_s)^2} + \dots\right),
#
# so at a fast spin the precession error should be
# :math:`m g l\, I_\perp |\cos\theta| / (I_s\omega_s)^2`:

fast = 1000.0  # rad/s
next_factor = weight_lever * transverse / (spin_moment * fast) ** 2
print(f"at ω_s = {fast:.0f} rad/s the expansion's ratio m g l I⊥ / (I_s ω_s)² = {next_factor:.1e}")
for tilt in tilts:
    predicted = next_factor * abs(math.cos(math.radians(tilt)))
    computed = gyroscope_errors(fast, tilt)[0]
    print(f"θ0 = {tilt:5.0f}°: error {computed:.4e}, leading term {predicted:.4e}")
    # The next term is smaller by another factor of the printed ratio; 1e-3 leaves
    # it room and fails any other power of ω_s.
    assert abs(computed / predicted - 1) < 1e-3

# %%
# The gyrocompass
# ---------------
#
# The lecture notes' equation :math:`I_{AB}\ddot\theta + \Omega L_s \sin\theta = 0`
# gives :math:`\theta(t) = \theta_0 \sin\beta t` for small swings. The exact
# equation, derived from the Lagrangian, has one more term,
#
# .. math::
#
#    I_{AB}\ddot\theta = -L_s \Omega \sin\theta + I_{AB}\Omega^2 \sin\theta\cos\theta,
#
# and :func:`tumble.theory.gyrocompass` gives its period at any amplitude. The
# error of :math:`\beta` is set by the amplitude (the pendulum's), and at a slow
# spin the :math:`\Omega^2` term adds to it:

amplitudes = np.linspace(2.0, 170.0, 85)  # degrees
compass_spins = (20.0, 100.0, 1000.0)  # rad/s
fig, ax = plt.subplots(figsize=(7, 4.5))
for spin in compass_spins:
    compass = tb.theory.gyrocompass(disk, spin, platform)
    exact = np.array([2 * math.pi / compass.period(math.radians(a)) for a in amplitudes])
    ax.semilogy(amplitudes, 100 * np.abs(compass.oscillation_frequency / exact - 1),
                label=f"ω_s = {spin:.0f} rad/s")  # fmt: skip
ax.axhline(1.0, color="0.5", lw=0.8, ls="--")
ax.set_xlabel("amplitude θ0 (deg)")
ax.set_ylabel("error of β = √(L_s Ω / I_AB) (%)")
ax.set_title("Gyrocompass: small-angle β against the exact frequency 2π / period")
ax.legend()
fig.tight_layout()

# %%
# For a small amplitude both corrections can be written down: the pendulum's
# period grows by :math:`\theta_0^2/16`, and the :math:`\Omega^2` term lowers the
# small-swing frequency to :math:`\sqrt{\beta^2 - \Omega^2}`, a relative
# :math:`\Omega^2/(2\beta^2)`. Their sum is the error of :math:`\beta` at 5°:

small = math.radians(5.0)
for spin in compass_spins:
    compass = tb.theory.gyrocompass(disk, spin, platform)
    beta = compass.oscillation_frequency
    computed = beta * compass.period(small) / (2 * math.pi) - 1
    predicted = small**2 / 16 + platform**2 / (2 * beta**2)
    print(f"ω_s = {spin:6.0f} rad/s: β = {beta:.4g} rad/s, error {computed:.4e}, "
          f"θ0²/16 + Ω²/(2β²) = {predicted:.4e}")  # fmt: skip
    # The neglected terms are of the order of the squares of the two (θ0⁴ and
    # Ω⁴/β⁴) and their product: at most a few per cent of their sum here.
    assert abs(computed / predicted - 1) < 0.03

# %%
# The table
# ---------
#
# The errors in per cent on the grid of :doc:`/approximations`, marked with
# ``*`` above 1 %:


table["main"]()
