"""The one place where numba is configured for the compiled core.

Every kernel is decorated with :data:`njit` (or :data:`njit_parallel`) from this
module, so compilation options are set once:

* ``cache=True`` writes compiled machine code next to the sources, so only the
  first process pays the compile time (about a second per kernel).
* ``TUMBLE_NUMBA_CACHE=0`` disables that cache (read-only installs, debugging).
* ``NUMBA_DISABLE_JIT=1`` (numba's own switch) runs every kernel as plain
  Python, which the test suite uses once so coverage sees the kernels.
"""

from __future__ import annotations

import os
from functools import partial
from typing import Any

import numba

CACHE = os.environ.get("TUMBLE_NUMBA_CACHE", "1").strip().lower() not in {"0", "false", "no", "off"}

#: Serial kernels: no fastmath, so IEEE semantics (NaN, inf, summation order) hold.
njit: Any = partial(numba.njit, cache=CACHE, nogil=True, error_model="numpy")

#: Kernels that split their outer loop across threads with ``numba.prange``.
njit_parallel: Any = partial(
    numba.njit, cache=CACHE, nogil=True, error_model="numpy", parallel=True
)

prange: Any = numba.prange

#: Kernels vectorised across bodies: the compiler may contract to FMA and
#: reassociate, but NaN and infinity keep their meaning (no 'nnan'/'ninf'), so
#: a diverging state is still detected.
njit_vector: Any = partial(
    numba.njit,
    cache=CACHE,
    nogil=True,
    error_model="numpy",
    parallel=True,
    fastmath={"contract", "arcp", "nsz", "reassoc", "afn"},
)
