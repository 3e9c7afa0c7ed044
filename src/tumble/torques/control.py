"""Attitude control: :class:`AttitudeController`, quaternion feedback acting
directly on the body (thrusters) or through its rotors (reaction wheels)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core import torques as kernels
from tumble.torques.model import Parameter, TorqueModel, register_torque
from tumble.units import unit_vector

__all__ = ["AttitudeController"]

Array = NDArray[np.float64]


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class AttitudeController(TorqueModel):
    """Quaternion feedback toward ``target``: the torque ``τ = −K ε − C ω`` on the
    body, its magnitude clipped to ``max_torque``.

    ε is the vector part of the error quaternion ``q_target⁻¹ ⊗ q`` (body axes;
    its sign chosen so its scalar part is >= 0, so the body turns the shorter
    way), ω the body's angular velocity (rad/s, body axes). For a rest-to-rest
    rotation by φ about a principal axis of moment I this is
    ``I φ̈ = −K sin(φ/2) − C φ̇``: small motions have the natural frequency
    √(K / (2 I)) and the damping ratio C / √(2 K I). The law is globally
    asymptotically stable for a rigid body (Wie, Weiss & Arapostathis, J. Guid.
    Control Dyn. 12 (1989) 375; Wie, *Space Vehicle Dynamics and Control*,
    §7.3).

    Parameters
    ----------
    target : the target attitude, a quaternion ``[w, x, y, z]`` (body → space;
        normalised here) or a scipy ``Rotation``.
    stiffness : K, N·m (> 0).
    damping : C, N·m·s (>= 0).
    max_torque : the largest torque magnitude, N·m (> 0; default no limit).
    actuator : ``"external"`` (thrusters, magnetorquers: a torque from outside)
        or ``"rotors"`` (the body's reaction wheels produce it: their motor
        torques share it out, within each wheel's own torque and speed limits,
        and the total angular momentum stays).
    """

    target: Any
    stiffness: Any
    damping: Any
    max_torque: Any = None
    actuator: str = "external"

    name = "attitude-control"
    closed_forms = frozenset({"slew"})
    summary = "quaternion feedback τ = −K ε − C ω toward a target attitude"
    parameters = (
        Parameter("target", "dimensionless", (4,), "target attitude quaternion [w, x, y, z]"),
        Parameter("stiffness", "torque", (), "proportional gain K", 0.0, strict=True),
        Parameter("damping", "damping", (), "rate gain C", 0.0),
        Parameter(
            "max_torque", "torque", (), "largest torque magnitude", 0.0, strict=True, optional=True
        ),
    )
    fields = ("target_w", "target_x", "target_y", "target_z", "stiffness", "damping", "max_torque")
    kernel = staticmethod(kernels.attitude_feedback)
    depends_on = frozenset({"attitude", "omega"})
    drives_rotors = True

    def __post_init__(self) -> None:
        target = self.target
        if hasattr(target, "as_quat"):
            object.__setattr__(self, "target", target.as_quat(scalar_first=True))
        super().__post_init__()
        unit = unit_vector(
            self.target,
            "target",
            noun="a non-zero quaternion [w, x, y, z]",
            shape=(4,),
            floor=1e-12,
        )
        object.__setattr__(self, "target", unit)

    def pack(self, body: Any, omega0: Array | None) -> Array:
        target = body.attitude_to_principal(self.target)
        largest = math.inf if self.max_torque is None else self.max_torque
        return np.concatenate([target, [self.stiffness, self.damping, largest]])
