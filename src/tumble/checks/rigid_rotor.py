"""The rigid rotor on elastic bearings run up: its orbits against the closed forms of
:class:`tumble.theory.RigidRotor`.

Compared: the steady orbits at the bearings (major semi-axis and the phase lag of
x behind the unbalance, fitted over the last tenth of the steady run) and the
critical speeds (the speeds where the run-up's orbit is largest come after
them, later the faster the run-up). Drawn: the Campbell diagram, the
unbalance response against the run-up's orbit, its phase, and the orbits.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.checks.base import Case, Comparison, Curve, Panel, TheoryCheck, comparison_row
from tumble.errors import InputError

if TYPE_CHECKING:
    from tumble.models import RunUp
    from tumble.theory import RigidRotor
    from tumble.trajectory import Trajectory

__all__ = ["RigidRotorCheck"]

Array = NDArray[np.float64]

#: Speeds at which the Campbell diagram and the unbalance response are drawn.
CURVE_POINTS = 400

#: The share of the steady run, at its end, over which its orbit is fitted.
STEADY_TAIL = 0.1

#: Critical speeds closer than this (relative) count as one peak of a run-up.
CLUSTER = 0.02


class RigidRotorCheck(TheoryCheck):
    """The run-ups of a rigid rotor on elastic bearings (:func:`tumble.models.run_up`)
    against its closed forms (:class:`tumble.theory.RigidRotor`). ``options``:
    ``rigid_rotor`` (the RigidRotor), ``unbalance`` (kg·m) at ``unbalance_position``
    (m along the axis), and ``speeds`` (rad/s, the run-up's first and last); the
    runs: ``"main"`` the run-up, ``"steady"`` (if any) a run at one speed."""

    name = "rigid-rotor"
    needs = "the rigid rotor on elastic bearings of a [rotordynamics] table"
    result_type = ()

    def fits(self, case: Case) -> bool:
        return "rigid_rotor" in case.options

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        raise InputError(
            "Expected the runs of tumble.models.run_up (their bearing orbits) for the "
            "rigid-rotor check, got a trajectory alone: run the rotor from a "
            "[rotordynamics] table."
        )

    def compare_runs(
        self, case: Case, trajectories: Mapping[str, Trajectory], results: Mapping[str, Any]
    ) -> Comparison:
        rotor = case.options["rigid_rotor"]
        unbalance = (case.options["unbalance"], case.options["unbalance_position"])
        low, high = case.options["speeds"]
        speeds = np.linspace(low, high, CURVE_POINTS)
        names = _bearing_names(rotor)
        critical = _critical_rows(rotor, results["main"], names, unbalance)
        rows = [{**row, "run": "main"} for row in critical]
        panels = [
            _campbell(rotor, speeds),
            _response(rotor, speeds, results["main"], unbalance, names),
            _phase(rotor, speeds, unbalance, names),
        ]
        notes = []
        if "steady" in results:
            steady = results["steady"]
            steady_rows, orbits = _steady(rotor, steady, unbalance, names)
            rows = steady_rows + rows
            panels.append(orbits)
            notes.extend(_transient_left(rotor, steady))
        return Comparison(rows, panels, notes=tuple(notes))


def _transient_left(rotor: RigidRotor, steady: RunUp) -> list[str]:
    """A note when the start-up transient of the steady run has not died away where
    its orbit is fitted. The free vibration of the start decays as e^{Re λ t}, its
    slowest mode's rate the least −Re λ; the orbit is fitted from (1 − STEADY_TAIL) T on."""
    speed = float(steady.speed[0])
    decay = float(-np.linalg.eigvals(rotor.state_matrices(speed)).real.min())
    left = math.exp(-decay * (1.0 - STEADY_TAIL) * float(steady.t[-1]))
    if left <= 1e-6:
        return []
    return [
        f"The start-up transient of the run at {speed:.4g} rad/s has decayed only to "
        f"{left:.1e} of its size where the orbit is fitted (the slowest mode decays at "
        f"{decay:.3g} 1/s): the steady rows carry that error (a longer [simulation] "
        "duration, or damped bearings, take it away)."
    ]


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
    rotor: RigidRotor, run: RunUp, unbalance: tuple[float, float], names: list[str]
) -> tuple[list[dict[str, Any]], Panel]:
    """The steady orbits' rows (semi-axis and phase lag at each bearing) and their panel."""
    from tumble.theory.rotordynamics import major_semi_axis

    speed = float(run.speed[0])
    expected = rotor.unbalance_orbits(speed, *unbalance)[0]
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
    rotor: RigidRotor, run: RunUp, names: list[str], unbalance: tuple[float, float]
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
        steady = rotor.unbalance_response(critical, *unbalance)
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
    rotor: RigidRotor, speeds: Array, run: RunUp, unbalance: tuple[float, float], names: list[str]
) -> Panel:
    """The steady unbalance response at each bearing against the run-up's orbit."""
    steady = rotor.unbalance_response(speeds, *unbalance)
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


def _phase(
    rotor: RigidRotor, speeds: Array, unbalance: tuple[float, float], names: list[str]
) -> Panel:
    """The phase lag of the steady orbit's x behind the unbalance, at each bearing."""
    orbits = rotor.unbalance_orbits(speeds, *unbalance)
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
