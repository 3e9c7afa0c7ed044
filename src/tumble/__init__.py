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

from importlib.metadata import PackageNotFoundError, version

from tumble import shapes
from tumble.errors import InputError, MeshError
from tumble.kinematics import angular_momentum, kinetic_energy, required_torque
from tumble.massprops import MassProperties, point_masses
from tumble.mesh import MeshOrientationWarning, from_mesh

try:
    __version__ = version("tumble")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"

__all__ = [
    "InputError",
    "MassProperties",
    "MeshError",
    "MeshOrientationWarning",
    "__version__",
    "angular_momentum",
    "from_mesh",
    "kinetic_energy",
    "point_masses",
    "required_torque",
    "shapes",
]
