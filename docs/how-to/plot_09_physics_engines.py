"""
How physics engines integrate a tumbling body
=============================================

Most rotating bodies are simulated inside a general physics engine, and the
engine does not say how wrong the rotation is. :mod:`tumble.conformance` runs
MuJoCo, PyBullet, Drake, DART and Rapier (and scipy's ``solve_ivp`` at its
default tolerances, and tumble's own integrators) on bodies whose exact motion
tumble knows in closed form, and measures each against it: the drift of the
energy and of the angular momentum, the error of the attitude and of ω, the
number of flips, and when the engine failed. This page runs the engines that
the machine building it has, explains what each behaviour means for the body,
and gives the setting that fixes it.

The engines are an optional extra: ``pip install 'tumble[engines]'``. In a
shell:

.. code-block:: console

   $ tumble conform --list                                  # every engine/variant, installed?
   $ tumble conform --scenario intermediate-fast --dt 1e-3  # every installed engine, 20 s
   $ tumble conform --engines mujoco,tumble/rk4 --scenario intermediate-slow \\
         --dt 0.02,0.01,0.005,0.0025 --duration 5 -o engines/  # a dt sweep, with an HTML report
   $ tumble conform --inertia 1,2,3 --omega 0.1,20,0.1 --duration 10 --json   # your own body
"""

# %%
# The engines and the scenarios
# -----------------------------
#
# Each engine is an adapter in a registry, named ``engine/variant``. An adapter
# builds one free rigid body from the mass properties given (no collision
# geometry, gravity off), reads back the mass and inertia the engine really uses
# (and refuses to run when they differ), sets the attitude and ω, steps at a
# fixed ``dt`` and reads the state back. An engine that is not installed here is
# skipped, with the reason in the result's ``skipped``.

import math
import time
from typing import ClassVar

import matplotlib.pyplot as plt
import numpy as np

import tumble as tb
from tumble.conformance import ENGINES, Engine, EngineBody, Scenario, register_engine

t_start = time.perf_counter()
for name in tb.conformance.engine_names():
    cls = ENGINES[name.split("/")[0]]
    missing = tb.conformance.unavailable(name, tb.conformance.SCENARIOS["major-spin"])
    state = "not installed" if missing else f"{cls.precision}, ω in {cls.omega_frame} axes"
    print(f"{name:26} {state}")

# %%
# The scenarios are bodies whose motion tumble computes exactly — Jacobi's
# elliptic functions for a torque-free body, the Lagrange top's closed form on a
# pivot (:func:`tumble.theory.free_motion`, :func:`tumble.theory.gyroscope`) —
# never by integrating:

for scenario in tb.conformance.SCENARIOS.values():
    print(f"{scenario.name:18} {scenario.description}")

# %%
# A fast tumble, every engine
# ---------------------------
#
# The body has principal moments (1, 2, 3) kg·m² and spins at 20 rad/s near its
# intermediate axis, so it flips over again and again (the tennis-racket
# motion): 18 times in 20 s. No gravity, no damping, ``dt = 1e-3`` s, which is
# 0.02 rad of rotation per step. :func:`tumble.conformance.run` returns one row
# per engine; the drifts are relative and signed, ``(x(t) − x(0)) / x(0)``, and
# "max" is the value of largest magnitude over the run.

COLUMNS = {
    "engine": "engine",
    "energy_drift_max": "energy",
    "momentum_drift_max": "|L|",
    "attitude_error_max": "attitude",
    "omega_error_max": "ω error",
    "flips": "flips",
    "flips_exact": "exact",
    "failed_at": "failed at",
    "steps_per_second": "steps/s",
}


def show(result, columns=COLUMNS):
    """Print a result's table (3 significant digits), then what was skipped."""
    table = result.table[list(columns)].rename(columns=columns)
    print(table.to_string(index=False, float_format=lambda x: f"{x:.3g}"))
    for name, reason in result.skipped.items():
        print(f"skipped {name}: {reason}")


def row(result, name):
    """The row of one engine as a dict (None when it was skipped or not asked for)."""
    rows = result.table[result.table["engine"] == name]
    return None if rows.empty else rows.iloc[0].to_dict()


fast = tb.conformance.run(None, "intermediate-fast", dt=1e-3, duration=20.0)
show(fast)

# %%
# What the adapters changed, so that each engine integrates the body and nothing
# else (the result's ``notes``):

for name, notes in fast.notes.items():
    for note in notes:
        print(f"{name:26} {note}")

# %%
# The energy of the main behaviours over the run, and the intermediate-axis
# component of ω (its sign changes are the flips) beside the exact one:

moments = fast.scenario.moments


def relative_energy(one):
    """The relative energy change at each sample of a run."""
    energy = 0.5 * np.sum(moments * one.samples.omega**2, axis=1)
    return energy / energy[0] - 1.0


runs = {one.engine: one for one in fast.runs}
shown = ["mujoco/euler", "mujoco/implicit", "pybullet", "drake/continuous", "rapier", "tumble/rk4"]
fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 6), layout="constrained", sharex=True)
for name in (name for name in shown if name in runs):
    top.plot(runs[name].samples.t, relative_energy(runs[name]), label=name, lw=1)
top.set_ylabel("relative energy change")
top.legend(fontsize="small", ncols=2)
top.set_title("intermediate-fast, dt = 1 ms")
exact_omega, _ = fast.scenario.reference(fast.runs[0].samples.t)
bottom.plot(fast.runs[0].samples.t, exact_omega[:, 1], "k", lw=2, label="exact")
for name in ("drake/continuous", "rapier"):
    if name in runs:
        bottom.plot(runs[name].samples.t, runs[name].samples.omega[:, 1], lw=0.8, label=name)
bottom.set_xlabel("time (s)")
bottom.set_ylabel("ω$_y$ (rad/s)")
bottom.legend(fontsize="small")
plt.show()

# %%
# What each behaviour means
# -------------------------
#
# **Semi-implicit Euler gains energy.** MuJoCo's default ``Euler``, PyBullet's
# default multibody (here undamped), Drake's discrete plant and DART's default
# step all advance the velocity first, with the gyroscopic torque
# :math:`\omega \times I\omega` of the *old* ω, then the attitude with the new ω.
# For a free body that velocity step is explicit Euler on Euler's equations,
# :math:`\omega_{n+1} = \omega_n + h\,\dot\omega_n`. The rate :math:`\dot\omega`
# is tangent to the energy ellipsoid (:math:`\omega \cdot I\dot\omega = 0`), and
# a straight step along a tangent leaves the ellipsoid outwards: every step adds
# exactly :math:`\tfrac12 h^2\,\dot\omega \cdot I\dot\omega` to the energy, and
# :math:`|\mathbf L|` grows the same way. The four engines take the same step, so
# their rows agree to every digit printed: about +59 % of energy in 20 s here.
# Physically the body speeds up with nothing driving it; the flips still happen,
# but the attitude is soon anywhere (an attitude error near π rad).

euler_like = ["mujoco/euler", "pybullet/undamped", "drake/discrete", "dart"]
for name in (name for name in euler_like if row(fast, name)):
    print(f"{name:18} energy {row(fast, name)['energy_drift_max']:+.6f}")
gains = [row(fast, name)["energy_drift_max"] for name in euler_like if row(fast, name)]
# The same explicit velocity step in float64: the same gain to well below the digits printed.
assert max(gains, default=0.0) - min(gains, default=0.0) < 1e-6
assert all(gain > 0.3 for gain in gains)

# %%
# **Implicit schemes lose energy.** MuJoCo's ``implicit`` and ``implicitfast``
# (on a free body; on a ball joint ``implicitfast`` steps as ``Euler`` does, see
# the heavy top below) and PyBullet's maximal-coordinates rigid body evaluate the
# gyroscopic term at the *new* ω, which removes (to leading order) the same
# :math:`\tfrac12 h^2` term instead of adding it: about −31 % here. The loss
# acts like a damping nobody put in; it damps the nutation about *either* stable
# axis (measured further down), where real internal dissipation would turn a
# body spinning about its minor axis over to its major axis (Explorer 1).

implicit = ["mujoco/implicit", "mujoco/implicitfast", "pybullet/maximal"]
for name in (name for name in implicit if row(fast, name)):
    print(f"{name:18} energy {row(fast, name)['energy_drift_max']:+.6f}")
assert all(row(fast, name)["energy_drift_max"] < -0.2 for name in implicit if row(fast, name))

# %%
# **PyBullet's default damping removes almost all of it.** A PyBullet body is
# created with ``linearDamping`` and ``angularDamping`` 0.04, applied to the
# base as the torque :math:`-I\omega\,(0.04 + 0.04\,|\omega|)` every step. At
# 20 rad/s that is a decay rate of 0.84 /s: the body has lost 99.9 % of its
# energy after 20 s, and flips 3 times instead of 18. The model says how fast:
# on each component :math:`d|\omega|/dt = -0.04\,|\omega|\,(1 + |\omega|)`, whose
# solution has :math:`|\omega| / (1 + |\omega|)` decaying as :math:`e^{-0.04 t}`.

if "pybullet" in runs:
    u = 20.0 / 21.0 * math.exp(-0.04 * 20.0)
    final = np.linalg.norm(runs["pybullet"].samples.omega[-1])
    damped = row(fast, "pybullet")
    print(
        f"energy {damped['energy_drift_final']:+.4f}, "
        f"flips {damped['flips']} (exact {damped['flips_exact']})"
    )
    print(f"|ω| after 20 s: {final:.3f} rad/s measured, {u / (1 - u):.3f} rad/s from the model")
    assert abs(final - u / (1 - u)) < 0.05 * final  # the model, to 5 % (ω0 is not on one axis)

# %%
# **Drake's default integrator miscounts the flips.** Drake's continuous plant
# is stepped by an error-controlled third-order Runge–Kutta at accuracy 1e-4.
# It keeps the energy to a few parts in 10⁴, but near the intermediate axis the
# time between flips depends on the energy (logarithmically, near the
# separatrix), so a small error in it moves every flip: it counts about half as
# many flips again as the exact motion has, and ω ends pointing the other way
# (an ω error of 2, relative to :math:`|\omega_0|`).

if row(fast, "drake/continuous"):
    drake_row = row(fast, "drake/continuous")
    print(
        f"energy {drake_row['energy_drift_max']:+.2e}, flips {drake_row['flips']} "
        f"(exact {drake_row['flips_exact']}), "
        f"ω error {drake_row['omega_error_max']:.2f}"
    )
    assert drake_row["flips"] > drake_row["flips_exact"]

# %%
# **Rapier drifts with the number of steps.** Rapier computes in float32 and
# turns ω into body axes and back in each of its four substeps; each turn adds a
# fixed fraction of an ulp to :math:`|\omega|`. That gain per step does not depend on
# ``dt``, so a smaller step, which takes more steps, gains *more* (measured
# below). At 1 ms it gains about 1.5 % of energy in 20 s, and its flips drift as
# Drake's do.

if row(fast, "rapier"):
    rapier_row = row(fast, "rapier")
    print(
        f"energy {rapier_row['energy_drift_max']:+.2e}, flips {rapier_row['flips']} "
        f"(exact {rapier_row['flips_exact']})"
    )

# %%
# The stable spins under Euler and under an implicit step: the tilt of
# :math:`\mathbf L` from the spin axis after 20 s (in body axes), against the
# exact motion's, which stays at its initial tilt. Euler tilts both spins away
# from their axes; the implicit step pulls both onto them.

for scenario, axis in (("minor-spin", 0), ("major-spin", 2)):
    spins = tb.conformance.run(["mujoco/euler", "mujoco/implicit"], scenario, dt=1e-3)
    for one in spins.runs:
        momentum = one.samples.omega * moments
        tilt = np.degrees(np.arccos(np.abs(momentum[:, axis]) / np.linalg.norm(momentum, axis=1)))
        print(f"{scenario:11} {one.engine:16} tilt {tilt[0]:.3f}° → {tilt[-1]:.3f}°")

# %%
# Rapier at four steps over 5 s: the energy it gains grows as the step shrinks,
# by a nearly constant amount per step.

rapier = tb.conformance.sweep(["rapier"], "intermediate-fast", [4e-3, 2e-3, 1e-3, 5e-4], 5.0)
for one in rapier.table.itertuples():
    steps = round(5.0 / one.dt)
    print(
        f"dt {one.dt:.4f} s: energy {one.energy_drift_final:+.2e}, "
        f"{one.energy_drift_final / steps:.2e} per step"
    )
if not rapier.table.empty:
    assert rapier.table["energy_drift_final"].is_monotonic_increasing  # dts are decreasing

# %%
# Rapier also puts a slow body to sleep: once its rates stay below its
# thresholds for 0.5 s, it stops it dead. The plain ``rapier`` variant turns
# sleeping off; ``rapier/sleeping`` keeps Rapier's defaults and reports the
# sleep as a failure. A body tumbling at 0.3 rad/s:

slow = Scenario((1.0, 2.0, 3.0), (0.01, 0.3, 0.01), 5.0, name="slow tumble")
sleeping = tb.conformance.run(["rapier", "rapier/sleeping"], slow)
show(sleeping, {**COLUMNS, "failure": "failure"})

# %%
# A stable spin that blows up
# ---------------------------
#
# A spin of 20 rad/s about the major axis is stable: the exact motion nutates
# within 0.2° of the axis for ever. The energy that semi-implicit Euler adds
# tilts the spin away from its axis, and the tilt grows exponentially (a
# straight line on the log axis of the figure below): the spin about the major
# axis, stable for the exact motion, is unstable for the scheme. Once the body
# tumbles fast enough the step itself is unstable and the state explodes. 45 s
# at ``dt = 1e-3`` s:

blowup_engines = ["mujoco/euler", "dart", "drake/discrete", "pybullet/undamped", "mujoco/rk4"]
blowup = tb.conformance.run(blowup_engines, "major-spin", dt=1e-3, duration=45.0)
show(blowup, {"engine": "engine", "energy_drift_max": "energy", "failed_at": "failed at"})
for one in blowup.table.itertuples():
    print(f"{one.engine:18} {one.failure or 'did not fail'}")

# %%
# How the Euler spin got there: the tilt of :math:`\mathbf L` from the major
# axis, and when it crosses the separatrix (where :math:`|\mathbf L|^2 / 2E`
# falls to the intermediate moment, 2 kg·m²) and starts to tumble:

fig, (upper, lower) = plt.subplots(2, 1, figsize=(7, 5.5), layout="constrained", sharex=True)
for one in blowup.runs:
    t = one.samples.t
    momentum = one.samples.omega * moments
    size = np.linalg.norm(momentum, axis=1)
    tilt = np.degrees(np.arccos(np.abs(momentum[:, 2]) / size))
    (line,) = upper.semilogy(t, tilt, label=one.engine, lw=1)
    lower.semilogy(t, np.linalg.norm(one.samples.omega, axis=1), color=line.get_color(), lw=1)
    if not math.isnan(one.row["failed_at"]):
        lower.plot(t[-1], np.linalg.norm(one.samples.omega[-1]), "x", color=line.get_color())
    if one.engine in ("mujoco/euler", "dart"):
        marks = ", ".join(f"{tilt[np.searchsorted(t, s)]:.1f}° at {s:g} s" for s in (5, 10, 20, 25))
        effective = size**2 / np.sum(momentum * one.samples.omega, axis=1)
        tumbling = t[np.argmax(effective < 2.0)] if effective.min() < 2.0 else math.nan
        print(
            f"{one.engine}: tilt {marks}; past 45° at {t[np.argmax(tilt > 45)]:.1f} s; "
            f"tumbling from {tumbling:.1f} s; "
            f"failed at {one.row['failed_at']:.2f} s"
        )
upper.set_ylabel("tilt of L from the\nmajor axis (degrees)")
upper.set_title("major-spin, dt = 1 ms (the semi-implicit Euler engines' lines coincide)")
upper.legend(fontsize="small")
lower.set_xlabel("time (s)")
lower.set_ylabel("|ω| (rad/s); × failed")
plt.show()

for name in ("mujoco/euler", "dart", "drake/discrete", "pybullet/undamped"):
    if row(blowup, name):
        assert 30.0 < row(blowup, name)["failed_at"] < 40.0
if row(blowup, "mujoco/rk4"):
    assert math.isnan(row(blowup, "mujoco/rk4")["failed_at"])

# %%
# The engines fail differently, and the suite reports each in ``failed_at`` and
# ``failure``. MuJoCo warns ``mjWARN_BADQACC`` and resets the body to the
# model's reference pose at rest, and a simulation that does not read its
# warnings simply goes on. DART raises nothing: its :math:`|\omega|` climbs from
# 10³ rad/s to beyond 10¹⁰⁰ within about 65 ms, then its state turns non-finite,
# with warnings on the console only. Drake's discrete plant goes non-finite
# silently. PyBullet's steps turn the body by more than π/4 rad before it fails,
# where Bullet caps the angle of the attitude update and the rotation is no
# longer the one ω gives. MuJoCo's RK4 keeps the spin to round-off.
#
# Convergence and the largest safe step
# -------------------------------------
#
# :func:`tumble.conformance.sweep` runs each engine at several steps and adds
# its observed order of convergence (the slope of the ω error against dt on
# log-log axes) and its largest safe step: the largest dt of the sweep at which,
# and at every smaller one, the energy and attitude errors stay within a
# tolerance (1e-6 by default). A slow tumble (2 rad/s) over 5 s:

dts = [0.02, 0.01, 0.005, 0.0025]
order = tb.conformance.sweep(
    ["mujoco/euler", "mujoco/rk4", "tumble/rk4"], "intermediate-slow", dts, 5.0
)
show(order, {**COLUMNS, "dt": "dt", "order": "order", "safe_dt": "safe dt"})

fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
for name, group in order.table.groupby("engine", sort=False):
    slope = group["order"].iloc[0]
    ax.loglog(group["dt"], group["omega_error_max"], "o-", label=f"{name} (order {slope:.2f})")
    # The slope of the observed order, drawn a factor 5 below the errors.
    ax.loglog(
        group["dt"],
        group["omega_error_max"].iloc[-1] / 5 * (group["dt"] / dts[-1]) ** slope,
        ":",
        color="grey",
    )
ax.set_xlabel("dt (s)")
ax.set_ylabel("largest ω error / |ω₀|")
ax.set_title("intermediate-slow, 5 s (dotted: the observed slopes)")
ax.legend(fontsize="small")
plt.show()

for name, expected, spread in (("mujoco/rk4", 4.0, 0.3), ("mujoco/euler", 1.0, 0.2)):
    if row(order, name):
        assert abs(row(order, name)["order"] - expected) < spread

# %%
# RK4 is fourth order and, for this body at this spin, keeps the energy and the
# attitude to 1e-6 at every step of the sweep, up to 20 ms; Euler is first order
# and keeps them at none. Its errors shrink in proportion to dt, so the step it
# would need follows from its smallest step's errors:

euler = order.table[order.table["engine"] == "mujoco/euler"]
if not euler.empty:
    last = euler.iloc[-1]
    needed = last["dt"] * 1e-6 / max(abs(last["energy_drift_max"]), last["attitude_error_max"])
    print(f"mujoco/euler: dt ≈ {needed:.1e} s to keep both within 1e-6 over 5 s")
    assert math.isnan(last["safe_dt"])
if row(order, "mujoco/rk4"):
    assert row(order, "mujoco/rk4")["safe_dt"] == max(dts)

# %%
# The same holds for every engine whose row in the first table matches MuJoCo's
# Euler.
#
# A body on a pivot
# -----------------
#
# The heavy top (the Lagrange top: a symmetric body on a pivot under gravity) has
# an exact solution too. Each engine builds the pivot its own way (the adapter's
# ``pivot_method``):

for cls in ENGINES.values():
    held = cls.pivot_method if cls.holds_pivot else "cannot hold a pivot"
    print(f"{cls.name:9} {held}")

# %%
# Five seconds at ``dt = 1e-3`` s; the energy now includes gravity's, and the
# momentum is the vertical component of :math:`\mathbf L` about the pivot (the
# one that is conserved), relative to :math:`|\mathbf L(0)|`:

heavy = tb.conformance.run(None, "heavy-top", dt=1e-3, duration=5.0)
show(heavy)

# %%
# PyBullet's default damping again takes most of the energy. On a pivot the
# "flips" count the sign changes of ω's y component as the top nutates: the
# semi-implicit Euler engines lose the phase of the nutation (fewer sign changes
# than the exact count; Drake's discrete plant fewest), while RK4 and Drake's
# continuous plant keep it. The joint adds its own error: PyBullet's
# maximal-coordinates body is held by a point-to-point constraint that its
# solver keeps to about 1e-5 m (the adapter's note):

for name, notes in heavy.notes.items():
    for note in notes:
        if "pivot" in note or "joint" in note:
            print(f"{name:26} {note}")
#
# The settings that fix each
# --------------------------
#
# * **MuJoCo:** ``<option integrator="RK4"/>`` in the model (or
#   ``model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4``), the row
#   ``mujoco/rk4`` above. ``implicit``/``implicitfast`` are for stiff damping
#   and contacts, not for free rotation. Read ``data.warning`` after stepping:
#   a nonzero ``mjWARN_BADQACC`` count means the state was reset.
# * **PyBullet:** ``p.changeDynamics(body, -1, linearDamping=0,
#   angularDamping=0)`` turns the damping off (``pybullet/undamped``), and a
#   multibody's ``maxJointVelocity`` (100 rad/s by default) should be raised
#   for a fast spin. Neither changes the scheme: the undamped multibody gains
#   energy exactly as MuJoCo's Euler does, and only a smaller step, with an
#   error proportional to it, reduces that.
# * **Drake:** the continuous plant's integrator accuracy,
#   ``simulator.get_mutable_integrator().set_target_accuracy(1e-8)`` (measured
#   below), or a smaller maximum step (``set_maximum_step_size``); another
#   scheme with ``ResetIntegratorFromFlags(simulator, "runge_kutta5", max_step)``.
#   The discrete plant is semi-implicit Euler: only a smaller ``time_step``.
# * **DART:** semi-implicit Euler too: only a smaller ``World.setTimeStep``.
# * **Rapier:** ``RigidBody.dynamic().can_sleep(False)`` keeps a slow body
#   moving, and ``allow_fast_rotation(True)`` lifts its π/4 cap on a step's
#   rotation. Its float32 drift grows with the number of steps: only a larger
#   step (where its truncation error allows) or a float64 build of Rapier (the
#   Rust crate ``rapier3d-f64``) reduces it.
#
# Your own engine
# ---------------
#
# An engine is a subclass of :class:`tumble.conformance.Engine` registered with
# :func:`tumble.conformance.register_engine`. It names itself and its variants,
# the Python modules it needs (missing ones skip it), and the axes in which it
# stores ω; it builds the body from an :class:`tumble.conformance.EngineBody`
# (mass, principal moments, optionally a pivot and gravity), reads back the mass
# and inertia, sets the state, steps and reads the state. ``failure`` (a warning
# or reset of the engine) and ``close`` are optional; an engine that integrates a
# whole run at once overrides ``simulate`` instead.
#
# This one writes semi-implicit Euler by hand in numpy, in body axes: ω first,
# with the old ω's gyroscopic torque, then the attitude with the new ω.


@register_engine
class SemiImplicitEuler(Engine):
    """Semi-implicit Euler on Euler's equations, in numpy: velocities, then the attitude."""

    name = "by-hand"
    variants: ClassVar[dict[str, str]] = {"": "semi-implicit Euler in numpy"}
    modules = ("numpy",)
    omega_frame = "body"

    def build(self, body: EngineBody, dt: float) -> None:
        self.mass, self.moments, self.dt = body.mass, np.asarray(body.moments), dt

    def inertia(self) -> tuple[float, np.ndarray]:
        return self.mass, np.diag(self.moments)

    def set_state(self, quaternion: np.ndarray, omega: np.ndarray) -> None:
        self.q, self.w = np.array(quaternion, dtype=float), np.array(omega, dtype=float)

    def step(self, count: int) -> None:
        moments, dt = self.moments, self.dt
        for _ in range(count):
            self.w = self.w + dt * np.cross(moments * self.w, self.w) / moments
            half = 0.5 * dt * self.w  # the turn of this step, as a unit quaternion's vector part
            angle = np.linalg.norm(half)
            turn = np.concatenate([[np.cos(angle)], np.sinc(angle / np.pi) * half])
            w0, v0, w1, v1 = self.q[0], self.q[1:], turn[0], turn[1:]
            self.q = np.concatenate([[w0 * w1 - v0 @ v1], w0 * v1 + w1 * v0 + np.cross(v0, v1)])

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        return self.q, self.w


# %%
# It runs like any other engine, and reproduces MuJoCo's Euler, PyBullet's
# undamped multibody, Drake's discrete plant and DART:

mine = tb.conformance.run(["by-hand", "mujoco/euler"], "intermediate-fast", dt=1e-3)
show(mine)
if row(mine, "mujoco/euler"):
    # The same scheme in float64: equal up to round-off accumulated over 20 000 steps.
    assert (
        abs(
            row(mine, "by-hand")["energy_drift_max"] - row(mine, "mujoco/euler")["energy_drift_max"]
        )
        < 1e-6
    )

# %%
# A subclass of a built-in adapter adds a variant with other settings: here
# Drake's continuous plant at a tighter integrator accuracy.

from tumble.conformance.engines.drake_engine import DrakeEngine  # noqa: E402


@register_engine
class AccurateDrake(DrakeEngine):
    """Drake's continuous plant with the integrator's target accuracy set."""

    name = "drake-accuracy"
    variants: ClassVar[dict[str, str]] = {
        "1e-6": "continuous plant, set_target_accuracy(1e-6)",
        "1e-8": "continuous plant, set_target_accuracy(1e-8)",
    }

    def build(self, body: EngineBody, dt: float) -> None:
        super().build(body, dt)  # any variant but "discrete" builds the continuous plant
        self.simulator.get_mutable_integrator().set_target_accuracy(float(self.variant))


drake = tb.conformance.run(["drake/continuous", "drake-accuracy/*"], "intermediate-fast", dt=1e-3)
show(drake)
if row(drake, "drake-accuracy/1e-8"):
    assert (
        row(drake, "drake-accuracy/1e-8")["flips"]
        == row(drake, "drake-accuracy/1e-8")["flips_exact"]
    )

# %%
# A tighter accuracy costs more of the integrator's own steps (``steps/s`` is the
# 20 s horizon counted in steps of 1 ms, per second of wall time); at 1e-8 the
# flips are all there and the attitude is right to a fraction of a radian after
# 20 s.
#
# The two examples stay in the registry for the rest of the session; a script
# that is done with them removes them:

for name in ("by-hand", "drake-accuracy"):
    del ENGINES[name]

# %%
# Your own body
# -------------
#
# :class:`tumble.conformance.Scenario` takes any body: its inertia (principal
# moments or a full tensor, with units if wanted), its ω, the horizon, and
# optionally an attitude, a mass, and a pivot with gravity (a symmetric top with
# the pivot on its axis, whose motion is exact). A book thrown about its
# intermediate axis, as in :doc:`/auto_how-to/plot_02_choosing_an_integrator`:

book = tb.shapes.box("1 kg", "30, 20, 10 cm")
thrown = Scenario(book.inertia, "0.05, 6, 0.05 rad/s", "10 s", mass=book.mass, name="book")
show(tb.conformance.run(["mujoco/euler", "mujoco/rk4", "tumble/rk4"], thrown, dt=1e-3))

print(f"\nthe whole page ran in {time.perf_counter() - t_start:.0f} s")
