r"""
A toy top with air drag
=======================

``examples/spinning_top.toml`` describes a toy top as an assembly of parts: a
disk of 60 g on a steel axle of 8 g, spinning at 3000 rpm on the axle's lower tip,
released at 20° from the vertical, with a little air drag
:math:`\boldsymbol\tau = -c\,\boldsymbol\omega`. The drag does work, so no closed
form describes the whole motion, and the file asks for no comparison
(``[theory] model = "none"``). Two exact laws still hold, and this page checks
them on the simulation: the spin about the symmetry axis decays exponentially,
and the energy lost is the work of the drag. For the first second, while the
spin has barely slowed, the precession is that of the drag-free Lagrange top.
"""

# %%
# The top
# -------
#
# The scenario's ``[[body.parts]]`` are two solid cylinders on one axis, the disk
# moved 1 cm up the axle; tumble adds their mass properties about their common
# centre of mass. The pivot is the axle's tip, 3 cm below the axle's centre.

import matplotlib.pyplot as plt
import numpy as np

import tumble as tb
import tumble.scenario

loaded = tumble.scenario.load("../../examples/spinning_top.toml")
print(loaded.spec.scenario.title)
result = tumble.scenario.run(loaded)
traj = result.trajectory
top = traj.mass_properties
print(top)
about_pivot = top.inertia_about(traj.pivot)
print("inertia about the pivot (kg·m²):", about_pivot.diagonal())
print("method:", traj.method, "—", traj.reason, f"({traj.steps} steps)")
print("theory:", result.theory, "; conserved:", traj.conserved_quantities or "nothing")

# %%
# tumble's own figures
# --------------------
#
# ``Trajectory.plot()`` returns the figures of the run's report as matplotlib
# figures: ω in body axes and the angular momentum in space axes (with the drift
# of the conserved quantities and the polhode, which say little for a damped
# top). tumble draws them without pyplot, which keeps no global state; each is
# handed to pyplot here so that the page shows it.


def show(figure):
    """Make a figure drawn without pyplot one of pyplot's figures."""
    manager = plt.figure(figsize=figure.get_size_inches()).canvas.manager
    manager.canvas.figure = figure
    figure.set_canvas(manager.canvas)


figures = traj.plot()
print("figures:", list(figures))
show(figures["omega"])
show(figures["angular_momentum"])

# %%
# The spin decays exponentially
# -----------------------------
#
# About the symmetry axis Euler's third equation reads
# :math:`C\dot\omega_3 + (B - A)\,\omega_1\omega_2 = \tau_3`. The top is symmetric,
# :math:`A = B` about the pivot, and gravity's torque about the pivot is
# perpendicular to the axis, so only the drag acts:
#
# .. math::
#
#    C \dot\omega_3 = -c\,\omega_3
#    \quad\Longrightarrow\quad
#    \omega_3(t) = \omega_3(0)\, e^{-c t / C},
#
# exactly, whatever the nutation.

c = 2e-7  # N·m·s, the file's damping coefficient
C = about_pivot[2, 2]  # kg·m², the axial moment
predicted = traj.omega[0, 2] * np.exp(-c * traj.t / C)
spin_error = np.max(np.abs(traj.omega[:, 2] / predicted - 1))
print(f"spin {traj.omega[0, 2]:.2f} → {traj.omega[-1, 2]:.2f} rad/s")
print(f"time constant C / c = {C / c:.0f} s")
print(f"largest relative gap to the exponential: {spin_error:.1e}")
# The adaptive method keeps each step's error below 1e-10 relative; over a few
# thousand steps that stays far below 1e-8.
assert spin_error < 1e-8

# %%
# The energy goes into the drag
# -----------------------------
#
# The drag's power is :math:`-c\,|\boldsymbol\omega|^2`, so the energy (kinetic,
# about the pivot, plus the potential energy of the weight) falls by
# :math:`c\int_0^t |\boldsymbol\omega|^2\,\mathrm dt`, which the trapezoid rule
# gives from the recorded samples:

speed2 = np.sum(traj.omega**2, axis=1)
slices = 0.5 * (speed2[1:] + speed2[:-1]) * np.diff(traj.t)
dissipated = c * np.concatenate([[0.0], np.cumsum(slices)])
lost = traj.energy[0] - traj.energy
energy_error = np.max(np.abs(lost - dissipated)) / lost[-1]
print(f"energy lost {lost[-1]:.6f} J, work of the drag {dissipated[-1]:.6f} J")
print(f"largest gap between the two: {energy_error:.1e} of the loss")
# |ω|² is nearly the spin's square, which changes slowly; its nutation ripple is
# sampled many times a period, so the trapezoid rule errs far below 1e-6.
assert energy_error < 1e-6

# %%
# Precession and nutation
# -----------------------
#
# The symmetry axis in space is the body's :math:`z` axis turned by the attitude.
# Its tilt from the vertical nods between two limits (the nutation) while its
# azimuth turns (the precession). :func:`tumble.theory.gyroscope` gives the exact
# motion of the same top without drag, released from rest at 20° with the same
# spin: its turning points and its mean precession rate over whole nutation
# periods.

axis = traj.rotation.apply([0.0, 0.0, 1.0])
tilt = np.degrees(np.arccos(np.clip(axis[:, 2], -1.0, 1.0)))
azimuth = np.unwrap(np.arctan2(axis[:, 1], axis[:, 0]))

free = tb.theory.gyroscope(top, traj.pivot, traj.omega[0, 2], np.radians(20.0))
limits = np.degrees(free.nutation_limits)
print(f"without drag: tilt between {limits[0]:.3f}° and {limits[1]:.3f}°")
print(f"nutation period {free.nutation_period * 1e3:.2f} ms")
print(f"mean precession {free.mean_precession_rate:.4f} rad/s")

periods = int(1.0 // free.nutation_period)  # whole nutation periods in the first second
end = np.searchsorted(traj.t, periods * free.nutation_period)
measured = (azimuth[end] - azimuth[0]) / traj.t[end]
gap = measured / free.mean_precession_rate - 1
print(f"over the first {periods} nutation periods: mean precession {measured:.4f} rad/s")
print(f"that is {gap:+.1%} from the drag-free top")
# In that second the drag slows the spin by the fraction t / (C / c), about a
# hundredth with the printed time constant, and the precession speeds up as the
# spin's inverse: a few per cent covers it, and fails a wrong law of precession.
assert abs(gap) < 0.03

fig, (upper, lower) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
upper.plot(traj.t, tilt, lw=0.8, label="simulated, with drag")
for limit in limits:
    upper.axhline(limit, color="k", ls="--", lw=0.8)
upper.set_ylabel("tilt from the vertical (deg)")
upper.set_title("The top's axis: nutation (dashed: turning points without drag)")
upper.legend(loc="lower right")
lower.plot(traj.t, np.degrees(azimuth - azimuth[0]), label="simulated, with drag")
mean_azimuth = np.degrees(free.mean_precession_rate * traj.t)
lower.plot(traj.t, mean_azimuth, "k--", lw=0.8, label="mean precession without drag")
lower.set_xlabel("t (s)")
lower.set_ylabel("azimuth of the axis (deg)")
lower.legend()
fig.tight_layout()

# %%
# As the drag slows the spin, the top precesses faster and its axis sinks: the
# tilt creeps past the drag-free turning point. A top with no drag, the same file
# without its ``[[torques]]`` table, is a Lagrange top, and ``method = "auto"``
# then solves it in closed form (:doc:`/explanation/methods`).
