"""What :func:`tumble.identify` returns: :class:`BodyFit`, a body, its motion and the
torque it flew under, fitted to measured rates."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core import drag_model, rate_model
from tumble.identification.torque_values import model_rates

__all__ = [
    "PARAMETERS",
    "TORQUE_MODELS",
    "TORQUE_UNITS",
    "BodyFit",
    "body_summary",
    "information_criterion",
    "principal_rates",
]

Array = NDArray[np.float64]

#: The parameters of a fit, in the order of its covariance: the ratios, a small rotation
#: of the axes, ω0, the bias (when fitted), then a drag's coefficients (when fitted).
PARAMETERS = ("r1", "r2", "rx", "ry", "rz", "w1", "w2", "w3", "bx", "by", "bz")

#: The names of a drag's coefficients c_i / I3 among a fit's parameters.
DRAG_PARAMETERS = ("c1", "c2", "c3")

#: The torque models a fit offers: torque-free, and air drag per principal axis.
TORQUE_MODELS = ("free", "drag", "quadratic-drag")

#: The units of each model's fitted parameters, the drag coefficients c_i / I3 per
#: principal axis (moments ascending): τ_i = −c_i ω_i (N·m·s) or −c_i ω_i |ω_i| (N·m·s²).
TORQUE_UNITS = {"free": "", "drag": "1/s", "quadratic-drag": "1/rad"}


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


def information_criterion(squares: float, count: int, parameters: int) -> float:
    """The Bayesian information criterion ``N ln(RSS/N) + k ln N`` of a fit of ``count``
    residuals whose squares sum to ``squares`` with ``parameters`` parameters (Schwarz,
    Ann. Stat. 6 (1978))."""
    return float(count * math.log(max(squares, 1e-300) / count) + parameters * math.log(count))


def body_summary(fit: Any) -> str:
    """The ratios with their standard errors and the torque of a fit (a :class:`BodyFit`
    or a joint fit), as its repr begins: ``"I1/I3=… ± …, I2/I3=… ± …, drag (…) 1/s, "``."""
    r, e = fit.moment_ratios, fit.uncertainty
    torque = ""
    if fit.torque != "free":
        values = ", ".join(f"{v:.3g}" for v in fit.torque_parameters)
        torque = f"{fit.torque} ({values}) {fit.torque_units}, "
    return f"I1/I3={r[0]:.5f} ± {e[0]:.1e}, I2/I3={r[1]:.5f} ± {e[1]:.1e}, {torque}"


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
    covariance : (k, k) covariance of the parameters :attr:`parameter_names`: the
        ratios, a small rotation of the axes (rad, about the fitted principal axes),
        ``omega0`` (rad/s), the bias (rad/s, when fitted), then a drag's coefficients.
    residual_rms : root-mean-square of the residuals, rad/s (the sensor's noise
        when the model fits).
    flip_period : period of ω(t) of the fitted body without its torque, s
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
    torque : the torque model fitted, one of ``TORQUE_MODELS``: ``"free"``
        (the exact torque-free motion), ``"drag"`` (τ_i = −c_i ω_i per principal
        axis) or ``"quadratic-drag"`` (τ_i = −c_i ω_i |ω_i|).
    torque_parameters : (3,) the drag coefficients c_i / I3 per principal axis
        (moments ascending) in :attr:`torque_units`; empty for ``"free"``.
    torque_uncertainty : their standard errors.
    choice : why this torque model: the models tried with their residuals and the
        criterion that chose (``torque="auto"``), or "as asked".
    torque_model : the fitted torque model (its parameters the fitted ones, for a body
        of I3 = 1 kg·m²) when a model was given as ``torque``; else None.
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
    torque: str = "free"
    torque_parameters: Array = field(default_factory=lambda: np.zeros(0))
    torque_uncertainty: Array = field(default_factory=lambda: np.zeros(0))
    choice: str = "as asked"
    torque_model: Any = None

    @property
    def torque_units(self) -> str:
        """The units of ``torque_parameters`` ("1/s" for linear drag, "1/rad" for
        quadratic drag, "" without a torque; a torque model's own SI units for a body of
        I3 = 1 kg·m²)."""
        return TORQUE_UNITS.get(self.torque, "SI, for a body of I3 = 1 kg·m²")

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """The names of the parameters of ``covariance``, in its order
        (:data:`PARAMETERS`, the bias only when fitted, then ``c1, c2, c3`` for a drag)."""
        drag = self.torque_parameters.size
        core = self.covariance.shape[0] - drag
        if self.torque_model is not None:
            return PARAMETERS[:core] + self.torque_model.flat_names()
        return PARAMETERS[:core] + DRAG_PARAMETERS[:drag]

    @property
    def information_criterion(self) -> float:
        """The Bayesian information criterion of the fit (:func:`information_criterion`)."""
        residuals = self.residuals.ravel()
        squares = float(residuals @ residuals)
        return information_criterion(squares, residuals.size, self.covariance.shape[0])

    @property
    def bias_fitted(self) -> bool:
        """Whether the sensor's bias was fitted (``bias=True``)."""
        return "bx" in self.parameter_names

    @property
    def noise_ratio(self) -> float:
        """``residual_rms`` over the noise σ of a component: about 1 when the model fits
        to the noise; a few for a real recording's model error (the uncertainties come
        from the residuals, so they grow with it)."""
        return float(self.residual_rms / max(self.noise, 1e-300))

    def principal_rates(self, t: Any) -> Array:
        """(n, 3) the fitted body's ω at times ``t`` (s), principal axes, rad/s: the exact
        torque-free motion, or the motion under the fitted drag stepped from the
        window's start (forwards and backwards)."""
        times = np.ascontiguousarray(np.asarray(t, dtype=float) - self.window[0])
        moments = np.array([*self.moment_ratios, 1.0])
        if self.torque == "free":
            return principal_rates(moments, self.omega0, times)
        order = np.argsort(times, kind="stable")
        if self.torque_model is not None:
            out = np.empty((times.size, 3))
            out[order] = model_rates(self.torque_model, moments, self.omega0, times[order])
            return out
        rates = drag_model.drag_rates(
            moments,
            np.asarray(self.torque_parameters, dtype=float),
            self.torque == "quadratic-drag",
            np.asarray(self.omega0, dtype=float),
            np.ascontiguousarray(times[order]),
        )
        out = np.empty_like(rates)
        out[order] = rates
        return out

    def predicted(self, t: Any) -> Array:
        """(n, 3) the fitted measurement at times ``t`` (s): ω in the sensor's axes
        plus the bias, rad/s."""
        return np.asarray(self.principal_rates(t) @ self.axes.T + self.bias)

    def forecast(self, t: Any) -> Array:
        """(n, 3) the fitted measurement at any times ``t`` (s), inside the window or
        beyond it: ω in the sensor's axes plus the bias, rad/s (as :meth:`predicted`)."""
        return self.predicted(t)

    @property
    def residuals(self) -> Array:
        """(n, 3) measured − fitted, rad/s, at the times ``t``."""
        return np.asarray(self.measured - self.predicted(self.t))

    def __repr__(self) -> str:
        return (
            f"BodyFit({body_summary(self)}"
            f"flip_period={self.flip_period:.4g} s, residual_rms={self.residual_rms:.3g} rad/s, "
            f"{len(self.t)} samples in {self.window[0]:.4g}–{self.window[1]:.4g} s)"
        )
