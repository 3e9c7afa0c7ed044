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
from tumble.parts import Rotor

__all__ = ["exact_principal", "exact_solution", "symmetric_gyrostat"]

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


def symmetric_gyrostat(
    body: RigidBody, omega0: Array, attitude0: Array, times: Array
) -> tuple[Array, Array, Array]:
    """The exact torque-free motion of a symmetric gyrostat
    (:meth:`tumble.body.RigidBody.symmetric_gyrostat_axis`): ω (n, 3) and the
    attitude (n, 4), body axes, and the rotors' values (n, k), at ``times`` (s).

    With e the symmetry axis, A and C the platform's transverse and axial
    moments and h the rotors' axial momentum along e (constant: no motor), the
    momentum in the body is ``H = A ω⊥ + (C ω_e + h) e``. Euler's equations
    give ``ω̇⊥ = λ e × ω⊥``, ``λ = ((C − A) ω_e + h) / A``, with ω_e constant:
    ω⊥ turns about e at λ. Since ``ω = (|H| / A) Ĥ − λ e``, the attitude is a
    turn about the fixed Ĥ at |H| / A after a turn about e at −λ (Hughes,
    *Spacecraft Attitude Dynamics*, §7.2; the rigid body's steady precession,
    Landau & Lifshitz §33, with the rotors' momentum added)."""
    axis = body.symmetric_gyrostat_axis()
    if axis is None:
        raise InputError(
            "Expected a symmetric gyrostat (two equal platform moments, rotors without "
            "motors on the axis of symmetry) for the exact solution, got another body."
        )
    e = np.eye(3)[axis]
    moments = body.moments
    transverse, axial = moments[(axis + 1) % 3], moments[axis]
    w0 = body.to_principal(np.asarray(omega0, dtype=float))
    values0 = body.initial_values(np.asarray(omega0, dtype=float))
    # Each rotor's axial momentum J (a·ω + Ω), along e with the sign of a·e.
    h = 0.0
    for k, part in enumerate(body.parts):
        assert isinstance(part, Rotor)  # symmetric_gyrostat_axis() said so
        own = float(part.momenta(np.asarray(omega0, dtype=float), values0[k : k + 1])[0])
        h += own * float(body.to_principal(part.axis) @ e)
    spin = float(w0 @ e)
    rate = ((axial - transverse) * spin + h) / transverse
    momentum = transverse * (w0 - spin * e) + (axial * spin + h) * e
    size = float(np.linalg.norm(momentum))
    start = Rotation.from_quat(body.attitude_to_principal(attitude0), scalar_first=True)
    direction = start.apply(momentum / size)  # Ĥ in space
    about_h = Rotation.from_rotvec(np.outer(times * size / transverse, direction))
    about_e = Rotation.from_rotvec(np.outer(-rate * times, e))
    attitude = about_h * start * about_e
    turned = Rotation.from_rotvec(np.outer(rate * times, e)).apply(w0 - spin * e)
    w = turned + spin * e
    omega = body.from_principal(w)
    q = body.attitude_from_principal(attitude.as_quat(scalar_first=True))
    return omega, q, np.tile(values0, (len(times), 1))
