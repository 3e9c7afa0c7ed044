"""The sweep file's schema: pydantic models for its structure, then a :class:`Plan` in SI.

A sweep file is TOML with the tables

* ``[sweep]``: ``name``, ``description``, ``seed``, ``samples`` (random draws
  per grid point), ``chunk_size`` (bodies per chunk of work and of storage);
* ``[base]``: the scenario every body shares: ``duration``, ``dt``,
  ``method`` and any per-body parameter (:data:`~tumble.sweep.plan.PARAMETERS`)
  held fixed;
* ``[vary.NAME]``: a parameter that varies, either a grid (``values = [...]``,
  or ``start``, ``stop``, ``num`` with ``scale = "linear"`` or ``"log"``) or a
  random draw (``distribution`` = ``"uniform"``, ``"loguniform"`` or
  ``"spherical"`` with ``min`` and ``max``); ``unit`` applies to its bare numbers;
* ``[outputs]``: ``metrics`` (a list of :data:`~tumble.sweep.plan.METRICS`),
  ``final_state``, ``initial_state``;
* ``[report]``: ``maps = [{x, y, metric, statistic, bins}]``;
* ``[dask]``: ``scheduler = "tcp://HOST:PORT"`` or ``workers = N``.

Pydantic checks the structure (types, required and unknown keys); the values
are then converted to SI with :mod:`tumble.units` and checked together
(ranges, the triangle inequality of the moments at every corner of the swept
box). Every error is one :class:`SweepError` naming the file, the line, the
key path, what was expected and what was given.
"""

from __future__ import annotations

import difflib
from functools import partial
from typing import Annotated, Any, Literal

from pydantic import (
    BeforeValidator,
    Field,
    StrictBool,
    StrictInt,
    StrictStr,
    model_validator,
)
from pydantic_core import PydanticCustomError

from tumble.config import (
    ConfigError,
    StrictModel,
    key_error,
    key_text,
    shown,
    unknown_key,
)
from tumble.config.registries import method_choice
from tumble.errors import InputError
from tumble.sweep.plan import (
    PARAMETERS,
    torque_parameters,
)

__all__ = ["SweepError", "SweepFile", "check_address"]

#: Chunk size when the file gives none: 65536 bodies (a few MB of state, 512
#: blocks of the batch kernel, a fraction of a second to a few seconds of work).
DEFAULT_CHUNK_SIZE = 1 << 16


class SweepError(ConfigError):
    """A sweep file is invalid; the message names the file, line and key."""


def _value(value: Any) -> Any:
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise PydanticCustomError(
            "sweep_value",
            "Expected a number or a quantity such as '2 rad/s', got {got}.",
            {"got": shown(value)},
        )
    return value


MetricName = Literal["flips", "first_flip_time", "max_nutation", "energy_drift", "momentum_drift"]

#: A number (SI) or a string with units ("2 rad/s", "5 deg").
Value = Annotated[int | float | str, BeforeValidator(_value)]


class SweepTable(StrictModel):
    """``[sweep]``: what the sweep is called and how it is cut into chunks."""

    name: Annotated[StrictStr, Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]*$", max_length=80)]
    description: StrictStr = ""
    seed: Annotated[StrictInt, Field(ge=0)] = 0
    samples: Annotated[StrictInt, Field(ge=1)] = 1
    chunk_size: Annotated[StrictInt, Field(ge=1)] = DEFAULT_CHUNK_SIZE


class Base(StrictModel):
    """``[base]``: the run and the fixed per-body parameters: those of the bodies
    here, those of the torque models (:func:`~tumble.sweep.plan.torque_parameters`,
    read from the torque registry) in ``torques``."""

    duration: Value
    dt: Value
    method: Annotated[str, BeforeValidator(partial(method_choice, batch=True))] = "rk4"
    moment_1: Value | None = None
    moment_2: Value | None = None
    moment_3: Value | None = None
    ratio_2: Value | None = None
    ratio_3: Value | None = None
    spin_axis: Literal[1, 2, 3] | None = None
    spin_rate: Value | None = None
    perturbation: Value | None = None
    perturbation_azimuth: Value | None = None
    torques: dict[str, Value] = {}

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any) -> Any:
        # The torque models' parameters are not fields: they come from the registry.
        if not isinstance(data, dict):
            return data
        torques = torque_parameters()
        known = [name for name in cls.model_fields if name != "torques"] + list(torques)
        own = {}
        for key, value in data.items():
            if key not in known:
                raise unknown_key(str(key), known)
            if key not in torques:
                own[key] = value
        return {**own, "torques": {k: v for k, v in data.items() if k in torques}}

    def value(self, name: str) -> Any:
        """The value given for a per-body parameter, or None."""
        return self.torques.get(name) if name in self.torques else getattr(self, name, None)


class Vary(StrictModel):
    """``[vary.NAME]``: a grid or a random draw of one parameter."""

    values: list[Value] | None = None
    start: Value | None = None
    stop: Value | None = None
    num: Annotated[StrictInt, Field(ge=1, le=10_000_000)] | None = None
    scale: Literal["linear", "log"] | None = None
    distribution: Literal["uniform", "loguniform", "spherical"] | None = None
    min: Value | None = None
    max: Value | None = None
    unit: StrictStr | None = None


class Outputs(StrictModel):
    """``[outputs]``: what is stored per body."""

    metrics: list[MetricName] = [
        "flips",
        "first_flip_time",
        "max_nutation",
        "energy_drift",
        "momentum_drift",
    ]
    final_state: StrictBool = True
    initial_state: StrictBool = True


class MapTable(StrictModel):
    """One map of the report."""

    x: StrictStr
    y: StrictStr | None = None
    metric: MetricName
    statistic: Literal["mean", "min", "max"] = "mean"
    bins: Annotated[StrictInt, Field(ge=1, le=1000)] = 40


class Report(StrictModel):
    """``[report]``: the maps of report.html (default: each metric over the first
    two varied parameters)."""

    maps: list[MapTable] | None = None


class DaskTable(StrictModel):
    """``[dask]``: where to run, unless the command line says otherwise."""

    scheduler: StrictStr | None = None
    workers: Annotated[StrictInt, Field(ge=1)] | None = None


class SweepFile(StrictModel):
    """A whole sweep file."""

    sweep: SweepTable
    base: Base
    vary: dict[str, Vary] = {}
    outputs: Outputs = Outputs()
    report: Report = Report()
    dask: DaskTable = DaskTable()

    @model_validator(mode="before")
    @classmethod
    def _parameter_names(cls, data: Any) -> Any:
        if isinstance(data, dict) and isinstance(data.get("vary"), dict):
            known = list(PARAMETERS)
            for key in data["vary"]:
                if key not in known:
                    close = difflib.get_close_matches(str(key), known, n=1)
                    hint = f" Did you mean `{close[0]}`?" if close else ""
                    raise key_error(
                        ("vary", str(key)),
                        f"Expected a parameter ({', '.join(known)}), got "
                        f"`{key_text(str(key))}`.{hint}",
                    )
        return data


def check_address(address: str) -> str:
    """A Dask scheduler address ``tcp://HOST:PORT`` (or ``tls://``), checked."""
    import re

    if not re.fullmatch(r"(tcp|tls)://[^\s:/]+:\d{1,5}", address.strip()):
        raise InputError(
            f"Expected a Dask scheduler address such as 'tcp://127.0.0.1:8786', got {address!r}."
        )
    return address.strip()
