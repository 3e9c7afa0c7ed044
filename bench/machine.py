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
from numba import prange


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


@numba.njit(parallel=True, fastmath=True, cache=True)
def fma_chains(a, b, n, threads):  # type: ignore[no-untyped-def]
    """``threads`` × 64 independent chains ``x ← a x + b``, ``n`` times each."""
    out = np.zeros(threads)
    for thread in prange(threads):
        acc = np.full(64, 1.0 + thread)
        for _ in range(n):
            for j in range(64):
                acc[j] = acc[j] * a + b
        out[thread] = acc.sum()
    return out


def fma_rate(threads: int, n: int = 2_000_000) -> float:
    """One timed run of :func:`fma_chains` on ``threads`` threads (numba's count
    must allow them; compiled first), flop/s: 2 flops an FMA."""
    fma_chains(0.999999, 1e-7, 10, threads)
    start = time.perf_counter()
    fma_chains(0.999999, 1e-7, n, threads)
    return 2 * 64 * n * threads / (time.perf_counter() - start)


def measured_peak(repeat: int, threads: int | None = None) -> float:
    """The machine's double-precision FMA throughput, flop/s (median of
    ``repeat`` runs of :func:`fma_rate`), on ``threads`` threads (numba's count
    when None): 64 independent multiply-add chains a thread."""
    before = numba.get_num_threads()
    threads = before if threads is None else threads
    numba.set_num_threads(threads)
    try:
        return statistics.median(fma_rate(threads) for _ in range(repeat))
    finally:
        numba.set_num_threads(before)
