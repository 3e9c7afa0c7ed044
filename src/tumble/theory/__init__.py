"""Closed-form results of rigid-body rotation: no simulation, exact where an exact answer exists.

* :func:`skew_rod` — the rotating skew rod: L not parallel to ω, the torque and
  bearing forces it needs.
* :func:`rotor_loads` — the same for any body turning about a fixed axis
  (unbalanced rotors), speeding up and under gravity: the drive torque too.
* :func:`pivot_loads` — the force and torque a support (a ball joint) exerts on
  a body in a given motion.
* :class:`RigidRotor` on :class:`Bearing` objects — a rigid rotor on elastic bearings:
  its whirl frequencies (Campbell diagram), critical speeds and unbalance
  response.
* :func:`flip_period` — period of ω(t) of a torque-free body (the tennis-racket flip).
* :func:`free_symmetric_top` — body and space cones of a torque-free symmetric top.
* :func:`axis_stability` — stability of steady rotation about each principal axis.
* :func:`gyroscope` — heavy symmetric top on a fixed pivot (Lagrange top):
  precession, nutation, the exact tilt θ(t) of a top released from rest.
* :func:`gyrocompass` — the gimballed gyroscope carried round a vertical axis.
* :func:`gyrostat_stability` — a body with rotors spinning about a principal
  axis: when the rotors stabilise it (dual spin), its nutation.
* :func:`kane_damper_decay` — the decay (or growth) of nutation by a damper:
  the major-axis rule.
* :func:`wheel_spin_up` — a wheel spun up by its motor in a body at rest.
* :func:`gravity_gradient_libration` — pitch and roll–yaw librations in a
  circular orbit, and their stability regions.
* :func:`attitude_slew` — a slew under quaternion feedback: its natural
  frequency and damping ratio.

The exact motions themselves, ω and the attitude at any time of the
torque-free rigid body and gyrostat and of the Lagrange top, are in
:mod:`tumble.theory.motions`: :func:`free_motion` and :func:`gyroscope`
evaluate them, and ``tumble.simulate(..., method="exact")`` samples them.

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

from tumble.theory.attitude import (
    AttitudeSlew,
    Libration,
    attitude_slew,
    gravity_gradient_libration,
)
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
from tumble.theory.gyrostats import (
    GyrostatStability,
    KaneDamperDecay,
    WheelSpinUp,
    gyrostat_stability,
    kane_damper_decay,
    wheel_spin_up,
)
from tumble.theory.loads import (
    PivotLoads,
    RotorLoads,
    SkewRod,
    pivot_loads,
    rotor_loads,
    skew_rod,
)
from tumble.theory.rotordynamics import Bearing, RigidRotor, Whirl
from tumble.theory.tops import Gyroscope, gyroscope

__all__ = [
    "AttitudeSlew",
    "AxisStability",
    "Bearing",
    "FreeMotion",
    "FreeSymmetricTop",
    "Gyrocompass",
    "Gyroscope",
    "GyrostatStability",
    "KaneDamperDecay",
    "Libration",
    "PivotLoads",
    "RigidRotor",
    "RotorLoads",
    "SkewRod",
    "WheelSpinUp",
    "Whirl",
    "attitude_slew",
    "axis_stability",
    "flip_period",
    "free_motion",
    "free_symmetric_top",
    "gravity_gradient_libration",
    "gyrocompass",
    "gyroscope",
    "gyrostat_stability",
    "kane_damper_decay",
    "pivot_loads",
    "rotor_loads",
    "skew_rod",
    "wheel_spin_up",
]
