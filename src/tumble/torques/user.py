"""A torque from a user's function compiled with numba: :class:`UserTorque`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core import torques as kernels
from tumble.errors import InputError
from tumble.torques.model import TorqueModel

__all__ = ["UserTorque"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False, repr=False)
class UserTorque(TorqueModel):
    """A torque computed by ``function``, compiled with ``numba.njit``.

    ``function(t, omega, quaternion, params, out)`` writes the torque on the
    body in body axes (N·m) into ``out`` (3,), given the time ``t`` (s), the
    angular velocity ``omega`` (3,) in body axes (rad/s) and the attitude
    ``quaternion`` (4,), scalar first, body → space. ``params`` (a sequence of
    floats) is passed through unchanged, so one compiled function serves many
    parameter values. The function is called
    once here on a test state, so a wrong signature fails now, not mid-run.

    Examples
    --------
    >>> import numba
    >>> @numba.njit
    ... def magnetic_damper(t, omega, quaternion, params, out):
    ...     out[0] = -params[0] * omega[0] ** 3
    >>> model = UserTorque(magnetic_damper, [0.01])
    """

    function: Any
    params: Any = ()
    actuator: str = "external"

    name = "user"
    summary = "a torque from a function compiled with numba"
    kernel = staticmethod(kernels.user_torque)
    depends_on = frozenset({"attitude", "time", "omega"})
    in_files = False
    one_per_sum = "compute both torques in one function"
    drives_rotors = True

    def __post_init__(self) -> None:
        from numba.core.dispatcher import Dispatcher

        super().__post_init__()
        function = self.function
        if not isinstance(function, Dispatcher):
            raise InputError(
                "Expected `function` to be compiled with numba.njit, got "
                f"{type(function).__name__} {getattr(function, '__name__', '')!r}."
            )
        values = np.asarray(self.params, dtype=float).reshape(-1).copy()
        try:
            function(0.0, np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]), values, np.zeros(3))
        except Exception as exc:  # numba raises its own typing errors
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise InputError(
                "Expected `function(t, omega, quaternion, params, out)` to run on a test state "
                f"(t = 0, omega = 0, identity attitude), got {type(exc).__name__}: {first}"
            ) from None
        values.flags.writeable = False
        object.__setattr__(self, "params", values)

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return np.zeros(0)

    def context(self, body: Any) -> Any:
        callback = _callback(self.function)
        return (
            np.ascontiguousarray(body.axes),
            np.asarray(body.principal_rotation.as_quat(scalar_first=True), dtype=float),
            np.array(self.params, dtype=float),  # writable copy
            np.zeros(3),
            np.zeros(4),
            np.zeros(3),
            callback,
        )

    def __repr__(self) -> str:
        name = getattr(self.function, "__name__", "function")
        through = "" if self.actuator == "external" else f", actuator={self.actuator!r}"
        return f"UserTorque({name}, params={np.asarray(self.params).tolist()}{through})"


#: One C callback per user function, compiled on first use.
_CALLBACKS: dict[Any, Any] = {}


def _callback(function: Any) -> Any:
    callback = _CALLBACKS.get(function)
    if callback is None:
        callback = _CALLBACKS[function] = kernels.compile_user_torque(function)
    return callback
