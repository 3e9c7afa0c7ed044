"""A body held at a steady rotation: the torque it needs and the bearing loads."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble import theory
from tumble.checks.base import (
    Case,
    Comparison,
    Curve,
    Panel,
    TheoryCheck,
    comparison_row,
)
from tumble.errors import InputError

if TYPE_CHECKING:
    from tumble.trajectory import Trajectory

__all__ = ["RotorLoadsCheck"]

Array = NDArray[np.float64]


def derivative(t: Array, values: Array) -> tuple[Array, Array]:
    """dvalues/dt by the five-point central difference (error O(h⁴)), at the
    interior samples of the evenly spaced part of ``t`` (a shorter last step is left out)."""
    steps = np.diff(t)
    even = len(t) if np.allclose(steps, steps[0], rtol=1e-9) else len(t) - 1
    h = float(steps[0])
    v = values[:even]
    rate = (v[:-4] - 8.0 * v[1:-3] + 8.0 * v[3:-1] - v[4:]) / (12.0 * h)
    return t[2 : even - 2], rate


class RotorLoadsCheck(TheoryCheck):
    """A body held at its initial rotation by :class:`tumble.torques.HoldRotation`
    (a shaft driven at a constant rate): L, the torque dL/dt the shaft supplies,
    the angle between L and ω and, given ``bearings``, the bearing forces
    (:func:`tumble.theory.rotor_loads`)."""

    name = "rotor-loads"
    needs = "a hold-rotation torque and no other"
    result_type = ()

    def fits(self, case: Case) -> bool:
        torques = case.torques
        held = bool(torques) and len(case.torques_for(self.name)) == len(torques)
        return held and case.rigid

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        mp = case.mass_properties
        point = np.asarray(case.pivot if case.pivot is not None else mp.center_of_mass)
        speed = float(np.linalg.norm(case.omega0))
        if speed == 0:
            raise InputError("Expected a non-zero initial ω to hold steady, got 0.")
        axis = case.omega0 / speed
        result = theory.rotor_loads(mp, speed, axis, point, case.options.get("bearings"))
        t = trajectory.t
        momentum = trajectory.angular_momentum
        times, torque = derivative(t, momentum)
        measured_torque = float(np.mean(np.linalg.norm(torque, axis=1)))
        omega_space = trajectory.omega_space
        cosines = np.einsum("ij,ij->i", momentum, omega_space) / (
            np.linalg.norm(momentum, axis=1) * np.linalg.norm(omega_space, axis=1)
        )
        angle = np.arccos(np.clip(cosines, -1.0, 1.0))
        l_theory = np.asarray(result.angular_momentum)
        size = float(np.linalg.norm(l_theory))
        angle_theory = float(np.arccos(np.clip(l_theory @ axis / size, -1.0, 1.0)))
        held = float(np.mean(np.linalg.norm(trajectory.omega, axis=1)))
        torque_theory = float(np.linalg.norm(result.torque))
        rows = [
            comparison_row("|ω| (held steady)", speed, held, "rad/s"),
            comparison_row(
                "|L|", size, float(np.mean(np.linalg.norm(momentum, axis=1))), "kg·m²/s"
            ),
            comparison_row("angle between L and ω", angle_theory, float(np.mean(angle)), "rad"),
            comparison_row("|τ| = |dL/dt|", torque_theory, measured_torque, "N·m"),
        ]
        if result.bearing_forces is not None and result.bearings is not None:
            separation = abs(float(result.bearings[0] - result.bearings[1]))
            # With the centre of mass on the axis each bearing carries |τ| / d.
            rows.append(
                comparison_row(
                    "bearing force (each)",
                    float(np.linalg.norm(result.bearing_forces[0])),
                    measured_torque / separation,
                    "N",
                )
            )
        panels = [
            Panel(
                "Torque needed to keep ω steady: |dL/dt| of the simulation vs ω × L",
                "|τ| (N·m)",
                [
                    Curve("|dL/dt| of the simulation", times, np.linalg.norm(torque, axis=1)),
                    Curve("theory |ω × (I ω)|", t, torque_theory * np.ones_like(t), "theory"),
                ],
                name="torque",
            ),
            Panel(
                "L sweeps a cone about ω: its component perpendicular to ω",
                "L (kg·m²/s)",
                [
                    Curve("L_x (space)", t, momentum[:, 0]),
                    Curve("L_y (space)", t, momentum[:, 1]),
                    Curve("L_z (space)", t, momentum[:, 2]),
                ],
                name="cone",
            ),
        ]
        return Comparison(rows, panels)

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        raise InputError("Expected a setup for the rotor loads (use compare), got a result.")
