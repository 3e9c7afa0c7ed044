"""The scenario file's schema: pydantic models that validate and convert to SI.

A scenario is a TOML file with the tables ``[scenario]`` (name, title,
description), ``[body]``, ``[[internal]]`` (its rotors and dampers,
:mod:`tumble.config.parts`), ``[initial]``, ``[environment]``,
``[[torques]]``, ``[simulation]``, ``[theory]``, ``[output]`` and, for the
gimballed gyroscope, ``[gyrocompass]``, for a rotor on elastic bearings
``[rotor]``. Quantities are numbers (SI) or strings with units (``"250 g"``,
``"3000 rpm"``, ``"0, 0, -10 cm"``); every value is converted to SI floats
here, with :mod:`tumble.units`, so what passes validation is a plain
description in SI. Unknown keys are errors (a typo must not be ignored
silently); see :func:`tumble.scenario.parse` for how errors are reported. The
``[body]`` table is :mod:`tumble.scenario.bodies`.
"""

from __future__ import annotations

import math
import re
from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, ValidationInfo, field_validator, model_validator

from tumble.config import StrictModel, key_error
from tumble.config.parts import InternalSpec
from tumble.config.registries import method_choice, theory_choice, torque_entry
from tumble.errors import quoted
from tumble.resources import DEFAULT_MAX_STEPS, DEFAULT_MAX_STEPS_TEXT
from tumble.scenario.bodies import (
    Angle,
    AngularVelocity,
    Attitude,
    Body,
    LengthVector,
    Time,
    Vector,
    scalar_field,
    vector_field,
)

__all__ = [
    "MAX_STEPS",
    "MAX_STEPS_TEXT",
    "Environment",
    "GyrocompassSettings",
    "Initial",
    "Output",
    "RotorBearing",
    "RotorSettings",
    "Scenario",
    "Simulation",
    "Theory",
    "Torque",
]


#: The most steps a scenario may take: :func:`tumble.simulate`'s default limit
#: (a few seconds of the compiled kernels). ``MAX_STEPS_TEXT`` is how messages write it.
MAX_STEPS = DEFAULT_MAX_STEPS
MAX_STEPS_TEXT = DEFAULT_MAX_STEPS_TEXT


# ------------------------------------------------------------ the rest
class Info(StrictModel):
    """``[scenario]``: a name (letters, digits, dashes), a title and a description."""

    name: str
    title: str = ""
    description: str = ""

    @field_validator("name")
    @classmethod
    def _slug(cls, value: str) -> str:
        if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,63}", value):
            raise ValueError(
                "Expected `name` to be letters, digits, '-', '_' or '.' (at most 64, it names "
                f"the run folder), got {quoted(value)}."
            )
        return value


class Initial(StrictModel):
    """``[initial]``: ω (in body axes, or space axes with ``omega_frame = "space"``)
    and the attitude at t = 0 (default: body axes along space axes)."""

    omega: Annotated[Vector, vector_field("angular_velocity")] = (0.0, 0.0, 0.0)
    omega_frame: Literal["body", "space"] = "body"
    attitude: Attitude | None = None


class Environment(StrictModel):
    """``[environment]``: a body point held fixed (``pivot``) and ``gravity`` (space axes)."""

    pivot: LengthVector | None = None
    gravity: Annotated[Vector, vector_field("acceleration")] | None = None

    @model_validator(mode="after")
    def _pivot_needs_gravity(self) -> Environment:
        if self.pivot is not None and self.gravity is None:
            raise ValueError(
                "Expected `gravity` with `pivot` (write gravity = [0, 0, 0] for a pivot "
                "without gravity)."
            )
        return self


class Torque(StrictModel):
    """``[[torques]]``: ``type``, the name of a torque model of the registry
    (:data:`tumble.torques.TORQUES`; for example ``constant-body`` with
    ``torque``, ``constant-space`` with ``torque``, ``damping`` with
    ``coefficient``, ``hold-rotation`` alone), and that model's parameters, with
    units. ``values`` holds them in SI once validated."""

    type: str
    values: dict[str, Any] = {}

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any) -> Any:
        # Replaces the strict check of the base: the keys are the model's parameters.
        return torque_entry(data)


class Simulation(StrictModel):
    """``[simulation]``: ``duration``, and optionally ``dt`` and ``method``
    (see :func:`tumble.simulate`)."""

    duration: Time
    dt: Time | None = None
    method: Annotated[str, BeforeValidator(method_choice)] = "auto"

    @model_validator(mode="after")
    def _steps(self) -> Simulation:
        if self.dt is not None and self.duration / self.dt > MAX_STEPS:
            raise ValueError(
                f"Expected at most {MAX_STEPS_TEXT} steps (duration / dt), got "
                f"{self.duration / self.dt:.3g}: a scenario should run in seconds (use "
                "tumble.simulate for long runs)."
            )
        return self


class Theory(StrictModel):
    """``[theory]``: which closed form to compare with: a theory check of the
    registry (:data:`tumble.checks.THEORY_CHECKS`), ``auto`` (the first that fits
    the setup) or ``none``; ``bearings`` for the rotor loads."""

    model: Annotated[str, BeforeValidator(theory_choice)] = "auto"
    bearings: Annotated[tuple[float, float], vector_field("length", (2,))] | None = None


class Output(StrictModel):
    """``[output]``: what the run records and produces."""

    samples: Annotated[int, Field(ge=10, le=1_000_000)] = 2000
    figures: bool = True
    viewer: bool = True
    viewer_frames: Annotated[int, Field(ge=2, le=2000)] = 300


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


def number_or_pair(kind: str) -> Any:
    """A validator of one value ≥ 0 (the same along both transverse axes) or a pair
    of them (along the rotor's x and y), in SI units of ``kind``."""

    def convert(value: Any, info: ValidationInfo) -> tuple[float, float]:
        from tumble.theory.rotordynamics import transverse_pair

        return transverse_pair(value, kind, str(info.field_name))

    return BeforeValidator(convert)


class RotorBearing(StrictModel):
    """``[[rotor.bearings]]``: one elastic bearing (:class:`tumble.theory.Bearing`):
    ``position`` along the rotor's axis from the body's origin; ``stiffness``
    (N/m) and ``damping`` (N·s/m), each one value or two (``"1e6, 2e6 N/m"``:
    along the rotor's x and y)."""

    position: Annotated[float, scalar_field("length")]
    stiffness: Annotated[tuple[float, float], number_or_pair("stiffness")]
    damping: Annotated[tuple[float, float], number_or_pair("linear_damping")] = (0.0, 0.0)


class RotorSettings(StrictModel):
    """``[rotor]``: ``[body]`` as a rigid rotor on elastic bearings
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
    bearings: list[RotorBearing]
    unbalance: Annotated[float, scalar_field("unbalance", positive=True)]
    unbalance_position: Annotated[float, scalar_field("length")] = 0.0
    speeds: Annotated[tuple[float, float], vector_field("angular_velocity", (2,))]
    steady_speed: Annotated[float, scalar_field("angular_velocity", positive=True)] | None = None

    @model_validator(mode="after")
    def _consistent(self) -> RotorSettings:
        if len(self.bearings) < 2:
            raise ValueError(
                "Expected two or more [[rotor.bearings]] (to hold the rotor's tilt), got "
                f"{len(self.bearings)}."
            )
        low, high = self.speeds
        if not 0 <= low < high:
            raise ValueError(
                f"Expected `speeds` = [from, to] with 0 <= from < to (rad/s), got [{low!r}, "
                f"{high!r}]."
            )
        return self


class Scenario(StrictModel):
    """A whole scenario file, validated and in SI units."""

    scenario: Info
    body: Body
    internal: list[InternalSpec] = []
    initial: Initial = Initial()
    environment: Environment = Environment()
    torques: list[Torque] = []
    simulation: Simulation
    theory: Theory = Theory()
    output: Output = Output()
    gyrocompass: GyrocompassSettings | None = None
    rotor: RotorSettings | None = None

    @model_validator(mode="after")
    def _consistent(self) -> Scenario:
        samples = self.output.samples
        if not self.simulation.duration / samples > 0:
            raise key_error(
                ("simulation", "duration"),
                f"Expected `duration` long enough to space [output] samples = {samples} apart, "
                f"got {self.simulation.duration!r} s (duration / samples rounds to 0 s).",
            )
        models = [name for name in ("gyrocompass", "rotor") if getattr(self, name) is not None]
        if len(models) > 1:
            raise ValueError("Expected one of [gyrocompass] and [rotor], got both.")
        if models:
            extra = [
                name
                for name, given in (
                    ("initial", self.initial != Initial()),
                    ("environment", self.environment != Environment()),
                    ("torques", bool(self.torques)),
                    ("internal", bool(self.internal)),
                    ("theory", self.theory != Theory()),
                )
                if given
            ]
            if extra:
                raise ValueError(
                    f"Expected no [{extra[0]}] with [{models[0]}] (its model sets the "
                    "initial state, the forces and the closed form)."
                )
        return self
