"""The ``[gyrocompass]`` table: the gimballed gyroscope on a turning platform, run
once per amplitude.

Each run is :func:`tumble.models.gyrocompass` started on the platform's axis with
θ̇ = β θ0, so that the small-angle solution is θ0 sin βt; its rows and the θ(t)
panel come from the gyrocompass theory check
(:class:`tumble.checks.gyrocompass.GyrocompassCheck`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Annotated, Any

from pydantic import Field, model_validator

from tumble.config import StrictModel
from tumble.scenario.bodies import Angle, AngularVelocity
from tumble.scenario.model_kinds.base import (
    ModelKind,
    ModelRuns,
    Progress,
    Span,
    register_model_kind,
)
from tumble.scenario.sampling import decimate, kept

if TYPE_CHECKING:
    from tumble.massprops import MassProperties
    from tumble.models import GyrocompassRun

__all__ = ["Gyrocompass", "GyrocompassSettings"]


class GyrocompassSettings(StrictModel):
    """``[gyrocompass]``: the gimballed gyroscope on a turning platform.

    The disk is ``[body]`` (symmetric about its z axis), spinning at
    ``spin_rate``; the platform turns at ``platform_rate``; each entry of
    ``amplitudes`` is one run released from rest at that angle θ0 between the
    spin axis and the platform's axis.
    """

    spin_rate: AngularVelocity
    platform_rate: AngularVelocity
    amplitudes: Annotated[list[Angle], Field(min_length=1, max_length=4)]

    @model_validator(mode="after")
    def _physical(self) -> GyrocompassSettings:
        if self.spin_rate == 0 or self.platform_rate == 0:
            raise ValueError(
                "Expected `spin_rate` and `platform_rate` ≠ 0 rad/s, got "
                f"{self.spin_rate!r} and {self.platform_rate!r}."
            )
        for theta in self.amplitudes:
            if not 0 < theta < math.pi:
                raise ValueError(
                    f"Expected each of `amplitudes` in (0, 180) deg, got {theta!r} rad."
                )
        return self


class Gyrocompass(ModelKind):
    """The gimbal model of :func:`tumble.models.gyrocompass`, one run per amplitude."""

    table = "gyrocompass"
    settings = GyrocompassSettings
    summary = "the gimballed gyroscope on a turning platform"
    check = "gyrocompass"
    notes = (
        "The gimbal model: the disk's energy is not conserved (the platform does work); "
        "the Jacobi integral T − Ω·L is.",
    )

    def run(self, body: MassProperties, settings: Any, span: Span, progress: Progress) -> ModelRuns:
        from tumble import models, theory
        from tumble.checks import Case

        beta = theory.gyrocompass(
            body, settings.spin_rate, settings.platform_rate
        ).oscillation_frequency
        total = len(settings.amplitudes)
        results: dict[str, GyrocompassRun] = {}
        for k, amplitude in enumerate(settings.amplitudes):
            label = "main" if k == 0 else f"amplitude-{math.degrees(amplitude):.0f}deg"

            def report(done: int, steps: int, k: int = k) -> None:
                if progress is not None:
                    progress(k * steps + done, total * steps)

            run = models.gyrocompass(
                body,
                settings.spin_rate,
                settings.platform_rate,
                0.0,
                angle_rate0=beta * amplitude,
                duration=span.duration,
                dt=span.dt,
                samples=span.samples,
                progress=report,
            )
            index = kept(len(run.trajectory.t), span.samples)
            results[label] = dataclasses.replace(
                run,
                trajectory=decimate(run.trajectory, span.samples),
                angle=run.angle[index],
                angle_rate=run.angle_rate[index],
                jacobi_integral=run.jacobi_integral[index],
            )
        main = results["main"].trajectory
        options = {"spin_rate": settings.spin_rate, "platform_rate": settings.platform_rate}
        return ModelRuns(
            {label: run.trajectory for label, run in results.items()},
            Case(body, main.omega[0], main.quaternion[0], options=options),
            results,
        )


register_model_kind(Gyrocompass())
