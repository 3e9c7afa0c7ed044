r"""
Euler's equations and the tennis-racket flip
============================================

Toss a tennis racket, a phone or a book spinning about each of its three
principal axes in turn. About the axes of the largest and of the smallest
moment it spins steadily; about the intermediate one it flips over, again and
again, however carefully it is thrown (the tennis-racket, or Dzhanibekov,
effect). This page derives the effect from Euler's equations, computes the
period of the flips in closed form with :func:`tumble.theory.flip_period`,
and compares it with a simulation by :func:`tumble.simulate` for perturbations
of several sizes.
"""

# %%
# Euler's equations
# -----------------
#
# In the principal axes of a body, with moments :math:`I_1 < I_2 < I_3` and
# :math:`\boldsymbol\omega` in body coordinates, the rate of change of
# :math:`\mathbf L = \mathsf I \boldsymbol\omega` in space,
# :math:`\dot{\mathbf L} = \boldsymbol\tau`, reads (Landau & Lifshitz,
# *Mechanics*, §36; Goldstein, *Classical Mechanics*, §5.5)
#
# .. math::
#
#    I_1 \dot\omega_1 + (I_3 - I_2)\, \omega_2 \omega_3 = \tau_1, \qquad
#    I_2 \dot\omega_2 + (I_1 - I_3)\, \omega_3 \omega_1 = \tau_2, \qquad
#    I_3 \dot\omega_3 + (I_2 - I_1)\, \omega_1 \omega_2 = \tau_3,
#
# or, in any body frame, :math:`\mathsf I \dot{\boldsymbol\omega} + \boldsymbol\omega
# \times \mathsf I \boldsymbol\omega = \boldsymbol\tau`
# (:func:`tumble.required_torque`). Some lecture notes print the second
# equation with :math:`I_1 \ddot\theta_2` in place of :math:`I_2 \dot\omega_2`;
# the equations are cyclic in 1 → 2 → 3 → 1, and the second one carries
# :math:`I_2` and :math:`\dot\omega_2`.
#
# Without torque two quantities are conserved: the kinetic energy
# :math:`2E = I_1\omega_1^2 + I_2\omega_2^2 + I_3\omega_3^2` and
# :math:`L^2 = I_1^2\omega_1^2 + I_2^2\omega_2^2 + I_3^2\omega_3^2`.
#
# Stability of the three axes
# ---------------------------
#
# Spin the body at :math:`\Omega` about axis :math:`k` and perturb it slightly.
# Linearising the equations for the two small components :math:`\omega_i,
# \omega_j` gives :math:`\ddot\omega_i = -s_k\, \omega_i` with
#
# .. math::
#
#    s_k = \Omega^2\, \frac{(I_k - I_i)(I_k - I_j)}{I_i I_j} .
#
# For the largest and the smallest axis both factors have the same sign:
# :math:`s_k > 0`, and the perturbation oscillates. For the intermediate axis
# they have opposite signs: the perturbation grows as :math:`e^{\gamma t}` with
#
# .. math::
#
#    \gamma = \Omega \sqrt{\frac{(I_2 - I_1)(I_3 - I_2)}{I_1 I_3}} .
#
# :func:`tumble.theory.axis_stability` evaluates both. The body here is the one
# of the built-in scenario ``tennis-racket`` (``tumble run tennis-racket``
# shows it in a report and a 3D viewer): a 0.5 kg block of
# 20 × 10 × 4 cm, spun at 10 rad/s about its intermediate axis, body :math:`y`.

import matplotlib.pyplot as plt
import numpy as np
from scipy import special

import tumble as tb

body = tb.shapes.box("0.5 kg", "20, 10, 4 cm")
moments, axes = body.principal()
spin = 10.0  # rad/s
stability = tb.theory.axis_stability(body, spin)
print("principal moments (kg·m²):", moments)
print("principal axes (columns):\n", axes)
for k in range(3):
    state = "stable" if stability.stable[k] else "UNSTABLE"
    print(
        f"axis {k + 1}: {state:8s} wobble {stability.oscillation_frequencies[k]:.4f} rad/s, "
        f"growth {stability.growth_rates[k]:.4f} 1/s"
    )
gamma = stability.growth_rates[1]

# %%
# The flip period
# ---------------
#
# The linear analysis says only that a small perturbation grows; the full
# motion is periodic. Euler's free equations are solved by Jacobi's elliptic
# functions (Landau & Lifshitz, §37). For :math:`L^2 > 2 E I_2` (:math:`\mathbf L`
# closer to the axis of :math:`I_3`)
#
# .. math::
#
#    \omega_1 \propto \operatorname{cn}(\lambda t, k),\quad
#    \omega_2 \propto \operatorname{sn}(\lambda t, k),\quad
#    \omega_3 \propto \operatorname{dn}(\lambda t, k),
#
# .. math::
#
#    \lambda^2 = \frac{(I_3 - I_2)(L^2 - 2 E I_1)}{I_1 I_2 I_3},\qquad
#    k^2 = \frac{(I_2 - I_1)(2 E I_3 - L^2)}{(I_3 - I_2)(L^2 - 2 E I_1)},
#
# and for :math:`L^2 < 2 E I_2` the same with :math:`I_1` and :math:`I_3`
# exchanged. :math:`\operatorname{sn}` has the period :math:`4K(k)`, with the
# complete elliptic integral
# :math:`K(k) = \int_0^{\pi/2} \mathrm d\varphi / \sqrt{1 - k^2 \sin^2\varphi}`,
# so ω(t) has the period
#
# .. math::
#
#    T = \frac{4 K(k)}{\lambda} .
#
# :math:`\omega_2` changes sign twice in each period: the body flips twice
# per :math:`T`, and the time between two flips is :math:`T/2`. Two factor
# slips are easy to make here: comparing :math:`T` with the interval between
# flips (a factor 2), and passing :math:`k` where a library expects the
# parameter :math:`m = k^2` (``scipy.special.ellipk(m)`` takes :math:`m`).
#
# Near the intermediate axis, :math:`1 - k^2` is of the order of the square
# of the perturbation :math:`\varepsilon`, :math:`\lambda \to \gamma`, and
# :math:`K \approx \ln(4 / \sqrt{1 - k^2})`, so
#
# .. math::
#
#    T \approx \frac{4}{\gamma} \ln\frac{1}{\varepsilon} + \text{const}:
#
# ten times smaller a perturbation adds the same :math:`4 \ln 10 / \gamma` to
# the period. The formulas above, written out, against
# :func:`tumble.theory.flip_period`:


def period_by_hand(inertia, omega):
    """T = 4 K(k) / λ from the formulas above (principal axes, I1 < I2 < I3)."""
    i1, i2, i3 = inertia
    two_e = np.sum(inertia * omega**2)
    l2 = np.sum((inertia * omega) ** 2)
    if l2 < two_e * i2:  # the other side of the separatrix: exchange 1 and 3
        i1, i3 = i3, i1
    lam = np.sqrt((i3 - i2) * (l2 - two_e * i1) / (i1 * i2 * i3))
    m = (i2 - i1) * (two_e * i3 - l2) / ((i3 - i2) * (l2 - two_e * i1))  # m = k²
    return 4 * special.ellipk(m) / lam


epsilons = [1e-1, 1e-2, 1e-3, 1e-4, 1e-6]
initial = {eps: np.array([eps * spin, spin, eps * spin]) for eps in epsilons}  # rad/s, body axes
for eps, omega0 in initial.items():
    hand, library = period_by_hand(moments, omega0), tb.theory.flip_period(body, omega0)
    print(
        f"ε = {eps:.0e}: T by hand {hand:.10f} s, flip_period {library:.10f} s, "
        f"relative difference {hand / library - 1:+.1e}"
    )
    # In float64, m = k² carries an error of ~1e-16, so 1 − m ~ ε² is known to
    # ~1e-16/ε² of itself and K, ≈ ln(4/√(1 − m)), to half that in absolute
    # terms: the hand formula loses digits as ε → 0 (at ε = 1e-6, 1e-4 of T).
    # flip_period evaluates E, L and k² in exact rational arithmetic instead.
    assert np.isclose(hand, library, rtol=1e-12 + 1e-14 / eps**2)


# %%
# Simulation
# ----------
#
# :func:`tumble.simulate` integrates Euler's equations with the attitude
# quaternion. ``method="rk4"`` steps them (1 ms steps, over 600 a turn); the
# default for a torque-free body would be the closed form itself. Each run
# lasts 3.2 periods, and :func:`tumble.analysis.flips` finds the sign changes
# of :math:`\omega_2` and returns twice their mean spacing as the period.

runs, measured = {}, {}
for eps, omega0 in initial.items():
    period = tb.theory.flip_period(body, omega0)
    run = tb.simulate(body, omega0, duration=3.2 * period, dt=1e-3, method="rk4")
    flips = tb.analysis.flips(run)
    runs[eps], measured[eps] = run, flips.period
    size = np.linalg.norm(run.angular_momentum, axis=1)
    print(
        f"ε = {eps:.0e}: T theory {period:8.5f} s, simulated {flips.period:8.5f} s "
        f"({flips.count} flips), relative error {flips.period / period - 1:+.1e}; "
        f"drift of E {np.ptp(run.energy) / run.energy[0]:.1e}, "
        f"of |L| {np.ptp(size) / size[0]:.1e}"
    )

# Where ε >= 1e-4 the period is well conditioned: RK4's errors in E and L (the
# printed drifts, ~1e-11) move 1 − k² ∝ ε² by less than 1e-3 of itself, and T
# by less than that over 2K (~1e-4); locating the flips by linear
# interpolation between 1 ms samples adds ~1e-9. At ε = 1e-6, ε² is itself
# ~1e-12 and the measured period is only as good as the printed error.
for eps in epsilons:
    if eps >= 1e-4:
        assert abs(measured[eps] / tb.theory.flip_period(body, initial[eps]) - 1) < 1e-4

# %%
# The flips
# ---------
#
# ω in the principal axes for :math:`\varepsilon = 10^{-3}`: :math:`\omega_2`
# stays near :math:`\pm\Omega` and reverses in a short tumble, while
# :math:`\omega_1` and :math:`\omega_3` swell during it. The dotted lines mark
# the measured flip times.

run = runs[1e-3]
fig, ax = plt.subplots(figsize=(8, 4), layout="constrained")
for k, colour in enumerate(["tab:red", "tab:green", "tab:blue"]):
    ax.plot(run.t, run.omega @ axes[:, k], color=colour, label=rf"$\omega_{k + 1}$")
for t_flip in tb.analysis.flips(run).times:
    ax.axvline(t_flip, color="0.5", linestyle=":", linewidth=1)
ax.set(xlabel="time (s)", ylabel="angular velocity (rad/s)")
ax.set_title(r"Spin about the intermediate axis, $\varepsilon = 10^{-3}$")
ax.legend(loc="lower right")

# %%
# The period against the size of the perturbation: a straight line in
# :math:`\ln(1/\varepsilon)` with the slope :math:`4/\gamma` of the asymptotic
# formula, the closed form through the simulated points.

fine = np.logspace(-7, -0.5, 60)
fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
ax.semilogx(
    fine,
    [tb.theory.flip_period(body, [e * spin, spin, e * spin]) for e in fine],
    color="k",
    label=r"$T = 4K(k)/\lambda$",
)
ax.semilogx(epsilons, [measured[e] for e in epsilons], "o", color="tab:orange", label="simulated")
ax.invert_xaxis()
ax.set(xlabel=r"perturbation $\varepsilon$ (of $\Omega$)", ylabel="period of ω(t) (s)")
ax.legend()

slope = np.polyfit(np.log(1 / np.array(epsilons[2:])), [measured[e] for e in epsilons[2:]], 1)[0]
print(f"slope dT/d ln(1/ε), simulated (ε <= 1e-3): {slope:.5f} s; 4/γ = {4 / gamma:.5f} s")
# The asymptotic slope is approached with corrections of order ε² (1e-6 here):
# the fit over ε <= 1e-3 must give 4/γ to well within 1e-3.
assert np.isclose(slope, 4 / gamma, rtol=1e-3)

# %%
# The polhode on the momentum sphere
# ----------------------------------
#
# In the body, :math:`\mathbf L` keeps its length and its energy, so its tip
# lies on the sphere :math:`|\mathbf L| = L` and on the ellipsoid
# :math:`\sum L_k^2 / (2 E I_k) = 1`. Their intersections, the *polhodes*,
# circle the axes of :math:`I_1` and :math:`I_3`; the two curves through the
# axis of :math:`I_2` (dashed, the *separatrix*) are two great circles,
# :math:`L_1 \sqrt{1/I_1 - 1/I_2} = \pm L_3 \sqrt{1/I_2 - 1/I_3}`. A body near
# the intermediate axis follows the separatrix from one end of that axis to the
# other: that is the flip. The polhodes here come from the exact solution,
# :func:`tumble.theory.free_motion`; the simulated run (:math:`\varepsilon =
# 10^{-3}`) is drawn from :func:`tumble.analysis.polhode`.

elevation, azimuth = np.radians(25), np.radians(40)
eye = np.array(
    [np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth), np.sin(elevation)]
)


def draw(ax, points, **style):
    """A curve on the unit sphere: solid where it faces the viewer, faint behind."""
    facing = points @ eye >= 0
    for visible, extra in ((True, {}), (False, {"alpha": 0.25, "lw": 0.7, "label": None})):
        part = np.where((facing == visible)[:, None], points, np.nan)
        ax.plot(*part.T, **{**style, **extra})


fig = plt.figure(figsize=(6.5, 6), layout="constrained")
ax = fig.add_subplot(projection="3d")
phi = np.linspace(0, 2 * np.pi, 400)
rim_1 = np.cross(eye, [0.0, 0.0, 1.0])
rim_1 /= np.linalg.norm(rim_1)
rim = np.outer(np.cos(phi), rim_1) + np.outer(np.sin(phi), np.cross(eye, rim_1))
ax.plot(*rim.T, color="0.6", lw=1)  # the outline of the sphere
for angle in np.radians([25, 50, 68, 80, 86]):
    direction = np.array([np.cos(angle), 0.0, np.sin(angle)])  # L/|L| in the 1–3 plane
    omega0 = direction / moments
    t = np.linspace(0, tb.theory.flip_period(moments, omega0), 400)
    omega, _ = tb.theory.free_motion(body, omega0).at(t)
    momentum = omega * moments
    unit = momentum / np.linalg.norm(momentum, axis=1, keepdims=True)
    for sign in (1, -1):
        draw(ax, sign * unit, color="tab:blue", lw=1)
a, c = np.sqrt(1 / moments[0] - 1 / moments[1]), np.sqrt(1 / moments[1] - 1 / moments[2])
for sign in (1, -1):
    normal = np.array([a, 0.0, -sign * c]) / np.hypot(a, c)  # the plane of one great circle
    first, second = np.array([0.0, 1.0, 0.0]), np.cross(normal, [0.0, 1.0, 0.0])
    circle = np.outer(np.cos(phi), first) + np.outer(np.sin(phi), second)
    draw(ax, circle, color="k", linestyle="--", lw=1, label="separatrix" if sign > 0 else None)
polhode = tb.analysis.polhode(runs[1e-3])
track = polhode.angular_momentum_body / polhode.momentum_sphere
draw(ax, track, color="tab:orange", lw=2.5, label=r"simulated, $\varepsilon = 10^{-3}$")
for k in range(3):
    ax.quiver(0, 0, 0, *(1.3 * np.eye(3)[k]), color="k", arrow_length_ratio=0.08, lw=1)
    ax.text(*(1.38 * np.eye(3)[k]), f"$L_{k + 1}$")
ax.set_axis_off()
ax.set_box_aspect((1, 1, 1), zoom=1.3)
ax.view_init(elev=np.degrees(elevation), azim=np.degrees(azimuth))
ax.set_title("Polhodes of the block on the momentum sphere (L/|L|, principal axes)")
ax.legend(loc="upper left")

# %%
# The second Euler equation, checked
# ----------------------------------
#
# On the exact solution, with :math:`\dot\omega_2` from a central difference,
# the correct second equation leaves a residual of the size of the difference
# error; the variant with :math:`I_1` in place of :math:`I_2` does not hold.

omega0 = initial[1e-3]
step = 1e-5  # s
t = np.linspace(0.0, 2 * tb.theory.flip_period(body, omega0), 400)
motion = tb.theory.free_motion(body, omega0)
(before, _), (now, _), (after, _) = motion.at(t - step), motion.at(t), motion.at(t + step)
rate_2 = (after[:, 1] - before[:, 1]) / (2 * step)
i1, i2, i3 = moments
coupling = (i1 - i3) * now[:, 2] * now[:, 0]
scale = np.max(np.abs(i2 * rate_2))
residual = np.max(np.abs(i2 * rate_2 + coupling)) / scale
residual_slip = np.max(np.abs(i1 * rate_2 + coupling)) / scale
print(f"I₂ ω̇₂ + (I₁ − I₃) ω₃ ω₁: largest residual {residual:.1e} of max |I₂ ω̇₂|")
print(f"I₁ ω̇₂ + (I₁ − I₃) ω₃ ω₁: largest residual {residual_slip:.1e} of max |I₂ ω̇₂|")
# The central difference errs by h² ω'''/6 ~ (1e-5 s)² (25 rad/s)² ~ 1e-7 relative.
assert residual < 1e-6

# %%
# Where the formulas stop holding
# -------------------------------
#
# The period :math:`4K(k)/\lambda` is exact for a rigid body without torque,
# on either side of the separatrix; on the separatrix itself it is infinite
# (the motion approaches the intermediate axis forever). In practice the
# flip period of a real object near the intermediate axis is ill conditioned:
# it depends on :math:`\ln(1/\varepsilon)`, so a racket thrown more cleanly
# flips later, but only a little, and in a simulation errors in :math:`E` and
# :math:`L` of the size of :math:`\varepsilon^2` change it, as the run at
# :math:`\varepsilon = 10^{-6}` shows. The linear growth rate :math:`\gamma`
# describes only the start of a flip, while the perturbation is small. Any
# torque (air drag on a racket, gravity gradient on a satellite) or any
# flexibility breaks the conservation of :math:`E` and :math:`L` on which the
# solution rests; energy dissipation, in particular, drives a body to its
# axis of largest moment, the subject of the tutorial on wheels and dampers
# (:ref:`tutorials`).
