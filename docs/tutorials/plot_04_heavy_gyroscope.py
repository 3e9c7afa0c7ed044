r"""
The heavy gyroscope: precession and nutation
============================================

A spinning disk on a pivot, its axis held horizontal and released: instead of
falling, the axis turns slowly about the vertical (precession) while nodding
quickly up and down (nutation). This is the heavy symmetric top, or Lagrange
top. This page compares the fast-top formulas of the textbooks with the exact
solution and with a simulation, draws the path of the axis, and finds the spin
below which the formulas fail.
"""

# %%
# Theory
# ------
#
# A body symmetric about its axis, of mass :math:`M`, with moment :math:`I_s`
# about the axis and :math:`I_\perp` across it at the centre of mass, turns
# about a fixed pivot on the axis a distance :math:`l` from the centre of
# mass. About the pivot the transverse moment is :math:`I_\perp' = I_\perp +
# M l^2`. With the Euler angles :math:`\phi` (precession about the upward
# vertical), :math:`\theta` (tilt of the axis from it) and :math:`\psi` (spin),
# the Lagrangian is
#
# .. math::
#
#    \mathcal L = \tfrac12 I_\perp'(\dot\theta^2 + \dot\phi^2\sin^2\theta)
#               + \tfrac12 I_s(\dot\psi + \dot\phi\cos\theta)^2 - M g l\cos\theta .
#
# :math:`\phi` and :math:`\psi` are cyclic: the spin :math:`\omega_s = \dot\psi +
# \dot\phi\cos\theta` (the whole angular velocity along the axis), the vertical
# component of :math:`\mathbf L`, and the energy are constant. With
# :math:`u = \cos\theta` they leave one equation, :math:`\dot u^2 = f(u)`, with
# :math:`f` a cubic; the tilt swings between two of its roots, and
# :math:`u(t)` is a Jacobi elliptic function, :math:`u = u_1 + (u_2 - u_1)
# \,\mathrm{sn}^2(pt + \tau_0\,|\,m)` (Goldstein, *Classical Mechanics*, §5.7;
# Landau & Lifshitz, *Mechanics*, §35). :func:`tumble.theory.gyroscope`
# evaluates this exact solution at any time.
#
# A steady precession at the tilt :math:`\theta` needs
# :math:`I_\perp'\cos\theta\,\Omega^2 - I_s\omega_s\,\Omega + M g l = 0`. For
# a fast top, :math:`I_s\omega_s \gg \sqrt{M g l I_\perp'}`, released from rest
# at :math:`\theta_0`, the expansion in the small parameter
# :math:`\varepsilon = M g l I_\perp' / (I_s\omega_s)^2` gives the textbook
# results
#
# .. math::
#
#    \Omega_p \approx \frac{M g l}{I_s\omega_s}, \qquad
#    \omega_n \approx \frac{I_s\omega_s}{I_\perp'}, \qquad
#    \frac{\theta_{\max} - \theta_{\min}}{2} \approx
#    \frac{M g l I_\perp'\sin\theta_0}{(I_s\omega_s)^2} = \varepsilon\sin\theta_0 :
#
# the precession rate, the nutation frequency and the half-amplitude of the
# nod, each with relative corrections of order :math:`\varepsilon`.

import math

import matplotlib.pyplot as plt
import numpy as np
from scipy.spatial.transform import Rotation

import tumble as tb

# The body and release of the default scenario (`tumble run`).
disk = tb.shapes.solid_cylinder("1 kg", radius="10 cm", height="1 cm")
pivot = [0.0, 0.0, -0.1]  # m, body axes: on the axis, 10 cm from the centre
g = 9.81  # m/s²
spin = 200.0  # rad/s
tilt0 = math.radians(90.0)  # released from rest with the axis horizontal

top = tb.theory.gyroscope(disk, pivot, spin, tilt0, g)
mgl = top.mass * g * top.lever_arm
momentum = top.axial_moment * spin  # I_s ω_s
epsilon = mgl * top.transverse_moment / momentum**2
print(
    f"I_s = {top.axial_moment:.6g} kg·m², I⊥' = {top.transverse_moment:.6g} kg·m² "
    f"(I⊥ = {disk.inertia[0, 0]:.6g} at the centre), M g l = {mgl:.6g} N·m"
)
print(f"ε = M g l I⊥' / (I_s ω_s)² = {epsilon:.4g}")

# %%
# Simulation against the exact solution
# -------------------------------------
#
# :func:`tumble.simulate` would pick the exact solution for this body by
# itself (``method="auto"``); here it steps Euler's equations with the
# fourth-order splitting integrator instead, so that the two are independent.
# The initial attitude turns the body's axis (body :math:`z`) by
# :math:`\theta_0` about space :math:`x`, as :func:`tumble.theory.gyroscope`
# does.


def attitude(tilt):
    """The attitude with body z tilted by `tilt` (rad) about space x, [w, x, y, z]."""
    return [math.cos(tilt / 2), math.sin(tilt / 2), 0.0, 0.0]


run = tb.simulate(
    disk,
    [0.0, 0.0, spin],
    attitude0=attitude(tilt0),
    duration=1.0,
    dt=1e-4,
    pivot=pivot,
    gravity=[0.0, 0.0, -g],
    method="splitting",
    record_every=5,
)
print(run)

exact_tilt = top.tilt_at(run.t)
_, exact_q = top.at(run.t)
nutation = tb.analysis.nutation(run)
precession = tb.analysis.precession(run)
tilt_error = np.max(np.abs(nutation.tilt - exact_tilt))
attitude_error = np.max(
    (Rotation.from_quat(exact_q, scalar_first=True).inv() * run.rotation).magnitude()
)
print(f"largest |θ_simulated − θ_exact| = {tilt_error:.1e} rad; attitude {attitude_error:.1e} rad")

low, high = top.nutation_limits
rows = [
    ("precession rate (rad/s)", top.precession_rate, top.mean_precession_rate, precession.rate),
    (
        "nutation frequency (rad/s)",
        top.nutation_frequency,
        2 * math.pi / top.nutation_period,
        nutation.frequency,
    ),
    ("nutation half-amplitude (rad)", top.nutation_amplitude, (high - low) / 2, nutation.amplitude),
]
print(f"{'':30s} {'fast top':>12s} {'exact':>12s} {'simulated':>12s} {'fast-top error':>15s}")
for name, fast, exact, simulated in rows:
    print(f"{name:30s} {fast:12.7g} {exact:12.7g} {simulated:12.7g} {fast / exact - 1:15.2e}")

# Fourth-order splitting at ω_s Δt = 0.02 follows the exact tilt to ~1e-12 rad;
# 1e-9 rad is under a millionth of the nod, far below anything the figures show.
assert tilt_error < 1e-9
# The fast-top formulas are the first terms of an expansion in ε: their
# relative errors are of order ε or smaller.
for _, fast, exact, _ in rows:
    assert abs(fast / exact - 1) < epsilon

# %%
# The path of the axis
# --------------------
#
# Seen as the tilt :math:`\theta` against the azimuth :math:`\phi`, the tip of
# the axis of a top released from rest traces cusps: it starts at rest, falls,
# picks up speed in azimuth, and comes back to rest at the top of each nod. A
# top launched with some precession already (``precession_rate0``) traces
# waves if it moves ahead in azimuth, loops if it starts backwards. Lines: the
# exact solution; dots: the simulation.


def tip(quaternions):
    """Tilt θ and unwrapped azimuth φ of body z, in degrees."""
    axis = Rotation.from_quat(quaternions, scalar_first=True).apply([0.0, 0.0, 1.0])
    theta = np.degrees(np.arccos(np.clip(axis[:, 2], -1.0, 1.0)))
    phi = np.degrees(np.unwrap(np.arctan2(axis[:, 1], axis[:, 0])))
    return theta, phi - phi[0]


rate_p = top.precession_rate
starts = {"loops": -0.5 * rate_p, "cusps": 0.0, "waves": 0.5 * rate_p}
duration = 3.5 * top.nutation_period
fig, axes = plt.subplots(1, 3, figsize=(11, 3.6), sharey=True, layout="constrained")
for ax, (name, phi_dot0) in zip(axes, starts.items(), strict=True):
    exact = tb.theory.gyroscope(disk, pivot, spin, tilt0, g, precession_rate0=phi_dot0)
    t = np.linspace(0.0, duration, 600)
    theta, phi = tip(exact.at(t)[1])
    ax.plot(phi, theta, lw=1.2, label="exact")
    sim = tb.simulate(
        disk,
        [0.0, phi_dot0 * math.sin(tilt0), spin],  # ω0 = (θ̇0, φ̇0 sin θ0, ω_s), body axes
        attitude0=attitude(tilt0),
        duration=duration,
        dt=1e-4,
        pivot=pivot,
        gravity=[0.0, 0.0, -g],
        method="splitting",
        record_every=20,
    )
    theta_s, phi_s = tip(sim.quaternion)
    ax.plot(phi_s, theta_s, ".", ms=3, color="C1", label="simulation")
    ax.set_title(rf"{name}: $\dot\phi_0$ = {phi_dot0:+.3f} rad/s", fontsize="medium")
    ax.set_xlabel("azimuth φ − φ0 (deg)")
axes[0].set_ylabel("tilt θ from the upward vertical (deg)")
axes[0].invert_yaxis()  # the axis dips downwards
axes[1].legend(fontsize="small", loc="lower center")
fig.suptitle(
    rf"Tip of the axis, $\omega_s$ = {spin:.0f} rad/s, "
    rf"released at $\theta_0$ = {math.degrees(tilt0):.0f}°"
)
plt.show()

# %%
# Precession rate against spin
# ----------------------------
#
# The mean precession rate of the released top over whole nutation periods,
# exact (``Gyroscope.mean_precession_rate``) and measured on simulations
# (:func:`tumble.analysis.precession`), against the fast-top
# :math:`M g l / (I_s\omega_s)`. The dashed line marks the spin at which
# :math:`I_s\omega_s = \sqrt{M g l I_\perp'}`, i.e. :math:`\varepsilon = 1`.

spins = np.geomspace(12.0, 1000.0, 80)
exact_rates = np.array(
    [tb.theory.gyroscope(disk, pivot, s, tilt0, g).mean_precession_rate for s in spins]
)
fast_rates = mgl / (top.axial_moment * spins)
crossover = math.sqrt(mgl * top.transverse_moment) / top.axial_moment

sim_spins = np.array([15.0, 25.0, 50.0, 100.0, 200.0, 500.0])
sim_rates = []
print(" ω_s (rad/s)  simulated   exact mean  fast top   fast-top error")
for s in sim_spins:
    exact = tb.theory.gyroscope(disk, pivot, s, tilt0, g)
    sim = tb.simulate(
        disk,
        [0.0, 0.0, s],
        attitude0=attitude(tilt0),
        duration=3.2 * exact.nutation_period,
        pivot=pivot,
        gravity=[0.0, 0.0, -g],
        method="splitting",
    )
    measured = tb.analysis.precession(sim).rate
    sim_rates.append(measured)
    off = exact.precession_rate / exact.mean_precession_rate - 1
    print(
        f"{s:12.0f} {measured:10.5f} {exact.mean_precession_rate:12.5f} "
        f"{exact.precession_rate:9.5f} {off:12.2%}"
    )
sim_rates = np.array(sim_rates)
print(f"ε = 1 at ω_s = {crossover:.1f} rad/s")
error = fast_rates / exact_rates - 1
print(
    f"the fast-top rate is within 1 % of the exact mean above ω_s = "
    f"{spins[np.argmax(error < 0.01)]:.0f} rad/s"
)

fig, (ax, bottom) = plt.subplots(2, 1, figsize=(7.0, 6.5), sharex=True, layout="constrained")
ax.loglog(spins, fast_rates, "--", label=r"fast top, $M g l / (I_s\omega_s)$")
ax.loglog(spins, exact_rates, label="exact mean rate")
ax.loglog(sim_spins, sim_rates, "o", mfc="none", label="simulation")
ax.axvline(crossover, color="0.5", lw=0.8, ls="--")
ax.set_ylabel("precession rate (rad/s)")
ax.legend(fontsize="small")
bottom.loglog(spins, 100 * error, color="C1", label="fast top vs exact mean")
bottom.loglog(
    sim_spins,
    100 * (mgl / (top.axial_moment * sim_spins) / sim_rates - 1),
    "o",
    color="C2",
    mfc="none",
    label="fast top vs simulation",
)
bottom.axhline(1.0, color="C3", lw=0.8)
bottom.text(spins[-1], 1.15, "1 %", color="C3", ha="right", va="bottom")
bottom.axvline(crossover, color="0.5", lw=0.8, ls="--")
ax.text(crossover * 1.05, ax.get_ylim()[0] * 1.2, r"$\varepsilon = 1$", color="0.4")
bottom.legend(fontsize="small")
bottom.set_xlabel(r"spin $\omega_s$ (rad/s)")
bottom.set_ylabel("fast-top error (%)")
plt.show()

# %%
# The fast-top rate is too high for a top released from rest: the axis
# starts with no azimuthal speed and spends part of each nod catching up. At
# slow spin the top falls far below the horizontal before it turns back, and
# its mean precession is much slower than :math:`M g l / (I_s\omega_s)`.
#
# Classic slips
# -------------
#
# The equations of motion in body axes are Euler's equations about the
# pivot. Lecture notes sometimes misprint the second; it reads
#
# .. math::
#
#    I_2\dot\omega_2 + (I_1 - I_3)\,\omega_3\omega_1 = \tau_2 ,
#
# with :math:`I_2\dot\omega_2`, not :math:`I_1\dot\theta_2`, and in any body
# frame :math:`\mathsf I\dot{\boldsymbol\omega} + \boldsymbol\omega\times
# (\mathsf I\boldsymbol\omega) = \boldsymbol\tau`, which is
# :func:`tumble.required_torque`. Applied to the exact motion (with
# :math:`\dot{\boldsymbol\omega}` by differences), it returns the torque of
# gravity about the pivot:

h = 1e-5  # s, the step of the five-point difference
t_check = 0.3
w_at = top.at(t_check + h * np.arange(-2, 3))[0]
w_dot = (w_at[0] - 8 * w_at[1] + 8 * w_at[3] - w_at[4]) / (12 * h)
w_now, q_now = top.at(t_check)
needed = tb.required_torque(disk, w_now, w_dot, about=pivot)
weight = Rotation.from_quat(q_now, scalar_first=True).inv().apply([0.0, 0.0, -top.mass * g])
gravity_torque = np.cross(disk.center_of_mass - np.array(pivot), weight)  # body axes
print(f"I ω̇ + ω × I ω about the pivot: {needed} N·m")
print(f"r × M g, body axes:            {gravity_torque} N·m")
# The five-point difference errs by ~(ω_s h)⁴ ~ 1e-11 and by round-off ~1e-16 |ω| / h
# ~ 1e-9 relative to the torque: 1e-6 of M g l leaves ample room.
assert np.allclose(needed, gravity_torque, atol=1e-6 * mgl)

# %%
# Two more slips are common. The transverse moment in the nutation frequency
# is the one about the pivot, :math:`I_\perp' = I_\perp + M l^2`, not about the
# centre of mass; here the difference is a large factor. And :math:`\omega_s`
# is the whole angular velocity along the axis, not the spin :math:`\dot\psi`
# relative to the precessing frame; they differ by :math:`\dot\phi\cos\theta`.

wrong = momentum / disk.inertia[0, 0]
print(
    f"I_s ω_s / I⊥' = {top.nutation_frequency:.2f} rad/s; with I⊥ at the centre of mass: "
    f"{wrong:.2f} rad/s, {wrong / top.nutation_frequency:.1f} times too fast"
)

# %%
# The built-in scenario
# ---------------------
#
# ``tumble run`` (or ``tumble run gyroscope``) runs this top for 5 s with the
# exact solution and writes a report comparing its precession, nutation
# frequency and amplitude with the same formulas; the built-in ``heavy-top``
# is a cone spinning too slowly for them. From Python:

import tumble.scenario  # noqa: E402

result = tumble.scenario.run("gyroscope")
print(result.scenario.spec.scenario.title, "—", result.trajectory.method)
for row in result.comparisons:
    print(
        f"{row['quantity']:42s} theory {row['theory']:10.6g} {row['unit']:6s} "
        f"relative error {row['relative_error']:.1e}"
    )

# %%
# Where the formulas stop holding
# -------------------------------
#
# The fast-top formulas are the first terms of an expansion in
# :math:`\varepsilon = M g l I_\perp'/(I_s\omega_s)^2`. They hold to a
# per cent or so when :math:`I_s\omega_s` is several times
# :math:`\sqrt{M g l I_\perp'}` and fail as the spin approaches it, where the
# top falls far before it turns back. At tilts other than 90° the steady
# precession rate is a root of the quadratic above, not
# :math:`M g l/(I_s\omega_s)`, and near the vertical a top needs
# :math:`(I_s\omega_s)^2 > 4 I_\perp' M g l` to sleep upright. The exact
# solution holds for any spin, but only for a symmetric body on a fixed,
# frictionless pivot: friction at the pivot and air drag slow the spin, so a
# real top precesses faster and faster, nods more, and eventually falls.
