"""From a structurally valid sweep file to a :class:`~tumble.sweep.plan.Plan` in SI:
values converted with their units and checked together (ranges, the triangle
inequality of the moments at every corner of the swept box, a coarse step),
each error one :class:`~tumble.sweep.schema.SweepError` naming the file, the
line and the key path.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import contextmanager
from itertools import product
from typing import Any

import numpy as np

from tumble.config import validate_toml, where
from tumble.errors import InputError
from tumble.integrators import INTEGRATORS, methods_for
from tumble.sweep.plan import (
    DISTRIBUTIONS,
    PARAMETERS,
    GridAxis,
    MapSpec,
    Plan,
    RandomAxis,
    defaults,
    torque_parameters,
)
from tumble.sweep.schema import MAX_GRID_VALUES, SweepError, SweepFile, Vary, check_address

__all__ = ["MAX_COUNT", "PlanBuilder", "parse_sweep"]

#: The most steps per body, and bodies, a sweep may have: 2**53, below which
#: float64 counts them exactly (the step times k·dt stay distinct), and far beyond
#: any run (2**53 body-steps at a billion a second take a hundred days).
MAX_COUNT = 2**53


def parse_sweep(text: str, source: str = "<sweep>") -> Plan:
    """Validate sweep text and convert it to a :class:`Plan` in SI.

    Raises
    ------
    SweepError
        Invalid TOML, or the first problem in the sweep.

    Warns
    -----
    tumble.CoarseStepWarning
        When ``dt`` gives fewer than 20 steps per turn at the fastest spin rate.
    """
    spec = validate_toml(
        SweepFile, text, source, error=SweepError, key_path=_key_path, name_input=True
    )
    return PlanBuilder(spec, text, source).plan()


def _key_path(loc: tuple[Any, ...]) -> list[Any]:
    """The key path of the file from pydantic's location: without the tags of the
    union of a value's types (a number or a quantity)."""
    return [part for part in loc if part not in ("int", "float", "str")]


class PlanBuilder:
    """Turns a structurally valid :class:`SweepFile` into a :class:`Plan`."""

    def __init__(self, spec: SweepFile, text: str, source: str) -> None:
        self.spec = spec
        self.text = text
        self.source = source

    @contextmanager
    def at(self, *path: Any) -> Iterator[None]:
        """Prefix an InputError raised inside with the file, line and key path."""
        try:
            yield
        except SweepError:
            raise
        except InputError as exc:
            raise SweepError(f"{where(self.text, self.source, path)}: {exc}") from None

    def fail(self, path: tuple[Any, ...], message: str) -> SweepError:
        return SweepError(f"{where(self.text, self.source, path)}: {message}")

    def si(self, value: Any, kind: str, path: tuple[Any, ...], unit: str | None = None) -> float:
        from tumble.units import to_si

        # The key's own name; a list entry is named by its parameter.
        name = next(str(p) for p in reversed(path) if isinstance(p, str) and p != "values")
        with self.at(*path):
            if kind == "axis":
                if isinstance(value, bool) or value not in (1, 2, 3):
                    raise InputError(f"Expected `{name}` to be 1, 2 or 3, got {value!r}.")
                return float(value)
            if unit is not None and not isinstance(value, str):
                return float(value) * to_si(f"1 {unit}", kind, "unit")
            return to_si(value, kind, name)

    # --------------------------------------------------------------- plan
    def plan(self) -> Plan:
        spec = self.spec
        fixed = self.fixed()
        self.check_grid_size()  # before the grid's values are built
        axes = [self.axis(name, vary) for name, vary in spec.vary.items()]
        grid = [axis for axis in axes if isinstance(axis, GridAxis)]
        random = [axis for axis in axes if isinstance(axis, RandomAxis)]
        for name, value in defaults().items():
            if name not in fixed and name not in spec.vary:
                fixed[name] = value
        varied = set(spec.vary)
        self.check_given(set(fixed) | varied, varied)
        ranges = {name: (value, value) for name, value in fixed.items()}
        for axis in grid:
            ranges[axis.name] = (float(axis.values.min()), float(axis.values.max()))
        for draw in random:
            ranges[draw.name] = (draw.low, draw.high)
        self.check_ranges(ranges, varied)
        self.check_triangle(ranges)
        duration, n_steps = self.steps()
        if INTEGRATORS[spec.base.method].kind != "sampling":  # a closed form takes no steps
            self.warn_coarse(ranges, duration / n_steps)
        parts = self.parts(ranges)
        maps = self.maps(tuple(spec.vary), tuple(spec.outputs.metrics))
        scheduler, timeout = self.dask()
        plan = Plan(
            name=spec.sweep.name,
            description=spec.sweep.description,
            fixed=fixed,
            grid=tuple(grid),
            random=tuple(random),
            samples=spec.sweep.samples,
            seed=spec.sweep.seed,
            chunk_size=spec.sweep.chunk_size,
            duration=duration,
            dt=duration / n_steps,
            n_steps=n_steps,
            method=spec.base.method,
            metrics=tuple(dict.fromkeys(spec.outputs.metrics)),
            final_state=spec.outputs.final_state,
            initial_state=spec.outputs.initial_state,
            maps=maps,
            scheduler=scheduler,
            workers=spec.dask.workers,
            timeout=timeout,
            text=self.text,
            parts=parts,
        )
        self.check_limits(plan)
        return plan

    def fixed(self) -> dict[str, float]:
        """The parameters [base] gives (SI), refused where [vary] varies them too."""
        spec = self.spec
        fixed: dict[str, float] = {}
        for name, (kind, _) in PARAMETERS.items():
            value = spec.base.value(name)
            if value is None:
                continue
            if name in spec.vary:
                raise self.fail(
                    ("vary", name),
                    f"Expected `{name}` in [base] or in [vary], not both, got both.",
                )
            fixed[name] = self.si(value, kind, ("base", name))
        return fixed

    def check_given(self, given: set[str], varied: set[str]) -> None:
        """Refuse a body given twice (a moment and its ratio) or not at all."""
        for first, second in (("moment_2", "ratio_2"), ("moment_3", "ratio_3")):
            if first in given and second in given:
                key = ("vary", second) if second in varied else ("base", second)
                raise self.fail(
                    key, f"Expected one of `{first}` and `{second}`, not both, got both."
                )
        for needed in (
            ("moment_1",),
            ("moment_2", "ratio_2"),
            ("moment_3", "ratio_3"),
            ("spin_rate",),
        ):
            if not any(n in given for n in needed):
                names = " or ".join(f"`{n}`" for n in needed)
                raise self.fail(("base",), f"Expected {names} in [base] or [vary], got neither.")

    def steps(self) -> tuple[float, int]:
        """The duration (s) and the whole number of steps that span it."""
        base = self.spec.base
        duration = self.si(base.duration, "time", ("base", "duration"))
        dt = self.si(base.dt, "time", ("base", "dt"))
        if not duration > 0:
            raise self.fail(("base", "duration"), f"Expected `duration` > 0 s, got {duration!r}.")
        if not dt > 0:
            raise self.fail(("base", "dt"), f"Expected `dt` > 0 s, got {dt!r}.")
        steps = duration / dt
        if not steps <= MAX_COUNT:
            raise self.fail(
                ("base", "dt"),
                f"Expected at most 2**53 steps per body (duration / dt), got {steps:.3g} from "
                f"duration = {duration!r} s and dt = {dt!r} s.",
            )
        return duration, max(1, math.ceil(steps * (1 - 1e-12)))

    def dask(self) -> tuple[str | None, float | None]:
        """[dask]'s scheduler address (checked) and timeout (s), if given."""
        spec = self.spec
        scheduler = spec.dask.scheduler
        if scheduler is not None and spec.dask.workers is not None:
            raise self.fail(
                ("dask",),
                "Expected at most one of `scheduler` and `workers` in [dask], got both.",
            )
        if scheduler is not None:
            with self.at("dask", "scheduler"):
                check_address(scheduler)
        timeout = None
        if spec.dask.timeout is not None:
            timeout = self.si(spec.dask.timeout, "time", ("dask", "timeout"))
            if not (math.isfinite(timeout) and timeout > 0):
                raise self.fail(("dask", "timeout"), f"Expected `timeout` > 0 s, got {timeout!r}.")
        return scheduler, timeout

    def check_grid_size(self) -> None:
        """Refuse, from the file alone, a grid whose values sweep.json could not
        list (:data:`~tumble.sweep.schema.MAX_GRID_VALUES`) or whose bodies could
        not be counted exactly."""
        spec = self.spec
        counts = {}
        for name, vary in spec.vary.items():
            if vary.values is not None:
                counts[name] = len(vary.values)
            elif vary.num is not None and vary.distribution is None:
                counts[name] = vary.num
        total = sum(counts.values())
        if total > MAX_GRID_VALUES:
            listed = ", ".join(f"{name}: {count}" for name, count in counts.items())
            raise self.fail(
                ("vary",),
                f"Expected at most {MAX_GRID_VALUES:.0e} grid values in all (sweep.json and "
                f"the store list them), got {total:.3g} ({listed}): draw a parameter at "
                "random (`distribution`, `min`, `max`) to sample it finely.",
            )
        bodies = math.prod(counts.values()) * spec.sweep.samples
        if bodies > MAX_COUNT:
            raise self.fail(
                ("sweep", "samples") if spec.sweep.samples > 1 else ("vary",),
                f"Expected at most 2**53 bodies (grid points × samples), got {bodies:.3g}.",
            )

    def check_limits(self, plan: Plan) -> None:
        """Refuse a sweep whose work or results exceed its [limits], with the estimate."""
        from tumble.resources import format_bytes
        from tumble.sweep.metrics import body_bytes

        limits = self.spec.limits
        bodies = plan.n_bodies
        stepping = INTEGRATORS[plan.method].kind != "sampling"  # a closed form: one a body
        work = bodies * (plan.n_steps if stepping else 1)
        if work > limits.max_body_steps:
            each = f"{plan.n_steps:.6g} steps" if stepping else "1 evaluation of the closed form"
            raise self.fail(
                ("limits", "max_body_steps"),
                f"Expected at most max_body_steps = {limits.max_body_steps:.6g} body-steps "
                f"(bodies × steps per body), got {bodies:.6g} bodies × {each} = {work:.6g}: "
                "raise `max_body_steps` in [limits] to run it, or ask for fewer bodies or steps.",
            )
        each_body = body_bytes(plan)
        size = bodies * each_body
        if size > limits.max_store_bytes:
            most = limits.max_store_bytes
            raise self.fail(
                ("limits", "max_store_bytes"),
                f"Expected results of at most max_store_bytes = {most:.6g} bytes "
                f"({format_bytes(most)}), got {bodies:.6g} bodies × {each_body} bytes = "
                f"{size:.3g} bytes ({format_bytes(size)}) uncompressed: raise "
                "`max_store_bytes` in [limits] to run it (the disk must hold it), or ask for "
                "fewer bodies or outputs.",
            )

    def axis(self, name: str, vary: Vary) -> GridAxis | RandomAxis:
        kind = PARAMETERS[name][0]
        path = ("vary", name)
        given = [k for k in type(vary).model_fields if getattr(vary, k) is not None and k != "unit"]
        forms = {
            "values": {"values"},
            "range": {"start", "stop", "num", "scale"},
            "random": {"distribution", "min", "max"},
        }
        used = [form for form, keys in forms.items() if keys & set(given)]
        if len(used) != 1:
            raise self.fail(
                path,
                "Expected a grid (`values`, or `start`, `stop`, `num`) or a random draw "
                "(`distribution`, `min`, `max`), got "
                + (", ".join(f"`{k}`" for k in given) if given else "no keys")
                + ".",
            )
        if vary.unit is not None and kind == "axis":
            raise self.fail((*path, "unit"), f"Expected no `unit` for `{name}`, got {vary.unit!r}.")
        form = used[0]
        if form == "values":
            assert vary.values is not None
            if not vary.values:
                raise self.fail((*path, "values"), "Expected at least one value, got none.")
            values = np.array(
                [
                    self.si(v, kind, (*path, "values", k), vary.unit)
                    for k, v in enumerate(vary.values)
                ]
            )
            return GridAxis(name, values)
        if kind == "axis":
            raise self.fail(
                path, f"Expected `values` for `{name}` (a list of axes 1, 2, 3), got {given[0]!r}."
            )
        if form == "range":
            return self.range_axis(name, vary)
        return self.random_axis(name, vary)

    def require(self, vary: Vary, path: tuple[str, ...], keys: tuple[str, ...]) -> None:
        """Refuse an axis that lacks one of the ``keys`` its form needs."""
        together = ", ".join(f"`{k}`" for k in keys)
        for key in keys:
            if getattr(vary, key) is None:
                message = f"Expected `{key}` with {together}, which is missing."
                raise self.fail((*path, key), message)

    def range_axis(self, name: str, vary: Vary) -> GridAxis:
        """A grid from `start` to `stop` in `num` values, evenly or on a log scale."""
        kind = PARAMETERS[name][0]
        path = ("vary", name)
        self.require(vary, path, ("start", "stop", "num"))
        assert vary.num is not None
        start = self.si(vary.start, kind, (*path, "start"), vary.unit)
        stop = self.si(vary.stop, kind, (*path, "stop"), vary.unit)
        if vary.scale == "log":
            if not (start > 0 and stop > 0):
                raise self.fail(
                    (*path, "start"),
                    f"Expected `start` and `stop` > 0 for a log scale, got {start!r} and {stop!r}.",
                )
            return GridAxis(name, np.geomspace(start, stop, vary.num))
        return GridAxis(name, np.linspace(start, stop, vary.num))

    def random_axis(self, name: str, vary: Vary) -> RandomAxis:
        """A parameter drawn at random between `min` and `max` by `distribution`."""
        kind = PARAMETERS[name][0]
        path = ("vary", name)
        self.require(vary, path, ("distribution", "min", "max"))
        assert vary.distribution in DISTRIBUTIONS
        low = self.si(vary.min, kind, (*path, "min"), vary.unit)
        high = self.si(vary.max, kind, (*path, "max"), vary.unit)
        if not low <= high:
            raise self.fail((*path, "max"), f"Expected `max` >= `min` ({low!r}), got {high!r}.")
        if vary.distribution == "loguniform" and not low > 0:
            raise self.fail(
                (*path, "min"), f"Expected `min` > 0 for a loguniform draw, got {low!r}."
            )
        if vary.distribution == "spherical":
            if kind != "angle":
                raise self.fail(
                    (*path, "distribution"),
                    f"Expected a 'spherical' draw only for an angle, got it for `{name}` "
                    f"({kind.replace('_', ' ')}).",
                )
            if not (low >= 0 and high <= math.pi):
                raise self.fail(
                    (*path, "min"),
                    f"Expected polar angles in [0, π] for a 'spherical' draw, got [{low!r}, "
                    f"{high!r}] rad.",
                )
        return RandomAxis(name, vary.distribution, low, high)

    def check_ranges(self, ranges: dict[str, tuple[float, float]], varied: set[str]) -> None:
        limits: dict[str, tuple[str, Any]] = {
            "moment_1": ("> 0", lambda v: v > 0),
            "moment_2": ("> 0", lambda v: v > 0),
            "moment_3": ("> 0", lambda v: v > 0),
            "ratio_2": ("> 0", lambda v: v > 0),
            "ratio_3": ("> 0", lambda v: v > 0),
            "spin_rate": (">= 0", lambda v: v >= 0),
        }
        for name, entry in torque_parameters().items():
            least = entry.parameter.minimum
            if least is not None:
                limits[name] = (f">= {least:g}", lambda v, least=least: v >= least)
        for name, (text, ok) in limits.items():
            if name not in ranges:
                continue
            low = ranges[name][0]
            if not ok(low):
                path = ("vary", name) if name in varied else ("base", name)
                kind = PARAMETERS[name][0]
                from tumble.units import SI_UNITS

                unit = f" {SI_UNITS[kind]}" if SI_UNITS[kind] else ""
                raise self.fail(
                    path, f"Expected `{name}` {text}{unit} for every body, got {low!r}."
                )

    def check_triangle(self, ranges: dict[str, tuple[float, float]]) -> None:
        """Principal moments must satisfy I1 + I2 >= I3 (and cyclic) for every body.
        Each condition is multilinear in the parameters, so it holds on the whole
        box of parameter ranges when it holds at the box's corners."""
        names = [
            n for n in ("moment_1", "moment_2", "ratio_2", "moment_3", "ratio_3") if n in ranges
        ]
        for corner in product(*(ranges[n] for n in names)):
            v = dict(zip(names, corner, strict=True))
            i1 = v["moment_1"]
            i2 = v["moment_2"] if "moment_2" in v else v["ratio_2"] * i1
            i3 = v["moment_3"] if "moment_3" in v else v["ratio_3"] * i1
            a, b, c = sorted((i1, i2, i3))
            if a + b < c * (1 - 1e-9):
                corner_values = ", ".join(f"{n} = {v[n]:.6g}" for n in names)
                key = next((("vary", n) for n in names if n in self.spec.vary), ("base", names[-1]))
                raise self.fail(
                    key,
                    "Expected principal moments satisfying the triangle inequality "
                    "(I1 + I2 >= I3 and cyclic) for every body, got "
                    f"I1, I2, I3 = {i1:.6g}, {i2:.6g}, {i3:.6g} kg·m² at {corner_values}.",
                )

    def parts(self, ranges: dict[str, tuple[float, float]]) -> tuple[Any, ...]:
        """The ``[[internal]]`` parts every body carries, checked against the sweep: given
        by their inertia (held in the swept moments), taken by batches, by the method
        and, for ``energy_drift``, with their energy's equation; their spin inertia
        left inside every body's moments."""
        from tumble.body import ZERO_MOMENT
        from tumble.parts import TableKeyError

        parts = []
        for k, spec in enumerate(self.spec.internal):
            try:
                read = spec.file_part()
            except TableKeyError as exc:
                raise self.fail(("internal", k, exc.key), str(exc)) from None
            except InputError as exc:
                raise self.fail(("internal", k), str(exc)) from None
            part = read.part
            if part.not_in_batches is not None:
                raise self.fail(
                    ("internal", k),
                    f"Expected parts that batches take, got a {part.kind} "
                    f"({part.not_in_batches.replace(': use simulate', '')}).",
                )
            if read.solid is not None:
                raise self.fail(
                    ("internal", k),
                    f"Expected parts held in the swept moments (given by their `inertia`), "
                    f"got a {part.kind} given by its mass, which would add to each body: "
                    "give its `inertia` and count it in the moments.",
                )
            parts.append(part)
        if not parts:
            return ()
        method = INTEGRATORS[self.spec.base.method]
        if method.parts_metrics is None or not method.handles(parts):
            able = methods_for(parts, "parts_metrics")
            kinds = ", ".join(sorted({part.kind for part in parts}))
            raise self.fail(
                ("base", "method"),
                f"Expected a method that measures bodies carrying {kinds} parts "
                f"({', '.join(able)}), got {method.name!r}.",
            )
        if "energy_drift" in self.spec.outputs.metrics:
            lacking = sorted({p.kind for p in parts if p.equations.energy is None})
            if lacking:
                raise self.fail(
                    ("outputs", "metrics"),
                    f"Expected parts whose energy can be measured for `energy_drift`, got "
                    f"{', '.join(lacking)} parts, whose equations leave it out "
                    "(PartEquations.energy).",
                )
        # The platform's smallest moment grows with every swept moment and ratio
        # (a positive diagonal added), so the box's lowest corner is the worst.
        low = {name: bounds[0] for name, bounds in ranges.items()}
        i1 = low["moment_1"]
        moments = [
            i1,
            low.get("moment_2", low.get("ratio_2", 0.0) * i1),
            low.get("moment_3", low.get("ratio_3", 0.0) * i1),
        ]
        platform = np.diag(moments) - sum(part.spin_inertia() for part in parts)
        left = np.linalg.eigvalsh(platform)
        if not left[0] > ZERO_MOMENT * max(moments):
            raise self.fail(
                ("internal",),
                "Expected internal parts whose spin inertia every body can hold (each "
                "part's spin inertia taken from the swept moments must leave positive "
                f"principal moments), got {np.round(left, 12).tolist()} kg·m² left at the "
                f"smallest moments {moments} kg·m².",
            )
        return tuple(parts)

    def warn_coarse(self, ranges: dict[str, tuple[float, float]], dt: float) -> None:
        from tumble.integrators.steps import warn_if_coarse

        # Warned from parse_sweep's caller: this method, plan(), parse_sweep, caller.
        warn_if_coarse(dt, ranges["spin_rate"][1], "the fastest spin", stacklevel=5)

    def maps(self, varied: tuple[str, ...], metrics: tuple[str, ...]) -> tuple[MapSpec, ...]:
        tables = self.spec.report.maps
        if tables is None:
            if not varied:
                return ()
            y = varied[1] if len(varied) > 1 else None
            return tuple(MapSpec(varied[0], y, m) for m in dict.fromkeys(metrics))
        out = []
        for k, table in enumerate(tables):
            for key in ("x", "y"):
                name = getattr(table, key)
                if name is not None and name not in varied:
                    raise self.fail(
                        ("report", "maps", k, key),
                        f"Expected a varied parameter ({', '.join(varied) or 'none'}), "
                        f"got {name!r}.",
                    )
            if table.metric not in metrics:
                raise self.fail(
                    ("report", "maps", k, "metric"),
                    f"Expected a metric listed in [outputs] ({', '.join(metrics)}), got "
                    f"{table.metric!r}.",
                )
            out.append(MapSpec(table.x, table.y, table.metric, table.statistic, table.bins))
        return tuple(out)
