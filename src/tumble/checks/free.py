"""Torque-free bodies: the symmetric top's cones and precession, the flip period."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from tumble import analysis, theory
from tumble.checks.base import (
    Case,
    Comparison,
    Curve,
    Panel,
    TheoryCheck,
    axis_angles,
    comparison_row,
    steady_state,
)
from tumble.errors import InputError

if TYPE_CHECKING:
    from tumble.trajectory import Trajectory

__all__ = ["FlipPeriodCheck", "FreeSymmetricTopCheck"]

#: Principal moments closer than this fraction of their sum count as equal.
SYMMETRY_TOLERANCE = 1e-9


def _unit(vectors: Any) -> Any:
    return vectors / np.linalg.norm(vectors, axis=1)[:, None]


class FreeSymmetricTopCheck(TheoryCheck):
    """A free body with two equal principal moments: the body and space cones,
    the precession of ω in the body and of the axis about L
    (:func:`tumble.theory.free_symmetric_top`)."""

    name = "free-symmetric-top"
    needs = "a free body with two equal principal moments and no internal parts"
    result_type = theory.FreeSymmetricTop

    def fits(self, case: Case) -> bool:
        moments, _ = case.mass_properties.principal()
        steps = np.abs(np.diff(moments))
        symmetric = bool(np.any(steps <= SYMMETRY_TOLERANCE * moments.sum()))
        return case.free and case.rigid and symmetric

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        """The rate at which ω turns about the symmetry axis in the body
        (least-squares slope of its azimuth) against ``body_precession_rate``, and
        the rate at which the symmetry axis turns about the initial L in space
        (:func:`tumble.analysis.precession` with that vertical) against
        ``space_precession_rate``; ``result`` computed for the trajectory's body,
        so its ``axis`` is in body coordinates (``axis=`` and ``vertical=`` override)."""
        axis = np.asarray(options.get("axis", result.axis), dtype=float)
        axis = axis / np.linalg.norm(axis)
        vertical = options.get("vertical", trajectory.angular_momentum[0])
        body_rate = analysis.body_precession_rate(trajectory, axis)
        space_rate = analysis.precession(trajectory, axis=axis, vertical=vertical).rate
        return [
            comparison_row("body precession rate", result.body_precession_rate, body_rate, "rad/s"),
            comparison_row(
                "space precession rate", result.space_precession_rate, space_rate, "rad/s"
            ),
        ]

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        steady = steady_state(case)
        if steady is not None:  # no cone, no precession to measure
            return Comparison([], [], notes=(steady,))
        result = theory.free_symmetric_top(case.mass_properties, case.omega0)
        rows = self.rows(trajectory, result)
        t = trajectory.t
        axis = np.array(result.axis, dtype=float)
        body_cone = np.arccos(np.clip(_unit(trajectory.omega) @ axis, -1.0, 1.0))
        l_unit = _unit(trajectory.angular_momentum)
        space_omega = _unit(trajectory.omega_space)
        space_cone = np.arccos(np.clip(np.einsum("ij,ij->i", space_omega, l_unit), -1.0, 1.0))
        rows += [
            comparison_row(
                "body cone half-angle (ω to the axis)",
                result.body_cone_half_angle,
                float(np.mean(body_cone)),
                "rad",
            ),
            comparison_row(
                "space cone half-angle (ω to L)",
                result.space_cone_half_angle,
                float(np.mean(space_cone)),
                "rad",
            ),
        ]
        _, azimuth = axis_angles(trajectory, axis, l_unit[0])
        ones = np.ones_like(t)
        body_theory = np.degrees(result.body_cone_half_angle) * ones
        space_theory = np.degrees(result.space_cone_half_angle) * ones
        panels = [
            Panel(
                "Cones: ω to the symmetry axis (body cone), ω to L (space cone)",
                "half-angle (deg)",
                [
                    Curve("body cone, simulation", t, np.degrees(body_cone)),
                    Curve("body cone, theory", t, body_theory, "theory"),
                    Curve("space cone, simulation", t, np.degrees(space_cone)),
                    Curve("space cone, theory", t, space_theory, "theory"),
                ],
                name="cones",
            ),
            Panel(
                "Precession of the symmetry axis about L",
                "azimuth (deg)",
                [
                    Curve("simulation", t, np.degrees(azimuth)),
                    Curve(
                        "theory: L / I⊥ · t",
                        t,
                        np.degrees(result.space_precession_rate * t),
                        "theory",
                    ),
                ],
                name="precession",
            ),
        ]
        return Comparison(rows, panels)


class FlipPeriodCheck(TheoryCheck):
    """A free body: the period of ω(t) (the tennis-racket flip) and the number of
    flips (:func:`tumble.theory.flip_period`)."""

    name = "flip-period"
    needs = "a free body (no pivot with gravity, no torques, no internal parts)"
    result_type = (float, int)

    def fits(self, case: Case) -> bool:
        return case.free and case.rigid

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        """The period from :func:`tumble.theory.flip_period` against the one
        :func:`tumble.analysis.flips` measures (``options`` are not used)."""
        measured = analysis.flips(trajectory).period
        return [comparison_row("flip period", float(result), measured, "s")]

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        mp = case.mass_properties
        period = theory.flip_period(mp, case.omega0)
        duration = float(trajectory.t[-1])
        rows: list[dict[str, Any]] = []
        moments, axes = mp.principal()
        along = trajectory.omega @ axes
        try:
            flips = analysis.flips(trajectory)
        except InputError:  # fewer than two flips: too short a run to measure a period
            flips = None
        if flips is not None and math.isfinite(period) and duration > period:
            rows = self.rows(trajectory, float(period))
        curves = [
            Curve(
                f"ω along principal axis {k + 1} (I{k + 1} = {moments[k]:.4g} kg·m²)",
                trajectory.t,
                along[:, k],
            )
            for k in range(3)
        ]
        if flips is not None and flips.count:
            expected = _expected_flips(flips.times[0], period, duration)
            rows.append(comparison_row("flips in the run", expected, float(flips.count), ""))
        panels = [Panel("Flips: ω along the principal axes", "ω (rad/s)", curves, name="flips")]
        notes: tuple[str, ...] = ()
        if not rows:
            notes = (_nothing_compared(case, period, duration),)
        return Comparison(rows, panels, notes=notes)


def _nothing_compared(case: Case, period: float, duration: float) -> str:
    """Why a free body's run gave no flip period to compare."""
    steady = steady_state(case)
    if steady is not None:
        return steady
    if not math.isfinite(period):
        return (
            "no theory comparison: the flip period is infinite (ω starts on the separatrix, "
            "or turns steadily in a plane of equal moments); nothing to compare."
        )
    return (
        f"no theory comparison: the run ({duration:.3g} s) holds fewer than two flips (the "
        f"flip period is {period:.3g} s); run longer to compare."
    )


def _expected_flips(first: float, period: float, duration: float) -> float:
    """Flips (sign changes, two per period) from the first one to the end of the run."""
    if not math.isfinite(period):
        return 1.0
    return float(1 + math.floor((duration - first) / (0.5 * period)))
