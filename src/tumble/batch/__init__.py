"""Many free bodies at once: :func:`simulate_batch`, and the batch driver sweeps share.

* :mod:`tumble.batch.driver`: :func:`step_batch`, the one driver of the compiled
  batch kernels (N bodies as a structure of arrays in their principal frames,
  stepped in chunks, with progress, the check that every state stayed finite
  and optional recording), and :func:`measure_batch`, which measures each body
  as it steps (:mod:`tumble.core.metrics`); both :func:`simulate_batch` and the
  sweep engine (:mod:`tumble.sweep`) run on them;
* :mod:`tumble.batch.simulate`: :func:`simulate_batch`;
* :mod:`tumble.batch.parts`: bodies carrying parts (RK4 in blocks of bodies, the
  splittings one compiled body per thread);
* :mod:`tumble.batch.memory`: the memory a batch takes, checked before any work;
* :mod:`tumble.batch.result`: what a batch run returns.
"""

from tumble.batch.driver import Batch, BatchRun, measure_batch, step_batch
from tumble.batch.memory import PEAK_PER_VALUE, PER_BODY, PER_RECORD, check_batch_memory
from tumble.batch.result import BatchResult
from tumble.batch.simulate import simulate_batch

__all__ = [
    "PEAK_PER_VALUE",
    "PER_BODY",
    "PER_RECORD",
    "Batch",
    "BatchResult",
    "BatchRun",
    "check_batch_memory",
    "measure_batch",
    "simulate_batch",
    "step_batch",
]
