"""Benchmark: the splitting around the exact free motion on a weakly perturbed body.

The case: an asymmetric satellite (principal moments 10, 40, 45 kg·m², body axes
not principal) tumbling at ~0.5 rad/s in a circular low orbit (n = 1.1e-3
rad/s), under the gravity-gradient torque 3 n² r × (I r), for one orbit
(≈ 5700 s, ~450 turns). The torque is ~1e-6 of what would change the rotation
in one turn: a weak perturbation of a fast rotation.

The truth is scipy's DOP853 at rtol 1e-13, atol 1e-15, in body axes with the
full inertia tensor and the attitude as a matrix (written here, sharing no code
with tumble), sampled every 100 s. The error of a run is the largest over the
samples of the attitude error (rad) and |Δω|/|ω0|.

Each method runs at steps from coarse to fine (each a divisor of 100 s). The
target: the splitting around the exact flow (``splitting-exact``) reaches a
given accuracy (1e-6 and 1e-9) with ≥ 10× fewer steps than RK4 and than the
rotation splitting (``splitting``). Times are medians of ``--repeat`` rounds.

Run from the repository root::

    .venv/bin/python bench/exact_splitting.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import itertools
import math
import statistics
import time
import warnings

import numpy as np
import scipy
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import tumble as tb
from machine import describe
from tumble.errors import CoarseStepWarning

AXES = Rotation.from_rotvec([0.3, -0.5, 0.8])
BODY = tb.MassProperties(
    500.0, [0.0, 0.0, 0.0], AXES.as_matrix() @ np.diag([10.0, 40.0, 45.0]) @ AXES.as_matrix().T
)
RATE = 1.1e-3  # rad/s, orbit rate
OMEGA0 = np.array([0.3, -0.35, 0.2])  # rad/s, body axes
Q0 = Rotation.from_rotvec([0.4, 0.2, -0.1]).as_quat(scalar_first=True)
SAMPLE = 100.0  # s
DURATION = SAMPLE * round(2 * math.pi / RATE / SAMPLE)  # one orbit, in whole samples
LEVELS = (1e-6, 1e-9)
TARGET = 10.0
STEPS = {
    "rk4": (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625),
    "splitting": (0.2, 0.1, 0.05, 0.025, 0.0125),
    "splitting-exact": (3.125, 1.5625, 0.78125, 0.390625, 0.1953125, 0.09765625),
    "strang-exact": (3.125, 1.5625, 0.78125, 0.390625, 0.1953125),
}


def truth(times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ω (n, 3) and attitude matrices (n, 3, 3) by DOP853: I ω̇ = τ − ω × I ω,
    τ = 3 n² r × (I r), r = Aᵀ (cos n t, sin n t, 0), Ȧ = A [ω]×."""
    inertia = BODY.inertia
    inverse = np.linalg.inv(inertia)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        w = y[:3]
        a = y[3:].reshape(3, 3)
        r = a.T @ np.array([math.cos(RATE * t), math.sin(RATE * t), 0.0])
        tau = 3 * RATE**2 * np.cross(r, inertia @ r)
        w_dot = inverse @ (tau - np.cross(w, inertia @ w))
        skew = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        return np.concatenate([w_dot, (a @ skew).ravel()])

    a0 = Rotation.from_quat(Q0, scalar_first=True).as_matrix()
    sol = solve_ivp(
        rhs, (0.0, times[-1]), np.concatenate([OMEGA0, a0.ravel()]), method="DOP853",
        rtol=1e-13, atol=1e-15, t_eval=times,
    )  # fmt: skip
    return sol.y[:3].T, sol.y[3:].T.reshape(-1, 3, 3)


def run(method: str, dt: float) -> tb.Trajectory:
    return tb.simulate(
        BODY, OMEGA0, attitude0=Q0, duration=DURATION, dt=dt, record_every=round(SAMPLE / dt),
        torque=tb.torques.GravityGradient(RATE), method=method,
    )  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    warnings.simplefilter("ignore", CoarseStepWarning)
    print("Weakly perturbed tumbling: the splitting around the exact free motion")
    print(describe({"scipy": scipy.__version__}))
    turns = np.linalg.norm(OMEGA0) * DURATION / (2 * math.pi)
    print(
        f"moments 10, 40, 45 kg·m²; |ω0| = {np.linalg.norm(OMEGA0):.3f} rad/s; orbit rate "
        f"{RATE} rad/s; about one orbit, {DURATION:.0f} s ≈ {turns:.0f} turns; samples "
        f"every {SAMPLE:.0f} s"
    )
    start = time.perf_counter()
    first = run("rk4", STEPS["rk4"][-1])
    w_true, a_true = truth(first.t)
    print(f"truth: DOP853 rtol 1e-13 ({time.perf_counter() - start:.1f} s)\n")

    rows = []
    for method, steps in STEPS.items():
        for dt in steps:
            result = run(method, dt)
            assert np.array_equal(result.t, first.t), (method, dt)
            turn = Rotation.from_quat(result.quaternion, scalar_first=True)
            attitude = np.max((turn * Rotation.from_matrix(a_true).inv()).magnitude())
            omega = np.max(np.linalg.norm(result.omega - w_true, axis=1)) / np.linalg.norm(OMEGA0)
            times = []
            for _ in range(args.repeat):
                begin = time.perf_counter()
                run(method, dt)
                times.append(time.perf_counter() - begin)
            rows.append((method, dt, result.steps, max(attitude, omega), statistics.median(times)))

    print(f"{'method':<16} {'dt s':>8} {'steps':>9} {'error':>9} {'time ms':>9}")
    for method, dt, steps, err, cost in rows:
        print(f"{method:<16} {dt:>8.4g} {steps:>9} {err:>9.2e} {cost * 1e3:>9.2f}")

    print(
        "\nsteps and time to reach an error, interpolated log-log between the two runs around it:"
    )
    for level in LEVELS:
        needed = {method: interpolated(rows, method, level) for method in STEPS}
        exact = needed["splitting-exact"]
        if exact is None:
            print(f"  error {level:.0e}: splitting-exact does not reach it in this scan")
            continue
        print(
            f"  error {level:.0e}: splitting-exact {exact[0]:,.0f} steps, {exact[1] * 1e3:.1f} ms"
        )
        for method in ("rk4", "splitting", "strang-exact"):
            other = needed[method]
            if other is None:
                print(f"    {method:<14} does not reach it in this scan")
                continue
            verdict = ""
            if method == "rk4":
                verdict = f" (target ≥ {TARGET:.0f}× fewer steps: " + (
                    "met)" if other[0] / exact[0] >= TARGET else "not met)"
                )
            print(
                f"    {method:<14} {other[0]:>11,.0f} steps, {other[1] * 1e3:7.1f} ms: "
                f"{other[0] / exact[0]:5.1f}× the steps, {other[1] / exact[1]:5.2f}× the time"
                f"{verdict}"
            )


def interpolated(rows: list, method: str, level: float) -> tuple[float, float] | None:
    """(steps, seconds) at which ``method`` reaches error ``level``: log-log
    interpolation between its last run above and its first run at or below it."""
    mine = [row for row in rows if row[0] == method]
    for before, after in itertools.pairwise(mine):
        if before[3] > level >= after[3]:
            x = math.log(level / before[3]) / math.log(after[3] / before[3])
            steps = before[2] * (after[2] / before[2]) ** x
            seconds = before[4] * (after[4] / before[4]) ** x
            return steps, seconds
    return None


if __name__ == "__main__":
    main()
