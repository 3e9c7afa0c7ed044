"""The torque-free motion fitted to measured body rates: :func:`tumble.identify`.

The model of a sample is ``ω_measured(t) = R ω(t − t0) + b + noise``: ω(t) the
exact torque-free angular velocity in the principal frame
(:func:`tumble.core.freebody.free_omega`, Jacobi elliptic functions, so the model
has no integration error), of a body with moments ``(r1, r2, 1)`` (only their
ratios show in ω(t)) and ω(t0) = ``omega0``; R the principal axes as columns in
the sensor's axes; b the sensor's bias. The 11 parameters (8 without a bias) are
fitted by nonlinear least squares (``scipy.optimize.least_squares``), from a
start that needs no guess (:func:`~tumble.identification.start.linear_start`),
in the manner of the estimation of inertia ratios from coasting telemetry
(Bergmann, Walker & Levy, J. Guid. Control Dyn. 10 (1987); Tanygin & Williams,
J. Guid. Control Dyn. 20 (1997)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from tumble.core import rate_model
from tumble.errors import InputError
from tumble.identification.checks import (
    MIN_SAMPLES,
    breaks_free_body,
    check_bias,
    check_loss,
    check_motion,
    flag,
    free_body_ratio,
    samples,
    window_bounds,
)
from tumble.identification.decimation import averaged
from tumble.identification.flight import free_flight, noise_level
from tumble.identification.start import linear_start, smoothed
from tumble.resources import check_memory
from tumble.theory import flip_period

__all__ = ["BodyFit", "identify", "principal_rates"]

Array = NDArray[np.float64]

#: The most a ratio's standard error may be for the ratios to count as
#: identified: beyond it the recording does not determine them.
MAX_RATIO_ERROR = 0.05

#: The smallest I1/I3 a fit returns: below it the fit has run to the limit of a
#: line of mass, where ω along it is not determined (no real body comes close).
MIN_RATIO = 1e-4

#: The most the residuals of a fit may be, in noise levels: beyond it no
#: torque-free body matched the samples (a hand or an impact in the window, or a
#: start from which the fit did not find the motion).
MAX_MISS = 10.0

#: Starts of the ratios tried when the fit from the linear start leaves residuals
#: well above the noise: points of the triangle r1 ≤ r2 ≤ 1 ≤ r1 + r2.
RATIO_STARTS = ((0.3, 0.8), (0.5, 0.6), (0.45, 0.9), (0.7, 0.85), (0.15, 0.95), (0.6, 0.95))

#: Samples a start of the fit is tried on (:func:`_fit`).
START_SAMPLES = 1000

#: Bytes a fit takes for each sample fitted, with a margin: the Jacobian's 33
#: numbers (three rates by 11 parameters) in several copies at once (the
#: solver's, its scaled one, the SVD of the check of what it determines) and the
#: residuals; the peak memory of fits of 10 000 and 20 000 samples grew by 1.9 kB
#: a sample.
FIT_BYTES = 2500

#: Lags of the residuals' autocorrelation that tell a miss from noise (:func:`_fits`).
LAGS = 10

PARAMETERS = ("r1", "r2", "rx", "ry", "rz", "w1", "w2", "w3", "bx", "by", "bz")


@dataclass(frozen=True, eq=False)
class BodyFit:
    """A body and its motion, fitted to measured rates by :func:`tumble.identify`.

    Attributes
    ----------
    moment_ratios : (2,) ``(I1/I3, I2/I3)``, principal moments ascending.
    uncertainty : (2,) standard errors of ``moment_ratios``.
    axes : (3, 3) principal axes as columns, in the sensor's axes (a proper
        rotation: the sensor's axes → principal axes is its transpose).
    omega0 : (3,) angular velocity at ``window[0]`` in the principal axes, rad/s.
    bias : (3,) sensor bias in the sensor's axes, rad/s (zeros if not fitted).
    covariance : (k, k) covariance of the parameters :data:`PARAMETERS` (the
        first 8 without a bias): the ratios, a small rotation of the axes (rad,
        about the fitted principal axes), ``omega0`` (rad/s) and the bias (rad/s).
    residual_rms : root-mean-square of the residuals, rad/s (the sensor's noise
        when the model fits).
    flip_period : period of ω(t) of the fitted body, s
        (:func:`tumble.theory.flip_period`): near the intermediate axis the body
        flips twice in it; ``inf`` on the separatrix.
    window : (start, end) of the samples fitted, s.
    t, measured : the samples fitted, s and rad/s (sensor's axes): block means
        of the samples given when they were averaged (see ``note``).
    noise : the noise σ of the samples fitted, rad/s per component (of the
        samples given over √k when k were averaged at a time).
    note : what was done to the samples before the fit, one sentence (a
        recording sampled far faster than its motion needs is averaged to
        fewer samples); "" when nothing was.
    """

    moment_ratios: Array
    uncertainty: Array
    axes: Array
    omega0: Array
    bias: Array
    covariance: Array
    residual_rms: float
    flip_period: float
    window: tuple[float, float]
    t: Array
    measured: Array
    noise: float = 0.0
    note: str = ""

    def principal_rates(self, t: Any) -> Array:
        """(n, 3) the fitted body's ω at times ``t`` (s), principal axes, rad/s."""
        times = np.asarray(t, dtype=float) - self.window[0]
        return principal_rates(np.array([*self.moment_ratios, 1.0]), self.omega0, times)

    def predicted(self, t: Any) -> Array:
        """(n, 3) the fitted measurement at times ``t`` (s): ω in the sensor's axes
        plus the bias, rad/s."""
        return np.asarray(self.principal_rates(t) @ self.axes.T + self.bias)

    @property
    def residuals(self) -> Array:
        """(n, 3) measured − fitted, rad/s, at the times ``t``."""
        return np.asarray(self.measured - self.predicted(self.t))

    def __repr__(self) -> str:
        r, e = self.moment_ratios, self.uncertainty
        return (
            f"BodyFit(I1/I3={r[0]:.5f} ± {e[0]:.1e}, I2/I3={r[1]:.5f} ± {e[1]:.1e}, "
            f"flip_period={self.flip_period:.4g} s, residual_rms={self.residual_rms:.3g} rad/s, "
            f"{len(self.t)} samples in {self.window[0]:.4g}–{self.window[1]:.4g} s)"
        )


def principal_rates(moments: Array, omega0: Array, times: Array) -> Array:
    """(n, 3) exact torque-free ω(t) in the principal frame for moments in any
    order (all > 0), ω(0) = ``omega0``: see
    :func:`tumble.core.rate_model.principal_rates`."""
    return np.asarray(
        rate_model.principal_rates(
            np.asarray(moments, dtype=float),
            np.asarray(omega0, dtype=float),
            np.ascontiguousarray(times, dtype=float),
        )
    )


# ------------------------------------------------------------------ the model
def _unpack(x: Array, frame: Array, with_bias: bool) -> tuple[Array, Array, Array, Array]:
    """The moments, principal axes, ω0 and bias of the parameters ``x`` (see
    :func:`tumble.core.rate_model.rate_residuals`)."""
    moments, axes = rate_model.moments_and_axes(x, np.ascontiguousarray(frame))
    bias = x[8:11] if with_bias else np.zeros(3)
    return moments, axes, x[5:8], bias


def _solve(
    x0: Array,
    frame: Array,
    times: Array,
    measured: Array,
    with_bias: bool,
    loss: str,
    tight: bool,
    noise: float,
) -> Any:
    """Least squares from ``x0``: Levenberg–Marquardt (MINPACK) for the plain loss,
    the trust-region method for a robust one, whose residuals count in full up to
    3 σ of the noise (``f_scale``) and less beyond. The ratios are fitted as their
    logarithms, so they stay positive without bounds."""
    # The robust losses' trust region does not reach 1e-13: 1e-10 is far below
    # the errors of any fit with noise.
    tolerance = (1e-13 if loss == "linear" else 1e-10) if tight else 1e-9
    # Evaluations a parameter: a start is only a start, and the robust losses'
    # steps crawl near the end, long after the answer has stopped changing.
    budget = 200 if tight and loss == "linear" else 40
    return least_squares(
        rate_model.rate_residuals,
        x0,
        # Contiguous once here, not at each of the many evaluations.
        args=(
            np.ascontiguousarray(frame),
            np.ascontiguousarray(times),
            np.ascontiguousarray(measured),
            with_bias,
        ),
        method="lm" if loss == "linear" else "trf",
        # For trf: LSMR, not a dense SVD of the (3n, 11) Jacobian at every step.
        **({} if loss == "linear" else {"tr_solver": "lsmr"}),
        loss=loss,
        f_scale=max(3.0 * noise, 1e-12 * float(np.abs(measured).max())),
        x_scale="jac",
        ftol=tolerance,
        xtol=tolerance,
        gtol=tolerance,
        max_nfev=budget * x0.size,
    )


def _canonical(moments: Array, axes: Array, omega0: Array) -> tuple[Array, Array, Array]:
    """The same body with moments ascending and scaled to the largest, axes a
    proper rotation with a fixed choice of signs, and ω0 in those axes."""
    order = np.argsort(moments, kind="stable")
    axes = axes[:, order]
    omega0 = omega0[order]
    # Signs: each of the first two axes has its largest component positive; the
    # third completes a right-handed frame (ω0 follows each flip).
    for k in range(2):
        if axes[np.argmax(np.abs(axes[:, k])), k] < 0:
            axes[:, k] *= -1.0
            omega0[k] *= -1.0
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1.0
        omega0[2] *= -1.0
    return moments[order] / moments[order][2], axes, omega0


# ------------------------------------------------------------------ the fit
def identify(
    t: Any,
    omega: Any,
    *,
    window: Any = None,
    bias: bool = True,
    loss: str = "linear",
) -> BodyFit:
    """Fit a torque-free rigid body to measured angular velocity.

    Parameters
    ----------
    t : (n,) sample times, s, increasing (the spacing may vary); or a pint
        quantity of times (of any registry: ms, µs, ...).
    omega : (n, 3) measured angular velocity in the sensor's axes, rad/s (a
        gyroscope fixed to the body; its axes need not be principal); or a
        pint quantity of rates (deg/s, turn/s, rpm, ...).
    window : (start, end) in s, the free flight to fit; None to find it
        (:func:`tumble.identification.free_flight`).
    bias : True or False: fit a constant sensor bias (3 more parameters).
    loss : ``"linear"`` (least squares) or a robust loss of
        ``scipy.optimize.least_squares`` (``"soft_l1"``, ``"huber"``,
        ``"cauchy"``, ``"arctan"``) for recordings with outliers; the covariance
        then holds only roughly.

    Returns
    -------
    BodyFit: the moment ratios with their standard errors, the principal axes
    in the sensor's axes, ω0, the bias, the covariance of the parameters (from
    the Jacobian at the solution and the residuals' variance), the residual and
    the flip period.

    Raises
    ------
    InputError
        For too few samples, values that are not finite, times that do not
        increase, quantities that are not times or rates, a recording with no
        free flight, rates no torque-free body shows (``|dω/dt| > |ω|²/√3``:
        rates too small for their motion, as rates in deg/s read as rad/s are),
        or one that does not determine the ratios (a spin about one principal
        axis stays constant and shows none).
    tumble.errors.RequestTooLargeError
        For a window of more samples than the memory budget
        (:mod:`tumble.resources`) can fit.

    Notes
    -----
    With ``window=None`` the window of :func:`tumble.identification.free_flight`
    is fitted, then narrowed to the samples the fitted motion matches within 5
    times the noise, and fitted again. The fit starts from Euler's equations
    solved for the tensor (no guess), and tries further starts when the residuals
    do not look like the noise. A recording sampled far faster than its motion
    needs (more than 20,000 samples to fit) is averaged in blocks of consecutive
    samples first, each block turning by at most 0.01 rad: ``note`` says so. A
    recording must show the motion the ratios shape:
    within a hair of the separatrix (ω along the middle axis to 1e-3) a window
    holding a single flip can be matched about equally well by other bodies, and
    the fit may settle on one of them.
    """
    bias = flag(bias, "bias")
    loss = check_loss(loss)
    times, rates = samples(t, omega)
    automatic = window is None
    given = None if automatic else window_bounds(window, times)
    noise = noise_level(times, rates)
    times, rates, block, note = averaged(times, rates, given)
    noise /= math.sqrt(block)  # white noise, averaged over blocks of that many samples
    start, end = free_flight(times, rates) if given is None else given
    inside = (times >= start) & (times <= end)
    count = int(inside.sum())
    if count < MIN_SAMPLES:
        raise InputError(
            f"Expected at least {MIN_SAMPLES} samples in the window {start:.6g}–{end:.6g} s, "
            f"got {count}."
        )
    check_memory(
        count * FIT_BYTES,
        f"a fit of {count} samples",
        "Fit a shorter window (`window=(start, end)`, --window START,END).",
    )
    fit = _fit(times[inside], rates[inside], noise, bias, loss, note)
    if automatic:
        # The rule of free_flight can keep the last samples of a throw (a fast
        # spin-up ends with |ω|² above |ω̇|); the samples the fitted free motion
        # misses by far more than the noise are cut from the ends, and the rest
        # fitted again.
        misses = np.linalg.norm(fit.residuals, axis=1) > 5.0 * np.sqrt(3.0) * noise
        kept = np.flatnonzero(~misses)
        first, last = (kept[0], kept[-1]) if kept.size else (0, misses.size - 1)
        if (first > 0 or last < misses.size - 1) and last - first + 1 >= MIN_SAMPLES:
            fit = _fit(
                fit.t[first : last + 1], fit.measured[first : last + 1], noise, bias, loss, note
            )
    return fit


def _fit(
    times: Array, rates: Array, noise: float, bias: bool, loss: str, note: str = ""
) -> BodyFit:
    """The fit of the samples of one window (see :func:`tumble.identify`)."""
    start = float(times[0])
    relative = times - start
    check_motion(rates, noise)

    smooth, derivative = smoothed(relative, rates)
    moments, frame, first = linear_start(smooth, derivative)
    # A second guess of the axes: those of the second moments of the samples
    # (a motion near the separatrix dwells along the middle axis).
    _, spread = np.linalg.eigh(rates.T @ rates)
    spread[:, 0] *= np.linalg.det(spread)
    starts = [(moments[:2], frame)] + [
        (np.array(r), axes) for axes in (frame, spread) for r in RATIO_STARTS
    ]
    # The starts are tried on at most START_SAMPLES of the samples, evenly spread
    # (the answer is polished on all of them below), and on growing spans of
    # them: over many flips a small error of ω0 shifts the late flips by whole
    # turns, and a fit from there can settle far away; a short span fixes ω0 first.
    every = max(1, len(times) // START_SAMPLES)
    some_times, some_rates = relative[::every], rates[::every]
    spans = [n for n in (len(some_times) // 8, len(some_times) // 4, len(some_times) // 2)
             if n >= 3 * MIN_SAMPLES] + [len(some_times)]  # fmt: skip
    # The starts are searched with soft_l1 where a robust loss is asked for: it
    # resists outliers as well, and its trust region converges where a
    # redescending loss (cauchy, arctan) crawls from a poor start, for minutes,
    # to a body off by several of its errors; the chosen loss polishes the best.
    search = "linear" if loss == "linear" else "soft_l1"
    best = None
    for ratios, axes in starts:
        x = np.concatenate(
            [np.log(ratios), np.zeros(3), axes.T @ first, np.zeros(3 if bias else 0)]
        )
        for n in spans:
            result = _solve(x, axes, some_times[:n], some_rates[:n], bias, search, False, noise)
            x = result.x
        if best is None or result.cost < best.cost:
            best, frame = result, axes
        if _fits(best.fun.reshape(-1, 3), noise, float(np.abs(rates).max())):
            break  # residuals like the noise: the other starts are for a miss
    assert best is not None

    # Polish in the canonical frame, from which the covariance is read.
    body, axes, omega0, offset = _unpack(best.x, frame, bias)
    moments, axes, omega0 = _canonical(body, axes, omega0)
    x = np.concatenate([np.log(moments[:2]), np.zeros(3), omega0, offset if bias else []])
    final = _solve(x, axes, relative, rates, bias, loss, tight=True, noise=noise)
    body, axes, omega0, offset = _unpack(final.x, axes, bias)
    moments, axes, omega0 = _canonical(body, axes, omega0)

    residual = float(np.sqrt(np.mean(final.fun**2)))
    # The typical residual (median-based: a few outliers do not count).
    typical = 1.4826 * float(np.median(np.abs(final.fun)))
    if typical > MAX_MISS * noise and typical > 1e-9 * float(np.abs(rates).max()):
        ratio = free_body_ratio(smooth, derivative)
        also = (
            f" (the rates break |dω/dt| ≤ |ω|²/√3 too, at {ratio:.3g} |ω|²: a hand's torque "
            "does, and so do rates too small for their unit, as deg/s read as rad/s)"
            if breaks_free_body(ratio)
            else ""
        )
        raise InputError(
            f"Expected the samples of {start:.6g}–{times[-1]:.6g} s to follow a torque-free "
            f"motion, got residuals of {typical:.3g} rad/s against noise of {noise:.3g} rad/s "
            f"for the best body found: is the window all free flight?{also}"
        )
    _check_determined(final.jac, bias)
    if moments[0] < MIN_RATIO:
        raise InputError(
            "Expected a recording that determines the moment ratios, got a fit that ran to a "
            f"degenerate body (I1/I3 = {moments[0]:.3g}, below {MIN_RATIO:g}): the motion "
            "shows too little of the body (a longer free flight, or a throw further from a "
            "principal axis, would)."
        )
    dof = max(rates.size - final.x.size, 1)
    variance = 2 * final.cost / dof
    covariance = variance * np.linalg.pinv(final.jac.T @ final.jac, rcond=1e-12, hermitian=True)
    # From the logarithms of the ratios to the ratios: d r = r d(ln r).
    scale = np.ones(final.x.size)
    scale[:2] = moments[:2]
    covariance = covariance * np.outer(scale, scale)
    errors = np.sqrt(np.abs(np.diag(covariance)[:2]))
    if not np.all(errors < MAX_RATIO_ERROR):
        raise InputError(
            f"Expected a recording that determines the moment ratios, got standard errors "
            f"{errors[0]:.3g} and {errors[1]:.3g} (above {MAX_RATIO_ERROR}): the motion shows "
            "too little of the body (a longer free flight, or a throw further from a "
            "principal axis, would)."
        )
    # A torque-free body matched the samples and determines the ratios, but no
    # sensor reads mostly its own offset: a bias beyond the rates is a unit error.
    check_bias(offset, rates)
    if bias and _symmetric(moments[:2], covariance):
        raise InputError(
            "Expected a recording that determines the moment ratios, got a body symmetric "
            f"within its errors (I1/I3 = {moments[0]:.5g}, I2/I3 = {moments[1]:.5g}): with a "
            "bias, a symmetric body's ratios trade off against it (fit with bias=False if "
            "the sensor has none, or take the bias from a recording at rest)."
        )
    ratios = moments[:2]
    return BodyFit(
        moment_ratios=ratios,
        uncertainty=errors,
        axes=axes,
        omega0=omega0,
        bias=offset,
        covariance=covariance,
        residual_rms=residual,
        # Of the nearest physical body where noise puts the ratios just outside
        # the triangle inequality (a flat plate has I1 + I2 = I3).
        flip_period=flip_period([max(ratios[0], 1.0 - ratios[1]), ratios[1], 1.0], omega0),
        window=(start, float(times[-1])),
        t=times,
        measured=rates,
        noise=noise,
        note=note,
    )


def _symmetric(ratios: Array, covariance: Array) -> bool:
    """Whether two of the moments (r1, r2, 1) are equal within 3 standard errors
    of their difference (from the covariance of the ratios)."""
    v11, v22, v12 = covariance[0, 0], covariance[1, 1], covariance[0, 1]
    upper = 1.0 - ratios[1] < 3.0 * np.sqrt(max(v22, 0.0))
    lower = ratios[1] - ratios[0] < 3.0 * np.sqrt(max(v11 + v22 - 2 * v12, 0.0))
    return bool(upper or lower)


def _check_determined(jacobian: Array, bias: bool) -> None:
    """Refuse a fit whose ratios some change of the other parameters can make up
    for exactly: a direction of the parameters (columns scaled to unit norm) the
    Jacobian does not see, with a share of the ratios. (A symmetric body's axes
    about its symmetry axis are such a direction too, but leave the ratios as
    they are: that is not refused.)"""
    norms = np.linalg.norm(jacobian, axis=0)
    norms[norms == 0] = 1.0
    _, values, directions = np.linalg.svd(jacobian / norms, full_matrices=False)
    unseen = directions[values < 1e-8 * values[0]]
    if any(np.linalg.norm(v[:2]) > 0.1 for v in unseen):
        advice = (
            "with a bias, a symmetric body's ratios trade off against it: fit with "
            "bias=False if the sensor has none, or record a less symmetric body"
            if bias
            else "record a longer or less regular motion"
        )
        raise InputError(
            "Expected a recording that determines the moment ratios, got one that other "
            f"ratios reproduce exactly ({advice})."
        )


def _fits(residuals: Array, noise: float, scale: float) -> bool:
    """Whether residuals (n, 3) look like the sensor's noise: about its size, and
    uncorrelated along the samples. A wrong body leaves a smooth pattern,
    correlated over many samples however small it is; the sum of the
    autocorrelations at lags 1 to m of white noise is 0 within √(m/n) (n the
    number of residuals), and a smooth pattern adds about m times its share.
    Outliers (beyond 5 σ√3, impacts and glitches) are left out of the judgement."""
    rms = float(np.sqrt(np.mean(residuals**2)))
    if rms <= 1e-12 * scale:
        return True
    inliers = residuals[np.linalg.norm(residuals, axis=1) <= 5.0 * np.sqrt(3.0) * noise]
    if len(inliers) < 0.9 * len(residuals):
        return False
    residuals = inliers
    rms = float(np.sqrt(np.mean(residuals**2)))
    centred = residuals - residuals.mean(axis=0)
    power = float(np.sum(centred**2))
    lags = min(LAGS, len(centred) // 4)
    correlation = sum(float(np.sum(centred[k:] * centred[:-k])) / power for k in range(1, lags + 1))
    return rms < 1.5 * noise and correlation < 4.0 * np.sqrt(lags / residuals.size)
