"""Benchmark: batches of bodies carrying a rotor, with the rotor's own state
against the prescribed-momentum torque, and against separate simulate calls.

N dual-spin bodies (locked moments 4, 6, 8 kg·m², spin 1 rad/s about the
intermediate axis, a rotor of J = 0.5 kg·m² along it, relative speeds spread
over the stability map): body-steps per second of

* ``simulate_batch(internal=[Rotor], rotor_speed=...)`` (the rotor's momentum
  in the state; one compiled body per thread), RK4 and the splitting;
* ``simulate_batch(torque=RotorMomentum(h))`` (the rotors held at their relative
  momentum by a torque; the blocked RK4 kernel, vectorised across bodies);
* a loop of ``simulate(internal=[Rotor])`` calls, one body each.

All in one run, medians of repeats, with the machine printed.

Run from the repository root::

    .venv/bin/python bench/batch_parts.py [--bodies 100000] [--steps 200] [--repeat 3]
"""

from __future__ import annotations

import argparse

import numpy as np

import tumble as tb
from machine import describe, median_rate

J = 0.5
DT = 1e-2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", type=int, default=100_000)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    n, steps = args.bodies, args.steps
    inertia = np.tile([4.0, 6.0, 8.0], (n, 1))
    omega = np.tile([0.01, 1.0, 0.0], (n, 1))
    relative = np.linspace(-10.0, 10.0, n)[:, None]
    rotor = tb.Rotor([0, 1, 0], J)
    duration = steps * DT
    rows = []
    for method in ("rk4", "splitting"):

        def with_parts(method: str = method) -> object:
            return tb.simulate_batch(inertia, omega, duration=duration, dt=DT, method=method,
                                     internal=[rotor], rotor_speed=relative)  # fmt: skip

        rows.append((f"internal Rotor, {method}", median_rate(with_parts, n * steps, args.repeat)))
    # The same bodies with the rotors' relative momentum held by RotorMomentum:
    # the platform inertia is the locked one less J a aᵀ.
    platform = inertia - np.array([0.0, J, 0.0])
    momentum = np.column_stack([0 * relative[:, 0], J * relative[:, 0], 0 * relative[:, 0]])
    held = tb.torques.RotorMomentum(momentum)

    def prescribed() -> object:
        return tb.simulate_batch(platform, omega, duration=duration, dt=DT, torque=held)

    rows.append(("RotorMomentum torque, rk4", median_rate(prescribed, n * steps, args.repeat)))
    few = min(n, 200)
    body = tb.MassProperties(10.0, [0, 0, 0], np.diag([4.0, 6.0, 8.0]))

    def separate() -> object:
        for k in range(few):
            tb.simulate(body, omega[k], duration=duration, dt=DT, method="rk4",
                        internal=[tb.Rotor([0, 1, 0], J, speed=relative[k, 0])])  # fmt: skip
        return None

    rows.append(("simulate() per body, rk4", median_rate(separate, few * steps, args.repeat)))
    print(describe({}))
    print(f"{n} bodies × {steps} steps")
    base = rows[0][1]
    print(f"{'what':32s} {'body-steps/s':>14s} {'vs internal rk4':>16s}")
    for name, rate in rows:
        print(f"{name:32s} {rate:14.3g} {rate / base:16.2f}")


if __name__ == "__main__":
    main()
