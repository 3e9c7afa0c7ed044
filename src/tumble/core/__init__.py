"""Compiled kernels of tumble.

Everything here takes and returns SI float64 (and int64) numpy arrays. The core
imports only numpy and numba: no units, no validation, no Python objects. The
friendly, validating wrappers live one level up in the package.
"""
