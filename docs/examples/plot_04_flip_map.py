r"""
The flip period near the intermediate axis
==========================================

A body spun about its intermediate principal axis turns over again and again:
the tennis-racket, or Dzhanibekov, effect. How long it waits between flips
depends on how far from that axis it started. This page spins a batch of bodies
at once with :func:`tumble.simulate_batch`, each a little off the axis, measures
the time between their flips from the recorded angular velocity, and compares it
with the closed form of :func:`tumble.theory.flip_period`.
"""

# %%
# Theory
# ------
#
# In the principal frame of a torque-free body with :math:`I_1 < I_2 < I_3`, the
# angular velocity is periodic with (Landau & Lifshitz, *Mechanics*, §37)
#
# .. math::
#
#    T = \frac{4 K(k^2)}{\lambda}, \qquad
#    \lambda^2 = \frac{(I_3 - I_2)(L^2 - 2 E I_1)}{I_1 I_2 I_3}, \qquad
#    k^2 = \frac{(I_2 - I_1)(2 E I_3 - L^2)}{(I_3 - I_2)(L^2 - 2 E I_1)}
#
# (for :math:`L^2 > 2 E I_2`; the roles of 1 and 3 exchange on the other side),
# and a body near the intermediate axis flips twice in each period. As the
# start approaches the axis, :math:`k^2 \to 1` and :math:`K` grows like
# :math:`\ln(4/\sqrt{1 - k^2})`: the period grows only logarithmically with the
# closeness to the axis, by the same amount for each factor of ten.
#
# The bodies
# ----------
#
# Principal moments :math:`(1, I_2, 3)` kg·m² for three intermediate moments, and
# a spin of 2 rad/s about the intermediate axis with a fraction :math:`\varepsilon`
# of it along the major axis, for :math:`\varepsilon` from :math:`10^{-6}` to
# :math:`10^{-1}`: 120 bodies in one batch. (A perturbation along the major axis
# keeps every body on one side of the separatrix, :math:`L^2 > 2 E I_2`; one along
# both other axes can land exactly on it, where the period is infinite.)

import matplotlib.pyplot as plt
import numpy as np

import tumble as tb

spin = 2.0  # rad/s about the intermediate axis
middles = (2.2, 2.5, 2.8)  # I2, kg·m² (I1 = 1, I3 = 3)
perturbations = np.geomspace(1e-6, 1e-1, 40)

moments, omega0 = [], []
for middle in middles:
    for eps in perturbations:
        moments.append([1.0, middle, 3.0])
        omega0.append([0.0, spin, eps * spin])
moments, omega0 = np.array(moments), np.array(omega0)
theory = np.array([tb.theory.flip_period(m, w) for m, w in zip(moments, omega0, strict=True)])
print(
    f"{len(moments)} bodies; theoretical periods from {theory.min():.2f} s to {theory.max():.2f} s"
)

# %%
# The batch
# ---------
#
# ω starts at the top of its oscillation along the intermediate axis; it crosses
# zero (a flip) a quarter period later, and again every half period. A run of 1.4
# of the longest period holds three crossings of every body. The batch steps all
# bodies together with the compiled RK4 kernel, vectorised across bodies, and
# keeps every 10th state.

dt = 2e-3  # s, against a turn of π s at 2 rad/s
batch = tb.simulate_batch(
    moments, omega0, duration=1.4 * theory.max(), dt=dt, method="rk4", record_every=10
)
t = batch.t
middle_rate = batch.omega_history[:, :, 1]  # (samples, bodies): ω along the middle axis
print(f"{batch.method}: {len(t)} recorded states of {len(moments)} bodies, dt = {batch.dt:.3g} s")

# %%
# The flip times are the zeros of that component, found between two samples of
# opposite sign by linear interpolation. Two flips make a period: the measured
# period is the time from the first crossing to the third.


def crossings(values: np.ndarray) -> np.ndarray:
    """The times at which ``values`` (samples at ``t``) changes sign."""
    k = np.flatnonzero(np.sign(values[1:]) != np.sign(values[:-1]))
    return t[k] - values[k] * (t[k + 1] - t[k]) / (values[k + 1] - values[k])


measured = np.array([np.diff(crossings(middle_rate[:, j])[[0, 2]])[0] for j in range(len(moments))])
error = np.abs(measured / theory - 1)
far = np.tile(perturbations >= 1e-3, len(middles))
print(f"largest relative difference from 4K/λ: {error[far].max():.1e} for ε ≥ 1e-3, "
      f"{error.max():.1e} for all")  # fmt: skip
# Away from the separatrix the crossings, interpolated between samples 0.02 s apart
# where ω₂ is nearly straight (sn has an inflection at its zeros), are good to a
# few 1e-7 s on periods of seconds, and RK4's error at this step is smaller still.
assert error[far].max() < 1e-6

# %%
# The period against the perturbation
# -----------------------------------
#
# On a logarithmic axis of :math:`\varepsilon` the period is a straight line at
# small perturbations: each factor of ten closer to the axis adds the same time,
# :math:`(4/\lambda)\ln 10` in the limit, with :math:`\lambda` the growth rate of a
# small wobble about the intermediate axis,
# :math:`\lambda = \omega \sqrt{(I_3 - I_2)(I_2 - I_1)/(I_1 I_3)}`.

fig, (ax, right) = plt.subplots(1, 2, figsize=(12, 4.5))
n = len(perturbations)
for i, middle in enumerate(middles):
    rows = slice(i * n, (i + 1) * n)
    ax.semilogx(perturbations, theory[rows], color=f"C{i}", lw=1, label=f"4K/λ, I₂ = {middle}")
    ax.semilogx(perturbations, measured[rows], "o", color=f"C{i}", ms=3.5, mfc="none")
    right.loglog(
        perturbations, error[rows], "o-", color=f"C{i}", ms=3, lw=0.8, label=f"I₂ = {middle}"
    )
    growth = spin * np.sqrt((3.0 - middle) * (middle - 1.0) / 3.0)
    slope = 4 * np.log(10) / growth
    small = np.polyfit(np.log10(perturbations[:10]), measured[rows][:10], 1)[0]
    print(f"I₂ = {middle}: the period grows by {-small:.3f} s per decade closer; "
          f"(4/λ) ln 10 = {slope:.3f} s")  # fmt: skip
ax.set_xlabel("perturbation ε (fraction of the spin)")
ax.set_ylabel("period of ω (s): two flips")
ax.set_title("Measured (circles) and 4K/λ (lines)")
ax.legend()
right.set_xlabel("perturbation ε (fraction of the spin)")
right.set_ylabel("|measured / 4K/λ − 1|")
right.set_title("Relative difference")
right.legend()
fig.tight_layout()

# %%
# Close to the separatrix the measured period departs from the closed form, the
# more the closer the start: there the time to the first flip is set by a
# perturbation of a fraction :math:`\varepsilon` of the spin, and the small errors
# of every step, rounding included, shift it by a growing fraction of that. Any
# integrator that steps loses digits there (scipy's DOP853 at ``rtol = 1e-13``
# too, if fewer); the closed form, evaluated from the initial state at any time
# (``method="exact"`` in :func:`tumble.simulate`, or
# :func:`tumble.theory.free_motion`), does not, which is why tumble's tests take
# it as the reference for the free body.

# %%
# A sweep (``tumble sweep flip-map``, :func:`tumble.sweep.run_sweep`) does the same
# for millions of bodies: it measures the flips inside the compiled kernels as they
# step, keeps no history, and streams the results to disk.
