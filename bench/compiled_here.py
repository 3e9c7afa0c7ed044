"""Benchmark: a batch kernel compiled in the process that runs it, against the same
kernel loaded from numba's cache.

A batch of bodies under a torque (``ConstantBodyTorque``, ``RotorMomentum`` with a
momentum per body) steps through a kernel specialised for that torque
(``tumble.core._jit.specialise``), compiled on first use and cached on disk; so do a
batch of bodies carrying a rotor (RK4's blocks of ``tumble.core.part_blocks``; and
the splitting's, under ``ConstantBodyTorque``) and a sweep chunk of bodies carrying
a rotor and a Kane damper (its measuring kernel; ``--steps`` of 2 ms, its bodies
``bench/sweep_parts.py``'s). Each case runs in two fresh processes that share an
empty cache folder (``NUMBA_CACHE_DIR``): the first compiles the kernel, the second
loads it. Each process times ``--repeat`` calls after its first (which compiles or
loads), and the medians are compared; then a process with the cache off
(``TUMBLE_NUMBA_CACHE=0``), as on a read-only install, which compiles every time;
then one that compiles into another empty cache folder at numba's own default
optimisation level (``NUMBA_OPT=3``; tumble sets ``max`` when the environment does
not say, :mod:`tumble.core`); then one that compiles into a third after declaring a
numba function of its own (numba's code generator is made then).

Run from the repository root::

    .venv/bin/python bench/compiled_here.py [--bodies 20000] [--steps 500] [--repeat 5]
        [--cases ConstantBodyTorque RotorMomentum Rotor "Rotor splitting" "Rotor sweep"]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

from machine import describe

#: One process: the case's batch timed ``repeat`` times after a first call; prints
#: the median and the first call's time, s, as JSON.
CHILD = """
import json, statistics, sys, time
import numpy as np
import tumble as tb
case, n, steps, repeat = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
if sys.argv[5:] == ["own"]:  # the program declares a numba function of its own first
    import numba

    @numba.njit
    def own(x):
        return x
rng = np.random.default_rng(1)
platform = np.tile([4.0, 5.5, 8.0], (n, 1))
omega = rng.normal(size=(n, 3))
options = {}
if case == "RotorMomentum":
    momentum = np.zeros((n, 3))
    momentum[:, 1] = rng.uniform(0.0, 1.5, n)
    options["torque"] = tb.torques.RotorMomentum(momentum)
elif case.startswith("Rotor"):
    options["internal"] = [tb.Rotor([0, 1, 0], 0.5)]
    options["rotor_speed"] = np.linspace(-10.0, 10.0, n)[:, None]
    if case == "Rotor splitting":
        options["method"] = "splitting"
        options["torque"] = tb.torques.ConstantBodyTorque([0.01, 0.0, 0.0])
else:
    options["torque"] = tb.torques.ConstantBodyTorque([0.01, 0.0, 0.0])
def run():
    tb.simulate_batch(platform, omega, duration=steps * 1e-2, dt=1e-2, **options)
if case == "Rotor sweep":
    sys.path.insert(0, "bench")
    from sweep_parts import DAMPER, ROTOR, sweep
    from tumble.sweep.build import parse_sweep
    from tumble.sweep.metrics import compute_chunk
    text = sweep(n, "rk4", ROTOR + DAMPER)
    plan = parse_sweep(text.replace("duration = 0.4", f"duration = {steps * 2e-3}"))
    def run():
        compute_chunk(plan, 0)
start = time.perf_counter()
run()
first = time.perf_counter() - start
times = []
for _ in range(repeat):
    start = time.perf_counter()
    run()
    times.append(time.perf_counter() - start)
print(json.dumps({"first": first, "median": statistics.median(times)}))
"""


CASES = ["ConstantBodyTorque", "RotorMomentum", "Rotor", "Rotor splitting", "Rotor sweep"]


def timed(
    case: str, args: argparse.Namespace, environment: dict[str, str], own: bool = False
) -> dict[str, float]:
    """The case's times in a fresh process with ``environment`` added (``own``: the
    process declares a numba function of its own before tumble compiles)."""
    command = [sys.executable, "-c", CHILD, case, str(args.bodies), str(args.steps)]
    finished = subprocess.run(
        [*command, str(args.repeat), *(["own"] if own else [])],
        env={**os.environ, **environment},
        capture_output=True,
        text=True,
        check=True,
    )
    return dict(json.loads(finished.stdout.strip().splitlines()[-1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", type=int, default=20_000)
    parser.add_argument("--steps", type=int, default=500)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--cases", nargs="+", choices=CASES, default=CASES)
    args = parser.parse_args()
    print(describe({}))
    print(f"{args.bodies} bodies × {args.steps} steps, medians of {args.repeat} calls a process")
    print(f"{'case':18s} {'process':26s} {'first call s':>13s} {'a call ms':>10s} {'ratio':>6s}")
    for case in args.cases:
        with (
            tempfile.TemporaryDirectory() as folder,
            tempfile.TemporaryDirectory() as other,
            tempfile.TemporaryDirectory() as third,
        ):
            cache = {"NUMBA_CACHE_DIR": folder}
            rows = [
                ("compiles (empty cache)", timed(case, args, cache)),
                ("loads (the cache filled)", timed(case, args, cache)),
                ("cache off", timed(case, args, {"TUMBLE_NUMBA_CACHE": "0"})),
                ("compiles, NUMBA_OPT=3", timed(case, args, {"NUMBA_CACHE_DIR": other,
                                                            "NUMBA_OPT": "3"})),
                ("compiles, own numba first", timed(case, args, {"NUMBA_CACHE_DIR": third},
                                                    own=True)),
            ]  # fmt: skip
        loaded = rows[1][1]["median"]
        for what, row in rows:
            print(
                f"{case:18s} {what:26s} {row['first']:13.2f} {row['median'] * 1e3:10.1f} "
                f"{row['median'] / loaded:6.2f}"
            )


if __name__ == "__main__":
    main()
