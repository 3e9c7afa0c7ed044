"""Benchmark: the heavy symmetric top in closed form against tumble's own steppers.

The case is the disk of ``bench/heavy_top.py`` (:class:`peers.Top`: m = 1 kg,
r = 0.1 m, pivot 0.1 m from its centre on the axis, spin 200 rad/s, axis
horizontal, released from rest), run for 100 nutation periods (≈ 7.9 s) and
sampled ten times a nutation period (1001 samples).

The truth is scipy's DOP853 at rtol 1e-13, atol 1e-15 at the same samples
(:func:`peers.scipy_top`). The error of a run is the largest, over the samples,
of the attitude error (rad: the angle of ``R_run R_truthᵀ``) and of |Δω|/|ω0|.

Measured:

* the closed form (``simulate(method="exact")``) at the samples, and its cost a
  sample from 1e6 samples (the public call, and the compiled evaluation alone);
* tumble's 4th-order splitting and RK4 at steps from coarse to fine (each a
  whole divisor of the sampling interval), every step's error and time.

Times are medians of ``--repeat`` interleaved rounds after one untimed warm-up
of each configuration. The targets: the closed form costs ≤ 1 µs a sample, and
is ≥ 100× faster than the splitting at equal accuracy (the splitting's first
step whose error is at most ``max(exact error, 1e-9)``; its error cannot reach
the closed form's ~1e-12, so this favours the splitting).

Run from the repository root::

    .venv/bin/python bench/lagrange_top.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
import warnings
from collections.abc import Callable

import numpy as np
from scipy.spatial.transform import Rotation

import tumble as tb
from peers import Top, environment, scipy_top
from tumble.body import RigidBody
from tumble.errors import CoarseStepWarning
from tumble.theory.motions import lagrange_top

PERIODS = 100
SAMPLES_PER_PERIOD = 10
TARGET_SAMPLE_COST = 1e-6  # s
TARGET_RATIO = 100.0
ERROR_FLOOR = 1e-9  # the splitting is compared where its error reaches max(exact, this)
STEPS_PER_SAMPLE = (1, 2, 4, 8, 16, 32, 64, 128)

TOP = Top()
DISK = tb.shapes.thin_disk(TOP.mass, TOP.radius)
PIVOT = np.array([0.0, 0.0, -TOP.lever])
GRAVITY = np.array([0.0, 0.0, -TOP.gravity])


def nutation_period() -> float:
    body = RigidBody(DISK, pivot=PIVOT)
    return lagrange_top(body, GRAVITY, TOP.omega0, TOP.attitude0).mean_rates()[0]


def run(method: str, duration: float, sample: float, steps_per_sample: int) -> tb.Trajectory:
    return tb.simulate(
        DISK,
        TOP.omega0,
        attitude0=TOP.attitude0,
        duration=duration,
        dt=sample / steps_per_sample,
        record_every=steps_per_sample,
        pivot=PIVOT,
        gravity=GRAVITY,
        method=method,
    )


def error(result: tb.Trajectory, truth_omega: np.ndarray, truth_q: np.ndarray) -> float:
    turn = Rotation.from_quat(result.quaternion, scalar_first=True)
    attitude = np.max((turn * Rotation.from_quat(truth_q, scalar_first=True).inv()).magnitude())
    omega = np.max(np.linalg.norm(result.omega - truth_omega, axis=1))
    return float(max(attitude, omega / np.linalg.norm(TOP.omega0)))


def median_time(jobs: dict[str, Callable[[], object]], repeat: int) -> dict[str, float]:
    """Median wall time of each job over ``repeat`` interleaved rounds (after a warm-up)."""
    for job in jobs.values():
        job()
    times: dict[str, list[float]] = {name: [] for name in jobs}
    for _ in range(repeat):
        for name, job in jobs.items():
            start = time.perf_counter()
            job()
            times[name].append(time.perf_counter() - start)
    return {name: statistics.median(values) for name, values in times.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print("The heavy symmetric top in closed form against tumble's steppers")
    print(environment())
    period = nutation_period()
    duration = PERIODS * period
    sample = period / SAMPLES_PER_PERIOD
    n_samples = PERIODS * SAMPLES_PER_PERIOD + 1
    print(
        f"disk m = {TOP.mass} kg, r = {TOP.radius} m, pivot {TOP.lever} m below its centre, "
        f"spin {TOP.spin} rad/s, axis horizontal, released from rest; nutation period "
        f"{period * 1e3:.4f} ms; {PERIODS} periods = {duration:.4f} s, {n_samples} samples"
    )
    times = np.linspace(0.0, duration, n_samples)
    start = time.perf_counter()
    truth = scipy_top(
        dataclasses.replace(TOP, duration=duration), rtol=1e-13, atol=1e-15, t_eval=times
    )
    print(f"truth: scipy DOP853 rtol 1e-13 atol 1e-15 ({time.perf_counter() - start:.1f} s)\n")

    configs: dict[str, Callable[[], tb.Trajectory]] = {
        "exact": lambda: run("exact", duration, sample, 1)
    }
    for method in ("splitting", "rk4"):
        for k in STEPS_PER_SAMPLE:
            configs[f"{method} dt={sample / k:.3g}"] = lambda m=method, k=k: run(
                m, duration, sample, k
            )
    errors = {}
    # The coarse steps are compared on purpose: their warnings are expected.
    warnings.simplefilter("ignore", CoarseStepWarning)
    for name, job in configs.items():
        result = job()
        assert np.allclose(result.t, truth.t, rtol=0, atol=1e-9 * duration), name
        errors[name] = error(result, truth.omega, truth.quaternion)
    costs = median_time(configs, args.repeat)

    print(f"{'method':<24} {'steps':>9} {'time ms':>9} {'error':>9}")
    for name in configs:
        steps = 0 if name == "exact" else round(duration / float(name.split("=")[1]))
        print(f"{name:<24} {steps:>9} {costs[name] * 1e3:>9.3f} {errors[name]:>9.2e}")

    many = np.linspace(0.0, 1e4 * period, 1_000_000)
    top = lagrange_top(RigidBody(DISK, pivot=PIVOT), GRAVITY, TOP.omega0, TOP.attitude0)

    def public() -> tb.Trajectory:
        return tb.simulate(
            DISK,
            TOP.omega0,
            attitude0=TOP.attitude0,
            duration=many[-1],
            dt=many[1] - many[0],
            pivot=PIVOT,
            gravity=GRAVITY,
            method="exact",
        )

    big = median_time({"public": public, "compiled": lambda: top.at(many)}, args.repeat)
    print(f"\ncost a sample over {len(many):.0e} samples (10⁴ nutation periods):")
    print(f"  simulate(method='exact')     {big['public'] / len(many) * 1e9:8.1f} ns")
    print(f"  LagrangeTop.at (compiled)    {big['compiled'] / len(many) * 1e9:8.1f} ns")
    per_sample = big["public"] / len(many)
    verdict = "met" if per_sample <= TARGET_SAMPLE_COST else "not met"
    print(f"  target ≤ {TARGET_SAMPLE_COST * 1e6:.0f} µs a sample: {verdict}")

    level = max(errors["exact"], ERROR_FLOOR)
    print(f"\nequal accuracy: error ≤ max(exact {errors['exact']:.1e}, {ERROR_FLOOR:.0e})")
    for method in ("splitting", "rk4"):
        reached = [name for name in configs if name.startswith(method) and errors[name] <= level]
        if not reached:
            finest = min(
                (name for name in configs if name.startswith(method)), key=lambda n: errors[n]
            )
            print(f"  {method}: never reaches it (best {errors[finest]:.1e} at {finest})")
            continue
        finest = [name for name in configs if name.startswith(method)][-1]
        for name in dict.fromkeys((reached[0], finest)):
            ratio = costs[name] / costs["exact"]
            verdict = "met" if ratio >= TARGET_RATIO else "not met"
            print(
                f"  {name:<22} error {errors[name]:.1e} in {costs[name] * 1e3:.2f} ms: "
                f"{ratio:,.0f}× the closed form's {costs['exact'] * 1e3:.3f} ms "
                f"(target ≥ {TARGET_RATIO:.0f}×: {verdict})"
            )


if __name__ == "__main__":
    main()
