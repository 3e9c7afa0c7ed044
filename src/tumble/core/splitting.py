"""Symplectic splitting of a rigid body's motion: exact rotations and torque kicks.

The state is the body's angular momentum ``L`` in principal-body coordinates
(kg·m²/s, inertia diag(I1, I2, I3), ascending) and the attitude quaternion
``q`` (principal → space). The kernels take and return ω = L / I.

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

The torque ``τ(t, q, ω)`` is applied in kicks that hold the attitude: the
exact flow of ``L̇ = τ_a − c ω`` with the attitude-dependent part τ_a held at
its value at the kick (exact for gravity, constant torques and the linear
damping ``c``; a user torque that depends on ω is integrated to first order
within the kick, so the method stays second order only for torques that
depend on the attitude and time alone).

One Strang step of length h at time t:

    kick(t, h/2) ∘ R1(h/2) ∘ R3(h) ∘ R1(h/2) ∘ R_L(h) ∘ kick(t + h, h/2)

(read right to left: the first kick is at t), symmetric, hence second order
and time-reversible; with a conservative torque (gravity) it is symplectic,
so the energy error stays bounded over any number of steps. The fourth-order
method is Yoshida's triple jump of that step (Phys. Lett. A 150 (1990) 262):
steps of w1 h, w0 h, w1 h with w1 = 1/(2 − 2^(1/3)), w0 = 1 − 2 w1.
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit, njit_parallel, prange
from tumble.core.rigid import (
    FINITE,
    _record,
    applied_torque,
    has_attitude_torque,
    no_extra_torque,
    user_torque_hook,
)

YOSHIDA_OUTER = 1.0 / (2.0 - 2.0 ** (1.0 / 3.0))
YOSHIDA_INNER = 1.0 - 2.0 * YOSHIDA_OUTER


@njit(inline="always")
def _turn(q0, q1, q2, q3, c, s, a1, a2, a3):  # type: ignore[no-untyped-def]
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
    angles (far too coarse a step) use the rotation matrix.
    """
    if c > 0.5:
        shear = -s / c
        x += shear * y
        y += 2.0 * s * c * x
        x += shear * y
        return x, y
    cosine = (c - s) * (c + s)
    sine = 2.0 * s * c
    return cosine * x - sine * y, sine * x + cosine * y


@njit
def _free(h, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3):  # type: ignore[no-untyped-def]
    """The second-order free flow R1(h/2) R3(h) R1(h/2) R_L(h), exact for a
    symmetric body. Returns the new (L, q). One sine and cosine of each half
    angle serve both the quaternion and the rotation of L, so the two turn by
    the same angle to round-off.
    """
    # R1(h/2): turn about axis 1 at ν = L1 (1/I1 − 1/I2); L turns by −ν h/2.
    half = 0.25 * h * l1 * (1.0 / i1 - 1.0 / i2)
    c, s = math.cos(half), math.sin(half)
    l3, l2 = _plane_rotation(l3, l2, c, s)
    q0, q1, q2, q3 = _turn(q0, q1, q2, q3, c, s, 1.0, 0.0, 0.0)
    # R3(h)
    half = 0.5 * h * l3 * (1.0 / i3 - 1.0 / i2)
    c, s = math.cos(half), math.sin(half)
    l2, l1 = _plane_rotation(l2, l1, c, s)
    q0, q1, q2, q3 = _turn(q0, q1, q2, q3, c, s, 0.0, 0.0, 1.0)
    # R1(h/2)
    half = 0.25 * h * l1 * (1.0 / i1 - 1.0 / i2)
    c, s = math.cos(half), math.sin(half)
    l3, l2 = _plane_rotation(l3, l2, c, s)
    q0, q1, q2, q3 = _turn(q0, q1, q2, q3, c, s, 1.0, 0.0, 0.0)
    # R_L(h): about L (fixed in the body during this part) at |L|/I2.
    size = math.sqrt(l1 * l1 + l2 * l2 + l3 * l3)
    if size > 0.0:
        half = 0.5 * h * size / i2
        c, s = math.cos(half), math.sin(half)
        q0, q1, q2, q3 = _turn(q0, q1, q2, q3, c, s, l1 / size, l2 / size, l3 / size)
    return l1, l2, l3, q0, q1, q2, q3


@njit(inline="always")
def _decay(c, moment, h):  # type: ignore[no-untyped-def]
    """∫₀ʰ exp(−c s / I) ds = (1 − exp(−c h / I)) I / c, and h when c = 0."""
    rate = c / moment
    if rate == 0.0:
        return h
    return -math.expm1(-rate * h) / rate


@njit(inline="always")
def _kick(t, h, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque, extra, context):  # type: ignore[no-untyped-def]
    """The exact flow of ``L̇ = τ_a − c L / I`` over h with the attitude held."""
    t1, t2, t3 = applied_torque(q0, q1, q2, q3, params, attitude_torque)
    e1, e2, e3 = extra(t, l1 / i1, l2 / i2, l3 / i3, q0, q1, q2, q3, context)
    c = params[12]
    l1 += (t1 + e1 - c * l1 / i1) * _decay(c, i1, h)
    l2 += (t2 + e2 - c * l2 / i2) * _decay(c, i2, h)
    l3 += (t3 + e3 - c * l3 / i3) * _decay(c, i3, h)
    return l1, l2, l3


@njit(inline="always")
def _strang(t, h, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque, extra, context):  # type: ignore[no-untyped-def]
    """One Strang step of length h (may be negative) from time t."""
    l1, l2, l3 = _kick(
        t, 0.5 * h, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque, extra, context
    )
    l1, l2, l3, q0, q1, q2, q3 = _free(h, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3)
    l1, l2, l3 = _kick(
        t + h, 0.5 * h, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque,
        extra, context,
    )  # fmt: skip
    return l1, l2, l3, q0, q1, q2, q3


@njit(inline="always")
def splitting_step(  # type: ignore[no-untyped-def]
    t, dt, order, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque, extra,
    context,
):  # fmt: skip
    """One step of ``dt`` from time t: Strang (``order`` 2) or Yoshida's triple
    jump of it (4), as sub-steps at one call site so the compiler inlines the
    Strang step once. Returns the new (L, q), q not renormalised."""
    if order == 2:
        fractions = (1.0, 0.0, 0.0)
        n_sub = 1
    else:
        fractions = (YOSHIDA_OUTER, YOSHIDA_INNER, YOSHIDA_OUTER)
        n_sub = 3
    for j in range(n_sub):
        h = fractions[j] * dt
        l1, l2, l3, q0, q1, q2, q3 = _strang(
            t, h, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque, extra, context
        )
        t += h
    return l1, l2, l3, q0, q1, q2, q3


@njit
def splitting_run(  # type: ignore[no-untyped-def]
    w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q, order
):
    """Advance (w, q) in place by ``n_steps`` splitting steps of ``dt`` s.

    ``order`` 2 (Strang) or 4 (Yoshida). Arguments, recording and the returned
    status as :func:`tumble.core.rigid.rk4_run`. The quaternion is renormalised
    after every step (the rotations keep it unit to round-off; this stops the
    round-off from accumulating).
    """
    return _splitting_loop(
        w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q, order,
        no_extra_torque, 0.0,
    )  # fmt: skip


@njit
def splitting_run_hooked(  # type: ignore[no-untyped-def]
    w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q, order, context
):
    """:func:`splitting_run` with a user's torque added (``context`` as in
    :func:`tumble.core.rigid.user_torque_hook`)."""
    return _splitting_loop(
        w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q, order,
        user_torque_hook, context,
    )  # fmt: skip


@njit(inline="always")
def _splitting_loop(  # type: ignore[no-untyped-def]
    w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q, order, extra,
    context,
):  # fmt: skip
    i1 = inertia[0]
    i2 = inertia[1]
    i3 = inertia[2]
    attitude_torque = has_attitude_torque(params)
    l1, l2, l3 = i1 * w[0], i2 * w[1], i3 * w[2]
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    for k in range(n_steps):
        t = (first_step + k) * dt
        m1, m2, m3, p0, p1, p2, p3 = splitting_step(
            t, dt, order, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque,
            extra, context,
        )  # fmt: skip
        norm = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3)
        if not (math.isfinite(norm) and math.isfinite(m1 + m2 + m3) and norm > 0.0):
            w[0], w[1], w[2] = l1 / i1, l2 / i2, l3 / i3
            q[0], q[1], q[2], q[3] = q0, q1, q2, q3
            return first_step + k + 1
        l1, l2, l3 = m1, m2, m3
        q0, q1, q2, q3 = p0 / norm, p1 / norm, p2 / norm, p3 / norm
        _record(
            first_step + k + 1, record_every, out_w, out_q,
            l1 / i1, l2 / i2, l3 / i3, q0, q1, q2, q3,
        )  # fmt: skip
    w[0], w[1], w[2] = l1 / i1, l2 / i2, l3 / i3
    q[0], q[1], q[2], q[3] = q0, q1, q2, q3
    return FINITE


@njit_parallel
def splitting_batch(w, q, inertia, params, dt, n_steps, order, status):  # type: ignore[no-untyped-def]
    """Advance N bodies in place by ``n_steps`` splitting steps, in parallel.

    Arrays as :func:`tumble.core.rigid.rk4_batch` (``params`` shared or per
    body); ``status`` (N,) int64 receives each body's status as in
    :func:`splitting_run` (the body then keeps its last finite state). Bodies
    are independent, one per thread at a time: the rotations' sines and cosines
    do not vectorise across bodies as RK4's products do.
    """
    n = w.shape[1]
    stride = 0 if params.shape[1] == 1 else 1  # shared or per-body params
    for body in prange(n):
        column = body * stride
        status[body] = _one_body(
            w[:, body], q[:, body], inertia[:, body], params[:, column], dt, n_steps, order
        )


@njit
def _one_body(w, q, inertia, params, dt, n_steps, order):  # type: ignore[no-untyped-def]
    """:func:`splitting_run` for one body of a batch, recording nothing."""
    never = np.iinfo(np.int64).max  # a record_every that no step number reaches
    return _splitting_loop(
        w, q, inertia, params, dt, n_steps, 0, never, np.zeros((1, 3)), np.zeros((1, 4)), order,
        no_extra_torque, 0.0,
    )  # fmt: skip
