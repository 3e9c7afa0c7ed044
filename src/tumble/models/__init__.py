"""Simulation models of mechanisms built around a rigid body.

* :func:`gyrocompass` — a spinning disk in a gimbal on a turning platform:
  the notes' gyrocompass (platform turning about the vertical), or a
  gyrocompass on the rotating Earth at a given latitude, settling north
  (:mod:`tumble.models.compass`).
* :func:`run_up` — a rigid rotor on elastic bearings run up through its
  critical speeds with an unbalance: its bearing orbits in time
  (:mod:`tumble.models.run_up`).

A model reduces the mechanism to its few degrees of freedom, integrates them
with a compiled kernel (:mod:`tumble.core.gimbal` for the gyrocompass) and
returns, besides its own coordinates, a :class:`tumble.Trajectory` of the
body's full attitude and angular velocity, so that everything that reads
trajectories (angular momentum, energy, Parquet files, the viewer) works on it.

Conventions as in the rest of tumble: SI units inside (numbers, pint
quantities or strings such as ``"20000 rpm"`` at the edge), quaternions
``[w, x, y, z]`` rotating body coordinates into space coordinates, angular
velocity in body coordinates unless a name says ``_space``.
"""

from __future__ import annotations

from tumble.models.compass import EARTH_ROTATION_RATE, GyrocompassRun, gyrocompass
from tumble.models.run_up import RunUp, run_up

__all__ = ["EARTH_ROTATION_RATE", "GyrocompassRun", "RunUp", "gyrocompass", "run_up"]
