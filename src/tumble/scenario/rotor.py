"""A scenario with a ``[rotor]`` table: a rigid rotor on elastic bearings, run up.

The body is a :class:`tumble.theory.RigidRotor` on the bearings of the table.
The main run is :func:`tumble.models.run_up` through the table's ``speeds``
over ``[simulation] duration``; with ``steady_speed`` a second run holds that
speed until the start-up transient has died away. Compared with the closed
forms: the steady orbits at the bearings (major semi-axis and the phase lag of
x behind the unbalance, fitted over the last tenth of the steady run) and the
critical speeds (the speeds where the run-up's orbit is largest come after
them, later the faster the run-up). Drawn: the Campbell diagram, the
unbalance response against the run-up's orbit, its phase, and the orbits.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.checks import Curve, Panel, comparison_row
from tumble.scenario.build import at_key
from tumble.scenario.schema import MAX_STEPS

if TYPE_CHECKING:
    from tumble.massprops import MassProperties
    from tumble.models import RunUp
    from tumble.scenario.loaded import LoadedScenario
    from tumble.theory import RigidRotor
    from tumble.trajectory import Trajectory

__all__ = ["CLOSED_FORM", "run_rotor"]

Array = NDArray[np.float64]
Progress = Callable[[int, int], object] | None

#: The name the report gives the closed form compared with.
CLOSED_FORM = "rigid-rotor"

#: Speeds at which the Campbell diagram and the unbalance response are drawn.
CURVE_POINTS = 400

#: The share of the steady run, at its end, over which its orbit is fitted.
STEADY_TAIL = 0.1

#: Critical speeds closer than this (relative) count as one peak of a run-up.
CLUSTER = 0.02


def run_rotor(
    loaded: LoadedScenario, mp: MassProperties, progress: Progress
) -> tuple[dict[str, Trajectory], list[dict[str, Any]], list[Panel], str, list[str]]:
    """The runs by label ("main" the run-up, "steady" the run at ``steady_speed``),
    the rows theory vs simulation, the panels, the name of the closed form and
    notes for the report."""
    from tumble import models, theory

    spec = loaded.spec
    settings = spec.rotor
    if settings is None:  # pragma: no cover - called for scenarios with [rotor] only
        raise ValueError("Expected a scenario with a [rotor] table.")
    bearings = [theory.Bearing(b.position, b.stiffness, b.damping) for b in settings.bearings]
    with at_key(loaded, "rotor"):
        rotor = theory.RigidRotor(mp, bearings, axis=settings.axis)
    low, high = settings.speeds
    duration = spec.simulation.duration
    planned = [("main", low, (high - low) / duration)]
    if settings.steady_speed is not None:
        planned.append(("steady", settings.steady_speed, 0.0))
    runs: dict[str, RunUp] = {}
    for k, (label, start, rate) in enumerate(planned):

        def report(done: int, steps: int, k: int = k) -> None:
            if progress is not None:
                progress(k * steps + done, len(planned) * steps)

        with at_key(loaded, "rotor"):
            runs[label] = models.run_up(
                rotor,
                settings.unbalance,
                duration=duration,
                speed=start,
                acceleration=rate,
                position=settings.unbalance_position,
                dt=spec.simulation.dt,
                samples=spec.output.samples,
                progress=report,
                max_steps=MAX_STEPS,
            )
    speeds = np.linspace(low, high, CURVE_POINTS)
    names = _bearing_names(rotor)
    rows = _critical_rows(rotor, runs["main"], names, settings)
    for row in rows:
        row["run"] = "main"
    panels = [
        _campbell(rotor, speeds),
        _response(rotor, speeds, runs["main"], settings, names),
        _phase(rotor, speeds, settings, names),
    ]
    notes = [
        "The rotor model: the motor does work and the bearings take it, so nothing is "
        "conserved; its whirl, critical speeds and unbalance response are "
        "tumble.theory.RigidRotor's."
    ]
    if "steady" in runs:
        steady_rows, orbits = _steady(rotor, runs["steady"], settings, names)
        rows = steady_rows + rows
        panels.append(orbits)
        # The free vibration of the start decays as e^{Re λ t}, its slowest mode's
        # rate the least −Re λ; the orbit is fitted from (1 − STEADY_TAIL) T on.
        decay = float(-np.linalg.eigvals(rotor.state_matrices(runs["steady"].speed[0])).real.min())
        left = math.exp(-decay * (1.0 - STEADY_TAIL) * duration)
        if left > 1e-6:
            notes.append(
                f"The start-up transient of the run at {settings.steady_speed:.4g} rad/s has "
                f"decayed only to {left:.1e} of its size where the orbit is fitted (the "
                f"slowest mode decays at {decay:.3g} 1/s): the steady rows carry that error "
                "(a longer [simulation] duration, or damped bearings, take it away)."
            )
    trajectories = {label: run.trajectory for label, run in runs.items()}
    return trajectories, rows, panels, CLOSED_FORM, notes


def _bearing_names(rotor: RigidRotor) -> list[str]:
    """ "bearing A at -0.25 m", … in the order of the table."""
    return [
        f"bearing {chr(ord('A') + k)} at {bearing.position:.3g} m"
        for k, bearing in enumerate(rotor.bearings)
    ]


def _fitted_orbit(run: RunUp, speed: float) -> NDArray[np.complex128]:
    """(n_bearings, 2) the complex amplitudes (X, Y) of the orbits
    ``Re(X e^{iΩt})``, fitted by least squares over the run's last tenth."""
    tail = run.t >= run.t[-1] * (1.0 - STEADY_TAIL)
    phase = speed * run.t[tail]
    basis = np.column_stack([np.cos(phase), -np.sin(phase)])
    samples = run.orbits[tail].reshape(int(tail.sum()), -1)
    (real, imaginary), *_ = np.linalg.lstsq(basis, samples, rcond=None)
    return np.asarray(real + 1j * imaginary).reshape(run.orbits.shape[1], 2)


def _steady(
    rotor: RigidRotor, run: RunUp, settings: Any, names: list[str]
) -> tuple[list[dict[str, Any]], Panel]:
    """The steady orbits' rows (semi-axis and phase lag at each bearing) and their panel."""
    from tumble.theory.rotordynamics import major_semi_axis

    speed = float(run.speed[0])
    expected = rotor.unbalance_orbits(speed, settings.unbalance, settings.unbalance_position)[0]
    measured = _fitted_orbit(run, speed)
    rows = []
    for name, theory_orbit, fitted in zip(names, expected, measured, strict=True):
        where = f"{name}, Ω = {speed:.4g} rad/s"
        rows.append(
            comparison_row(
                f"{where}: orbit's major semi-axis",
                major_semi_axis(theory_orbit[0], theory_orbit[1]),
                major_semi_axis(fitted[0], fitted[1]),
                "m",
            )
        )
        # The lag in [0°, 360°); the fit's, as the theory's plus their difference
        # (in (−180°, 180°]), so that neither wraps apart from the other.
        lag = -math.degrees(np.angle(theory_orbit[0])) % 360.0
        fitted_lag = lag - math.degrees(np.angle(fitted[0] / theory_orbit[0]))
        rows.append(comparison_row(f"{where}: phase lag of x", lag, fitted_lag, "deg"))
    for row in rows:
        row["run"] = "steady"
    tail = run.t >= run.t[-1] - 2 * math.pi / speed  # the last turn
    circle = np.exp(1j * np.linspace(0.0, 2 * math.pi, 181))
    curves = []
    for name, theory_orbit, orbit in zip(
        names, expected, run.orbits.transpose(1, 0, 2), strict=True
    ):
        curves.append(Curve(f"{name}, run", 1e6 * orbit[tail, 0], 1e6 * orbit[tail, 1]))
        ellipse = 1e6 * np.real(theory_orbit[:, None] * circle)
        curves.append(Curve(f"{name}, steady response", ellipse[0], ellipse[1], "theory"))
    panel = Panel(
        f"Orbits at the bearings at {speed:.4g} rad/s (the run's last turn)",
        "y (µm)",
        curves,
        name="orbits",
        xlabel="x (µm)",
        equal_aspect=True,
    )
    return rows, panel


def _critical_rows(
    rotor: RigidRotor, run: RunUp, names: list[str], settings: Any
) -> list[dict[str, Any]]:
    """For each critical speed the run-up passes, the speed where the orbit is
    largest after it (up to halfway to the next, and 30 % above it at most), at
    the bearing that moves most there: the peak comes after the critical speed,
    the later the faster the run-up (Friswell et al. §3.6), so the relative
    difference is the lag."""
    criticals = rotor.critical_speeds()
    # Critical speeds within CLUSTER of each other (anisotropic bearings split a
    # pair only a little) make one peak, after the last of them.
    last = np.append(criticals[1:] > (1.0 + CLUSTER) * criticals[:-1], True)
    inside = [c for c in criticals[last] if run.speed.min() < c < run.speed.max()]
    rows = []
    for k, critical in enumerate(inside):
        following = criticals[criticals > critical]
        upper = 1.3 * critical
        if following.size:
            upper = min(upper, 0.5 * (critical + float(following[0])))
        near = (run.speed >= critical) & (run.speed <= upper)
        if not near.any():
            continue
        steady = rotor.unbalance_response(critical, settings.unbalance, settings.unbalance_position)
        bearing = int(np.argmax(steady[0]))
        amplitude = run.amplitude[near, bearing]
        peak = float(run.speed[near][np.argmax(amplitude)])
        rows.append(
            comparison_row(
                f"critical speed {k + 1}: the run-up's peak ({names[bearing]})",
                float(critical),
                peak,
                "rad/s",
            )
        )
    return rows


def _campbell(rotor: RigidRotor, speeds: Array) -> Panel:
    """Whirl frequencies against the spin, forward solid and backward apart, the
    1× line and the critical speeds."""
    modes = rotor.whirl(speeds)
    curves = []
    # Backward first, so that forward whirl is drawn over it where they meet.
    for label, keep in (("backward whirl", ~modes.forward), ("forward whirl", modes.forward)):
        # Each of the four branches, broken (NaN) where its mode turns the other way.
        values = np.where(keep, modes.frequencies, np.nan).T
        gaps = np.full((4, 1), np.nan)
        x = np.concatenate([np.tile(speeds, (4, 1)), gaps], axis=1).ravel()
        curves.append(Curve(label, x, np.concatenate([values, gaps], axis=1).ravel()))
    curves.append(Curve("1× (the spin)", speeds, speeds, "fit"))
    top = float(np.nanmax(modes.frequencies))
    inside = [c for c in rotor.critical_speeds() if speeds[0] <= c <= speeds[-1]]
    if inside:  # one vertical line each, broken (NaN) between them
        x = np.repeat(inside, 3)
        y = np.tile([0.0, top, np.nan], len(inside))
        curves.append(Curve("critical speeds", x, y, "fit"))
    return Panel(
        "Campbell diagram: whirl frequencies against the spin",
        "frequency (rad/s)",
        curves,
        name="campbell",
        xlabel="spin speed Ω (rad/s)",
    )


def _response(
    rotor: RigidRotor, speeds: Array, run: RunUp, settings: Any, names: list[str]
) -> Panel:
    """The steady unbalance response at each bearing against the run-up's orbit."""
    steady = rotor.unbalance_response(speeds, settings.unbalance, settings.unbalance_position)
    curves = []
    # Drawn from a thousandth of the largest orbit up (it starts from 0 at rest).
    floor = 1e-3 * float(steady.max())
    for k, name in enumerate(names):
        measured = np.where(run.amplitude[:, k] >= floor, 1e6 * run.amplitude[:, k], np.nan)
        expected = np.where(steady[:, k] >= floor, 1e6 * steady[:, k], np.nan)
        curves.append(Curve(f"{name}, run-up", run.speed, measured))
        curves.append(Curve(f"{name}, steady response", speeds, expected, "theory"))
    return Panel(
        "Unbalance response: the orbit's size against the spin",
        "orbit (µm)",
        curves,
        name="response",
        log=True,
        xlabel="spin speed Ω (rad/s)",
    )


def _phase(rotor: RigidRotor, speeds: Array, settings: Any, names: list[str]) -> Panel:
    """The phase lag of the steady orbit's x behind the unbalance, at each bearing."""
    orbits = rotor.unbalance_orbits(speeds, settings.unbalance, settings.unbalance_position)
    curves = [
        Curve(name, speeds, -np.degrees(np.unwrap(np.angle(orbits[:, k, 0]))))
        for k, name in enumerate(names)
    ]
    return Panel(
        "Phase of the unbalance response: x behind the unbalance",
        "phase lag (deg)",
        curves,
        name="phase",
        xlabel="spin speed Ω (rad/s)",
    )
