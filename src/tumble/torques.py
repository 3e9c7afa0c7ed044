"""Torque models for :func:`tumble.simulate`.

Each model is a small immutable description; models add with ``+``. They are
turned into one packed parameter vector for the compiled integrators (see
:mod:`tumble.core.rigid`), so a sum of models costs no more per step than one.

* :class:`Gravity` — uniform gravity acting at the centre of mass; a torque only
  about a pivot (a free body's centre of mass feels none).
* :class:`ConstantBodyTorque` — fixed in body axes (a thruster, a motor).
* :class:`ConstantSpaceTorque` — fixed in space axes.
* :class:`LinearDamping` — ``τ = −c ω`` (bearing friction, air drag at low speed).
* :class:`UserTorque` — any torque, from a function compiled with numba.

A user torque function has the signature::

    @numba.njit
    def torque(t, omega, quaternion, params, out):
        ...

with ``t`` the time (s), ``omega`` (3,) the angular velocity in body axes
(rad/s), ``quaternion`` (4,) the attitude ``[w, x, y, z]`` (body → space),
``params`` the float64 array given to :class:`UserTorque`, and ``out`` (3,) a
zeroed array to fill with the torque on the body in body axes (N·m). It must
not keep references to its arguments (they are scratch buffers). The
integrators are compiled once per process for each function (a few seconds).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.units import to_si, vector_to_si

__all__ = [
    "ConstantBodyTorque",
    "ConstantSpaceTorque",
    "Gravity",
    "LinearDamping",
    "TorqueModel",
    "UserTorque",
]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class TorqueModel:
    """A sum of torque terms. Build with the model classes and ``+``.

    Attributes (SI): ``body`` N·m in body axes, ``space`` N·m in space axes,
    ``gravity`` m/s² in space axes, ``damping`` N·m·s; ``function`` a user's
    compiled torque function (or None) and ``function_params`` its parameters.
    """

    body: Array
    space: Array
    gravity: Array
    damping: Any  # float, or (N,) per body
    function: Any = None
    function_params: Array = field(default_factory=lambda: np.zeros(0))

    def __add__(self, other: object) -> TorqueModel:
        if not isinstance(other, TorqueModel):
            return NotImplemented
        if self.function is not None and other.function is not None:
            raise InputError(
                "Expected at most one UserTorque in a sum, got two (compute both torques in "
                "one function)."
            )
        user = self if self.function is not None else other
        try:
            return TorqueModel(
                self.body + other.body,
                self.space + other.space,
                self.gravity + other.gravity,
                self.damping + other.damping,
                user.function,
                user.function_params,
            )
        except ValueError:  # numpy: per-body terms of different lengths
            raise InputError(
                "Expected per-body torque terms for the same number of bodies, got "
                f"{self!r} and {other!r}."
            ) from None

    def __radd__(self, other: object) -> TorqueModel:
        if isinstance(other, int) and other == 0:
            return self
        return NotImplemented

    @property
    def conservative(self) -> bool:
        """True when the torque derives from a potential (gravity only, or none): a
        free body under it is torque-free, gravity acting at its centre of mass."""
        return not (
            np.any(self.body)
            or np.any(self.space)
            or np.any(self.damping)
            or self.function is not None
        )

    @property
    def per_body(self) -> bool:
        """True when some term has one value per body (for batches)."""
        return bool(np.ndim(self.body) == 2 or np.ndim(self.space) == 2 or np.ndim(self.damping))

    def __repr__(self) -> str:
        terms = []
        if np.any(self.gravity):
            terms.append(f"Gravity({self.gravity.tolist()} m/s²)")
        for name, value in (("ConstantBodyTorque", self.body), ("ConstantSpaceTorque", self.space)):
            if value.ndim == 2:
                terms.append(f"{name}(per body, {len(value)} vectors)")
            elif np.any(value):
                terms.append(f"{name}({value.tolist()} N·m)")
        if np.ndim(self.damping):
            terms.append(f"LinearDamping(per body, {np.size(self.damping)} values)")
        elif self.damping:
            terms.append(f"LinearDamping({self.damping} N·m·s)")
        if self.function is not None:
            name = getattr(self.function, "__name__", "function")
            terms.append(f"UserTorque({name}, params={self.function_params.tolist()})")
        return " + ".join(terms) if terms else "no torque"


_ZERO = np.zeros(3)


def Gravity(
    acceleration: Any = (0.0, 0.0, -9.81),
) -> TorqueModel:  # named like a type: it builds one
    """Uniform gravity, the acceleration vector in space axes (m/s², default −9.81 ẑ)."""
    return TorqueModel(
        _ZERO, _ZERO, vector_to_si(acceleration, "acceleration", "acceleration"), 0.0
    )


def _torque_vector(torque: Any) -> Array:
    """(3,) for one body, or (N, 3) per body for :func:`tumble.simulate_batch`."""
    shape = (-1, 3) if np.ndim(torque) == 2 else (3,)
    return vector_to_si(torque, "torque", "torque", shape)


def ConstantBodyTorque(torque: Any) -> TorqueModel:
    """A constant torque in body axes (N·m): (3,), or (N, 3) one per body of a batch."""
    return TorqueModel(_torque_vector(torque), _ZERO, _ZERO, 0.0)


def ConstantSpaceTorque(torque: Any) -> TorqueModel:
    """A constant torque in space axes (N·m): (3,), or (N, 3) one per body of a batch."""
    return TorqueModel(_ZERO, _torque_vector(torque), _ZERO, 0.0)


def LinearDamping(coefficient: Any) -> TorqueModel:
    """Viscous damping ``τ = −c ω`` with ``c`` >= 0 in N·m·s: a number, or (N,) one
    per body of a batch."""
    if np.ndim(coefficient) == 1:
        c: Any = vector_to_si(coefficient, "damping", "coefficient", (-1,))
        if np.any(c < 0):
            k = int(np.argmin(c))
            raise InputError(
                f"Expected `coefficient` >= 0 N·m·s, got coefficient[{k}] = {float(c[k])!r}."
            )
        return TorqueModel(_ZERO, _ZERO, _ZERO, c)
    c = to_si(coefficient, "damping", "coefficient")
    if c < 0:
        raise InputError(f"Expected `coefficient` >= 0 N·m·s, got {c!r}.")
    return TorqueModel(_ZERO, _ZERO, _ZERO, c)


def UserTorque(function: Any, params: Any = ()) -> TorqueModel:
    """A torque computed by ``function``, compiled with ``numba.njit``.

    ``function(t, omega, quaternion, params, out)`` writes the torque on the
    body in body axes (N·m) into ``out``; see this module's docstring for the
    arguments. ``params`` (a sequence of floats) is passed through unchanged, so
    one compiled function serves many parameter values. The function is called
    once here on a test state, so a wrong signature fails now, not mid-run.

    Example
    -------
    >>> import numba
    >>> @numba.njit
    ... def magnetic_damper(t, omega, quaternion, params, out):
    ...     out[0] = -params[0] * omega[0] ** 3
    >>> model = UserTorque(magnetic_damper, [0.01])
    """
    from numba.core.dispatcher import Dispatcher

    if not isinstance(function, Dispatcher):
        raise InputError(
            "Expected `function` to be compiled with numba.njit, got "
            f"{type(function).__name__} {getattr(function, '__name__', '')!r}."
        )
    values = np.asarray(params, dtype=float).reshape(-1).copy()
    out = np.zeros(3)
    try:
        function(0.0, np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]), values, out)
    except Exception as exc:  # numba raises its own typing errors
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputError(
            "Expected `function(t, omega, quaternion, params, out)` to run on a test state "
            f"(t = 0, omega = 0, identity attitude), got {type(exc).__name__}: {first}"
        ) from None
    values.flags.writeable = False
    return TorqueModel(_ZERO, _ZERO, _ZERO, 0.0, function, values)
