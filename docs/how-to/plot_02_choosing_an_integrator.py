"""
Choosing an integrator
======================

:func:`tumble.simulate` takes ``method=``: a closed form sampled at any times, four
splittings, classical Runge–Kutta or an adaptive Dormand–Prince method. This page
lists them, says which one ``"auto"`` picks, and measures them on a tumbling box
against its exact solution, on a heavy top over a long run and under a
non-conservative torque; the recommendation at the end follows from those numbers.
"""

# %%
# The methods
# -----------
#
# Every method is an entry of the integrator registry, ``tumble.integrators.INTEGRATORS``:
# its kind (``dt`` is a fixed step, a sampling interval, or the output interval
# of a method that chooses its own steps), its order (0 for a closed form) and
# what it keeps exactly or bounded.

import textwrap
import time

import matplotlib.pyplot as plt
import numpy as np
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.integrators import INTEGRATORS

for name, entry in INTEGRATORS.items():
    print(f"{name:16} {entry.kind:9} order {entry.order}")
    print(textwrap.indent(textwrap.fill(entry.preserves, 70), " " * 17))

# %%
# What "auto" picks
# -----------------
#
# ``method="auto"`` (the default) takes the exact solution when the body is
# torque-free or a symmetric top under uniform gravity, the fourth-order splitting
# when the torque is otherwise conservative (gravity about a pivot, a user torque
# with its potential energy), and the adaptive method otherwise.
# ``Trajectory.reason`` says which and why:

book = tb.shapes.box("1 kg", "30, 20, 10 cm")  # moments I_x < I_y < I_z
disk = tb.shapes.thin_disk("1 kg", "10 cm")
tilted = [np.cos(0.15), np.sin(0.15), 0.0, 0.0]  # 17° from the vertical about x
on_pivot = {"pivot": [0, 0, -0.05], "gravity": [0, 0, -9.81], "attitude0": tilted}
cases = {
    "free box": (book, {}),
    "disk on a pivot": (disk, on_pivot),
    "box on a pivot": (book, on_pivot),
    "box with damping": (book, {"torque": tb.torques.LinearDamping("1e-3 N*m*s")}),
}
for label, (body, extra) in cases.items():
    run = tb.simulate(body, [0.5, 1.0, 60.0], duration=0.1, dt=1e-3, **extra)
    print(f"{label:17} {run.method:10} {run.reason}")

# %%
# Accuracy and cost on a torque-free body
# ---------------------------------------
#
# The box is thrown spinning mostly about its intermediate axis y, so it flips over
# again and again (the tennis-racket motion). Its exact motion is known
# (Jacobi elliptic functions; Landau & Lifshitz, *Mechanics* §37):
# :func:`tumble.theory.free_motion` gives it at any times. Each method runs for
# 50 s at a few step sizes; the table gives the largest error in ω (relative to
# :math:`|\omega_0|`) and in the attitude (the angle of the rotation between the
# computed and the exact attitude), the largest relative drift of the energy
# :math:`E` and of :math:`|\mathbf L|`, and the median wall time of five runs.
# The adaptive method is set by its tolerance (``rtol``, with ``atol = rtol / 100``)
# instead of a step.

omega0 = np.array([1.0, 4.0, 1.0])  # rad/s, body axes
duration, every = 50.0, 0.1  # s; samples compared every 0.1 s
exact = tb.theory.free_motion(book, omega0)


def timed(**kwargs):
    """The trajectory of one run and the median wall time of five, s."""
    times = []
    for _ in range(5):
        start = time.perf_counter()
        run = tb.simulate(book, omega0, duration=duration, **kwargs)
        times.append(time.perf_counter() - start)
    return run, float(np.median(times))


def errors(run):
    """Largest relative ω error, largest attitude error (rad), E and |L| drift."""
    omega, quaternion = exact.at(run.t)
    d_omega = np.max(np.linalg.norm(run.omega - omega, axis=1)) / np.linalg.norm(omega0)
    wrong = Rotation.from_quat(quaternion, scalar_first=True).inv() * run.rotation
    momentum = np.linalg.norm(run.angular_momentum, axis=1)
    d_momentum = np.max(np.abs(momentum / momentum[0] - 1))
    return d_omega, np.max(wrong.magnitude()), run.drift["energy"], d_momentum


settings = [("exact", "dt", every)]
for method in ("splitting", "strang", "splitting-exact", "strang-exact", "rk4"):
    settings += [(method, "dt", dt) for dt in (0.05, 0.01, 0.002)]
settings += [("adaptive", "rtol", rtol) for rtol in (1e-6, 1e-9, 1e-12)]

print(f"{'method':16}{'setting':>13}{'steps':>7}{'ω error':>10}{'attitude':>10}"
      f"{'E drift':>10}{'|L| drift':>10}{'time ms':>9}")  # fmt: skip
free = {}
for method, knob, value in settings:
    if knob == "dt":
        run, seconds = timed(method=method, dt=value, record_every=max(1, round(every / value)))
    else:
        run, seconds = timed(method=method, dt=every, rtol=value, atol=value / 100)
    free[method, value] = errors(run)
    columns = "".join(f"{x:10.1e}" for x in free[method, value])
    print(f"{method:16}{knob + f' {value:g}':>13}{run.steps:7}{columns}{seconds * 1e3:9.2f}")

# %%
# What the table shows:
#
# * ``exact`` is the reference itself (the same closed form), so its errors are
#   zero; its drifts are round-off, and its cost depends on the number of samples,
#   not on the duration.
# * ``splitting-exact`` and ``strang-exact`` step the *exact* free motion, so with
#   no torque their error is round-off at any step: for a torque-free body they are
#   a more expensive ``exact``.
# * The splittings keep :math:`|\mathbf L|` to round-off at every step size (each
#   sub-step is an exact rotation), while RK4's :math:`|\mathbf L|` drifts with its
#   error. ``splitting`` and ``rk4`` are both fourth order — a step five times
#   shorter divides the error by about :math:`5^4 = 625` (printed below) — and of
#   similar accuracy at the same step; RK4 costs less per step (compare the times
#   at the shortest step). ``strang`` is second order.
# * The adaptive method reaches a given accuracy in fewer steps than RK4, each
#   step costing more (six evaluations of the equations to RK4's four).

for method in ("splitting", "rk4"):
    ratio = free[method, 0.01][0] / free[method, 0.002][0]
    print(f"{method}: error at dt 0.01 / error at dt 0.002 = {ratio:.0f}")
    # Fourth order: 625 in theory; > 200 leaves room for the higher-order terms.
    assert ratio > 200
# The exact free flow: only round-off accumulates, about 1e-14 a step over up to
# 25 000 steps.
assert max(free["splitting-exact", dt][0] for dt in (0.05, 0.01, 0.002)) < 1e-8
# Exact rotations keep |L| to round-off whatever the step.
assert max(free[m, 0.05][3] for m in ("splitting", "strang")) < 1e-12

# %%
# A long conservative run: a heavy top
# ------------------------------------
#
# On a pivot under gravity the asymmetric box has no closed form, and its energy
# is the quantity to watch over a long run. The same step, 2 ms, for 2000 s
# (a million steps), spinning at 30 rad/s about its axis of largest moment:
# RK4's energy error grows steadily with time, the symplectic splitting's stays
# bounded (Hairer, Lubich & Wanner, *Geometric Numerical Integration*, ch. IX).

top = {"duration": 2000.0, "dt": 2e-3, "record_every": 500, **on_pivot}
energy_error = {}
for method in ("rk4", "splitting"):
    start = time.perf_counter()
    run = tb.simulate(book, [0.0, 0.5, 30.0], method=method, **top)
    seconds = time.perf_counter() - start
    energy_error[method] = np.abs(run.relative_change("energy"))
    half = len(run.t) // 2
    first, second = energy_error[method][:half].max(), energy_error[method][half:].max()
    print(f"{method:10} largest |ΔE/E| in the first half {first:.1e}, "
          f"in the second half {second:.1e}; {seconds:.2f} s")  # fmt: skip
    if method == "rk4":
        # Secular growth: the second half's error is well above the first's.
        assert second > 1.5 * first
    else:
        # Bounded: the second half's error no larger than the first's (to 10 %).
        assert second < 1.1 * first

fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
for method, values in energy_error.items():
    ax.semilogy(run.t[1:], values[1:], label=method, lw=0.8)
ax.set_xlabel("time (s)")
ax.set_ylabel("relative energy error |ΔE / E|")
ax.legend()
ax.set_title("Box on a pivot under gravity, dt = 2 ms")
plt.show()

# %%
# Under a non-conservative torque
# -------------------------------
#
# A constant body torque (a thruster along z) and viscous damping: no energy or
# :math:`\mathbf L` to keep, and no closed form. The reference is the adaptive
# method at ``rtol = 1e-13``; the error is the largest in ω over 60 s, relative to
# :math:`|\omega_0|`.

forced = tb.torques.ConstantBodyTorque("0, 0, 2e-3 N*m") + tb.torques.LinearDamping("1e-3 N*m*s")
duration = 60.0
reference = tb.simulate(
    book, omega0, duration=duration, dt=every, torque=forced, rtol=1e-13, atol=1e-15
)
print(f"{'method':10}{'setting':>12}{'steps':>7}{'ω error':>10}{'time ms':>9}")
forced_error = {}
for method, knob, value in (
    [("rk4", "dt", dt) for dt in (0.05, 0.01, 0.002)]
    + [("splitting", "dt", dt) for dt in (0.05, 0.01, 0.002)]
    + [("adaptive", "rtol", rtol) for rtol in (1e-6, 1e-9, 1e-12)]
):
    if knob == "dt":
        kwargs = {"dt": value, "record_every": round(every / value)}
    else:
        kwargs = {"dt": every, "rtol": value, "atol": value / 100}
    run, seconds = timed(method=method, torque=forced, **kwargs)
    error = np.max(np.linalg.norm(run.omega - reference.omega, axis=1)) / np.linalg.norm(omega0)
    forced_error[method, value] = error
    print(f"{method:10}{knob + f' {value:g}':>12}{run.steps:7}{error:10.1e}{seconds * 1e3:9.2f}")

# %%
# Here RK4 is more accurate than the splitting at the same step, and cheaper; the
# adaptive method reaches the same accuracy in fewer steps.

# At equal steps RK4 is at least as accurate as the splitting under this torque.
assert all(forced_error["rk4", dt] <= forced_error["splitting", dt] for dt in (0.05, 0.01, 0.002))

# %%
# Which one to use
# ----------------
#
# From the tables above and the registry:
#
# * **Torque-free, or a symmetric top under uniform gravity: ``exact``** (what
#   ``auto`` picks). No stepping error, and a cost set by the number of samples,
#   not by the duration.
# * **Long runs under a conservative torque (gravity about a pivot):
#   ``splitting``** (``auto``'s choice). Its energy error stays bounded where
#   RK4's grows, and :math:`|\mathbf L|` or its conserved components are kept to
#   round-off. ``strang`` is its cheaper second-order variant, for when the
#   energy's bound matters more than the error in the motion.
# * **Weak torques on a fast, asymmetric rotation: ``splitting-exact``.** Its free
#   flow is exact, so the step only has to resolve the torque, not the rotation.
# * **Any other torque: ``adaptive``** (``auto``'s choice) for an accuracy set by
#   ``rtol``, or **``rk4``** for a fixed, predictable cost, the cheapest per step.
#   Neither conserves anything exactly, but under a non-conservative torque there
#   is nothing to conserve.
#
# The timings here are those of runs of 50 or 60 s on the machine that built this page,
# where the fixed cost of a call (a fraction of a millisecond) is part of each.
# :doc:`/explanation/performance` gives the measured accuracy and cost of each
# method on longer runs, and against other libraries.
