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

The second part fits a racquet thrown twelve times under air drag
(:func:`tumble.identify_many`): each throw alone, then all of them as one body,
with a forecast of the motion each fit did not see.
"""

# %%
# The recording
# -------------

import matplotlib.pyplot as plt
import numpy as np

import tumble as tb
from tumble.identification import (
    example_throws_path,
    free_flight,
    free_flights,
    read_recording,
    synthetic_phone,
)

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
# Many throws, under air drag
# ---------------------------
#
# A racquet with a phone strapped to it, thrown twelve times about its
# intermediate axis and caught each time, in one recording of 24 s:
# :func:`tumble.identification.example_throws_path`, read with
# :func:`tumble.identification.read_recording` like any phyphox export. It was
# made by :func:`tumble.identification.synthetic_throws` ``(12, seed=0)``, so its
# truth is known: moment ratios 0.067 and 0.94, linear drag ``c_i / I3`` of
# 0.05, 0.12 and 0.15 1/s per principal axis, noise 0.0035 rad/s.
#
# :func:`tumble.identification.free_flights` finds every free flight by the
# rule of ``free_flight`` (shaded below); the holding and the catches between
# them are left out.

RATIOS = np.array([0.067, 0.94])  # the racquet's I1/I3, I2/I3
DRAG = np.array([0.05, 0.12, 0.15])  # c_i / I3, 1/s, principal axes (moments ascending)
NOISE = 0.0035  # the gyroscope's σ per component, rad/s

recording = read_recording(example_throws_path())
t, omega = recording.t, recording.omega
windows = free_flights(t, omega)
print(f"{t.size} samples over {t[-1]:.2f} s; {len(windows)} free flights found")

fig, ax = plt.subplots(figsize=(8, 3.5))
for start, end in windows:
    ax.axvspan(start, end, color="0.88", lw=0)
ax.plot(t, omega, lw=0.6, label=["x", "y", "z"])
ax.set_xlabel("t (s)")
ax.set_ylabel("measured ω (rad/s)")
ax.set_title("twelve throws; the free flights found are shaded")
ax.legend(title="sensor axis", loc="upper left", bbox_to_anchor=(1.0, 1.0))
fig.tight_layout()

# %%
# Why the drag matters
# ^^^^^^^^^^^^^^^^^^^^
#
# Air drag on a racquet is small: ``c_i / I3`` of 0.05–0.15 1/s against rates
# of about 10 rad/s, a torque about 1 % of :math:`I_3|\boldsymbol\omega|^2`, the
# scale of :math:`\dot{\mathbf L}` in the body's axes (and about 5 % of the
# gyroscopic term :math:`\boldsymbol\omega \times I\boldsymbol\omega` that
# flips it). Yet over a flight of 0.8 s it takes a tenth of the angular
# momentum, and shifts the flip so far that by the catch the rates stand
# radians per second from the torque-free motion's. 80 samples with noise of
# 0.0035 rad/s see that many times over: the torque-free model misses them by
# ten times the noise, and bends the ratios to make up what it cannot follow.

free_fit = tb.identify(t, omega, window=windows[0], torque="free")
print(f"torque-free: {free_fit}")

# %%
# ``torque="drag"`` fits the motion under linear drag per principal axis,
# :math:`\tau_i = -c_i \omega_i`, stepped by Runge–Kutta, and the three
# coefficients ``c_i / I3`` with it (``torque_parameters``, in
# ``torque_units``).

drag_fit = tb.identify(t, omega, window=windows[0], torque="drag")
print(drag_fit)
for name, value, error, truth in zip(
    ("c1/I3", "c2/I3", "c3/I3"),
    drag_fit.torque_parameters,
    drag_fit.torque_uncertainty,
    DRAG,
    strict=True,
):
    print(f"{name} = {value:.4f} ± {error:.4f} {drag_fit.torque_units}   (truth {truth})")

# %%
# One throw determines the drag about the axis it spins on; the others, whose
# rates stay small, far less well. With ``torque="auto"`` (the default) a fit is
# torque-free when its residuals look like the noise; otherwise the models
# (``"free"``, ``"drag"``, ``"quadratic-drag"``) are fitted and the one of
# least Bayesian information criterion :math:`N \ln(\mathrm{RSS}/N) + k \ln N`
# wins, each drag paying for its three coefficients; a torque is chosen over
# the torque-free body only on decisive evidence, a criterion lower by more than
# 10 (Kass & Raftery 1995). ``choice`` says what was compared:

print(tb.identify(t, omega, window=windows[0]).choice)

# %%
# Every throw, then all together
# ^^^^^^^^^^^^^^^^^^^^^^^^^^^^^^
#
# :func:`tumble.identify_many` fits each throw alone (``windows=None``: every
# free flight found), then all the throws that fit as one body
# (:class:`tumble.identification.JointFit`). The throws share what belongs to
# the body and the sensor: the two moment ratios, the principal axes in the
# sensor's axes, the sensor's bias and the drag coefficients (11 numbers); each
# keeps only its own motion, ω at its release (3 numbers a throw). So every
# throw's samples inform the shared numbers at once.
#
# ``hold_out=0.4`` also fits the first 60 % of each throw, to forecast the last
# 40 % (below). It runs a few dozen fits, many stepping the drag model: about
# a minute.

many = tb.identify_many(t, omega, hold_out=0.4)
print(many)
for number, fit in enumerate(many.fits, start=1):
    if isinstance(fit, str):
        print(f"throw {number} refused: {fit[:110]}...")
many.table[
    ["throw", "start", "end", "torque", "r1", "r1_error", "r2", "r2_error", "c3", "outlier"]
].round(5)

# %%
# A throw one fit cannot determine is refused, and keeps its reason (``fits``,
# the table's ``reason``): above, one flew too near a principal axis to show
# the body, and one fit went astray (its bias grew past the rates). The others
# mostly choose linear drag on their own.
#
# The joint fit takes the torque every throw chose; when they differ, as here,
# each model chosen is fitted to all the throws and the least information
# criterion wins, by the same rule as for one throw (``choice`` says which). A
# throw is an outlier when its own body lies further from the joint one than
# both their errors allow (a χ² test at the 3 σ level), or when the joint body
# misses its samples by far more than its own fit does: a throw caught early,
# knocked in the air, or fitted to a wrong minimum. It is flagged (``outliers``,
# the table's ``outlier``, and its ``disagreement`` in standard errors) and left
# out of the joint fit, so that it does not pull the body. Here one throw's own
# fit settled on quadratic drag and a body far from the others'.

joint = many.joint
print(joint.choice)
print(f"joint throws {[i + 1 for i in joint.throws]}, outliers {[i + 1 for i in joint.outliers]}")
print(f"{len(joint.parameter_names)} parameters; residual {joint.residual_rms:.5f} rad/s")
for name, value, error, truth in zip(
    ("I1/I3", "I2/I3", "c1/I3", "c2/I3", "c3/I3"),
    [*joint.moment_ratios, *joint.torque_parameters],
    [*joint.uncertainty, *joint.torque_uncertainty],
    [*RATIOS, *DRAG],
    strict=True,
):
    print(
        f"{name} = {value:.5f} ± {error:.5f}   (truth {truth}, "
        f"{abs(value - truth) / error:.1f} standard errors away)"
    )
assert joint.torque == "drag"
assert np.all(np.abs(joint.moment_ratios - RATIOS) < 3 * joint.uncertainty)
assert np.all(np.abs(joint.torque_parameters - DRAG) < 3 * joint.torque_uncertainty)

# %%
# The joint ratios are more precise than the best single throw's, and far more
# than a typical one's. The band is the joint fit's ± 3 standard errors; an
# outlier off the scale is drawn at its edge.

table = many.table
best = table.loc[table.fitted & ~table.outlier, ["r1_error", "r2_error"]].min().to_numpy()
print(
    f"standard errors of I1/I3, I2/I3: best throw {best[0]:.1e}, {best[1]:.1e}; "
    f"joint {joint.uncertainty[0]:.1e}, {joint.uncertainty[1]:.1e}"
)
fitted = table[table.fitted & ~table.outlier]
flagged = table[table.outlier]
fig, axes = plt.subplots(1, 2, figsize=(8, 3.5), sharex=True)
for k, (ax, name) in enumerate(zip(axes, ("I1/I3", "I2/I3"), strict=True)):
    value, error = joint.moment_ratios[k], joint.uncertainty[k]
    column = f"r{k + 1}"
    low, high = value - 0.006, value + 0.006
    ax.axhspan(
        value - 3 * error, value + 3 * error, color="C1", alpha=0.4, lw=0, label="joint fit ± 3σ"
    )
    ax.axhline(RATIOS[k], color="k", lw=0.6, ls="--", label="truth")
    ax.errorbar(
        fitted.throw,
        fitted[column],
        yerr=fitted[f"{column}_error"],
        fmt="o",
        ms=4,
        capsize=2,
        label="one throw ± σ",
    )
    ax.plot(
        flagged.throw, np.clip(flagged[column], low, high), "x", color="C3", ms=8, label="outlier"
    )
    ax.set_ylim(low, high)
    ax.set_xlabel("throw")
    ax.set_title(name)
axes[0].legend(fontsize=8)
fig.tight_layout()

# %%
# Forecasting what was not seen
# ^^^^^^^^^^^^^^^^^^^^^^^^^^^^^
#
# A fit that matches its samples can still be a wrong body that bends to them;
# a forecast tells. With ``hold_out=0.4`` the last 40 % of every throw is kept
# from a second joint fit (``held_out_joint``: the body from the first 60 % of
# all the throws, each throw's release from its own), whose motion is then
# carried past the cut and compared with the samples there:
# ``forecast_errors`` is the rms of forecast − measured over the rms of
# ``|ω|``, a fraction. ``single_forecast_errors`` is the same of each throw's
# own held-out fit, the throw alone.

print(
    f"median forecast error: joint {np.nanmedian(many.forecast_errors):.2%}, "
    f"each throw alone {np.nanmedian(many.single_forecast_errors):.2%}"
)

# The first throw that has both forecasts.
i = next(k for k in many.held_out_joint.throws if many.held_out_fits[k] is not None)
start, end = many.windows[i]
cut = start + (1.0 - many.hold_out) * (end - start)
inside = (t >= start) & (t <= end)
later = inside & (t > cut)
dense = np.linspace(start, end, 400)
joint_body = many.held_out_joint.throw_fit(i)
alone = many.held_out_fits[i]

fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
top.plot(t[inside], omega[inside], ".", ms=2.5)
top.set_prop_cycle(None)
top.plot(dense, joint_body.forecast(dense), lw=1.0)
top.axvline(cut, color="k", lw=0.8)
top.axvspan(cut, end, color="0.92", lw=0)
top.set_ylabel("ω (rad/s)")
top.set_title(f"throw {i + 1}: measured (dots), joint body fitted left of the line (lines)")
for label, fit in (("joint body", joint_body), ("throw alone", alone)):
    missed = np.linalg.norm(fit.forecast(t[later]) - omega[later], axis=1)
    bottom.semilogy(t[later], missed, lw=1.0, label=label)
bottom.axhline(np.sqrt(3) * NOISE, color="k", lw=0.6, ls="--", label="noise (√3 σ)")
bottom.set_xlabel("t (s)")
bottom.set_ylabel("|forecast − measured| (rad/s)")
bottom.legend(fontsize=8)
fig.tight_layout()

# %%
# The joint body forecasts the held-out samples to about the noise; the throw
# alone, its body known from its own few dozen samples, drifts away from them
# as the flip it mistimes grows. The table's ``forecast_error`` and
# ``single_forecast_error`` give every throw's.

# %%
# From the command line
# ---------------------
#
# ``tumble fit RECORDING.csv`` reads a phyphox export (or any CSV or Parquet
# file, with ``--columns``), prints the same numbers and writes a report and a
# scenario that ``tumble run`` replays; without a file it fits this recording.
# See :doc:`/reference/cli`.
