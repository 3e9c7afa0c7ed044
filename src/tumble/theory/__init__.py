"""Closed-form results of rigid-body rotation: no simulation, exact where an exact answer exists.

* :func:`skew_rod` — the rotating skew rod: L not parallel to ω, the torque and
  bearing forces it needs.
* :func:`rotor_loads` — the same for any body spun at a constant rate about a
  fixed axis (unbalanced rotors).
* :func:`flip_period` — period of ω(t) of a torque-free body (the tennis-racket flip).
* :func:`free_symmetric_top` — body and space cones of a torque-free symmetric top.
* :func:`axis_stability` — stability of steady rotation about each principal axis.
* :func:`gyroscope` — heavy symmetric top on a fixed pivot (Lagrange top):
  precession, nutation, the exact tilt θ(t) of a top released from rest.
* :func:`gyrocompass` — the gimballed gyroscope carried round a vertical axis.

Conventions as in the rest of tumble: SI units inside (numbers, pint quantities
or strings such as ``"3000 rpm"`` at the edge), angular velocity in body
coordinates unless said otherwise, inertia tensors about the centre of mass in
body axes unless a point is named, products of inertia ``I_xy = −Σ m x y``.
Each function but :func:`flip_period` returns a small immutable dataclass whose
docstring gives the units.

The lecture notes' gyrocompass equation ``I_AB θ̈ + Ω L_s sin θ = 0`` is the
fast-spin approximation: it drops ``−I_AB Ω² sin θ cos θ``, which
:func:`gyrocompass` keeps.
"""

from __future__ import annotations

from tumble.theory.compass import Gyrocompass, gyrocompass
from tumble.theory.free import (
    AxisStability,
    FreeMotion,
    FreeSymmetricTop,
    axis_stability,
    flip_period,
    free_motion,
    free_symmetric_top,
)
from tumble.theory.rotors import RotorLoads, SkewRod, rotor_loads, skew_rod
from tumble.theory.tops import Gyroscope, gyroscope

__all__ = [
    "AxisStability",
    "FreeMotion",
    "FreeSymmetricTop",
    "Gyrocompass",
    "Gyroscope",
    "RotorLoads",
    "SkewRod",
    "axis_stability",
    "flip_period",
    "free_motion",
    "free_symmetric_top",
    "gyrocompass",
    "gyroscope",
    "rotor_loads",
    "skew_rod",
]
