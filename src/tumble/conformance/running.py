"""Engines run on a scenario and measured against its exact motion: :func:`run`, :func:`sweep`."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from tumble.conformance.engine import (
    ENGINES,
    Engine,
    Samples,
    engine_class,
    engine_names,
    missing_modules,
    split_name,
)
from tumble.conformance.metrics import METRICS, Reference, measure
from tumble.conformance.scenarios import Scenario, get_scenario
from tumble.errors import InputError
from tumble.units import to_si

__all__ = [
    "MAX_STEPS",
    "READ_BACK_TOLERANCE",
    "ConformanceResult",
    "Run",
    "chosen_engines",
    "observed_order",
    "run",
    "safe_step",
    "sweep",
    "unavailable",
]

#: The most steps one run may take: beyond it a run of an engine stepped from Python
#: would last hours, and the request is refused before any work.
MAX_STEPS = 20_000_000

#: The relative difference between the inertia given and the one an engine reads back
#: beyond which it is not run: float32 engines (Rapier) round to ~6e-8.
READ_BACK_TOLERANCE = 1e-6

#: Samples recorded per run (at most): enough for the flips of the named scenarios
#: (tens of samples per flip) and for smooth figures.
SAMPLES = 2000


@dataclass(eq=False)
class Run:
    """One engine's run at one step: its samples and its row of the table."""

    engine: str
    dt: float
    samples: Samples
    row: dict[str, Any]


@dataclass(eq=False)
class ConformanceResult:
    """Engines measured on one scenario (see :func:`run` and :func:`sweep`).

    Attributes
    ----------
    scenario : the scenario run.
    table : pandas DataFrame, one row per engine × dt (columns in :func:`run`).
    runs : every :class:`Run`, with its samples (for figures).
    skipped : engine → why it was not run (not installed, no pivot, inertia read back wrong).
    notes : engine → what its adapter changed or saw (sleeping turned off, a clamp raised).
    reference_seconds, engine_seconds : wall time of the exact reference and of the engines.
    """

    scenario: Scenario
    table: Any
    runs: list[Run] = field(default_factory=list)
    skipped: dict[str, str] = field(default_factory=dict)
    notes: dict[str, list[str]] = field(default_factory=dict)
    reference_seconds: float = 0.0
    engine_seconds: float = 0.0


def chosen_engines(engines: str | Iterable[str] | None) -> list[str]:
    """The "engine/variant" names meant by ``engines``: None is every registered one; a
    plain engine name is its plain variant, or all its variants when it has none;
    "engine/*" is all its variants. An InputError names an unknown one."""
    if engines is None:
        return engine_names()
    names = [engines] if isinstance(engines, str) else list(engines)
    chosen: list[str] = []
    for name in names:
        engine, variant = split_name(name)
        every = variant == "*" or (not variant and "" not in ENGINES.get(engine, Engine).variants)
        if engine in ENGINES and every:
            chosen += [f"{engine}/{v}" if v else engine for v in ENGINES[engine].variants]
            continue
        engine_class(name)
        chosen.append(name.strip())
    if not chosen:
        raise InputError("Expected at least one engine, got none.")
    return chosen


def _steps(dt: Any, duration: float) -> tuple[float, int]:
    step = to_si(dt, "time", "dt")
    if not step > 0.0:
        raise InputError(f"Expected dt > 0 s, got {dt!r}.")
    if step > duration:
        raise InputError(f"Expected dt no longer than the duration {duration:g} s, got {step:g} s.")
    steps = round(duration / step)
    if steps > MAX_STEPS:
        raise InputError(
            f"Expected at most {MAX_STEPS:,} steps (duration / dt), got {steps:,} "
            f"({duration:g} s at dt = {step:g} s)."
        )
    return step, steps


def unavailable(name: str, scenario: Scenario) -> str:
    """Why engine ``name`` cannot run ``scenario`` here ("" if it can)."""
    cls = engine_class(name)
    missing = missing_modules(cls)
    if missing:
        return f"not installed: {', '.join(missing)} (pip install 'tumble[{cls.extra}]')"
    if scenario.body.pivot is not None and not cls.holds_pivot:
        return "cannot hold a body on a pivot"
    return ""


def _read_back(engine: Engine, scenario: Scenario) -> str:
    body = scenario.body
    mass, inertia = engine.inertia()
    mass_error = abs(mass - body.mass) / body.mass
    inertia_error = float(np.max(np.abs(inertia - body.inertia)) / np.max(body.moments))
    if mass_error > READ_BACK_TOLERANCE or inertia_error > READ_BACK_TOLERANCE:
        return (
            f"refused: it uses mass {mass:.9g} kg and inertia "
            f"{np.array2string(np.asarray(inertia), precision=9)} kg·m², not the "
            f"{body.mass:.9g} kg and diag{tuple(float(m) for m in body.moments)} given"
        )
    return ""


def _one_run(
    name: str,
    scenario: Scenario,
    dt: float,
    steps: int,
    reference: Reference,
    result: ConformanceResult,
    progress: Callable[[int], object] | None,
) -> None:
    body = scenario.body
    engine = engine_class(name)(split_name(name)[1])
    try:
        engine.build(body, dt)
        refusal = _read_back(engine, scenario)
        if refusal:
            result.skipped[name] = refusal
            return
        quaternion0, omega0 = scenario.initial_state
        every = _every(steps)
        samples = engine.simulate(body, quaternion0, omega0, dt, steps, every, progress)
    except (RuntimeError, ValueError, TypeError, ArithmeticError) as error:
        result.skipped[name] = f"failed to run: {type(error).__name__}: {error}"
        return
    finally:
        engine.close()
    if engine.notes:
        result.notes[name] = list(dict.fromkeys(engine.notes))
    start = time.perf_counter()
    row = {"engine": name, "dt": dt, **measure(reference, samples)}
    result.reference_seconds += time.perf_counter() - start
    result.engine_seconds += samples.wall_time
    result.runs.append(Run(name, dt, samples, row))


def _every(steps: int) -> int:
    """Steps between samples: at most :data:`SAMPLES` samples a run."""
    return max(1, steps // SAMPLES)


def _sample_times(dt: float, steps: int) -> Any:
    """The times at which :meth:`Engine.simulate` records a run of ``steps`` steps."""
    every = _every(steps)
    counts = np.append(np.arange(0, steps, every), steps)
    return counts * dt


def _table(rows: Sequence[dict[str, Any]], extra: Sequence[str] = ()) -> Any:
    import pandas as pd

    columns = ["engine", "dt", *METRICS, *extra, "failure"]
    return pd.DataFrame(list(rows), columns=columns)


def run(
    engines: str | Iterable[str] | None = None,
    scenario: Scenario | str = "intermediate-fast",
    dt: Any = 1e-3,
    duration: Any = None,
    *,
    progress: Callable[[int, int], object] | None = None,
) -> ConformanceResult:
    """Run physics engines on a scenario and measure them against its exact motion.

    Parameters
    ----------
    engines : "engine/variant" names (see :func:`tumble.conformance.engine_names`), a plain
        engine name for all its variants, or None for every registered engine. Engines
        not installed, or unable to run the scenario, are skipped with the reason in
        ``skipped``.
    scenario : a built-in scenario's name (:data:`tumble.conformance.SCENARIOS`) or a
        :class:`Scenario`.
    dt : the step, s (for engines that choose their own steps, the sampling interval).
    duration : the horizon, s; None: the scenario's (20 s for the built-in ones).
    progress : None or a callable ``(done, total)`` in steps over all engines.

    Returns
    -------
    ConformanceResult
        ``.table`` has one row per engine with the columns ``engine``, ``dt`` (s),
        ``energy_drift_max`` and ``energy_drift_final`` (relative, signed),
        ``momentum_drift_max`` (relative drift of |L|; about a pivot, of L's vertical
        component over |L(0)|), ``direction_drift_max`` (rad, L's direction in space;
        NaN about a pivot), ``attitude_error_max`` (rad), ``omega_error_max`` (relative
        to |ω0|), ``flips`` (sign changes of ω's intermediate-axis component, principal
        axes), ``flips_exact``, ``failed_at`` (s; NaN if the run did not fail),
        ``steps_per_second`` (wall time) and ``failure`` (what failed).

    Raises
    ------
    InputError
        For an unknown engine or scenario, a dt or duration that is not positive, a dt
        longer than the duration, or more than :data:`MAX_STEPS` steps.
    """
    return sweep(engines, scenario, [dt], duration, progress=progress, _orders=False)


def sweep(
    engines: str | Iterable[str] | None,
    scenario: Scenario | str,
    dts: Iterable[Any],
    duration: Any = None,
    *,
    tolerance: float = 1e-6,
    progress: Callable[[int, int], object] | None = None,
    _orders: bool = True,
) -> ConformanceResult:
    """:func:`run` at each step of ``dts``; the table adds ``order`` and ``safe_dt`` per engine.

    ``order`` is the observed order of convergence: the least-squares slope of
    log(``omega_error_max``) against log(dt) over the steps whose error lies between
    1e-10 (round-off) and 0.1 (beyond it, the error no longer grows like a power of dt),
    NaN with fewer than two such steps. ``safe_dt`` is the largest dt of the sweep
    whose run, and every run at a smaller dt, did not fail and kept
    |``energy_drift_max``| and ``attitude_error_max`` (rad) within ``tolerance``; NaN
    if none.
    """
    chosen = get_scenario(scenario)
    horizon = chosen.duration if duration is None else to_si(duration, "time", "duration")
    if not (math.isfinite(horizon) and horizon > 0.0):
        raise InputError(f"Expected a duration > 0 s, got {duration!r}.")
    names = list(dict.fromkeys(chosen_engines(engines)))
    steps = [_steps(dt, horizon) for dt in dts]
    if not steps:
        raise InputError("Expected at least one dt, got none.")
    result = ConformanceResult(chosen, None)
    runnable = []
    for name in names:
        reason = unavailable(name, chosen)
        if reason:
            result.skipped[name] = reason
        else:
            runnable.append(name)
    total = len(runnable) * sum(count for _, count in steps)
    done = 0

    def advance(count: int) -> None:
        nonlocal done
        done += count
        if progress is not None:
            progress(done, total)

    for dt, count in steps:
        start = time.perf_counter()
        reference = Reference.sampled(chosen, _sample_times(dt, count))
        result.reference_seconds += time.perf_counter() - start
        for name in runnable:
            before = done
            _one_run(name, chosen, dt, count, reference, result, advance)
            advance(before + count - done)  # a run that stopped early still counts whole
    rows = [one.row for one in result.runs]
    if _orders:
        for row in rows:
            same = [other for other in rows if other["engine"] == row["engine"]]
            row["order"] = observed_order(same)
            row["safe_dt"] = safe_step(same, tolerance)
    result.table = _table(rows, ("order", "safe_dt") if _orders else ())
    return result


def observed_order(rows: Sequence[dict[str, Any]]) -> float:
    """The slope of log(omega_error_max) against log(dt) over rows whose error is between
    1e-10 and 0.1 and whose run did not fail; NaN with fewer than two dts."""
    points = [
        (math.log(row["dt"]), math.log(row["omega_error_max"]))
        for row in rows
        if 1e-10 < row["omega_error_max"] < 0.1 and not math.isfinite(row["failed_at"])
    ]
    if len({x for x, _ in points}) < 2:
        return float("nan")
    x, y = np.array(points).T
    return float(np.polyfit(x, y, 1)[0])


def safe_step(rows: Sequence[dict[str, Any]], tolerance: float) -> float:
    """The largest dt whose run and every run at a smaller dt kept within ``tolerance``."""
    safe = float("nan")
    for row in sorted(rows, key=lambda one: one["dt"]):
        good = (
            not math.isfinite(row["failed_at"])
            and abs(row["energy_drift_max"]) <= tolerance
            and row["attitude_error_max"] <= tolerance
        )
        if not good:
            break
        safe = row["dt"]
    return safe
