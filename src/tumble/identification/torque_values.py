"""The parameters of a torque model as the numbers a fit changes, and the rates of a
body under it: what :mod:`tumble.identification.torque_fit` fits and what a
:class:`~tumble.identification.BodyFit` under a torque model forecasts."""

from __future__ import annotations

from dataclasses import replace
from typing import Any, TypeGuard, cast

import numpy as np
from numpy.typing import NDArray

from tumble.body import body_model
from tumble.core.drag_model import MOST_SUBSTEPS, MOST_TURN
from tumble.core.dynamics import euler_coefficients
from tumble.core.stepped_model import stepped_rates
from tumble.massprops import MassProperties
from tumble.torques import TorqueModel, UserTorque
from tumble.torques.binding import bind

__all__ = [
    "fits_torque_model",
    "model_rates",
    "parameter_names",
    "values_of",
    "why_not_fitted",
    "with_values",
]

Array = NDArray[np.float64]

#: The registry's torque models a fit steps with its own compiled model (their names
#: are values of ``torque=``).
BUILT_IN = ("drag", "quadratic-drag")

#: A body whose principal axes are its body axes (distinct moments, kg·m²).
AXES_BODY = MassProperties(1.0, np.zeros(3), np.diag([1.0, 2.0, 2.5]))


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
        and values_of(torque).size > 0
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


def parameter_names(torque: TorqueModel) -> tuple[str, ...]:
    """The names of a model's fitted parameters, flattened: ``coefficients[0]``, ..."""
    if isinstance(torque, UserTorque):
        return tuple(f"params[{k}]" for k in range(len(torque.params)))
    names: list[str] = []
    for parameter in torque.parameters:
        size = int(np.prod(parameter.shape))
        shown = [f"{parameter.name}[{k}]" for k in range(size)]
        names += shown if parameter.shape else [parameter.name]
    return tuple(names)


def values_of(torque: TorqueModel) -> Array:
    """A model's parameter values, flattened (SI)."""
    if isinstance(torque, UserTorque):
        return np.asarray(torque.params, dtype=float).reshape(-1)
    values = [np.asarray(value, dtype=float).reshape(-1) for value in torque.values().values()]
    return np.concatenate(values) if values else np.zeros(0)


def with_values(torque: TorqueModel, values: Array) -> TorqueModel:
    """The same model with its parameters ``values`` (flattened, SI)."""
    if isinstance(torque, UserTorque):
        return replace(torque, params=np.array(values, dtype=float))
    changed, at = {}, 0
    for parameter in torque.parameters:
        size = int(np.prod(parameter.shape))
        chunk = np.array(values[at : at + size], dtype=float)
        changed[parameter.name] = chunk.reshape(parameter.shape) if parameter.shape else chunk[0]
        at += size
    return replace(cast(Any, torque), **changed)  # every registered model is a dataclass


def model_rates(torque: TorqueModel, moments: Array, omega0: Array, times: Array) -> Array:
    """(n, 3) principal rates (rad/s) at ``times`` (n,) s, ascending, of the body of
    ``moments`` (3,) kg·m² under ``torque``, ω(0) = ``omega0`` (3,) rad/s.

    The torque's fields are packed for :data:`AXES_BODY`, whose principal axes are its
    body axes as the fitted body's are: a torque of ω and time reads nothing else of
    the body, and the moments a fit tries on its way need not make a physical body."""
    moments = np.asarray(moments, dtype=float)
    bound = bind(torque, body_model(AXES_BODY), np.asarray(omega0, dtype=float))
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
