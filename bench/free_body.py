"""Benchmark: a tumbling free body, tumble against scipy and MuJoCo, side by side in one run.

The case: I = (1, 2, 3) kg·m², ω₀ = (0.01, 2, 0.01) rad/s, over T = 1000 s
(about 60 periods, two intermediate-axis flips each). For each integrator:
the error of ω at T against a reference, the relative drift of the energy and
of |L|, the wall time (median of repeats), and tumble's speed ratio against each
peer that reaches equal or worse accuracy.

Peers: scipy's DOP853 and RK45 on Euler's equations alone; MuJoCo (a free joint,
no gravity, no contacts; :mod:`peers`) with its RK4, Euler, implicit and
implicitfast integrators, which step ω and the attitude, at dt = 1e-3 s (and 1e-2 s
for RK4 and Euler). MuJoCo's energy and |L| are sampled every 0.1 s of simulated
time; a run that goes NaN (MuJoCo then resets it to t = 0) is reported as diverged.
tumble: exact and rk4, plus splitting, strang and adaptive where this version
of tumble has them (a method name it refuses is reported as not available).

Reference: tumble's exact solution (Jacobi elliptic functions); tumble RK4 at
dt = 2e-5 s and scipy DOP853 at rtol 1e-13 are printed beside it as cross-checks.

Run from the repository root::

    .venv/bin/python bench/free_body.py [--duration 1000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from typing import TypeVar

import numpy as np
from scipy.integrate import solve_ivp

import tumble as tb
from peers import environment, mujoco_free_body, mujoco_free_body_frame_check

Result = TypeVar("Result")

MOMENTS = np.array([1.0, 2.0, 3.0])
OMEGA0 = np.array([0.01, 2.0, 0.01])
MUJOCO_RUNS = (("RK4", 1e-3), ("RK4", 1e-2), ("Euler", 1e-3), ("Euler", 1e-2))
MUJOCO_RUNS += (("implicit", 1e-3), ("implicitfast", 1e-3))
MUJOCO_SAMPLE = 0.1  # s of simulated time between MuJoCo's samples of E and |L|


def euler_rhs(_t: float, w: np.ndarray) -> np.ndarray:
    """Euler's equations only (the peers get the easier problem: no attitude)."""
    i1, i2, i3 = MOMENTS
    return np.array(
        [
            (i2 - i3) / i1 * w[1] * w[2],
            (i3 - i1) / i2 * w[2] * w[0],
            (i1 - i2) / i3 * w[0] * w[1],
        ]
    )


def invariants(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    energy = 0.5 * np.sum(MOMENTS * w**2, axis=-1)
    momentum = np.linalg.norm(MOMENTS * w, axis=-1)
    return energy, momentum


def timed(call: Callable[[], Result], repeat: int) -> tuple[float, Result]:
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = call()
        times.append(time.perf_counter() - start)
    assert result is not None
    return statistics.median(times), result


def tumble_refuses(call: Callable[[], object]) -> str | None:
    """tumble's message when it refuses a method (or its keywords), else None."""
    try:
        call()
    except tb.InputError as error:
        return str(error)
    except TypeError as error:  # e.g. no `rtol` keyword in this version
        return str(error)
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--duration", type=float, default=1000.0)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag(MOMENTS))
    duration = args.duration

    tb.simulate(body, OMEGA0, duration=0.01, dt=1e-3, method="rk4")  # compile the kernels
    tb.simulate(body, OMEGA0, duration=0.01, dt=1e-3, method="exact")
    reference = tb.simulate(body, OMEGA0, duration=duration, dt=duration, method="exact").omega[-1]
    fine = tb.simulate(body, OMEGA0, duration=duration, dt=2e-5, method="rk4", record_every=10**9)
    dop_ref = solve_ivp(euler_rhs, (0, duration), OMEGA0, method="DOP853", rtol=1e-13, atol=1e-15)
    print(environment())
    print(f"free body I = {MOMENTS.tolist()}, ω0 = {OMEGA0.tolist()}, T = {duration:g} s")
    print(
        f"reference: tumble exact; |ω_exact − ω_RK4(dt 2e-5)| = "
        f"{np.linalg.norm(reference - fine.omega[-1]):.1e}, "
        f"|ω_exact − ω_DOP853(rtol 1e-13)| = {np.linalg.norm(reference - dop_ref.y[:, -1]):.1e}"
    )
    as_body, as_world = mujoco_free_body_frame_check(MOMENTS, OMEGA0)
    print(
        "MuJoCo free joint, body turned, RK4 10 s: space-frame L changes by "
        f"{as_body:.1e} (relative) reading qvel[3:6] as body-frame ω, by {as_world:.1e} "
        "reading it as world-frame ω\n"
    )

    rows = []
    notes: list[str] = []
    energy0, momentum0 = invariants(OMEGA0)

    def add(
        name: str, seconds: float, trajectory_w: np.ndarray, final: np.ndarray, steps: str
    ) -> None:
        energy, momentum = invariants(trajectory_w)
        rows.append(
            (
                name,
                steps,
                seconds,
                float(np.linalg.norm(final - reference)),
                float(np.max(np.abs(energy - energy0)) / energy0),
                float(np.max(np.abs(momentum - momentum0)) / momentum0),
            )
        )

    for samples in (1, 1000):
        seconds, run = timed(
            lambda n=samples: (
                tb.simulate(body, OMEGA0, duration=duration, dt=duration / n, method="exact").omega
            ),
            args.repeat,
        )
        add(f"tumble exact, {samples} samples", seconds, run, run[-1], "none")
    for dt in (1e-2, 3e-3, 1e-3):
        seconds, run = timed(
            lambda dt=dt: (
                tb.simulate(
                    body, OMEGA0, duration=duration, dt=dt, method="rk4", record_every=100
                ).omega
            ),
            args.repeat,
        )
        add(f"tumble rk4 dt={dt:g}", seconds, run, run[-1], f"{duration / dt:.0e} steps")
    for method in ("splitting", "strang"):
        why = tumble_refuses(
            lambda m=method: tb.simulate(body, OMEGA0, duration=0.01, dt=1e-3, method=m)
        )
        if why is not None:
            notes.append(f"tumble {method}: not available ({why})")
            continue
        for dt in (1e-2, 3e-3, 1e-3):
            seconds, run = timed(
                lambda dt=dt, m=method: (
                    tb.simulate(
                        body, OMEGA0, duration=duration, dt=dt, method=m, record_every=100
                    ).omega
                ),
                args.repeat,
            )
            add(f"tumble {method} dt={dt:g}", seconds, run, run[-1], f"{duration / dt:.0e} steps")
    # adaptive: dt is passed as the sampling interval of the output (1000 samples)
    why = tumble_refuses(
        lambda: tb.simulate(
            body, OMEGA0, duration=0.01, dt=1e-3, method="adaptive", rtol=1e-8, atol=1e-11
        )
    )
    if why is not None:
        notes.append(f"tumble adaptive: not available ({why})")
    else:
        for rtol in (1e-8, 1e-10, 1e-12):
            seconds, run = timed(
                lambda r=rtol: (
                    tb.simulate(
                        body,
                        OMEGA0,
                        duration=duration,
                        dt=duration / 1000,
                        method="adaptive",
                        rtol=r,
                        atol=r * 1e-3,
                    ).omega
                ),
                args.repeat,
            )
            add(f"tumble adaptive rtol={rtol:g}", seconds, run, run[-1], "adaptive")
    for rtol in (1e-6, 1e-8, 1e-10):
        for method in ("DOP853", "RK45"):
            seconds, sol = timed(
                lambda m=method, r=rtol: (
                    solve_ivp(euler_rhs, (0, duration), OMEGA0, method=m, rtol=r, atol=r * 1e-3).y
                ),
                args.repeat,
            )
            add(
                f"scipy {method} rtol={rtol:g}", seconds, sol.T, sol[:, -1], f"{sol.shape[1]} steps"
            )

    for integrator, dt in MUJOCO_RUNS:
        sample = max(1, round(MUJOCO_SAMPLE / dt))
        seconds, mj = timed(
            lambda i=integrator, dt=dt, n=sample: mujoco_free_body(
                MOMENTS, OMEGA0, duration, dt, i, sample_every=n
            ),
            args.repeat,
        )
        name = f"mujoco {integrator} dt={dt:g}"
        if mj.diverged_at is not None:
            notes.append(
                f"{name}: NaN/huge acceleration at t ≈ {mj.diverged_at:.1f} s (MuJoCo reset the "
                "state to t = 0 and went on); drifts measured on the samples before"
            )
        rows.append(
            (
                name,
                f"{mj.steps:.0e} steps",
                seconds,
                float(np.linalg.norm(mj.omega - reference)),
                float(np.max(np.abs(mj.energy - energy0)) / energy0),
                float(np.max(np.abs(mj.momentum - momentum0)) / momentum0),
            )
        )

    header = (
        f"{'integrator':28s} {'steps':>12s} {'time s':>9s} {'|Δω| at T':>10s} "
        f"{'energy':>9s} {'|L|':>9s}"
    )
    print(header)
    print("-" * len(header))
    for name, steps, seconds, error, de, dl in rows:
        print(f"{name:28s} {steps:>12s} {seconds:9.4f} {error:10.1e} {de:9.1e} {dl:9.1e}")
    for line in notes:
        print("  " + line)
    print(
        "\nspeed-up of tumble at equal or better accuracy (peer time / fastest tumble run that is "
        "at least as accurate):"
    )
    ours = [r for r in rows if r[0].startswith("tumble")]
    for name, _, seconds, error, _, _ in rows:
        if name.startswith("tumble"):
            continue
        if not np.isfinite(error):
            print(f"  vs {name:26s}  diverged")
            continue
        better = [r for r in ours if r[3] <= error]
        if better:
            best = min(better, key=lambda r: r[2])
            print(f"  vs {name:26s} {seconds / best[2]:7.1f}x  ({best[0]})")
        else:
            print(f"  vs {name:26s}  no tumble run here is as accurate")
    print("time ratio at the same step (MuJoCo time / tumble rk4 time):")
    for name, _, seconds, _, _, _ in rows:
        if name.startswith("mujoco"):
            dt_text = name.rsplit("dt=", 1)[1]
            same = [r for r in ours if r[0] == f"tumble rk4 dt={dt_text}"]
            if same:
                print(f"  {name:28s} {seconds / same[0][2]:7.1f}x  ({same[0][0]})")


if __name__ == "__main__":
    main()
