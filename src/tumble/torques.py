"""Torque models for :func:`tumble.simulate`.

Each model is a small immutable description; models add with ``+``. They are
turned into one packed parameter vector for the compiled integrators (see
:mod:`tumble.core.rigid`), so a sum of models costs no more per step than one.

* :class:`Gravity` — uniform gravity acting at the centre of mass; a torque only
  about a pivot (a free body's centre of mass feels none).
* :class:`ConstantBodyTorque` — fixed in body axes (a thruster, a motor).
* :class:`ConstantSpaceTorque` — fixed in space axes.
* :class:`LinearDamping` — ``τ = −c ω`` (bearing friction, air drag at low speed).
"""

from __future__ import annotations

from dataclasses import dataclass
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
]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class TorqueModel:
    """A sum of torque terms. Build with the model classes and ``+``.

    Attributes (SI): ``body`` N·m in body axes, ``space`` N·m in space axes,
    ``gravity`` m/s² in space axes, ``damping`` N·m·s.
    """

    body: Array
    space: Array
    gravity: Array
    damping: float

    def __add__(self, other: object) -> TorqueModel:
        if not isinstance(other, TorqueModel):
            return NotImplemented
        return TorqueModel(
            self.body + other.body,
            self.space + other.space,
            self.gravity + other.gravity,
            self.damping + other.damping,
        )

    def __radd__(self, other: object) -> TorqueModel:
        if isinstance(other, int) and other == 0:
            return self
        return NotImplemented

    @property
    def conservative(self) -> bool:
        """True when the torque derives from a potential (gravity only, or none): a
        free body under it is torque-free, gravity acting at its centre of mass."""
        return not (np.any(self.body) or np.any(self.space) or self.damping)

    def __repr__(self) -> str:
        terms = []
        if np.any(self.gravity):
            terms.append(f"Gravity({self.gravity.tolist()} m/s²)")
        if np.any(self.body):
            terms.append(f"ConstantBodyTorque({self.body.tolist()} N·m)")
        if np.any(self.space):
            terms.append(f"ConstantSpaceTorque({self.space.tolist()} N·m)")
        if self.damping:
            terms.append(f"LinearDamping({self.damping} N·m·s)")
        return " + ".join(terms) if terms else "no torque"


_ZERO = np.zeros(3)


def Gravity(
    acceleration: Any = (0.0, 0.0, -9.81),
) -> TorqueModel:  # named like a type: it builds one
    """Uniform gravity, the acceleration vector in space axes (m/s², default −9.81 ẑ)."""
    return TorqueModel(
        _ZERO, _ZERO, vector_to_si(acceleration, "acceleration", "acceleration"), 0.0
    )


def ConstantBodyTorque(torque: Any) -> TorqueModel:
    """A constant torque in body axes (N·m)."""
    return TorqueModel(vector_to_si(torque, "torque", "torque"), _ZERO, _ZERO, 0.0)


def ConstantSpaceTorque(torque: Any) -> TorqueModel:
    """A constant torque in space axes (N·m)."""
    return TorqueModel(_ZERO, vector_to_si(torque, "torque", "torque"), _ZERO, 0.0)


def LinearDamping(coefficient: Any) -> TorqueModel:
    """Viscous damping ``τ = −c ω`` with ``c`` >= 0 in N·m·s."""
    c = to_si(coefficient, "damping", "coefficient")
    if c < 0:
        raise InputError(f"Expected `coefficient` >= 0 N·m·s, got {c!r}.")
    return TorqueModel(_ZERO, _ZERO, _ZERO, c)
