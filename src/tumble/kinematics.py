"""Angular momentum, kinetic energy and the torque a given rotation needs.

All vectors are in **body** coordinates; ``omega`` is the angular velocity in
body coordinates (rad/s), ``omega_dot`` its time derivative in body
coordinates (rad/s²). Each function accepts one vector ``(3,)`` or a stack
``(n, 3)``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.massprops import MassProperties, as_mass_properties
from tumble.units import vector_to_si

__all__ = [
    "angular_momentum",
    "as_attitude",
    "kinetic_energy",
    "required_torque",
    "same_hemisphere",
]

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

    Examples
    --------
    A brick spun about a diagonal of its xy plane: ``L = I ω`` leans toward x,
    the axis of the larger moment, so it is not parallel to ω.

    >>> import numpy as np
    >>> import tumble as tb
    >>> brick = tb.shapes.box(1.0, [0.1, 0.2, 0.3])
    >>> L = tb.angular_momentum(brick, [1.0, 1.0, 0.0])
    >>> np.allclose(L, brick.inertia @ [1.0, 1.0, 0.0])
    True
    >>> print(f"L = ({L[0]:.6f}, {L[1]:.6f}, {L[2]:.6f}) kg·m²/s")
    L = (0.010833, 0.008333, 0.000000) kg·m²/s
    """
    w = _vectors(omega, "angular_velocity", "omega")
    return np.asarray(w @ _inertia(mp, about).T)


def kinetic_energy(mp: MassProperties, omega: Any, about: Any = None) -> Array | float:
    """Rotational kinetic energy ``½ ωᵀ I ω``, J.

    ``about`` as in :func:`angular_momentum`: None for rotation about the centre
    of mass, or a fixed body point (the total kinetic energy of a body turning
    about a pivot). Returns a float for one ω, an (n,) array for a stack.

    Examples
    --------
    A 2 kg ball of radius 10 cm at 10 rad/s: ``½ (2/5 m r²) ω² = 0.4 J``; at
    twice the rate, four times the energy.

    >>> import tumble as tb
    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)
    >>> print(f"{tb.kinetic_energy(ball, [0, 0, 10.0]):.6f} J")
    0.400000 J
    >>> print(tb.kinetic_energy(ball, [[0, 0, 10.0], [0, 0, 20.0]]).round(6))
    [0.4 1.6]

    A rod swinging about its end (``I = m L² / 3``):

    >>> rod = tb.shapes.thin_rod(3.0, 2.0)
    >>> print(f"{tb.kinetic_energy(rod, [2.0, 0, 0], about=[0, 0, 1.0]):.6f} J")
    8.000000 J
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

    Examples
    --------
    The skew rod: two 1 kg masses 0.5 m from the axis point, the rod 30° from
    the plane perpendicular to z, turned at a steady 10 rad/s about z, need
    ``2 m ℓ² ω² sin α cos α ≈ 21.65 N·m`` (compare
    :func:`tumble.theory.skew_rod`):

    >>> import numpy as np
    >>> import tumble as tb
    >>> tip = 0.5 * np.array([np.cos(np.pi / 6), 0.0, np.sin(np.pi / 6)])
    >>> rod = tb.point_masses([1.0, 1.0], [tip, -tip])
    >>> torque = tb.required_torque(rod, [0, 0, 10.0], [0, 0, 0])
    >>> print(f"{np.linalg.norm(torque):.4f} N·m")
    21.6506 N·m

    A ball spun up at 2 rad/s² needs only ``I ω̇``:

    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)
    >>> print(f"{tb.required_torque(ball, [0, 0, 10.0], [0, 0, 2.0])[2]:.6f} N·m")
    0.016000 N·m
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
    a quaternion (4,) of any non-zero length (normalised here) or a single scipy
    ``Rotation``."""
    if value is None:
        return np.array([1.0, 0.0, 0.0, 0.0])
    from scipy.spatial.transform import Rotation

    if isinstance(value, Rotation):
        if not value.single:
            raise InputError(f"Expected `{name}` to be a single rotation, got {len(value)}.")
        return np.asarray(value.as_quat(scalar_first=True), dtype=float)
    q = vector_to_si(value, "dimensionless", name, (4,))
    largest = float(np.max(np.abs(q)))
    if largest == 0.0:
        raise InputError(
            f"Expected `{name}` to be a non-zero quaternion [w, x, y, z], got {q.tolist()}."
        )
    # Divided by its largest component first: the squares of [1e300, 1e300, 0, 0]
    # overflow and those of [1e-300, 1e-300, 0, 0] underflow; only its direction counts.
    q = q / largest
    return np.asarray(q / math.sqrt(float(q @ q)))


def same_hemisphere(quaternion: Array) -> Array:
    """(n, 4) the attitudes ``quaternion`` (n, 4), each of sign chosen in the
    hemisphere of the one before (q and −q are one attitude), as a stepped
    attitude would be: for attitudes computed sample by sample in closed form."""
    flips = np.einsum("ij,ij->i", quaternion[1:], quaternion[:-1]) < 0
    signs = np.concatenate(([1.0], np.where(np.cumsum(flips) % 2 == 1, -1.0, 1.0)))
    return np.asarray(quaternion * signs[:, None])
