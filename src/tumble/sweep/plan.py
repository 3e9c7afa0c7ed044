"""A validated sweep in SI, and the bodies of each of its chunks.

A :class:`Plan` is what a sweep file becomes once checked: plain floats and
numpy arrays, small, picklable, and free of pydantic and pint, so it can be
sent to Dask workers. Everything a chunk needs is computed from the plan and
the chunk's index alone:

* body ``b`` sits at grid point ``b // samples`` (C order over the grid
  parameters, in the order of the file) and is random draw ``b % samples``
  there;
* the random draws of chunk ``c`` come from a generator seeded with
  ``SeedSequence(seed, spawn_key=(c,))``, the parameters drawn in the order
  of the file, so a chunk's bodies do not depend on which chunks ran before,
  where, or how often.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.torques import TORQUES, Parameter, TorqueModel, TorqueSum
from tumble.units import SI_UNITS

Array = NDArray[np.float64]

#: The parameters of the bodies themselves a sweep may fix in [base] or vary in
#: [vary]: kind of quantity (a key of :data:`tumble.units.SI_UNITS`, or "axis")
#: and meaning. The bodies' axes are their principal axes.
BODY_PARAMETERS: dict[str, tuple[str, str]] = {
    "moment_1": ("inertia", "principal moment I1, kg·m²"),
    "moment_2": ("inertia", "principal moment I2, kg·m²"),
    "moment_3": ("inertia", "principal moment I3, kg·m²"),
    "ratio_2": ("dimensionless", "I2 / I1"),
    "ratio_3": ("dimensionless", "I3 / I1"),
    "spin_axis": ("axis", "principal axis (1, 2 or 3) the body is spun about"),
    "spin_rate": ("angular_velocity", "|ω| at t = 0, rad/s"),
    "perturbation": ("angle", "angle between ω and the spin axis at t = 0, rad"),
    "perturbation_azimuth": (
        "angle",
        "direction of the perturbation about the spin axis, rad, from the next axis "
        "(cyclic: 1 → 2 → 3 → 1) towards the one after",
    ),
}

#: Values of the body parameters a sweep file leaves out (a torque parameter left
#: out is zero: no torque of that model).
BODY_DEFAULTS: dict[str, float] = {
    "spin_axis": 3.0,
    "perturbation": 0.0,
    "perturbation_azimuth": 0.0,
}


@dataclass(frozen=True)
class TorqueParameter:
    """A per-body sweep parameter of a torque model: component ``component`` (None
    for a number) of the model's ``parameter``."""

    model: type[TorqueModel]
    parameter: Parameter
    component: int | None


def torque_parameters() -> dict[str, TorqueParameter]:
    """The sweep parameters of the torque models that batches accept and whose every
    parameter has sweep names, by name, read from the torque registry
    (:data:`tumble.torques.TORQUES`)."""
    found = {}
    for model in TORQUES.values():
        if not (model.in_batches and all(p.sweep for p in model.parameters)):
            continue
        for parameter in model.parameters:
            for k, name in enumerate(parameter.sweep):
                found[name] = TorqueParameter(model, parameter, k if parameter.shape else None)
    return found


class _Parameters(Mapping[str, tuple[str, str]]):
    """Every per-body parameter: the bodies' own, then those of the torque models
    registered when it is read (kind of quantity, meaning)."""

    def _all(self) -> dict[str, tuple[str, str]]:
        found = dict(BODY_PARAMETERS)
        for name, entry in torque_parameters().items():
            unit = SI_UNITS[entry.parameter.kind].replace("*", "·")
            component = "" if entry.component is None else f", component {entry.component + 1}"
            found[name] = (
                entry.parameter.kind,
                f"{entry.model.__name__}: {entry.parameter.description}{component}, {unit}",
            )
        return found

    def __getitem__(self, name: str) -> tuple[str, str]:
        return self._all()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._all())

    def __len__(self) -> int:
        return len(self._all())


#: The per-body parameters a sweep may fix in [base] or vary in [vary]: kind of
#: quantity (a key of :data:`tumble.units.SI_UNITS`, or "axis") and meaning.
PARAMETERS: Mapping[str, tuple[str, str]] = _Parameters()


def defaults() -> dict[str, float]:
    """Values of the parameters a sweep file leaves out."""
    return {**BODY_DEFAULTS, **dict.fromkeys(torque_parameters(), 0.0)}


#: Per-body measures a sweep can record, with their units and meaning.
METRICS: dict[str, tuple[str, str]] = {
    "flips": (
        "",
        "number of flips: sign changes of the angular velocity's component along the spin "
        "axis (the spin axis crossing the plane perpendicular to L)",
    ),
    "first_flip_time": ("s", "time of the first flip (NaN when none)"),
    "max_nutation": ("rad", "largest angle between the spin axis and L over the run"),
    "energy_drift": ("", "largest |E − E0| / E0 over the run"),
    "momentum_drift": ("", "largest ||L| − |L0|| / |L0| over the run"),
}

DISTRIBUTIONS = ("uniform", "loguniform", "spherical")

#: Version of the layout of the output folder and of the plan's identity.
FORMAT = 1


@dataclass(frozen=True)
class GridAxis:
    """A parameter that takes each of ``values`` (SI) in turn."""

    name: str
    values: Array


@dataclass(frozen=True)
class RandomAxis:
    """A parameter drawn per body: ``uniform`` or ``loguniform`` on [low, high],
    or ``spherical`` (an angle θ from an axis, with cos θ uniform: directions
    uniform on the sphere between the polar angles low and high)."""

    name: str
    distribution: str
    low: float
    high: float


@dataclass(frozen=True)
class MapSpec:
    """A map in the report: ``statistic`` of ``metric`` over parameters x, y
    (y None: a curve over x); random parameters are binned in ``bins``."""

    x: str
    y: str | None
    metric: str
    statistic: str = "mean"
    bins: int = 40


@dataclass(frozen=True, eq=False)
class Plan:
    """A sweep in SI: fixed parameters, grid and random axes, the run, the outputs,
    where it runs (``timeout``: seconds a Dask scheduler has to answer; None: the
    default, :data:`tumble.sweep.dask_backend.CONNECT_TIMEOUT`), and the parts every
    body carries (:class:`tumble.parts.InternalPart`, held in its moments)."""

    name: str
    description: str
    fixed: dict[str, float]
    grid: tuple[GridAxis, ...]
    random: tuple[RandomAxis, ...]
    samples: int
    seed: int
    chunk_size: int
    duration: float
    dt: float
    n_steps: int
    method: str
    metrics: tuple[str, ...]
    final_state: bool
    initial_state: bool
    maps: tuple[MapSpec, ...] = ()
    scheduler: str | None = None
    workers: int | None = None
    timeout: float | None = None
    text: str = field(default="", repr=False)
    parts: tuple[Any, ...] = ()

    # ------------------------------------------------------------ sizes
    @property
    def grid_shape(self) -> tuple[int, ...]:
        return tuple(len(axis.values) for axis in self.grid)

    @property
    def n_bodies(self) -> int:
        return math.prod(self.grid_shape) * self.samples

    @property
    def n_chunks(self) -> int:
        return -(-self.n_bodies // self.chunk_size)

    @property
    def varied(self) -> tuple[str, ...]:
        """Names of the grid and random parameters, in the order of the file."""
        return tuple(a.name for a in self.grid) + tuple(a.name for a in self.random)

    def chunk_range(self, index: int) -> tuple[int, int]:
        """Bodies ``[start, stop)`` of chunk ``index``."""
        start = index * self.chunk_size
        return start, min(start + self.chunk_size, self.n_bodies)

    # --------------------------------------------------------- identity
    def identity(self) -> dict[str, Any]:
        """Everything that decides the results, as JSON-ready values (floats
        written exactly by ``repr``): two sweeps with the same identity give the
        same bits. Names, descriptions, maps and where it runs are left out (and
        the parts, when there are none: the identity of a sweep without parts is
        what it was before sweeps took them)."""
        parts = {"parts": [part.describe() for part in self.parts]} if self.parts else {}
        return {
            "format": FORMAT,
            "fixed": {k: self.fixed[k] for k in sorted(self.fixed)},
            "grid": [{"name": a.name, "values": a.values.tolist()} for a in self.grid],
            "random": [
                {"name": a.name, "distribution": a.distribution, "low": a.low, "high": a.high}
                for a in self.random
            ],
            "samples": self.samples,
            "seed": self.seed,
            "chunk_size": self.chunk_size,
            "duration": self.duration,
            "dt": self.dt,
            "n_steps": self.n_steps,
            "method": self.method,
            "metrics": list(self.metrics),
            "final_state": self.final_state,
            "initial_state": self.initial_state,
            **parts,
        }

    # ----------------------------------------------------------- bodies
    def grid_indices(self, start: int, stop: int) -> tuple[NDArray[np.int64], ...]:
        """For bodies ``[start, stop)``, the index into each grid axis's values."""
        bodies = np.arange(start, stop, dtype=np.int64)
        if not self.grid:
            return ()
        return tuple(
            np.asarray(i, dtype=np.int64)
            for i in np.unravel_index(bodies // self.samples, self.grid_shape)
        )

    def chunk_parameters(self, index: int) -> dict[str, Array]:
        """Every parameter of chunk ``index``'s bodies, (n,) arrays in SI."""
        start, stop = self.chunk_range(index)
        n = stop - start
        values: dict[str, Array] = {}
        for axis, where in zip(self.grid, self.grid_indices(start, stop), strict=True):
            values[axis.name] = axis.values[where]
        if self.random:
            rng = np.random.Generator(
                np.random.PCG64(np.random.SeedSequence(self.seed, spawn_key=(index,)))
            )
            for draw in self.random:
                values[draw.name] = _draw(rng, draw, n)
        for name, value in self.fixed.items():
            values[name] = np.full(n, value)
        return values

    def bodies(self, values: dict[str, Array]) -> Bodies:
        """Principal moments, initial ω, spin axes and torque of bodies with these
        parameters (from :meth:`chunk_parameters`)."""
        i1 = values["moment_1"]
        i2 = values["moment_2"] if "moment_2" in values else values["ratio_2"] * i1
        i3 = values["moment_3"] if "moment_3" in values else values["ratio_3"] * i1
        n = len(i1)
        axis = values["spin_axis"].astype(np.int64) - 1
        theta = values["perturbation"]
        phi = values["perturbation_azimuth"]
        rate = values["spin_rate"]
        rows = np.arange(n)
        omega = np.empty((n, 3))
        omega[rows, axis] = rate * np.cos(theta)
        omega[rows, (axis + 1) % 3] = rate * np.sin(theta) * np.cos(phi)
        omega[rows, (axis + 2) % 3] = rate * np.sin(theta) * np.sin(phi)
        unit = np.zeros((3, n))
        unit[axis, rows] = 1.0
        return Bodies(np.column_stack([i1, i2, i3]), omega, unit, self.torque(values))

    def torque(self, values: dict[str, Array]) -> TorqueModel | None:
        """The torque models of bodies with these parameters: one value per body for a
        model with a varied parameter, one for all otherwise; models whose
        parameters are all zero are left out."""
        by_model: dict[type[TorqueModel], dict[str, list[tuple[int | None, str]]]] = {}
        for name, entry in torque_parameters().items():
            fields = by_model.setdefault(entry.model, {})
            fields.setdefault(entry.parameter.name, []).append((entry.component, name))
        n = len(values["moment_1"])
        values = {**{name: np.zeros(n) for name in torque_parameters()}, **values}
        terms = []
        for model, fields in by_model.items():
            names = [name for components in fields.values() for _, name in components]
            if not any(np.any(values[name]) for name in names):
                continue
            varied = any(name in self.varied for name in names)
            arguments: dict[str, Any] = {}
            for parameter, components in fields.items():
                columns = [values[name] for _, name in sorted(components, key=_component)]
                stacked = np.column_stack(columns) if len(columns) > 1 else columns[0]
                arguments[parameter] = stacked if varied else stacked[0]
            terms.append(model(**arguments))
        return TorqueSum(tuple(terms)) if terms else None


def _component(entry: tuple[int | None, str]) -> int:
    return entry[0] or 0


@dataclass(frozen=True, eq=False)
class Bodies:
    """Bodies ready for the kernels: ``moments`` (n, 3) kg·m², ``omega`` (n, 3)
    rad/s in principal axes, ``axis`` (3, n) unit spin axes, ``torque`` the
    torque models (per body or shared), or None."""

    moments: Array
    omega: Array
    axis: Array
    torque: TorqueModel | None


def _draw(rng: np.random.Generator, draw: RandomAxis, n: int) -> Array:
    u = rng.random(n)
    if draw.distribution == "uniform":
        return draw.low + u * (draw.high - draw.low)
    if draw.distribution == "loguniform":
        low, high = math.log(draw.low), math.log(draw.high)
        return np.exp(low + u * (high - low))
    # spherical: cos θ uniform between cos(low) and cos(high)
    top, bottom = math.cos(draw.low), math.cos(draw.high)
    return np.arccos(np.clip(top + u * (bottom - top), -1.0, 1.0))
