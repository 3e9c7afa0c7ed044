"""Run a scenario: simulate, measure, and compare with the closed forms of
:mod:`tumble.theory` (measurements from :mod:`tumble.analysis`).

The result, :class:`RunResult`, holds everything a report needs: the
trajectories, the rows theory vs simulation, the drift of the conserved
quantities, and a few scenario-specific curves (:class:`Panel`) to draw.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.scenario.build import (
    at_key,
    initial_state,
    mass_properties,
    torque_model,
)
from tumble.scenario.files import ScenarioError

if TYPE_CHECKING:
    from tumble.massprops import MassProperties
    from tumble.scenario.files import LoadedScenario
    from tumble.simulation import Trajectory

__all__ = ["Curve", "Panel", "RunResult", "decimate", "execute"]

Array = NDArray[np.float64]
Progress = Callable[[int, int], object] | None


@dataclass(frozen=True)
class Curve:
    """One line of a panel: ``t`` (s), ``values`` and a legend ``label``;
    ``style`` is "simulation" (solid) or "theory" (dashed)."""

    label: str
    t: Array
    values: Array
    style: str = "simulation"


@dataclass(frozen=True)
class Panel:
    """A scenario-specific plot: a title, the y label with its unit, and curves."""

    title: str
    ylabel: str
    curves: list[Curve]
    name: str = "angles"
    until: float | None = None  # show t <= until only (a few periods of a fast oscillation)


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
        (:func:`tumble.analysis.compare`), with ``run`` naming the trajectory.
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
        from tumble import __version__

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


def _kept(count: int, samples: int) -> NDArray[np.int64]:
    """Indices of every k-th of ``count`` samples, and the last, about ``samples`` in all."""
    index = np.arange(0, count, max(1, count // samples))
    if index[-1] != count - 1:
        index = np.append(index, count - 1)
    return index


def decimate(traj: Trajectory, samples: int) -> Trajectory:
    """Every k-th sample (and the last) so that about ``samples`` remain."""
    index = _kept(len(traj.t), samples)
    if len(index) == len(traj.t):
        return traj
    return traj.samples(index)


def _record_every(duration: float, dt: float | None, samples: int) -> int:
    if dt is None:
        return 1
    return max(1, math.ceil(duration / dt) // samples)


# ------------------------------------------------------------------ the run
def execute(loaded: LoadedScenario, progress: Progress = None) -> RunResult:
    """Run a validated scenario (see :func:`tumble.scenario.run`)."""
    spec = loaded.spec
    start = time.perf_counter()
    mp = mass_properties(spec.body, loaded.folder, loaded)
    theory: str | None
    if spec.gyrocompass is not None:
        runs, comparisons, panels, theory = _gyrocompass(loaded, mp, progress)
        notes = [
            "The gimbal model: the disk's energy is not conserved (the platform does work); "
            "the Jacobi integral T − Ω·L is."
        ]
    else:
        runs, comparisons, panels, theory, notes = _rigid_body(loaded, mp, progress)
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


def _rigid_body(
    loaded: LoadedScenario, mp: MassProperties, progress: Progress
) -> tuple[dict[str, Trajectory], list[dict[str, Any]], list[Panel], str | None, list[str]]:
    from tumble.simulation import prepare, simulate

    spec = loaded.spec
    state = initial_state(spec)
    torque = torque_model(spec, loaded)
    sim = spec.simulation
    env = spec.environment
    dt = sim.dt
    with at_key(loaded, "simulation"):
        chosen = prepare(
            mp, state.omega, attitude0=state.attitude, pivot=env.pivot, gravity=env.gravity,
            torque=torque, method=sim.method,
        ).integrator  # fmt: skip
        if dt is None and chosen.kind != "stepping":
            # Methods that sample every dt rather than step by it (the exact
            # solution, the adaptive method): sample as often as [output] asks.
            dt = sim.duration / spec.output.samples
        traj = simulate(
            mp,
            state.omega,
            attitude0=state.attitude,
            duration=sim.duration,
            dt=dt,
            pivot=env.pivot,
            gravity=env.gravity,
            torque=torque,
            method=sim.method,
            record_every=_record_every(sim.duration, dt, spec.output.samples),
            progress=progress,
        )
    traj = decimate(traj, spec.output.samples)
    theory = _choose_theory(loaded, mp, state)
    comparisons: list[dict[str, Any]] = []
    panels: list[Panel] = []
    notes: list[str] = []
    with at_key(loaded, "theory"):
        if theory == "gyroscope":
            comparisons, panels = _gyroscope(loaded, mp, traj, state)
        elif theory == "free-symmetric-top":
            comparisons, panels = _free_symmetric_top(mp, traj, state)
        elif theory == "flip-period":
            comparisons, panels = _flips(mp, traj, state)
        elif theory == "rotor-loads":
            comparisons, panels = _rotor(loaded, mp, traj, state)
    for row in comparisons:
        row.setdefault("run", "main")
    return {"main": traj}, comparisons, panels, theory, notes


def _row(quantity: str, theory: float, measured: float, unit: str) -> dict[str, Any]:
    """A row of the comparison table, as :func:`tumble.analysis.compare` makes them."""
    from tumble.analysis import comparison_row

    return comparison_row(quantity, theory, measured, unit)


def _up(gravity: Any) -> Array:
    g = np.asarray(gravity, dtype=float)
    return -g / np.linalg.norm(g)


def _choose_theory(loaded: LoadedScenario, mp: MassProperties, state: Any) -> str | None:
    """The closed form named in [theory], or the one that fits the setup for ``auto``."""
    from tumble import theory

    spec = loaded.spec
    wanted = spec.theory.model
    if wanted == "none":
        return None
    env = spec.environment
    heavy = env.pivot is not None and env.gravity is not None and any(env.gravity)
    kinds = {t.type for t in spec.torques}
    free = not kinds and not heavy
    moments, _ = mp.principal()
    symmetric = bool(np.any(np.abs(np.diff(moments)) <= 1e-9 * moments.sum()))
    fits = {
        "gyroscope": heavy and not kinds,
        "rotor-loads": kinds == {"hold-rotation"},
        "free-symmetric-top": free and symmetric,
        "flip-period": free,
    }
    if wanted == "auto":
        for name in ("gyroscope", "rotor-loads", "free-symmetric-top", "flip-period"):
            if fits[name]:
                if name == "gyroscope":
                    try:
                        theory.gyroscope(mp, env.pivot, 1.0, 0.5, 1.0)
                    except InputError:
                        return None
                return name
        return None
    if not fits[wanted]:
        needs = {
            "gyroscope": "a pivot with gravity and no other torque",
            "rotor-loads": "a hold-rotation torque and no other",
            "free-symmetric-top": "a free body with two equal principal moments",
            "flip-period": "a free body (no pivot with gravity, no torques)",
        }[wanted]
        raise ScenarioError(
            f"{loaded.source}, `theory.model`: Expected {needs} for {wanted!r}, got another setup "
            '(use model = "auto" or "none").'
        )
    return wanted


def _axis_angles(traj: Trajectory, axis: Array, vertical: Array) -> tuple[Array, Array]:
    """Tilt of a body axis from a space direction, and its azimuth about it (unwrapped), rad."""
    directions = traj.rotation.apply(np.array(axis, dtype=float))
    tilt = np.arccos(np.clip(directions @ vertical, -1.0, 1.0))
    helper = np.array([1.0, 0.0, 0.0]) if abs(vertical[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(vertical, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(vertical, e1)
    azimuth = np.unwrap(np.arctan2(directions @ e2, directions @ e1))
    return tilt, azimuth - azimuth[0]


def _gyroscope(
    loaded: LoadedScenario, mp: MassProperties, traj: Trajectory, state: Any
) -> tuple[list[dict[str, Any]], list[Panel]]:
    from tumble import analysis, theory

    env = loaded.spec.environment
    assert env.gravity is not None  # the gyroscope theory is chosen only with gravity
    up = _up(env.gravity)
    axis = np.array([0.0, 0.0, 1.0])
    tilt0 = float(np.arccos(np.clip(traj.rotation[0].apply(axis) @ up, -1.0, 1.0)))
    spin = float(state.omega[2])
    result = theory.gyroscope(mp, env.pivot, spin, tilt0, float(np.linalg.norm(env.gravity)))
    rows = analysis.compare(traj, result, axis=axis, vertical=up)
    tilt, azimuth = _axis_angles(traj, axis, up)
    exact = np.asarray(result.tilt_at(traj.t))
    rate = analysis.precession(traj, axis=axis, vertical=up).rate
    panels = [
        Panel(
            "Nutation: tilt θ of the symmetry axis from the vertical",
            "θ (deg)",
            [
                Curve("simulation", traj.t, np.degrees(tilt)),
                Curve(
                    "exact (Lagrange top released from rest)", traj.t, np.degrees(exact), "theory"
                ),
            ],
            name="nutation",
            until=_periods(result.nutation_period, 6, float(traj.t[-1])),
        ),
        Panel(
            "Precession: azimuth φ of the symmetry axis about the vertical",
            "φ (deg)",
            [
                Curve("simulation", traj.t, np.degrees(azimuth)),
                Curve(
                    "fast top: m g l / (I_s ω_s) · t",
                    traj.t,
                    np.degrees(result.precession_rate * traj.t),
                    "theory",
                ),
                Curve(
                    f"measured mean rate {rate:.4g} rad/s · t",
                    traj.t,
                    np.degrees(rate * traj.t),
                    "fit",
                ),
            ],
            name="precession",
        ),
    ]
    return rows, panels


def _periods(period: float, count: int, duration: float) -> float | None:
    """The end of the first ``count`` periods, or None when the run is not much longer."""
    if not math.isfinite(period) or count * period * 2 > duration:
        return None
    return count * period


def _free_symmetric_top(
    mp: MassProperties, traj: Trajectory, state: Any
) -> tuple[list[dict[str, Any]], list[Panel]]:
    from tumble import analysis, theory

    result = theory.free_symmetric_top(mp, state.omega)
    rows = analysis.compare(traj, result)
    axis = np.array(result.axis, dtype=float)
    omega_unit = traj.omega / np.linalg.norm(traj.omega, axis=1)[:, None]
    body_cone = np.arccos(np.clip(omega_unit @ axis, -1.0, 1.0))
    momentum = traj.angular_momentum
    l_unit = momentum / np.linalg.norm(momentum, axis=1)[:, None]
    space_omega = traj.omega_space / np.linalg.norm(traj.omega_space, axis=1)[:, None]
    space_cone = np.arccos(np.clip(np.einsum("ij,ij->i", space_omega, l_unit), -1.0, 1.0))
    rows += [
        _row(
            "body cone half-angle (ω to the axis)",
            result.body_cone_half_angle,
            float(np.mean(body_cone)),
            "rad",
        ),
        _row(
            "space cone half-angle (ω to L)",
            result.space_cone_half_angle,
            float(np.mean(space_cone)),
            "rad",
        ),
    ]
    _, azimuth = _axis_angles(traj, axis, l_unit[0])
    ones = np.ones_like(traj.t)
    panels = [
        Panel(
            "Cones: ω to the symmetry axis (body cone), ω to L (space cone)",
            "half-angle (deg)",
            [
                Curve("body cone, simulation", traj.t, np.degrees(body_cone)),
                Curve(
                    "body cone, theory",
                    traj.t,
                    np.degrees(result.body_cone_half_angle) * ones,
                    "theory",
                ),
                Curve("space cone, simulation", traj.t, np.degrees(space_cone)),
                Curve(
                    "space cone, theory",
                    traj.t,
                    np.degrees(result.space_cone_half_angle) * ones,
                    "theory",
                ),
            ],
            name="cones",
        ),
        Panel(
            "Precession of the symmetry axis about L",
            "azimuth (deg)",
            [
                Curve("simulation", traj.t, np.degrees(azimuth)),
                Curve(
                    "theory: L / I⊥ · t",
                    traj.t,
                    np.degrees(result.space_precession_rate * traj.t),
                    "theory",
                ),
            ],
            name="precession",
        ),
    ]
    return rows, panels


def _flips(
    mp: MassProperties, traj: Trajectory, state: Any
) -> tuple[list[dict[str, Any]], list[Panel]]:
    from tumble import analysis, theory

    period = theory.flip_period(mp, state.omega)
    rows: list[dict[str, Any]] = []
    moments, axes = mp.principal()
    along = traj.omega @ axes
    try:
        flips = analysis.flips(traj)
    except InputError:  # fewer than two flips: too short a run to measure a period
        flips = None
    if flips is not None and math.isfinite(period) and traj.t[-1] > period:
        rows = analysis.compare(traj, float(period))
    curves = [
        Curve(
            f"ω along principal axis {k + 1} (I{k + 1} = {moments[k]:.4g} kg·m²)",
            traj.t,
            along[:, k],
        )
        for k in range(3)
    ]
    panels = [Panel("Flips: ω along the principal axes", "ω (rad/s)", curves, name="flips")]
    if flips is not None and flips.count:
        rows.append(
            _row(
                "flips in the run",
                float(_expected_flips(flips.times[0], period, float(traj.t[-1]))),
                float(flips.count),
                "",
            )
        )
    return rows, panels


def _expected_flips(first: float, period: float, duration: float) -> int:
    """Flips (sign changes, two per period) from the first one to the end of the run."""
    if not math.isfinite(period):
        return 1
    return 1 + math.floor((duration - first) / (0.5 * period))


def _derivative(t: Array, values: Array) -> tuple[Array, Array]:
    """dvalues/dt by the five-point central difference (error O(h⁴)), at the
    interior samples of the evenly spaced part of ``t`` (a shorter last step is left out)."""
    steps = np.diff(t)
    even = len(t) if np.allclose(steps, steps[0], rtol=1e-9) else len(t) - 1
    h = float(steps[0])
    v = values[:even]
    rate = (v[:-4] - 8.0 * v[1:-3] + 8.0 * v[3:-1] - v[4:]) / (12.0 * h)
    return t[2 : even - 2], rate


def _rotor(
    loaded: LoadedScenario, mp: MassProperties, traj: Trajectory, state: Any
) -> tuple[list[dict[str, Any]], list[Panel]]:
    from tumble import theory

    pivot = loaded.spec.environment.pivot
    point = np.asarray(pivot if pivot is not None else mp.center_of_mass, dtype=float)
    speed = float(np.linalg.norm(state.omega))
    if speed == 0:
        raise InputError("Expected a non-zero initial ω to hold steady, got 0.")
    axis = state.omega / speed
    bearings = loaded.spec.theory.bearings
    result = theory.rotor_loads(mp, speed, axis, point, bearings)
    momentum = traj.angular_momentum
    times, torque = _derivative(traj.t, momentum)
    measured_torque = float(np.mean(np.linalg.norm(torque, axis=1)))
    omega_space = traj.omega_space
    cosines = np.einsum("ij,ij->i", momentum, omega_space) / (
        np.linalg.norm(momentum, axis=1) * np.linalg.norm(omega_space, axis=1)
    )
    angle = np.arccos(np.clip(cosines, -1.0, 1.0))
    l_theory = np.asarray(result.angular_momentum)
    angle_theory = float(np.arccos(np.clip(l_theory @ axis / np.linalg.norm(l_theory), -1.0, 1.0)))
    rows = [
        _row(
            "|ω| (held steady)", speed, float(np.mean(np.linalg.norm(traj.omega, axis=1))), "rad/s"
        ),
        _row(
            "|L|",
            float(np.linalg.norm(l_theory)),
            float(np.mean(np.linalg.norm(momentum, axis=1))),
            "kg·m²/s",
        ),
        _row("angle between L and ω", angle_theory, float(np.mean(angle)), "rad"),
        _row("|τ| = |dL/dt|", float(np.linalg.norm(result.torque)), measured_torque, "N·m"),
    ]
    if result.bearing_forces is not None and result.bearings is not None:
        separation = abs(float(result.bearings[0] - result.bearings[1]))
        # With the centre of mass on the axis each bearing carries |τ| / d.
        rows.append(
            _row(
                "bearing force (each)",
                float(np.linalg.norm(result.bearing_forces[0])),
                measured_torque / separation,
                "N",
            )
        )
    ones = np.ones_like(traj.t)
    panels = [
        Panel(
            "Torque needed to keep ω steady: |dL/dt| of the simulation vs ω × L",
            "|τ| (N·m)",
            [
                Curve("|dL/dt| of the simulation", times, np.linalg.norm(torque, axis=1)),
                Curve(
                    "theory |ω × (I ω)|",
                    traj.t,
                    float(np.linalg.norm(result.torque)) * ones,
                    "theory",
                ),
            ],
            name="torque",
        ),
        Panel(
            "L sweeps a cone about ω: its component perpendicular to ω",
            "L (kg·m²/s)",
            [
                Curve("L_x (space)", traj.t, momentum[:, 0]),
                Curve("L_y (space)", traj.t, momentum[:, 1]),
                Curve("L_z (space)", traj.t, momentum[:, 2]),
            ],
            name="cone",
        ),
    ]
    return rows, panels


# ------------------------------------------------------------------ gyrocompass
def _gyrocompass(
    loaded: LoadedScenario, mp: MassProperties, progress: Progress
) -> tuple[dict[str, Trajectory], list[dict[str, Any]], list[Panel], str]:
    from tumble import analysis, models, theory

    spec = loaded.spec
    settings = spec.gyrocompass
    assert settings is not None
    with at_key(loaded, "gyrocompass"):
        result = theory.gyrocompass(mp, settings.spin_rate, settings.platform_rate)
    beta = result.oscillation_frequency
    runs: dict[str, Trajectory] = {}
    rows: list[dict[str, Any]] = []
    curves: list[Curve] = []
    total = len(settings.amplitudes)
    for k, amplitude in enumerate(settings.amplitudes):
        label = "main" if k == 0 else f"amplitude-{math.degrees(amplitude):.0f}deg"

        def report(done: int, steps: int, k: int = k) -> None:
            if progress is not None:
                progress(k * steps + done, total * steps)

        with at_key(loaded, "gyrocompass"):
            # Started on the axis with θ̇ = β θ0, so that the small-angle solution is θ0 sin βt.
            run = models.gyrocompass(
                mp,
                settings.spin_rate,
                settings.platform_rate,
                0.0,
                angle_rate0=beta * amplitude,
                duration=spec.simulation.duration,
                dt=spec.simulation.dt,
                record_every=_record_every(
                    spec.simulation.duration, spec.simulation.dt, spec.output.samples
                ),
                progress=report,
            )
        index = _kept(len(run.trajectory.t), spec.output.samples)
        traj = decimate(run.trajectory, spec.output.samples)
        angle = np.asarray(run.angle)[index]
        runs[label] = traj
        direction = np.sign(settings.platform_rate) * np.array([0.0, 0.0, 1.0])
        for row in analysis.compare(traj, result, vertical=direction):
            row["quantity"] = f"θ0 = {math.degrees(amplitude):.0f}°: {row['quantity']}"
            row["run"] = label
            rows.append(row)
        name = f"θ0 = {math.degrees(amplitude):.0f}°"
        curves.append(Curve(f"{name}, simulation", traj.t, np.degrees(angle)))
        curves.append(
            Curve(
                f"{name}, θ0 sin βt",
                traj.t,
                np.degrees(amplitude * np.sin(beta * traj.t)),
                "theory",
            )
        )
    panels = [
        Panel(
            "Gyrocompass: angle θ of the spin axis from the platform's axis",
            "θ (deg)",
            curves,
            name="theta",
        )
    ]
    return runs, rows, panels, "gyrocompass"
