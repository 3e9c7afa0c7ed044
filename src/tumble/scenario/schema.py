"""The scenario file's schema: pydantic models that validate and convert to SI.

A scenario is a TOML file with the tables ``[scenario]`` (name, title,
description), ``[body]``, ``[[internal]]`` (its rotors and dampers,
:mod:`tumble.config.parts`), ``[initial]``, ``[environment]``,
``[[torques]]``, ``[simulation]``, ``[theory]``, ``[output]``, or instead of
the free body the table of a model kind (:mod:`tumble.scenario.model_kinds`:
``[gyrocompass]``, ``[rotordynamics]``, the registry's; :func:`scenario_schema`
adds them). Quantities are numbers (SI) or strings with units (``"250 g"``,
``"3000 rpm"``, ``"0, 0, -10 cm"``); every value is converted to SI floats
here, with :mod:`tumble.units`, so what passes validation is a plain
description in SI. Unknown keys are errors (a typo must not be ignored
silently); see :func:`tumble.scenario.parse` for how errors are reported. The
``[body]`` table is :mod:`tumble.scenario.bodies`.
"""

from __future__ import annotations

import functools
import re
import warnings
from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import BeforeValidator, Field, create_model, field_validator, model_validator

from tumble.config import StrictModel, key_error
from tumble.config.parts import InternalSpec
from tumble.config.registries import method_choice, theory_choice, torque_entry
from tumble.errors import quoted
from tumble.resources import DEFAULT_MAX_STEPS, DEFAULT_MAX_STEPS_TEXT
from tumble.scenario.bodies import (
    Attitude,
    Body,
    LengthVector,
    Time,
    Vector,
    vector_field,
)

if TYPE_CHECKING:
    from tumble.scenario.model_kinds import ModelKind

__all__ = [
    "MAX_STEPS",
    "MAX_STEPS_TEXT",
    "SCENARIO_TABLES",
    "Environment",
    "Initial",
    "Output",
    "Scenario",
    "Simulation",
    "Theory",
    "Torque",
    "scenario_schema",
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

    @model_validator(mode="after")
    def _consistent(self) -> Scenario:
        samples = self.output.samples
        if not self.simulation.duration / samples > 0:
            raise key_error(
                ("simulation", "duration"),
                f"Expected `duration` long enough to space [output] samples = {samples} apart, "
                f"got {self.simulation.duration!r} s (duration / samples rounds to 0 s).",
            )
        tables = self.model_tables()
        if len(tables) > 1:
            raise ValueError(f"Expected one model table at most, got [{'] and ['.join(tables)}].")
        for table, kind in tables.items():
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
                    f"Expected no [{extra[0]}] with [{table}] (its model sets the "
                    "initial state, the forces and the closed form)."
                )
            if table != kind.table:
                warnings.warn(
                    f"The table [{table}] is now called [{kind.table}]: the old name "
                    "is read until the next release.",
                    FutureWarning,
                    stacklevel=2,
                )
        return self

    def model_tables(self) -> dict[str, ModelKind]:
        """The model tables the file holds, by the name it gives them, with their kinds
        (:data:`tumble.scenario.model_kinds.MODEL_KINDS`)."""
        from tumble.scenario.model_kinds import MODEL_KINDS

        return {
            name: kind
            for kind in MODEL_KINDS.values()
            for name in (kind.table, *kind.former_tables)
            if getattr(self, name, None) is not None
        }


#: The tables of every scenario file; a model kind's table takes another name.
SCENARIO_TABLES = tuple(Scenario.model_fields)


def scenario_schema() -> type[Scenario]:
    """The schema of scenario files: :class:`Scenario` with a table for each registered
    model kind (:data:`tumble.scenario.model_kinds.MODEL_KINDS`), and for each of
    their former names, made anew when the registry changes.

    Raises
    ------
    ValueError
        A model kind whose table takes the name of one of every file's tables.
    """
    from tumble.scenario.model_kinds import MODEL_KINDS

    tables = tuple(
        (name, kind.settings)
        for kind in MODEL_KINDS.values()
        for name in (kind.table, *kind.former_tables)
    )
    for name, _ in tables:
        if name in SCENARIO_TABLES:
            raise ValueError(
                f"Expected the model kinds' tables to be named other than every file's tables "
                f"({', '.join(SCENARIO_TABLES)}), got {name!r}."
            )
    return _schema_with(tables)


@functools.cache
def _schema_with(tables: tuple[tuple[str, type[StrictModel]], ...]) -> type[Scenario]:
    fields: dict[str, Any] = {name: (settings | None, None) for name, settings in tables}
    return create_model("Scenario", __base__=Scenario, __module__=__name__, **fields)
