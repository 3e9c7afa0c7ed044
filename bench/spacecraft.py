"""Benchmark: spacecraft with reaction wheels and in orbit, tumble against Basilisk,
side by side in one run.

Three cases, set up in Basilisk by :mod:`basilisk_cases` (``bsk`` 2.12.1, a
bench-only dependency) and here in tumble, the same physical system in both
(Basilisk's balanced wheels add no mass or inertia: its hub holds them, as
tumble's body does):

a. **Reaction wheels**: a 750 kg hub, three 9 kg wheels (Js = 0.15, Jt = 0.08
   kg·m²) on its axes at 0.5 m, spinning at (100, −200, 300) rad/s, the body at
   (0.05, −0.03, 0.02) rad/s; motor torques (0.2, −0.1, 0.15) N·m for 0.5 s,
   then a coast to 20 s. Oracle: an independent DOP853 integration at rtol
   1e-13 (velocities as the state, body axes, tests/reference.py); the total H
   (the motors' torques are internal) and, after 0.5 s, the energy are conserved.
b. **Gravity gradient**: a 100 kg body, moments (5, 50, 52) kg·m², in a circular
   orbit of 7000 km, pitched 5° from the local vertical at rest in the orbiting
   frame, over three orbits. The motion stays in the orbit plane and the pitch
   is a pendulum in 2θ: ``sin θ(t) = sin θ0 cd(ω_p t | sin² θ0)``,
   ω_p = n √(3 (B − A)/C) — the oracle, in closed form. (Basilisk integrates
   the orbit as well; tumble's orbit is the exact circle.)
c. **Spin-up**: a wheel (Js = 0.5 kg·m²) on axis z of a body at rest (I_z =
   15.5 kg·m² with it), 0.1 N·m for 10 s. Oracle: the closed form
   (:func:`tumble.theory.wheel_spin_up`).

For each configuration (integrator and step): the largest error of the attitude
(rad) against the oracle over the run, and the wall time, medians of ``--repeat``
rounds in which the configurations of both sides are called one after the other,
each timed three ways: *alternated* (right after another configuration's or the
peer's call), *hot* (at once again: its code and data in the caches) and *cold*
(after 64 MB of other memory traffic). Basilisk's time is its
``ExecuteSimulation`` alone (its setup left out), tumble's a whole
:func:`tumble.simulate` call (its setup in: kept between calls that describe the
same motion); each side times its own call, the bench's work around it left out.
Both do the same work: the states
recorded every ``record`` s of simulated time, nothing else (Basilisk's Python-side
logger of H and the energy is left out: ``basilisk_cases`` adds it only when asked).
Then, for each Basilisk configuration and each way of timing, the fastest tumble
configuration at equal or better accuracy (errors below ``FLOOR``, the oracles' own
accuracy, count as equal) and the ratio of their times.

Run from the repository root (``make bench`` installs Basilisk)::

    .venv/bin/python bench/spacecraft.py [--repeat 5] [--cases abc]
"""

from __future__ import annotations

import argparse
import itertools
import math
import statistics
import sys
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation
from scipy.special import ellipj

import basilisk_cases as bsk
import tumble as tb
from machine import describe

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from reference import gyrostat_reference  # the tests' independent reference

#: Errors below this (rad) count as equal: the oracles' own accuracy in these runs (the
#: smallest error measured against them is 8.9e-14 rad, case a's adaptive runs: the
#: reference's own round-off over 20 s).
FLOOR = 1e-13

# Case a ----------------------------------------------------------------------
WHEEL_AXES = np.eye(3)
WHEEL_SPEEDS = np.array([100.0, -200.0, 300.0])
WHEEL_TORQUES = np.array([0.2, -0.1, 0.15])
WHEELS_OMEGA0 = np.array([0.05, -0.03, 0.02])
WHEELS_DURATION = 20.0
TORQUE_OFF = 0.5

# Case b ----------------------------------------------------------------------
ORBIT_RADIUS = 7000e3
ORBIT_RATE = math.sqrt(bsk.MU_EARTH / ORBIT_RADIUS**3)
BOOM = tb.MassProperties(100.0, [0, 0, 0], np.diag([5.0, 50.0, 52.0]))
PITCH0 = math.radians(5.0)
ORBIT_DURATION = 17490.0  # three orbits, in whole steps of 10 s


def stepping(method: str, setting: float, record: float) -> dict[str, Any]:
    """simulate's keywords for a configuration: a step of ``setting`` s, or for the
    adaptive method its rtol, the samples every ``record`` s either way."""
    if method == "adaptive":
        return {"method": method, "dt": record, "rtol": setting, "atol": 1e-16}
    return {"method": method, "dt": setting, "record_every": max(1, round(record / setting))}


def wheel_body() -> tb.MassProperties:
    """Case a's hub with its three wheels locked inside (tumble's convention)."""
    hub = tb.MassProperties(750.0, [0, 0, 0], np.diag([900.0, 800.0, 600.0]))
    for axis in WHEEL_AXES:
        turn, _ = Rotation.align_vectors([axis], [[0.0, 0.0, 1.0]])
        own = turn.as_matrix() @ np.diag([0.08, 0.08, 0.15]) @ turn.as_matrix().T
        hub = hub + tb.MassProperties(9.0, 0.5 * axis, own)
    return hub


#: Case a's body and rotors, built once (the setup, outside the timed calls).
WHEEL_BODY = wheel_body()
ROTORS = [
    tb.Rotor(axis, 0.15, speed=speed, torque=[(0.0, u), (TORQUE_OFF, 0.0)])
    for axis, speed, u in zip(WHEEL_AXES, WHEEL_SPEEDS, WHEEL_TORQUES, strict=True)
]


def simulated(body: tb.MassProperties, omega0: Any, **keywords: Any) -> tuple[Any, float]:
    """``tb.simulate``'s trajectory and the wall time of that call alone (s), as
    Basilisk's runs report their ``ExecuteSimulation``'s: the bench's own work
    around the call (its keywords, its results) is not counted on either side."""
    start = time.perf_counter()
    run = tb.simulate(body, omega0, **keywords)
    return run, time.perf_counter() - start


def wheels_tumble(method: str, dt: float, record: float) -> dict[str, Any]:
    run, wall = simulated(
        WHEEL_BODY, WHEELS_OMEGA0, duration=WHEELS_DURATION, internal=ROTORS,
        **stepping(method, dt, record),
    )  # fmt: skip
    return {"t": run.t, "quaternion": run.quaternion, "run": run, "wall_s": wall}


def wheels_reference(times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    def motor(u: float) -> Callable[[float], float]:
        return lambda t: u if t < TORQUE_OFF else 0.0

    rotors = [
        (axis, 0.15, speed, motor(u))
        for axis, speed, u in zip(WHEEL_AXES, WHEEL_SPEEDS, WHEEL_TORQUES, strict=True)
    ]
    omega, matrices, _, _ = gyrostat_reference(
        WHEEL_BODY, WHEELS_OMEGA0, np.array([1.0, 0, 0, 0]), WHEELS_DURATION, rotors=rotors,
        times=times, breaks=(TORQUE_OFF,),
    )  # fmt: skip
    return omega, matrices


def angle_error(quaternion: np.ndarray, matrices: np.ndarray) -> float:
    turned = (
        Rotation.from_quat(quaternion, scalar_first=True) * Rotation.from_matrix(matrices).inv()
    )
    return float(np.max(turned.magnitude()))


def pitch_of(quaternion: np.ndarray, radial: np.ndarray) -> np.ndarray:
    """The angle (rad) of body x from the radial direction, about the orbit normal z."""
    x_axis = Rotation.from_quat(quaternion, scalar_first=True).apply([1.0, 0.0, 0.0])
    along = np.cross([0.0, 0.0, 1.0], radial)
    return np.arctan2(np.einsum("ij,ij->i", x_axis, along), np.einsum("ij,ij->i", x_axis, radial))


def pitch_exact(t: np.ndarray) -> np.ndarray:
    """sin θ = sin θ0 cd(ω_p t | sin² θ0), the pendulum in 2θ released from rest."""
    a, b, c = np.diag(BOOM.inertia)
    rate = ORBIT_RATE * math.sqrt(3 * (b - a) / c)
    _, cn, dn, _ = ellipj(rate * t, math.sin(PITCH0) ** 2)
    return np.arcsin(math.sin(PITCH0) * cn / dn)


def orbit_tumble(method: str, dt: float, record: float) -> dict[str, Any]:
    start = Rotation.from_euler("z", PITCH0)
    run, wall = simulated(
        BOOM, [0.0, 0.0, ORBIT_RATE], attitude0=start, duration=ORBIT_DURATION,
        torque=tb.torques.GravityGradient(ORBIT_RATE), **stepping(method, dt, record),
    )  # fmt: skip
    radial = np.column_stack([np.cos(ORBIT_RATE * run.t), np.sin(ORBIT_RATE * run.t), 0 * run.t])
    return {"t": run.t, "pitch": pitch_of(run.quaternion, radial), "wall_s": wall}


SPUN = tb.MassProperties(52.0, [0, 0, 0], np.diag([10.3, 12.3, 15.5]))  # hub and wheel
SPINNER = [tb.Rotor([0, 0, 1], 0.5, torque=0.1)]


def spin_up_tumble(method: str, dt: float, record: float) -> dict[str, Any]:
    run, wall = simulated(
        SPUN, [0, 0, 0], duration=10.0, internal=SPINNER, **stepping(method, dt, record)
    )
    return {"t": run.t, "quaternion": run.quaternion, "wall_s": wall}


def spin_up_error(t: np.ndarray, quaternion: np.ndarray) -> float:
    closed = tb.theory.wheel_spin_up(SPUN, 0.5, 0.1)
    angle = closed.at(t)[2]
    expected = Rotation.from_rotvec(np.outer(angle, [0.0, 0.0, 1.0]))
    return float(
        np.max((Rotation.from_quat(quaternion, scalar_first=True) * expected.inv()).magnitude())
    )


# ------------------------------------------------------------------ running
#: How each call is timed: right after a call of its own ("hot": its code and data in
#: the caches), right after another configuration's or the peer's call ("alternated"),
#: and after ``TRAFFIC`` bytes of other memory traffic ("cold").
SETTINGS = ("hot", "alternated", "cold")

#: The memory traffic before a cold call: more than the last-level cache of the
#: machines here (up to 32 MB on a server's socket), read and written once.
TRAFFIC = 64 * 2**20

_SCRATCH = np.zeros(TRAFFIC // 8)


def churn() -> None:
    """Read and write :data:`TRAFFIC` bytes, as other work between two calls would."""
    _SCRATCH[:] += 1.0


def timed(call: Callable[[], dict[str, Any]]) -> tuple[float, dict[str, Any]]:
    """One call's wall time (each side reports its own ``wall_s``) and result."""
    result = call()
    return result["wall_s"], result


def case(
    name: str,
    runs: list[tuple[str, str, Callable[[], dict[str, Any]]]],
    error: Callable[[dict[str, Any]], float],
    repeat: int,
) -> list[tuple[str, str, float, dict[str, float]]]:
    """Time and measure every configuration of a case, the configurations of both
    sides alternated call by call (so that the host's slow phases hit them alike):
    each ``repeat`` round times each configuration alternated (after the one before
    it), hot (at once again) and cold (after :func:`churn`). Print and return
    (who, configuration, error, median seconds by setting) rows."""
    print(f"\n{name}")
    print(
        f"  {'who':9s} {'configuration':32s} {'attitude error':>15s} "
        + " ".join(f"{setting + ' (s)':>15s}" for setting in SETTINGS)
    )
    # The two sides interleaved: a Basilisk configuration, a tumble one, and so on.
    peers = [run for run in runs if run[0] == "Basilisk"]
    ours = [run for run in runs if run[0] != "Basilisk"]
    runs = [run for pair in itertools.zip_longest(peers, ours) for run in pair if run]
    results = {label: call() for _, label, call in runs}  # warm-up: compile, import
    times: dict[str, dict[str, list[float]]] = {
        label: {setting: [] for setting in SETTINGS} for _, label, _ in runs
    }
    for _ in range(repeat):
        for _, label, call in runs:
            seconds, results[label] = timed(call)
            times[label]["alternated"].append(seconds)
            times[label]["hot"].append(timed(call)[0])
            churn()
            times[label]["cold"].append(timed(call)[0])
    rows = []
    for who, label, _ in peers + ours:
        wrong = error(results[label])
        medians = {setting: statistics.median(times[label][setting]) for setting in SETTINGS}
        rows.append((who, label, wrong, medians))
        print(
            f"  {who:9s} {label:32s} {wrong:15.3e} "
            + " ".join(f"{medians[setting]:15.5f}" for setting in SETTINGS)
        )
    return rows


def ratios(rows: list[tuple[str, str, float, dict[str, float]]]) -> dict[str, list[float]]:
    """For each Basilisk row and each setting, the fastest tumble row at equal or better
    accuracy (errors below FLOOR count as equal) and the ratio of their times."""
    found: dict[str, list[float]] = {setting: [] for setting in SETTINGS}
    print(
        f"  {'Basilisk':32s} {'fastest tumble at equal or better accuracy':44s} "
        + " ".join(f"{setting:>10s}" for setting in SETTINGS)
    )
    for who, label, wrong, seconds in rows:
        if who != "Basilisk":
            continue
        able = [r for r in rows if r[0] == "tumble" and r[2] <= max(wrong, FLOOR)]
        if not able:
            print(f"  {label:32s} {'none':44s}")
            continue
        shown = []
        for setting in SETTINGS:
            best = min(able, key=lambda r: r[3][setting])
            found[setting].append(seconds[setting] / best[3][setting])
            shown.append(best)
        best = shown[0]
        print(
            f"  {label:32s} {best[1] + f' ({best[2]:.1e})':44s} "
            + " ".join(f"{found[setting][-1]:10.1f}" for setting in SETTINGS)
        )
    return found


Run = tuple[str, str, Callable[[], dict[str, Any]]]


def tumble_runs(
    configurations: tuple[tuple[str, float], ...],
    call: Callable[[str, float, float], dict[str, Any]],
    record: float,
) -> list[Run]:
    """tumble's configurations (method, step in s or the adaptive method's rtol)."""
    runs: list[Run] = []
    for method, setting in configurations:
        label = (
            f"{method} rtol {setting:g}" if method == "adaptive" else f"{method} dt = {setting:g} s"
        )
        runs.append(("tumble", label, partial(call, method, setting, record)))
    return runs


def wheels_case(repeat: int) -> dict[str, list[float]]:
    """Case a: three reaction wheels; its ratios by setting."""
    record = 0.1
    times = np.arange(0.0, WHEELS_DURATION + record / 2, record)
    matrices_ref = wheels_reference(times)[1]
    runs: list[Run] = [
        ("Basilisk", f"RK4 dt = {dt:g} s", partial(bsk.reaction_wheels, dt, record_dt=record))
        for dt in (0.1, 0.05, 0.01, 0.001)
    ]
    for tol in (1e-8, 1e-12):
        call = partial(
            bsk.reaction_wheels, 0.1, record_dt=record, integrator="rkf78", tolerance=tol,
            abs_tolerance=tol * 1e-4,
        )  # fmt: skip
        runs.append(("Basilisk", f"RKF78 dt = 0.1 s, tol {tol:g}", call))
    configurations = (("rk4", 0.1), ("rk4", 0.05), ("rk4", 0.01), ("splitting", 0.1),
                      ("splitting", 0.05), ("adaptive", 1e-10), ("adaptive", 1e-13))  # fmt: skip
    runs += tumble_runs(configurations, wheels_tumble, record)

    def wheels_error(result: dict[str, Any]) -> float:
        at = np.searchsorted(result["t"], times - 1e-9)
        return angle_error(result["quaternion"][at], matrices_ref)

    title = "a. three reaction wheels: torques for 0.5 s, then a coast to 20 s"
    found = ratios(case(title, runs, wheels_error, repeat))
    run = wheels_tumble("rk4", 0.01, record)["run"]
    after = run.t >= TORQUE_OFF
    print(
        f"  tumble rk4 dt = 0.01 s: |ΔH|/|H| {run.drift['angular_momentum_vector']:.1e}, the "
        f"energy after 0.5 s within {np.ptp(run.energy[after]):.1e} J of {run.energy[-1]:.6g} J"
    )
    return found


def orbit_case(repeat: int) -> dict[str, list[float]]:
    """Case b: the gravity-gradient pitch libration; its ratios by setting."""
    record = 10.0

    def orbit_error(result: dict[str, Any]) -> float:
        if "pitch" not in result:  # Basilisk's: the radial direction from its own position
            radial = result["position"] / np.linalg.norm(result["position"], axis=1)[:, None]
            result["pitch"] = pitch_of(result["quaternion"], radial)
        return float(np.max(np.abs(result["pitch"] - pitch_exact(result["t"]))))

    orbit = partial(bsk.gravity_gradient, duration=ORBIT_DURATION, record_dt=record)
    runs = [("Basilisk", f"RK4 dt = {dt:g} s", partial(orbit, dt)) for dt in (10.0, 5.0, 1.0)]
    call = partial(orbit, 10.0, integrator="rkf78", tolerance=1e-12, abs_tolerance=1e-16)
    runs.append(("Basilisk", "RKF78 dt = 10 s, tol 1e-12", call))
    configurations = (("rk4", 10.0), ("rk4", 5.0), ("rk4", 1.0), ("splitting", 10.0),
                      ("adaptive", 1e-10), ("adaptive", 1e-13))  # fmt: skip
    runs += tumble_runs(configurations, orbit_tumble, record)
    title = "b. gravity-gradient pitch libration, three orbits (pitch error, rad)"
    return ratios(case(title, runs, orbit_error, repeat))


def spin_up_case(repeat: int) -> dict[str, list[float]]:
    """Case c: a wheel spun up; its ratios by setting."""
    record = 0.1
    runs = [
        ("Basilisk", f"RK4 dt = {dt:g} s", partial(bsk.spin_up, dt, record_dt=record))
        for dt in (0.1, 0.01)
    ]
    configurations = (("rk4", 0.1), ("splitting", 0.1), ("adaptive", 1e-10))
    runs += tumble_runs(configurations, spin_up_tumble, record)

    def spin_error(result: dict[str, Any]) -> float:
        return spin_up_error(result["t"], result["quaternion"])

    return ratios(case("c. one wheel spun up from rest, 10 s", runs, spin_error, repeat))


CASES = {"a": wheels_case, "b": orbit_case, "c": spin_up_case}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument(
        "--cases", default="abc", help="which cases to run (letters of a, b, c; default all)"
    )
    args = parser.parse_args()
    from Basilisk import __version__ as bsk_version

    print(describe({"Basilisk": bsk_version}))
    summary = {name: CASES[name](args.repeat) for name in sorted(set(args.cases) & set(CASES))}
    print(
        "\nSpeed of tumble over Basilisk at equal or better accuracy (the smallest per case, "
        "and the largest), by how the calls were timed:"
    )
    for name, found in summary.items():
        for setting in SETTINGS:
            values = found[setting]
            shown = f"{min(values):.1f}× (up to {max(values):.1f}×)" if values else "none"
            print(f"  case {name}, {setting:10s}: {shown}")


if __name__ == "__main__":
    main()
