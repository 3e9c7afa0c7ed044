"""Benchmark: N free bodies at once, tumble's batch kernels against numpy.

Body-steps per second for N = 1e4, 1e5, 1e6 (Euler's equations + attitude
quaternion, renormalised each step): tumble.simulate_batch with RK4 (compiled,
parallel over blocks of 128 bodies, vectorised across the bodies of a block)
and with the fourth-order splitting (one body per thread at a time), against
the same RK4 written with numpy arrays over all bodies; and the closed form
(``method="exact"``, one evaluation a body whatever the duration), as a cost a
body and the number of RK4 steps it equals. All in one run; medians of repeats.

Peak estimate: RK4 on this state costs about 200 floating-point operations per
body-step (4 evaluations of ~40 flops, the combination and renormalisation).
The machine's double-precision peak is taken as cores × clock × 16 flop/cycle
(two 4-wide FMA pipes, AVX2), printed with the result.

Run from the repository root::

    .venv/bin/python bench/batch.py [--steps 200] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import numpy as np

import tumble as tb
from tumble.body import BodyBatch
from tumble.integrators import INTEGRATORS
from tumble.torques import bind

FLOP_PER_BODY_STEP = 200


def numpy_rk4(moments: np.ndarray, w: np.ndarray, q: np.ndarray, dt: float, steps: int) -> None:
    """The same RK4 with numpy over all bodies ((3, N) and (4, N) arrays), in place."""
    i1, i2, i3 = moments

    def rates(w: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        dw = np.stack(
            [
                (i2 - i3) / i1 * w[1] * w[2],
                (i3 - i1) / i2 * w[2] * w[0],
                (i1 - i2) / i3 * w[0] * w[1],
            ]
        )
        dq = 0.5 * np.stack(
            [
                -q[1] * w[0] - q[2] * w[1] - q[3] * w[2],
                q[0] * w[0] + q[2] * w[2] - q[3] * w[1],
                q[0] * w[1] + q[3] * w[0] - q[1] * w[2],
                q[0] * w[2] + q[1] * w[1] - q[2] * w[0],
            ]
        )
        return dw, dq

    for _ in range(steps):
        a = rates(w, q)
        b = rates(w + 0.5 * dt * a[0], q + 0.5 * dt * a[1])
        c = rates(w + 0.5 * dt * b[0], q + 0.5 * dt * b[1])
        d = rates(w + dt * c[0], q + dt * c[1])
        w += dt / 6 * (a[0] + 2 * (b[0] + c[0]) + d[0])
        q += dt / 6 * (a[1] + 2 * (b[1] + c[1]) + d[1])
        q /= np.linalg.norm(q, axis=0)


def clock_ghz() -> float:
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("cpu MHz"):
            return float(line.split(":")[1]) / 1000
    return float("nan")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    cores = len(os.sched_getaffinity(0))
    peak = cores * clock_ghz() * 1e9 * 16
    print(
        f"{cores} cores at {clock_ghz():.2f} GHz: estimated peak {peak / 1e9:.0f} GFLOP/s "
        f"(AVX2 FMA); {FLOP_PER_BODY_STEP} flop per body-step"
    )
    rng = np.random.default_rng(0)
    small = np.ones((3, 8))
    free = bind(None, BodyBatch(small.T + 1), bodies=8)
    rk4_batch = INTEGRATORS["rk4"].kernel("batch", free)  # compiled (or loaded) before timing
    rk4_batch(
        small.copy(),
        np.vstack([np.ones(8), np.zeros((3, 8))]),
        small + 1,
        free.params,
        free.context,
        0.0,
        1e-3,
        2,
        np.zeros(8, dtype=np.int64),
    )
    tb.simulate_batch(np.ones((2, 3)), np.ones((2, 3)), duration=1e-3, dt=1e-3, method="splitting")
    print(
        f"{'N':>9s} {'rk4 body-steps/s':>17s} {'splitting':>10s} {'numpy rk4':>10s} "
        f"{'rk4/numpy':>9s} {'split/numpy':>11s} {'rk4 % peak':>10s}"
    )
    rows = []
    tb.simulate_batch(np.ones((2, 3)), np.ones((2, 3)), duration=1e-3, dt=1e-3, method="exact")
    for n in (10**4, 10**5, 10**6):
        moments = np.sort(rng.uniform(1.0, 3.0, size=(n, 3)), axis=1)
        moments[:, 2] = np.minimum(moments[:, 2], moments[:, 0] + moments[:, 1])
        omega = rng.normal(size=(n, 3))
        ours, split, theirs = [], [], []
        numpy_steps = max(2, args.steps // 20)
        for _ in range(args.repeat):
            start = time.perf_counter()
            tb.simulate_batch(moments, omega, duration=args.steps * 1e-3, dt=1e-3)
            ours.append(n * args.steps / (time.perf_counter() - start))
            start = time.perf_counter()
            tb.simulate_batch(
                moments, omega, duration=numpy_steps * 1e-3, dt=1e-3, method="splitting"
            )
            split.append(n * numpy_steps / (time.perf_counter() - start))
            w = omega.T.copy()
            q = np.vstack([np.ones(n), np.zeros((3, n))])
            start = time.perf_counter()
            numpy_rk4(moments.T.copy(), w, q, 1e-3, numpy_steps)
            theirs.append(n * numpy_steps / (time.perf_counter() - start))
        a, b = statistics.median(ours), statistics.median(theirs)
        c = statistics.median(split)
        print(
            f"{n:9d} {a:17.3g} {c:10.3g} {b:10.3g} {a / b:9.1f} {c / b:11.1f} "
            f"{100 * a * FLOP_PER_BODY_STEP / peak:9.1f}%"
        )
        exact_times = []
        for _ in range(args.repeat):
            start = time.perf_counter()
            tb.simulate_batch(moments, omega, duration=1e3, dt=1e-3, method="exact")
            exact_times.append(time.perf_counter() - start)
        per_body = statistics.median(exact_times) / n
        rows.append((n, per_body, per_body * a))
    # The closed form's cost does not depend on the duration: one evaluation a
    # body. It equals this many RK4 steps of the same batch.
    print(f"{'N':>9s} {'exact µs a body (any duration)':>31s} {'= RK4 steps':>12s}")
    for n, per_body, steps in rows:
        print(f"{n:9d} {1e6 * per_body:31.2f} {steps:12.0f}")


if __name__ == "__main__":
    main()
