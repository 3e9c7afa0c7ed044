"""Benchmark: where a cold `tumble.simulate` call spends its time.

The call of ``bench/spacecraft.py``'s case c (a body and one wheel spun up, RK4,
100 steps, every state recorded) and of its case a (three wheels, the adaptive
method at rtol 1e-13), timed hot (at once after a call of its own) and cold (after
64 MB of other memory traffic, ``spacecraft.churn``), ``--repeat`` times each,
medians; then the same calls under cProfile, hot and cold, with the cumulative time
of the call's phases (:data:`PHASES`): the run's key and its look-up among the runs
kept (``tumble.simulation.prepare``'s and ``simulate``'s), the setup and the plan of
a run not kept (the body, its parts and the method checked and built; the steps and
samples checked), the driver's run (its compiled kernel and the read-back) and the
trajectory made from the samples; the rest is ``simulate``'s own work (the
arguments, the memory budget's variable, the warnings). Calls that repeat a run
find it kept; case c is also timed for a motion new at each call
(:func:`spin_up_new`), which is set up anew. And the floor of such a call, case c's
compiled steps alone (:func:`bare_steps`), hot and cold. cProfile adds its own cost
to every Python call: its times are larger than the plain ones, and their shares,
hot against cold, are what it shows.

Run from the repository root::

    .venv/bin/python bench/cold_call.py [--repeat 200]
"""

from __future__ import annotations

import argparse
import cProfile
import itertools
import pstats
import statistics
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import tumble as tb
from machine import describe
from spacecraft import ROTORS, SPINNER, SPUN, WHEEL_BODY, WHEELS_OMEGA0, churn

#: The phases of a call: their names, and the (file, function) cProfile names them
#: by, counted where ``simulate`` calls them; the rest of the call is simulate's own
#: work.
PHASES = {
    "key": ("simulation.py", "_motion_key"),
    "look-up": ("recent.py", "get"),
    "setup (new)": ("simulation.py", "prepare"),
    "plan (new)": ("simulation.py", "plan"),
    "driver's run": ("stepping.py", "run"),
    "driver's run (adaptive)": ("adaptive.py", "run_adaptive"),
    "trajectory": ("simulation.py", "_trajectory"),
}


def spin_up() -> Any:
    return tb.simulate(SPUN, [0, 0, 0], duration=10.0, internal=SPINNER, method="rk4", dt=0.1)


_starts = itertools.count(1)


def spin_up_new() -> Any:
    """Case c's call for a motion not set up before: ω0 new at each call (a turn
    rate of k·1e-15 rad/s about x, the k-th call), so that nothing is kept."""
    omega0 = [next(_starts) * 1e-15, 0.0, 0.0]
    return tb.simulate(SPUN, omega0, duration=10.0, internal=SPINNER, method="rk4", dt=0.1)


def wheels() -> Any:
    return tb.simulate(
        WHEEL_BODY, WHEELS_OMEGA0, duration=20.0, internal=ROTORS, method="adaptive",
        dt=0.1, rtol=1e-13, atol=1e-16,
    )  # fmt: skip


def bare_steps() -> Callable[[], Any]:
    """Case c's compiled steps alone, as a call from Python at its leanest: the
    initial state copied, the samples allocated, one call of the kernel's machine
    code (without numba's dispatch; what ``tumble.simulate`` adds around them is
    the rest of its time)."""
    from tumble.integrators.problem import parts_start
    from tumble.integrators.steps import compiled_for
    from tumble.simulation import prepare

    setup = prepare(SPUN, [0, 0, 0], internal=SPINNER, method="rk4")
    schedule = setup.plan(10.0, 0.1, 1, rtol=1e-10, atol=1e-12, max_steps=None).schedule
    start, torque = parts_start(setup.integrator, setup.problem), setup.torque
    rows, step, n_steps = len(schedule.times), schedule.step, schedule.n_steps
    arguments = (start.state.copy(), start.moments, start.parts, torque.params, torque.context,
                 step, n_steps, 0, 1, np.empty((rows, start.state.size)))  # fmt: skip
    kernel = compiled_for(start.kernel, arguments)

    def call() -> Any:
        y = start.state.copy()
        out = np.empty((rows, y.size))
        out[0] = y
        kernel(y, start.moments, start.parts, torque.params, torque.context,
               step, n_steps, 0, 1, out)  # fmt: skip
        return out

    return call


def plain(call: Callable[[], Any], cold: bool, repeat: int) -> float:
    """The median time of ``repeat`` calls, each after :func:`churn` when ``cold``."""
    times = []
    for _ in range(repeat):
        if cold:
            churn()
        else:
            call()
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def profiled(call: Callable[[], Any], cold: bool, repeat: int) -> dict[str, float]:
    """The cumulative time a call (ms, cProfile's) spends in each phase of PHASES."""
    profile = cProfile.Profile()
    for _ in range(repeat):
        if cold:
            churn()
        else:
            call()
        profile.enable()
        call()
        profile.disable()
    stats = pstats.Stats(profile).stats  # type: ignore[attr-defined]
    found = {"whole": 0.0}
    for (path, _, name), (_, _, _, cumulative, callers) in stats.items():
        for phase, (where, function) in PHASES.items():
            if name == function and path.endswith(where):
                found[phase] = (
                    1e3
                    / repeat
                    * sum(
                        timing[3]
                        for (_, _, caller), timing in callers.items()
                        if caller == "simulate"
                    )
                )
        if name in ("spin_up", "spin_up_new", "wheels") and path.endswith("cold_call.py"):
            found["whole"] += cumulative / repeat * 1e3
    found["simulate's own"] = found["whole"] - sum(found.get(phase, 0.0) for phase in PHASES)
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=200)
    args = parser.parse_args()
    print(describe({}))
    steps = bare_steps()
    steps()
    hot, cold = plain(steps, False, args.repeat), plain(steps, True, args.repeat)
    print(
        f"\nc's compiled steps alone (a state copied, the samples allocated, one call of the "
        f"kernel's machine code): {1e3 * hot:.3f} ms hot, {1e3 * cold:.3f} ms cold "
        f"({cold / hot:.1f}×)"
    )
    for name, call in (
        ("c. one wheel, RK4 dt 0.1 s", spin_up),
        ("c., a motion new at each call (nothing kept)", spin_up_new),
        ("a. three wheels, adaptive", wheels),
    ):
        call()  # compile
        hot, cold = plain(call, False, args.repeat), plain(call, True, args.repeat)
        print(f"\n{name}: {1e3 * hot:.3f} ms hot, {1e3 * cold:.3f} ms cold ({cold / hot:.1f}×)")
        shares = {
            setting: profiled(call, setting == "cold", args.repeat) for setting in ("hot", "cold")
        }
        print(f"  {'phase (cProfile, ms a call)':30s} {'hot':>8s} {'cold':>8s} {'cold − hot':>10s}")
        for phase in ("whole", *PHASES, "simulate's own"):
            h, c = shares["hot"].get(phase, np.nan), shares["cold"].get(phase, np.nan)
            print(f"  {phase:30s} {h:8.3f} {c:8.3f} {c - h:10.3f}")


if __name__ == "__main__":
    main()
