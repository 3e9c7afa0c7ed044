"""What the benchmarks share: the head of every output (the date, the machine
and the versions), and a median rate.

Machines here are shared, noisy and not all alike: a benchmark compares tumble
with its peers in one run and prints where it ran.
"""

from __future__ import annotations

import datetime
import os
import platform
import statistics
import time
from collections.abc import Callable
from pathlib import Path

import numba
import numpy as np


def describe(versions: dict[str, str]) -> str:
    """Date, machine (nproc, CPU model) and the versions of tumble, numpy, numba
    and of the peers named in ``versions`` (name → version)."""
    import tumble

    model = platform.processor() or "unknown CPU"
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.is_file():
        for line in cpuinfo.read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    peers = "".join(f"{name} {version}, " for name, version in versions.items())
    return (
        f"{datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M:%S UTC}\n"
        f"nproc {os.cpu_count()}, usable CPUs {len(os.sched_getaffinity(0))}, CPU {model!r}\n"
        f"tumble {tumble.__version__}, {peers}numpy {np.__version__}, "
        f"numba {numba.__version__} ({numba.get_num_threads()} threads), "
        f"Python {platform.python_version()}"
    )


def median_rate(run: Callable[[], object], body_steps: float, repeat: int) -> float:
    """Body-steps per second: the median over ``repeat`` timed runs (after one warm-up)."""
    run()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return body_steps / statistics.median(times)
