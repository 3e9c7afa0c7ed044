"""Quaternion products for stacks of attitudes (scalar-first ``[w, x, y, z]``).

scipy's ``Rotation`` does the same with more checks and a Python object per
call; here the products run inside compiled loops (the exact solution's
attitude, the change between principal and body axes of every sample).
"""

from __future__ import annotations

import numpy as np

from tumble.core._jit import njit


@njit(inline="always")
def multiply(a0, a1, a2, a3, b0, b1, b2, b3):  # type: ignore[no-untyped-def]
    """The Hamilton product ``a ⊗ b`` (rotation b first, then a)."""
    return (
        a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
        a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
        a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
        a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
    )


@njit(inline="always")
def _unit_product(quaternions, k, r0, r1, r2, r3, out):  # type: ignore[no-untyped-def]
    """Row ``k`` of ``out``: row k of ``quaternions`` ⊗ r, renormalised."""
    p = multiply(
        quaternions[k, 0],
        quaternions[k, 1],
        quaternions[k, 2],
        quaternions[k, 3],
        r0,
        r1,
        r2,
        r3,
    )
    scale = 1.0 / np.sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3])
    for i in range(4):
        out[k, i] = p[i] * scale


@njit
def multiply_right(quaternions, r):  # type: ignore[no-untyped-def]
    """``q ⊗ r`` for each row q of ``quaternions`` (n, 4) and one unit ``r`` (4,);
    the rows are renormalised (inputs unit to round-off stay unit)."""
    out = np.empty((quaternions.shape[0], 4))
    multiply_right_into(quaternions, r, out)
    return out


@njit
def multiply_right_into(quaternions, r, out):  # type: ignore[no-untyped-def]
    """:func:`multiply_right` written into ``out`` (n, 4)."""
    for k in range(quaternions.shape[0]):
        _unit_product(quaternions, k, r[0], r[1], r[2], r[3], out)


@njit
def multiply_rows(quaternions, turns):  # type: ignore[no-untyped-def]
    """``q_k ⊗ r_k`` for each row q_k of ``quaternions`` and r_k of ``turns`` (n, 4),
    unit; the rows are renormalised."""
    n = quaternions.shape[0]
    out = np.empty((n, 4))
    for k in range(n):
        _unit_product(quaternions, k, turns[k, 0], turns[k, 1], turns[k, 2], turns[k, 3], out)
    return out
