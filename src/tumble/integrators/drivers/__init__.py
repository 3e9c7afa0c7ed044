"""The single-body drivers, one per kind of integrator
(:data:`tumble.integrators.Kind`), each ``run(integrator, problem, schedule,
progress) -> Samples`` (:mod:`tumble.integrators.problem`, body axes): fixed
steps (:func:`run_stepping`), adaptive steps sampled by dense output
(:func:`run_adaptive`), or the closed forms of :mod:`tumble.theory.motions`
sampled directly (:func:`run_exact`). A body carrying parts (rotors, dampers)
runs on the integrator's kernels for parts (:mod:`tumble.core.parts`), whose
state holds the parts' momenta besides the body's.
"""

from tumble.integrators.drivers.adaptive import ADAPTIVE_CHUNK, run_adaptive
from tumble.integrators.drivers.exact import check_finite_motion, run_exact
from tumble.integrators.drivers.stepping import ready_stepping, run_stepping

__all__ = [
    "ADAPTIVE_CHUNK",
    "check_finite_motion",
    "ready_stepping",
    "run_adaptive",
    "run_exact",
    "run_stepping",
]
