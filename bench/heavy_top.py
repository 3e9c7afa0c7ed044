"""Benchmark: the heavy gyroscope, tumble against MuJoCo and scipy, side by side in one run.

The case (:class:`peers.Top`): a thin disk, m = 1 kg, r = 0.1 m (about its centre
I_s = m r²/2 about its axis, I_⊥ = m r²/4), on a fixed pivot on its symmetry axis
l = 0.1 m from its centre, gravity 9.81 m/s² down. At t = 0 the axis is horizontal,
the disk spins at 200 rad/s about it and is otherwise at rest (no precession). Over
5 s the axis precesses at about m g l/(I_s ω_s) = 0.98 rad/s and nutates at about
I_s ω_s/I₁ = 80 rad/s between θ₀ = 90° and θ₁ ≈ 91.40° (θ from the upward vertical).

Measured for each integrator:

* ``nutation``: the nutation half-amplitude (θ_max − θ_min)/2 over the whole run,
  degrees, and its error relative to the truth. The extremes of the sampled θ are
  refined by a parabola through the three samples around each one (at 1e-3 s
  spacing this is good to 4e-11 relative on the reference, checked);
* ``last``: the nutation half-amplitude over the last 0.5 s (about six nutation
  periods), from a least-squares fit of a quadratic trend plus a sinusoid (its
  frequency searched between 0.5 and 1.5 times I_s ω_s/I₁) to θ(t): it shows whether
  the nutation is damped or grows even when the axis drifts down meanwhile;
* ``θ(T)``: the polar angle of the axis at the end, degrees (between 90° and θ₁ when
  the top neither sinks nor rises);
* ``φ̇``: the mean precession rate (φ(T) − φ(0))/T, rad/s, φ the azimuth of the axis;
* ``energy``: the largest |E − E₀|/E₀ over the samples (E₀ = ½ I_s ω_s² = 100 J);
* ``time``: wall time of the run (median of ``--repeat`` rounds; in each round every
  configuration runs once, in turn, after one untimed warm-up run of each). MuJoCo's
  models are compiled beforehand; MuJoCo steps in C (``mujoco.rollout``) and keeps
  every step (1e-3 s); tumble and scipy keep a sample about every 1e-3 s too (tumble:
  every k-th step, k = round(1e-3 s / dt)).

The truth: scipy DOP853 at rtol 1e-13, atol 1e-15, its turning points (θ̇ = 0)
located on its dense output; its θ₁ is checked against the exact turning point,
the root of the cubic u̇² = f(u), u = cos θ (Goldstein §5.7). The reference peer
is DOP853 at rtol 1e-12, atol 1e-14, sampled every 1e-3 s.

tumble: every method it knows among rk4, splitting, strang (fixed step: ``dt``
scanned from coarse to fine until the nutation amplitude is right to 1e-6) and
adaptive (``rtol`` scanned, ``atol = rtol × 1e-3``, ``dt`` then the sampling
interval). A method name tumble refuses (InputError) is reported as not available.

Run from the repository root::

    .venv/bin/python bench/heavy_top.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import curve_fit

import tumble as tb
from peers import INTEGRATORS, Top, TopRun, environment, mujoco_top, scipy_top, top_model
from tumble.errors import CoarseStepWarning

TARGET = 1e-6  # relative error of the nutation amplitude tumble must reach
MUJOCO_DT = 1e-3
SAMPLE_DT = 1e-3  # sampling interval of tumble's and scipy's outputs, as MuJoCo's steps
LAST_WINDOW = 0.5  # s: "last" nutation amplitude over this final window
FIXED_STEP_DTS = (
    5e-3,
    2e-3,
    1.5e-3,
    1e-3,
    5e-4,
    3e-4,
    2.5e-4,
    2e-4,
    1.5e-4,
    1e-4,
    5e-5,
    2e-5,
    1e-5,
)
ADAPTIVE_RTOLS = (1e-6, 1e-8, 1e-9, 1e-10, 1e-12)

TOP = Top()
DISK = tb.shapes.thin_disk(TOP.mass, TOP.radius)  # centred, symmetry axis body z
PIVOT = [0.0, 0.0, -TOP.lever]  # so the centre is `lever` above the pivot along +z
GRAVITY = [0.0, 0.0, -TOP.gravity]


# ------------------------------------------------------------- measurements
def extremes(t: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Local extremes of sampled θ, each refined by a parabola through its three samples.

    Returns their times (of the middle sample) and refined values; the first and
    last samples are included as they are.
    """
    a, b, c = theta[:-2], theta[1:-1], theta[2:]
    curvature = a - 2 * b + c
    peak = ((b >= a) & (b >= c) & (curvature < 0)) | ((b <= a) & (b <= c) & (curvature > 0))
    index = np.flatnonzero(peak)
    value = b[index] - (c[index] - a[index]) ** 2 / (8 * curvature[index])
    times = np.concatenate([[t[0]], t[1:-1][index], [t[-1]]])
    values = np.concatenate([[theta[0]], value, [theta[-1]]])
    return times, values


def last_nutation(run: TopRun, nutation_rate: float) -> float:
    """Half-amplitude (rad) of the nutation over the last ``LAST_WINDOW`` s of the run.

    θ(t) ≈ c0 + c1 t + c2 t² + a cos ωt + b sin ωt, fitted by linear least squares on
    a grid of ω, the best ω refined by ``curve_fit``; returns √(a² + b²).
    """
    keep = run.t >= run.t[-1] - LAST_WINDOW
    t = run.t[keep] - run.t[-1]
    theta = run.theta[keep]

    def basis(w: float) -> np.ndarray:
        return np.column_stack([np.ones_like(t), t, t * t, np.cos(w * t), np.sin(w * t)])

    def model(t_: np.ndarray, *p: float) -> np.ndarray:
        c0, c1, c2, a, b, w = p
        return c0 + c1 * t_ + c2 * t_ * t_ + a * np.cos(w * t_) + b * np.sin(w * t_)

    best: tuple[float, float, np.ndarray] | None = None
    for w in np.linspace(0.5 * nutation_rate, 1.5 * nutation_rate, 201):
        coef = np.linalg.lstsq(basis(w), theta, rcond=None)[0]
        residual = float(np.sum((basis(w) @ coef - theta) ** 2))
        if best is None or residual < best[0]:
            best = (residual, w, coef)
    assert best is not None
    try:
        p, _ = curve_fit(model, t, theta, p0=[*best[2], best[1]])
    except RuntimeError:  # no convergence: keep the grid's best
        p = np.append(best[2], best[1])
    return float(np.hypot(p[3], p[4]))


@dataclass(frozen=True)
class Measure:
    nutation: float  # half-amplitude over the run, rad
    last: float  # half-amplitude over the last window (fitted), rad
    end_theta: float  # θ at the last sample, rad
    precession: float  # mean φ̇, rad/s
    energy: float  # largest relative energy change


def measure(run: TopRun) -> Measure:
    _, values = extremes(run.t, run.theta)
    if run.turning_theta is not None:
        values = np.concatenate([values, run.turning_theta])
    energy = run.energy(TOP)
    return Measure(
        nutation=0.5 * float(values.max() - values.min()),
        last=last_nutation(run, TOP.fast_top()[1]),
        end_theta=float(run.theta[-1]),
        precession=float((run.phi[-1] - run.phi[0]) / (run.t[-1] - run.t[0])),
        energy=float(np.max(np.abs(energy - TOP.energy0)) / TOP.energy0),
    )


# ------------------------------------------------------------------ runners
def tumble_run(method: str, dt: float | None = None, rtol: float | None = None) -> TopRun:
    extra = {} if rtol is None else {"rtol": rtol, "atol": rtol * 1e-3}
    step = SAMPLE_DT if dt is None else dt
    trajectory = tb.simulate(
        DISK,
        TOP.omega0,
        attitude0=TOP.attitude0,
        duration=TOP.duration,
        dt=step,
        pivot=PIVOT,
        gravity=GRAVITY,
        method=method,
        record_every=max(1, round(SAMPLE_DT / step)),
        **extra,
    )
    # thin_disk's body axes are principal about the pivot too: ω compares directly
    return TopRun(
        t=trajectory.t,
        omega=trajectory.omega,
        quaternion=trajectory.quaternion,
        # accepted steps for the adaptive method, where the trajectory reports them
        steps=getattr(trajectory, "steps", round(TOP.duration / trajectory.dt)),
    )


def tumble_available(method: str, adaptive: bool) -> str | None:
    """None if tumble runs `method`; otherwise why not (tumble's own message)."""
    extra = {"rtol": 1e-6, "atol": 1e-9} if adaptive else {}
    try:
        tb.simulate(
            DISK,
            TOP.omega0,
            attitude0=TOP.attitude0,
            duration=1e-3,
            dt=1e-4,
            pivot=PIVOT,
            gravity=GRAVITY,
            method=method,
            **extra,
        )
    except tb.InputError as error:
        return str(error)
    except TypeError as error:  # e.g. no `rtol` keyword yet
        return str(error)
    return None


@dataclass
class Config:
    name: str
    call: Callable[[], TopRun]
    family: str  # "tumble", "mujoco", "scipy"
    run: TopRun | None = None
    result: Measure | None = None
    seconds: float = float("nan")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    print("Heavy gyroscope: tumble vs MuJoCo and scipy")
    print(environment())
    precession, nutation_rate, half_amplitude = TOP.fast_top()
    print(
        f"disk m = {TOP.mass:g} kg, r = {TOP.radius:g} m, pivot {TOP.lever:g} m from its centre "
        f"on the axis; ω_s = {TOP.spin:g} rad/s, axis horizontal, released from rest, "
        f"T = {TOP.duration:g} s"
    )
    print(
        f"fast-top estimates: precession {precession:.4f} rad/s, nutation {nutation_rate:.1f} "
        f"rad/s, half-amplitude {np.degrees(half_amplitude):.4f}°"
    )

    # Truth ----------------------------------------------------------------
    start = time.perf_counter()
    truth_run = scipy_top(
        TOP,
        rtol=1e-13,
        atol=1e-15,
        t_eval=np.linspace(0, TOP.duration, round(TOP.duration / SAMPLE_DT) + 1),
        turning_points=True,
    )
    truth_seconds = time.perf_counter() - start
    truth = measure(truth_run)
    exact_half = 0.5 * (TOP.turning_angle() - np.pi / 2)
    print(
        f"truth: scipy DOP853 rtol 1e-13 atol 1e-15 ({truth_seconds:.1f} s): half-amplitude "
        f"{np.degrees(truth.nutation):.10f}°, exact turning point gives "
        f"{np.degrees(exact_half):.10f}° (relative difference "
        f"{abs(truth.nutation / exact_half - 1):.1e}); mean φ̇ {truth.precession:.10f} rad/s\n"
    )

    # Configurations -------------------------------------------------------
    configs: list[Config] = [
        Config(
            "scipy DOP853 rtol=1e-12",
            lambda: scipy_top(
                TOP,
                rtol=1e-12,
                atol=1e-14,
                t_eval=np.linspace(0, TOP.duration, round(TOP.duration / SAMPLE_DT) + 1),
            ),
            "scipy",
        )
    ]
    for integrator in INTEGRATORS:
        model = top_model(TOP, MUJOCO_DT, integrator)
        configs.append(
            Config(
                f"mujoco {integrator} dt={MUJOCO_DT:g}",
                lambda m=model: mujoco_top(TOP, m),
                "mujoco",
            )
        )

    tb.simulate(  # compile tumble's kernels (or load them from numba's cache)
        DISK, TOP.omega0, duration=1e-2, dt=1e-3, pivot=PIVOT, gravity=GRAVITY, method="rk4"
    )
    unavailable: list[str] = []
    notes: list[str] = []
    chosen: dict[str, Config] = {}
    for method in ("rk4", "splitting", "strang", "adaptive"):
        adaptive = method == "adaptive"
        why = tumble_available(method, adaptive)
        if why is not None:
            unavailable.append(f"tumble {method}: not available ({why})")
            continue
        scan: list[Config] = []
        for value in ADAPTIVE_RTOLS if adaptive else FIXED_STEP_DTS:
            if adaptive:
                config = Config(
                    f"tumble adaptive rtol={value:g}",
                    lambda r=value, m=method: tumble_run(m, rtol=r),
                    "tumble",
                )
            else:
                config = Config(
                    f"tumble {method} dt={value:g}",
                    lambda d=value, m=method: tumble_run(m, dt=d),
                    "tumble",
                )
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", CoarseStepWarning)
                try:
                    config.run = config.call()  # warm-up, and the accuracy
                except tb.InputError as error:  # e.g. the state became NaN
                    notes.append(f"{config.name}: failed ({error})")
                    continue
            coarse = [w for w in caught if issubclass(w.category, CoarseStepWarning)]
            if coarse:
                notes.append(f"{config.name}: tumble warned: {coarse[0].message}")
            config.result = measure(config.run)
            scan.append(config)
            if abs(config.result.nutation / truth.nutation - 1) <= TARGET:
                chosen[method] = config
                break
        configs.extend(scan)

    # Warm-up of the peers, then interleaved timing ------------------------
    for config in configs:
        if config.run is None:
            config.run = config.call()
            config.result = measure(config.run)
    samples: dict[str, list[float]] = {c.name: [] for c in configs}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoarseStepWarning)  # noted once above
        for _ in range(args.repeat):
            for config in configs:
                start = time.perf_counter()
                config.call()
                samples[config.name].append(time.perf_counter() - start)
    for config in configs:
        config.seconds = statistics.median(samples[config.name])

    # Table ----------------------------------------------------------------
    print(
        "nutation: half-amplitude (θmax − θmin)/2 over the run; last: fitted half-amplitude "
        f"over the last {LAST_WINDOW:g} s;\nθ(T): polar angle of the axis at the end; errors "
        "relative to the truth; energy: max |E − E0|/E0;\n"
        "steps: time steps (scipy: right-hand-side evaluations; adaptive: accepted steps); "
        f"time: median of {args.repeat} interleaved runs"
    )
    header = (
        f"{'integrator':30s} {'steps':>7s} {'time s':>8s} {'nutation°':>12s} {'rel err':>8s} "
        f"{'last°':>9s} {'θ(T)°':>9s} {'mean φ̇':>9s} {'rel err':>8s} {'energy':>8s}"
    )
    print(header)
    print("-" * len(header))
    print(
        f"{'truth (DOP853 rtol=1e-13)':30s} {'':>7s} {truth_seconds:8.4f} "
        f"{np.degrees(truth.nutation):12.8f} {'':>8s} {np.degrees(truth.last):9.2e} "
        f"{np.degrees(truth.end_theta):9.4f} "
        f"{truth.precession:9.6f} {'':>8s} {truth.energy:8.1e}"
    )
    for config in configs:
        m = config.result
        assert m is not None and config.run is not None
        print(
            f"{config.name:30s} {config.run.steps:7d} {config.seconds:8.4f} "
            f"{np.degrees(m.nutation):12.8f} {abs(m.nutation / truth.nutation - 1):8.1e} "
            f"{np.degrees(m.last):9.2e} {np.degrees(m.end_theta):9.4f} {m.precession:9.6f} "
            f"{abs(m.precession / truth.precession - 1):8.1e} {m.energy:8.1e}"
        )
        if config.run.diverged_at is not None:
            notes.append(
                f"{config.name}: NaN/huge acceleration at t = {config.run.diverged_at:.3f} s, "
                "MuJoCo reset the state to t = 0 and went on; measured on the samples before"
            )
    for line in notes + unavailable:
        print("  " + line)

    euler = next(c for c in configs if c.name.startswith("mujoco Euler"))
    fast = next(c for c in configs if c.name.startswith("mujoco implicitfast"))
    assert euler.run is not None and fast.run is not None
    same = euler.run.t.size == fast.run.t.size and np.array_equal(
        euler.run.quaternion, fast.run.quaternion
    )
    print(f"  mujoco implicitfast gives the same states as Euler on this model: {same}")

    # Ratios ---------------------------------------------------------------
    mujoco_rk4 = next(c for c in configs if c.name.startswith("mujoco RK4"))
    assert mujoco_rk4.result is not None
    rk4_error = abs(mujoco_rk4.result.nutation / truth.nutation - 1)
    print(
        f"\ntarget: tumble's nutation amplitude right to {TARGET:g} relative, in less time than "
        f"MuJoCo RK4 at dt={MUJOCO_DT:g} ({mujoco_rk4.seconds * 1e3:.1f} ms, "
        f"error {rk4_error:.1e})"
    )
    for config in chosen.values():
        assert config.result is not None
        error = abs(config.result.nutation / truth.nutation - 1)
        verdict = "met" if config.seconds < mujoco_rk4.seconds else "not met"
        print(
            f"  {config.name:30s} error {error:.1e} in {config.seconds * 1e3:.1f} ms; "
            f"MuJoCo RK4 time / tumble time = {mujoco_rk4.seconds / config.seconds:.2f} "
            f"({verdict})"
        )
        for peer in configs:
            if peer.family != "tumble" and peer is not mujoco_rk4:
                ratio = peer.seconds / config.seconds
                print(f"      peer time / tumble time, {peer.name:28s} {ratio:8.2f}x")
    missing = [m for m in ("rk4", "splitting", "strang", "adaptive") if m not in chosen]
    for method in missing:
        if not any(line.startswith(f"tumble {method}:") for line in unavailable):
            print(f"  tumble {method}: no setting scanned reached {TARGET:g}")


if __name__ == "__main__":
    main()
