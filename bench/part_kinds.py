"""Benchmark: the kernels of bodies carrying parts, this tree against another.

Nanoseconds per step of one body (``simulate``, recording every 100th step)
and per body-step of a batch of 2000 bodies (``simulate_batch``), for a rotor,
a rotor with a Kane damper (RK4 and the splitting where it applies) and a
spring–mass damper, each tree in fresh processes, alternated, medians of the
repeats. With ``--other SRC`` (another tree's ``src``, e.g. the commit before a
change checked out with ``git worktree``) the two are printed side by side with
their ratio (> 1: this tree is faster).

Run from the repository root::

    .venv/bin/python bench/part_kinds.py [--repeat 5] [--other /path/src]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

from machine import describe

#: One process's measurements: its cases, timed after a warm-up call.
CHILD = r"""
import json, sys, time
import numpy as np
import tumble as tb

body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 1.5, 2.0]))
wheel = tb.Rotor([0, 0, 1], 0.1, speed=5.0, torque=0.01)
damper = tb.KaneDamper(0.05, 0.02)
spring = tb.SpringMassDamper(0.1, [0.3, 0, 0], [0, 1, 0], 5.0, 0.1)
cases = {
    "rotor, rk4": ([wheel], "rk4", True),
    "rotor, splitting": ([wheel], "splitting", True),
    "rotor + damper, rk4": ([wheel, damper], "rk4", True),
    "spring-mass damper, rk4": ([spring], "rk4", False),
}
out = {}
w0 = [0.1, 0.2, 1.0]
for name, (parts, method, batch) in cases.items():
    kw = dict(internal=parts, method=method)
    tb.simulate(body, w0, duration=0.1, dt=1e-3, **kw)
    start = time.perf_counter()
    tb.simulate(body, w0, duration=20.0, dt=1e-4, record_every=100, **kw)
    out[name + " (one body)"] = (time.perf_counter() - start) / 2e5 * 1e9
    if batch:
        inertia = np.tile(body.inertia, (2000, 1, 1))
        omega = np.tile(w0, (2000, 1))
        tb.simulate_batch(inertia, omega, duration=0.01, dt=1e-3, **kw)
        start = time.perf_counter()
        tb.simulate_batch(inertia, omega, duration=1.0, dt=1e-3, **kw)
        out[name + " (batch)"] = (time.perf_counter() - start) / 2e6 * 1e9
print(json.dumps(out))
"""


def measure(source: str | None, child: str = CHILD) -> dict[str, float]:
    """ns per step of each case of the program ``child``, in a fresh process on
    ``source`` (None: this tree)."""
    environment = dict(os.environ)
    if source:
        environment["PYTHONPATH"] = source
    done = subprocess.run(
        [sys.executable, "-c", child], env=environment, capture_output=True, text=True, check=True
    )
    return dict(json.loads(done.stdout.strip().splitlines()[-1]))


def main(child: str = CHILD, description: str = __doc__, unit: str = "ns per (body-)step") -> None:
    """Run ``child`` (a program printing its cases' times as JSON, in ``unit``) in this
    tree and in ``--other``, alternated, and print the medians side by side."""
    parser = argparse.ArgumentParser(description=description.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--other", help="Another tree's src folder, measured alongside.")
    args = parser.parse_args()
    print(describe({}))
    trees = {"this tree": None, **({"other": args.other} if args.other else {})}
    runs: dict[str, list[dict[str, float]]] = {tree: [] for tree in trees}
    for _ in range(args.repeat):
        for tree, source in trees.items():  # alternated: the host's phases hit both
            runs[tree].append(measure(source, child))
    cases = list(runs["this tree"][0])
    print(f"medians of {args.repeat}, {unit}")
    header = f"{'case':<38} {'this tree':>10}"
    if args.other:
        header += f" {'other':>10} {'other/this':>11}"
    print(header)
    for case in cases:
        mine = statistics.median(run[case] for run in runs["this tree"])
        line = f"{case:<38} {mine:10.1f}"
        if args.other:
            theirs = statistics.median(run[case] for run in runs["other"])
            line += f" {theirs:10.1f} {theirs / mine:11.2f}"
        print(line, flush=True)


if __name__ == "__main__":
    main()
