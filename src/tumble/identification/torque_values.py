"""Which torque models a fit of rates fits (:mod:`tumble.identification.torque_fit`),
and the rates of a body under one, which a :class:`~tumble.identification.BodyFit`
under a torque model forecasts."""

from __future__ import annotations

from functools import cache
from typing import Any, TypeGuard

import numpy as np
from numpy.typing import NDArray

from tumble.body import body_model
from tumble.core.drag_model import MOST_SUBSTEPS, MOST_TURN
from tumble.core.dynamics import euler_coefficients
from tumble.core.stepped_model import stepped_rates
from tumble.massprops import MassProperties
from tumble.torques import TorqueModel
from tumble.torques.binding import bind

__all__ = ["axes_body", "fits_torque_model", "model_rates", "why_not_fitted"]

Array = NDArray[np.float64]

#: The registry's torque models a fit steps with its own compiled model (their names
#: are values of ``torque=``).
BUILT_IN = ("drag", "quadratic-drag")


@cache
def axes_body() -> Any:
    """A body whose principal axes are its body axes (distinct moments, kg·m²), built
    once, when a torque model is first bound."""
    return body_model(MassProperties(1.0, np.zeros(3), np.diag([1.0, 2.0, 2.5])))


def fits_torque_model(torque: Any) -> TypeGuard[TorqueModel]:
    """Whether ``torque`` is a torque model whose parameters a fit of rates fits by
    stepping its compiled function: one that depends on ω and time alone, acts from
    outside, and has parameters, other than the drags per axis (:data:`BUILT_IN`)."""
    if not isinstance(torque, TorqueModel) or len(torque.terms) != 1:
        return False
    if torque.name in BUILT_IN:
        return False  # fitted by the compiled drag model, from its own search
    return (
        "attitude" not in torque.depends_on
        and torque.actuator == "external"
        and torque.flat_values().size > 0
    )


def why_not_fitted(torque: Any) -> str:
    """Why a fit of rates does not fit ``torque`` (a registry model's name, class or
    instance), one clause."""
    if isinstance(torque, (str, type)):
        return "a name or a class gives no starting values (give a model with them)"
    if len(torque.terms) != 1:
        return "a sum of models (fit one model)"
    if "attitude" in torque.depends_on:
        return "its torque reads the attitude, which rates do not show"
    if torque.actuator != "external":
        return "it acts through the body's rotors, which rates do not show"
    return "it has no parameters to fit"


def model_rates(torque: TorqueModel, moments: Array, omega0: Array, times: Array) -> Array:
    """(n, 3) principal rates (rad/s) at ``times`` (n,) s, ascending, of the body of
    ``moments`` (3,) kg·m² under ``torque``, ω(0) = ``omega0`` (3,) rad/s.

    The torque's fields are packed for :func:`axes_body`, whose principal axes are its
    body axes as the fitted body's are: a torque of ω and time reads nothing else of
    the body, and the moments a fit tries on its way need not make a physical body."""
    moments = np.asarray(moments, dtype=float)
    bound = bind(torque, axes_body(), np.asarray(omega0, dtype=float))
    return np.asarray(
        stepped_rates(
            bound.function,
            euler_coefficients(moments[0], moments[1], moments[2]),
            bound.params,
            bound.context,
            np.asarray(omega0, dtype=float),
            np.ascontiguousarray(times, dtype=float),
            MOST_TURN,
            MOST_SUBSTEPS,
        )
    )
