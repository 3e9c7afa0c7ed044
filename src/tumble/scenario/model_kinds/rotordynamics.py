"""The ``[rotordynamics]`` table: ``[body]`` as a rigid rotor on elastic bearings, run
up through its critical speeds.

The body is a :class:`tumble.theory.RigidRotor` on the bearings of the table.
The main run is :func:`tumble.models.run_up` through the table's ``speeds``
over ``[simulation] duration``; with ``steady_speed`` a second run holds that
speed until the start-up transient has died away. The rigid-rotor theory check
(:class:`tumble.checks.rigid_rotor.RigidRotorCheck`) compares them with the
closed forms and draws them. The table was called ``[rotor]``, a name it shared
with the ``rotor`` part of ``[[internal]]``: that name is still read, with a
warning, for one release.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any

from pydantic import BeforeValidator, ValidationInfo, model_validator

from tumble.config import StrictModel, key_error
from tumble.resources import DEFAULT_MAX_STEPS
from tumble.scenario.bodies import Vector, scalar_field, vector_field
from tumble.scenario.model_kinds.base import (
    ModelKind,
    ModelRuns,
    Progress,
    Span,
    register_model_kind,
)

if TYPE_CHECKING:
    from tumble.massprops import MassProperties
    from tumble.models import RunUp

__all__ = ["BearingSettings", "Rotordynamics", "RotordynamicsSettings"]


def number_or_pair(kind: str) -> Any:
    """A validator of one value ≥ 0 (the same along both transverse axes) or a pair
    of them (along the rotor's x and y), in SI units of ``kind``."""

    def convert(value: Any, info: ValidationInfo) -> tuple[float, float]:
        from tumble.theory.rotordynamics import transverse_pair

        return transverse_pair(value, kind, str(info.field_name))

    return BeforeValidator(convert)


class BearingSettings(StrictModel):
    """``[[rotordynamics.bearings]]``: one elastic bearing
    (:class:`tumble.theory.Bearing`): ``position`` along the rotor's axis from the
    body's origin; ``stiffness`` (N/m) and ``damping`` (N·s/m), each one value or
    two (``"1e6, 2e6 N/m"``: along the rotor's x and y)."""

    position: Annotated[float, scalar_field("length")]
    stiffness: Annotated[tuple[float, float], number_or_pair("stiffness")]
    damping: Annotated[tuple[float, float], number_or_pair("linear_damping")] = (0.0, 0.0)


class RotordynamicsSettings(StrictModel):
    """``[rotordynamics]``: ``[body]`` as a rigid rotor on elastic bearings
    (:class:`tumble.theory.RigidRotor`), spinning about ``axis`` (body axes; a
    principal axis with equal moments about the other two).

    The run (:func:`tumble.models.run_up`) takes the rotor from the first of
    ``speeds`` to the second over ``[simulation] duration`` with an
    ``unbalance`` (kg·m, the unbalance mass times its radius) at
    ``unbalance_position`` along the axis; a second run at ``steady_speed``
    (if given) settles on the steady orbits. The Campbell diagram and the
    unbalance response are drawn over ``speeds``.
    """

    axis: Annotated[Vector, vector_field("dimensionless")] = (0.0, 0.0, 1.0)
    bearings: list[BearingSettings]
    unbalance: Annotated[float, scalar_field("unbalance", positive=True)]
    unbalance_position: Annotated[float, scalar_field("length")] = 0.0
    speeds: Annotated[tuple[float, float], vector_field("angular_velocity", (2,))]
    steady_speed: Annotated[float, scalar_field("angular_velocity", positive=True)] | None = None

    @model_validator(mode="after")
    def _consistent(self) -> RotordynamicsSettings:
        if len(self.bearings) < 2:
            raise key_error(
                "bearings",
                "Expected two or more bearings (to hold the rotor's tilt), got "
                f"{len(self.bearings)}.",
            )
        low, high = self.speeds
        if not 0 <= low < high:
            raise ValueError(
                f"Expected `speeds` = [from, to] with 0 <= from < to (rad/s), got [{low!r}, "
                f"{high!r}]."
            )
        return self


class Rotordynamics(ModelKind):
    """The rigid rotor on elastic bearings of :func:`tumble.models.run_up`: a run-up
    through ``speeds``, and a run at ``steady_speed`` if one is given."""

    table = "rotordynamics"
    former_tables = ("rotor",)
    settings = RotordynamicsSettings
    summary = "a rigid rotor on elastic bearings, run up through its critical speeds"
    check = "rigid-rotor"
    notes = (
        "The rotor model: the motor does work and the bearings take it, so nothing is "
        "conserved; its whirl, critical speeds and unbalance response are "
        "tumble.theory.RigidRotor's.",
    )

    def run(self, body: MassProperties, settings: Any, span: Span, progress: Progress) -> ModelRuns:
        from tumble import models, theory
        from tumble.checks import Case

        bearings = [theory.Bearing(b.position, b.stiffness, b.damping) for b in settings.bearings]
        rotor = theory.RigidRotor(body, bearings, axis=settings.axis)
        low, high = settings.speeds
        planned = [("main", low, (high - low) / span.duration)]
        if settings.steady_speed is not None:
            planned.append(("steady", settings.steady_speed, 0.0))
        results: dict[str, RunUp] = {}
        for k, (label, start, rate) in enumerate(planned):

            def report(done: int, steps: int, k: int = k) -> None:
                if progress is not None:
                    progress(k * steps + done, len(planned) * steps)

            results[label] = models.run_up(
                rotor,
                settings.unbalance,
                duration=span.duration,
                speed=start,
                acceleration=rate,
                position=settings.unbalance_position,
                dt=span.dt,
                samples=span.samples,
                progress=report,
                max_steps=DEFAULT_MAX_STEPS,
            )
        main = results["main"].trajectory
        options = {
            "rigid_rotor": rotor,
            "unbalance": settings.unbalance,
            "unbalance_position": settings.unbalance_position,
            "speeds": settings.speeds,
        }
        return ModelRuns(
            {label: run.trajectory for label, run in results.items()},
            Case(body, main.omega[0], main.quaternion[0], options=options),
            results,
        )


register_model_kind(Rotordynamics())
