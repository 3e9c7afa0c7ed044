"""The built-in engine adapters; importing this package registers them.

Each adapter imports its engine only when it is built, so the registry lists
every engine whether it is installed or not.
"""

from tumble.conformance.engine import ENGINES
from tumble.conformance.engines import (
    dart_engine,
    drake_engine,
    integrators,
    mujoco_engine,
    pybullet_engine,
    rapier_engine,
)

#: The order in which tables list the built-in engines: the physics engines, then the
#: ODE solvers a user would write by hand, then tumble's own integrators.
ORDER = ("mujoco", "pybullet", "drake", "dart", "rapier", "scipy", "tumble")

for _name in sorted(ENGINES, key=lambda name: ORDER.index(name) if name in ORDER else 0):
    ENGINES[_name] = ENGINES.pop(_name)

__all__ = [
    "ORDER",
    "dart_engine",
    "drake_engine",
    "integrators",
    "mujoco_engine",
    "pybullet_engine",
    "rapier_engine",
]
