"""The equations of motion of a rigid body, written once for every integrator.

State, in the body's **principal** frame about its reference point (the centre
of mass, or a pivot held fixed), inertia ``diag(I1, I2, I3)``:

* ``w`` = (ω1, ω2, ω3): angular velocity in principal-body coordinates, rad/s;
* ``q`` = (q0, q1, q2, q3): unit quaternion ``[w, x, y, z]`` rotating
  principal-body coordinates into space coordinates.

Equations: Euler's ``I ω̇ + ω × (I ω) = τ``, in the principal frame
``I1 ω̇1 + (I3 − I2) ω2 ω3 = τ1`` and cyclic, and ``q̇ = ½ q ⊗ (0, ω)``.

The body enters the kernels as its :func:`euler_coefficients`
``c1 = (I2 − I3)/I1`` (cyclic), ``r = 1/I`` and the moments themselves, so
that a step needs multiplications only (they vectorise across bodies). The torque enters as a
compiled function of the shared signature of :mod:`tumble.core.torques`,
``torque(t, w, q, params, column, context) -> (τ1, τ2, τ3, c)``: the torque on
the body is ``τ − c ω`` (N·m, principal-body axes). A free body's torque is
:func:`free_torque`, which :func:`rates` recognises while it is compiled: it
then adds no torque term at all (``(0 − 0 ω) / I`` cannot be folded away by the
compiler, which must keep NaN and infinity meaningful, and costs a quarter of
a vectorised RK4 step).
"""

from __future__ import annotations

import math

from numba import types
from numba.extending import overload

from tumble.core._jit import njit


@njit(inline="always")
def euler_coefficients(i1, i2, i3):  # type: ignore[no-untyped-def]
    """``(c1, c2, c3, r1, r2, r3, I1, I2, I3)``: ``c1 = (I2 − I3)/I1`` (cyclic),
    ``r = 1/I`` and the moments, from the principal moments (kg·m², scalars or
    arrays of the same shape)."""
    return (
        (i2 - i3) / i1,
        (i3 - i1) / i2,
        (i1 - i2) / i3,
        1.0 / i1,
        1.0 / i2,
        1.0 / i3,
        i1,
        i2,
        i3,
    )


@njit(inline="always")
def quaternion_rates(q0, q1, q2, q3, w1, w2, w3):  # type: ignore[no-untyped-def]
    """``q̇ = ½ q ⊗ (0, ω)`` (1/s) for ω in the frame that q turns into space."""
    return (
        0.5 * (-q1 * w1 - q2 * w2 - q3 * w3),
        0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
        0.5 * (q0 * w2 + q3 * w1 - q1 * w3),
        0.5 * (q0 * w3 + q1 * w2 - q2 * w1),
    )


@njit(inline="always")
def free_torque(t, w, q, params, column, context):  # type: ignore[no-untyped-def]
    """The torque of a free body, of the shared signature: zero (see the module's
    docstring)."""
    return 0.0, 0.0, 0.0, 0.0


def is_free(torque) -> bool:  # type: ignore[no-untyped-def]
    """Whether the numba type of a torque function is that of :func:`free_torque`:
    for the overloads that leave out the torque's terms while compiling."""
    return isinstance(torque, types.Dispatcher) and torque.dispatcher is free_torque


def _with_torque(torque, t, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    w1, w2, w3, q0, q1, q2, q3 = state
    c1, c2, c3, r1, r2, r3 = coefficients[:6]
    t1, t2, t3, c = torque(t, (w1, w2, w3), (q0, q1, q2, q3), params, column, context)
    return (
        (t1 - c * w1) * r1 + c1 * w2 * w3,
        (t2 - c * w2) * r2 + c2 * w3 * w1,
        (t3 - c * w3) * r3 + c3 * w1 * w2,
    )


def _without_torque(torque, t, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    w1, w2, w3 = state[0], state[1], state[2]
    return coefficients[0] * w2 * w3, coefficients[1] * w3 * w1, coefficients[2] * w1 * w2


def euler_rates(torque, t, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """``(ω̇1, ω̇2, ω̇3)``, rad/s²: Euler's equations with the torque of ``torque``;
    compiled, without a torque term when ``torque`` is :func:`free_torque`."""
    return _with_torque(torque, t, state, coefficients, params, column, context)


@overload(euler_rates, inline="always")
def _euler_rates(torque, t, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    return _without_torque if is_free(torque) else _with_torque


@njit(inline="always")
def rates(torque, t, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """``(ω̇1, ω̇2, ω̇3, q̇0, q̇1, q̇2, q̇3)`` at time ``t`` (s) for ``state`` =
    ``(ω1, ω2, ω3, q0, q1, q2, q3)``, the body's :func:`euler_coefficients`, and the
    torque function with its ``params`` column and ``context``."""
    w1, w2, w3, q0, q1, q2, q3 = state
    e1, e2, e3 = euler_rates(torque, t, state, coefficients, params, column, context)
    d0, d1, d2, d3 = quaternion_rates(q0, q1, q2, q3, w1, w2, w3)
    return e1, e2, e3, d0, d1, d2, d3


@njit(inline="always")
def normalised(state):  # type: ignore[no-untyped-def]
    """The state with its quaternion scaled to unit length."""
    w1, w2, w3, q0, q1, q2, q3 = state
    scale = 1.0 / math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return w1, w2, w3, q0 * scale, q1 * scale, q2 * scale, q3 * scale


@njit(inline="always")
def is_finite(state):  # type: ignore[no-untyped-def]
    """True when every entry of the state is finite and the quaternion is not zero."""
    w1, w2, w3, q0, q1, q2, q3 = state
    norm = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3
    return math.isfinite(norm) and math.isfinite(w1 + w2 + w3) and norm > 0.0


@njit(inline="always")
def rotate_to_body(q, v):  # type: ignore[no-untyped-def]
    """``Aᵀ v``: a space vector ``v`` (3-tuple) in the coordinates of the frame that
    the unit quaternion ``q`` (4-tuple) turns into space."""
    s = q[0]
    ux = -q[1]
    uy = -q[2]
    uz = -q[3]
    # v' = v + 2 s (u × v) + 2 u × (u × v), with u the conjugate's vector part.
    cx = uy * v[2] - uz * v[1]
    cy = uz * v[0] - ux * v[2]
    cz = ux * v[1] - uy * v[0]
    return (
        v[0] + 2.0 * (s * cx + uy * cz - uz * cy),
        v[1] + 2.0 * (s * cy + uz * cx - ux * cz),
        v[2] + 2.0 * (s * cz + ux * cy - uy * cx),
    )


@njit(inline="always")
def record(step, record_every, out_w, out_q, state):  # type: ignore[no-untyped-def]
    """Write ``state`` to row ``step // record_every`` of ``out_w`` (·, 3) and
    ``out_q`` (·, 4) when ``step`` is a multiple of ``record_every``."""
    if step % record_every == 0:
        row = step // record_every
        for i in range(3):
            out_w[row, i] = state[i]
        for i in range(4):
            out_q[row, i] = state[3 + i]
