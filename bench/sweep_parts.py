"""Benchmark: sweeps of bodies carrying parts, measured as they step, against the
same bodies stepped without measures and against free bodies.

N dual-spin bodies (locked moments 1, I2, 2 kg·m² with I2/I1 over 1.2–1.8, spin
1 rad/s 3° off the intermediate axis, a rotor of J = 0.05 kg·m² along it at
2 rad/s and a Kane damper), 200 steps of 2 ms: body-steps per second of

* a sweep chunk (:func:`tumble.sweep.metrics.compute_chunk`: the parts'
  measuring kernel, every measure and the final state), RK4 and the splitting
  (rotor only: the splittings take no damper);
* ``simulate_batch`` of the same bodies and parts (the parts' batch kernel,
  nothing measured), the bare cost of the steps;
* a sweep chunk of the same bodies without parts (the free body's blocked
  measuring kernel), for scale.

All in one run, medians of repeats, with the machine printed.

Run from the repository root::

    .venv/bin/python bench/sweep_parts.py [--bodies 65536] [--repeat 3]
"""

from __future__ import annotations

import argparse
import textwrap

import numpy as np

import tumble as tb
from machine import describe, median_rate
from tumble.sweep.build import parse_sweep
from tumble.sweep.metrics import compute_chunk

STEPS, DT = 200, 2e-3
ROTOR = '[[internal]]\ntype = "rotor"\naxis = [0, 1, 0]\ninertia = 0.05\nspeed = 2.0\n'
DAMPER = '[[internal]]\ntype = "kane-damper"\ninertia = 0.02\ndamping = 0.01\n'


def sweep(n: int, method: str, parts: str) -> str:
    return (
        textwrap.dedent(f"""
        [sweep]
        name = "bench"
        seed = 1
        samples = {n}
        chunk_size = {n}
        [base]
        duration = {STEPS * DT}
        dt = {DT}
        method = "{method}"
        moment_1 = 1.0
        ratio_3 = 2.0
        spin_axis = 2
        spin_rate = 1.0
        perturbation = "3 deg"
        [vary.ratio_2]
        distribution = "uniform"
        min = 1.2
        max = 1.8
        """)
        + parts
        + textwrap.dedent("""
        [outputs]
        metrics = ["flips", "first_flip_time", "max_nutation", "energy_drift", "momentum_drift"]
        final_state = true
        """)
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", type=int, default=65536)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    n = args.bodies
    rows = []
    # The same spread of I2/I1 as the sweep's (not the same draws: the rate does
    # not depend on them).
    inertia = np.column_stack([np.ones(n), np.random.default_rng(1).uniform(1.2, 1.8, n),
                               2.0 * np.ones(n)])  # fmt: skip
    tilt = np.radians(3.0)
    omega = np.tile([0.0, np.cos(tilt), np.sin(tilt)], (n, 1))
    for method, parts, internal in (
        ("rk4", ROTOR + DAMPER, [tb.Rotor([0, 1, 0], 0.05, speed=2.0),
                                 tb.KaneDamper(inertia=0.02, damping=0.01)]),
        ("splitting", ROTOR, [tb.Rotor([0, 1, 0], 0.05, speed=2.0)]),
    ):  # fmt: skip
        plan = parse_sweep(sweep(n, method, parts))
        rows.append((f"sweep chunk, {method}, parts",
                     median_rate(lambda plan=plan: compute_chunk(plan, 0), n * STEPS,
                                 args.repeat)))  # fmt: skip

        def batch(method: str = method, internal: list[object] = internal) -> object:
            return tb.simulate_batch(inertia, omega, duration=STEPS * DT, dt=DT, method=method,
                                     internal=internal)  # fmt: skip

        rows.append((f"simulate_batch, {method}, parts", median_rate(batch, n * STEPS,
                                                                     args.repeat)))  # fmt: skip
        free = parse_sweep(sweep(n, method, ""))
        rows.append((f"sweep chunk, {method}, free body",
                     median_rate(lambda free=free: compute_chunk(free, 0), n * STEPS,
                                 args.repeat)))  # fmt: skip
    print(describe({}))
    print(f"{n} bodies × {STEPS} steps")
    print(f"{'what':36s} {'body-steps/s':>14s}")
    for name, rate in rows:
        print(f"{name:36s} {rate:14.3g}")


if __name__ == "__main__":
    main()
