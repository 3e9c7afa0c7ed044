"""The rates a time step must resolve: the body's fastest rotation, its swing
about a pivot, its parts' own motion.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from tumble.invariants import largest_rate

if TYPE_CHECKING:
    from tumble.body.protocol import BodyModel

__all__ = ["StepRates"]

Array = NDArray[np.float64]


class StepRates:
    """The fastest rates of a body's motion (:class:`tumble.body.RigidBody`), for
    the choice and the checks of a time step."""

    def fastest_rate(
        self: BodyModel, omega: Array, weight: float, exact_spin: bool = False
    ) -> float:
        """An upper estimate of the fastest angular rate a time step must resolve, rad/s.

        Torque-free, the largest |ω| the motion reaches (``omega`` in body axes,
        rad/s): :func:`tumble.invariants.largest_rate`, exact, where the bound |L| / I1 would
        overstate an elongated body's rate many times. A body on a pivot under a
        weight ``weight`` (N) adds the pendulum rate √(m g l / I1). With
        ``exact_spin`` (integrators whose free flow turns a symmetric body
        exactly), a symmetric body's spin about its symmetry axis needs no
        resolving: the rate is |L| / I⊥, that of the precession of the axis
        about L (and of nutation). With parts, ω = I_p⁻¹ (L − the parts'
        momenta) stays below (|L| + |the parts' momenta|) / I1 (platform
        moments; their momenta at t = 0: a motor changes them).
        """
        moments = self.moments
        principal = self.to_principal(omega)
        # Norms by hypot: no overflow of the squares of a body of 1e300 kg.
        if self.parts:
            total, momenta = self._initial_momenta(omega)
            momentum = math.hypot(*total.tolist()) + sum(
                math.hypot(*np.ravel(own).tolist()) for own in momenta
            )
            rate = momentum / moments[0]
        # principal_decomposition makes repeated moments exactly equal: I⊥ = I2 for
        # a prolate body (I2 = I3) and an oblate one (I1 = I2).
        elif exact_spin and moments[1] in (moments[0], moments[2]):
            rate = math.hypot(*(moments / moments[1] * principal))  # |L| / I⊥
        else:
            rate = largest_rate(moments, principal)
        return rate + self.pendulum_rate(weight)

    def internal_rate(self: BodyModel) -> tuple[float, list[str]]:
        """An upper bound of the fastest rate of the parts' own motion relative to
        the platform, 1/s, and the kinds of parts it comes from (0 and none
        without such parts): what an explicit step must keep within its
        stability interval (:func:`tumble.parts.internal_rate`)."""
        rate, names = self._internal_rate
        return rate, list(names)

    @cached_property
    def _internal_rate(self: BodyModel) -> tuple[float, tuple[str, ...]]:
        from tumble.parts import internal_rate

        if not self.parts:
            return 0.0, ()
        rate, names = internal_rate(self.parts, self.platform_inertia)
        return rate, tuple(names)

    def pendulum_rate(self: BodyModel, weight: float) -> float:
        """√(m g l / I1), rad/s: an upper estimate of the rate of the swing that a
        weight ``weight`` (N) at the centre of mass drives about the pivot (0
        for a free body)."""
        if self.pivot is None:
            return 0.0
        return math.sqrt(weight * float(np.linalg.norm(self.lever)) / self.moments[0])
