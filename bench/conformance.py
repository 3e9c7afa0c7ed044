"""The whole conformance table, timed: every installed engine on every scenario.

For each scenario it runs every engine of ``tumble.conformance`` once at the
step given (default 1 ms over 20 s, the suite's defaults), prints the table and
the time spent in the engines and in the exact reference (the closed forms
evaluated at the sample times, the exact flip count and the metrics). The
target: the reference costs at most 1 % of the engines' time. Medians over
``--repeat`` runs; the head says where it ran.

    .venv/bin/python bench/conformance.py [--repeat 3] [--dt 1e-3] [--duration 20]
"""

from __future__ import annotations

import argparse
import statistics
from importlib.metadata import PackageNotFoundError, version

import pandas as pd

import tumble as tb
from machine import describe

#: The reference's share of the engines' time that the suite allows.
TARGET = 0.01


def _versions() -> dict[str, str]:
    found = {}
    for package in ("mujoco", "pybullet", "drake", "dartpy", "rapier3d", "scipy"):
        try:
            found[package] = version(package)
        except PackageNotFoundError:
            found[package] = "not installed"
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--dt", type=float, default=1e-3)
    parser.add_argument("--duration", type=float, default=20.0)
    parser.add_argument("--scenarios", default=",".join(tb.conformance.scenario_names()))
    parser.add_argument("--table", action="store_true", help="print every scenario's table")
    arguments = parser.parse_args()
    print(describe(_versions()))
    pd.set_option("display.width", 200)
    pd.set_option("display.max_columns", 20)
    print(f"dt {arguments.dt:g} s, {arguments.duration:g} s a run, median of {arguments.repeat}\n")
    print(f"{'scenario':<18} {'engines':>7} {'engines s':>10} {'reference s':>12} {'share':>8}")
    shares = []
    for name in arguments.scenarios.split(","):
        engine_times, reference_times = [], []
        for _ in range(arguments.repeat):
            result = tb.conformance.run(None, name, arguments.dt, arguments.duration)
            engine_times.append(result.engine_seconds)
            reference_times.append(result.reference_seconds)
        engines = statistics.median(engine_times)
        reference = statistics.median(reference_times)
        shares.append(reference / engines)
        print(
            f"{name:<18} {len(result.table):>7} {engines:>10.3f} {reference:>12.4f} "
            f"{reference / engines:>8.2%}"
        )
        if arguments.table:
            columns = [
                "engine",
                "energy_drift_final",
                "attitude_error_max",
                "flips",
                "flips_exact",
                "failed_at",
                "steps_per_second",
            ]
            print(result.table[columns].to_string(index=False), "\n")
    worst = max(shares)
    verdict = "met" if worst <= TARGET else "NOT met"
    print(
        f"\nreference's largest share of the engines' time: {worst:.2%} (target ≤ 1 %: {verdict})"
    )
    skipped = sorted(result.skipped.items())
    for engine, reason in skipped:
        print(f"skipped on {name}: {engine}: {reason}")


if __name__ == "__main__":
    main()
