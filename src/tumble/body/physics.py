"""A body's angular momentum and kinetic energy, its parts' included, and the
quantities its motion conserves.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.invariants import FREE_BODY_INVARIANTS, reduce_invariants

if TYPE_CHECKING:
    from tumble.body.protocol import BodyModel

__all__ = ["Physics"]

Array = NDArray[np.float64]


class Physics:
    """L, the kinetic energy and the conserved quantities of a body
    (:class:`tumble.body.RigidBody`)."""

    def angular_momentum(self: BodyModel, omega: Array, values: Array | None = None) -> Array:
        """Angular momentum about the reference point, body axes, kg·m²/s, for ω
        (..., 3) rad/s: ``I ω`` without parts; with parts ``I_p ω`` plus each
        part's own (``values`` (..., m) the parts' values, None: their
        initial values, a damper turning with the body)."""
        omega = np.asarray(omega, dtype=float)
        momentum = omega @ self.platform_inertia.T
        for part, own in zip(self.parts, self.split_values(values, omega), strict=True):
            momentum = momentum + part.momentum(omega, own)
        return np.asarray(momentum)

    def kinetic_energy(self: BodyModel, omega: Array, values: Array | None = None) -> Array:
        """Kinetic energy, J, for ω (..., 3) rad/s in body axes: ``½ ω · I ω``, with
        the parts' own (``values`` as in :meth:`angular_momentum`)."""
        omega = np.asarray(omega, dtype=float)
        energy = 0.5 * np.einsum("...i,...i->...", omega, omega @ self.platform_inertia.T)
        for part, own in zip(self.parts, self.split_values(values, omega), strict=True):
            energy = energy + part.kinetic_energy(omega, own)
        return np.asarray(energy)

    def conserved(self: BodyModel, torques: Any) -> tuple[str, ...]:
        """The quantities (keys of :data:`tumble.invariants.INVARIANTS`) the motion
        of this body conserves under the torque models ``torques`` (those that act
        on it; see :meth:`tumble.torques.TorqueModel.conserves`): what a
        torque-free body conserves, less what each model changes. Internal parts
        keep L (their torques are internal); a motor or a damper changes the
        energy."""
        kept = set(FREE_BODY_INVARIANTS)
        if any(part.driven or part.dissipative for part in self.parts):
            kept.discard("energy")
        for torque in torques:
            if getattr(torque, "actuator", "external") == "rotors":
                kept.discard("energy")  # the motors do work; L moves between body and rotors
            else:
                kept &= torque.conserves(self)
        return reduce_invariants(kept)
