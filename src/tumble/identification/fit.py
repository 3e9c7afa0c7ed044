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
import re
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from tumble.core import drag_model, rate_model
from tumble.errors import InputError
from tumble.identification.decimation import averaged
from tumble.identification.flight import free_flight, noise_level
from tumble.identification.result import TORQUE_MODELS, BodyFit
from tumble.identification.start import linear_start, smoothed
from tumble.identification.torque_fit import fit_torque_model
from tumble.identification.torque_values import fits_torque_model
from tumble.identification.validation import (
    MAX_RATIO_ERROR,
    MIN_RATIO,
    MIN_SAMPLES,
    biases_within_rates,
    canonical,
    check_bias,
    check_determined,
    check_loss,
    check_miss,
    check_motion,
    check_torque,
    flag,
    looks_like_noise,
    samples,
    symmetric_within_errors,
    window_bounds,
)
from tumble.resources import check_memory
from tumble.theory import flip_period

__all__ = ["identify"]

Array = NDArray[np.float64]

#: Starts of the ratios tried when the fit from the linear start leaves residuals
#: well above the noise: points of the triangle r1 ≤ r2 ≤ 1 ≤ r1 + r2.
RATIO_STARTS = ((0.3, 0.8), (0.5, 0.6), (0.45, 0.9), (0.7, 0.85), (0.15, 0.95), (0.6, 0.95))

#: The difference of the Bayesian information criterion that counts as decisive evidence
#: for a torque over the torque-free body (Kass & Raftery, J. Am. Stat. Assoc. 90 (1995):
#: "very strong" beyond 10).
DECISIVE = 10.0

#: Why ``torque="auto"`` keeps a body torque-free.
FREE_CHOICE = "torque-free: its residuals look like the noise"

#: A refusal of a fit for its residuals: the models with a torque may fit instead.
MISSED = re.compile(r"to follow a .*?, got residuals of ([0-9.e+-]+) rad/s")

#: The best torque-free results of the search a drag is searched from.
DRAG_STARTS = 3

#: Samples a start of the fit is tried on (:func:`_fit`).
START_SAMPLES = 1000

#: Bytes a fit takes for each sample fitted, with a margin: the Jacobian's 33
#: numbers (three rates by 11 parameters) in several copies at once (the
#: solver's, its scaled one, the SVD of the check of what it determines) and the
#: residuals; the peak memory of fits of 10 000 and 20 000 samples grew by 1.9 kB
#: a sample.
FIT_BYTES = 2500


# ------------------------------------------------------------------ the model
def _unpack(x: Array, frame: Array, with_bias: bool) -> tuple[Array, Array, Array, Array, Array]:
    """The moments, principal axes, ω0, bias and drag coefficients (empty without a
    torque) of the parameters ``x`` (see :func:`tumble.core.rate_model.rate_residuals`
    and :func:`tumble.core.drag_model.drag_residuals`)."""
    moments, axes = rate_model.moments_and_axes(x, np.ascontiguousarray(frame))
    bias = x[8:11] if with_bias else np.zeros(3)
    return moments, axes, x[5:8], bias, x[11 if with_bias else 8 :]


def _solve(
    x0: Array,
    frame: Array,
    times: Array,
    measured: Array,
    with_bias: bool,
    loss: str,
    tight: bool,
    noise: float,
    torque: str = "free",
) -> Any:
    """Least squares from ``x0``: Levenberg–Marquardt (MINPACK) for the plain loss,
    the trust-region method for a robust one, whose residuals count in full up to
    3 σ of the noise (``f_scale``) and less beyond. The ratios are fitted as their
    logarithms, so they stay positive without bounds. With a drag ``torque`` the
    model is stepped (:mod:`tumble.core.drag_model`), its Jacobian compiled."""
    # The robust losses' trust region does not reach 1e-13: 1e-10 is far below
    # the errors of any fit with noise.
    tolerance = (1e-13 if loss == "linear" else 1e-10) if tight else 1e-9
    # Evaluations a parameter: a start is only a start, and the robust losses'
    # steps crawl near the end, long after the answer has stopped changing.
    budget = 200 if tight and loss == "linear" else (40 if torque == "free" else 25)
    # Contiguous once here, not at each of the many evaluations.
    args: tuple[Any, ...] = (
        np.ascontiguousarray(frame),
        np.ascontiguousarray(times),
        np.ascontiguousarray(measured),
        with_bias,
    )
    model: dict[str, Any] = {"fun": rate_model.rate_residuals, "jac": rate_model.rate_jacobian}
    if torque != "free":
        args += (torque == "quadratic-drag",)
        model = {"fun": drag_model.drag_residuals, "jac": drag_model.drag_jacobian}
    with np.errstate(over="ignore"):  # a step far off overflows its cost: it is rejected
        return least_squares(
            x0=x0,
            args=args,
            **model,
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


# ------------------------------------------------------------------ the fit
def identify(
    t: Any,
    omega: Any,
    *,
    window: Any = None,
    bias: bool = True,
    loss: str = "linear",
    torque: str = "auto",
) -> BodyFit:
    """Fit a rigid body, torque-free or under air drag, to measured angular velocity.

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
    torque : the torque the body flew under: ``"free"`` (the exact torque-free
        motion), ``"drag"`` (linear air drag per principal axis, τ_i = −c_i ω_i:
        tumble.torques.AxisDrag), ``"quadratic-drag"`` (τ_i = −c_i ω_i |ω_i|:
        QuadraticDrag; either class, or a model of it), or ``"auto"``: torque-free when
        its residuals look like the noise, else the model of the three with the least
        Bayesian information criterion (``BodyFit.choice`` says why). A drag is stepped
        (classical Runge–Kutta, :mod:`tumble.core.drag_model`) and fits c_i / I3 too.
        Or any torque model of ω and time (of tumble.torques, or a UserTorque): its
        values start its parameters, fitted for a body of I3 = 1 kg·m²
        (``BodyFit.torque_model``), from the ``"auto"`` fit's body and motion.

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
    if fits_torque_model(torque):  # from the start of the best of the built-in models
        best = identify(t, omega, window=window, bias=bias, loss=loss)
        return fit_torque_model(best, torque, loss)
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
    torque = check_torque(torque)
    window_times, window_rates = times[inside], rates[inside]
    if automatic and torque == "auto":
        # The window found may hold a few samples of the hand: the torque-free fit
        # narrows it first (below), and the torque is chosen on what is left.
        try:
            fit = _fit(window_times, window_rates, noise, bias, loss, note, "free")
        except InputError as error:
            if MISSED.search(str(error)) is None:
                raise
            fit = _fit_torque(window_times, window_rates, noise, bias, loss, note, torque)
    else:
        fit = _fit_torque(window_times, window_rates, noise, bias, loss, note, torque)
    if automatic:
        # The rule of free_flight can keep the last samples of a throw (a fast
        # spin-up ends with |ω|² above |ω̇|); the samples the fitted free motion
        # misses by far more than the noise are cut from the ends, and the rest
        # fitted again.
        misses = np.linalg.norm(fit.residuals, axis=1) > 5.0 * np.sqrt(3.0) * noise
        kept = np.flatnonzero(~misses)
        first, last = (kept[0], kept[-1]) if kept.size else (0, misses.size - 1)
        if (first > 0 or last < misses.size - 1) and last - first + 1 >= MIN_SAMPLES:
            chosen, choice = fit.torque, fit.choice
            if torque == "auto" and fit.choice == "as asked":
                chosen = "auto"  # the narrowed window's torque is chosen now
            kept_times, kept_rates = fit.t[first : last + 1], fit.measured[first : last + 1]
            fit = _fit_torque(kept_times, kept_rates, noise, bias, loss, note, chosen)
            if chosen != "auto":
                fit = replace(fit, choice=choice)
        elif torque == "auto" and fit.choice == "as asked":
            if looks_like_noise(fit.residuals, noise, float(np.abs(fit.measured).max())):
                fit = replace(fit, choice=FREE_CHOICE)
            else:
                fit = _fit_torque(fit.t, fit.measured, noise, bias, loss, note, "auto")
    return fit


def _fit_torque(
    times: Array, rates: Array, noise: float, bias: bool, loss: str, note: str, torque: str
) -> BodyFit:
    """The fit with the torque model asked for, or chosen (``"auto"``): torque-free when
    its residuals look like the noise; else, of the models that fit, the one of least
    Bayesian information criterion ``N ln(RSS/N) + k ln N`` (N residuals, k parameters:
    three more for a drag), which asks a drag to pay for its coefficients. Refused only
    when no model fits, naming each with its residual or its refusal."""
    if torque != "auto":
        return _fit(times, rates, noise, bias, loss, note, torque)
    fits: dict[str, BodyFit] = {}
    refusals: dict[str, str] = {}
    hint = ""  # what the torque-free fit's refusal adds about the rates
    for model in TORQUE_MODELS:
        # Quadratic drag starts from the linear drag's fit, when there is one: a model
        # that does not fit the samples would otherwise be searched from every start.
        start_from = fits.get("drag") if model == "quadratic-drag" else None
        try:
            fits[model] = _fit(times, rates, noise, bias, loss, note, model, start_from)
        except InputError as error:
            missed = MISSED.search(str(error))
            if model == "free" and missed is None:
                raise  # not a motion a torque could explain: the rates, their unit, a spin
            if model == "free":
                hint = str(error).partition("is the window all free flight?")[2]
            refusals[model] = (
                f"residuals of {missed.group(1)} rad/s" if missed else str(error).rstrip(".")
            )
            if missed and float(missed.group(1)) >= 0.1 * drag_model.GIVEN_UP:
                refusals[model] = "no motion found (every drag tried ran away)"
        if model == "free" and model in fits:
            scale = float(np.abs(rates).max())
            if looks_like_noise(fits[model].residuals, noise, scale):
                return replace(fits[model], choice=FREE_CHOICE)
    if not fits:
        tried = "; ".join(f"{model}: {reason}" for model, reason in refusals.items())
        raise InputError(
            f"Expected a window that one of the torque models fits, got none, against noise of "
            f"{noise:.3g} rad/s: {tried}: is the window all free flight?{hint}"
        )
    criteria = {model: fit.information_criterion for model, fit in fits.items()}
    chosen = min(criteria, key=lambda model: criteria[model])
    if "free" in fits and criteria["free"] - criteria[chosen] <= DECISIVE:
        chosen = "free"  # a torque is chosen only on decisive evidence
    said = ", ".join(
        f"{model} {criteria[model]:.1f} (residual {fit.residual_rms:.3g} rad/s)"
        for model, fit in fits.items()
    )
    refused = "".join(f"; {model} refused" for model in refusals)
    rule = "the least" if chosen != "free" else "no decisive (by more than 10) gain over the"
    choice = (
        f"{chosen}: {rule} Bayesian information criterion of {said}{refused}, "
        f"against noise {noise:.3g} rad/s"
    )
    return replace(fits[chosen], choice=choice)


def _start_of(fit: BodyFit, torque: str, bias: bool) -> Array:
    """The parameters of a fit of the same samples as the start of a fit with ``torque``:
    its body, motion and bias; a linear drag's coefficients k turned into a quadratic
    one's as k / ⟨|ω_i|⟩ (the same mean torque), and none where the fit had none."""
    drag = np.zeros(0 if torque == "free" else 3)
    if torque != "free" and fit.torque != "free":
        drag = np.array(fit.torque_parameters, dtype=float)
        if torque == "quadratic-drag" and fit.torque == "drag":
            mean_rates = np.abs(fit.principal_rates(fit.t)).mean(axis=0)
            drag = drag / np.maximum(mean_rates, 1e-12)
    offset = fit.bias if bias else np.zeros(0)
    ratios = np.log(fit.moment_ratios)
    return np.concatenate([ratios, np.zeros(3), fit.omega0, offset, drag])


def _starts(
    rates: Array, smooth: Array, derivative: Array, bias: bool
) -> list[tuple[Array, Array]]:
    """The torque-free starts (parameters, the frame their rotation turns): the
    linear start (:func:`linear_start`) and a grid of ratios, each in the linear
    start's axes and in those of the second moments of the samples (a motion near
    the separatrix dwells along the middle axis)."""
    moments, frame, first = linear_start(smooth, derivative)
    _, spread = np.linalg.eigh(rates.T @ rates)
    spread[:, 0] *= np.linalg.det(spread)
    guesses = [(moments[:2], frame)] + [
        (np.array(r), axes) for axes in (frame, spread) for r in RATIO_STARTS
    ]
    offset = np.zeros(3 if bias else 0)
    return [
        (np.concatenate([np.log(ratios), np.zeros(3), axes.T @ first, offset]), axes)
        for ratios, axes in guesses
    ]


@dataclass(frozen=True)
class _Samples:
    """The samples the starts are searched on (times from the window's start, s, and
    rates, rad/s), the fit's bias flag and noise, and the largest rate."""

    times: Array
    rates: Array
    bias: bool
    noise: float
    largest: float

    def search(
        self, starts: list[tuple[Array, Array]], loss: str, torque: str, spans: bool = True
    ) -> list[tuple[Any, Array]]:
        """Each start searched (on growing spans of the samples with ``spans``), until
        one leaves residuals like the noise; the results with their frames, least cost
        first."""
        count = len(self.times)
        lengths = [n for n in (count // 8, count // 4, count // 2) if n >= 3 * MIN_SAMPLES]
        lengths = [*lengths, count] if spans else [count]
        found = []
        for x, axes in starts:
            for n in lengths:
                result = _solve(
                    x,
                    axes,
                    self.times[:n],
                    self.rates[:n],
                    self.bias,
                    loss,
                    False,
                    self.noise,
                    torque,
                )
                x = result.x
            found.append((result, axes))
            if looks_like_noise(result.fun.reshape(-1, 3), self.noise, self.largest):
                break  # residuals like the noise: the other starts are for a miss
        return sorted(found, key=lambda pair: pair[0].cost)


def _polish(
    best: Any,
    frame: Array,
    times: Array,
    rates: Array,
    bias: bool,
    loss: str,
    noise: float,
    torque: str,
) -> tuple[Any, Array, Array, Array, Array, Array]:
    """The best search polished on all the samples in the canonical frame, from which
    the covariance is read: the solver's result, the moments, axes, ω0, bias and drag
    coefficients (each with its axis)."""
    moments, axes, omega0, offset, drag = _canonical_parameters(best.x, frame, bias)
    x = np.concatenate([np.log(moments[:2]), np.zeros(3), omega0, offset if bias else [], drag])
    final = _solve(x, axes, times, rates, bias, loss, tight=True, noise=noise, torque=torque)
    return final, *_canonical_parameters(final.x, axes, bias)


def _canonical_parameters(
    x: Array, frame: Array, bias: bool
) -> tuple[Array, Array, Array, Array, Array]:
    """The moments, axes and ω0 of the parameters ``x`` in the canonical frame
    (:func:`canonical`), with the bias and the drag coefficients, each with its axis."""
    body, axes, omega0, offset, drag = _unpack(x, frame, bias)
    if drag.size:
        drag = drag[np.argsort(body, kind="stable")]  # each coefficient with its axis
    moments, axes, omega0 = canonical(body, axes, omega0)
    return moments, axes, omega0, offset, drag


def _covariance(final: Any, moments: Array, size: int, bias: bool) -> tuple[Array, Array]:
    """The covariance of the parameters (the ratios themselves, not their logarithms)
    from the residuals of ``size`` numbers and the Jacobian, and the ratios' standard
    errors; refused when they do not determine the ratios."""
    if moments[0] < MIN_RATIO:
        raise InputError(
            "Expected a recording that determines the moment ratios, got a fit that ran to a "
            f"degenerate body (I1/I3 = {moments[0]:.3g}, below {MIN_RATIO:g}): the motion "
            "shows too little of the body (a longer free flight, or a throw further from a "
            "principal axis, would)."
        )
    dof = max(size - final.x.size, 1)
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
    if bias and symmetric_within_errors(moments[:2], covariance):
        raise InputError(
            "Expected a recording that determines the moment ratios, got a body symmetric "
            f"within its errors (I1/I3 = {moments[0]:.5g}, I2/I3 = {moments[1]:.5g}): with a "
            "bias, a symmetric body's ratios trade off against it (fit with bias=False if "
            "the sensor has none, or take the bias from a recording at rest)."
        )
    return covariance, errors


def _fit(
    times: Array,
    rates: Array,
    noise: float,
    bias: bool,
    loss: str,
    note: str = "",
    torque: str = "free",
    start_from: BodyFit | None = None,
) -> BodyFit:
    """The fit of the samples of one window with one torque model (see
    :func:`tumble.identify`); from the starts of the linear start and of a grid of
    ratios, or only from the body, motion, bias (and drag) of ``start_from`` (a fit of
    the same samples with another torque model)."""
    start = float(times[0])
    relative = times - start
    check_motion(rates, noise)
    smooth, derivative = smoothed(relative, rates)
    # The starts are tried on at most START_SAMPLES of the samples, evenly spread
    # (the answer is polished on all of them below), and on growing spans of
    # them: over many flips a small error of ω0 shifts the late flips by whole
    # turns, and a fit from there can settle far away; a short span fixes ω0 first.
    every = max(1, len(times) // START_SAMPLES)
    some = _Samples(relative[::every], rates[::every], bias, noise, float(np.abs(rates).max()))
    # The starts are searched with soft_l1 where a robust loss is asked for: it
    # resists outliers as well, and its trust region converges where a
    # redescending loss (cauchy, arctan) crawls from a poor start, for minutes,
    # to a body off by several of its errors; the chosen loss polishes the best.
    search = "linear" if loss == "linear" else "soft_l1"
    # Each start is searched torque-free (exact, fast, and unable to run off into a
    # drag that decays faster than the samples); a drag is then searched from the best
    # few torque-free results, the coefficients from none: the decay the torque-free
    # body leaves over takes them from zero in a few steps. A fit of another model
    # starts the drag directly.
    if start_from is None:
        found = some.search(_starts(rates, smooth, derivative, bias), search, "free")
    else:
        starts = [(_start_of(start_from, torque, bias), start_from.axes)]
        found = some.search(starts, search, torque)
    if torque != "free" and start_from is None:
        if bias:
            biases = np.array([result.x[8:11] for result, _ in found])
            within = biases_within_rates(biases, rates, smooth, derivative)
            found = [pair for pair, keep in zip(found, within, strict=True) if keep]
        drag_starts = [(np.concatenate([r.x, np.zeros(3)]), axes) for r, axes in found]
        found = some.search(drag_starts[:DRAG_STARTS], search, torque, spans=False)
    final, moments, axes, omega0, offset, drag = _polish(
        *found[0], relative, rates, bias, loss, noise, torque
    )
    check_miss(final.fun, noise, times, rates, smooth, derivative, torque)
    # A body matched the samples, but no sensor reads mostly its own offset: a bias
    # beyond the rates is a unit error (whatever else the fit leaves undetermined).
    check_bias(offset, rates)
    check_determined(final.jac, bias)
    covariance, errors = _covariance(final, moments, rates.size, bias)
    ratios = moments[:2]
    return BodyFit(
        moment_ratios=ratios,
        uncertainty=errors,
        axes=axes,
        omega0=omega0,
        bias=offset,
        covariance=covariance,
        residual_rms=float(np.sqrt(np.mean(final.fun**2))),
        # Of the nearest physical body where noise puts the ratios just outside
        # the triangle inequality (a flat plate has I1 + I2 = I3).
        flip_period=flip_period([max(ratios[0], 1.0 - ratios[1]), ratios[1], 1.0], omega0),
        window=(start, float(times[-1])),
        t=times,
        measured=rates,
        noise=noise,
        note=note,
        torque=torque,
        torque_parameters=drag,
        torque_uncertainty=np.sqrt(np.abs(np.diag(covariance)[covariance.shape[0] - drag.size :])),
    )
