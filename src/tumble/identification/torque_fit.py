"""A body and the parameters of a torque model of tumble's registry, or a user's,
fitted to measured rates: ``tumble.identify(t, omega, torque=<a torque model>)``.

A torque that depends on ω and time alone (a recording of rates does not know the
attitude) acts on the fitted body, whose moments are ``(r1, r2, 1)`` kg·m²: its
parameters are fitted for a body of I3 = 1 kg·m², so that torques come out per unit
of I3 (a drag coefficient c / I3 in 1/s). The model's values given are the start of
its parameters; the body, the axes, ω0 and the bias start from the fit that
``torque="auto"`` makes of the same samples. The rates are stepped with the torque's
compiled function (:func:`tumble.core.stepped_model.stepped_rates`); the Jacobian is
taken by forward differences.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from tumble.core import rate_model
from tumble.errors import InputError
from tumble.identification.result import BodyFit
from tumble.identification.torque_values import model_rates
from tumble.identification.validation import MAX_MISS
from tumble.theory import flip_period
from tumble.torques import TorqueModel

__all__ = ["fit_torque_model"]

Array = NDArray[np.float64]

#: The residual of a sample whose motion the stepping gave up, rad/s (finite, so that
#: the solver rejects the step).
GIVEN_UP = 1e6


def _residuals(
    x: Array, frame: Array, times: Array, measured: Array, bias: bool, torque: TorqueModel
) -> Array:
    """The residuals (3 n,), rad/s, of the parameters ``x``: the logarithms of the
    ratios, a rotation of ``frame``, ω0, the bias (when fitted), then the torque's."""
    moments, axes = rate_model.moments_and_axes(x, frame)
    offset = x[8:11] if bias else np.zeros(3)
    count = 11 if bias else 8
    try:
        rates = model_rates(torque.with_flat_values(x[count:]), moments, x[5:8], times)
    except (InputError, ValueError):
        return np.full(measured.size, GIVEN_UP)  # values the model refuses: a step too far
    out = (rates @ axes.T + offset - measured).ravel()
    out[~np.isfinite(out)] = GIVEN_UP
    return out


def fit_torque_model(start: BodyFit, torque: TorqueModel, loss: str) -> BodyFit:
    """The fit of the samples of ``start`` (a fit of them by ``torque="auto"``) with the
    body under ``torque``, whose values start its parameters.

    Raises
    ------
    InputError
        When the fitted motion misses the samples by far more than the noise.
    """
    bias = start.bias_fitted
    relative = np.ascontiguousarray(start.t - start.window[0])
    measured = np.ascontiguousarray(start.measured)
    offset = start.bias if bias else np.zeros(0)
    head = [np.log(start.moment_ratios), np.zeros(3), start.omega0, offset]
    x0 = np.concatenate([*head, torque.flat_values()])
    result = least_squares(
        _residuals,
        x0,
        args=(start.axes, relative, measured, bias, torque),
        method="lm" if loss == "linear" else "trf",
        loss=loss,
        f_scale=max(3.0 * start.noise, 1e-12),
        x_scale="jac",
        max_nfev=200 * x0.size,
    )
    body, axes = rate_model.moments_and_axes(result.x, np.ascontiguousarray(start.axes))
    if np.any(np.diff(body) < 0):
        raise InputError(
            f"Expected the fit under {torque!r} to keep the moments' order, got moments "
            f"{body[0]:.4g}, {body[1]:.4g}, 1 (the torque took over the motion the ratios make)."
        )
    # The start's axes are canonical and the rotation from them small: no sign to
    # change (a change would turn a torque given per body axis too).
    moments, omega0 = body, result.x[5:8]
    typical = 1.4826 * float(np.median(np.abs(result.fun)))
    if typical > MAX_MISS * start.noise:
        raise InputError(
            f"Expected the samples of {start.window[0]:.6g}–{start.window[1]:.6g} s to follow a "
            f"motion under {torque!r}, got residuals of {typical:.3g} rad/s against noise of "
            f"{start.noise:.3g} rad/s."
        )
    dof = max(result.fun.size - result.x.size, 1)
    variance = 2.0 * result.cost / dof
    covariance = variance * np.linalg.pinv(result.jac.T @ result.jac, rcond=1e-12, hermitian=True)
    scale = np.ones(result.x.size)
    scale[:2] = moments[:2]
    covariance *= np.outer(scale, scale)
    errors = np.sqrt(np.abs(np.diag(covariance)))
    count = 11 if bias else 8
    values = result.x[count:]
    ratios = moments[:2]
    return BodyFit(
        moment_ratios=ratios,
        uncertainty=errors[:2],
        axes=axes,
        omega0=omega0,
        bias=result.x[8:11] if bias else np.zeros(3),
        covariance=covariance,
        residual_rms=float(np.sqrt(np.mean(result.fun**2))),
        flip_period=flip_period([max(ratios[0], 1.0 - ratios[1]), ratios[1], 1.0], omega0),
        window=start.window,
        t=start.t,
        measured=measured,
        noise=start.noise,
        note=start.note,
        torque=torque.name or type(torque).__name__,
        torque_parameters=values,
        torque_uncertainty=errors[count:],
        choice="as asked",
        torque_model=torque.with_flat_values(values),
    )
