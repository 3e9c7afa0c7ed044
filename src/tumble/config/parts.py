"""The ``[[internal]]`` tables of scenario and sweep files: the parts a body carries.

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

Each ``type`` is a part kind of the registry (:data:`tumble.parts.PARTS`), and
its other keys are that kind's (:meth:`tumble.parts.InternalPart.keys_in_files`).
A part given by ``mass`` and ``radius`` is a uniform solid (a disc of
``thickness``, default a fifth of the radius, for a rotor; a sphere for a
damper) that tumble adds to the body at ``position``. A part given by its
``inertia`` is already in ``[body]``, as if locked to it (tumble's convention:
the body's mass properties hold every internal part); ``position`` then only
places its drawing. ``max_torque`` and ``max_speed`` limit a rotor's motor. A
spring–mass damper is always given by its ``mass`` (a point mass tumble adds at
``position``), with ``axis``, ``stiffness``, ``damping`` and optionally the
``displacement`` it starts at.

In a sweep file, every body carries the parts of its ``[[internal]]`` tables,
given by their ``inertia``: the swept moments are the whole body's, its parts
held inside as if locked. The sweep's ``method`` must integrate them (``rk4``
takes every kind batches take; the splittings, rotors); its measures take the
total angular momentum H (body and parts) for L, and the energy of the body and
its parts (:attr:`tumble.core.parts.PartEquations.energy`).
"""

from __future__ import annotations

from typing import Any

from pydantic import model_validator

from tumble.config import StrictModel
from tumble.config.registries import part_entry

__all__ = ["InternalSpec"]


class InternalSpec(StrictModel):
    """One ``[[internal]]`` table: ``type``, a part kind of the registry
    (:data:`tumble.parts.PARTS`), and that kind's keys, with units. ``values``
    holds them in SI once validated; :meth:`file_part` makes the part."""

    type: str
    values: dict[str, Any] = {}

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any) -> Any:
        # Replaces the strict check of the base: the keys are the kind's own.
        return part_entry(data)

    def file_part(self) -> Any:
        """The part, the solid tumble adds to the body for it and where it is drawn
        (:class:`tumble.parts.FilePart`).

        Raises
        ------
        tumble.parts.TableKeyError
            A value wrong or missing, about one key.
        InputError
            A value the part refuses (a zero axis, a schedule out of order …).
        """
        from tumble.parts import part_class

        return part_class(self.type).from_table(self.values)
