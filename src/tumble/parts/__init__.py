"""Parts a body carries inside it, each kind a registered plugin
(:data:`PARTS`, :func:`register_part`): :class:`Rotor` (reaction and momentum
wheels, the rotor of a dual-spin satellite), :class:`KaneDamper` (a sphere in
viscous fluid) and :class:`SpringMassDamper` (a point mass on a spring), the
two internal energy sinks.

**Convention.** A body's :class:`~tumble.MassProperties` hold every internal
part *as if it were locked to the body*: its mass and all of its inertia, about
the body's centre of mass, in body axes (build them with ``+``, e.g.
``hub + shapes.solid_cylinder(...).transformed(...)``). The part objects here
add only what locking hides: a rotor's spin relative to the body about its
axis, a damper's sphere turning inside its cavity. (Basilisk's reaction-wheel
effector, for comparison, takes the hub's inertia *without* the wheels and
adds them itself.)

What a part contributes, with ω the body's angular velocity (body axes):

* :class:`Rotor` (axis a, axial moment J, relative spin Ω): angular momentum
  ``J (a·ω + Ω) a`` beyond the locked ``J (a·ω) a``; kinetic energy
  ``h² / (2 J)`` with ``h = J (a·ω + Ω)`` its axial momentum;
* :class:`KaneDamper` (moment J, sphere angular velocity ω_s): ``J ω_s`` and
  ``J |ω_s|² / 2`` in place of the locked ``J ω`` and ``J |ω|² / 2``;
* :class:`SpringMassDamper` (mass m displaced by x along n): the change of the
  inertia about the moving centre of mass and the coupling of ẋ with ω, the
  kinetic energy of its sliding and the spring's elastic energy.

**A new kind** is one module: a frozen dataclass subclassing
:class:`InternalPart` with its parameters, state, energy and momentum, its
packed rows (:meth:`InternalPart.pack`) and its compiled equations
(:class:`tumble.core.parts.PartEquations`), decorated with
:func:`register_part`. The body's equations of motion with parts are in
:mod:`tumble.core.parts`, each kind's in its own module (:mod:`tumble.core.rotor`,
:mod:`tumble.core.dampers`).
"""

from __future__ import annotations

from tumble.parts.base import (
    PARTS,
    FilePart,
    InternalPart,
    PartDrawing,
    Siblings,
    TableKeyError,
    internal_rate,
    part_class,
    register_part,
)
from tumble.parts.dampers import KaneDamper, SpringMassDamper
from tumble.parts.packing import (
    check_parts,
    from_description,
    pack_parts,
    spin_columns,
    switch_times,
    value_columns,
)
from tumble.parts.rotor import Rotor

__all__ = [
    "PARTS",
    "FilePart",
    "InternalPart",
    "KaneDamper",
    "PartDrawing",
    "Rotor",
    "Siblings",
    "SpringMassDamper",
    "TableKeyError",
    "check_parts",
    "from_description",
    "internal_rate",
    "pack_parts",
    "part_class",
    "register_part",
    "spin_columns",
    "switch_times",
    "value_columns",
]
