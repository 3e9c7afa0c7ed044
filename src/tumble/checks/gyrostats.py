"""Bodies carrying rotors and dampers: the dual-spin body and the energy sink."""

from __future__ import annotations

import contextlib
import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble import analysis, theory
from tumble.checks.base import Case, Comparison, Curve, Panel, TheoryCheck, comparison_row
from tumble.errors import InputError

if TYPE_CHECKING:
    from tumble.trajectory import Trajectory

__all__ = ["DualSpinCheck", "EnergySinkCheck", "spin_axis"]

Array = NDArray[np.float64]

#: A body counts as spun about an axis when ω0 is within this angle of it, rad.
SPIN_CONE = 0.3
#: The tilt of an asymmetric body's axis swings (twice per nutation): with this
#: many peaks or more the nutation's rate is fitted to them, not to every sample.
MANY_SWINGS = 10


def spin_axis(case: Case, candidates: Array | None = None) -> tuple[Array, float] | None:
    """The principal axis (body coordinates, unit, signed like ω0) the body is spun
    about, and the spin rate along it; None when ω0 is not within ``SPIN_CONE``
    of one (of ``candidates``, columns, if given)."""
    speed = float(np.linalg.norm(case.omega0))
    if speed == 0:
        return None
    axes = case.mass_properties.principal()[1] if candidates is None else candidates
    cosines = axes.T @ case.omega0 / speed
    k = int(np.argmax(np.abs(cosines)))
    if abs(cosines[k]) < math.cos(SPIN_CONE):
        return None
    axis = axes[:, k] * math.copysign(1.0, cosines[k])
    return axis, float(case.omega0 @ axis)


def _tilt(trajectory: Trajectory, axis: Array) -> Array:
    """The angle (rad) between a body axis and the initial L, in space."""
    momentum = trajectory.angular_momentum[0]
    directions = trajectory.rotation.apply(axis)
    cross = np.linalg.norm(np.cross(directions, momentum), axis=1)
    return np.asarray(np.arctan2(cross, directions @ momentum))


class DualSpinCheck(TheoryCheck):
    """A free body whose rotors lie along the principal axis it spins about:
    whether the rotors make the spin stable, its nutation, and the same body
    without them (:func:`tumble.theory.gyrostat_stability`)."""

    name = "dual-spin"
    needs = "a free body spun about a principal axis, its rotors along that axis and no damper"
    result_type = theory.GyrostatStability

    def _axis(self, case: Case) -> tuple[Array, float, float] | None:
        rotors = case.parts_for(self.name)
        if not rotors or len(rotors) != len(case.internal) or not case.free:
            return None
        spun = spin_axis(case)
        if spun is None:
            return None
        axis, rate = spun
        if any(abs(float(rotor.axis @ axis)) < 1 - 1e-9 for rotor in rotors):
            return None
        momentum = sum(rotor.inertia * rotor.speed * float(rotor.axis @ axis) for rotor in rotors)
        return axis, rate, float(momentum)

    def fits(self, case: Case) -> bool:
        return self._axis(case) is not None

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        """The nutation frequency (stable) or the growth rate of the transverse ω
        (unstable, over its linear stage) against ``result``; ``options``: ``axis``,
        the spin axis (body coordinates, default z)."""
        axis = np.asarray(options.get("axis", (0.0, 0.0, 1.0)), dtype=float)
        axis = axis / np.linalg.norm(axis)
        transverse = trajectory.omega - np.outer(trajectory.omega @ axis, axis)
        if result.stable:
            helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
            across = np.cross(axis, helper)
            measured = analysis.oscillation_frequency(trajectory.t, transverse @ across)
            return [
                comparison_row("nutation frequency", result.nutation_frequency, measured, "rad/s")
            ]
        # The growing mode alone (ten times the start: the decaying one has died
        # away), still linear (below 5 % of the spin: corrections ~0.25 %).
        size = np.linalg.norm(transverse, axis=1)
        band = (10.0 * float(size[0]), 0.05 * abs(result.spin_rate))
        measured = analysis.exponential_rate(trajectory.t, size, band)
        return [comparison_row("growth rate of the wobble", result.growth_rate, measured, "1/s")]

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        from tumble.simulation import simulate

        found = self._axis(case)
        if found is None:
            raise InputError(f"Expected {self.needs}, got another setup.")
        axis, rate, momentum = found
        mp = case.mass_properties
        held = theory.gyrostat_stability(mp, rate, momentum, axis)
        alone = theory.gyrostat_stability(mp, rate, 0.0, axis)
        # The same body with its rotors locked: torque-free, so the exact solution,
        # sampled like the run.
        duration = float(trajectory.t[-1])
        locked = simulate(
            mp,
            case.omega0,
            attitude0=case.attitude0,
            duration=duration,
            dt=duration / max(len(trajectory.t) - 1, 1),
            method="auto",
        )
        rows = [
            dict(row, quantity=f"{row['quantity']} with the rotors")
            for row in self.rows(trajectory, held, axis=axis)
        ]
        with contextlib.suppress(InputError):  # too small a wobble, or too short a run
            rows += [
                dict(row, quantity=f"{row['quantity']} without them", run="without-rotors")
                for row in self.rows(locked, alone, axis=axis)
            ]
        t = trajectory.t
        with_rotors = np.degrees(_tilt(trajectory, axis))
        without = np.degrees(_tilt(locked, axis))
        curves = [
            Curve(f"with the rotors (h = {momentum:.4g} kg·m²/s)", t, with_rotors),
            Curve("without them", locked.t, without),
        ]
        if not alone.stable and without[0] > 0:
            grown = without[0] * np.exp(alone.growth_rate * locked.t)
            early = grown < 30.0
            curves.append(
                Curve("theory: linear growth ∝ exp(γ t)", locked.t[early], grown[early], "theory")
            )
        panel = Panel(
            f"Spin about a principal axis ({'stable' if held.stable else 'unstable'} with the "
            f"rotors, {'stable' if alone.stable else 'unstable'} without): its angle from L",
            "angle (deg)",
            curves,
            name="dual-spin",
        )
        return Comparison(rows, [panel], {"without-rotors": locked})


class EnergySinkCheck(TheoryCheck):
    """A free body spun about a principal axis with a Kane damper: the nutation's
    exponential growth or decay while it is small
    (:func:`tumble.theory.kane_damper_decay`), and the end, a pure spin about
    the major axis with E = |H|² / (2 I_max) (the major-axis rule)."""

    name = "energy-sink"
    needs = "a free body spun about a principal axis with one Kane damper and no rotor"
    result_type = theory.KaneDamperDecay

    def fits(self, case: Case) -> bool:
        dampers = case.parts_for(self.name)
        return (
            case.free
            and len(dampers) == 1
            and len(case.internal) == 1
            and spin_axis(case) is not None
        )

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        """The nutation's rate (the angle of ``axis``, default body z, from the
        initial L, fitted over its linear stage; of a body without an axis of
        symmetry the tilt swings twice per nutation, so its peaks) against ``result``."""
        axis = np.asarray(options.get("axis", (0.0, 0.0, 1.0)), dtype=float)
        t, tilt = trajectory.t, _tilt(trajectory, axis / np.linalg.norm(axis))
        peaks = np.flatnonzero((tilt[1:-1] > tilt[:-2]) & (tilt[1:-1] >= tilt[2:])) + 1
        if peaks.size >= MANY_SWINGS:
            t, tilt = t[peaks], tilt[peaks]
        start = max(float(tilt[0]), 1e-12)
        band = (2.0 * start, min(0.1, 0.5 * float(np.max(tilt)))) if result.grows else (1e-9, start)
        measured = analysis.exponential_rate(t, tilt, band)
        name = "growth rate of the nutation" if result.grows else "decay rate of the nutation"
        sign = 1.0 if result.grows else -1.0
        return [comparison_row(name, -result.decay_rate * sign, measured * sign, "1/s")]

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        spun = spin_axis(case)
        if spun is None or not self.fits(case):
            raise InputError(f"Expected {self.needs}, got another setup.")
        axis, rate = spun
        damper = case.parts_for(self.name)[0]
        mp = case.mass_properties
        decay = theory.kane_damper_decay(mp, damper.inertia, damper.damping, rate, axis)
        moments = mp.principal()[0]
        momentum = float(np.linalg.norm(trajectory.angular_momentum[0]))
        final_energy = momentum**2 / (2.0 * moments[2])
        rows: list[dict[str, Any]] = []
        with contextlib.suppress(InputError):  # no linear stage to fit in this run
            rows += self.rows(trajectory, decay, axis=axis)
        end_energy = float(trajectory.energy[-1])
        name = "energy at the end: |H|² / (2 I_max)"
        rows.append(comparison_row(name, final_energy, end_energy, "J"))
        # Spinning about a major axis (any of them, if two are equal), H = I_max ω.
        end = float(np.linalg.norm(trajectory.omega[-1]))
        ratio = float(np.linalg.norm(trajectory.body_momentum[-1])) / (moments[2] * end)
        rows.append(comparison_row("|H| / (I_max |ω|) at the end", 1.0, ratio, ""))
        t = trajectory.t
        tilt = np.degrees(_tilt(trajectory, axis))
        curves = [Curve("simulation", t, tilt)]
        if tilt[0] > 0:
            linear = tilt[0] * np.exp(-decay.decay_rate * t)
            keep = linear < 45.0
            curves.append(Curve("theory: linear, ∝ exp(−σ t)", t[keep], linear[keep], "theory"))
        panels = [
            Panel(
                "Energy falls to that of a pure spin about the major axis, |H| kept",
                "energy (J)",
                [
                    Curve("kinetic energy (body and damper)", t, trajectory.energy),
                    Curve("theory: |H|² / (2 I_max)", t, np.full_like(t, final_energy), "theory"),
                ],
                name="energy",
            ),
            Panel(
                "Nutation: the spin axis's angle from L (time constant "
                f"{decay.time_constant:.4g} s)",
                "angle (deg)",
                curves,
                name="nutation",
                log=True,
            ),
        ]
        return Comparison(rows, panels)
