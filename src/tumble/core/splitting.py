"""Symplectic splitting of a rigid body's motion: exact rotations and torque kicks.

The method works on the body's angular momentum ``L`` in principal-body
coordinates (kg·m²/s, inertia diag(I1, I2, I3), ascending) and the attitude
quaternion ``q`` (principal → space). Its steps are steppers of
:mod:`tumble.core.stepping` of these variables (:data:`MOMENTUM`), so one body, a
batch vectorised across bodies and a measured batch run it as they run RK4:
the rotations' sines and cosines are :func:`tumble.core.trig.cos_sin`, which
vectorises, and every choice inside a step is a select, not a branch.

The kinetic energy is split into three parts whose flows are exact rotations
(in the spirit of Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107 (1997)
5840, and of Touma & Wisdom, Astron. J. 107 (1994) 1189):

    T = |L|²/(2 I2) + ½ L1² (1/I1 − 1/I2) + ½ L3² (1/I3 − 1/I2)

* ``|L|²/(2 I2)``: the body turns about its (fixed) L at rate |L|/I2;
* ``½ L_k² (1/I_k − 1/I2)``: the body turns about its axis k at rate
  ``ν = L_k (1/I_k − 1/I2)`` while L turns the opposite way in the body.

The first commutes with the others (it is a rotation about the space-fixed L,
a left multiplication; the others are right multiplications), so a symmetric
body (I1 = I2 or I2 = I3) moves exactly, whatever the step. Each part keeps
|L| and the space-frame L exactly.

The torque ``τ − c ω`` (:mod:`tumble.core.torques`) is applied in kicks that
hold the attitude: the exact flow of ``L̇ = τ − c ω`` with τ held at its value
at the kick (exact for gravity, constant torques and the linear damping ``c``;
a torque whose τ depends on ω is integrated to first order within the kick,
so the method stays second order only for torques whose τ depends on the
attitude and time alone).

One Strang step of length h at time t:

    kick(t, h/2) ∘ R1(h/2) ∘ R3(h) ∘ R1(h/2) ∘ R_L(h) ∘ kick(t + h, h/2)

(read right to left: the first kick is at t), symmetric, hence second order
and time-reversible; with a conservative torque (gravity) it is symplectic,
so the energy error stays bounded over any number of steps. The fourth-order
method is Yoshida's triple jump of that step (Phys. Lett. A 150 (1990) 262):
steps of w1 h, w0 h, w1 h with w1 = 1/(2 − 2^(1/3)), w0 = 1 − 2 w1. For a
free body the three steps' adjacent rotations about axis 1 merge, and the
rotations about L (which commute with the others) merge into one, so the step
takes eight sines and cosines rather than twelve; the map is the same.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import types
from numba.extending import overload

from tumble.core._jit import file_stamp, njit, njit_block, own_name
from tumble.core.dynamics import free_torque, is_free, normalised
from tumble.core.freebody import free_step
from tumble.core.stepping import Variables, block_steps, no_observer
from tumble.core.trig import (
    LARGEST_ANGLE,
    QUARTER_TURN,
    cos_sin,
    cos_sin_small,
    library_cos_sin,
)

__all__ = [
    "MOMENTUM",
    "YOSHIDA_INNER",
    "YOSHIDA_OUTER",
    "block_advance",
    "decay_integral",
    "exact_free_flow",
    "exact_strang_step",
    "exact_yoshida_step",
    "free_flow",
    "free_flow_one_body",
    "free_turns",
    "momentum_state",
    "momentum_vectors",
    "principal_turn",
    "strang_step",
    "strang_step_one_body",
    "sub_step",
    "sub_step_start",
    "sub_steps",
    "turn",
    "turn_about_momentum",
    "velocity_state",
    "yoshida_step",
    "yoshida_step_one_body",
]

YOSHIDA_OUTER = 1.0 / (2.0 - 2.0 ** (1.0 / 3.0))
YOSHIDA_INNER = 1.0 - 2.0 * YOSHIDA_OUTER


@njit(inline="always")
def turn(q0, q1, q2, q3, c, s, a1, a2, a3):  # type: ignore[no-untyped-def]
    """``q ⊗ (c, s a)``: q turned about the unit body axis a, with c and s the
    cosine and sine of half the angle."""
    b1 = s * a1
    b2 = s * a2
    b3 = s * a3
    return (
        q0 * c - q1 * b1 - q2 * b2 - q3 * b3,
        q0 * b1 + q1 * c + q2 * b3 - q3 * b2,
        q0 * b2 - q1 * b3 + q2 * c + q3 * b1,
        q0 * b3 + q1 * b2 - q2 * b1 + q3 * c,
    )


@njit(inline="always")
def _plane_rotation(x, y, c, s):  # type: ignore[no-untyped-def]
    """(x, y) turned by the angle θ whose half has cosine c and sine s.

    Below 120° as three shears (Paeth, Graphics Interface 1986), by tan(θ/2) =
    s/c, sin θ = 2 s c, then tan(θ/2) again: each shear has determinant exactly
    1 whatever the rounding of its coefficient, so a rotation repeated with the
    same angle step after step (a steady spin) keeps the length of the vector
    bounded instead of scaling it by the same 1 + O(ε) every step. Larger
    angles (far too coarse a step) use the rotation matrix. Both are computed
    and one is selected, so that a loop over bodies vectorises.
    """
    tangent = -s / c
    sine = 2.0 * s * c
    sheared_x = x + tangent * y
    sheared_y = y + sine * sheared_x
    sheared_x += tangent * sheared_y
    cosine = (c - s) * (c + s)
    turned_x = cosine * x - sine * y
    turned_y = sine * x + cosine * y
    shears = c > 0.5
    return (sheared_x if shears else turned_x), (sheared_y if shears else turned_y)


@njit(inline="always")
def principal_turn(axis, c, s, l1, l2, l3, q0, q1, q2, q3):  # type: ignore[no-untyped-def]
    """The body turned about its principal axis ``axis`` (0, 1 or 2, a constant of
    the compiled code) by the angle θ whose half has cosine c and sine s, and L
    by −θ in the body (:func:`_plane_rotation`): ``q ⊗ (c, s e_axis)``, written
    out (the compiler keeps the products by zero of :func:`turn`: they are NaN
    for an infinite factor). Returns the new (L, q)."""
    if axis == 0:
        l3, l2 = _plane_rotation(l3, l2, c, s)
        return l1, l2, l3, q0 * c - q1 * s, q0 * s + q1 * c, q2 * c + q3 * s, q3 * c - q2 * s
    if axis == 1:
        l1, l3 = _plane_rotation(l1, l3, c, s)
        return l1, l2, l3, q0 * c - q2 * s, q1 * c - q3 * s, q0 * s + q2 * c, q1 * s + q3 * c
    l2, l1 = _plane_rotation(l2, l1, c, s)
    return l1, l2, l3, q0 * c - q3 * s, q1 * c + q2 * s, q2 * c - q1 * s, q3 * c + q0 * s


@njit(inline="always")
def _about_axis_1(h, l1, l2, l3, q0, q1, q2, q3, a1, sines):  # type: ignore[no-untyped-def]
    """R1(h): the body turns about its axis 1 at ν = L1 a1 (``a1`` = 1/I1 − 1/I2)
    and L by −ν h in the body. One sine and cosine of the half angle serve both,
    so the two turn by the same angle to round-off; ``sines`` computes them
    (:func:`~tumble.core.trig.cos_sin`, or ``cos_sin_small`` where the angle is
    known to be small)."""
    c, s = sines(0.5 * h * l1 * a1)
    return principal_turn(0, c, s, l1, l2, l3, q0, q1, q2, q3)


@njit(inline="always")
def _about_axis_3(h, l1, l2, l3, q0, q1, q2, q3, a3, sines):  # type: ignore[no-untyped-def]
    """R3(h), as :func:`_about_axis_1` about axis 3 (``a3`` = 1/I3 − 1/I2)."""
    c, s = sines(0.5 * h * l3 * a3)
    return principal_turn(2, c, s, l1, l2, l3, q0, q1, q2, q3)


@njit(inline="always")
def turn_about_momentum(h, l1, l2, l3, q0, q1, q2, q3, largest, rate, sines):  # type: ignore[no-untyped-def]
    """R_L(h): the body turns about L (fixed in the body during this part) at
    |L| ``rate`` (``rate`` = 1/I2, or the inverse moment of another reference
    axis); no turn when L = 0. Returns the new q.

    Every angle of a free flow over h, here and in R1 and R3 (which keep |L|),
    is at most |h| |L| ``largest`` (the largest inverse moment, 1/I1); beyond
    :data:`~tumble.core.trig.LARGEST_ANGLE` q is NaN, a step that did not stay
    finite: :func:`~tumble.core.trig.cos_sin` is accurate only up to there (and
    the step is then absurdly coarse).
    """
    size = (l1 * l1 + l2 * l2 + l3 * l3) ** 0.5
    inverse = 1.0 / size if size > 0.0 else 0.0
    c, s = sines(0.5 * h * size * rate)
    inside = abs(h) * size * largest <= LARGEST_ANGLE
    c = c if inside else math.nan
    return turn(q0, q1, q2, q3, c, s, l1 * inverse, l2 * inverse, l3 * inverse)


@njit(inline="always")
def free_flow(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, r3):  # type: ignore[no-untyped-def]
    """The second-order free flow R1(h/2) R3(h) R1(h/2) R_L(h) (``r`` = 1/I), exact
    for a symmetric body. Returns the new (L, q)."""
    return _flow(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, r3, cos_sin)


@njit(inline="always")
def free_flow_one_body(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, r3):  # type: ignore[no-untyped-def]
    """:func:`free_flow` with the C library's sines
    (:func:`~tumble.core.trig.library_cos_sin`): the same map, faster where
    bodies are turned one at a time rather than in vectorised loops."""
    return _flow(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, r3, library_cos_sin)


@njit(inline="always")
def _flow(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, r3, sines):  # type: ignore[no-untyped-def]
    """:func:`free_flow` with its sines and cosines from ``sines``."""
    l1, l2, l3, q0, q1, q2, q3 = free_turns(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, r3, sines)
    q0, q1, q2, q3 = turn_about_momentum(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, sines)
    return l1, l2, l3, q0, q1, q2, q3


@njit(inline="always")
def free_turns(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, r3, sines):  # type: ignore[no-untyped-def]
    """R1(h/2) R3(h) R1(h/2) (``r`` = 1/I): :func:`free_flow` but its turn about L,
    which commutes with them, with its sines and cosines from ``sines``. Returns
    the new (L, q)."""
    a1 = r1 - r2
    l1, l2, l3, q0, q1, q2, q3 = _about_axis_1(0.5 * h, l1, l2, l3, q0, q1, q2, q3, a1, sines)
    l1, l2, l3, q0, q1, q2, q3 = _about_axis_3(h, l1, l2, l3, q0, q1, q2, q3, r3 - r2, sines)
    return _about_axis_1(0.5 * h, l1, l2, l3, q0, q1, q2, q3, a1, sines)


@njit(inline="always")
def _free_triple_jump(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, r3, sines):  # type: ignore[no-untyped-def]
    """Yoshida's triple jump of :func:`free_flow` over h, its adjacent turns about
    axis 1 merged and its turns about L (which commute with the others) made one:
    R1(a/2) R3(a) R1((a+b)/2) R3(b) R1((a+b)/2) R3(a) R1(a/2) R_L(h) with
    a, b = w1 h, w0 h. Returns the new (L, q)."""
    a1 = r1 - r2
    a3 = r3 - r2
    outer = YOSHIDA_OUTER * h
    inner = YOSHIDA_INNER * h
    middle = 0.5 * (outer + inner)
    l1, l2, l3, q0, q1, q2, q3 = _about_axis_1(0.5 * outer, l1, l2, l3, q0, q1, q2, q3, a1, sines)
    l1, l2, l3, q0, q1, q2, q3 = _about_axis_3(outer, l1, l2, l3, q0, q1, q2, q3, a3, sines)
    l1, l2, l3, q0, q1, q2, q3 = _about_axis_1(middle, l1, l2, l3, q0, q1, q2, q3, a1, sines)
    l1, l2, l3, q0, q1, q2, q3 = _about_axis_3(inner, l1, l2, l3, q0, q1, q2, q3, a3, sines)
    l1, l2, l3, q0, q1, q2, q3 = _about_axis_1(middle, l1, l2, l3, q0, q1, q2, q3, a1, sines)
    l1, l2, l3, q0, q1, q2, q3 = _about_axis_3(outer, l1, l2, l3, q0, q1, q2, q3, a3, sines)
    l1, l2, l3, q0, q1, q2, q3 = _about_axis_1(0.5 * outer, l1, l2, l3, q0, q1, q2, q3, a1, sines)
    q0, q1, q2, q3 = turn_about_momentum(h, l1, l2, l3, q0, q1, q2, q3, r1, r2, sines)
    return l1, l2, l3, q0, q1, q2, q3


@njit
def exact_free_flow(h, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3):  # type: ignore[no-untyped-def]
    """The free flow of :func:`free_flow` solved exactly for any body: Euler's
    equations by Jacobi's elliptic functions and the attitude by the precession
    angle about L (:func:`tumble.core.freebody.free_step`), so a splitting with
    it errs only through the torque (Celledoni, Fassò, Säfström & Zanna, SIAM J.
    Sci. Comput. 30 (2008) 2084; their printed solution has sign and separatrix
    errors, so this uses tumble's own, checked against DOP853). Returns the new
    (L, q)."""
    moments = np.array([i1, i2, i3])
    w = np.array([l1 / i1, l2 / i2, l3 / i3])
    q = np.array([q0, q1, q2, q3])
    free_step(moments, w, q, h)
    return i1 * w[0], i2 * w[1], i3 * w[2], q[0], q[1], q[2], q[3]


@njit(inline="always")
def _rotations(h, m, body):  # type: ignore[no-untyped-def]
    """:func:`free_flow` of the state ``m`` = (L, q) of a body of :func:`euler
    coefficients <tumble.core.dynamics.euler_coefficients>` ``body``."""
    return free_flow(h, m[0], m[1], m[2], m[3], m[4], m[5], m[6], body[3], body[4], body[5])


@njit(inline="always")
def _rotations_one_body(h, m, body):  # type: ignore[no-untyped-def]
    """:func:`_rotations` with :func:`free_flow_one_body`."""
    return free_flow_one_body(
        h, m[0], m[1], m[2], m[3], m[4], m[5], m[6], body[3], body[4], body[5]
    )


@njit(inline="always")
def _exact(h, m, body):  # type: ignore[no-untyped-def]
    """:func:`exact_free_flow` of the state ``m`` = (L, q), as :func:`_rotations`."""
    return exact_free_flow(h, m[0], m[1], m[2], m[3], m[4], m[5], m[6], body[6], body[7], body[8])


@njit
def decay_integral(c, moment, h):  # type: ignore[no-untyped-def]
    """∫₀ʰ exp(−c s / I) ds = (1 − exp(−c h / I)) I / c, and h when c = 0.

    ``c`` is tested first: for a torque without damping it is a constant zero,
    so the compiler drops the rest, and a loop of kicks across bodies keeps no
    call to ``expm1`` and vectorises (measured: a block of bodies carrying a rotor
    under a constant torque stepped 6× slower with the call left in)."""
    if c == 0.0:
        return h
    rate = c / moment
    if rate == 0.0:
        return h
    return -math.expm1(-rate * h) / rate


def _torque_kick(torque, t, h, m, body, params, column, context):  # type: ignore[no-untyped-def]
    w1, w2, w3 = m[0] * body[3], m[1] * body[4], m[2] * body[5]
    t1, t2, t3, c = torque(t, (w1, w2, w3), m[3:], params, column, context)
    return (
        m[0] + (t1 - c * w1) * decay_integral(c, body[6], h),
        m[1] + (t2 - c * w2) * decay_integral(c, body[7], h),
        m[2] + (t3 - c * w3) * decay_integral(c, body[8], h),
        m[3],
        m[4],
        m[5],
        m[6],
    )


def _no_kick(torque, t, h, m, body, params, column, context):  # type: ignore[no-untyped-def]
    return m


def kick(torque, t, h, m, body, params, column, context):  # type: ignore[no-untyped-def]
    """The state ``m`` = (L, q) after the exact flow of ``L̇ = τ − c L / I`` over h
    s from time t with the attitude and τ held; compiled, ``m`` itself for a free
    body (:func:`tumble.core.dynamics.free_torque`)."""
    return _torque_kick(torque, t, h, m, body, params, column, context)


@overload(kick, inline="always")
def _kick(torque, t, h, m, body, params, column, context):  # type: ignore[no-untyped-def]
    return _no_kick if is_free(torque) else _torque_kick


@njit(inline="always")
def _strang(torque, flow, t, h, m, body, params, column, context):  # type: ignore[no-untyped-def]
    """One Strang step of length h (may be negative) from time t of the state
    ``m`` = (L, q), with the free flow ``flow`` (:func:`_rotations` or
    :func:`_exact`)."""
    m = kick(torque, t, 0.5 * h, m, body, params, column, context)
    m = flow(h, m, body)
    return kick(torque, t + h, 0.5 * h, m, body, params, column, context)


def _triple_jump(torque, flow, t, dt, m, body, params, column, context):  # type: ignore[no-untyped-def]
    outer = YOSHIDA_OUTER * dt
    inner = YOSHIDA_INNER * dt
    m = _strang(torque, flow, t, outer, m, body, params, column, context)
    m = _strang(torque, flow, t + outer, inner, m, body, params, column, context)
    return _strang(torque, flow, t + outer + inner, outer, m, body, params, column, context)


def _free_rotations(torque, flow, t, dt, m, body, params, column, context):  # type: ignore[no-untyped-def]
    return _free_triple_jump(
        dt, m[0], m[1], m[2], m[3], m[4], m[5], m[6], body[3], body[4], body[5], cos_sin
    )


def _free_rotations_one_body(torque, flow, t, dt, m, body, params, column, context):  # type: ignore[no-untyped-def]
    return _free_triple_jump(
        dt, m[0], m[1], m[2], m[3], m[4], m[5], m[6], body[3], body[4], body[5], library_cos_sin
    )


def triple_jump(torque, flow, t, dt, m, body, params, column, context):  # type: ignore[no-untyped-def]
    """Yoshida's triple jump of :func:`_strang` over dt from time t; compiled, for a
    free body and the rotations, :func:`_free_triple_jump`, the same map with
    fewer rotations."""
    return _triple_jump(torque, flow, t, dt, m, body, params, column, context)


@overload(triple_jump, inline="always")
def _triple_jump_overload(torque, flow, t, dt, m, body, params, column, context):  # type: ignore[no-untyped-def]
    if not (is_free(torque) and isinstance(flow, types.Dispatcher)):
        return _triple_jump
    if flow.dispatcher is _rotations:
        return _free_rotations
    return _free_rotations_one_body if flow.dispatcher is _rotations_one_body else _triple_jump


@njit(inline="always")
def momentum_state(state, coefficients):  # type: ignore[no-untyped-def]
    """The state (L, q) of the state (ω, q): L = I ω."""
    i1, i2, i3 = coefficients[6], coefficients[7], coefficients[8]
    return i1 * state[0], i2 * state[1], i3 * state[2], state[3], state[4], state[5], state[6]


@njit(inline="always")
def velocity_state(state, coefficients):  # type: ignore[no-untyped-def]
    """The state (ω, q) of the state (L, q): ω = L / I."""
    i1, i2, i3 = coefficients[6], coefficients[7], coefficients[8]
    return state[0] / i1, state[1] / i2, state[2] / i3, state[3], state[4], state[5], state[6]


@njit(inline="always")
def momentum_vectors(state, coefficients):  # type: ignore[no-untyped-def]
    """``(L, ω)`` of the state (L, q): ω = L (1/I), a product (no division)."""
    l1, l2, l3 = state[0], state[1], state[2]
    return l1, l2, l3, l1 * coefficients[3], l2 * coefficients[4], l3 * coefficients[5]


#: The splittings step (L, q): :func:`momentum_state`, :func:`velocity_state` and
#: :func:`momentum_vectors`.
MOMENTUM = Variables(momentum_state, velocity_state, momentum_vectors)


@njit(inline="always")
def strang_step(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """One Strang step of ``dt`` s from time t around the rotations, a stepper of
    :mod:`tumble.core.stepping` of the :data:`MOMENTUM` variables: the new state
    (L, q), q renormalised."""
    return normalised(
        _strang(torque, _rotations, t, dt, state, coefficients, params, column, context)
    )


@njit(inline="always")
def yoshida_step(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """One step of Yoshida's triple jump of :func:`strang_step`, as it."""
    return normalised(
        triple_jump(torque, _rotations, t, dt, state, coefficients, params, column, context)
    )


@njit(inline="always")
def strang_step_one_body(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """:func:`strang_step` for the kernels of one body: the same map, with the C
    library's sines (:func:`~tumble.core.trig.library_cos_sin`), faster one
    angle at a time."""
    return normalised(
        _strang(torque, _rotations_one_body, t, dt, state, coefficients, params, column, context)
    )


@njit(inline="always")
def yoshida_step_one_body(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """:func:`yoshida_step` for the kernels of one body, as :func:`strang_step_one_body`."""
    return normalised(
        triple_jump(
            torque, _rotations_one_body, t, dt, state, coefficients, params, column, context
        )
    )


@njit(inline="always")
def exact_strang_step(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """One Strang step around the exact free flow (:func:`exact_free_flow`), as
    :func:`strang_step`."""
    return normalised(_strang(torque, _exact, t, dt, state, coefficients, params, column, context))


@njit(inline="always")
def exact_yoshida_step(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """One step of Yoshida's triple jump of :func:`exact_strang_step`, as it."""
    return normalised(
        triple_jump(torque, _exact, t, dt, state, coefficients, params, column, context)
    )


@njit(inline="always")
def sub_steps(order):  # type: ignore[no-untyped-def]
    """How many Strang sub-steps a step takes: one whole step (``order`` 2), or
    Yoshida's triple jump (4)."""
    return 1 if order == 2 else 3


@njit(inline="always")
def sub_step(order, j):  # type: ignore[no-untyped-def]
    """The fraction of a step taken by Strang sub-step ``j`` (:func:`sub_steps`):
    1, or w1, w0, w1."""
    return 1.0 if order == 2 else (YOSHIDA_INNER if j == 1 else YOSHIDA_OUTER)


@njit(inline="always")
def sub_step_start(order, j, t, dt):  # type: ignore[no-untyped-def]
    """The time (s) at which Strang sub-step ``j`` of a step of ``dt`` s from ``t``
    starts: the sub-steps before it added to ``t`` one by one, as a loop over them
    adds them."""
    first = t + sub_step(order, 0) * dt
    return t if j == 0 else (first if j == 1 else first + sub_step(order, 1) * dt)


# ------------------------------------------------------------------ whole blocks
# A free body's step is a chain of turns, each needing the last one's L, with a
# sine and cosine in each: in one loop over the bodies of a block the compiler
# runs out of registers and waits on that chain. One loop per turn, each over the
# whole block (in L1 cache), keeps every loop short and its bodies independent
# (measured 1.3× faster than one loop of whole steps). And as |L| is conserved,
# one look at the block tells whether every angle of every step stays within
# π/4, where the sines need no reduction (1.2× faster again).


@njit(inline="always")
def _block_about_axis_1(h, state, a1, sines):  # type: ignore[no-untyped-def]
    """R1(h) of every body of a block (the state arrays (L, q); ``a1`` the array of
    1/I1 − 1/I2), in place; L1 does not change."""
    l1, l2, l3, q0, q1, q2, q3 = state
    for j in range(l1.shape[0]):
        _, l2[j], l3[j], q0[j], q1[j], q2[j], q3[j] = _about_axis_1(
            h, l1[j], l2[j], l3[j], q0[j], q1[j], q2[j], q3[j], a1[j], sines
        )


@njit(inline="always")
def _block_about_axis_3(h, state, a3, sines):  # type: ignore[no-untyped-def]
    """R3(h) of every body of a block (``a3`` the array of 1/I3 − 1/I2), in place;
    L3 does not change."""
    l1, l2, l3, q0, q1, q2, q3 = state
    for j in range(l1.shape[0]):
        l1[j], l2[j], _, q0[j], q1[j], q2[j], q3[j] = _about_axis_3(
            h, l1[j], l2[j], l3[j], q0[j], q1[j], q2[j], q3[j], a3[j], sines
        )


@njit(inline="always")
def _block_about_momentum(h, state, coefficients, sines):  # type: ignore[no-untyped-def]
    """R_L(h) of every body of a block, then its quaternion renormalised, in place."""
    l1, l2, l3, q0, q1, q2, q3 = state
    r1, r2 = coefficients[3], coefficients[4]
    for j in range(l1.shape[0]):
        turned = turn_about_momentum(
            h, l1[j], l2[j], l3[j], q0[j], q1[j], q2[j], q3[j], r1[j], r2[j], sines
        )
        scale = 1.0 / (turned[0] ** 2 + turned[1] ** 2 + turned[2] ** 2 + turned[3] ** 2) ** 0.5
        q0[j], q1[j], q2[j], q3[j] = (
            turned[0] * scale,
            turned[1] * scale,
            turned[2] * scale,
            turned[3] * scale,
        )


@njit(inline="always")
def _largest_rate(state, coefficients):  # type: ignore[no-untyped-def]
    """The largest rate (rad/s) of any turn of a free step over the bodies of a
    block: |L| max(|1/I1 − 1/I2|, |1/I3 − 1/I2|, 1/I2) ≤ |L| / I1."""
    l1, l2, l3 = state[0], state[1], state[2]
    r1, r2, r3 = coefficients[3], coefficients[4], coefficients[5]
    largest = 0.0
    for j in range(l1.shape[0]):
        size = (l1[j] * l1[j] + l2[j] * l2[j] + l3[j] * l3[j]) ** 0.5
        largest = max(largest, size * max(abs(r1[j] - r2[j]), abs(r3[j] - r2[j]), r2[j]))
    return largest


@njit(inline="always")
def _strang_turns(dt, n_steps, state, coefficients, a1, a3, sines, observer, arguments):  # type: ignore[no-untyped-def]
    for k in range(n_steps):
        _block_about_axis_1(0.5 * dt, state, a1, sines)
        _block_about_axis_3(dt, state, a3, sines)
        _block_about_axis_1(0.5 * dt, state, a1, sines)
        _block_about_momentum(dt, state, coefficients, sines)
        observer(k, arguments)


@njit(inline="always")
def _yoshida_turns(dt, n_steps, state, coefficients, a1, a3, sines, observer, arguments):  # type: ignore[no-untyped-def]
    outer = YOSHIDA_OUTER * dt
    inner = YOSHIDA_INNER * dt
    middle = 0.5 * (outer + inner)
    for k in range(n_steps):
        _block_about_axis_1(0.5 * outer, state, a1, sines)
        _block_about_axis_3(outer, state, a3, sines)
        _block_about_axis_1(middle, state, a1, sines)
        _block_about_axis_3(inner, state, a3, sines)
        _block_about_axis_1(middle, state, a1, sines)
        _block_about_axis_3(outer, state, a3, sines)
        _block_about_axis_1(0.5 * outer, state, a1, sines)
        _block_about_momentum(dt, state, coefficients, sines)
        observer(k, arguments)


@njit(inline="always")
def _small_angles(dt, state, coefficients):  # type: ignore[no-untyped-def]
    """Whether every half angle of a free step's turns stays within π/4 for every
    body of the block, whatever the number of steps: |L| is conserved (to
    round-off, hence the margin of 1 %) and the largest sub-step is
    |w0| dt = 1.71 dt, so its half angles are at most 0.86 |dt| times
    :func:`_largest_rate`."""
    return 0.86 * abs(dt) * _largest_rate(state, coefficients) <= 0.99 * QUARTER_TURN


@njit(inline="always")
def _free_block(turns, dt, n_steps, state, coefficients, observer, arguments):  # type: ignore[no-untyped-def]
    """``turns`` (:func:`_strang_turns` or :func:`_yoshida_turns`) over a whole
    block, the sines without their reduction when every angle is small; the
    observer after each step. The test and the differences of 1/I look at the
    block once for all its steps: redone at each step, they cost nearly half a
    Strang step (measured)."""
    a1 = coefficients[3] - coefficients[4]
    a3 = coefficients[5] - coefficients[4]
    if _small_angles(dt, state, coefficients):
        turns(dt, n_steps, state, coefficients, a1, a3, cos_sin_small, observer, arguments)
    else:
        turns(dt, n_steps, state, coefficients, a1, a3, cos_sin, observer, arguments)


@njit(inline="always")
def _free_strang_block(  # type: ignore[no-untyped-def]
    step, torque, t0, dt, n_steps, state, coefficients, params, context, observer, arguments
):
    """:func:`strang_step` of a free body, for a whole block (see above)."""
    _free_block(_strang_turns, dt, n_steps, state, coefficients, observer, arguments)


@njit(inline="always")
def _free_yoshida_block(  # type: ignore[no-untyped-def]
    step, torque, t0, dt, n_steps, state, coefficients, params, context, observer, arguments
):
    """:func:`yoshida_step` of a free body (:func:`_free_triple_jump`), for a whole
    block."""
    _free_block(_yoshida_turns, dt, n_steps, state, coefficients, observer, arguments)


def _unobserved_block(turns: Any) -> Any:
    """As :func:`_free_block` with no observer, each range of angles a compiled
    function of its own, called once for a block's whole run. numba copies a
    callee's code, block by block, at every place it inlines it, at a cost that
    grows as the square of its size: the two runs inlined take half as long
    again to compile (measured: a Yoshida splitting's batch kernel, 16 s
    inlined, 11 s so), and the call costs nothing measurable. (Behind such a
    call a measuring kernel, whose observer reads the block's whole array, ran
    3 % slower, measured on one thread: it inlines them.)"""

    stamp = file_stamp(turns)

    @njit_block
    @own_name(f"splitting.small|{stamp}")
    def small(dt, n_steps, state, coefficients, a1, a3):  # type: ignore[no-untyped-def]
        turns(dt, n_steps, state, coefficients, a1, a3, cos_sin_small, no_observer, ())

    @njit_block
    @own_name(f"splitting.reduced|{stamp}")
    def reduced(dt, n_steps, state, coefficients, a1, a3):  # type: ignore[no-untyped-def]
        turns(dt, n_steps, state, coefficients, a1, a3, cos_sin, no_observer, ())

    @njit(inline="always")
    def advance(  # type: ignore[no-untyped-def]
        step, torque, t0, dt, n_steps, state, coefficients, params, context, observer, arguments
    ):
        a1 = coefficients[3] - coefficients[4]
        a3 = coefficients[5] - coefficients[4]
        if _small_angles(dt, state, coefficients):
            small(dt, n_steps, state, coefficients, a1, a3)
        else:
            reduced(dt, n_steps, state, coefficients, a1, a3)

    return advance


_UNOBSERVED = {
    strang_step: _unobserved_block(_strang_turns),
    yoshida_step: _unobserved_block(_yoshida_turns),
}
_OBSERVED = {strang_step: _free_strang_block, yoshida_step: _free_yoshida_block}


# Under a torque, Yoshida's triple jump takes a loop across the block for each of
# its three Strang steps: in one loop of whole steps the compiler vectorised
# nothing (measured: 1e5 bodies under a constant torque, 3.9 s for 300 steps
# against 0.2 s free; Strang's single step vectorises). Each is :func:`_strang`
# from the time and of the length the triple jump gives its sub-step
# (:func:`sub_step_start`, :func:`sub_step`), so the map is :func:`yoshida_step`'s.
@njit(inline="always")
def _jump_of(j, torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    start = sub_step_start(4, j, t, dt)
    h = sub_step(4, j) * dt
    return _strang(torque, _rotations, start, h, state, coefficients, params, column, context)


@njit(inline="always")
def _first_jump(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    return _jump_of(0, torque, t, dt, state, coefficients, params, column, context)


@njit(inline="always")
def _middle_jump(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    return _jump_of(1, torque, t, dt, state, coefficients, params, column, context)


@njit(inline="always")
def _last_jump(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    flowed = _jump_of(2, torque, t, dt, state, coefficients, params, column, context)
    return normalised(flowed)


@njit(inline="always")
def _jump(jump, torque, t, dt, state, coefficients, params, context):  # type: ignore[no-untyped-def]
    """One Strang step of the triple jump (``jump``) of every body of a block."""
    block_steps(jump, torque, t, dt, 1, state, coefficients, params, context, no_observer, ())


@njit(inline="always")
def _yoshida_jumps(  # type: ignore[no-untyped-def]
    step, torque, t0, dt, n_steps, state, coefficients, params, context, observer, arguments
):
    """:func:`yoshida_step` under a torque, for a whole block: its three Strang
    steps one after the other, each a loop across the block
    (:func:`tumble.core.stepping.block_steps` of one step)."""
    for k in range(n_steps):
        t = t0 + k * dt
        _jump(_first_jump, torque, t, dt, state, coefficients, params, context)
        _jump(_middle_jump, torque, t, dt, state, coefficients, params, context)
        _jump(_last_jump, torque, t, dt, state, coefficients, params, context)
        observer(k, arguments)


def block_advance(step: Any, torque: Any, observed: bool = False) -> Any:
    """The ``advance`` of the batch and measuring kernels
    (:func:`tumble.core.stepping.batch_kernel`, :func:`~tumble.core.stepping.metrics_kernel`)
    for ``step`` and ``torque``: for a free body and the rotations, one loop over
    the block per turn (the same operations as :func:`strang_step` and
    :func:`yoshida_step` body by body); under a torque, for :func:`yoshida_step`,
    one loop per Strang step (:func:`_yoshida_jumps`); else None, the
    body-by-body default.
    ``observed``: whether it calls its observer (else it calls none, and compiles
    faster)."""
    if torque is not free_torque:
        return _yoshida_jumps if step is yoshida_step else None
    return (_OBSERVED if observed else _UNOBSERVED).get(step)
