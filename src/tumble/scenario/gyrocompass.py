"""A scenario with a ``[gyrocompass]`` table: the gimbal model run once per amplitude.

Each run is :func:`tumble.models.gyrocompass` started on the platform's axis
with θ̇ = β θ0, so that the small-angle solution is θ0 sin βt; its rows come
from the gyrocompass theory check (:class:`tumble.checks.gyrocompass.GyrocompassCheck`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from tumble.checks import THEORY_CHECKS, Case, Curve, Panel
from tumble.scenario.build import at_key
from tumble.scenario.sampling import decimate, kept

if TYPE_CHECKING:
    from tumble.massprops import MassProperties
    from tumble.scenario.loaded import LoadedScenario
    from tumble.trajectory import Trajectory

__all__ = ["run_gyrocompass"]

Progress = Callable[[int, int], object] | None


def run_gyrocompass(
    loaded: LoadedScenario, mp: MassProperties, progress: Progress
) -> tuple[dict[str, Trajectory], list[dict[str, Any]], list[Panel], str]:
    """The runs by label ("main" first), the rows of each, the θ(t) panel, and the
    name of the check."""
    from tumble import models, theory

    spec = loaded.spec
    settings = spec.gyrocompass
    if settings is None:  # pragma: no cover - called for scenarios with [gyrocompass] only
        raise ValueError("Expected a scenario with a [gyrocompass] table.")
    check = THEORY_CHECKS["gyrocompass"]
    with at_key(loaded, "gyrocompass"):
        result = theory.gyrocompass(mp, settings.spin_rate, settings.platform_rate)
    beta = result.oscillation_frequency
    options = {"spin_rate": settings.spin_rate, "platform_rate": settings.platform_rate}
    runs: dict[str, Trajectory] = {}
    rows: list[dict[str, Any]] = []
    curves: list[Curve] = []
    total = len(settings.amplitudes)
    for k, amplitude in enumerate(settings.amplitudes):
        label = "main" if k == 0 else f"amplitude-{math.degrees(amplitude):.0f}deg"

        def report(done: int, steps: int, k: int = k) -> None:
            if progress is not None:
                progress(k * steps + done, total * steps)

        with at_key(loaded, "gyrocompass"):
            run = models.gyrocompass(
                mp,
                settings.spin_rate,
                settings.platform_rate,
                0.0,
                angle_rate0=beta * amplitude,
                duration=spec.simulation.duration,
                dt=spec.simulation.dt,
                samples=spec.output.samples,
                progress=report,
            )
        index = kept(len(run.trajectory.t), spec.output.samples)
        traj = decimate(run.trajectory, spec.output.samples)
        angle = np.asarray(run.angle)[index]
        runs[label] = traj
        case = Case(mp, traj.omega[0], traj.quaternion[0], options=options)
        name = f"θ0 = {math.degrees(amplitude):.0f}°"
        for row in check.compare(case, traj).rows:
            row["quantity"] = f"{name}: {row['quantity']}"
            row["run"] = label
            rows.append(row)
        curves.append(Curve(f"{name}, simulation", traj.t, np.degrees(angle)))
        small = np.degrees(amplitude * np.sin(beta * traj.t))
        curves.append(Curve(f"{name}, θ0 sin βt", traj.t, small, "theory"))
    panel = Panel(
        "Gyrocompass: angle θ of the spin axis from the platform's axis",
        "θ (deg)",
        curves,
        name="theta",
    )
    return runs, rows, [panel], check.name
