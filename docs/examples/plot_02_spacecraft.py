r"""
A spacecraft spun up by a thruster
==================================

A scenario file describes a whole simulation in TOML, with units as strings.
``examples/spacecraft.toml`` is a 1200 kg spacecraft given by its measured mass
properties (a full inertia tensor about its centre of mass, products of inertia
included), turning slowly about an axis given in *space* axes, when a thruster
pair starts to fire about its body :math:`z` axis. This page loads the file
through tumble's scenario API, runs it as ``tumble run`` does, and checks the
result against the two laws that hold whatever the body: the work done by the
torque is the change of kinetic energy, and its angular impulse is the change of
angular momentum.
"""

# %%
# Loading the scenario
# --------------------
#
# ``tumble.scenario.load`` takes a built-in scenario's name or a file, and
# validates it: every key, every unit, the physical validity of the tensor. An
# error names the file, the line and the key.

import matplotlib.pyplot as plt
import numpy as np

import tumble.scenario

loaded = tumble.scenario.load("../../examples/spacecraft.toml")
print(loaded.name, "—", loaded.spec.scenario.title)
print(loaded.text)

# %%
# Running it
# ----------
#
# ``tumble.scenario.run`` builds the body, chooses the integrator, simulates and
# compares with the closed form that fits the setup, if any. (``tumble run
# examples/spacecraft.toml`` does the same, then writes a run folder with a report
# and a 3D viewer.) A constant torque in body axes does work, so ``method =
# "auto"`` takes the adaptive Dormand–Prince method, and no closed form fits: the
# run has nothing to compare, and the motion conserves nothing.

result = tumble.scenario.run(loaded)
summary = result.summary()
for key in ("method", "reason", "dt", "steps", "samples", "theory", "comparisons", "drift"):
    print(f"{key:12} {summary[key]}")

traj = result.trajectory
print(traj.mass_properties)

# %%
# The file gives the initial rotation in space axes (``omega_frame = "space"``);
# the trajectory holds ω in body axes, and the initial attitude turns one into
# the other:

print("ω0, space axes (deg/s):", np.degrees(traj.omega_space[0]).round(6) + 0.0)
print("ω0, body axes (deg/s): ", np.degrees(traj.omega[0]).round(6))
# The file's "0.5, 0, 0.2 deg/s", read back through the attitude to round-off.
assert np.allclose(np.degrees(traj.omega_space[0]), [0.5, 0.0, 0.2], rtol=0, atol=1e-12)

# %%
# The motion
# ----------
#
# The thruster's torque is along body :math:`z`, close to the principal axis of
# the smallest moment (the products of inertia tilt it slightly), so the spin
# about :math:`z` builds up almost linearly while the other two rates wobble.

t_min = traj.t / 60
omega = np.degrees(traj.omega)
fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
left.plot(t_min, omega[:, 2], color="C2")
left.set_xlabel("t (min)")
left.set_ylabel("ω_z, body axes (deg/s)")
left.set_title("The spin about body z")
right.plot(t_min, omega[:, 0], label="ω_x")
right.plot(t_min, omega[:, 1], label="ω_y")
right.set_xlabel("t (min)")
right.set_ylabel("ω, body axes (deg/s)")
right.set_title("The transverse rates")
right.legend()
fig.tight_layout()

# %%
# The attitude: how far the body's :math:`z` axis has moved in space from where
# it pointed at the start, and its angle to the angular momentum
# :math:`\mathbf L` (the nutation), from the trajectory's ``rotation`` (one scipy
# ``Rotation`` holding every sample, body → space). At first :math:`\mathbf L` is small and
# the body turns about an axis far from :math:`z`; as the thruster's impulse
# builds :math:`\mathbf L` along body :math:`z`, the nutation cone closes, and the
# wobble quickens with the spin.

z_axis = traj.rotation.apply([0.0, 0.0, 1.0])  # body z in space axes, (n, 3)
moved = np.degrees(np.arccos(np.clip(z_axis @ z_axis[0], -1.0, 1.0)))
L = traj.angular_momentum
L_unit = L / np.linalg.norm(L, axis=1, keepdims=True)
nutation = np.degrees(np.arccos(np.clip(np.sum(z_axis * L_unit, axis=1), -1.0, 1.0)))

fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
left.plot(t_min, moved)
left.set_xlabel("t (min)")
left.set_ylabel("angle (deg)")
left.set_title("Body z from its initial direction")
right.plot(t_min, nutation, color="C3")
right.set_xlabel("t (min)")
right.set_ylabel("angle (deg)")
right.set_title("Body z from L (nutation)")
fig.tight_layout()
print(f"at the end body z has moved {moved[-1]:.2f}° in space; its angle to L: {nutation[-1]:.3f}°")

# %%
# Work and angular impulse
# ------------------------
#
# The torque :math:`\boldsymbol\tau` is fixed in the body. Its power is
# :math:`\boldsymbol\tau\cdot\boldsymbol\omega`, so the kinetic energy grows by the
# work
#
# .. math::
#
#    E(t) - E(0) = \int_0^t \boldsymbol\tau\cdot\boldsymbol\omega\,\mathrm dt,
#
# and in space axes the angular momentum grows by the angular impulse
#
# .. math::
#
#    \mathbf L(t) - \mathbf L(0) = \int_0^t R(t)\,\boldsymbol\tau\,\mathrm dt,
#
# with :math:`R(t)` the attitude. Both integrals are taken here from the recorded
# samples by the trapezoid rule, independently of the integrator.

torque = np.array([0.0, 0.0, 1.5])  # N·m, body axes: the file's [[torques]]
dt = np.diff(traj.t)

power = traj.omega @ torque  # W
work = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * dt)])
gain = traj.energy - traj.energy[0]

torque_space = traj.rotation.apply(torque)  # (n, 3), N·m
steps = 0.5 * (torque_space[1:] + torque_space[:-1]) * dt[:, None]
impulse = np.concatenate([np.zeros((1, 3)), np.cumsum(steps, axis=0)])
change = L - L[0]

energy_error = np.abs(gain - work).max() / np.abs(gain).max()
momentum_error = np.linalg.norm(change - impulse, axis=1).max() / np.linalg.norm(change[-1])
print(f"energy gained {gain[-1]:.4f} J, work {work[-1]:.4f} J (largest gap {energy_error:.1e})")
print(f"L gained {change[-1].round(3)} kg·m²/s, impulse {impulse[-1].round(3)} kg·m²/s")
print(f"largest gap between L(t) − L(0) and the impulse: {momentum_error:.1e} of the change")
# The trapezoid rule errs by about (Δt/2)² times the curvature of the integrand:
# the power grows almost linearly (an error far below 1e-6), while the torque in
# space axes turns with the slow nutation, which samples 0.2 s apart resolve well
# within 1e-5 of the change.
assert energy_error < 1e-6
assert momentum_error < 1e-5

fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
left.plot(t_min, gain, label="E(t) − E(0), simulated")
left.plot(t_min, work, "--", label="∫ τ·ω dt")
left.set_xlabel("t (min)")
left.set_ylabel("energy (J)")
left.set_title("Kinetic energy and work")
left.legend()
for k, axis_name in enumerate("xyz"):
    right.plot(t_min, change[:, k], color=f"C{k}", label=f"ΔL_{axis_name}")
    right.plot(t_min, impulse[:, k], "k--", lw=0.8)
right.set_xlabel("t (min)")
right.set_ylabel("kg·m²/s, space axes")
right.set_title("Angular momentum and impulse (dashed)")
right.legend()
fig.tight_layout()

# %%
# The spacecraft scenarios built into tumble (``tumble list``: ``dual-spin``,
# ``explorer-1``, ``gravity-gradient``, ``reaction-wheel-slew``) add reaction
# wheels, dampers, a circular orbit and a controller, each compared with its
# closed form; :doc:`/reference/scenario-keys` lists every key of a scenario
# file.
