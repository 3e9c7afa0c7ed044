"""What the closed forms of :mod:`tumble.theory` share: checks of their inputs,
times given in any shape, turns about z, read-only results."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.massprops import PHYSICAL_TOLERANCE, MassProperties
from tumble.units import SI_UNITS, to_si, vector_to_si

__all__ = [
    "UNITS",
    "as_flat",
    "as_times",
    "check_moments",
    "format_values",
    "positive",
    "principal_state",
    "rotate_about_z",
]

Array = NDArray[np.float64]


def positive(value: Any, kind: str, name: str) -> float:
    """``value`` in SI, refused unless > 0."""
    result = to_si(value, kind, name)
    if result <= 0:
        unit = UNITS.get(kind, SI_UNITS[kind].replace("*", "·").replace("^2", "²"))
        raise InputError(f"Expected `{name}` > 0 {unit}, got {result!r}.")
    return result


UNITS = {"mass": "kg", "length": "m", "acceleration": "m/s²"}


def spin_axis(axis: Any) -> Array:
    """The unit vector of a spin ``axis`` given in body coordinates (any length > 0)."""
    direction = vector_to_si(axis, "dimensionless", "axis", (3,))
    length = float(np.linalg.norm(direction))
    if not length > 0:
        raise InputError(f"Expected `axis` to be a non-zero vector, got {direction.tolist()}.")
    return direction / length


def as_flat(value: Any, kind: str, name: str) -> tuple[Array, tuple[int, ...]]:
    """One value or a list of them (numbers, quantities or strings with units of
    ``kind``) in SI units as a flat array, and the shape given (``()`` for one)."""
    if np.ndim(value) == 0:
        return np.array([to_si(value, kind, name)]), ()
    values = vector_to_si(value, kind, name, (-1,))
    return values, values.shape


def as_times(t: Any) -> tuple[Array, tuple[int, ...]]:
    """Times in s as a flat array, and the shape of ``t`` (``()`` for a scalar)."""
    return as_flat(t, "time", "t")


def rotate_about_z(vectors: Array, angles: Array) -> Array:
    """Each (..., 3) vector turned by each angle about +z: result (n, ..., 3)."""
    c = np.cos(angles).reshape((-1,) + (1,) * (vectors.ndim - 1))
    s = np.sin(angles).reshape(c.shape)
    x, y, z = vectors[..., 0], vectors[..., 1], vectors[..., 2]
    return np.stack((c * x - s * y, s * x + c * y, np.broadcast_to(z, (c * x).shape)), axis=-1)


def check_moments(moments: Array, name: str) -> None:
    """Principal moments usable in Euler's equations: positive, triangle inequality."""
    if np.any(moments <= 0):
        raise InputError(
            f"Expected `{name}` to be three principal moments > 0 kg·m² (Euler's equations "
            f"divide by each; a thin rod or a point mass has none to spin about), "
            f"got {format_values(moments)}."
        )
    ordered = np.sort(moments)
    if ordered[0] + ordered[1] < ordered[2] * (1 - PHYSICAL_TOLERANCE):
        raise InputError(
            f"Expected `{name}` to satisfy the triangle inequality I1 + I2 >= I3, got "
            f"{format_values(moments)} kg·m² (no distribution of mass has these moments)."
        )


def principal_state(body: Any, omega0: Any, name: str) -> tuple[Array, Array, Array]:
    """Principal moments, ω0 in the principal frame, and the principal axes.

    ``body`` is a MassProperties (ω0 in its body axes; axes from ``principal()``,
    moments ascending) or three principal moments (ω0 in the same principal axes,
    axes the identity, moments in the order given).
    """
    omega = vector_to_si(omega0, "angular_velocity", "omega0", (3,))
    if isinstance(body, MassProperties):
        moments, axes = body.principal()
        moments = np.array(moments)
        omega = axes.T @ omega
    else:
        moments = vector_to_si(body, "inertia", name, (3,))
        axes = np.eye(3)
    check_moments(moments, name)
    return moments, omega, axes


def format_values(values: Any) -> str:
    """Numbers as ``[a, b, c]`` with six digits, for messages."""
    return "[" + ", ".join(f"{v:.6g}" for v in np.asarray(values, dtype=float)) + "]"
