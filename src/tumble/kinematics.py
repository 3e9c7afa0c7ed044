"""Angular momentum, kinetic energy and the torque a given rotation needs.

All vectors are in **body** coordinates; ``omega`` is the angular velocity in
body coordinates (rad/s), ``omega_dot`` its time derivative in body
coordinates (rad/s²). Each function accepts one vector ``(3,)`` or a stack
``(n, 3)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.massprops import MassProperties, as_mass_properties
from tumble.units import vector_to_si

__all__ = ["angular_momentum", "as_attitude", "kinetic_energy", "required_torque"]

Array = NDArray[np.float64]


def _vectors(value: Any, kind: str, name: str) -> Array:
    """A (3,) or (n, 3) SI array."""
    ndim = np.ndim(value) if not isinstance(value, str) else 1
    if ndim == 2:
        return vector_to_si(value, kind, name, (-1, 3))
    return vector_to_si(value, kind, name, (3,))


def _inertia(mp: Any, about: Any) -> Array:
    mp = as_mass_properties(mp)
    if about is None:
        return mp.inertia
    return mp.inertia_about(vector_to_si(about, "length", "about", (3,)))


def angular_momentum(mp: MassProperties, omega: Any, about: Any = None) -> Array:
    """Angular momentum ``L = I ω`` in body coordinates, kg·m²/s.

    Parameters
    ----------
    mp : the body.
    omega : (3,) or (n, 3) angular velocity in body coordinates, rad/s.
    about : None for the angular momentum about the centre of mass (valid for
        any motion: the spin part), or a body point (3,), m, about which the body
        rotates while that point stays fixed (a pivot); then ``I`` is the inertia
        about that point.

    Notes
    -----
    L is parallel to ω only when ω lies along a principal axis (the rotating
    skew rod is the classic counter-example).
    """
    w = _vectors(omega, "angular_velocity", "omega")
    return np.asarray(w @ _inertia(mp, about).T)


def kinetic_energy(mp: MassProperties, omega: Any, about: Any = None) -> Array | float:
    """Rotational kinetic energy ``½ ωᵀ I ω``, J.

    ``about`` as in :func:`angular_momentum`: None for rotation about the centre
    of mass, or a fixed body point (the total kinetic energy of a body turning
    about a pivot). Returns a float for one ω, an (n,) array for a stack.
    """
    w = _vectors(omega, "angular_velocity", "omega")
    energy = 0.5 * np.einsum("...i,ij,...j->...", w, _inertia(mp, about), w)
    return float(energy) if np.ndim(energy) == 0 else np.asarray(energy)


def required_torque(mp: MassProperties, omega: Any, omega_dot: Any, about: Any = None) -> Array:
    """Torque that makes the body follow a given rotation: ``τ = I ω̇ + ω × (I ω)``.

    Euler's equations in any body frame; all vectors in body coordinates, N·m.
    ``about`` as in :func:`angular_momentum` (None: about the centre of mass;
    a body point: about that fixed point). For a body spun at constant ω about
    an axis that is not principal (``omega_dot = 0``) this is the gyroscopic
    torque ``ω × L`` the bearings must supply.
    """
    w = _vectors(omega, "angular_velocity", "omega")
    w_dot = _vectors(omega_dot, "angular_acceleration", "omega_dot")
    inertia = _inertia(mp, about)
    if w.ndim == w_dot.ndim == 2 and w.shape != w_dot.shape:
        raise InputError(
            f"Expected `omega_dot` to have the shape of `omega` {w.shape} (or (3,)), "
            f"got {w_dot.shape}."
        )
    w, w_dot = np.broadcast_arrays(w, w_dot)
    return np.asarray(w_dot @ inertia.T + np.cross(w, w @ inertia.T))


def as_attitude(value: Any, name: str = "attitude0") -> Array:
    """A unit quaternion ``[w, x, y, z]`` (body → space) from None (the identity),
    a quaternion (4,) (normalised here) or a single scipy ``Rotation``."""
    from scipy.spatial.transform import Rotation

    if value is None:
        return np.array([1.0, 0.0, 0.0, 0.0])
    if isinstance(value, Rotation):
        if not value.single:
            raise InputError(f"Expected `{name}` to be a single rotation, got {len(value)}.")
        return np.asarray(value.as_quat(scalar_first=True), dtype=float)
    q = vector_to_si(value, "dimensionless", name, (4,))
    norm = float(np.linalg.norm(q))
    if norm < 1e-12:
        raise InputError(
            f"Expected `{name}` to be a non-zero quaternion [w, x, y, z], got {q.tolist()}."
        )
    return q / norm
