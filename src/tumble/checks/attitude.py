"""Spacecraft attitude: libration in a circular orbit, a slew under feedback control."""

from __future__ import annotations

import contextlib
import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble import analysis, theory
from tumble.analysis.common import turning_points
from tumble.checks.base import Case, Comparison, Curve, Panel, TheoryCheck, comparison_row
from tumble.errors import InputError

if TYPE_CHECKING:
    from tumble.trajectory import Trajectory

__all__ = ["LibrationCheck", "SlewCheck"]

Array = NDArray[np.float64]

#: A body counts as near its equilibrium in orbit when its axes are within this, rad.
NEAR_EQUILIBRIUM = 0.35
#: A slew's axis counts as principal when it is within this angle of one, rad.
PRINCIPAL_CONE = 1e-6


def _only(case: Case, check: str) -> Any:
    """The one torque model of a case with no other and no pivot, whose kind declares
    the closed form of the check named ``check``, on a body whose parts all declare it
    too (a slew's reaction wheels; no damper); None otherwise."""
    if case.pivot is not None or len(case.parts_for(check)) != len(case.internal):
        return None
    held = case.torques_for(check)
    return held[0] if len(held) == len(case.torques) == 1 else None


def _closest_axis(axes: Array, direction: Array) -> tuple[Array, float]:
    """The principal axis (a column of ``axes``, signed) nearest ``direction``, and
    the angle between them, rad."""
    cosines = axes.T @ direction / np.linalg.norm(direction)
    k = int(np.argmax(np.abs(cosines)))
    axis = axes[:, k] * math.copysign(1.0, cosines[k])
    return axis, math.acos(min(1.0, abs(float(cosines[k]))))


class LibrationCheck(TheoryCheck):
    """A free body in a circular orbit under the gravity-gradient torque alone,
    near its equilibrium (principal axes along the local vertical and the orbit
    normal, at rest in the orbiting frame): the pitch libration's frequency
    (:func:`tumble.theory.gravity_gradient_libration`)."""

    name = "libration"
    needs = "a free rigid body under the gravity-gradient torque alone, near its equilibrium"

    def _equilibrium(self, case: Case) -> tuple[Any, Array, Array] | None:
        model = _only(case, self.name)
        if model is None or not case.rigid:
            return None
        e1, _ = model.plane()
        normal = np.array(model.orbit_normal, dtype=float)  # a writable copy, for scipy
        start = Rotation.from_quat(case.attitude0, scalar_first=True)
        axes = case.mass_properties.principal()[1]
        radial, off_radial = _closest_axis(axes, start.inv().apply(e1))
        up, off_normal = _closest_axis(axes, start.inv().apply(normal))
        if max(off_radial, off_normal) > NEAR_EQUILIBRIUM or abs(radial @ up) > 0.5:
            return None
        return model, radial, up

    def fits(self, case: Case) -> bool:
        return self._equilibrium(case) is not None

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        """The frequency of the pitch angle (about the orbit normal from the
        equilibrium; ``options``: ``pitch``, its samples, rad, and ``amplitude``,
        its largest angle, rad, for the exact large-swing frequency; default the
        small-swing one) against ``result``."""
        pitch = np.asarray(options["pitch"], dtype=float)
        measured = analysis.oscillation_frequency(trajectory.t, pitch)
        amplitude = options.get("amplitude")
        expected = (
            result.pitch_frequency if amplitude is None else result.pitch_frequency_at(amplitude)
        )
        return [comparison_row("pitch libration frequency", expected, measured, "rad/s")]

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        found = self._equilibrium(case)
        if found is None:
            raise InputError(f"Expected {self.needs}, got another setup.")
        model, radial, normal = found
        rate = float(model.orbit_rate)
        result = theory.gravity_gradient_libration(case.mass_properties, rate, radial, normal)
        deviation = analysis.orbit_deviation(
            trajectory, rate, radial, normal, model.radial0, model.orbit_normal
        )
        t = trajectory.t
        rows: list[dict[str, Any]] = []
        pitch = deviation[:, 2]
        swings = np.ptp(pitch) > 1e-9 and result.pitch_stable
        spin = float(case.omega0 @ normal) - rate  # pitch rate in the orbiting frame
        turns_over = False
        if swings:
            amplitude = result.pitch_amplitude(float(pitch[0]), spin)
            # Past the separatrix (θ̇² + ω_p² sin² θ ≥ ω_p²) the pitch turns over
            # instead of swinging: no libration to compare with.
            turns_over = amplitude >= 0.5 * math.pi
            swings = not turns_over
        if swings:
            rows += self.rows(trajectory, result, pitch=pitch, amplitude=amplitude)
        names = (
            "yaw (about the local vertical)",
            "roll (along track)",
            "pitch (about the orbit normal)",
        )
        curves = [Curve(name, t, np.degrees(deviation[:, k])) for k, name in enumerate(names)]
        if swings:
            # Pitch from its initial angle and rate in the orbiting frame, at the
            # frequency of its amplitude.
            start = float(pitch[0])
            w = result.pitch_frequency_at(amplitude)
            theory_pitch = start * np.cos(w * t) + spin / w * np.sin(w * t)
            curves.append(
                Curve(
                    "theory: the pitch pendulum's frequency", t, np.degrees(theory_pitch), "theory"
                )
            )
        frequencies = ", ".join(f"{f:.4g}" for f in result.roll_yaw_frequencies)
        over = "; the pitch turns over, past its separatrix" if turns_over else ""
        panel = Panel(
            f"Libration in orbit ({result.region}; roll–yaw at {frequencies} rad/s{over})",
            "angle from the equilibrium (deg)",
            curves,
            name="libration",
        )
        return Comparison(rows, [panel])


class SlewCheck(TheoryCheck):
    """A free body turned toward a target by :class:`tumble.torques.AttitudeController`
    (from outside or through its rotors) about a principal axis: the rate at
    which the pointing error dies out near the target
    (:func:`tumble.theory.attitude_slew`)."""

    name = "slew"
    needs = "a free body under an attitude controller alone, its error about a principal axis"

    def _slew(self, case: Case) -> tuple[Any, Array, float] | None:
        control = _only(case, self.name)
        if control is None:
            return None
        target = Rotation.from_quat(control.target, scalar_first=True)
        start = Rotation.from_quat(case.attitude0, scalar_first=True)
        turn = (target.inv() * start).as_rotvec()
        angle = float(np.linalg.norm(turn))
        if angle == 0:
            return None
        axis, off = _closest_axis(case.mass_properties.principal()[1], turn)
        return (control, axis, angle) if off < PRINCIPAL_CONE else None

    def fits(self, case: Case) -> bool:
        return self._slew(case) is not None

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        """The exponential rate at which the pointing error (``options``: ``target``,
        a quaternion body → space) dies out over its last decades, from 1 % to
        1e-7 of the largest error (its peaks when it oscillates)."""
        error = analysis.pointing_error(trajectory, options["target"])
        t = trajectory.t
        top = float(np.max(error))
        if result.damping_ratio < 1.0:  # its overshoots: the peaks of |error| after the first
            t, error = turning_points(t, error)[:2]
        measured = -analysis.exponential_rate(t, error, (1e-7 * top, 1e-2 * top))
        return [
            comparison_row("decay rate of the pointing error", result.decay_rate, measured, "1/s")
        ]

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        found = self._slew(case)
        if found is None:
            raise InputError(f"Expected {self.needs}, got another setup.")
        control, axis, angle = found
        result = theory.attitude_slew(
            case.mass_properties, control.stiffness, control.damping, axis
        )
        rows: list[dict[str, Any]] = []
        with contextlib.suppress(InputError):  # the run ends before the error's last decades
            rows += self.rows(trajectory, result, target=control.target)
        t = trajectory.t
        error = np.degrees(analysis.pointing_error(trajectory, control.target))
        tail = np.flatnonzero(error < 1e-2 * np.degrees(angle))
        curves = [Curve("simulation", t, np.maximum(error, 1e-12))]
        if tail.size:
            first = int(tail[0])
            asymptote = error[first] * np.exp(-result.decay_rate * (t[first:] - t[first]))
            curves.append(
                Curve("theory: ∝ exp(−rate · t) near the target", t[first:], asymptote, "theory")
            )
        panel = Panel(
            f"Pointing error (ω_n = {result.natural_frequency:.4g} rad/s, "
            f"ζ = {result.damping_ratio:.3g})",
            "error (deg)",
            curves,
            name="slew",
            log=True,
        )
        return Comparison(rows, [panel])
