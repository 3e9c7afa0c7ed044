"""The gimballed gyroscope on a turning platform: the swing of its spin axis."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from tumble import analysis, theory
from tumble.checks.base import Case, Comparison, Curve, Panel, TheoryCheck, comparison_row

if TYPE_CHECKING:
    from tumble.trajectory import Trajectory

__all__ = ["GyrocompassCheck"]


class GyrocompassCheck(TheoryCheck):
    """The disk of a gyrocompass (:func:`tumble.models.gyrocompass`) swinging about
    the direction of the platform's rotation: its frequency against β of
    :func:`tumble.theory.gyrocompass` (``options``: ``spin_rate`` and
    ``platform_rate``, rad/s)."""

    name = "gyrocompass"
    needs = "the gimballed gyroscope of a [gyrocompass] table"
    result_type = theory.Gyrocompass

    def fits(self, case: Case) -> bool:
        return "platform_rate" in case.options and "spin_rate" in case.options

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        """``options``: ``axis``, the body spin axis (default z), and ``vertical``, the
        platform's axis of rotation in space (default z, of either sign). The
        tilt of the spin axis from the direction it swings through, +vertical or
        −vertical (the one it comes nearer to: where its angular momentum settles
        along Ω), is |θ|, which peaks at both ends of each swing, so the
        swing's angular frequency is half the frequency
        :func:`tumble.analysis.nutation` measures on it. Compared with
        ``oscillation_frequency`` β (the Ω² term dropped),
        ``small_oscillation_frequency`` and ``2π / period(θ0)``, the exact
        frequency at the measured amplitude θ0 (the mean refined maximum of |θ|)."""
        axis = np.asarray(options.get("axis", (0.0, 0.0, 1.0)), dtype=float)
        up = np.asarray(options.get("vertical", (0.0, 0.0, 1.0)), dtype=float)
        up = up / np.linalg.norm(up)
        directions = trajectory.rotation.apply(axis / np.linalg.norm(axis))
        tilt = np.arccos(np.clip(directions @ up, -1.0, 1.0))
        if float(tilt.min()) > math.pi - float(tilt.max()):
            up = -up
        nut = analysis.nutation(trajectory, axis=axis, vertical=up)
        frequency = 0.5 * nut.frequency
        amplitude = float(nut.maxima.mean()) if nut.maxima.size else float(nut.tilt.max())
        return [
            comparison_row(
                "oscillation frequency β", result.oscillation_frequency, frequency, "rad/s"
            ),
            comparison_row(
                "oscillation frequency (small, exact)",
                result.small_oscillation_frequency,
                frequency,
                "rad/s",
            ),
            comparison_row(
                "oscillation frequency (amplitude, exact)",
                2 * math.pi / result.period(amplitude),
                frequency,
                "rad/s",
            ),
        ]

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        """The rows of one run, its platform turning about +z (or −z for a negative rate)."""
        rate = float(case.options["platform_rate"])
        result = theory.gyrocompass(case.mass_properties, case.options["spin_rate"], rate)
        direction = np.sign(rate) * np.array([0.0, 0.0, 1.0])
        return Comparison(self.rows(trajectory, result, vertical=direction), [])

    def compare_runs(
        self, case: Case, trajectories: Mapping[str, Trajectory], results: Mapping[str, Any]
    ) -> Comparison:
        """The rows of each run of the gimbal model (``results``: a
        :class:`~tumble.models.GyrocompassRun` by label, each named by its amplitude
        θ0), and one panel of θ(t) against the small swing from the same start,
        ``θ(0) cos βt + θ̇(0)/β sin βt``."""
        beta = theory.gyrocompass(
            case.mass_properties, case.options["spin_rate"], case.options["platform_rate"]
        ).oscillation_frequency
        rows: list[dict[str, Any]] = []
        curves: list[Curve] = []
        for label, run in results.items():
            trajectory = trajectories[label]
            angle0, rate0 = float(run.angle[0]), float(run.angle_rate[0])
            name = f"θ0 = {math.degrees(math.hypot(angle0, rate0 / beta)):.0f}°"
            for row in self.compare(case, trajectory).rows:
                rows.append({**row, "quantity": f"{name}: {row['quantity']}", "run": label})
            curves.append(Curve(f"{name}, simulation", trajectory.t, np.degrees(run.angle)))
            phase = beta * trajectory.t
            small = angle0 * np.cos(phase) + rate0 / beta * np.sin(phase)
            curves.append(Curve(f"{name}, θ0 sin βt", trajectory.t, np.degrees(small), "theory"))
        panel = Panel(
            "Gyrocompass: angle θ of the spin axis from the platform's axis",
            "θ (deg)",
            curves,
            name="theta",
        )
        return Comparison(rows, [panel])
