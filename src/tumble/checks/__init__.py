"""Theory checks: each closed form a simulation can be compared with, in one registry.

* :data:`THEORY_CHECKS` — the checks by name, in the order ``auto`` tries them:
  ``dual-spin`` and ``energy-sink`` (:mod:`~tumble.checks.gyrostats`),
  ``libration`` and ``slew`` (:mod:`~tumble.checks.attitude`), ``gyroscope``
  (:mod:`~tumble.checks.tops`), ``rotor-loads`` (:mod:`~tumble.checks.loads`),
  ``free-symmetric-top`` and ``flip-period`` (:mod:`~tumble.checks.free`),
  ``gyrocompass`` (:mod:`~tumble.checks.gyrocompass`), ``rigid-rotor``
  (:mod:`~tumble.checks.rigid_rotor`).
* :func:`choose_check` — the check a scenario's ``[theory] model`` names, or
  the first that fits its case.
* :func:`compare`, :func:`comparison_row`, :func:`comparison_table` — closed-form
  results next to the same quantities measured on a trajectory.

A new check is a :class:`TheoryCheck` subclass and one :func:`register_check`
call: scenario files can then name it.
"""

from __future__ import annotations

from tumble.checks.attitude import LibrationCheck, SlewCheck
from tumble.checks.base import (
    THEORY_CHECKS,
    Case,
    Comparison,
    Curve,
    Panel,
    TheoryCheck,
    choose_check,
    compare,
    comparison_row,
    comparison_table,
    register_check,
)
from tumble.checks.free import FlipPeriodCheck, FreeSymmetricTopCheck
from tumble.checks.gyrocompass import GyrocompassCheck
from tumble.checks.gyrostats import DualSpinCheck, EnergySinkCheck
from tumble.checks.loads import RotorLoadsCheck
from tumble.checks.rigid_rotor import RigidRotorCheck
from tumble.checks.tops import GyroscopeCheck

# In the order `auto` tries them: the most specific cases first.
for _check in (
    DualSpinCheck(),
    EnergySinkCheck(),
    LibrationCheck(),
    SlewCheck(),
    GyroscopeCheck(),
    RotorLoadsCheck(),
    FreeSymmetricTopCheck(),
    FlipPeriodCheck(),
    GyrocompassCheck(),
    RigidRotorCheck(),
):
    register_check(_check)

__all__ = [
    "THEORY_CHECKS",
    "Case",
    "Comparison",
    "Curve",
    "Panel",
    "TheoryCheck",
    "choose_check",
    "compare",
    "comparison_row",
    "comparison_table",
    "register_check",
]
