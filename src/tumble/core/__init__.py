"""Compiled kernels of tumble.

Everything here takes and returns SI float64 (and int64) numpy arrays. The core
imports only numpy and numba: no units, no validation, no Python objects. The
friendly, validating wrappers live one level up in the package.

numba's optimisation level is set to ``max`` (``NUMBA_OPT``) when the environment
does not set it, at ``import tumble`` (:mod:`tumble`), before the program or tumble
declares any numba function. By default numba optimises each function cheaply
first, without vectorising its loops, and fully only once its module is whole;
the kernels of batches of bodies carrying parts, compiled so, ran 3.6–3.8×
slower in the process that compiled them than loaded from numba's cache. At
``max`` they run as fast compiled as loaded, for up to 45 % more compile time on
some kernels (``bench/compiled_here.py``). It is numba's setting for the whole
process: set ``NUMBA_OPT`` (numba's own default is ``3``) to choose another; a
process that declared numba functions before it imported tumble keeps numba's.
"""
