"""Benchmark: how soon a request that cannot work is refused.

Each case is a request that used to fail only after minutes of work (or be
killed by the operating system), timed from the call to the refusal:

* ``simulate(box, ω, duration=1e9 s, dt=1e-3 s)``: 1e12 recorded samples;
* ``simulate_batch`` of 1e6 bodies for 1e4 s at dt = 1e-3 s, recording every
  step: ~1e13 recorded states (the arrays of the bodies are made first, as a
  user would, and not timed);
* ``tumble run gyroscope -o /dev/null/x`` in a fresh process (start-up
  included), against ``tumble --version`` in a fresh process: the refusal's
  own cost is the difference.

The target: each refused in under a second, with the estimate in its message.
Times are medians of ``--repeat`` rounds after one untimed warm-up.

Run from the repository root::

    .venv/bin/python bench/refusals.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from collections.abc import Callable

import numpy as np

import tumble as tb
from machine import describe

TARGET = 1.0  # s
BOX = tb.shapes.box(1.0, [0.1, 0.2, 0.3])
BODIES = 10**6


def refusal(call: Callable[[], object]) -> tuple[float, str]:
    """Seconds from the call to its InputError, and the message."""
    start = time.perf_counter()
    try:
        call()
    except tb.InputError as exc:
        return time.perf_counter() - start, str(exc)
    raise AssertionError("the request was not refused")


def script(*args: str) -> tuple[float, subprocess.CompletedProcess[str]]:
    """Seconds a fresh ``tumble`` process takes, and its result."""
    command = [sys.executable, "-c", "from tumble.cli import main; main()", *args]
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    return time.perf_counter() - start, done


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print(describe({}))
    inertia = np.tile([1.0, 2.0, 3.0], (BODIES, 1))
    omega = np.tile([0.1, 2.0, 0.1], (BODIES, 1))
    cases: dict[str, Callable[[], object]] = {
        "simulate, 1e12 samples": lambda: tb.simulate(BOX, [1.0, 2.0, 3.0], duration=1e9, dt=1e-3),
        "simulate_batch, 1e6 bodies x 1e7 records": lambda: tb.simulate_batch(
            inertia, omega, duration=1e4, dt=1e-3, record_every=1
        ),
    }
    print(f"\n{'case':<44} {'median s':>9}  target < {TARGET} s  message")
    for name, call in cases.items():
        refusal(call)  # warm-up: imports, compilation of nothing
        times = []
        for _ in range(args.repeat):
            seconds, message = refusal(call)
            times.append(seconds)
        median = statistics.median(times)
        verdict = "met" if median < TARGET else "NOT met"
        print(f"{name:<44} {median:9.3f}  {verdict:<14} {message[:150]}...")
    script("--version")
    start_up, refused = [], []
    for _ in range(args.repeat):
        start_up.append(script("--version")[0])
        seconds, done = script("run", "gyroscope", "-o", "/dev/null/x")
        assert done.returncode == 2, done.stderr
        refused.append(seconds)
    own = statistics.median(refused) - statistics.median(start_up)
    verdict = "met" if statistics.median(refused) < TARGET else "NOT met"
    print(
        f"{'tumble run -o /dev/null/x (fresh process)':<44} {statistics.median(refused):9.3f}  "
        f"{verdict:<14} {done.stderr.strip()}"
    )
    print(f"{'  of which start-up (tumble --version)':<44} {statistics.median(start_up):9.3f}")
    print(f"{'  the refusal itself':<44} {own:9.3f}")


if __name__ == "__main__":
    main()
