"""One body fitted to many throws at once: :func:`joint_fit` and :class:`JointFit`.

Every throw of one body shares the body's moment ratios, the sensor's axes in the
body, the sensor's bias and (under air drag) the drag coefficients; only the motion
at each throw's start is its own. The joint fit fits them all to all the
throws' samples by one least squares: 5 (the ratios and the axes) + 3 (bias) + 3
(drag) shared parameters and 3 a throw. Each throw's residuals are those of the single fit's model
(:func:`tumble.core.rate_model.rate_residuals`, or the stepped drag model
:func:`tumble.core.drag_model.drag_residuals`), so a throw's block of the
Jacobian holds its own ω0 columns and the shared ones: the joint Jacobian is
assembled from the throws' blocks. It starts from the throws' own fits (the
median of their ratios, biases and drags, the axes of the best determined, each
ω0 turned into those axes), so it needs no guess.

Throws whose body (ratios and axes) disagrees with the joint one beyond what both
their errors allow (by more than :data:`OUTLIER_DEVIATION` standard errors), or
whose samples the joint body misses by far more than their own fit does, are
outliers: they are flagged and left out of the joint fit.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from tumble.core import drag_model, rate_model
from tumble.errors import InputError
from tumble.identification.result import (
    DRAG_PARAMETERS,
    PARAMETERS,
    TORQUE_UNITS,
    BodyFit,
    body_summary,
)
from tumble.identification.validation import canonical
from tumble.theory import flip_period

__all__ = ["OUTLIER_DEVIATION", "JointFit", "disagreement", "joint_fit"]

Array = NDArray[np.float64]

#: Standard errors beyond which a throw's ratio or axis disagrees with another's: a
#: normal deviate beyond 3.5 has a chance of 4.7e-4, so a throw that agrees is flagged
#: for one of its five numbers with a chance of at most 0.23 %.
OUTLIER_DEVIATION = 3.5

#: How many times its own fit's residual a throw's residual under the joint body may
#: be before the joint body is taken not to explain the throw.
OUTLIER_MISS = 2.0


@dataclass(frozen=True, eq=False)
class JointFit:
    """One body fitted to many throws at once, by :func:`tumble.identify_many`.

    Attributes
    ----------
    moment_ratios : (2,) ``(I1/I3, I2/I3)``, principal moments ascending.
    uncertainty : (2,) their standard errors.
    axes : (3, 3) principal axes as columns in the sensor's axes (a proper rotation).
    bias : (3,) the sensor's bias in its axes, rad/s (zeros when not fitted).
    omega0 : (m, 3) ω at each joint throw's start, principal axes, rad/s.
    throws : the indices of the throws in the joint fit (of ``identify_many``'s windows).
    outliers : the indices of the fitted throws left out of it: their ratios disagree
        with the joint ones, or the joint body misses their samples.
    torque : the torque model shared by the throws (see :class:`BodyFit`).
    torque_parameters : (3,) the drag coefficients c_i / I3 per principal axis in
        :attr:`torque_units`; empty for ``"free"``.
    torque_uncertainty : their standard errors.
    covariance : (k, k) covariance of :attr:`parameter_names`: the ratios, a small
        rotation of the axes (rad), the bias (rad/s, when fitted), the drag, then each
        throw's ω0 (rad/s).
    residual_rms : root-mean-square of all the joint throws' residuals, rad/s.
    noise : the sensor's noise σ per component, rad/s (the median of the throws').
    choice : why this torque model, one sentence.
    fits : the joint throws' single fits, in the order of ``throws``.
    """

    moment_ratios: Array
    uncertainty: Array
    axes: Array
    bias: Array
    omega0: Array
    throws: tuple[int, ...]
    outliers: tuple[int, ...]
    torque: str
    torque_parameters: Array
    torque_uncertainty: Array
    covariance: Array
    residual_rms: float
    noise: float
    choice: str
    fits: tuple[BodyFit, ...] = field(repr=False)

    @property
    def torque_units(self) -> str:
        """The units of ``torque_parameters`` (see :attr:`BodyFit.torque_units`)."""
        return TORQUE_UNITS[self.torque]

    @property
    def bias_fitted(self) -> bool:
        """Whether the sensor's bias was fitted."""
        return self.fits[0].bias_fitted

    @property
    def noise_ratio(self) -> float:
        """``residual_rms`` over the noise σ: about 1 when the model fits to the noise."""
        return float(self.residual_rms / max(self.noise, 1e-300))

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """The names of the parameters of ``covariance``, in its order."""
        shared = PARAMETERS[:5] + (PARAMETERS[8:11] if self.bias_fitted else ())
        shared += DRAG_PARAMETERS[: self.torque_parameters.size]
        starts = tuple(f"w{k + 1}[{i}]" for i in self.throws for k in range(3))
        return shared + starts

    def throw_fit(self, throw: int) -> BodyFit:
        """The joint body's fit of one throw (an index of ``identify_many``'s windows, one
        of ``throws``), as a :class:`BodyFit`: the shared ratios, axes, bias and drag
        with the throw's own ω0, so that its ``predicted`` and ``forecast`` give the joint
        body's motion of that throw."""
        if throw not in self.throws:
            raise InputError(
                f"Expected a throw of the joint fit (one of {list(self.throws)}), got {throw!r}."
            )
        k = self.throws.index(throw)
        single = self.fits[k]
        shared = _shared_count(self.bias_fitted, self.torque_parameters.size)
        # The covariance in BodyFit's order: ratios, rotation, ω0, bias, drag.
        own = shared + 3 * k
        drag_at = 5 + (3 if self.bias_fitted else 0)
        order = [0, 1, 2, 3, 4, own, own + 1, own + 2]
        order += list(range(5, drag_at)) + list(range(drag_at, shared))
        ratios = self.moment_ratios
        fit = BodyFit(
            moment_ratios=ratios,
            uncertainty=self.uncertainty,
            axes=self.axes,
            omega0=self.omega0[k],
            bias=self.bias,
            covariance=self.covariance[np.ix_(order, order)],
            residual_rms=0.0,
            flip_period=flip_period(
                [max(ratios[0], 1.0 - ratios[1]), ratios[1], 1.0], self.omega0[k]
            ),
            window=single.window,
            t=single.t,
            measured=single.measured,
            noise=single.noise,
            note=single.note,
            torque=self.torque,
            torque_parameters=self.torque_parameters,
            torque_uncertainty=self.torque_uncertainty,
            choice=f"the joint fit of {len(self.throws)} throws",
        )
        residual = float(np.sqrt(np.mean(fit.residuals**2)))
        return BodyFit(**{**fit.__dict__, "residual_rms": residual})

    def __repr__(self) -> str:
        return (
            f"JointFit({body_summary(self)}{len(self.throws)} throws, "
            f"{len(self.outliers)} outliers, residual_rms={self.residual_rms:.3g} rad/s)"
        )


def _shared_count(bias: bool, drag: int) -> int:
    """The number of shared parameters: ratios, rotation, bias, drag."""
    return 5 + (3 if bias else 0) + drag


class _Throws:
    """The joint model: the throws' samples, their columns among the joint parameters,
    and the residuals and Jacobian of them all."""

    def __init__(self, fits: list[BodyFit], frame: Array, bias: bool, torque: str) -> None:
        self.frame = np.ascontiguousarray(frame)
        self.bias = bias
        self.torque = torque
        drag = 0 if torque == "free" else 3
        self.shared = _shared_count(bias, drag)
        self.times = [np.ascontiguousarray(fit.t - fit.window[0]) for fit in fits]
        self.rates = [np.ascontiguousarray(fit.measured) for fit in fits]
        rows = np.cumsum([0] + [3 * len(t) for t in self.times])
        self.rows = [slice(int(a), int(b)) for a, b in itertools.pairwise(rows)]
        bias_columns = list(range(5, 8)) if bias else []
        drag_columns = list(range(self.shared - drag, self.shared))
        # Each throw's parameters in the single fit's order: ratios, rotation, ω0,
        # bias, drag.
        self.columns = []
        for k in range(len(fits)):
            own = range(self.shared + 3 * k, self.shared + 3 * k + 3)
            self.columns.append(np.array([*range(5), *own, *bias_columns, *drag_columns]))
        self.size = self.shared + 3 * len(fits)

    def _arguments(self, k: int) -> tuple[Any, ...]:
        args: tuple[Any, ...] = (self.frame, self.times[k], self.rates[k], self.bias)
        return args if self.torque == "free" else (*args, self.torque == "quadratic-drag")

    def residuals(self, x: Array) -> Array:
        """All the throws' residuals, rad/s, one after the other."""
        model = rate_model.rate_residuals if self.torque == "free" else drag_model.drag_residuals
        return np.concatenate(
            [model(x[columns], *self._arguments(k)) for k, columns in enumerate(self.columns)]
        )

    def jacobian(self, x: Array) -> Array:
        """The joint Jacobian, assembled from each throw's block."""
        out = np.zeros((self.rows[-1].stop, self.size))
        free = self.torque == "free"
        jacobian = rate_model.rate_jacobian if free else drag_model.drag_jacobian
        for k, columns in enumerate(self.columns):
            block = jacobian(x[columns], *self._arguments(k))
            out[self.rows[k], columns] += block
        return out


def disagreement(fit: BodyFit, other: BodyFit | JointFit) -> float:
    """How far a throw's body lies from another's (a throw's, or the joint one), in
    standard errors: the largest, over the two ratios and the three angles of the
    rotation (rad) that turns the throw's principal axes into the other's, of the
    difference over the standard error of both together. (Not χ² of the five at once:
    their covariances are near singular, the ratios correlated to −1.000 when a body
    is near a flat plate, and the small nonlinear part of the differences lies along
    those directions.) The axes are matched column by column first, up to their signs."""
    signs = np.sign(np.diag(fit.axes.T @ other.axes))
    signs[signs == 0] = 1.0
    turn = Rotation.from_matrix((fit.axes * signs).T @ other.axes).as_rotvec()
    difference = np.concatenate([fit.moment_ratios - other.moment_ratios, turn])
    errors = np.sqrt(np.diag(fit.covariance)[:5] + np.diag(other.covariance)[:5])
    return float(np.max(np.abs(difference) / np.maximum(errors, 1e-300)))


def joint_fit(
    fits: list[BodyFit], indices: list[int], torque: str, bias: bool, loss: str, choice: str
) -> JointFit:
    """The joint fit of the single ``fits`` of the throws ``indices`` with ``torque``,
    without the outliers (see the module's docstring). The throws are first matched
    against the one that agrees best with the others (the least median disagreement), so
    that an outlier does not pull the first joint fit; the joint fit then judges them all
    again, and is made once more when that changes which throws it leaves out.

    Raises
    ------
    InputError
        When fewer than two throws agree on one body.
    """
    spread = [[disagreement(a, b) for b in fits] for a in fits]
    central = fits[int(np.argmin(np.median(spread, axis=1)))]
    kept = [k for k, fit in enumerate(fits) if disagreement(fit, central) <= OUTLIER_DEVIATION]
    joint = None
    for _ in range(2):
        if len(kept) < 2:
            raise InputError(
                f"Expected at least 2 throws that agree on one body, got {len(kept)} of "
                f"{len(indices)} fitted (the others' ratios or axes disagree with them)."
            )
        outliers = tuple(indices[k] for k in range(len(fits)) if k not in kept)
        joint = _fit_together(
            [fits[k] for k in kept],
            [indices[k] for k in kept],
            torque,
            bias,
            loss,
            choice,
            outliers,
        )
        judged = [k for k in range(len(fits)) if not _disagrees(joint, fits[k], indices[k])]
        if judged == kept:
            break
        kept = judged
    assert joint is not None
    return joint


def _disagrees(joint: JointFit, single: BodyFit, throw: int) -> bool:
    """Whether a throw is an outlier of the joint fit: its body disagrees, or (for a throw
    of the joint fit) the joint body misses its samples by far more than its own fit."""
    if disagreement(single, joint) > OUTLIER_DEVIATION:
        return True
    return (
        throw in joint.throws
        and joint.throw_fit(throw).residual_rms > OUTLIER_MISS * single.residual_rms
    )


def _start(fits: list[BodyFit], torque: str, bias: bool) -> tuple[Array, Array]:
    """The joint parameters' start and the frame they are counted from, from the throws'
    own fits: the axes of the best determined throw, the medians of the ratios, biases
    and drags (of the throws fitted with ``torque``), each ω0 turned into those axes."""
    best = min(fits, key=lambda fit: float(np.sum(fit.uncertainty)))
    frame = best.axes
    ratios = np.median([fit.moment_ratios for fit in fits], axis=0)
    offset = np.median([fit.bias for fit in fits], axis=0) if bias else np.zeros(0)
    drag = np.zeros(0 if torque == "free" else 3)
    same = [fit.torque_parameters for fit in fits if fit.torque == torque]
    if drag.size and same:
        drag = np.median(same, axis=0)
    starts = [frame.T @ fit.axes @ fit.omega0 for fit in fits]
    x = np.concatenate([np.log(ratios), np.zeros(3), offset, drag, *starts])
    return x, frame


def _fit_together(
    fits: list[BodyFit],
    indices: list[int],
    torque: str,
    bias: bool,
    loss: str,
    choice: str,
    outliers: tuple[int, ...],
) -> JointFit:
    """One least squares of the throws ``fits`` (of the windows ``indices``) together."""
    x, frame = _start(fits, torque, bias)
    model = _Throws(fits, frame, bias, torque)
    noise = float(np.median([fit.noise for fit in fits]))
    scale = max(3.0 * noise, 1e-12 * max(float(np.abs(fit.measured).max()) for fit in fits))
    # The throws' own fits have found the motion: the joint fit only polishes, so it
    # stops where the single fits' polish does.
    tolerance = 1e-12 if loss == "linear" else 1e-10
    result = least_squares(
        model.residuals,
        x,
        jac=model.jacobian,
        method="lm" if loss == "linear" else "trf",
        loss=loss,
        f_scale=scale,
        x_scale="jac",
        ftol=tolerance,
        xtol=tolerance,
        gtol=tolerance,
        max_nfev=100 * x.size,
    )
    moments, axes = rate_model.moments_and_axes(result.x, np.ascontiguousarray(frame))
    shared = model.shared
    offset = result.x[5:8] if bias else np.zeros(3)
    drag = result.x[shared - (0 if torque == "free" else 3) : shared]
    order = np.argsort(moments, kind="stable")
    starts = result.x[shared:].reshape(-1, 3)
    # The same body in the canonical order and signs of the single fits; every
    # throw's ω0 follows the axes (canonical takes ω0 as rows of a (3, m) array).
    moments, axes, turned = canonical(moments, axes, starts.T.copy())
    drag = drag[order] if drag.size else drag

    dof = max(result.fun.size - result.x.size, 1)
    variance = 2.0 * result.cost / dof
    jacobian = result.jac
    covariance = variance * np.linalg.pinv(jacobian.T @ jacobian, rcond=1e-12, hermitian=True)
    # From the logarithms of the ratios to the ratios: d r = r d(ln r).
    to_ratios = np.ones(result.x.size)
    to_ratios[:2] = moments[:2]
    covariance *= np.outer(to_ratios, to_ratios)
    errors = np.sqrt(np.abs(np.diag(covariance)))
    return JointFit(
        moment_ratios=moments[:2],
        uncertainty=errors[:2],
        axes=axes,
        bias=offset,
        omega0=turned.T.copy(),
        throws=tuple(indices),
        outliers=outliers,
        torque=torque,
        torque_parameters=drag,
        torque_uncertainty=errors[shared - drag.size : shared][order] if drag.size else drag,
        covariance=covariance,
        residual_rms=float(np.sqrt(np.mean(result.fun**2))),
        noise=noise,
        choice=choice,
        fits=tuple(fits),
    )


def fit_under(joint: JointFit, times: Array, rates: Array, reason: str) -> BodyFit | None:
    """A throw refused alone (``reason``), fitted under the joint body: its ω0 alone
    (three parameters), the ratios, axes, bias and drag held at the joint ones; None
    when the joint body misses its samples (rms beyond :data:`OUTLIER_MISS` times the
    joint fit's). A throw too short or too near a principal axis to determine a body
    still shows its own motion, which a known body determines.

    ``times`` (n,) s and ``rates`` (n, 3) rad/s are the window's samples."""
    shared, drag = _shared_count(joint.bias_fitted, joint.torque_parameters.size), joint.torque
    relative = np.ascontiguousarray(times - times[0])
    measured = np.ascontiguousarray(rates)
    head = np.concatenate([np.log(joint.moment_ratios), np.zeros(3)])
    tail = np.concatenate([joint.bias if joint.bias_fitted else [], joint.torque_parameters])
    args: tuple[Any, ...] = (
        np.ascontiguousarray(joint.axes),
        relative,
        measured,
        joint.bias_fitted,
    )
    model: Any = rate_model.rate_residuals
    if drag != "free":
        args += (drag == "quadratic-drag",)
        model = drag_model.drag_residuals

    def residuals(omega0: Array) -> Array:
        return np.asarray(model(np.concatenate([head, omega0, tail]), *args))

    # ω0 is seen directly: the first samples less the bias, in the principal axes.
    start = joint.axes.T @ (measured[:3].mean(axis=0) - joint.bias)
    result = least_squares(residuals, start, method="lm", x_scale="jac")
    rms = float(np.sqrt(np.mean(result.fun**2)))
    if not rms <= OUTLIER_MISS * joint.residual_rms:
        return None
    dof = max(result.fun.size - 3, 1)
    own = 2.0 * result.cost / dof * np.linalg.pinv(result.jac.T @ result.jac, hermitian=True)
    # The covariance in BodyFit's order (ratios, rotation, ω0, bias, drag): the joint
    # body's, and the throw's ω0 given that body.
    covariance = np.zeros((shared + 3, shared + 3))
    body = list(range(shared))
    placed = [0, 1, 2, 3, 4, *range(8, shared + 3)]
    covariance[np.ix_(placed, placed)] = joint.covariance[np.ix_(body, body)]
    covariance[5:8, 5:8] = own
    ratios = joint.moment_ratios
    return BodyFit(
        moment_ratios=ratios,
        uncertainty=joint.uncertainty,
        axes=joint.axes,
        omega0=result.x,
        bias=joint.bias,
        covariance=covariance,
        residual_rms=rms,
        flip_period=flip_period([max(ratios[0], 1.0 - ratios[1]), ratios[1], 1.0], result.x),
        window=(float(times[0]), float(times[-1])),
        t=np.asarray(times, dtype=float),
        measured=measured,
        noise=joint.noise,
        torque=drag,
        torque_parameters=joint.torque_parameters,
        torque_uncertainty=joint.torque_uncertainty,
        choice=f"fitted under the joint body; alone: {reason}",
    )
