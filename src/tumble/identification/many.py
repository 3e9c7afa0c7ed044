"""Every throw of one body in a recording, fitted one by one and together:
:func:`tumble.identify_many` and :class:`ThrowFits`.

A recording of a thrown body holds dozens of throws, each a free flight between a
throw and a catch. Each is fitted alone (:func:`tumble.identify`); the throws that
fit are then fitted together (:func:`tumble.identification.joint.joint_fit`),
sharing the body's ratios, the sensor's axes and bias, and the drag, so that the
body is known far better than from any one throw. A throw held out in part (its
last fraction ``hold_out``) measures how well a fit forecasts the motion beyond
the samples it saw.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.identification.fit import DECISIVE, identify
from tumble.identification.flight import free_flights
from tumble.identification.joint import JointFit, disagreement, fit_under, joint_fit
from tumble.identification.result import BodyFit, information_criterion
from tumble.identification.torque_values import fits_torque_model
from tumble.identification.validation import MIN_SAMPLES, check_torque, flag, samples
from tumble.identification.windows import check_windows

__all__ = ["ThrowFits", "identify_many"]

Array = NDArray[np.float64]

#: The columns of :attr:`ThrowFits.table`.
COLUMNS = (
    "throw",
    "start",
    "end",
    "samples",
    "fitted",
    "reason",
    "torque",
    "r1",
    "r1_error",
    "r2",
    "r2_error",
    "c1",
    "c2",
    "c3",
    "residual_rms",
    "noise_ratio",
    "forecast_error",
    "single_forecast_error",
    "in_joint",
    "outlier",
    "disagreement",
)


@dataclass(frozen=True, eq=False)
class ThrowFits:
    """The throws of one body in a recording, each fitted alone, and their joint fit.

    Attributes
    ----------
    windows : the throws' windows (start, end), s, in time order.
    fits : per throw, its :class:`BodyFit`, or the reason it was refused (a str).
    joint : the fit of the fitted throws together (:class:`JointFit`), or None when
        fewer than two were fitted (``joint_refusal`` says why).
    joint_refusal : why there is no joint fit; "" when there is one.
    joined : the throws refused alone but fitted under the joint body (their ω0 alone,
        :func:`~tumble.identification.joint.fit_under`), and so in the joint fit.
    held_out_fits : per throw, the fit of its first ``1 − hold_out`` of the samples, or
        None (no hold-out asked, or that fit refused).
    held_out_joint : the joint fit of the joint throws' first ``1 − hold_out`` of the
        samples, or None.
    forecast_errors : (k,) per throw, the rms of ``held_out_joint``'s forecast less the
        measured rates over the held-out samples, over the rms of ``|ω|`` there (a
        fraction): the body known from the first parts of all the throws, the throw's
        motion from its own; nan where there is none.
    single_forecast_errors : (k,) the same of each throw's ``held_out_fits``: the throw
        alone.
    hold_out : the fraction of each window held out.
    """

    windows: tuple[tuple[float, float], ...]
    fits: tuple[BodyFit | str, ...]
    joint: JointFit | None
    joint_refusal: str
    joined: tuple[int, ...]
    held_out_fits: tuple[BodyFit | None, ...]
    held_out_joint: JointFit | None
    forecast_errors: Array
    single_forecast_errors: Array
    hold_out: float

    def cut(self, throw: int) -> float:
        """The time, s, after which the samples of a throw (an index of ``windows``) were
        held out."""
        return _cut(self.windows[throw], self.hold_out)

    @property
    def fitted(self) -> tuple[int, ...]:
        """The indices of the throws fitted."""
        return tuple(i for i, fit in enumerate(self.fits) if isinstance(fit, BodyFit))

    @property
    def table(self) -> pd.DataFrame:
        """One row per throw: its window (s) and samples, whether it was fitted and why
        not, its torque model, ratios and standard errors, drag coefficients c_i / I3
        (in the torque's units), residual rms (rad/s) and its ratio to the noise, the
        forecast errors of the held-out part (fractions; the joint body's and the throw's
        own), whether it is in the joint fit (``joined`` throws are, refused alone),
        whether it is an outlier of the joint fit, and how far its body lies from the
        joint one (standard errors of its ratios and axes:
        :func:`~tumble.identification.joint.disagreement`)."""
        rows = []
        joint = self.joint
        for i, ((start, end), fit) in enumerate(zip(self.windows, self.fits, strict=True)):
            row: dict[str, Any] = dict.fromkeys(COLUMNS, math.nan)
            row.update(throw=i + 1, start=start, end=end, fitted=isinstance(fit, BodyFit))
            row.update(outlier=joint is not None and i in joint.outliers, torque="")
            row["in_joint"] = joint is not None and i in joint.throws
            row["reason"] = "" if isinstance(fit, BodyFit) else fit
            row["forecast_error"] = self.forecast_errors[i]
            row["single_forecast_error"] = self.single_forecast_errors[i]
            if isinstance(fit, BodyFit):
                drag = fit.torque_parameters if fit.torque != "free" else np.zeros(3)
                row.update(
                    samples=len(fit.t),
                    torque=fit.torque,
                    r1=fit.moment_ratios[0],
                    r1_error=fit.uncertainty[0],
                    r2=fit.moment_ratios[1],
                    r2_error=fit.uncertainty[1],
                    c1=drag[0],
                    c2=drag[1],
                    c3=drag[2],
                    residual_rms=fit.residual_rms,
                    noise_ratio=fit.noise_ratio,
                )
                if joint is not None:
                    row["disagreement"] = disagreement(fit, joint)
            rows.append(row)
        table = pd.DataFrame(rows, columns=list(COLUMNS))
        return table.astype({"throw": int, "fitted": bool, "in_joint": bool, "outlier": bool})

    def __repr__(self) -> str:
        joint = (
            repr(self.joint) if self.joint is not None else f"no joint fit: {self.joint_refusal}"
        )
        return f"ThrowFits({len(self.fitted)} of {len(self.windows)} throws fitted; {joint})"


def identify_many(
    t: Any,
    omega: Any,
    windows: Any = None,
    *,
    bias: bool = True,
    loss: str = "linear",
    torque: str = "auto",
    hold_out: float = 0.0,
    progress: Callable[[int, int], None] | None = None,
) -> ThrowFits:
    """Fit every throw of one body in a recording, one by one and together.

    Parameters
    ----------
    t : (n,) sample times, s, increasing; or a pint quantity of times.
    omega : (n, 3) measured angular velocity in the sensor's axes, rad/s; or a pint
        quantity of rates.
    windows : the throws' free flights, a sequence of (start, end) in s; None to find
        every free flight of the recording
        (:func:`tumble.identification.free_flights`).
    bias : fit a constant sensor bias (shared by the throws in the joint fit).
    loss : the loss of each fit (see :func:`tumble.identify`).
    torque : the torque model of each throw (see :func:`tumble.identify`); with
        ``"auto"`` each throw chooses its own, and the joint fit the one most throws
        chose, or of those chosen the one of least Bayesian information criterion
        when they differ.
    hold_out : the fraction (0 to 0.9) of each window's end held out: each throw is
        also fitted on the rest, and its forecast of the held-out samples compared with
        them (``ThrowFits.forecast_errors``); 0 for none.
    progress : called with (throws done, throws) after each throw is fitted.

    Returns
    -------
    ThrowFits: each throw's fit or why it was refused, and the joint fit.

    Raises
    ------
    InputError
        For samples :func:`tumble.identify` refuses, windows that overlap, lie outside
        the recording or hold too few samples, no free flight found, or a hold-out
        outside [0, 0.9).
    """
    bias = flag(bias, "bias")
    if fits_torque_model(torque):
        raise InputError(
            "Expected `torque` to be one of auto, free, drag, quadratic-drag, got "
            f"{torque!r}: the joint fit of many throws shares the drags per principal axis "
            "only (fit each throw under that model with tumble.identify)."
        )
    torque = check_torque(torque)
    if not (isinstance(hold_out, (int, float)) and 0.0 <= hold_out < 0.9):
        raise InputError(f"Expected `hold_out` a fraction in [0, 0.9), got {hold_out!r}.")
    times, rates = samples(t, omega)
    spans = tuple(free_flights(times, rates) if windows is None else check_windows(windows, times))
    fits: list[BodyFit | str] = []
    held: list[BodyFit | None] = []
    single_errors = np.full(len(spans), math.nan)
    for i, span in enumerate(spans):
        fits.append(_attempt(times, rates, span, bias, loss, torque))
        held.append(None)
        if hold_out > 0.0 and isinstance(fits[-1], BodyFit):
            cut = _cut(span, hold_out)
            early = _attempt(times, rates, (span[0], cut), bias, loss, torque)
            if isinstance(early, BodyFit):
                held[-1] = early
                single_errors[i] = _forecast_error(early, times, rates, cut, span[1])
        if progress is not None:
            progress(i + 1, len(spans))
    indices = [i for i, fit in enumerate(fits) if isinstance(fit, BodyFit)]
    joint, refusal = None, ""
    if len(indices) < 2:
        refusal = f"{len(indices)} of {len(spans)} throws fitted; a joint fit needs 2"
    else:
        try:
            joint = _joint([fits[i] for i in indices], indices, torque, bias, loss)  # type: ignore[misc]
        except InputError as error:
            refusal = str(error)
    joined: dict[int, BodyFit] = {}
    if joint is not None:
        joint, joined = _join_refused(joint, fits, spans, times, rates, bias, loss)
    held_joint, errors = None, np.full(len(spans), math.nan)
    if joint is not None and hold_out > 0.0:
        held_joint = _held_out_joint(joint, hold_out, bias, loss)
        for i in held_joint.throws if held_joint is not None else ():
            assert held_joint is not None
            cut = _cut(spans[i], hold_out)
            errors[i] = _forecast_error(held_joint.throw_fit(i), times, rates, cut, spans[i][1])
    return ThrowFits(
        windows=spans,
        fits=tuple(fits),
        joint=joint,
        joint_refusal=refusal,
        joined=tuple(sorted(joined)),
        held_out_fits=tuple(held),
        held_out_joint=held_joint,
        forecast_errors=errors,
        single_forecast_errors=single_errors,
        hold_out=float(hold_out),
    )


def _join_refused(
    joint: JointFit,
    fits: list[BodyFit | str],
    spans: tuple[tuple[float, float], ...],
    times: Array,
    rates: Array,
    bias: bool,
    loss: str,
) -> tuple[JointFit, dict[int, BodyFit]]:
    """The throws refused alone (``fits``: their reasons) fitted under the joint body
    (:func:`fit_under`: their ω0 alone), and the joint fit again with those that it
    matches; the joint fit as it was when none does."""
    joined: dict[int, BodyFit] = {}
    for i, fit in enumerate(fits):
        inside = (times >= spans[i][0]) & (times <= spans[i][1])
        if isinstance(fit, str) and inside.sum() >= MIN_SAMPLES:
            under = fit_under(joint, times[inside], rates[inside], fit)
            if under is not None:
                joined[i] = under
    if not joined:
        return joint, joined
    members = sorted(set(joint.throws) | set(joint.outliers) | set(joined))
    alone = dict(zip(joint.throws, joint.fits, strict=True))
    alone |= {i: fits[i] for i in joint.outliers}  # type: ignore[misc]
    refitted = joint_fit(
        [joined.get(i) or alone[i] for i in members],
        members,
        joint.torque,
        bias,
        loss,
        joint.choice,
    )
    return refitted, joined


def _held_out_joint(joint: JointFit, hold_out: float, bias: bool, loss: str) -> JointFit | None:
    """The joint body's forecast: the same throws' first parts fitted together (from
    their whole fits, whose start values hold for their first parts too); None when
    too few throws agree on their first parts."""
    first_parts = [
        replace(fit, t=fit.t[keep], measured=fit.measured[keep])
        for fit in joint.fits
        for keep in [fit.t <= _cut(fit.window, hold_out)]
    ]
    try:
        return joint_fit(first_parts, list(joint.throws), joint.torque, bias, loss, "held out")
    except InputError:
        return None


def _cut(span: tuple[float, float], hold_out: float) -> float:
    """The time, s, after which a window's samples are held out."""
    return span[0] + (1.0 - hold_out) * (span[1] - span[0])


def _forecast_error(fit: BodyFit, times: Array, rates: Array, cut: float, end: float) -> float:
    """The rms of a fit's forecast less the measured rates over the samples of
    ``(cut, end]``, over the rms of ``|ω|`` there."""
    later = (times > cut) & (times <= end)
    missed = fit.forecast(times[later]) - rates[later]
    size = float(np.sqrt(np.mean(np.sum(rates[later] ** 2, axis=1))))
    return float(np.sqrt(np.mean(np.sum(missed**2, axis=1)))) / size


def _attempt(
    times: Array, rates: Array, span: tuple[float, float], bias: bool, loss: str, torque: str
) -> BodyFit | str:
    """One throw's fit, or the reason it is refused."""
    try:
        return identify(times, rates, window=span, bias=bias, loss=loss, torque=torque)
    except InputError as error:
        return str(error)


def _joint(fits: list[BodyFit], indices: list[int], torque: str, bias: bool, loss: str) -> JointFit:
    """The joint fit with the torque asked, or (``"auto"``) the one the throws chose:
    the most chosen, or when they differ the one of least information criterion over
    the joint fits of each (a torque over torque-free only on decisive evidence)."""
    if torque != "auto":
        return joint_fit(fits, indices, torque, bias, loss, "as asked")
    counts = Counter(fit.torque for fit in fits)
    said = ", ".join(f"{model} by {count}" for model, count in counts.most_common())
    if len(counts) == 1:
        (model,) = counts
        return joint_fit(fits, indices, model, bias, loss, f"{model}: chosen by every throw")
    joints, refused = {}, {}
    for model in counts:
        try:
            joints[model] = joint_fit(fits, indices, model, bias, loss, "")
        except InputError as error:
            refused[model] = str(error)
    if not joints:
        tried = "; ".join(f"{model}: {reason}" for model, reason in refused.items())
        raise InputError(f"Expected a joint fit of one of the torque models, got none: {tried}")
    criteria = {model: _information(joint) for model, joint in joints.items()}
    chosen = min(criteria, key=lambda model: criteria[model])
    if "free" in criteria and criteria["free"] - criteria[chosen] <= DECISIVE:
        chosen = "free"
    values = ", ".join(f"{model} {value:.1f}" for model, value in criteria.items())
    choice = (
        f"{chosen}: the throws chose {said}; the joint fits' Bayesian information "
        f"criteria are {values}"
    )
    return JointFit(**{**joints[chosen].__dict__, "choice": choice})


def _information(joint: JointFit) -> float:
    """The Bayesian information criterion of a joint fit (:func:`information_criterion`)."""
    count = sum(3 * len(fit.t) for fit in joint.fits)
    return information_criterion(joint.residual_rms**2 * count, count, joint.covariance.shape[0])
