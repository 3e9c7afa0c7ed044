"""Compiled kernels of tumble.

Everything here takes and returns SI float64 (and int64) numpy arrays. The core
imports only numpy and numba: no units, no validation, no Python objects. The
friendly, validating wrappers live one level up in the package.

numba's optimisation level is set to ``max`` (``NUMBA_OPT``) when the environment
does not set it, before any kernel is declared. By default numba optimises each
function cheaply first, without vectorising its loops, and fully only once its
module is whole; the kernels of batches of bodies carrying parts, compiled so, ran
3.6–3.8× slower in the process that compiled them than loaded from numba's cache.
At ``max`` they run as fast compiled as loaded, for up to 45 % more compile time on
some kernels (``bench/compiled_here.py``). It is numba's setting for the whole process: set
``NUMBA_OPT`` (numba's own default is ``3``) to choose another; a process that
compiled with numba before it imported tumble's kernels keeps numba's.
"""

import os
import sys

if "NUMBA_OPT" not in os.environ:
    os.environ["NUMBA_OPT"] = "max"
    # numba imported already reads its settings again, before its first kernel
    # makes the code generator that reads this one.
    if "numba.core.config" in sys.modules:
        sys.modules["numba.core.config"].reload_config()
