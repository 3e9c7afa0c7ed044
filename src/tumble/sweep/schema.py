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
* ``[[internal]]``: the parts every body carries, as in scenario files
  (:mod:`tumble.config.parts`), given by their ``inertia``: the swept moments
  are the whole body's, its parts locked inside;
* ``[outputs]``: ``metrics`` (a list of :data:`~tumble.sweep.plan.METRICS`),
  ``final_state``, ``initial_state``;
* ``[report]``: ``maps = [{x, y, metric, statistic, bins}]``;
* ``[dask]``: ``scheduler = "tcp://HOST:PORT"`` or ``workers = N``, and
  ``timeout`` for the scheduler's answer;
* ``[limits]``: ``max_body_steps`` and ``max_store_bytes``, the largest sweep
  accepted (a larger one is refused, with its estimate, before anything is built
  or written).

Pydantic checks the structure (types, required and unknown keys); the values
are then converted to SI with :mod:`tumble.units` and checked together
(ranges, the triangle inequality of the moments at every corner of the swept
box). Every error is one :class:`SweepError` naming the file, the line, the
key path, what was expected and what was given.
"""

from __future__ import annotations

from functools import partial
from typing import Annotated, Any, Literal

from pydantic import (
    BeforeValidator,
    Field,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
    model_validator,
)
from pydantic_core import PydanticCustomError

from tumble.config import (
    ConfigError,
    StrictModel,
    key_error,
    shown,
    unknown_key,
)
from tumble.config.parts import InternalSpec
from tumble.config.registries import method_choice
from tumble.errors import InputError, quoted, unknown_choice
from tumble.sweep.plan import (
    PARAMETERS,
    torque_parameters,
)

__all__ = [
    "MAX_BODY_STEPS",
    "MAX_GRID_VALUES",
    "MAX_STORE_BYTES",
    "SweepError",
    "SweepFile",
    "check_address",
]

#: Chunk size when the file gives none: 65536 bodies (a few MB of state, 512
#: blocks of the batch kernel, a fraction of a second to a few seconds of work).
DEFAULT_CHUNK_SIZE = 1 << 16

#: The most body-steps (bodies × steps per body; a closed form counts one a body)
#: a sweep may take unless its [limits] says more: about half an hour of the RK4
#: kernels on two cores (5e8 body-steps/s, bench/RESULTS.md).
MAX_BODY_STEPS = 1e12

#: The most bytes of results (uncompressed) a sweep may write unless its [limits]
#: says more: 1e11, about 5e8 bodies with every output.
MAX_STORE_BYTES = 1e11

#: The most grid values of all [vary] tables together: sweep.json and the store's
#: attributes list each one (1e6 take about 20 MB there). Finer sampling is what
#: random draws are for.
MAX_GRID_VALUES = 1_000_000


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
    num: Annotated[StrictInt, Field(ge=1, le=MAX_GRID_VALUES)] | None = None
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
    """``[dask]``: where to run, unless the command line says otherwise: a
    scheduler's address ``tcp://HOST:PORT`` (an IPv6 address in brackets,
    ``tcp://[::1]:8786``; ``tls://`` with Dask's TLS settings), or a local
    cluster of ``workers``; ``timeout``, how long the scheduler has to answer
    (default 10 s)."""

    scheduler: StrictStr | None = None
    workers: Annotated[StrictInt, Field(ge=1)] | None = None
    timeout: Value | None = None


#: A limit: a number >= 1 (1e12 or 1_000_000_000_000).
Limit = Annotated[StrictFloat, Field(ge=1, allow_inf_nan=False)]


class Limits(StrictModel):
    """``[limits]``: the largest sweep accepted. A sweep estimated beyond either is
    refused before anything is built or written, with the estimate; raise them
    here for a sweep meant to be that large. ``max_body_steps``: bodies × steps
    per body (the closed form, ``method = "exact"``, counts one a body);
    ``max_store_bytes``: the results, uncompressed."""

    max_body_steps: Limit = MAX_BODY_STEPS
    max_store_bytes: Limit = MAX_STORE_BYTES


class SweepFile(StrictModel):
    """A whole sweep file."""

    sweep: SweepTable
    base: Base
    vary: dict[str, Vary] = {}
    internal: list[InternalSpec] = []
    outputs: Outputs = Outputs()
    report: Report = Report()
    dask: DaskTable = DaskTable()
    limits: Limits = Limits()

    @model_validator(mode="before")
    @classmethod
    def _parameter_names(cls, data: Any) -> Any:
        if isinstance(data, dict) and isinstance(data.get("vary"), dict):
            known = list(PARAMETERS)
            for key in data["vary"]:
                if key not in known:
                    error = unknown_choice(key, known, "a parameter")
                    raise key_error(("vary", str(key)), str(error))
        return data


def check_address(address: str) -> str:
    """A Dask scheduler address ``tcp://HOST:PORT`` or ``tls://HOST:PORT``, checked:
    HOST a name or an IPv4 address, or an IPv6 address in brackets; PORT 1 to 65535.

    Raises
    ------
    InputError
        Naming what is wrong.
    """
    import ipaddress
    import re

    text = address.strip()
    shown = quoted(text)
    found = re.fullmatch(r"(?:tcp|tls)://(\[[^\]]*\]|[A-Za-z0-9._-]+):([0-9]+)", text)
    if found is None:
        hint = ""
        if re.fullmatch(r"(?:tcp|tls)://[0-9A-Fa-f:.]+:[0-9]+", text) and text.count(":") > 3:
            hint = ": write an IPv6 address in brackets, as in 'tcp://[::1]:8786'"
        raise InputError(
            f"Expected a Dask scheduler address such as 'tcp://127.0.0.1:8786', got {shown}{hint}."
        )
    host, port = found.group(1), int(found.group(2))
    if host.startswith("["):
        try:
            ipaddress.IPv6Address(host[1:-1])
        except ValueError:
            raise InputError(
                "Expected an IPv6 address in the brackets of the Dask scheduler address "
                f"{shown}, got {host[1:-1]!r}."
            ) from None
    if not 1 <= port <= 65535:
        raise InputError(
            f"Expected the port of the Dask scheduler address {shown} to be from 1 to 65535, "
            f"got {port}."
        )
    return text
