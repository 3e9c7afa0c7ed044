"""
Identify a body from its measured rotation
==========================================

A phone thrown spinning about its intermediate axis flips over in the air: the
tennis-racket experiment. Its gyroscope records the angular velocity in the
phone's own axes; from those samples alone :func:`tumble.identify` finds the
phone's moment ratios, its principal axes in the sensor's axes, the sensor's
bias and the motion, with their uncertainties. The same fit serves a
spacecraft's coasting telemetry.

The recording here is :func:`tumble.identification.synthetic_phone`: made in
code, with a known truth, and with what a real one has — sensor axes that are
not principal, a bias, noise, uneven sampling, and the hand before the throw
and after the catch.
"""

# %%
# The recording
# -------------

import matplotlib.pyplot as plt
import numpy as np

import tumble as tb
from tumble.identification import free_flight, synthetic_phone

phone = synthetic_phone(seed=0)
t, omega = phone.t, phone.omega
print(f"{t.size} samples over {t[-1]:.2f} s, intervals {np.diff(t).min() * 1e3:.2f} to "
      f"{np.diff(t).max() * 1e3:.2f} ms")  # fmt: skip

fig, ax = plt.subplots(figsize=(8, 3.5))
ax.plot(t, omega, lw=0.8, label=["x", "y", "z"])
ax.set_xlabel("t (s)")
ax.set_ylabel("measured ω (rad/s)")
ax.legend(title="sensor axis")
fig.tight_layout()

# %%
# The free flight
# ---------------
#
# Only the flight is torque-free. :func:`tumble.identification.free_flight`
# finds it by a rule from Euler's equations: a free body has
# :math:`|\dot{\boldsymbol\omega}| \le |\boldsymbol\omega|^2`, which the hand's
# torque and the catch's impact break. A window ``(start, end)`` passed to
# :func:`tumble.identify` overrides it.

start, end = free_flight(t, omega)
print(f"free flight found: {start:.3f}–{end:.3f} s (thrown at {phone.release:.3f} s, "
      f"caught at {phone.catch:.3f} s)")  # fmt: skip

# %%
# The fit
# -------
#
# The model is the exact torque-free motion (Jacobi elliptic functions), turned
# into the sensor's axes, plus a bias: 11 parameters fitted by least squares.

fit = tb.identify(t, omega)
print(fit)
for name, value, error, truth in zip(
    ("I1/I3", "I2/I3"), fit.moment_ratios, fit.uncertainty, phone.moment_ratios, strict=True
):
    print(f"{name} = {value:.5f} ± {error:.5f}   (truth {truth:.5f}, "
          f"{abs(value - truth) / error:.1f} standard errors away)")  # fmt: skip
print(f"bias = {np.round(fit.bias, 4)} rad/s (truth {phone.bias})")
print(f"flip period {fit.flip_period:.3f} s; residual {fit.residual_rms:.4f} rad/s "
      f"(sensor noise {phone.noise} rad/s)")  # fmt: skip
angle = np.degrees(np.arccos(np.clip(np.abs(np.diag(fit.axes.T @ phone.axes)), -1, 1)))
print(f"principal axes off by {np.round(angle, 3)} deg")
# The truth lies within 3 standard errors (the test suite checks the coverage of
# these errors over many recordings).
assert np.all(np.abs(fit.moment_ratios - phone.moment_ratios) < 3 * fit.uncertainty)

# %%
# Measured against fitted
# -----------------------
#
# The residuals are the sensor's noise: nothing of the motion is left in them.

fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
top.plot(fit.t, fit.measured, ".", ms=1.5, alpha=0.5)
top.set_prop_cycle(None)
top.plot(fit.t, fit.predicted(fit.t), lw=1.0)
top.set_ylabel("ω (rad/s)")
top.set_title("measured (dots) and fitted (lines), sensor axes")
bottom.plot(fit.t, fit.residuals, lw=0.5)
bottom.set_xlabel("t (s)")
bottom.set_ylabel("residual (rad/s)")
fig.tight_layout()

# %%
# From the command line
# ---------------------
#
# ``tumble fit RECORDING.csv`` reads a phyphox export (or any CSV or Parquet
# file, with ``--columns``), prints the same numbers and writes a report and a
# scenario that ``tumble run`` replays; without a file it fits this recording.
# See :doc:`/reference/cli`.
