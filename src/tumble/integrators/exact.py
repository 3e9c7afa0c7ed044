"""The exact torque-free motion of a rigid body, at any times, without stepping.

ω from Jacobi elliptic functions (:func:`tumble.core.freebody.free_omega`); the
attitude written with z-x-z Euler angles about the fixed L (Landau & Lifshitz,
*Mechanics* §37): with L along the Z axis of a space frame R_L,
``A = R_L Rz(φ) Rx(θ) Rz(ψ)``, where ``cos θ = L3/L`` and ``tan ψ = L1/L2``
follow from ω, and φ is the integral of
``φ̇ = L (I1 ω1² + I2 ω2²)/(I1² ω1² + I2² ω2²)``
(:func:`tumble.core.freebody.free_precession_angle`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.body import ZERO_MOMENT, RigidBody
from tumble.errors import InputError
from tumble.massprops import MassProperties

__all__ = ["exact_principal", "exact_solution"]

Array = NDArray[np.float64]


def exact_solution(
    mp: MassProperties, omega0: Array, attitude0: Array, times: Array
) -> tuple[Array, Array]:
    """The exact torque-free motion of ``mp`` about its centre of mass at ``times``
    (s): ω (n, 3) in body axes, rad/s, and the attitude (n, 4) body → space, from
    ω0 (body axes, rad/s) and the unit quaternion ``attitude0``."""
    body = RigidBody(mp)
    moments = body.moments
    if moments[0] <= ZERO_MOMENT * moments[2]:
        raise InputError(
            f"Expected a body with no zero principal moment, got moments {moments.tolist()} kg·m²."
        )
    w, q = exact_principal(
        moments, body.to_principal(omega0), body.attitude_to_principal(attitude0), times
    )
    return body.from_principal(w), body.attitude_from_principal(q)


def exact_principal(moments: Array, w0: Array, q0: Array, times: Array) -> tuple[Array, Array]:
    """Exact torque-free ω (principal frame, rad/s) and attitude (principal →
    space) at ``times`` (s), from ω0 and q0 in the principal frame of the
    ascending principal ``moments`` (kg·m²)."""
    from tumble.core.freebody import free_attitude

    start = Rotation.from_quat(q0, scalar_first=True)
    on_axis = np.count_nonzero(w0 == 0.0) >= 2 or moments[0] == moments[2]
    if on_axis:
        # Steady rotation about a principal axis, or any rotation of a sphere.
        attitude = start * Rotation.from_rotvec(np.outer(times, w0))
        return np.tile(w0, (times.size, 1)), attitude.as_quat(scalar_first=True)
    l0 = moments * w0
    initial = Rotation.from_euler(
        "ZXZ", [0.0, np.arctan2(np.hypot(l0[0], l0[1]), l0[2]), np.arctan2(l0[0], l0[1])]
    )
    frame = (start * initial.inv()).as_quat(scalar_first=True)  # R_L: its z axis along L
    w, q = free_attitude(moments, w0, np.asarray(frame, dtype=float), times)
    return w, q
