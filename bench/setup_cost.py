"""Benchmark: the fixed cost of a :func:`tumble.simulate` call, stage by stage.

A short simulation costs little integration and much set-up: validating and
converting the arguments, the body model and its principal axes, binding the
torque, choosing the integrator and planning the steps (with the memory check),
finding the compiled kernel, the kernel call itself, turning states into and
out of the kernels' principal frame, and building the Trajectory. This script
times, for tiny runs,

* a free body, 10 RK4 steps (the target: at most ``TARGET_US`` µs a call);
* the same body by the closed form (``method="exact"``), 11 samples;
* the body carrying one rotor, 10 RK4 steps;
* the body under a torque (gravity gradient), 10 RK4 steps;
* a body whose axes are not principal (products of inertia), 10 RK4 steps;

each a median over ``--repeat`` calls after a warm-up, and each stage the same
way, by calling the functions ``simulate`` calls with the same arguments; what
no stage covers is the rest of ``simulate`` (its own lines and the calls
between). With ``--other SRC`` (a tree, or its ``src`` folder) the same runs
for another tree of tumble, in turns with this one (``--rounds`` each, the
median of the rounds' medians), side by side with the ratio other / this.
Each tree runs in its own process.

Run from the repository root::

    .venv/bin/python bench/setup_cost.py [--repeat 3000] [--rounds 3] [--other /tmp/before]
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import statistics
import subprocess
import sys
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

#: The target for the free body's 10 RK4 steps, µs a call.
TARGET_US = 50.0

#: The cases: simulate's keywords besides the body and ω0.
CASES = ("free body, rk4, 10 steps", "free body, exact, 11 samples",
         "one rotor, rk4, 10 steps", "gravity gradient, rk4, 10 steps",
         "axes not principal, rk4, 10 steps")  # fmt: skip

STAGES = (
    "validation and units",
    "body model and principal axes",
    "torque binding",
    "integrator, steps, memory check",
    "kernel lookup",
    "kernel call",
    "states to and from the kernels",
    "Trajectory and recording",
    "rest of simulate",
)

Timer = Callable[[], object]


def median_us(run: Timer, repeat: int) -> float:
    """The median time of ``run()``, µs, over ``repeat`` calls after ``repeat // 10`` more."""
    for _ in range(max(repeat // 10, 20)):
        run()
    times = []
    clock = time.perf_counter_ns
    for _ in range(repeat):
        start = clock()
        run()
        times.append(clock() - start)
    return statistics.median(times) / 1e3


def first(*paths: str) -> Any:
    """The first of ``module:name`` paths that this tree defines (trees differ in
    where some internal names live)."""
    for path in paths:
        module, _, name = path.partition(":")
        try:
            return getattr(importlib.import_module(module), name)
        except (ImportError, AttributeError):
            continue
    raise ImportError(f"none of {paths}")


def case_stages(case: str) -> tuple[Timer, dict[str, Timer]]:
    """The whole call and its stages (all but the rest of simulate) for one case."""
    import numpy as np

    import tumble as tb
    from tumble import body as body_module
    from tumble.integrators import auto_choice, get_integrator
    from tumble.integrators.limits import check_internal_stability, check_record_every
    from tumble.kinematics import as_attitude
    from tumble.massprops import as_mass_properties
    from tumble.parts import check_parts, value_columns
    from tumble.simulation import prepare
    from tumble.torques import bind
    from tumble.trajectory import Trajectory
    from tumble.units import to_si, vector_to_si

    problem_class = first(
        "tumble.integrators.problem:Problem", "tumble.integrators.drivers:Problem"
    )
    schedule_class = first(
        "tumble.integrators.problem:Schedule", "tumble.integrators.drivers:Schedule"
    )
    time_step = first("tumble.integrators.steps:time_step", "tumble.integrators.drivers:time_step")
    warn_if_coarse = first(
        "tumble.integrators.steps:warn_if_coarse", "tumble.integrators.drivers:warn_if_coarse"
    )
    check_recording = first(
        "tumble.integrators.limits:check_recording", "tumble.simulation:check_recording"
    )
    # The body model as simulate builds it: shared between calls where the tree
    # has the cache, built each call where it has not.
    model = getattr(body_module, "body_model", None) or body_module.RigidBody

    inertia = (
        [[1.5, -0.5, 0.0], [-0.5, 1.5, 0.0], [0.0, 0.0, 3.0]]
        if "axes" in case
        else np.diag([1.0, 2.0, 3.0])
    )
    mp = tb.MassProperties(1.0, [0, 0, 0], inertia)
    omega0 = [0.1, 1.0, 0.1]
    method, parts, torque = "rk4", [], None
    if "exact" in case:
        method = "exact"
    if "rotor" in case:
        parts = [tb.Rotor([0, 0, 1], 0.1, speed=10.0)]
    if "gravity" in case:
        torque = tb.torques.GravityGradient(0.001)
    duration, dt = 0.1, 0.01
    keywords: dict[str, Any] = {"duration": duration, "dt": dt, "method": method}
    if parts:
        keywords["internal"] = parts
    if torque is not None:
        keywords["torque"] = torque

    def whole() -> object:
        return tb.simulate(mp, omega0, **keywords)

    setup = prepare(mp, omega0, method=method, internal=parts or None, torque=torque)
    body, bound, integrator = setup.body, setup.torque, setup.integrator
    omega = setup.omega0
    most = 5e7

    def validation() -> None:
        check_record_every(1)
        as_mass_properties(mp)
        get_integrator(method)
        vector_to_si(omega0, "angular_velocity", "omega0")
        as_attitude(None)
        check_parts(parts or None)
        to_si(duration, "time", "duration")
        time_step(dt, 1.0, duration)

    def body_stage() -> None:
        # The model and the derived values a run reads: built once per body where
        # the tree shares the model between calls, at each call where it does not.
        built = model(mp, None, tuple(parts))
        built.check_simulable()
        built.attitude_to_principal(setup.attitude0)
        built.internal_rate()
        if parts:
            built.layout, built.packed_parts  # noqa: B018 (computed on first use)

    def binding() -> None:
        bind(torque, body, omega)

    def planning() -> None:
        integrator.refuses(body, bound)
        if method == "auto":
            auto_choice(bound, body)
        fastest = setup.fastest_rate()
        step = time_step(dt, fastest, duration)
        rate, names = body.internal_rate()
        check_recording(duration, step, 1, len(value_columns(body.parts)))
        schedule = schedule_class.build(duration, step, 1, rtol=1e-10, atol=1e-12, most_steps=most)
        check_internal_stability(rate, names, integrator.kind, schedule.step, duration, most)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            warn_if_coarse(schedule.step, fastest, "the fastest rotation")

    schedule = schedule_class.build(duration, dt, 1, rtol=1e-10, atol=1e-12, most_steps=most)
    problem = problem_class(body, bound, omega, setup.attitude0)
    role = "parts_single" if parts else "single"

    def lookup() -> None:
        if method != "exact":
            integrator.kernel(role, bound, *([body.layout] if parts else []))

    kernel_call = _kernel_call(method, parts, body, bound, integrator, omega, setup, schedule)

    def driver() -> None:
        integrator.run(integrator, problem, schedule, None)

    samples = integrator.run(integrator, problem, schedule, None)

    def trajectory() -> None:
        Trajectory(
            t=schedule.times, omega=samples.omega, quaternion=samples.quaternion,
            mass_properties=mp, pivot=None, method=integrator.name, reason=setup.reason,
            dt=schedule.step, steps=samples.steps, conserved=body.conserved(bound.terms),
            torque=setup.model, internal=body.parts, internal_values=samples.values,
        )  # fmt: skip

    stages = {
        "validation and units": validation,
        "body model and principal axes": body_stage,
        "torque binding": binding,
        "integrator, steps, memory check": planning,
        "kernel lookup": lookup,
        "kernel call": kernel_call,
        "driver": driver,
        "Trajectory and recording": trajectory,
    }
    return whole, stages


def _kernel_call(
    method: str, parts: list[Any], body: Any, bound: Any, integrator: Any, omega: Any,
    setup: Any, schedule: Any,
) -> Timer:  # fmt: skip
    """The compiled call alone, on arrays prepared as the driver prepares them (the
    closed form: its evaluation in the principal frame)."""
    import numpy as np

    from tumble.theory.motions import exact_principal

    rows = len(schedule.times)
    moments = np.ascontiguousarray(body.moments)
    if method == "exact":
        w0 = body.to_principal(omega)
        q0 = body.attitude_to_principal(setup.attitude0)
        return lambda: exact_principal(moments, w0, q0, schedule.times)
    if parts:
        kernel = integrator.kernel("parts_single", bound, body.layout)
        y = body.kernel_state(omega, setup.attitude0)
        out = np.empty((rows, y.size))
        packed = np.array(body.packed_parts)
        return lambda: kernel(
            y, moments, packed, bound.params, bound.context, schedule.step, 10, 0, 1, out
        )
    kernel = integrator.kernel("single", bound)
    w = np.array(body.to_principal(omega))
    q = np.array(body.attitude_to_principal(setup.attitude0))
    out_w, out_q = np.empty((rows, 3)), np.empty((rows, 4))
    return lambda: kernel(
        w, q, moments, bound.params, bound.context, schedule.step, 10, 0, 1, out_w, out_q
    )


def worker(repeat: int) -> None:
    """Time every case in this process's tree; print JSON (case → stage → µs)."""
    import tumble

    results: dict[str, Any] = {"load": os.getloadavg()[0], "version": tumble.__version__}
    for case in CASES:
        whole, stages = case_stages(case)
        measured = {name: median_us(run, repeat) for name, run in stages.items()}
        total = median_us(whole, repeat)
        driver = measured.pop("driver")
        measured["states to and from the kernels"] = max(
            driver - measured["kernel lookup"] - measured["kernel call"], 0.0
        )
        measured["rest of simulate"] = total - sum(measured.values())
        measured["total"] = total
        results[case] = measured
    results["load_after"] = os.getloadavg()[0]
    print(json.dumps(results))


def run_tree(source: Path, repeat: int) -> dict[str, Any]:
    """:func:`worker` in a fresh process with ``source`` (a ``src`` folder) first on the path."""
    env = dict(os.environ, PYTHONPATH=str(source))
    done = subprocess.run(
        [sys.executable, __file__, "--worker", "--repeat", str(repeat)],
        env=env, check=True, capture_output=True, text=True,
    )  # fmt: skip
    return json.loads(done.stdout.strip().splitlines()[-1])


def source_folder(tree: str) -> Path:
    """A tree's ``src`` folder (the tree itself when it holds ``tumble``)."""
    path = Path(tree).resolve()
    return path if (path / "tumble").is_dir() else path / "src"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=3000, help="calls per median")
    parser.add_argument("--rounds", type=int, default=3, help="runs of each tree, in turns")
    parser.add_argument("--other", help="another tree of tumble (or its src) to compare")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    options = parser.parse_args()
    if options.worker:
        worker(options.repeat)
        return

    from machine import describe

    here = Path(__file__).resolve().parent.parent / "src"
    trees = {"this": here}
    if options.other:
        trees["other"] = source_folder(options.other)
    print(describe({}))
    for label, path in trees.items():
        print(f"{label}: {path}")
    runs: dict[str, list[dict[str, Any]]] = {label: [] for label in trees}
    for _ in range(options.rounds):
        for label, path in reversed(trees.items()):  # the other tree first in each round
            runs[label].append(run_tree(path, options.repeat))
    loads = [run["load"] for rounds in runs.values() for run in rounds]
    loads += [run["load_after"] for rounds in runs.values() for run in rounds]
    print(
        f"load average (1 min) during the runs: {min(loads):.2f}–{max(loads):.2f}; "
        f"{options.rounds} rounds, medians of {options.repeat} calls, µs per call"
    )
    for case in CASES:
        print(f"\n{case}")
        header = f"  {'stage':34s}" + "".join(f"{label:>10s}" for label in trees)
        print(header + ("   other/this" if "other" in trees else ""))
        for stage in (*STAGES, "total"):
            values = {
                label: statistics.median(run[case][stage] for run in rounds)
                for label, rounds in runs.items()
            }
            line = f"  {stage:34s}" + "".join(f"{values[label]:10.1f}" for label in trees)
            if "other" in trees and values["this"] > 0.05:
                line += f"   {values['other'] / values['this']:8.1f}×"
            print(line)
    free = statistics.median(run[CASES[0]]["total"] for run in runs["this"])
    verdict = "met" if free <= TARGET_US else "not met"
    print(f"\ntarget: {CASES[0]} <= {TARGET_US:g} µs a call: {free:.1f} µs, {verdict}")


if __name__ == "__main__":
    main()
