"""Benchmark: N free bodies at once, tumble's batch kernels against the machine.

Body-steps per second for N = 1e4, 1e5, 1e6 (Euler's equations + attitude
quaternion, renormalised each step), all in one run, medians of repeats:

* ``tumble.simulate_batch`` with RK4 (compiled, parallel over blocks of bodies,
  vectorised across the bodies of a block, with tumble's features: torques,
  per-body parameters, divergence detection, recording);
* a **bare reference kernel**: the same RK4 written out by hand for this one
  case (512-body blocks, the steps inside the block loop, SIMD across the
  block, full fast-math, no features but the renormalisation, so that its
  results are tumble's): the speed a hand-written numba kernel reaches here.
  tumble's ratio to it, and the largest difference of the states (≤ 1e-12);
* the splittings, fourth order (``splitting``) and second (``strang``),
  vectorised across the bodies of a block like RK4 (their sines and cosines
  are :func:`tumble.core.trig.cos_sin`; a free body's turns one loop over the
  block each), at the same step, and their ratios to tumble's RK4;
* the same RK4 written with numpy arrays over all bodies;
* the closed form (``method="exact"``, one evaluation a body whatever the
  duration), as a cost a body and the number of RK4 steps it equals.

The machine's double-precision peak is **measured** in the same run: a kernel
of independent multiply-add chains (64 accumulators a thread, as many threads
as numba uses), 2 flops per FMA. An RK4 body-step here is about
``FLOP_PER_BODY_STEP`` flops (four evaluations of 30, the three stages and the
combination, 42 each, the renormalisation).

Run from the repository root::

    .venv/bin/python bench/batch.py [--steps 1000] [--repeat 5]
"""

from __future__ import annotations

import argparse
import math

import numba
import numpy as np
from numba import prange

import tumble as tb
from machine import describe, measured_peak, median_rate

#: Flops of one RK4 body-step of the bare kernel (FMA counted as 2): four
#: evaluations of Euler's and the quaternion's equations (30 each), three
#: intermediate states (14 each), the combination (42) and the renormalisation (13).
FLOP_PER_BODY_STEP = 4 * 30 + 3 * 14 + 42 + 13

#: Bodies per block of the bare kernel.
BARE_BLOCK = 512


@numba.njit(inline="always", fastmath=True)
def _rates(d1, d2, d3, state):  # type: ignore[no-untyped-def]
    """ω̇ = c ω ω (c1 = (I2 − I3)/I1, cyclic) and q̇ = ½ q ⊗ (0, ω) at ``state``."""
    b1, b2, b3, r0, r1, r2, r3 = state
    return (
        d1 * b2 * b3, d2 * b3 * b1, d3 * b1 * b2,
        0.5 * (-r1 * b1 - r2 * b2 - r3 * b3), 0.5 * (r0 * b1 + r2 * b3 - r3 * b2),
        0.5 * (r0 * b2 + r3 * b1 - r1 * b3), 0.5 * (r0 * b3 + r1 * b2 - r2 * b1),
    )  # fmt: skip


@numba.njit(inline="always", fastmath=True)
def _ahead(state, f, k):  # type: ignore[no-untyped-def]
    """``state`` ``f`` s ahead along the rates ``k``."""
    return (
        state[0] + f * k[0], state[1] + f * k[1], state[2] + f * k[2], state[3] + f * k[3],
        state[4] + f * k[4], state[5] + f * k[5], state[6] + f * k[6],
    )  # fmt: skip


@numba.njit(parallel=True, fastmath=True, cache=True)
def bare_rk4(w, q, inertia, dt, n_steps):  # type: ignore[no-untyped-def]
    """RK4 for torque-free bodies, written out: ``w`` (3, N), ``q`` (4, N) in place,
    principal moments ``inertia`` (3, N)."""
    n = w.shape[1]
    for block in prange((n + BARE_BLOCK - 1) // BARE_BLOCK):
        s = block * BARE_BLOCK
        e = min(s + BARE_BLOCK, n)
        w1, w2, w3 = w[0, s:e].copy(), w[1, s:e].copy(), w[2, s:e].copy()
        q0, q1, q2, q3 = q[0, s:e].copy(), q[1, s:e].copy(), q[2, s:e].copy(), q[3, s:e].copy()
        i1, i2, i3 = inertia[0, s:e], inertia[1, s:e], inertia[2, s:e]
        c1, c2, c3 = (i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3
        h = 0.5 * dt
        sixth = dt / 6.0
        for _ in range(n_steps):
            for j in range(e - s):
                a1, a2, a3 = w1[j], w2[j], w3[j]
                p0, p1, p2, p3 = q0[j], q1[j], q2[j], q3[j]
                d1, d2, d3 = c1[j], c2[j], c3[j]
                start = (a1, a2, a3, p0, p1, p2, p3)
                k1 = _rates(d1, d2, d3, start)
                k2 = _rates(d1, d2, d3, _ahead(start, h, k1))
                k3 = _rates(d1, d2, d3, _ahead(start, h, k2))
                k4 = _rates(d1, d2, d3, _ahead(start, dt, k3))
                k1w1, k1w2, k1w3, k1q0, k1q1, k1q2, k1q3 = k1
                k2w1, k2w2, k2w3, k2q0, k2q1, k2q2, k2q3 = k2
                k3w1, k3w2, k3w3, k3q0, k3q1, k3q2, k3q3 = k3
                k4w1, k4w2, k4w3, k4q0, k4q1, k4q2, k4q3 = k4
                w1[j] = a1 + sixth * (k1w1 + 2.0 * (k2w1 + k3w1) + k4w1)
                w2[j] = a2 + sixth * (k1w2 + 2.0 * (k2w2 + k3w2) + k4w2)
                w3[j] = a3 + sixth * (k1w3 + 2.0 * (k2w3 + k3w3) + k4w3)
                n0 = p0 + sixth * (k1q0 + 2.0 * (k2q0 + k3q0) + k4q0)
                n1 = p1 + sixth * (k1q1 + 2.0 * (k2q1 + k3q1) + k4q1)
                n2 = p2 + sixth * (k1q2 + 2.0 * (k2q2 + k3q2) + k4q2)
                n3 = p3 + sixth * (k1q3 + 2.0 * (k2q3 + k3q3) + k4q3)
                scale = 1.0 / math.sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3)
                q0[j], q1[j], q2[j], q3[j] = n0 * scale, n1 * scale, n2 * scale, n3 * scale
        w[0, s:e], w[1, s:e], w[2, s:e] = w1, w2, w3
        q[0, s:e], q[1, s:e], q[2, s:e], q[3, s:e] = q0, q1, q2, q3


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


def one_size(n: int, rng: np.random.Generator, steps: int, repeat: int, peak: float) -> tuple:
    """Time N = ``n`` random bodies every way, print the row; (n, exact s a body,
    the RK4 steps that cost as much)."""
    dt = 1e-3
    moments = np.sort(rng.uniform(1.0, 3.0, size=(n, 3)), axis=1)
    moments[:, 2] = np.minimum(moments[:, 2], moments[:, 0] + moments[:, 1])
    omega = rng.normal(size=(n, 3))
    inertia = np.ascontiguousarray(moments.T)

    def bare() -> tuple[np.ndarray, np.ndarray]:
        w, q = omega.T.copy(), np.vstack([np.ones(n), np.zeros((3, n))])
        bare_rk4(w, q, inertia, dt, steps)
        return w, q

    def numpy_run() -> None:
        numpy_rk4(inertia, omega.T.copy(), np.vstack([np.ones(n), np.zeros((3, n))]), dt, short)

    def batch(method: str, count: int) -> object:
        return tb.simulate_batch(moments, omega, duration=count * dt, dt=dt, method=method)

    short = max(2, steps // 10)
    ours = median_rate(lambda: batch("rk4", steps), n * steps, repeat)
    reference = median_rate(bare, n * steps, repeat)
    split = median_rate(lambda: batch("splitting", steps), n * steps, repeat)
    strang = median_rate(lambda: batch("strang", steps), n * steps, repeat)
    theirs = median_rate(numpy_run, n * short, repeat)
    result = tb.simulate_batch(moments, omega, duration=steps * dt, dt=dt)
    w, q = bare()
    difference = max(
        float(np.max(np.abs(result.omega - w.T))), float(np.max(np.abs(result.quaternion - q.T)))
    )
    print(
        f"{n:9d} {ours:17.3g} {reference:11.3g} {ours / reference:8.2f} {difference:10.1e} "
        f"{100 * ours * FLOP_PER_BODY_STEP / peak:5.1f}% {split:10.3g} {split / ours:9.3f} "
        f"{strang:10.3g} {strang / ours:10.3f} {theirs:10.3g} {ours / theirs:9.1f}"
    )
    exact = median_rate(lambda: batch("exact", 10**6), n, repeat)  # body-evaluations a second
    return n, 1.0 / exact, ours / exact


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    # The targets (RK4 ≥ 0.9× the bare kernel, the splitting ≥ 0.3× RK4) are set
    # at 1000 steps: at fewer, a call's fixed cost (its arrays' conversions)
    # weighs more against the steps.
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print(describe({}))
    peak = measured_peak(args.repeat)
    print(
        f"measured FMA peak: {peak / 1e9:.1f} GFLOP/s ({numba.get_num_threads()} threads); "
        f"RK4: {FLOP_PER_BODY_STEP} flop a body-step"
    )
    rng = np.random.default_rng(0)
    # Compile (or load) every kernel before timing.
    bare_rk4(np.ones((3, 8)), np.vstack([np.ones(8), np.zeros((3, 8))]), np.ones((3, 8)), 1e-3, 1)
    for method in ("rk4", "splitting", "strang", "exact"):
        tb.simulate_batch(np.ones((2, 3)), np.ones((2, 3)), duration=1e-3, dt=1e-3, method=method)
    print(
        f"{'N':>9s} {'rk4 body-steps/s':>17s} {'bare kernel':>11s} {'rk4/bare':>8s} "
        f"{'max |diff|':>10s} {'% peak':>6s} {'splitting':>10s} {'split/rk4':>9s} "
        f"{'strang':>10s} {'strang/rk4':>10s} {'numpy rk4':>10s} {'rk4/numpy':>9s}"
    )
    rows = [one_size(n, rng, args.steps, args.repeat, peak) for n in (10**4, 10**5, 10**6)]
    # The closed form's cost does not depend on the duration: one evaluation a
    # body. It equals this many RK4 steps of the same batch.
    print(f"{'N':>9s} {'exact µs a body (any duration)':>31s} {'= RK4 steps':>12s}")
    for n, per_body, rk4_steps in rows:
        print(f"{n:9d} {1e6 * per_body:31.2f} {rk4_steps:12.0f}")


if __name__ == "__main__":
    main()
