"""A rigid rotor on elastic bearings run up through its critical speeds in time:
tumble's compiled RK4 (:func:`tumble.models.run_up`) beside scipy's DOP853 on
the same equations with a Python right-hand side (what one writes by hand,
and what :func:`run_up` did before it was compiled), in one run.

The rotor is the built-in scenario's (a 20 kg shaft on bearings of 2 and
3 MN/m, damped, 50 g·mm of unbalance 10 cm off centre), run from rest to
1000 rad/s in 2 s. Both give the orbits at the bearings; they are compared
with each other (the largest difference over the run, relative to the largest
orbit) and, for a run held at 300 rad/s, with the steady unbalance response
of :meth:`tumble.theory.RigidRotor.unbalance_orbits` at the end.

Run from the repository root::

    .venv/bin/python bench/run_up.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from scipy.integrate import solve_ivp

import tumble as tb
from machine import describe
from tumble.models import run_up

UNBALANCE = 5e-5  # kg·m
POSITION = 0.1  # m from the centre


def rotor() -> tb.theory.RigidRotor:
    shaft = tb.shapes.solid_cylinder(20.0, 0.05, 0.6)
    bearings = [tb.theory.Bearing(-0.25, 2e6, 400.0), tb.theory.Bearing(0.2, 3e6, 400.0)]
    return tb.theory.RigidRotor(shaft, bearings)


def scipy_run_up(
    machine: tb.theory.RigidRotor, duration: float, speed: float, acceleration: float,
    times: np.ndarray, rtol: float,
) -> np.ndarray:  # fmt: skip
    """The orbits (n, n_bearings, 2) by solve_ivp's DOP853 on M q̈ + (C + ΩG) q̇ +
    (K + Ω̇G) q = f(t), the right-hand side in numpy."""
    inverse = np.linalg.inv(machine.mass_matrix)
    stiffness, damping, gyroscopic = machine.stiffness, machine.damping, machine.gyroscopic
    arm = POSITION - machine.centre

    def rates(t: float, y: np.ndarray) -> np.ndarray:
        spin = speed + acceleration * t
        angle = speed * t + 0.5 * acceleration * t * t
        c, s = np.cos(angle), np.sin(angle)
        fx = UNBALANCE * (spin * spin * c + acceleration * s)
        fy = UNBALANCE * (spin * spin * s - acceleration * c)
        force = np.array([fx, fy, -arm * fy, arm * fx])
        q, v = y[:4], y[4:]
        accel = inverse @ (
            force - (damping + spin * gyroscopic) @ v - (stiffness + acceleration * gyroscopic) @ q
        )
        return np.concatenate([v, accel])

    solution = solve_ivp(rates, (0.0, duration), np.zeros(8), method="DOP853", t_eval=times,
                         rtol=rtol, atol=1e-16)  # fmt: skip
    state = solution.y[:4].T
    arms = machine.arms
    return np.stack(
        [state[:, [0]] + arms * state[:, [3]], state[:, [1]] - arms * state[:, [2]]], axis=2
    )


def timed(function: object, repeat: int) -> tuple[float, object]:
    """The median wall time of ``repeat`` calls (s) and the last result."""
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()  # type: ignore[operator]
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    import scipy

    print(describe({"scipy": scipy.__version__}))
    machine = rotor()
    run_up(machine, UNBALANCE, duration=0.01, speed=1.0)  # compile (or load) the kernel
    print(f"\n{'case':<34} {'tumble (s)':>11} {'scipy (s)':>10} {'ratio':>7}  agreement")
    for name, duration, speed, rate in (
        ("run-up 0 → 1000 rad/s in 2 s", 2.0, 0.0, 500.0),
        ("held at 300 rad/s for 2 s", 2.0, 300.0, 0.0),
    ):
        ours_time, ours = timed(
            lambda d=duration, s=speed, r=rate: run_up(
                machine, UNBALANCE, duration=d, speed=s, acceleration=r, position=POSITION
            ),
            args.repeat,
        )
        theirs_time, theirs = timed(
            lambda d=duration, s=speed, r=rate, t=ours.t: scipy_run_up(machine, d, s, r, t, 1e-10),  # type: ignore[attr-defined]
            max(1, args.repeat // 2),
        )
        orbits = ours.orbits  # type: ignore[attr-defined]
        difference = np.abs(orbits - theirs).max() / np.abs(theirs).max()
        note = f"max |Δ orbit| / max orbit = {difference:.1e}"
        if rate == 0.0:
            steady = machine.unbalance_orbits(speed, UNBALANCE, POSITION)[0]
            end = ours.t[-1]  # type: ignore[attr-defined]
            expected = np.real(steady * np.exp(1j * speed * end))
            error = np.abs(orbits[-1] - expected).max() / np.abs(steady).max()
            note += f"; end vs steady response {error:.1e}"
        ratio = theirs_time / ours_time
        print(f"{name:<34} {ours_time:>11.3f} {theirs_time:>10.2f} {ratio:>6.0f}×  {note}")


if __name__ == "__main__":
    main()
