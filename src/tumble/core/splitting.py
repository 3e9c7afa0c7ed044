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
steps of w1 h, w0 h, w1 h with w1 = 1/(2 − 2^(1/3)), w0 = 1 − 2 w1.
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import FINITE, njit, njit_parallel, prange, specialise
from tumble.core.dynamics import is_finite, normalised, record
from tumble.core.freebody import free_step
from tumble.core.metrics import (
    ENERGY_DEVIATION,
    FIRST_FLIP,
    FLIPS,
    MIN_COS,
    MOMENTUM_DEVIATION,
    finish,
    initial,
    observe,
)

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
def free_flow(h, l1, l2, l3, q0, q1, q2, q3, i1, i2, i3):  # type: ignore[no-untyped-def]
    """The second-order free flow R1(h/2) R3(h) R1(h/2) R_L(h), exact for a
    symmetric body. Returns the new (L, q). One sine and cosine of each half
    angle serve both the quaternion and the rotation of L, so the two turn by
    the same angle to round-off.
    """
    # R1(h/2): turn about axis 1 at ν = L1 (1/I1 − 1/I2); L turns by −ν h/2.
    half = 0.25 * h * l1 * (1.0 / i1 - 1.0 / i2)
    c, s = math.cos(half), math.sin(half)
    l3, l2 = _plane_rotation(l3, l2, c, s)
    q0, q1, q2, q3 = turn(q0, q1, q2, q3, c, s, 1.0, 0.0, 0.0)
    # R3(h)
    half = 0.5 * h * l3 * (1.0 / i3 - 1.0 / i2)
    c, s = math.cos(half), math.sin(half)
    l2, l1 = _plane_rotation(l2, l1, c, s)
    q0, q1, q2, q3 = turn(q0, q1, q2, q3, c, s, 0.0, 0.0, 1.0)
    # R1(h/2)
    half = 0.25 * h * l1 * (1.0 / i1 - 1.0 / i2)
    c, s = math.cos(half), math.sin(half)
    l3, l2 = _plane_rotation(l3, l2, c, s)
    q0, q1, q2, q3 = turn(q0, q1, q2, q3, c, s, 1.0, 0.0, 0.0)
    # R_L(h): about L (fixed in the body during this part) at |L|/I2.
    size = math.sqrt(l1 * l1 + l2 * l2 + l3 * l3)
    if size > 0.0:
        half = 0.5 * h * size / i2
        c, s = math.cos(half), math.sin(half)
        q0, q1, q2, q3 = turn(q0, q1, q2, q3, c, s, l1 / size, l2 / size, l3 / size)
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
def decay_integral(c, moment, h):  # type: ignore[no-untyped-def]
    """∫₀ʰ exp(−c s / I) ds = (1 − exp(−c h / I)) I / c, and h when c = 0."""
    rate = c / moment
    if rate == 0.0:
        return h
    return -math.expm1(-rate * h) / rate


@njit(inline="always")
def _kick(torque, t, h, l1, l2, l3, q, i1, i2, i3, params, column, context):  # type: ignore[no-untyped-def]
    """The exact flow of ``L̇ = τ − c L / I`` over h with the attitude and τ held."""
    t1, t2, t3, c = torque(t, (l1 / i1, l2 / i2, l3 / i3), q, params, column, context)
    l1 += (t1 - c * l1 / i1) * decay_integral(c, i1, h)
    l2 += (t2 - c * l2 / i2) * decay_integral(c, i2, h)
    l3 += (t3 - c * l3 / i3) * decay_integral(c, i3, h)
    return l1, l2, l3


@njit(inline="always")
def _strang(torque, flow, t, h, l1, l2, l3, q, i1, i2, i3, params, column, context):  # type: ignore[no-untyped-def]
    """One Strang step of length h (may be negative) from time t, with the free
    flow ``flow`` (:func:`free_flow` or :func:`exact_free_flow`)."""
    l1, l2, l3 = _kick(torque, t, 0.5 * h, l1, l2, l3, q, i1, i2, i3, params, column, context)
    l1, l2, l3, q0, q1, q2, q3 = flow(h, l1, l2, l3, q[0], q[1], q[2], q[3], i1, i2, i3)
    q = (q0, q1, q2, q3)
    l1, l2, l3 = _kick(torque, t + h, 0.5 * h, l1, l2, l3, q, i1, i2, i3, params, column, context)
    return l1, l2, l3, q


@njit(inline="always")
def sub_steps(order):  # type: ignore[no-untyped-def]
    """The fractions of a step taken by Strang sub-steps, and how many: one whole
    step (``order`` 2), or Yoshida's triple jump (4)."""
    if order == 2:
        return (1.0, 0.0, 0.0), 1
    return (YOSHIDA_OUTER, YOSHIDA_INNER, YOSHIDA_OUTER), 3


@njit(inline="always")
def splitting_step(torque, flow, t, dt, order, state, inertia, params, column, context):  # type: ignore[no-untyped-def]
    """One step of ``dt`` s from time t of ``state`` = (L1, L2, L3, q0, … q3) (L in
    kg·m²/s, principal axes; ``inertia`` the principal moments): Strang
    (``order`` 2) or Yoshida's triple jump of it (4), as sub-steps at one call
    site so the compiler inlines the Strang step once; ``flow`` is the free
    flow. Returns the new state, the quaternion renormalised."""
    fractions, n_sub = sub_steps(order)
    l1, l2, l3, q0, q1, q2, q3 = state
    i1, i2, i3 = inertia
    q = (q0, q1, q2, q3)
    for j in range(n_sub):
        h = fractions[j] * dt
        l1, l2, l3, q = _strang(
            torque, flow, t, h, l1, l2, l3, q, i1, i2, i3, params, column, context
        )
        t += h
    return normalised((l1, l2, l3, q[0], q[1], q[2], q[3]))


@njit(inline="always")
def _momentum(w, q, i1, i2, i3):  # type: ignore[no-untyped-def]
    """The state (L, q) of (ω, q) arrays: L = I ω."""
    return (i1 * w[0], i2 * w[1], i3 * w[2], q[0], q[1], q[2], q[3])


@njit(inline="always")
def _velocity(state, i1, i2, i3):  # type: ignore[no-untyped-def]
    """The state (ω, q) of (L, q)."""
    return (
        state[0] / i1, state[1] / i2, state[2] / i3, state[3], state[4], state[5], state[6]
    )  # fmt: skip


@njit(inline="always")
def _steps(  # type: ignore[no-untyped-def]
    torque, flow, w, q, inertia, params, column, context, t0, dt, n_steps, order, record_every,
    out_w, out_q, first_step,
):  # fmt: skip
    """``n_steps`` splitting steps of one body, in place; its status. The time of
    step k is ``t0 + k dt`` (global step ``first_step + k``)."""
    i1, i2, i3 = inertia[0], inertia[1], inertia[2]
    state = _momentum(w, q, i1, i2, i3)
    status = FINITE
    for k in range(n_steps):
        step = splitting_step(
            torque, flow, t0 + k * dt, dt, order, state, (i1, i2, i3), params, column, context
        )
        if not is_finite(step):
            status = first_step + k + 1
            break
        state = step
        record(first_step + k + 1, record_every, out_w, out_q, _velocity(state, i1, i2, i3))
    final = _velocity(state, i1, i2, i3)
    for i in range(3):
        w[i] = final[i]
    for i in range(4):
        q[i] = final[3 + i]
    return status


def _flow(exact_flow):  # type: ignore[no-untyped-def]
    """The free flow and the kernels' name: the rotations, or the exact flow."""
    return (exact_free_flow, "splitting-exact") if exact_flow else (free_flow, "splitting")


def single_kernel(torque, identity, order, exact_flow=False):  # type: ignore[no-untyped-def]
    """``run(w, q, inertia, params, context, dt, n_steps, first_step, record_every,
    out_w, out_q) -> status``: ``n_steps`` steps of ``order`` 2 (Strang) or 4
    (Yoshida), arguments, recording and status as
    :func:`tumble.core.stepping.single_kernel`; with ``exact_flow``, around the
    exact free flow (:func:`exact_free_flow`)."""
    flow, name = _flow(exact_flow)

    @specialise(njit, f"{name}.single.{order}|{identity}")
    def run(w, q, inertia, params, context, dt, n_steps, first_step, record_every, out_w, out_q):  # type: ignore[no-untyped-def]
        return _steps(
            torque, flow, w, q, inertia, params, 0, context, first_step * dt, dt, n_steps, order,
            record_every, out_w, out_q, first_step,
        )  # fmt: skip

    return run


def batch_kernel(torque, identity, order, exact_flow=False):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, t0, dt, n_steps, status)``: N bodies
    (arrays as :func:`tumble.core.stepping.batch_kernel`) advanced in place, one body
    per thread at a time (the rotations' sines and cosines do not vectorise
    across bodies as RK4's products do); ``status`` (N,) int64 receives each
    body's status (the body then keeps its last finite state). ``exact_flow``
    as :func:`single_kernel`."""
    flow, name = _flow(exact_flow)

    # One body per call of a compiled function of its own: inlined into the
    # parallel loop, the stepping's tuples defeat numba's parfor analysis.
    @specialise(njit, f"{name}.body.{order}|{identity}")
    def one_body(w, q, inertia, params, column, context, t0, dt, n_steps):  # type: ignore[no-untyped-def]
        never = np.iinfo(np.int64).max  # a record_every that no step number reaches
        return _steps(
            torque, flow, w, q, inertia, params, column, context, t0, dt, n_steps, order, never,
            np.zeros((1, 3)), np.zeros((1, 4)), 0,
        )  # fmt: skip

    @specialise(njit_parallel, f"{name}.batch.{order}|{identity}")
    def batch(w, q, inertia, params, context, t0, dt, n_steps, status):  # type: ignore[no-untyped-def]
        stride = 0 if params.shape[1] == 1 else 1  # shared or per-body params
        for body in prange(w.shape[1]):
            status[body] = one_body(
                w[:, body], q[:, body], inertia[:, body], params, body * stride, context, t0,
                dt, n_steps,
            )  # fmt: skip

    return batch


def metrics_kernel(torque, identity, order, exact_flow=False):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status)``:
    as :func:`batch_kernel`, measuring each body after every step into ``out``
    (``N_METRICS``, N) (see :mod:`tumble.core.metrics`); a body's measures stop
    at its last finite state. ``exact_flow`` as :func:`single_kernel`."""
    flow, name = _flow(exact_flow)

    @specialise(njit, f"{name}.measured.{order}|{identity}")
    def one_body(w, q, inertia, params, column, context, axis, t0, dt, n_steps, out):  # type: ignore[no-untyped-def]
        return _measured(
            torque, flow, w, q, inertia, params, column, context, axis, t0, dt, n_steps, order,
            out,
        )  # fmt: skip

    @specialise(njit_parallel, f"{name}.metrics.{order}|{identity}")
    def batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status):  # type: ignore[no-untyped-def]
        stride = 0 if params.shape[1] == 1 else 1
        for body in prange(w.shape[1]):
            status[body] = one_body(
                w[:, body], q[:, body], inertia[:, body], params, body * stride, context,
                axis[:, body], t0, dt, n_steps, out[:, body],
            )  # fmt: skip

    return batch


@njit(inline="always")
def _measured(  # type: ignore[no-untyped-def]
    torque, flow, w, q, inertia, params, column, context, axis, t0, dt, n_steps, order, out
):
    i1, i2, i3 = inertia[0], inertia[1], inertia[2]
    a1, a2, a3 = axis[0], axis[1], axis[2]
    state = _momentum(w, q, i1, i2, i3)
    reference, energy0, squared0, lowest = initial(w[0], w[1], w[2], i1, i2, i3, a1, a2, a3)
    flips = 0.0
    crossed_at = before = after = 0.0
    energy_dev = 0.0
    smallest = largest = squared0
    status = FINITE
    for k in range(n_steps):
        step = splitting_step(
            torque, flow, t0 + k * dt, dt, order, state, (i1, i2, i3), params, column, context
        )
        if not is_finite(step):
            status = k + 1
            break
        state = step
        reference, flips, crossed_at, before, after, lowest, energy_dev, smallest, largest = (
            observe(
                t0 + (k + 1) * dt, state[0] / i1, state[1] / i2, state[2] / i3, i1, i2, i3,
                a1, a2, a3, reference, flips, crossed_at, before, after, lowest, energy0,
                energy_dev, smallest, largest,
            )
        )  # fmt: skip
    final = _velocity(state, i1, i2, i3)
    for i in range(3):
        w[i] = final[i]
    for i in range(4):
        q[i] = final[3 + i]
    (
        out[FLIPS], out[FIRST_FLIP], out[MIN_COS], out[ENERGY_DEVIATION], out[MOMENTUM_DEVIATION],
    ) = finish(
        dt, flips, crossed_at, before, after, lowest, energy_dev, squared0, smallest, largest
    )  # fmt: skip
    return status
