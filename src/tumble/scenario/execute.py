"""Run a scenario: simulate, then compare with the theory check that fits it.

The check comes from the registry (:mod:`tumble.checks`): the one the file's
``[theory] model`` names, or the first that fits the case. A scenario with the
table of a model kind (:mod:`tumble.scenario.model_kinds`: ``[gyrocompass]``,
``[rotordynamics]``, …) runs that model instead, compared by the check the kind
names. The result, :class:`RunResult`, holds
everything a report needs: the trajectories, the rows theory vs simulation,
the drift of the conserved quantities, and the curves (:class:`~tumble.checks.Panel`)
to draw.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble._version import __version__
from tumble.checks import Case, Comparison, Panel, TheoryCheck, choose_check
from tumble.errors import InputError
from tumble.scenario.build import (
    at_key,
    initial_state,
    internal_parts,
    mass_properties,
    torque_model,
)
from tumble.scenario.loaded import ScenarioError, where
from tumble.scenario.sampling import decimate, record_every
from tumble.scenario.schema import MAX_STEPS, MAX_STEPS_TEXT

if TYPE_CHECKING:
    from tumble.massprops import MassProperties
    from tumble.scenario.loaded import LoadedScenario
    from tumble.scenario.model_kinds import ModelKind
    from tumble.trajectory import Trajectory

__all__ = ["RunResult", "execute"]

Array = NDArray[np.float64]
Progress = Callable[[int, int], object] | None


@dataclass(frozen=True)
class RunResult:
    """The outcome of :func:`tumble.scenario.run`.

    Attributes
    ----------
    scenario : the :class:`~tumble.scenario.LoadedScenario` that ran.
    trajectory : the main trajectory (the first run of several).
    runs : every trajectory by label (``"main"`` first; the gyrocompass adds one per amplitude).
    theory : the name of the closed form compared with, or None.
    comparisons : rows ``{quantity, theory, measured, relative_error, unit}``
        (:func:`tumble.checks.comparison_row`), with ``run`` naming the trajectory.
    drift : relative drift of each quantity the motion of the main trajectory
        conserves (:attr:`tumble.Trajectory.drift`).
    panels : scenario-specific curves (tilt and precession angles, θ(t), ...).
    elapsed : seconds spent simulating and measuring.
    """

    scenario: LoadedScenario
    trajectory: Trajectory
    runs: dict[str, Trajectory]
    theory: str | None
    comparisons: list[dict[str, Any]]
    drift: dict[str, Any]
    panels: list[Panel]
    elapsed: float
    notes: list[str] = field(default_factory=list)

    def summary(self) -> dict[str, Any]:
        """The JSON-ready summary written to ``summary.json``."""
        spec = self.scenario.spec
        traj = self.trajectory
        return {
            "scenario": spec.scenario.name,
            "title": spec.scenario.title,
            "source": self.scenario.source,
            "tumble_version": __version__,
            "method": traj.method,
            "reason": traj.reason,
            "dt": traj.dt,
            "steps": traj.steps,
            "duration": float(traj.t[-1]),
            "samples": len(traj.t),
            "theory": self.theory,
            "comparisons": [_jsonable(row) for row in self.comparisons],
            "drift": _jsonable(self.drift),
            "runs": list(self.runs),
            "notes": list(self.notes),
            "elapsed_s": self.elapsed,
        }


def _jsonable(value: Any) -> Any:
    """Floats that JSON can hold: inf and NaN become None (JSON has neither)."""
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


# ------------------------------------------------------------------ the run
def execute(loaded: LoadedScenario, progress: Progress = None) -> RunResult:
    """Run a validated scenario (see :func:`tumble.scenario.run`)."""
    spec = loaded.spec
    start = time.perf_counter()
    mp = mass_properties(spec.body, loaded.folder, loaded)
    parts, added = internal_parts(spec, loaded)
    if added is not None:
        mp = mp + added
    tables = spec.model_tables()
    theory: str | None
    if tables:
        table, kind = next(iter(tables.items()))
        runs, comparisons, panels, theory, notes = _model(loaded, mp, table, kind, progress)
    else:
        runs, comparisons, panels, theory, notes = _rigid_body(loaded, mp, parts, progress)
    main = next(iter(runs.values()))
    drift: dict[str, Any] = dict(main.drift)
    return RunResult(
        scenario=loaded,
        trajectory=main,
        runs=runs,
        theory=theory,
        comparisons=comparisons,
        drift=drift,
        panels=panels,
        elapsed=time.perf_counter() - start,
        notes=notes,
    )


def check_steps(loaded: LoadedScenario, total: int) -> None:
    """Refuse a run of more than :data:`~tumble.scenario.schema.MAX_STEPS` steps.

    Raises
    ------
    ScenarioError
        Naming the file, the line and ``[simulation]``.
    """
    if total > MAX_STEPS:
        raise ScenarioError(
            f"{where(loaded, ('simulation',))}: Expected at most {MAX_STEPS_TEXT} steps, got "
            f"{total:.3g} (dt follows the fastest rotation when it is not given): a scenario "
            "should run in seconds (give a longer `dt` or a shorter `duration`, or use "
            "tumble.simulate for long runs)."
        )


def _model(
    loaded: LoadedScenario, mp: MassProperties, table: str, kind: ModelKind, progress: Progress
) -> tuple[dict[str, Trajectory], list[dict[str, Any]], list[Panel], str, list[str]]:
    """The runs of the model kind of the file's ``table``, compared by the theory check
    the kind names."""
    from tumble.checks import THEORY_CHECKS
    from tumble.scenario.model_kinds import Span

    spec = loaded.spec
    span = Span(spec.simulation.duration, spec.simulation.dt, spec.output.samples)
    with at_key(loaded, table):
        done = kind.run(mp, getattr(spec, table), span, progress)
    check = THEORY_CHECKS[kind.check]
    comparison = check.compare_runs(done.case, done.trajectories, done.results)
    notes = [*kind.notes, *comparison.notes]
    return dict(done.trajectories), comparison.rows, comparison.panels, check.name, notes


def _rigid_body(
    loaded: LoadedScenario, mp: MassProperties, parts: tuple[Any, ...], progress: Progress
) -> tuple[dict[str, Trajectory], list[dict[str, Any]], list[Panel], str | None, list[str]]:
    """The free rigid body of ``[body]`` (with its parts, torques and supports)
    simulated, and compared with the theory check ``[theory]`` chooses."""
    spec = loaded.spec
    state = initial_state(spec)
    torque = torque_model(spec, loaded)
    traj, dt = _simulate(loaded, mp, parts, state, torque, progress)
    env = spec.environment
    options: dict[str, Any] = {
        "method": spec.simulation.method,
        "dt": dt,
        "samples": spec.output.samples,
    }
    if spec.theory.bearings is not None:
        options["bearings"] = spec.theory.bearings
    case = Case(
        mp,
        state.omega,
        state.attitude,
        env.pivot,
        env.gravity,
        torque,
        options=options,
        internal=parts,
    )
    comparison, check = _compare(loaded, case, traj)
    for row in comparison.rows:
        row.setdefault("run", "main")
    theory = None if check is None else check.name
    runs = {"main": traj, **comparison.runs}
    return runs, comparison.rows, comparison.panels, theory, list(comparison.notes)


def _simulate(
    loaded: LoadedScenario,
    mp: MassProperties,
    parts: tuple[Any, ...],
    state: Any,
    torque: Any,
    progress: Progress,
) -> tuple[Trajectory, float | None]:
    """The run of ``[simulation]``, kept to about ``[output] samples`` samples, and the
    step the file gives (or the sampling interval of a method that samples)."""
    from tumble.integrators.limits import check_recording
    from tumble.integrators.steps import whole_steps
    from tumble.parts import value_columns
    from tumble.simulation import prepare, simulate

    spec = loaded.spec
    sim = spec.simulation
    env = spec.environment
    dt = sim.dt
    with at_key(loaded, "internal" if parts else "simulation"):
        prepared = prepare(
            mp,
            state.omega,
            attitude0=state.attitude,
            pivot=env.pivot,
            gravity=env.gravity,
            torque=torque,
            method=sim.method,
            internal=parts,
        )
    with at_key(loaded, "simulation"):
        if dt is None and prepared.integrator.kind != "stepping":
            # Methods that sample every dt rather than step by it (the exact
            # solution, the adaptive method): sample as often as [output] asks.
            dt = sim.duration / spec.output.samples
        # The default step is known here, so that only the samples kept are recorded.
        step = prepared.step_size(dt, sim.duration)
        if prepared.integrator.kind == "stepping":
            check_steps(loaded, whole_steps(sim.duration, step))
        every = record_every(sim.duration, step, spec.output.samples)
        check_recording(
            sim.duration,
            step,
            every,
            len(value_columns(prepared.body.parts)),
            "Ask for fewer samples in [output], or a shorter duration or a larger dt in "
            "[simulation].",
        )
        traj = simulate(
            mp,
            state.omega,
            attitude0=state.attitude,
            duration=sim.duration,
            dt=step,
            pivot=env.pivot,
            gravity=env.gravity,
            torque=torque,
            method=sim.method,
            record_every=every,
            progress=progress,
            internal=parts,
            max_steps=MAX_STEPS,
        )
    return decimate(traj, spec.output.samples), dt


def _compare(
    loaded: LoadedScenario, case: Case, traj: Trajectory
) -> tuple[Comparison, TheoryCheck | None]:
    """The comparison with the check ``[theory] model`` names (or the first that fits),
    and that check; none, with a note saying why, when none fits or the check chosen
    for the case cannot measure this run of it."""
    spec = loaded.spec
    model = spec.theory.model
    with at_key(loaded, "theory", "model"):
        check = choose_check(model, case)
    if check is None:
        return Comparison([], [], notes=(_no_check(model),)), None
    try:
        return check.compare(case, traj), check
    except ScenarioError:
        raise
    except InputError as exc:
        if model != "auto" or spec.theory.bearings is not None:  # asked for: say it
            raise ScenarioError(
                f'{where(loaded, ("theory",))}: {exc} Set [theory] model = "none" to run '
                "it without a comparison."
            ) from None
        # The check chosen for the case cannot measure this state of it (an
        # upright top has no azimuth): the run stands, and says why.
        note = f"no theory comparison: the {check.name} check cannot measure this run: {exc}"
        return Comparison([], [], notes=(note,)), None


def _no_check(model: str) -> str:
    """Why no check was chosen: ``[theory] model = "none"``, or none fits the case."""
    if model == "none":
        return 'no theory comparison: [theory] model = "none".'
    from tumble.checks import THEORY_CHECKS

    return (
        f"no theory comparison: none of the closed forms ({', '.join(THEORY_CHECKS)}) "
        "describes this setup."
    )
