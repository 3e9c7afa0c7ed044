"""tumble: the rotation of rigid bodies.

Mass properties and inertia tensors (solids, point masses, triangle meshes,
assemblies), angular momentum and the torque a given motion needs.

Conventions: SI units inside (pint quantities or strings such as ``"250 g"`` at
the edge); quaternions scalar-first ``[w, x, y, z]``, body → space; angular
velocity in body coordinates unless named ``_space``; products of inertia
``I_xy = −Σ m x y``; inertia about the centre of mass in body axes unless a
point is named; principal moments ascending with axes as the columns of a
proper rotation matrix.
"""

from __future__ import annotations

import importlib
from importlib.metadata import PackageNotFoundError, version
from typing import TYPE_CHECKING, Any

from tumble.errors import (
    InputError,
    MeshError,
    OutputError,
    OutputInUseError,
    RequestTooLargeError,
)

if TYPE_CHECKING:
    from tumble import analysis, models, shapes, theory, torques, units
    from tumble.batch import simulate_batch
    from tumble.kinematics import angular_momentum, kinetic_energy, required_torque
    from tumble.massprops import MassProperties, point_masses
    from tumble.mesh import MeshOrientationWarning, MeshRepairWarning, from_mesh
    from tumble.parts import KaneDamper, Rotor, SpringMassDamper
    from tumble.simulation import simulate
    from tumble.trajectory import Trajectory

try:
    __version__ = version("tumble")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"

# Public names load on first use, so `import tumble` (and `tumble --help`) does
# not pay for pint's registry or numba until they are needed.
_WHERE = {
    "MassProperties": "tumble.massprops",
    "point_masses": "tumble.massprops",
    "from_mesh": "tumble.mesh",
    "MeshOrientationWarning": "tumble.mesh",
    "MeshRepairWarning": "tumble.mesh",
    "angular_momentum": "tumble.kinematics",
    "kinetic_energy": "tumble.kinematics",
    "required_torque": "tumble.kinematics",
    "simulate": "tumble.simulation",
    "Trajectory": "tumble.trajectory",
    "simulate_batch": "tumble.batch",
    "Rotor": "tumble.parts",
    "KaneDamper": "tumble.parts",
    "SpringMassDamper": "tumble.parts",
    "identify": "tumble.identification.fit",
}
_SUBMODULES = {
    "analysis",
    "identification",
    "models",
    "shapes",
    "sweep",
    "symbolic",
    "theory",
    "torques",
    "units",
}

__all__ = [
    "InputError",
    "KaneDamper",
    "MassProperties",
    "MeshError",
    "MeshOrientationWarning",
    "MeshRepairWarning",
    "OutputError",
    "OutputInUseError",
    "RequestTooLargeError",
    "Rotor",
    "SpringMassDamper",
    "Trajectory",
    "__version__",
    "analysis",
    "angular_momentum",
    "from_mesh",
    "identification",
    "identify",
    "kinetic_energy",
    "models",
    "point_masses",
    "required_torque",
    "shapes",
    "simulate",
    "simulate_batch",
    "sweep",
    "theory",
    "torques",
    "units",
]


def __getattr__(name: str) -> Any:
    if name in _SUBMODULES:
        value: Any = importlib.import_module(f"tumble.{name}")
    elif name in _WHERE:
        value = getattr(importlib.import_module(_WHERE[name]), name)
    else:
        raise AttributeError(f"module 'tumble' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
