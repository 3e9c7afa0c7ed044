"""Benchmark: bodies fitted to throws under air drag, one throw at a time and 30
throws at once, tumble against the same model written with scipy (``solve_ivp``
inside ``least_squares``), in one run. ``bench/identify.py`` runs these parts after
its torque-free one; this file runs them alone.

The data, with a known truth: :func:`tumble.identification.throws.synthetic_throws`,
a racquet (I1/I3 = 0.067, I2/I3 = 0.94) carrying a phone whose axes are turned from
its principal axes, thrown again and again about its intermediate axis at 7–12 rad/s
under linear air drag c/I3 = (0.05, 0.12, 0.15) 1/s per principal axis; each free
flight 80 samples at 100 Hz, gyroscope noise σ = 0.0035 rad/s and a bias of
(0.01, −0.005, 0.003) rad/s; between flights the hand holds, throws and catches it.

* Single throws: the throws of ``synthetic_throws(--singles, seed=0)``, one by one.
  tumble: ``tumble.identify(t, omega, window=..., torque="drag")``, from no guess.
  The peer: the same 14 parameters (the two ratios as logarithms, a rotation vector
  of the axes, ω0, the bias, c/I3) fitted by ``least_squares(method="lm")`` with its
  default numerical Jacobian (``x_scale="jac"``), each residual integrating Euler's
  equations with the drag term by ``solve_ivp(method="DOP853", rtol=RTOL, atol=ATOL,
  t_eval=...)``. Then tumble alone on ``synthetic_throws(--singles, seed=1,
  samples=100)``: the goal, a throw of 100 samples in ≤ 0.5 s warm, on the median.
* A joint fit: ``synthetic_throws(30, seed)`` for seeds 0 to ``--joint-seeds`` − 1.
  tumble: ``tumble.identification.many.identify_many(t, omega, windows,
  torque="drag")``, timed whole (30 single fits, then the joint fit). The peer: one
  ``least_squares`` over all the throws' residuals, sharing the ratios, the axes, the
  bias and the drag (11 parameters) with ω0 per throw (3 a throw: 101 in all), each
  throw's residuals from its own ``solve_ivp``; ``method="trf"`` with the default
  numerical Jacobian told its block structure (``jac_sparsity``: a throw's residuals
  depend on the shared parameters and its own ω0 only), so that a Jacobian takes 14
  evaluations instead of 101, and ``x_scale="jac"`` (without it the trust region
  crawls: 76 s instead of 28 s on 8 throws).

Both peers start from the truth moved by a fixed offset (:func:`peer_start`): a head
start that tumble does not get, so their times are lower bounds. Their integrator's
tolerance is the loosest that keeps its error far below the noise (the head prints
the check), which makes them faster than at scipy's tightest. A trial step far from
any body (I1/I3 of 1e12) makes Euler's equations so stiff that DOP853 would crawl for
minutes: an integration is abandoned after ``MAX_CALLS`` evaluations and its residuals
made large, which turns the step back.

Accuracy: the larger over the two ratios of |ratio − truth| and of |ratio − truth| /
its standard error (tumble's ``uncertainty``; the peers' from their Jacobian at the
solution, σ² (JᵀJ)⁻¹, as tumble computes it); the larger over the three of |c/I3 −
truth| / its standard error; the residuals' rms over the noise. Tables give medians
over the fits, and the ratio of the peer's median time to tumble's.

Not timed tests: numbers, printed for bench/RESULTS.md. Run from the root::

    .venv/bin/python bench/identify_drag.py [--singles 4] [--joint-seeds 1]
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import dataclass

import numpy as np
import scipy
from numpy.typing import NDArray
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares
from scipy.sparse import lil_matrix
from scipy.spatial.transform import Rotation

import tumble as tb
from machine import describe
from tumble.identification.many import identify_many
from tumble.identification.throws import ThrowsRecording, synthetic_throws

Array = NDArray[np.float64]

#: The goal for the time of one throw of 100 samples, warm (s).
GOAL = 0.5

#: The peers' integrator tolerances: the check in the head shows their error at the
#: truth is some 1e-7 rad/s, four orders below the noise.
RTOL, ATOL = 1e-8, 1e-10

#: The peers' head start: the truth moved by these offsets, the bias and the drag from 0.
RATIO_OFFSET = (0.01, -0.02)
AXES_OFFSET_DEG = 2.0  # about (1, 1, 1)/√3 of the principal frame
OMEGA0_OFFSET = (0.01, -0.01, 0.01)  # relative, per component

#: Evaluations of Euler's equations after which an integration is abandoned: a flight
#: at the truth takes a few hundred; a trial step of the fit far from any body (I1/I3 of
#: 1e12, say) makes the equations so stiff that DOP853 would crawl for minutes.
MAX_CALLS = 20_000


class Runaway(Exception):
    """An integration abandoned after ``MAX_CALLS`` evaluations."""


#: Shared parameters of the joint peer: ln r (2), rotation vector (3), bias (3), drag (3).
SHARED = 11


@dataclass(frozen=True)
class Outcome:
    """One fit: its time and how far it is from the truth."""

    seconds: float
    ratio_error: float  # max over the two ratios of |fitted − true|
    error_per_se: float  # max over the two ratios of |fitted − true| / SE
    se: float  # the standard error of I1/I3
    drag_per_se: float  # max over the three of |fitted − true c/I3| / SE
    noise_ratio: float  # residual rms / noise


def outcome(
    truth: ThrowsRecording,
    seconds: float,
    ratios: Array,
    errors: Array,
    drag: Array,
    drag_errors: Array,
    rms: float,
) -> Outcome:
    off = np.abs(ratios - truth.moment_ratios)
    return Outcome(
        seconds=seconds,
        ratio_error=float(off.max()),
        error_per_se=float(np.max(off / errors)),
        se=float(errors[0]),
        drag_per_se=float(np.max(np.abs(drag - truth.drag) / drag_errors)),
        noise_ratio=rms / truth.noise,
    )


def flight(recording: ThrowsRecording, window: tuple[float, float]) -> tuple[Array, Array]:
    """Times from the release (s) and measured rates of one throw's free flight."""
    inside = (recording.t >= window[0]) & (recording.t <= window[1])
    t = recording.t[inside]
    return t - t[0], recording.omega[inside]


# ------------------------------------------------------------------ the peers
def integrated_rates(
    ratios: Array, drag: Array, omega0: Array, times: Array, rtol: float = RTOL
) -> Array | None:
    """(n, 3) ω at ``times`` (from 0), principal axes, moments (r1, r2, 1): Euler's
    equations with linear drag, I ω' = −ω × Iω − c ω, integrated by scipy's DOP853;
    None when it fails."""
    r1, r2 = float(ratios[0]), float(ratios[1])
    c1, c2, c3 = (float(c) for c in drag)
    calls = 0

    def euler(_t: float, w: Array) -> Array:
        nonlocal calls
        calls += 1
        if calls > MAX_CALLS:
            raise Runaway
        # Written out: three times as fast as np.cross on 3-vectors.
        w1, w2, w3 = w
        return np.array(
            [
                ((r2 - 1.0) * w2 * w3 - c1 * w1) / r1,
                ((1.0 - r1) * w3 * w1 - c2 * w2) / r2,
                (r1 - r2) * w1 * w2 - c3 * w3,
            ]
        )

    try:
        solution = solve_ivp(
            euler,
            (0.0, float(times[-1])),
            omega0,
            method="DOP853",
            rtol=rtol,
            atol=rtol * ATOL / RTOL,
            t_eval=times,
        )
    except Runaway:
        return None
    if not solution.success or solution.y.shape[1] != times.size:
        return None
    return np.asarray(solution.y.T)


def throw_residuals(
    shared: Array, omega0: Array, frame: Array, times: Array, measured: Array
) -> Array:
    """Model − measurement of one throw, flattened; ``shared`` = (ln r1, ln r2,
    rotation vector of the axes from ``frame``, bias, c/I3)."""
    rates = integrated_rates(np.exp(shared[:2]), shared[8:11], omega0, times)
    if rates is None:  # far from any motion: a large residual turns the step back
        return np.full(measured.size, 1e3)
    axes = frame @ Rotation.from_rotvec(shared[2:5]).as_matrix()
    return np.asarray((rates @ axes.T + shared[5:8] - measured).ravel())


def peer_start(truth: ThrowsRecording, throws: list[int]) -> tuple[Array, Array, Array]:
    """The peers' head start, (shared, ω0 per throw, frame): the true ratios moved by
    ``RATIO_OFFSET``, the true axes turned by ``AXES_OFFSET_DEG``, each component of
    each true ω0 moved by ``OMEGA0_OFFSET`` (relative), the bias and the drag 0."""
    ratios = truth.moment_ratios + np.array(RATIO_OFFSET)
    turn = Rotation.from_rotvec(np.radians(AXES_OFFSET_DEG) * np.ones(3) / np.sqrt(3.0))
    frame = truth.axes @ turn.as_matrix()
    omega0 = truth.omega0[throws] * (1.0 + np.array(OMEGA0_OFFSET))
    return np.concatenate([np.log(ratios), np.zeros(9)]), omega0, frame


def peer_errors(result: scipy.optimize.OptimizeResult, jac: Array) -> tuple[Array, Array, Array]:
    """The fitted ratios, their and the drag's standard errors: σ² (JᵀJ)⁻¹ as tumble's,
    d r = r d(ln r); the shared parameters lead ``jac``'s columns."""
    ratios = np.exp(result.x[:2])
    variance = 2 * result.cost / max(result.fun.size - result.x.size, 1)
    covariance = variance * np.linalg.pinv(jac.T @ jac, hermitian=True)
    errors = np.sqrt(np.abs(np.diag(covariance)))
    return ratios, ratios * errors[:2], errors


def peer_single(truth: ThrowsRecording, throw: int) -> Outcome:
    """The 14-parameter drag fit of one throw by least_squares over solve_ivp, timed.
    Its parameters: the shared ones then ω0 (tumble orders them differently; the
    fit does not care)."""
    times, measured = flight(truth, truth.windows[throw])
    shared, omega0, frame = peer_start(truth, [throw])

    def residuals(x: Array) -> Array:
        return throw_residuals(x[:SHARED], x[SHARED:], frame, times, measured)

    start = time.perf_counter()
    result = least_squares(
        residuals, np.concatenate([shared, omega0[0]]), method="lm", x_scale="jac"
    )
    seconds = time.perf_counter() - start
    ratios, errors, every = peer_errors(result, result.jac)
    rms = float(np.sqrt(np.mean(result.fun**2)))
    return outcome(truth, seconds, ratios, errors, result.x[8:11], every[8:11], rms)


def peer_joint(truth: ThrowsRecording) -> Outcome:
    """All the throws at once: shared body, axes, bias and drag, ω0 per throw; one
    least_squares told the Jacobian's block structure, timed."""
    throws = list(range(len(truth.windows)))
    flights = [flight(truth, truth.windows[i]) for i in throws]
    shared, omega0, frame = peer_start(truth, throws)
    rows = np.cumsum([0] + [m.size for _, m in flights])
    sparsity = lil_matrix((int(rows[-1]), SHARED + 3 * len(throws)), dtype=int)
    for i in throws:
        sparsity[rows[i] : rows[i + 1], :SHARED] = 1
        sparsity[rows[i] : rows[i + 1], SHARED + 3 * i : SHARED + 3 * i + 3] = 1

    def residuals(x: Array) -> Array:
        return np.concatenate(
            [
                throw_residuals(
                    x[:SHARED], x[SHARED + 3 * i : SHARED + 3 * i + 3], frame, *flights[i]
                )
                for i in throws
            ]
        )

    start = time.perf_counter()
    result = least_squares(
        residuals,
        np.concatenate([shared, omega0.ravel()]),
        method="trf",
        jac_sparsity=sparsity,
        x_scale="jac",
    )
    seconds = time.perf_counter() - start
    ratios, errors, every = peer_errors(result, result.jac.toarray())
    rms = float(np.sqrt(np.mean(result.fun**2)))
    return outcome(truth, seconds, ratios, errors, result.x[8:11], every[8:11], rms)


# ------------------------------------------------------------------ tumble
def tumble_single(truth: ThrowsRecording, throw: int) -> Outcome:
    """``tumble.identify(torque="drag")`` on one throw of the recording, timed."""
    start = time.perf_counter()
    fit = tb.identify(truth.t, truth.omega, window=truth.windows[throw], torque="drag")
    seconds = time.perf_counter() - start
    return outcome(
        truth,
        seconds,
        fit.moment_ratios,
        fit.uncertainty,
        fit.torque_parameters,
        fit.torque_uncertainty,
        fit.residual_rms,
    )


def tumble_joint(truth: ThrowsRecording) -> tuple[Outcome, str]:
    """``identify_many(torque="drag")`` on the recording's windows, timed whole; and
    how many throws it fitted alone and joined."""
    start = time.perf_counter()
    many = identify_many(truth.t, truth.omega, list(truth.windows), torque="drag")
    seconds = time.perf_counter() - start
    joint = many.joint
    if joint is None:
        raise SystemExit(f"identify_many made no joint fit: {many.joint_refusal}")
    note = (
        f"{len(many.fitted)}/{len(truth.windows)} fitted alone, {len(joint.throws)} joined, "
        f"{len(joint.outliers)} outliers"
    )
    return (
        outcome(
            truth,
            seconds,
            joint.moment_ratios,
            joint.uncertainty,
            joint.torque_parameters,
            joint.torque_uncertainty,
            joint.residual_rms,
        ),
        note,
    )


# ------------------------------------------------------------------ the report
HEAD = (
    f"{'method':<34s} {'fits':>4s} {'median s':>9s} {'ratio error':>11s} {'err/SE':>7s} "
    f"{'SE r1':>8s} {'drag err/SE':>11s} {'rms/σ':>6s} {'peer/tumble':>11s}"
)


def row(name: str, fits: list[Outcome], ratio: str = "") -> str:
    def med(values: list[float]) -> float:
        return statistics.median(values)

    return (
        f"{name:<34s} {len(fits):4d} {med([f.seconds for f in fits]):9.3f} "
        f"{med([f.ratio_error for f in fits]):11.1e} {med([f.error_per_se for f in fits]):7.2f} "
        f"{med([f.se for f in fits]):8.1e} {med([f.drag_per_se for f in fits]):11.2f} "
        f"{med([f.noise_ratio for f in fits]):6.2f} {ratio:>11s}"
    ).rstrip()


def times_ratio(ours: list[Outcome], theirs: list[Outcome]) -> str:
    peer = statistics.median(f.seconds for f in theirs)
    return f"{peer / statistics.median(f.seconds for f in ours):.1f}x"


def model_check() -> str:
    """The peers' model at the truth against the integration the data came from
    (``tumble.simulate`` under ``AxisDrag``, adaptive at 1e-12)."""
    truth = synthetic_throws(3, seed=0)
    body = tb.MassProperties(1.0, np.zeros(3), np.diag([*truth.moment_ratios, 1.0]))
    gap = 0.0
    for i in range(3):
        times, _ = flight(truth, truth.windows[i])
        peer = integrated_rates(truth.moment_ratios, truth.drag, truth.omega0[i], times)
        data = tb.simulate(
            body,
            truth.omega0[i],
            duration=float(times[-1]),
            dt=float(times[1]),
            torque=tb.torques.AxisDrag(truth.drag),
            method="adaptive",
            rtol=1e-12,
            atol=1e-12,
        )
        assert peer is not None
        gap = max(gap, float(np.max(np.abs(peer - np.asarray(data.omega)[: times.size]))))
    return (
        f"peer model check: |ω(DOP853, rtol {RTOL:g}) − ω(the data's integration)| ≤ "
        f"{gap:.1e} rad/s over 3 flights at the truth; peers start from the truth + ratios "
        f"{RATIO_OFFSET}, axes {AXES_OFFSET_DEG:g}°, ω0 × (1 + {OMEGA0_OFFSET}), bias 0, "
        "drag 0 (a head start: their times are lower bounds)"
    )


def singles(count: int) -> list[Outcome]:
    """Single throws, tumble and the peer interleaved; prints their table."""
    truth = synthetic_throws(count, seed=0)
    ours, theirs = [], []
    for throw in range(count):
        ours.append(tumble_single(truth, throw))
        theirs.append(peer_single(truth, throw))
    print(
        f"\nsingle throws: synthetic_throws({count}, seed=0), one throw a fit, 80 samples at "
        f"100 Hz, true ratios {truth.moment_ratios[0]:g}, {truth.moment_ratios[1]:g}, "
        f"c/I3 {truth.drag.tolist()} 1/s, noise σ {truth.noise:g} rad/s"
    )
    print(HEAD)
    print(row('tumble.identify(torque="drag")', ours))
    print(row("solve_ivp in least_squares (lm)", theirs, times_ratio(ours, theirs)))
    print(f"{'throw':>5s} {'tumble s':>8s} {'err/SE':>7s} {'peer s':>8s} {'err/SE':>7s}")
    for throw, (a, b) in enumerate(zip(ours, theirs, strict=True)):
        print(
            f"{throw:5d} {a.seconds:8.3f} {a.error_per_se:7.2f} "
            f"{b.seconds:8.3f} {b.error_per_se:7.2f}"
        )
    return ours


def joints(seeds: int, count: int) -> None:
    """Joint fits of ``count`` throws, tumble and the peer interleaved; prints their table."""
    ours, theirs, notes = [], [], []
    for seed in range(seeds):
        truth = synthetic_throws(count, seed=seed)
        fit, note = tumble_joint(truth)
        ours.append(fit)
        notes.append(note)
        theirs.append(peer_joint(truth))
    print(
        f"\njoint fit: synthetic_throws({count}, seed) for seed in range({seeds}), "
        f"{SHARED} shared parameters + 3 a throw for the peer"
    )
    print(HEAD)
    print(row('identify_many(torque="drag")', ours))
    print(row("solve_ivp in least_squares (trf)", theirs, times_ratio(ours, theirs)))
    for seed, (a, b, note) in enumerate(zip(ours, theirs, notes, strict=True)):
        print(
            f"seed {seed}: tumble {a.seconds:.2f} s ({note}), err/SE {a.error_per_se:.2f}; "
            f"peer {b.seconds:.2f} s, err/SE {b.error_per_se:.2f}"
        )


def goal(count: int) -> None:
    """tumble alone on throws of 100 samples: the goal's size."""
    truth = synthetic_throws(count, seed=1, samples=100)
    seconds = []
    for window in truth.windows:
        start = time.perf_counter()
        tb.identify(truth.t, truth.omega, window=window, torque="drag")
        seconds.append(time.perf_counter() - start)
    median = statistics.median(seconds)
    verdict = "met" if median <= GOAL else "NOT met"
    print(
        f"synthetic_throws({count}, seed=1, samples=100), tumble.identify(torque='drag'): "
        f"median {median:.3f} s, largest {max(seconds):.3f} s "
        f"(goal ≤ {GOAL:g} s a throw of 100 samples, on the median: {verdict})"
    )


def warm_up() -> None:
    """Compile (or load) tumble's kernels before anything is timed."""
    truth = synthetic_throws(3, seed=99)
    identify_many(truth.t, truth.omega, list(truth.windows), torque="drag")


def run(singles_count: int, joint_seeds: int, throws: int) -> None:
    """The drag parts of the benchmark, in order (the machine printed by the caller)."""
    print(model_check())
    warm_up()
    singles(singles_count)
    goal(singles_count)
    if joint_seeds:
        joints(joint_seeds, throws)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--singles", type=int, default=4, help="single throws (default 4)")
    parser.add_argument("--joint-seeds", type=int, default=1, help="joint fits (default 1)")
    parser.add_argument("--throws", type=int, default=30, help="throws a joint fit (default 30)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    add_arguments(parser)
    args = parser.parse_args()
    print(describe({"scipy": scipy.__version__}))
    run(args.singles, args.joint_seeds, args.throws)


if __name__ == "__main__":
    main()
