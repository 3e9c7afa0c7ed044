"""The validation of what :func:`tumble.identify` is given: the samples, the window
and whether the motion in it can show a body at all."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, quoted, unknown_choice
from tumble.identification.torque_values import why_not_fitted
from tumble.torques import TORQUES, TorqueModel
from tumble.units import pint, vector_to_si

__all__ = [
    "FREE_BODY_BOUND",
    "LAGS",
    "LOSSES",
    "MAX_MISS",
    "MAX_RATIO_ERROR",
    "MIN_RATIO",
    "MIN_SAMPLES",
    "biases_within_rates",
    "breaks_free_body",
    "canonical",
    "check_bias",
    "check_determined",
    "check_loss",
    "check_miss",
    "check_motion",
    "check_torque",
    "flag",
    "free_body_ratio",
    "looks_like_noise",
    "samples",
    "symmetric_within_errors",
    "torque_at_ends",
    "window_bounds",
]

Array = NDArray[np.float64]

#: Fewest samples a fit takes: 11 parameters, and enough beyond them for the
#: residuals to say how good the fit is.
MIN_SAMPLES = 30

#: The losses of ``scipy.optimize.least_squares`` a fit takes.
LOSSES = ("linear", "soft_l1", "huber", "cauchy", "arctan")

#: The most |dω/dt| / |ω|² of a torque-free body. Euler's equations give
#: ``ω̇_i = (I_j − I_k) ω_j ω_k / I_i`` and the triangle inequality of the moments
#: ``|I_j − I_k| ≤ I_i``, so ``ω̇_i² ≤ ω_j² ω_k²``; summed over i,
#: ``|ω̇|² ≤ ω₁²ω₂² + ω₂²ω₃² + ω₃²ω₁² ≤ (ω₁² + ω₂² + ω₃²)² / 3`` (for a, b, c ≥ 0,
#: ab + bc + ca ≤ (a + b + c)²/3, equal when a = b = c). A flat plate ever closer
#: to a rod (I = ε, 1, 1 + ε with ε → 0: all three factors (I_j − I_k)/I_i tend
#: to 1) spinning with ω's three components equal approaches it, so no smaller
#: bound holds for every body.
FREE_BODY_BOUND = 1.0 / math.sqrt(3.0)

#: How far beyond :data:`FREE_BODY_BOUND` the measured ratio may go before a
#: refusal of a window that no body fits says the bound is broken too: the
#: derivative of smoothed noisy samples, and |ω|² of the samples with their
#: bias, are estimates (the shipped recording reaches 0.85 of the bound), while
#: rates in deg/s read as rad/s are 57 times too small.
FREE_BODY_MARGIN = 2.0

#: The share of a window's samples whose |dω/dt| / |ω|² is judged (a high
#: percentile: a few samples spoilt by noise or an impact do not decide).
FREE_BODY_PERCENTILE = 90.0


def _as_array(value: Any, kind: str, name: str, shape: tuple[int, ...]) -> Array:
    """``value`` as a float array in SI: plain numbers as they are (a recording
    holds up to millions, which numpy reads at once), quantities and strings
    converted by :func:`tumble.units.vector_to_si`."""
    if not isinstance(value, str | pint.Quantity):
        try:
            return np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            pass  # quantities among the values, or no numbers at all: said below
    return vector_to_si(value, kind, name, shape)


def samples(t: Any, omega: Any) -> tuple[Array, Array]:
    """``t`` (n,) s and ``omega`` (n, 3) rad/s as float arrays (numbers, or pint
    quantities of any registry, converted), checked: shapes, enough samples,
    finite values, increasing times."""
    times = _as_array(t, "time", "t", (-1,))
    rates = _as_array(omega, "angular_velocity", "omega", (-1, 3))
    if times.ndim != 1 or rates.shape != (times.size, 3):
        raise InputError(
            f"Expected t of shape (n,) and omega of shape (n, 3), got {times.shape} and "
            f"{rates.shape}."
        )
    if times.size < MIN_SAMPLES:
        raise InputError(f"Expected at least {MIN_SAMPLES} samples, got {times.size}.")
    bad = ~np.isfinite(times) | ~np.isfinite(rates).all(axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        count = int(bad.sum())
        which = "1 sample that is not" if count == 1 else f"{count} samples that are not"
        raise InputError(
            f"Expected finite times and rates, got {which} (the first is sample {k}: "
            f"t = {float(times[k])!r}, omega = {rates[k].tolist()})."
        )
    steps = np.diff(times)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0))
        raise InputError(
            f"Expected increasing times, got t[{k + 1}] = {float(times[k + 1])!r} after "
            f"t[{k}] = {float(times[k])!r}."
        )
    return times, rates


def flag(value: Any, name: str) -> bool:
    """``value`` as a bool: True or False only (numpy's too), not a truthy string
    such as ``"no"``."""
    if not isinstance(value, bool | np.bool_):
        raise InputError(f"Expected `{name}` to be True or False, got {quoted(value)}.")
    return bool(value)


def check_torque(torque: Any, name: str = "`torque`") -> str:
    """A torque model of a fit: "auto", "free", "drag" or "quadratic-drag", or the class
    or an instance of the registry's drags of those names (:class:`tumble.torques.AxisDrag`,
    :class:`tumble.torques.QuadraticDrag`: their coefficients are what is fitted). Any
    other torque model is refused (the models of ω and time with parameters that
    :func:`tumble.identify` steps are taken before this check)."""
    choices = ["auto", "free", "drag", "quadratic-drag"]
    if isinstance(torque, str) and torque in choices:
        return torque
    kind = torque if isinstance(torque, type) else type(torque)
    if issubclass(kind, TorqueModel) and kind.name in choices:
        return kind.name
    registered = torque if isinstance(torque, str) else getattr(kind, "name", None)
    if registered in TORQUES or isinstance(torque, TorqueModel):
        raise InputError(
            f"Expected {name} to be one of {', '.join(choices)}, or a model of a torque of "
            f"ω and time with its parameters' starting values, got {torque!r}: "
            f"{why_not_fitted(torque)}."
        )
    raise unknown_choice(torque, choices, name)


def check_loss(loss: Any, name: str = "`loss`") -> str:
    """``loss``, one of :data:`LOSSES` (``name``: how the message calls it)."""
    if not isinstance(loss, str) or loss not in LOSSES:
        raise unknown_choice(loss, LOSSES, name)
    return loss


def window_bounds(window: Any, times: Array) -> tuple[float, float]:
    """``window`` as (start, end), s, checked against the samples' ``times``."""
    try:
        start, end = (float(v) for v in window)
    except (TypeError, ValueError):
        raise InputError(f"Expected `window` to be (start, end) in s, got {window!r}.") from None
    if not (np.isfinite(start) and np.isfinite(end) and start < end):
        raise InputError(f"Expected `window` start < end, both finite, got {window!r}.")
    if end < times[0] or start > times[-1]:
        raise InputError(
            f"Expected `window` to overlap the samples ({times[0]:.6g}–{times[-1]:.6g} s), "
            f"got {start:.6g}–{end:.6g} s."
        )
    return start, end


def check_motion(rates: Array, noise: float) -> None:
    """Refuse a window whose rate stays constant within the noise: a spin about
    a principal axis, which no moment ratio changes."""
    spread = float(np.max(np.linalg.norm(rates - rates.mean(axis=0), axis=1)))
    if spread <= 5 * noise + 1e-12 * float(np.abs(rates).max()):
        raise InputError(
            f"Expected the angular velocity to change in the window, got changes of at most "
            f"{spread:.3g} rad/s against noise of {noise:.3g} rad/s: a steady spin about one "
            "principal axis does not reveal the moment ratios."
        )


def free_body_ratio(smooth: Array, derivative: Array) -> float:
    """|dω/dt| / |ω|² over a window, its :data:`FREE_BODY_PERCENTILE` th percentile,
    from the smoothed rates ``smooth`` (n, 3) and their derivative
    ``derivative`` (n, 3); 0 for a body at rest."""
    speed = np.sum(smooth**2, axis=1)
    moving = speed > 0.0
    if not moving.any():
        return 0.0
    ratio = np.linalg.norm(derivative[moving], axis=1) / speed[moving]
    return float(np.percentile(ratio, FREE_BODY_PERCENTILE))


def breaks_free_body(ratio: float) -> bool:
    """Whether a window's :func:`free_body_ratio` is beyond what any torque-free
    body shows (:data:`FREE_BODY_BOUND`, with the margin :data:`FREE_BODY_MARGIN`)."""
    return ratio > FREE_BODY_MARGIN * FREE_BODY_BOUND


def torque_at_ends(times: Array, smooth: Array, derivative: Array) -> str:
    """Where a window holds a hand's torque at its ends, as a clause of a refusal: the
    samples whose |dω/dt| / |ω|² (smoothed rates ``smooth`` (n, 3) at ``times`` (n,) s,
    their derivative ``derivative``) breaks what any free body shows, when most of them
    lie before or after the longest run of samples that keep it, and that run holds
    most of the window (a throw or a catch inside it); "" otherwise."""
    n = len(times)
    speed = np.maximum(np.sum(smooth**2, axis=1), 1e-300)
    broken = np.linalg.norm(derivative, axis=1) / speed > FREE_BODY_MARGIN * FREE_BODY_BOUND
    edges = np.flatnonzero(np.diff(np.concatenate([[1], broken.astype(np.int8), [1]])))
    if not broken.any() or edges.size < 2:
        return ""
    runs = edges.reshape(-1, 2)  # [first, past-the-last) of each run that keeps the bound
    first, past = runs[int(np.argmax(runs[:, 1] - runs[:, 0]))]
    before, after = int(broken[:first].sum()), int(broken[past:].sum())
    if before + after < max(2, 0.8 * broken.sum()) or past - first < max(MIN_SAMPLES, 0.5 * n):
        return ""  # not a free flight with a hand at its ends: the rates' unit, or no flight
    where = "both ends" if before and after else ("start" if before else "end")
    return (
        f" (the rates break |dω/dt| ≤ |ω|²/√3, which a free body keeps, at the window's "
        f"{where}, {before + after} samples: a throw or a catch inside the window? Its "
        f"samples of {times[first]:.6g}–{times[past - 1]:.6g} s keep it)"
    )


def check_miss(
    residuals: Array,
    noise: float,
    times: Array,
    rates: Array,
    smooth: Array,
    derivative: Array,
    torque: str,
) -> None:
    """Refuse a fit whose typical residual (rad/s, median-based: a few outliers do not
    count) exceeds :data:`MAX_MISS` times the ``noise``, saying what may have broken the
    motion: a torque at the window's ends (a throw or a catch inside it), or rates that
    break |dω/dt| ≤ |ω|²/√3 (a hand's torque, or a unit too small)."""
    typical = 1.4826 * float(np.median(np.abs(residuals)))
    if typical <= MAX_MISS * noise or typical <= 1e-9 * float(np.abs(rates).max()):
        return
    ratio = free_body_ratio(smooth, derivative)
    also = torque_at_ends(times, smooth, derivative) or (
        f" (the rates break |dω/dt| ≤ |ω|²/√3 too, at {ratio:.3g} |ω|²: a hand's torque "
        "does, and so do rates too small for their unit, as deg/s read as rad/s)"
        if breaks_free_body(ratio)
        else ""
    )
    motion = "torque-free motion" if torque == "free" else f"motion under {torque}"
    raise InputError(
        f"Expected the samples of {times[0]:.6g}–{times[-1]:.6g} s to follow a {motion}, "
        f"got residuals of {typical:.3g} rad/s against noise of {noise:.3g} rad/s "
        f"for the best body found: is the window all free flight?{also}"
    )


def check_bias(bias: Array, rates: Array) -> None:
    """Refuse a fit whose sensor bias (rad/s, sensor axes) is larger than the rates
    measured (``rates`` (n, 3), their median length). No gyroscope reads mostly its
    own offset in flight; a fit does so when the rates are in a unit larger than
    they are read in, so too small by its factor (57.3 for deg/s read as rad/s):
    the rates then break |dω/dt| ≤ |ω|²/√3, which every torque-free body keeps,
    and the fit makes up the difference with a fast spin hidden in the bias
    (the shipped recording in deg/s read as rad/s: a bias of 7.4 rad/s against
    rates of 0.21 rad/s; in rad/s, 0.027 against 12)."""
    offset = float(np.linalg.norm(bias))
    typical = float(np.median(np.linalg.norm(rates, axis=1)))
    if offset > typical:
        raise InputError(
            f"Expected a sensor bias smaller than the rates measured, got a fit whose bias "
            f"({offset:.3g} rad/s) exceeds the rates' median ({typical:.3g} rad/s): the rates "
            "look too small for their unit (they break |dω/dt| ≤ |ω|²/√3, which every "
            "torque-free body keeps, and the bias makes up the rest): were they in deg/s read "
            "as rad/s (57.3 times), or in turn/s (6.28 times)? (Give them in rad/s, or as "
            "quantities with their unit.)"
        )


def biases_within_rates(biases: Array, rates: Array, smooth: Array, derivative: Array) -> Array:
    """Which of the fitted biases ``biases`` (k, 3) rad/s lie within the largest rate
    measured (``rates`` (n, 3)): the starts a drag may be searched from. A torque-free
    search can end on a body near a sphere, whose ω0 trades off against the bias, far
    beyond every sample; a drag searched from there drifts further along that trade.
    Refused when none does: as a unit error (:func:`check_bias`) where the smoothed
    rates and their derivative break |dω/dt| ≤ |ω|²/√3, as a motion showing too
    little of the body otherwise."""
    largest = float(np.linalg.norm(rates, axis=1).max())
    within = np.linalg.norm(biases, axis=1) <= largest
    if not within.any():
        best = biases[0]
        if breaks_free_body(free_body_ratio(smooth, derivative)):
            check_bias(best, rates)
        raise InputError(
            "Expected a recording that determines the moment ratios, got only bodies whose "
            f"bias exceeds every rate measured (the best: {np.linalg.norm(best):.3g} rad/s "
            f"against rates up to {largest:.3g} rad/s): near a sphere, ω0 trades off against "
            "a bias, and the motion shows too little of the body (a longer free flight, or a "
            "throw further from a principal axis, would)."
        )
    return within


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

#: Lags of the residuals' autocorrelation that tell a miss from noise (:func:`looks_like_noise`).
LAGS = 10


def canonical(moments: Array, axes: Array, omega0: Array) -> tuple[Array, Array, Array]:
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


def symmetric_within_errors(ratios: Array, covariance: Array) -> bool:
    """Whether two of the moments (r1, r2, 1) are equal within 3 standard errors
    of their difference (from the covariance of the ratios)."""
    v11, v22, v12 = covariance[0, 0], covariance[1, 1], covariance[0, 1]
    upper = 1.0 - ratios[1] < 3.0 * np.sqrt(max(v22, 0.0))
    lower = ratios[1] - ratios[0] < 3.0 * np.sqrt(max(v11 + v22 - 2 * v12, 0.0))
    return bool(upper or lower)


def check_determined(jacobian: Array, bias: bool) -> None:
    """Refuse a fit whose ratios some change of the other parameters can make up
    for exactly: a direction of the parameters (columns scaled to unit norm) the
    Jacobian does not see, with a share of the ratios. (A symmetric body's axes
    about its symmetry axis are such a direction too, but leave the ratios as
    they are: that is not refused.)"""
    norms = np.linalg.norm(jacobian, axis=0)
    norms[norms == 0] = 1.0
    _, values, directions = np.linalg.svd(jacobian / norms, full_matrices=False)
    # The Jacobian comes from forward differences, good to ~1e-8 relative (1e-7 for a
    # stepped model): a direction it does not see shows a singular value of that
    # order, 1e-6 of the largest is beyond any that a recording determines. Such
    # directions can span several dimensions (a symmetric body's ratio against the
    # bias, and its turn about the axis), each mixed with the others as round-off
    # chooses: the share of the ratios is taken over all of them together.
    unseen = directions[values < 1e-6 * values[0]]
    if np.linalg.norm(unseen[:, :2]) > 0.1:
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


def looks_like_noise(residuals: Array, noise: float, scale: float) -> bool:
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
