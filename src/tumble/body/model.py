"""The rigid body model: a body's mass properties turning about a reference
point, the parts it carries, its platform inertia and principal frame.

:class:`RigidBody` gathers the concerns of the sibling modules (its frames,
its parts' state, its physics, its symmetries, its rates), each a mixin of
methods on the values defined here.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from tumble.body.frames import PrincipalFrame
from tumble.body.physics import Physics
from tumble.body.rates import StepRates
from tumble.body.state import PartsState
from tumble.body.symmetry import Symmetry
from tumble.errors import InputError
from tumble.massprops import MassProperties, principal_decomposition
from tumble.parts import InternalPart

__all__ = ["ZERO_MOMENT", "RigidBody"]

Array = NDArray[np.float64]

#: A principal moment below this fraction of the largest counts as zero: such a
#: body (a thin rod, point masses on a line) has an axis it cannot spin about,
#: and Euler's equations divide by each moment.
ZERO_MOMENT = 1e-12


@dataclass(frozen=True, eq=False)
class RigidBody(PrincipalFrame, PartsState, Physics, Symmetry, StepRates):
    """A rigid body turning about its reference point: the centre of mass
    (``pivot`` None) or a body point held fixed in space, possibly carrying parts.

    Attributes
    ----------
    mass_properties : the body, its parts included as if locked (its inertia about
        the centre of mass, body axes).
    pivot : None, or (3,) body coordinates of the fixed point, m.
    parts : the parts it carries (:mod:`tumble.parts`), in the order given.

    Raises
    ------
    InputError
        Parts whose spin inertia the body cannot hold (the platform inertia
        would not be positive definite).
    """

    mass_properties: MassProperties
    pivot: Array | None = None
    parts: tuple[InternalPart, ...] = ()

    def __post_init__(self) -> None:
        if self.parts:
            attached = tuple(part.attached(self.mass_properties) for part in self.parts)
            object.__setattr__(self, "parts", attached)
            for part in attached:
                if self.pivot is not None and part.free_body_only is not None:
                    raise InputError(
                        f"Expected a free body for a {type(part).__name__} "
                        f"({part.free_body_only}), got a pivot."
                    )
            moments = np.linalg.eigvalsh(0.5 * (self.platform_inertia + self.platform_inertia.T))
            if not moments[0] > ZERO_MOMENT * max(float(moments[2]), 0.0):
                locked = np.linalg.eigvalsh(self.inertia)
                left = np.round(moments, 12).tolist()
                raise InputError(
                    "Expected internal parts whose spin inertia the body can hold (each "
                    "rotor's J a aᵀ and each damper's J 1 taken from the body's inertia must "
                    f"leave positive principal moments), got {left} kg·m² left of the body's "
                    f"{np.round(locked, 12).tolist()} kg·m²: is a part's inertia missing from "
                    "the body's mass properties, or too large?"
                )

    @cached_property
    def reference_point(self) -> Array:
        """(3,) body coordinates of the point the body turns about, m."""
        mp = self.mass_properties
        return mp.center_of_mass if self.pivot is None else np.asarray(self.pivot, dtype=float)

    @cached_property
    def inertia(self) -> Array:
        """(3, 3) inertia about the reference point, body axes, kg·m² (the parts locked)."""
        mp = self.mass_properties
        return mp.inertia if self.pivot is None else mp.inertia_about(self.reference_point)

    @cached_property
    def platform_inertia(self) -> Array:
        """(3, 3) the inertia that turns at the body's own rate ω (kg·m², body axes,
        about the reference point): :attr:`inertia` less each part's spin inertia."""
        tensor = np.array(self.inertia, dtype=float)
        for part in self.parts:
            tensor -= part.spin_inertia()
        return tensor

    @cached_property
    def _principal(self) -> tuple[Array, Array]:
        if self.pivot is None and not self.parts:
            # The platform is the body: its decomposition, computed once per body. Copies,
            # writable: the kernels' arguments keep the type they were compiled for.
            moments, axes = self.mass_properties.principal()
            return np.array(moments), np.array(axes)
        return principal_decomposition(self.platform_inertia)

    @property
    def moments(self) -> Array:
        """(3,) principal moments of the platform inertia (the inertia about the
        reference point for a body without parts), ascending, kg·m²."""
        return self._principal[0]

    @property
    def axes(self) -> Array:
        """(3, 3) their principal axes as columns in body coordinates (a proper
        rotation): the frame the kernels work in."""
        return self._principal[1]

    @cached_property
    def inertia_principal(self) -> Array:
        """(3, 3) the whole inertia (parts locked) about the reference point in the
        principal axes of :attr:`moments`, kg·m² (diagonal without parts)."""
        return np.asarray(self.axes.T @ self.inertia @ self.axes)

    @cached_property
    def lever(self) -> Array:
        """(3,) from the reference point to the centre of mass, body axes, m."""
        return np.asarray(self.mass_properties.center_of_mass - self.reference_point)

    def check_simulable(self) -> None:
        """Raise InputError for a body with a zero principal moment."""
        moments = self.moments
        if moments[0] <= ZERO_MOMENT * moments[2]:
            raise InputError(
                f"Expected a body with no zero principal moment to simulate, got moments "
                f"{moments.tolist()} kg·m² (an idealised rod or point masses on a line: give the "
                "body some thickness)."
            )
