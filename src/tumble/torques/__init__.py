"""Torque models for :func:`tumble.simulate` and :func:`tumble.simulate_batch`, and their registry.

Each model is one class, registered under the name scenario files give it
(``[[torques]] type = "constant-body"``). The class says everything the rest of
tumble needs, so that nothing else names a torque: its parameters (units,
shapes, limits, per-body sweep names), the fields it packs for its compiled
function in :mod:`tumble.core.torques` (one shared signature), what it
depends on, whether it is conservative and its potential energy (which
:attr:`tumble.Trajectory.energy` adds), whether it is uniform gravity (a heavy
top's closed form), whether batches may give it one value per body, and which
quantities the motion keeps under it.

* :class:`Gravity` — uniform gravity acting at the centre of mass; a torque only
  about a pivot (a free body's centre of mass feels none).
* :class:`ConstantBodyTorque` — fixed in body axes (a thruster, a motor).
* :class:`ConstantSpaceTorque` — fixed in space axes.
* :class:`LinearDamping` — ``τ = −c ω`` (bearing friction, air drag at low speed).
* :class:`AxisDrag` — linear drag per body axis, ``τᵢ = −cᵢ ωᵢ`` (a thrown object).
* :class:`QuadraticDrag` — quadratic drag per body axis, ``τᵢ = −cᵢ ωᵢ |ωᵢ|``.
* :class:`GravityGradient` — the torque of a circular orbit, ``3 n² r × (I r)``.
* :class:`HoldRotation` — the body-fixed torque ``ω0 × (I ω0)`` that keeps the
  initial rotation steady (a motor holding a shaft at a constant rate).
* :class:`RotorMomentum` — rotors of prescribed relative momentum h(t): the
  gyroscopic torque ``−ω × h − ḣ`` (batches and sweeps of gyrostats).
* :class:`AttitudeController` — quaternion feedback ``τ = −K ε − C ω`` toward a
  target attitude, from outside or through the body's rotors (reaction wheels).
* :class:`UserTorque` — any torque, from a function compiled with numba.

Models whose class has ``drives_rotors`` take ``actuator="rotors"``: their
torque is then produced by the body's rotors (:class:`tumble.Rotor`), whose
motor torques share it out, and the body's total angular momentum stays.

Models add with ``+``. A new model is a subclass of :class:`TorqueModel`
decorated with :func:`register_torque`, plus its compiled function: simulate,
simulate_batch, sweeps and scenario files then accept it.

A user torque function has the signature::

    @numba.njit
    def torque(t, omega, quaternion, params, out):
        ...

with ``t`` the time (s), ``omega`` (3,) the angular velocity in body axes
(rad/s), ``quaternion`` (4,) the attitude ``[w, x, y, z]`` (body → space),
``params`` the float64 array given to :class:`UserTorque`, and ``out`` (3,) a
zeroed array to fill with the torque on the body in body axes (N·m). It must
not keep references to its arguments (they are scratch buffers). A conservative
torque also gives its potential energy, compiled with numba too::

    @numba.njit
    def potential(t, quaternion, params):
        ...
        return energy  # J

passed as ``UserTorque(torque, params, potential=potential)``.
"""

from __future__ import annotations

from tumble.torques.binding import BoundTorque, bind
from tumble.torques.builtin import (
    AxisDrag,
    ConstantBodyTorque,
    ConstantSpaceTorque,
    Gravity,
    HoldRotation,
    LinearDamping,
    QuadraticDrag,
    RotorMomentum,
)
from tumble.torques.control import AttitudeController
from tumble.torques.environment import GravityGradient
from tumble.torques.model import (
    ACTUATORS,
    TORQUES,
    Parameter,
    TorqueModel,
    TorqueSum,
    from_description,
    register_torque,
)
from tumble.torques.user import UserTorque

__all__ = [
    "ACTUATORS",
    "TORQUES",
    "AttitudeController",
    "AxisDrag",
    "BoundTorque",
    "ConstantBodyTorque",
    "ConstantSpaceTorque",
    "Gravity",
    "GravityGradient",
    "HoldRotation",
    "LinearDamping",
    "Parameter",
    "QuadraticDrag",
    "RotorMomentum",
    "TorqueModel",
    "TorqueSum",
    "UserTorque",
    "bind",
    "from_description",
    "register_torque",
]
