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
import os
import sys
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    # What type checkers see: every name of _PUBLIC, imported where it is defined
    # ("X as X" marks it re-exported). tests/test_public.py holds it to the table.
    from tumble import analysis as analysis
    from tumble import conformance as conformance
    from tumble import identification as identification
    from tumble import models as models
    from tumble import robots as robots
    from tumble import rotordynamics as rotordynamics
    from tumble import shapes as shapes
    from tumble import sweep as sweep
    from tumble import symbolic as symbolic
    from tumble import theory as theory
    from tumble import torques as torques
    from tumble import units as units
    from tumble._version import __version__ as __version__
    from tumble.batch import simulate_batch as simulate_batch
    from tumble.errors import CoarseStepWarning as CoarseStepWarning
    from tumble.errors import InputError as InputError
    from tumble.errors import IntegrationError as IntegrationError
    from tumble.errors import MeshError as MeshError
    from tumble.errors import OutputError as OutputError
    from tumble.errors import OutputInUseError as OutputInUseError
    from tumble.errors import RequestTooLargeError as RequestTooLargeError
    from tumble.identification.fit import identify as identify
    from tumble.identification.many import identify_many as identify_many
    from tumble.kinematics import angular_momentum as angular_momentum
    from tumble.kinematics import kinetic_energy as kinetic_energy
    from tumble.kinematics import required_torque as required_torque
    from tumble.massprops import MassProperties as MassProperties
    from tumble.massprops import point_masses as point_masses
    from tumble.mesh import MeshOrientationWarning as MeshOrientationWarning
    from tumble.mesh import MeshRepairWarning as MeshRepairWarning
    from tumble.mesh import from_mesh as from_mesh
    from tumble.parts import KaneDamper as KaneDamper
    from tumble.parts import Rotor as Rotor
    from tumble.parts import SpringMassDamper as SpringMassDamper
    from tumble.simulation import simulate as simulate
    from tumble.trajectory import Trajectory as Trajectory

#: Every public name of the package and the module that defines it (a public
#: module maps to itself). ``__all__``, ``dir(tumble)`` and the loader below are
#: made from it. Names load on first use, so that ``import tumble`` (and
#: ``tumble --help``) pays for neither numba nor pint's registry until needed.
_PUBLIC = {
    "__version__": "tumble._version",
    # mass properties
    "MassProperties": "tumble.massprops",
    "point_masses": "tumble.massprops",
    "from_mesh": "tumble.mesh",
    # motion
    "angular_momentum": "tumble.kinematics",
    "kinetic_energy": "tumble.kinematics",
    "required_torque": "tumble.kinematics",
    "simulate": "tumble.simulation",
    "simulate_batch": "tumble.batch",
    "Trajectory": "tumble.trajectory",
    "Rotor": "tumble.parts",
    "KaneDamper": "tumble.parts",
    "SpringMassDamper": "tumble.parts",
    # from measurements
    "identify": "tumble.identification.fit",
    "identify_many": "tumble.identification.many",
    # errors and warnings
    "InputError": "tumble.errors",
    "IntegrationError": "tumble.errors",
    "MeshError": "tumble.errors",
    "OutputError": "tumble.errors",
    "OutputInUseError": "tumble.errors",
    "RequestTooLargeError": "tumble.errors",
    "CoarseStepWarning": "tumble.errors",
    "MeshOrientationWarning": "tumble.mesh",
    "MeshRepairWarning": "tumble.mesh",
    # public modules
    "analysis": "tumble.analysis",
    "conformance": "tumble.conformance",
    "identification": "tumble.identification",
    "models": "tumble.models",
    "robots": "tumble.robots",
    "rotordynamics": "tumble.rotordynamics",
    "shapes": "tumble.shapes",
    "sweep": "tumble.sweep",
    "symbolic": "tumble.symbolic",
    "theory": "tumble.theory",
    "torques": "tumble.torques",
    "units": "tumble.units",
}

#: Public names that need an optional dependency (sympy): loaded on use like the
#: others, but left out of ``__all__`` so that ``from tumble import *`` needs none.
_OPTIONAL = frozenset({"symbolic"})

__all__ = sorted(name for name in _PUBLIC if name not in _OPTIONAL)

# numba's optimisation level for tumble's kernels (:mod:`tumble.core` says why),
# set at ``import tumble``: numba's code generator reads it once, when the
# process first declares a numba function, which may be the program's own
# before tumble compiles anything (then, set only with tumble's kernels, the
# kernels of bodies carrying parts compiled in the process ran 3.7× slower).
if "NUMBA_OPT" not in os.environ:
    os.environ["NUMBA_OPT"] = "max"
    # numba imported already reads its settings again.
    if "numba.core.config" in sys.modules:
        sys.modules["numba.core.config"].reload_config()


def __getattr__(name: str) -> Any:
    where = _PUBLIC.get(name)
    if where is None:
        raise AttributeError(f"module 'tumble' has no attribute {name!r}")
    module = importlib.import_module(where)
    value = module if where == f"tumble.{name}" else getattr(module, name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(_PUBLIC)
