"""Benchmark: batches of bodies carrying parts against the free body, per body-step.

N dual-spin bodies (locked moments 4, 6, 8 kg·m², spin 1 rad/s about the
intermediate axis), 1000 steps of 10 ms: body-steps per second of

* ``simulate_batch`` of the free bodies (RK4, the splitting of order 4 and
  Strang's; the blocked kernels vectorised across bodies), the yardsticks;
* ``simulate_batch(internal=...)`` with RK4 (the blocked kernel of
  ``tumble.core.part_blocks.block_kernel``) for a rotor (J = 0.5 kg·m² along the
  spin axis, relative speeds spread over the stability map, one column of parts
  per body), a Kane damper, the two together; and the rotor with the two
  splittings (their blocked kernels);
* the same free bodies and rotors with the splittings under a constant body
  torque (``ConstantBodyTorque``: their kicks);
* ``simulate_batch(torque=RotorMomentum(h))`` (the rotors held at their relative
  momentum by a torque, through the free body's kernel);
* a loop of ``simulate(internal=[Rotor])`` calls, one body each.

Each row's cost per body-step against the free body's of its method is printed
beside it (the goal for the parts: ≤ 3). All in one run, medians of repeats, with the machine
printed.

Run from the repository root::

    .venv/bin/python bench/batch_parts.py [--bodies 100000] [--steps 1000] [--repeat 3]
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

import numpy as np

import tumble as tb
from machine import describe, median_rate

J = 0.5
DT = 1e-2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", type=int, default=100_000)
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    n, steps = args.bodies, args.steps
    inertia = np.tile([4.0, 6.0, 8.0], (n, 1))
    omega = np.tile([0.01, 1.0, 0.0], (n, 1))
    relative = np.linspace(-10.0, 10.0, n)[:, None]
    rotor = tb.Rotor([0, 1, 0], J)
    damper = tb.KaneDamper(0.05, 0.02)
    duration = steps * DT

    def batch(method: str = "rk4", **options: object) -> Callable[[], object]:
        return lambda: tb.simulate_batch(
            inertia, omega, duration=duration, dt=DT, method=method, **options
        )

    cases: list[tuple[str, Callable[[], object]]] = [
        ("free body, rk4", batch()),
        ("Rotor, rk4", batch(internal=[rotor], rotor_speed=relative)),
        ("KaneDamper, rk4", batch(internal=[damper])),
        ("Rotor + KaneDamper, rk4", batch(internal=[rotor, damper], rotor_speed=relative)),
        ("free body, splitting", batch("splitting")),
        ("Rotor, splitting", batch("splitting", internal=[rotor], rotor_speed=relative)),
        ("free body, strang", batch("strang")),
        ("Rotor, strang", batch("strang", internal=[rotor], rotor_speed=relative)),
    ]
    # Under a constant body torque: the splittings' kicks.
    push = tb.torques.ConstantBodyTorque([0.01, 0.0, 0.0])
    for method in ("splitting", "strang"):
        cases.append((f"free body + torque, {method}", batch(method, torque=push)))
        pushed = batch(method, internal=[rotor], rotor_speed=relative, torque=push)
        cases.append((f"Rotor + torque, {method}", pushed))
    # The same bodies with the rotors' relative momentum held by RotorMomentum:
    # the platform inertia is the locked one less J a aᵀ.
    platform = inertia - np.array([0.0, J, 0.0])
    momentum = np.column_stack([0 * relative[:, 0], J * relative[:, 0], 0 * relative[:, 0]])
    held = tb.torques.RotorMomentum(momentum)
    cases.append(
        (
            "RotorMomentum torque, rk4",
            lambda: tb.simulate_batch(platform, omega, duration=duration, dt=DT, torque=held),
        )
    )
    rows = [(name, median_rate(run, n * steps, args.repeat)) for name, run in cases]
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
    # Each row against the free body of its own method.
    free = {name.split(", ")[1]: rate for name, rate in rows if name.split(", ")[0] == "free body"}
    print(f"{'what':28s} {'body-steps/s':>14s} {'cost / free body':>17s}")
    for name, rate in rows:
        print(f"{name:28s} {rate:14.3g} {free[name.split(', ')[1]] / rate:17.2f}")


if __name__ == "__main__":
    main()
