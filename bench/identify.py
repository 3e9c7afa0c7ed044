"""Benchmark: bodies fitted to gyroscope samples, tumble against a generic fit
(scipy ``solve_ivp`` inside ``least_squares``) of the same model, in one run: 10 s
of torque-free flight; single throws under air drag; 30 throws under air drag
fitted jointly.

The drag parts are described in ``bench/identify_drag.py`` (which runs them alone);
this file describes the torque-free part, which runs first (``--parts`` chooses).

The data, with a known truth: :func:`tumble.identification.synthetic_phone`
with ``flight=10``: a box of a phone's proportions (I1/I3 = 0.182, I2/I3 =
0.822), its principal axes turned a few degrees from the sensor's, thrown at
12 rad/s about its intermediate axis; 10 s of free flight sampled at 500 Hz
(each interval ±15 %), about 5000 samples and eight flips, with a bias of
(0.02, −0.015, 0.01) rad/s and white noise σ = 0.01 rad/s. Both fits take the
samples of ``window=(release, catch)``. Seeds 0 to ``--seeds`` − 1.

* tumble: ``tumble.identify(t, omega, window=...)``, the exact torque-free
  motion (Jacobi elliptic functions) fitted by least squares from a start it
  finds itself. One timing a seed, after a warm-up call that compiles (or
  loads) the numba kernels.
* the peer: the same model and its 11 parameters (the two ratios as
  logarithms, a rotation vector of the axes, ω0, the bias) fitted by
  ``scipy.optimize.least_squares(method="lm")`` with its default numerical
  Jacobian, each residual integrating Euler's torque-free equations with
  ``solve_ivp(method="DOP853", rtol=1e-10, atol=1e-12, t_eval=the samples)``:
  the fit one writes by hand. It starts from the truth moved by a fixed offset
  (:func:`peer_start`): a head start that tumble does not get, so its time is
  a lower bound. Seeds 0 to ``--peer-seeds`` − 1 (each fit takes seconds).

Accuracy of a fit: the larger of |ratio − truth| over the two ratios, and of
|ratio − truth| / its standard error (tumble's ``uncertainty``; the peer's
from its Jacobian at the solution, σ² (JᵀJ)⁻¹, as tumble computes it); the
largest angle between a fitted principal axis and the true one (deg); |bias −
truth| (rad/s). A fit whose residuals' rms exceeds 1.5 σ has not found the
motion: it is counted as a miss. The table gives medians over the seeds, the
time ratio medians over the seeds both fitted.

Not timed tests: numbers, printed for bench/RESULTS.md. Run from the root::

    .venv/bin/python bench/identify.py [--seeds 3] [--peer-seeds 1] [--singles 4]
        [--joint-seeds 1] [--throws 30] [--parts free,drag]

A default run takes about four minutes on two cores, most of it the two joint fits of
30 throws (``--throws 10`` for a quicker look).
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
from scipy.spatial.transform import Rotation

import identify_drag
import tumble as tb
from machine import describe
from tumble.identification import PhoneRecording, synthetic_phone
from tumble.identification.result import principal_rates
from tumble.theory import flip_period

Array = NDArray[np.float64]

#: Seconds of free flight, and the goal for tumble's time to fit them.
FLIGHT = 10.0
GOAL = 1.0

#: The peer's head start: the truth moved by these offsets.
RATIO_OFFSET = (0.02, -0.02)
AXES_OFFSET_DEG = 2.0  # about (1, 1, 1)/√3 of the principal frame
OMEGA0_OFFSET = (0.01, -0.01, 0.01)  # relative, per component

#: A fit whose residuals' rms exceeds this many σ of the noise missed the motion.
MISS = 1.5


@dataclass(frozen=True)
class Outcome:
    """One fit of one recording: its time and how far it is from the truth."""

    seconds: float
    ratio_error: float  # max over the two ratios of |fitted − true|
    error_per_se: float  # max over the two ratios of |fitted − true| / SE
    axis_error_deg: float  # largest angle between a fitted and a true principal axis
    bias_error: float  # |fitted − true bias|, rad/s
    residual_rms: float  # rad/s

    def missed(self, noise: float) -> bool:
        return self.residual_rms > MISS * noise


def recording(seed: int) -> tuple[PhoneRecording, Array, Array]:
    """The seed's recording, and the times and rates of its free flight."""
    phone = synthetic_phone(seed, flight=FLIGHT)
    inside = (phone.t >= phone.release) & (phone.t <= phone.catch)
    return phone, phone.t[inside], phone.omega[inside]


def outcome(
    phone: PhoneRecording,
    seconds: float,
    ratios: Array,
    errors: Array,
    axes: Array,
    bias: Array,
    rms: float,
) -> Outcome:
    """A fit's errors against the truth (axes compared up to their signs)."""
    off = np.abs(ratios - phone.moment_ratios)
    cosines = np.clip(np.abs(np.sum(axes * phone.axes, axis=0)), 0.0, 1.0)
    return Outcome(
        seconds=seconds,
        ratio_error=float(off.max()),
        error_per_se=float(np.max(off / errors)),
        axis_error_deg=float(np.degrees(np.arccos(cosines)).max()),
        bias_error=float(np.linalg.norm(bias - phone.bias)),
        residual_rms=rms,
    )


def tumble_fit(seed: int) -> Outcome:
    """``tumble.identify`` on the seed's recording, timed."""
    phone, _, _ = recording(seed)
    start = time.perf_counter()
    fit = tb.identify(phone.t, phone.omega, window=(phone.release, phone.catch))
    seconds = time.perf_counter() - start
    return outcome(
        phone, seconds, fit.moment_ratios, fit.uncertainty, fit.axes, fit.bias, fit.residual_rms
    )


# ------------------------------------------------------------------ the peer
def integrated_rates(moments: Array, omega0: Array, times: Array) -> Array:
    """(n, 3) ω at ``times`` (from 0), principal axes: Euler's torque-free
    equations integrated by scipy's DOP853."""
    i1, i2, i3 = moments
    c = np.array([(i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3])

    def euler(_t: float, w: Array) -> Array:
        return c * np.array([w[1] * w[2], w[2] * w[0], w[0] * w[1]])

    solution = solve_ivp(
        euler,
        (0.0, float(times[-1])),
        omega0,
        method="DOP853",
        rtol=1e-10,
        atol=1e-12,
        t_eval=times,
    )
    return np.asarray(solution.y.T)


def peer_residuals(x: Array, frame: Array, times: Array, measured: Array) -> Array:
    """Model − measurement, flattened: x = (ln r1, ln r2, rotation vector of the
    axes from ``frame``, ω0, bias), tumble's model with an integrator inside."""
    moments = np.array([np.exp(x[0]), np.exp(x[1]), 1.0])
    axes = frame @ Rotation.from_rotvec(x[2:5]).as_matrix()
    predicted = integrated_rates(moments, x[5:8], times) @ axes.T + x[8:11]
    return np.asarray((predicted - measured).ravel())


def peer_start(phone: PhoneRecording) -> tuple[Array, Array]:
    """The peer's head start, (x0, frame): the true ratios moved by
    ``RATIO_OFFSET``, the true axes turned by ``AXES_OFFSET_DEG``, each
    component of the true ω0 moved by ``OMEGA0_OFFSET`` (relative), the bias 0
    (as tumble starts it)."""
    ratios = phone.moment_ratios + np.array(RATIO_OFFSET)
    turn = Rotation.from_rotvec(np.radians(AXES_OFFSET_DEG) * np.ones(3) / np.sqrt(3.0))
    frame = phone.axes @ turn.as_matrix()
    omega0 = phone.omega0 * (1.0 + np.array(OMEGA0_OFFSET))
    return np.concatenate([np.log(ratios), np.zeros(3), omega0, np.zeros(3)]), frame


def peer_fit(seed: int) -> Outcome:
    """The generic fit on the seed's recording, timed."""
    phone, t, omega = recording(seed)
    times = t - phone.release
    x0, frame = peer_start(phone)
    start = time.perf_counter()
    result = least_squares(peer_residuals, x0, args=(frame, times, omega), method="lm")
    seconds = time.perf_counter() - start
    # Standard errors as tumble's: σ² (JᵀJ)⁻¹, d r = r d(ln r).
    ratios = np.exp(result.x[:2])
    variance = 2 * result.cost / max(omega.size - result.x.size, 1)
    covariance = variance * np.linalg.pinv(result.jac.T @ result.jac, hermitian=True)
    errors = ratios * np.sqrt(np.abs(np.diag(covariance)[:2]))
    axes = frame @ Rotation.from_rotvec(result.x[2:5]).as_matrix()
    rms = float(np.sqrt(np.mean(result.fun**2)))
    return outcome(phone, seconds, ratios, errors, axes, result.x[8:11], rms)


# ------------------------------------------------------------------ the report
def row(name: str, fits: list[Outcome], noise: float, ratio: str) -> str:
    def med(values: list[float]) -> float:
        return statistics.median(values)

    misses = sum(f.missed(noise) for f in fits)
    return (
        f"{name:<28s} {len(fits):5d} {med([f.seconds for f in fits]):9.3f} "
        f"{med([f.ratio_error for f in fits]):12.1e} {med([f.error_per_se for f in fits]):9.2f} "
        f"{med([f.axis_error_deg for f in fits]):10.4f} {med([f.bias_error for f in fits]):11.1e} "
        f"{misses:6d} {ratio:>12s}"
    )


def detail(label: str, f: Outcome | None, noise: float) -> str:
    if f is None:
        return f"{label} {'':>8s} {'':>9s} {'':>7s} {'':>8s} {'':>5s}"
    mark = "miss" if f.missed(noise) else ""
    return (
        f"{label} {f.seconds:8.3f} {f.ratio_error:9.1e} {f.error_per_se:7.2f} "
        f"{f.axis_error_deg:8.4f} {mark:>5s}"
    )


def torque_free(seeds: int, peer_seeds: int) -> None:
    """The torque-free part: 10 s of flight, tumble and the peer; prints their table."""
    phone, t, _ = recording(0)
    noise = phone.noise
    print(
        f"data: synthetic_phone(seed, flight={FLIGHT:g}), {t.size} samples in the window "
        f"(mean {1 / np.mean(np.diff(t)):.0f} Hz, ±15 %), true ratios "
        f"{phone.moment_ratios[0]:.5f}, {phone.moment_ratios[1]:.5f}, flip period "
        f"{flip_period([*phone.moment_ratios, 1.0], phone.omega0):.3g} s, "
        f"noise σ {noise:g} rad/s, bias {phone.bias.tolist()} rad/s"
    )
    times = t - phone.release
    moments = np.array([*phone.moment_ratios, 1.0])
    gap = np.max(
        np.abs(
            integrated_rates(moments, phone.omega0, times)
            - principal_rates(moments, phone.omega0, times)
        )
    )
    print(
        f"peer model check: |ω(DOP853, rtol 1e-10) − ω(exact)| ≤ {gap:.1e} rad/s over the "
        f"flight at the truth; peer starts from the truth + ratios {RATIO_OFFSET}, axes "
        f"{AXES_OFFSET_DEG:g}°, ω0 × (1 + {OMEGA0_OFFSET}), bias 0 (a head start: its time is "
        "a lower bound)"
    )

    # Compile (or load) tumble's kernels before timing.
    warm = synthetic_phone(0)
    tb.identify(warm.t, warm.omega, window=(warm.release, warm.catch))

    ours = [tumble_fit(seed) for seed in range(seeds)]
    theirs = [peer_fit(seed) for seed in range(peer_seeds)]

    both = min(len(ours), len(theirs))
    ratio = "-"
    if both:
        peer_time = statistics.median(f.seconds for f in theirs[:both])
        ratio = f"{peer_time / statistics.median(f.seconds for f in ours[:both]):.1f}x"
    print(
        f"{'method':<28s} {'fits':>5s} {'median s':>9s} {'ratio error':>12s} {'err/SE':>9s} "
        f"{'axis deg':>10s} {'bias error':>11s} {'misses':>6s} {'peer/tumble':>12s}"
    )
    print(row("tumble.identify", ours, noise, "").rstrip())
    if theirs:
        print(row("solve_ivp in least_squares", theirs, noise, ratio))
    print(
        f"{'seed':>4s} {'tumble s':>8s} {'ratio err':>9s} {'err/SE':>7s} {'axis deg':>8s} "
        f"{'':>5s} {'peer s':>8s} {'ratio err':>9s} {'err/SE':>7s} {'axis deg':>8s}"
    )
    for seed, fit in enumerate(ours):
        peer = theirs[seed] if seed < len(theirs) else None
        print(f"{detail(f'{seed:4d}', fit, noise)} {detail('', peer, noise)}".rstrip())

    median = statistics.median(f.seconds for f in ours)
    missed = [f for f in ours if f.missed(noise)]
    met = median <= GOAL and not missed
    note = f"tumble's median {median:.3f} s"
    if missed:
        note += (
            f"; {len(missed)} of {len(ours)} fits missed the motion (residual rms up to "
            f"{max(f.residual_rms for f in missed):.3g} rad/s against σ {noise:g}) after "
            f"{max(f.seconds for f in missed):.1f} s"
        )
    print(f"goal ≤ {GOAL:g} s: {'met' if met else 'NOT met'} ({note})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--seeds", type=int, default=3, help="torque-free fits (default 3)")
    parser.add_argument("--peer-seeds", type=int, default=1, help="of them by the peer (1)")
    identify_drag.add_arguments(parser)
    parser.add_argument(
        "--parts", default="free,drag", help="free (torque-free), drag (singles and joint)"
    )
    args = parser.parse_args()
    parts = set(args.parts.split(","))
    if not parts <= {"free", "drag"}:
        parser.error(f"Expected --parts of free and drag, got {args.parts!r}.")
    print(describe({"scipy": scipy.__version__}))
    start = time.perf_counter()
    if "free" in parts:
        torque_free(args.seeds, args.peer_seeds)
    if "drag" in parts:
        print()
        identify_drag.run(args.singles, args.joint_seeds, args.throws)
    print(f"\n{time.perf_counter() - start:.0f} s in all")


if __name__ == "__main__":
    main()
