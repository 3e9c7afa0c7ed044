"""The heavy symmetric top on a pivot (a gyroscope): precession and nutation."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.spatial.transform import Rotation

from tumble import analysis, theory
from tumble.checks.base import (
    Case,
    Comparison,
    Curve,
    Panel,
    TheoryCheck,
    axis_angles,
    comparison_row,
    periods,
)
from tumble.errors import InputError

if TYPE_CHECKING:
    from tumble.trajectory import Trajectory

__all__ = ["GyroscopeCheck"]


class GyroscopeCheck(TheoryCheck):
    """A symmetric top about a pivot on its symmetry axis (body z) under gravity,
    from any initial state: :func:`tumble.theory.gyroscope`."""

    name = "gyroscope"
    needs = "a pivot with gravity and no other torque"
    result_type = theory.Gyroscope

    def fits(self, case: Case) -> bool:
        if not case.heavy or case.torques or not case.rigid:
            return False
        try:  # symmetric about body z, the pivot on that axis
            theory.gyroscope(case.mass_properties, case.pivot, 1.0, 0.5, 1.0)
        except InputError:
            return False
        return True

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        """The precession rate (:func:`tumble.analysis.precession`, over whole
        nutation periods) against the exact mean rate ``mean_precession_rate``,
        the slow steady rate at θ0 ``precession_rates[0]`` and the fast-top
        ``precession_rate``; the nutation frequency (:func:`tumble.analysis.nutation`)
        against the exact ``2π / nutation_period``, the small nutation about the
        steady precession ``small_nutation_frequencies[0]`` and the fast-top
        ``nutation_frequency``; the nutation amplitude against half the
        difference of the exact ``nutation_limits`` and the fast-top
        ``nutation_amplitude``. ``options`` (``axis``, ``vertical``) go to the
        measurements. A released top's mean precession differs from the steady
        rates, and its nutation from the small nutation, by
        O(m g l I⊥' / (I_s ω_s)²): physics, not error."""
        rate = analysis.precession(trajectory, **options).rate
        nut = analysis.nutation(trajectory, **options)
        rows = [
            comparison_row(
                "precession rate (mean, exact)", result.mean_precession_rate, rate, "rad/s"
            )
        ]
        if result.precession_rates is not None:
            rows.append(
                comparison_row(
                    "precession rate (steady at θ0)", result.precession_rates[0], rate, "rad/s"
                )
            )
        rows.append(
            comparison_row("precession rate (fast top)", result.precession_rate, rate, "rad/s")
        )
        rows.append(
            comparison_row(
                "nutation frequency (exact)",
                2 * math.pi / result.nutation_period,
                nut.frequency,
                "rad/s",
            )
        )
        if result.small_nutation_frequencies is not None:
            rows.append(
                comparison_row(
                    "nutation frequency (small, about steady)",
                    result.small_nutation_frequencies[0],
                    nut.frequency,
                    "rad/s",
                )
            )
        rows.append(
            comparison_row(
                "nutation frequency (fast top)", result.nutation_frequency, nut.frequency, "rad/s"
            )
        )
        low, high = result.nutation_limits
        rows.append(
            comparison_row("nutation amplitude (exact)", 0.5 * (high - low), nut.amplitude, "rad")
        )
        rows.append(
            comparison_row(
                "nutation amplitude (fast top)", result.nutation_amplitude, nut.amplitude, "rad"
            )
        )
        return rows

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        g = np.asarray(case.gravity, dtype=float)
        up = -g / math.hypot(*g)  # hypot: no overflow of the squares
        axis = np.array([0.0, 0.0, 1.0])
        # The theory's space z is up: turn the initial attitude into such axes.
        level = Rotation.align_vectors([axis], [up])[0]
        start = level * trajectory.rotation[0]
        result = theory.gyroscope(
            case.mass_properties,
            case.pivot,
            gravity=math.hypot(*g),
            omega0=case.omega0,
            attitude0=start,
        )
        rows = self.rows(trajectory, result, axis=axis, vertical=up)
        t = trajectory.t
        tilt, azimuth = axis_angles(trajectory, axis, up)
        exact = np.degrees(result.tilt_at(t))
        rate = analysis.precession(trajectory, axis=axis, vertical=up).rate
        panels = [
            Panel(
                "Nutation: tilt θ of the symmetry axis from the vertical",
                "θ (deg)",
                [
                    Curve("simulation", t, np.degrees(tilt)),
                    Curve("exact (Lagrange top)", t, exact, "theory"),
                ],
                name="nutation",
                until=periods(result.nutation_period, 6, float(t[-1])),
            ),
            Panel(
                "Precession: azimuth φ of the symmetry axis about the vertical",
                "φ (deg)",
                [
                    Curve("simulation", t, np.degrees(azimuth)),
                    Curve(
                        f"exact mean rate {result.mean_precession_rate:.6g} rad/s · t",
                        t,
                        np.degrees(result.mean_precession_rate * t),
                        "theory",
                    ),
                    Curve(
                        "fast top: m g l / (I_s ω_s) · t",
                        t,
                        np.degrees(result.precession_rate * t),
                        "theory",
                    ),
                    Curve(
                        f"measured mean rate {rate:.6g} rad/s · t",
                        t,
                        np.degrees(rate * t),
                        "fit",
                    ),
                ],
                name="precession",
            ),
        ]
        return Comparison(rows, panels)
