"""The scenario file's ``[[internal]]`` tables: the rotors and dampers a body carries.

Each table is one part (:mod:`tumble.parts`)::

    [[internal]]
    type = "rotor"                 # a wheel spinning about a body-fixed axis
    axis = [0, 1, 0]
    mass = "4 kg"                  # a uniform disc: added to [body] at `position`
    radius = "15 cm"
    position = "0, 0.3, 0 m"
    speed = "3000 rpm"             # relative to the body
    torque = [["0 s", "0.05 N*m"], ["2 s", 0]]   # the motor: a constant, or a schedule

    [[internal]]
    type = "kane-damper"           # a sphere in viscous fluid: an energy sink
    inertia = "0.02 kg*m^2"        # already in [body], as if locked
    damping = "0.01 N*m*s"

    [[internal]]
    type = "spring-mass-damper"    # a point mass on a spring: another energy sink
    mass = "1 kg"                  # added to the body at `position`, its rest point
    position = "0, 0.4, 0 m"
    axis = [1, 0, 0]               # the direction it slides along
    stiffness = "6 N/m"
    damping = "1 N*s/m"

A part given by ``mass`` and ``radius`` is a uniform solid (a disc of
``thickness``, default a fifth of the radius, for a rotor; a sphere for a
damper) that tumble adds to the body at ``position``. A part given by its
``inertia`` is already in ``[body]``, as if locked to it (tumble's convention:
the body's mass properties hold every internal part); ``position`` then only
places its drawing. ``max_torque`` and ``max_speed`` limit a rotor's motor. A
spring–mass damper is always given by its ``mass`` (a point mass tumble adds at
``position``), with ``axis``, ``stiffness``, ``damping`` and optionally the
``displacement`` it starts at.
"""

from __future__ import annotations

import math
from typing import Annotated, Any

import numpy as np
from pydantic import model_validator

from tumble.config import StrictModel, key_error
from tumble.errors import InputError, unknown_choice
from tumble.scenario.bodies import (
    AngularVelocity,
    Length,
    LengthVector,
    Mass,
    Vector,
    scalar_field,
    vector_field,
)

__all__ = ["PART_KEYS", "InternalSpec"]

Inertia = Annotated[float, scalar_field("inertia", positive=True)]

#: The keys each kind of part takes besides ``type``, ``position`` and its size
#: (``inertia``, or ``mass`` and ``radius``).
PART_KEYS: dict[str, tuple[str, ...]] = {
    "rotor": ("axis", "speed", "torque", "max_torque", "max_speed", "thickness"),
    "kane-damper": ("damping",),
    "spring-mass-damper": ("axis", "stiffness", "damping", "displacement"),
}


class InternalSpec(StrictModel):
    """One ``[[internal]]`` table (see the module's docstring). Values in SI once
    validated; the schedule of ``torque`` and the limits are checked by the
    part itself (``part()``)."""

    type: str
    inertia: Inertia | None = None
    mass: Mass | None = None
    radius: Length | None = None
    thickness: Length | None = None
    position: LengthVector = (0.0, 0.0, 0.0)
    axis: Annotated[Vector, vector_field("dimensionless")] | None = None
    speed: AngularVelocity = 0.0
    torque: Any = 0.0
    max_torque: Any = None
    max_speed: Any = None
    damping: Any = None
    stiffness: Any = None
    displacement: Any = 0.0

    @model_validator(mode="after")
    def _consistent(self) -> InternalSpec:
        kinds = list(PART_KEYS)
        if self.type not in kinds:
            raise key_error("type", str(unknown_choice(self.type, kinds, "`type`")))
        given = {key for key in self.model_fields_set if key not in {"type", "position"}}
        spring = self.type == "spring-mass-damper"
        sizes = {"mass"} if spring else {"inertia", "mass", "radius"}
        allowed = {*sizes, *PART_KEYS[self.type]}
        for key in sorted(given - allowed):
            raise key_error(key, f"Expected no `{key}` for a {self.type}, got one.")
        if spring:
            for key, what in (("mass", "kg"), ("axis", "the direction it slides along"),
                              ("stiffness", "N/m")):  # fmt: skip
                if getattr(self, key) is None:
                    raise key_error(key, f"Expected `{key}` ({what}), which is missing.")
            return self
        by_mass = self.mass is not None or self.radius is not None
        if (self.inertia is not None) == by_mass:
            raise key_error(
                "inertia",
                f"Expected either `inertia` (a {self.type} already in [body]) or `mass` and "
                f"`radius` (a uniform one tumble adds), got "
                + ("both." if by_mass else "neither."),
            )
        if by_mass and (self.mass is None or self.radius is None):
            missing = "mass" if self.mass is None else "radius"
            other = "radius" if missing == "mass" else "mass"
            raise key_error(missing, f"Expected `{missing}` with `{other}`, which is missing.")
        if self.type == "rotor" and self.axis is None:
            raise key_error(
                "axis", "Expected `axis` (the rotor's spin axis, body axes), which is missing."
            )
        if self.type == "kane-damper" and self.damping is None:
            raise key_error("damping", "Expected `damping` (N·m·s), which is missing.")
        return self

    # ------------------------------------------------------------ to the library
    def solid(self) -> Any:
        """The uniform solid tumble adds to the body (a MassProperties at
        ``position``), or None for a part already in ``[body]``."""
        if self.type == "spring-mass-damper":
            from tumble.massprops import point_masses

            return point_masses([self.mass], [list(self.position)])
        if self.mass is None or self.radius is None:
            return None
        from scipy.spatial.transform import Rotation

        from tumble import shapes

        if self.type == "kane-damper":
            return shapes.solid_sphere(self.mass, self.radius).transformed(None, self.position)
        assert self.axis is not None  # checked on validation
        disc = shapes.solid_cylinder(self.mass, self.radius, self.disc_thickness)
        turn, _ = Rotation.align_vectors([self.axis], [[0.0, 0.0, 1.0]])
        return disc.transformed(turn, self.position)

    @property
    def disc_thickness(self) -> float:
        """A rotor's thickness, m (a fifth of its radius unless given)."""
        radius = self.radius if self.radius is not None else 0.0
        return self.thickness if self.thickness is not None else radius / 5.0

    def moment(self) -> float:
        """The part's J, kg·m²: given, or that of its uniform solid."""
        if self.inertia is not None:
            return self.inertia
        assert self.mass is not None and self.radius is not None  # checked on validation
        factor = 0.5 if self.type == "rotor" else 0.4
        moment = factor * self.mass * self.radius * self.radius
        if not math.isfinite(moment):
            raise InputError(
                f"Expected a {self.type} whose moment of inertia {factor} m r² is within "
                f"float64's range, got m = {self.mass:.6g} kg and r = {self.radius:.6g} m."
            )
        return moment

    def part(self) -> Any:
        """The library's part (:class:`tumble.Rotor` or :class:`tumble.KaneDamper`).

        Raises
        ------
        InputError
            A value the part refuses (a zero axis, a schedule out of order …).
        """
        from tumble.parts import KaneDamper, Rotor, SpringMassDamper

        if self.type == "spring-mass-damper":
            return SpringMassDamper(
                self.mass, self.position, self.axis, self.stiffness,
                0.0 if self.damping is None else self.damping, self.displacement,
            )  # fmt: skip
        if self.type == "kane-damper":
            return KaneDamper(self.moment(), self.damping)
        torque = self.torque
        if isinstance(torque, list) and torque and all(isinstance(p, list) for p in torque):
            torque = [tuple(pair) for pair in torque]
        return Rotor(
            self.axis, self.moment(), speed=self.speed, torque=torque,
            max_torque=self.max_torque, max_speed=self.max_speed,
        )  # fmt: skip

    def drawing_radius(self, reach: float) -> float:
        """The radius to draw it with, m: its own, or one from J for a body of
        size ``reach`` (a thin disc or a sphere of the body's density)."""
        if self.radius is not None:
            return self.radius
        return float(np.clip(0.2 * reach, 1e-3, None))
