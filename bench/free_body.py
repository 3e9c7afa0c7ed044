"""Benchmark: a tumbling free body, tumble against scipy, side by side in one run.

The case: I = (1, 2, 3) kg·m², ω₀ = (0.01, 2, 0.01) rad/s, over T = 1000 s
(about 60 periods, two intermediate-axis flips each). For each integrator:
the error of ω at T against a reference, the relative drift of the energy and
of |L|, the wall time (median of repeats), and tumble's speed ratio against each
scipy peer that reaches equal or worse accuracy.

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

import numpy as np
from scipy.integrate import solve_ivp

import tumble as tb

MOMENTS = np.array([1.0, 2.0, 3.0])
OMEGA0 = np.array([0.01, 2.0, 0.01])


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


def timed(call: Callable[[], np.ndarray], repeat: int) -> tuple[float, np.ndarray]:
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = call()
        times.append(time.perf_counter() - start)
    assert result is not None
    return statistics.median(times), result


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
    print(f"free body I = {MOMENTS.tolist()}, ω0 = {OMEGA0.tolist()}, T = {duration:g} s")
    print(
        f"reference: tumble exact; |ω_exact − ω_RK4(dt 2e-5)| = "
        f"{np.linalg.norm(reference - fine.omega[-1]):.1e}, "
        f"|ω_exact − ω_DOP853(rtol 1e-13)| = {np.linalg.norm(reference - dop_ref.y[:, -1]):.1e}\n"
    )

    rows = []
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

    header = (
        f"{'integrator':28s} {'steps':>12s} {'time s':>9s} {'|Δω| at T':>10s} "
        f"{'energy':>9s} {'|L|':>9s}"
    )
    print(header)
    print("-" * len(header))
    for name, steps, seconds, error, de, dl in rows:
        print(f"{name:28s} {steps:>12s} {seconds:9.4f} {error:10.1e} {de:9.1e} {dl:9.1e}")
    print(
        "\nspeed-up of tumble at equal or better accuracy (peer time / fastest tumble run that is "
        "at least as accurate):"
    )
    ours = [r for r in rows if r[0].startswith("tumble")]
    for name, _, seconds, error, _, _ in rows:
        if name.startswith("tumble"):
            continue
        better = [r for r in ours if r[3] <= error]
        if better:
            best = min(better, key=lambda r: r[2])
            print(f"  vs {name:26s} {seconds / best[2]:7.1f}x  ({best[0]})")
        else:
            print(f"  vs {name:26s}  no tumble run here is as accurate")


if __name__ == "__main__":
    main()
