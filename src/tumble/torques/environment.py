"""Torques of a body's surroundings in space: :class:`GravityGradient`."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core import torques as kernels
from tumble.errors import InputError
from tumble.torques.model import Parameter, TorqueModel, register_torque

__all__ = ["GravityGradient"]

Array = NDArray[np.float64]


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class GravityGradient(TorqueModel):
    """The gravity-gradient torque on a body in a circular orbit of rate ``orbit_rate``
    n (rad/s, > 0; n² = μ / a³), about its centre of mass: ``3 n² r × (I r)``, r the
    unit vector from the planet's centre to the body in body axes (Hughes,
    *Spacecraft Attitude Dynamics*, §8.1; Schaub & Junkins §4.6).

    In space axes r starts at ``radial0`` and turns about ``orbit_normal`` at n
    (``radial0`` is taken perpendicular to the normal: its component along the
    normal is dropped). The body's centre of mass stays where the simulation
    puts it: the orbit's translation does not enter the rotation. A body in a
    circular orbit keeps no energy or L in space axes (the torque depends on
    time); it keeps a Jacobi integral in the orbiting frame.
    """

    orbit_rate: Any
    orbit_normal: Any = (0.0, 0.0, 1.0)
    radial0: Any = (1.0, 0.0, 0.0)

    name = "gravity-gradient"
    closed_forms = frozenset({"libration"})
    summary = "the gravity-gradient torque of a circular orbit, 3 n² r × (I r)"
    parameters = (
        Parameter("orbit_rate", "angular_velocity", (), "orbit rate n", 0.0, strict=True),
        Parameter("orbit_normal", "dimensionless", (3,), "normal of the orbit plane, space axes"),
        Parameter("radial0", "dimensionless", (3,), "unit vector to the body at t = 0, space"),
    )
    fields = (
        "orbit_rate",
        "radial_x",
        "radial_y",
        "radial_z",
        "along_x",
        "along_y",
        "along_z",
        "inertia_11",
        "inertia_22",
        "inertia_33",
        "inertia_12",
        "inertia_13",
        "inertia_23",
    )
    kernel = staticmethod(kernels.gravity_gradient)
    depends_on = frozenset({"attitude", "time"})
    in_batches = True

    def __post_init__(self) -> None:
        super().__post_init__()
        if not np.linalg.norm(self.orbit_normal) > 0:
            raise InputError(
                "Expected `orbit_normal` to be a non-zero vector, got "
                f"{np.asarray(self.orbit_normal).tolist()}."
            )

    def plane(self) -> tuple[Array, Array]:
        """(e1, e2): r = e1 cos n t + e2 sin n t, space axes."""
        e1, e2 = self._plane
        return e1.copy(), e2.copy()

    @cached_property
    def _plane(self) -> tuple[Array, Array]:
        normal = np.asarray(self.orbit_normal, dtype=float)
        normal = normal / np.linalg.norm(normal)
        radial = np.asarray(self.radial0, dtype=float)
        radial = radial - (radial @ normal) * normal
        size = float(np.linalg.norm(radial))
        if not size > 1e-12 * max(float(np.linalg.norm(self.radial0)), 1e-300):
            raise InputError(
                "Expected `radial0` off the orbit's normal (the direction to the body in the "
                f"orbit plane), got {np.asarray(self.radial0).tolist()} along "
                f"{normal.tolist()}."
            )
        e1 = radial / size
        e2 = np.cross(normal, e1)
        e1.flags.writeable = e2.flags.writeable = False
        return e1, e2

    def pack(self, body: Any, omega0: Array | None) -> Array:
        if getattr(body, "pivot", None) is not None:
            raise InputError(
                "Expected a free body for GravityGradient (the torque is about the centre of "
                "mass), got a pivot."
            )
        e1, e2 = self._plane  # found once per model
        # The whole inertia (parts locked: a spinning wheel's mass distribution is
        # the same) in the kernels' axes: (1 or N, 3, 3).
        tensors = np.asarray(body.inertia_principal, dtype=float).reshape(-1, 3, 3)
        packed = np.empty((len(self.fields), tensors.shape[0]))
        packed[0] = np.broadcast_to(np.asarray(self.orbit_rate, dtype=float), packed.shape[1:])
        packed[1:4] = e1[:, None]
        packed[4:7] = e2[:, None]
        for row, (i, j) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)), start=7):
            packed[row] = tensors[:, i, j]
        return packed
