"""Equations of motion of a body carrying internal parts, and the loops that step it.

A body may carry *rotors* (symmetric wheels spinning on body-fixed axes, driven
by motors: reaction and momentum wheels, a dual-spin rotor) and *Kane dampers*
(spheres turning in a viscous fluid inside it). Everything here is in the
principal frame of the body's **platform inertia** ``I_p = diag(p1, p2, p3)``:
its inertia about the reference point (the centre of mass, or a pivot) less
each rotor's ``J a aᵀ`` and each damper's ``J 1``, the part of the inertia
that turns at the body's own rate ω.

State ``y`` (``7 + m``):

* ``y[0:3]`` H: total angular momentum about the reference point (the body and
  every part), kg·m²/s;
* ``y[3:7]`` q: unit quaternion ``[w, x, y, z]`` turning principal-platform
  coordinates into space coordinates;
* one entry per rotor: its axial angular momentum ``h = J (a·ω + Ω)``,
  kg·m²/s (Ω its spin rate relative to the body);
* three per damper: the sphere's angular momentum ``σ = J ω_s``, kg·m²/s
  (ω_s its absolute angular velocity, in body components);
* two for a spring–mass damper (one a body at most): the point mass's
  displacement x along its direction n (m) and its momentum
  ``p = g·ω + μ ẋ`` (kg·m/s).

Velocities: ``ω = I_p⁻¹ (H − Σ h a − Σ σ)``, ``Ω = h / J − a·ω``, ``ω_s = σ / J``.
With a spring–mass damper (reduced mass μ = m (M − m) / M, rest position d0
from the rest of the body's centre of mass, ``d = d0 + x n``, ``g = μ d0 × n``)
the body's inertia about the moving centre of mass becomes ``I_p + Δ(x)``,
``Δ = μ ((|d|² − |d0|²) 1 − (d dᵀ − d0 d0ᵀ))``, and ω and ẋ solve
``(I_p + Δ) ω + g ẋ = H − Σ h a − Σ σ``, ``g·ω + μ ẋ = p``: the kinetic energy is
``½ ωᵀ (I_p + Δ) ω + ẋ ω·g + ½ μ ẋ²`` (checked against the sum over the masses
with sympy in the tests).
Equations (Hughes, *Spacecraft Attitude Dynamics*, 1986, §6.2 for the
gyrostat; Schaub & Junkins, *Analytical Mechanics of Space Systems*, §4.5)::

    Ḣ = τ − c ω − ω × H              (τ − c ω: the external torque)
    q̇ = ½ q ⊗ (0, ω)
    ḣ = u                             (the motor torque on the rotor; the body feels −u a)
    σ̇ = D (ω − ω_s) − ω × σ          (D: the damper's viscous coupling, N·m·s)
    ṗ = μ (ω × n)·(ω × d) − k x − c ẋ  (k the spring's stiffness, c its damping)

Internal torques (motors, the fluid) move momentum between the body and its
parts and leave H alone. Each rotor's motor torque ``u`` is its own schedule
(piecewise constant in time) plus its share of the torque that the torque
models acting *through the rotors* (an attitude controller driving reaction
wheels) ask of them: ``u = −P v`` with ``v`` that torque on the body and P the
pseudo-inverse of the matrix of rotor axes, so that ``−Σ u a = v`` when the
axes span space. ``u`` is then clipped to the rotor's largest torque, and set
to zero when it would drive the rotor past its largest speed.

Parts are packed in their order as rows of ``parts`` (rows, 1 shared or N per
body): per rotor ``ROTOR_FIELDS`` then ``n_schedule`` switch times and
``n_schedule`` torques (times padded with +inf), per damper ``DAMPER_FIELDS``,
for the spring–mass damper ``SPRING_FIELDS``. The kernels are built for one
layout ``(kinds, n_schedule)``: ``kinds`` the parts' kinds in order (``ROTOR``,
``DAMPER`` or ``SPRING``), the same order as the state.

A rotor's schedule is read at one *hold* time per step (its middle; for the
adaptive method, the middle of each stretch between switches, where the
driver ends its calls), so the motor torque is constant over a step and a
switch on a step boundary is integrated exactly, whatever the stages'
times (the fourth-order splitting steps outside [t, t + dt]).
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import FINITE, file_stamp, njit, njit_parallel, prange, specialise
from tumble.core.adaptive import adaptive_loop
from tumble.core.dynamics import quaternion_rates
from tumble.core.splitting import decay_integral, free_flow_one_body, sub_steps, turn

__all__ = [
    "DAMPER",
    "DAMPER_FIELDS",
    "ROTOR",
    "ROTOR_FIELDS",
    "SPRING",
    "SPRING_FIELDS",
    "adaptive_kernel",
    "batch_kernel",
    "parts_rk4_step",
    "rotor_rows",
    "single_kernel",
    "splitting_step",
    "strang_step",
    "velocity",
    "yoshida_step",
]

#: The rows of one rotor, before its schedule: axis (principal-platform axes),
#: axial moment J (kg·m²), largest motor torque (N·m), largest relative speed
#: (rad/s), and its row of the allocation matrix P (1/… : u = −P v).
ROTOR_FIELDS = ("axis_1", "axis_2", "axis_3", "inertia", "max_torque", "max_speed",
                "allocation_1", "allocation_2", "allocation_3")  # fmt: skip
#: The rows of one damper: the sphere's moment J (kg·m²) and the coupling D (N·m·s).
DAMPER_FIELDS = ("inertia", "damping")
#: The rows of a spring–mass damper: the rest position d0 (m, from the centre of
#: mass of the rest of the body), the unit direction n, the reduced mass μ (kg),
#: the stiffness k (N/m) and the damping c (N·s/m).
SPRING_FIELDS = ("rest_1", "rest_2", "rest_3", "direction_1", "direction_2", "direction_3",
                 "reduced_mass", "stiffness", "damping")  # fmt: skip

_ROTOR = len(ROTOR_FIELDS)
_DAMPER = len(DAMPER_FIELDS)
_SPRING = len(SPRING_FIELDS)

#: The kinds of part in a layout.
ROTOR = 0
DAMPER = 1
SPRING = 2


@njit(inline="always")
def rotor_rows(n_schedule):  # type: ignore[no-untyped-def]
    """Rows one rotor takes in ``parts``."""
    return _ROTOR + 2 * n_schedule


@njit(inline="always")
def velocity(layout, y, inverse, parts, pc):  # type: ignore[no-untyped-def]
    """ω (rad/s, principal-platform axes) of state ``y``: ``I_p⁻¹ (H − Σ h a − Σ σ)``,
    or with a spring–mass damper the solution of the module's docstring."""
    g1, g2, g3 = _internal_momentum(layout, y, parts, pc, True)
    r1, r2, r3 = y[0] - g1, y[1] - g2, y[2] - g3
    k, row = _spring_at(layout)
    if k < 0:
        return r1 * inverse[0], r2 * inverse[1], r3 * inverse[2]
    d1, d2, d3, _, _, _, mu, e1, e2, e3, g4, g5, g6 = _spring_geometry(y, parts, row, pc, k)
    # (I_p + Δ − g gᵀ / μ) ω = r − g p / μ, Δ = μ ((|d|² − |d0|²) 1 − (d dᵀ − d0 d0ᵀ)).
    grow = (d1 * d1 + d2 * d2 + d3 * d3) - (e1 * e1 + e2 * e2 + e3 * e3)
    p = y[k + 1]
    a11 = 1.0 / inverse[0] + mu * (grow - (d1 * d1 - e1 * e1)) - g4 * g4 / mu
    a22 = 1.0 / inverse[1] + mu * (grow - (d2 * d2 - e2 * e2)) - g5 * g5 / mu
    a33 = 1.0 / inverse[2] + mu * (grow - (d3 * d3 - e3 * e3)) - g6 * g6 / mu
    a12 = -mu * (d1 * d2 - e1 * e2) - g4 * g5 / mu
    a13 = -mu * (d1 * d3 - e1 * e3) - g4 * g6 / mu
    a23 = -mu * (d2 * d3 - e2 * e3) - g5 * g6 / mu
    return _solve3(a11, a12, a13, a22, a23, a33, r1 - g4 * p / mu, r2 - g5 * p / mu,
                   r3 - g6 * p / mu)  # fmt: skip


@njit(inline="always")
def _solve3(a11, a12, a13, a22, a23, a33, b1, b2, b3):  # type: ignore[no-untyped-def]
    """x of the symmetric 3 × 3 system A x = b, by cofactors (A positive definite)."""
    c11 = a22 * a33 - a23 * a23
    c12 = a13 * a23 - a12 * a33
    c13 = a12 * a23 - a13 * a22
    c22 = a11 * a33 - a13 * a13
    c23 = a12 * a13 - a11 * a23
    c33 = a11 * a22 - a12 * a12
    det = a11 * c11 + a12 * c12 + a13 * c13
    return (
        (c11 * b1 + c12 * b2 + c13 * b3) / det,
        (c12 * b1 + c22 * b2 + c23 * b3) / det,
        (c13 * b1 + c23 * b2 + c33 * b3) / det,
    )


@njit(inline="always")
def _spring_at(layout):  # type: ignore[no-untyped-def]
    """The index in the state and the first row of the spring–mass damper, or (−1, −1)."""
    kinds, n_schedule = layout
    k = 7
    row = 0
    for kind in kinds:
        if kind == SPRING:
            return k, row
        if kind == ROTOR:
            k += 1
            row += rotor_rows(n_schedule)
        else:
            k += 3
            row += _DAMPER
    return -1, -1


@njit(inline="always")
def _spring_geometry(y, parts, row, pc, k):  # type: ignore[no-untyped-def]
    """d = d0 + x n, n, μ, d0 and g = μ d0 × n of the spring–mass damper."""
    x = y[k]
    e1 = parts[row, pc]
    e2 = parts[row + 1, pc]
    e3 = parts[row + 2, pc]
    n1 = parts[row + 3, pc]
    n2 = parts[row + 4, pc]
    n3 = parts[row + 5, pc]
    mu = parts[row + 6, pc]
    return (
        e1 + x * n1, e2 + x * n2, e3 + x * n3, n1, n2, n3, mu, e1, e2, e3,
        mu * (e2 * n3 - e3 * n2), mu * (e3 * n1 - e1 * n3), mu * (e1 * n2 - e2 * n1),
    )  # fmt: skip


@njit(inline="always")
def _scheduled(parts, row, pc, n_schedule, hold):  # type: ignore[no-untyped-def]
    """The scheduled motor torque at time ``hold`` (right-continuous)."""
    value = 0.0
    for j in range(n_schedule):
        if parts[row + _ROTOR + j, pc] <= hold:
            value = parts[row + _ROTOR + n_schedule + j, pc]
    return value


@njit(inline="always")
def _motor(parts, row, pc, n_schedule, hold, h, w1, w2, w3, v1, v2, v3):  # type: ignore[no-untyped-def]
    """A rotor's motor torque (N·m): its schedule read at ``hold`` plus its share of
    the torque ``v`` the rotors must exert on the body, clipped to its limits."""
    a1 = parts[row, pc]
    a2 = parts[row + 1, pc]
    a3 = parts[row + 2, pc]
    u = _scheduled(parts, row, pc, n_schedule, hold) - (
        parts[row + 6, pc] * v1 + parts[row + 7, pc] * v2 + parts[row + 8, pc] * v3
    )
    largest = parts[row + 4, pc]
    u = min(max(u, -largest), largest)
    speed = h / parts[row + 3, pc] - (a1 * w1 + a2 * w2 + a3 * w3)
    limit = parts[row + 5, pc]
    if (speed >= limit and u > 0.0) or (speed <= -limit and u < 0.0):
        u = 0.0
    return u


@njit(inline="always")
def _torques(torque, drive, t, w1, w2, w3, q, system):  # type: ignore[no-untyped-def]
    """The external torque ``(τ1, τ2, τ3, c)`` (its damping c apart) and the torque
    ``v`` the rotors must exert on the body (its damping included)."""
    params, column, context = system[4], system[5], system[6]
    t1, t2, t3, c = torque(t, (w1, w2, w3), q, params, column, context)
    v1, v2, v3, cv = drive(t, (w1, w2, w3), q, params, column, context)
    return t1, t2, t3, c, v1 - cv * w1, v2 - cv * w2, v3 - cv * w3


@njit(inline="always")
def part_rates(torque, drive, layout, t, hold, y, dy, system):  # type: ignore[no-untyped-def]
    """``dy = f(t, y)`` for the state of the module's docstring, the schedules read
    at time ``hold``.

    ``system`` is ``(moments, inverse, parts, pc, params, column, context)``: the
    platform moments and their inverses (3,), the packed parts and their column,
    and the torque's params, column and context (:mod:`tumble.core.torques`).
    ``torque`` gives the external torque, ``drive`` the torque the rotors must
    exert on the body.
    """
    kinds, n_schedule = layout
    inverse, parts, pc = system[1], system[2], system[3]
    w1, w2, w3 = velocity(layout, y, inverse, parts, pc)
    q = (y[3], y[4], y[5], y[6])
    t1, t2, t3, c, v1, v2, v3 = _torques(torque, drive, t, w1, w2, w3, q, system)
    dy[0] = t1 - c * w1 - (w2 * y[2] - w3 * y[1])
    dy[1] = t2 - c * w2 - (w3 * y[0] - w1 * y[2])
    dy[2] = t3 - c * w3 - (w1 * y[1] - w2 * y[0])
    dy[3], dy[4], dy[5], dy[6] = quaternion_rates(q[0], q[1], q[2], q[3], w1, w2, w3)
    k = 7
    row = 0
    for kind in kinds:
        if kind == ROTOR:
            dy[k] = _motor(parts, row, pc, n_schedule, hold, y[k], w1, w2, w3, v1, v2, v3)
            k += 1
            row += rotor_rows(n_schedule)
        elif kind == DAMPER:
            moment = parts[row, pc]
            damping = parts[row + 1, pc]
            s1 = y[k]
            s2 = y[k + 1]
            s3 = y[k + 2]
            dy[k] = damping * (w1 - s1 / moment) - (w2 * s3 - w3 * s2)
            dy[k + 1] = damping * (w2 - s2 / moment) - (w3 * s1 - w1 * s3)
            dy[k + 2] = damping * (w3 - s3 / moment) - (w1 * s2 - w2 * s1)
            k += 3
            row += _DAMPER
        else:
            d1, d2, d3, n1, n2, n3, mu, _, _, _, g4, g5, g6 = _spring_geometry(y, parts, row, pc, k)
            speed = (y[k + 1] - (g4 * w1 + g5 * w2 + g6 * w3)) / mu
            # ∂T/∂x = μ (ω × n)·(ω × d), then the spring and its damping.
            c1, c2, c3 = w2 * n3 - w3 * n2, w3 * n1 - w1 * n3, w1 * n2 - w2 * n1
            f1, f2, f3 = w2 * d3 - w3 * d2, w3 * d1 - w1 * d3, w1 * d2 - w2 * d1
            dy[k] = speed
            dy[k + 1] = (
                mu * (c1 * f1 + c2 * f2 + c3 * f3)
                - parts[row + 7, pc] * y[k]
                - parts[row + 8, pc] * speed
            )
            k += 2
            row += _SPRING


@njit(inline="always")
def _normalise(y):  # type: ignore[no-untyped-def]
    scale = 1.0 / math.sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6])
    for i in range(3, 7):
        y[i] *= scale


@njit(inline="always")
def _finite(y):  # type: ignore[no-untyped-def]
    total = 0.0
    for i in range(y.shape[0]):
        total += y[i]
    norm = y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]
    return math.isfinite(total) and math.isfinite(norm) and norm > 0.0


@njit(inline="always")
def parts_rk4_step(torque, drive, layout, t, dt, y, work, system):  # type: ignore[no-untyped-def]
    """One classical Runge–Kutta step of ``dt`` s from time ``t``, in place on ``y``
    (``work`` (5, len(y)) scratch); the quaternion renormalised."""
    n = y.shape[0]
    hold = t + 0.5 * dt
    k1 = work[0]
    k2 = work[1]
    k3 = work[2]
    k4 = work[3]
    stage = work[4]
    part_rates(torque, drive, layout, t, hold, y, k1, system)
    for i in range(n):
        stage[i] = y[i] + 0.5 * dt * k1[i]
    part_rates(torque, drive, layout, hold, hold, stage, k2, system)
    for i in range(n):
        stage[i] = y[i] + 0.5 * dt * k2[i]
    part_rates(torque, drive, layout, hold, hold, stage, k3, system)
    for i in range(n):
        stage[i] = y[i] + dt * k3[i]
    part_rates(torque, drive, layout, t + dt, hold, stage, k4, system)
    sixth = dt / 6.0
    for i in range(n):
        y[i] += sixth * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i])
    _normalise(y)


# ------------------------------------------------------------------ the gyrostat splitting
@njit(inline="always")
def _internal_momentum(layout, y, parts, pc, dampers):  # type: ignore[no-untyped-def]
    """Σ h a (kg·m²/s, principal-platform axes): the rotors' momentum along their
    axes, plus the dampers' Σ σ when ``dampers``."""
    kinds, n_schedule = layout
    s1 = 0.0
    s2 = 0.0
    s3 = 0.0
    k = 7
    row = 0
    for kind in kinds:
        if kind == ROTOR:
            h = y[k]
            s1 += h * parts[row, pc]
            s2 += h * parts[row + 1, pc]
            s3 += h * parts[row + 2, pc]
            k += 1
            row += rotor_rows(n_schedule)
        elif kind == DAMPER:
            if dampers:
                s1 += y[k]
                s2 += y[k + 1]
                s3 += y[k + 2]
            k += 3
            row += _DAMPER
        else:  # a spring–mass damper: in the velocity's own solve
            k += 2
            row += _SPRING
    return s1, s2, s3


@njit(inline="always")
def _link(layout, h, y, system):  # type: ignore[no-untyped-def]
    """The exact flow over h of ``−b·H``, ``b = I_p⁻¹ Σ h a``: the body turns about
    the body-fixed b at the rate −|b|, so H turns about b by +|b| h in the body."""
    inverse = system[1]
    parts = system[2]
    pc = system[3]
    g1, g2, g3 = _internal_momentum(layout, y, parts, pc, False)
    b1 = g1 * inverse[0]
    b2 = g2 * inverse[1]
    b3 = g3 * inverse[2]
    size = math.sqrt(b1 * b1 + b2 * b2 + b3 * b3)
    if size == 0.0:
        return
    e1 = b1 / size
    e2 = b2 / size
    e3 = b3 / size
    half = 0.5 * size * h
    c = math.cos(half)
    s = math.sin(half)
    # H' = H + 2c s (e × H) + 2 s² e × (e × H): H turned about e by 2·half.
    l1 = y[0]
    l2 = y[1]
    l3 = y[2]
    x1 = e2 * l3 - e3 * l2
    x2 = e3 * l1 - e1 * l3
    x3 = e1 * l2 - e2 * l1
    z1 = e2 * x3 - e3 * x2
    z2 = e3 * x1 - e1 * x3
    z3 = e1 * x2 - e2 * x1
    y[0] = l1 + 2.0 * s * (c * x1 + s * z1)
    y[1] = l2 + 2.0 * s * (c * x2 + s * z2)
    y[2] = l3 + 2.0 * s * (c * x3 + s * z3)
    y[3], y[4], y[5], y[6] = turn(y[3], y[4], y[5], y[6], c, -s, e1, e2, e3)


@njit(inline="always")
def _kick(torque, drive, layout, t, hold, h, y, system):  # type: ignore[no-untyped-def]
    """The torques over h with the attitude and the torques held: the external
    torque on H (its damping ``c`` integrated exactly) and the motor torques on
    the rotors' momenta (schedules read at ``hold``)."""
    kinds, n_schedule = layout
    moments, inverse, parts, pc = system[0], system[1], system[2], system[3]
    g1, g2, g3 = _internal_momentum(layout, y, parts, pc, False)
    w1 = (y[0] - g1) * inverse[0]
    w2 = (y[1] - g2) * inverse[1]
    w3 = (y[2] - g3) * inverse[2]
    q = (y[3], y[4], y[5], y[6])
    t1, t2, t3, c, v1, v2, v3 = _torques(torque, drive, t, w1, w2, w3, q, system)
    k = 7
    row = 0
    for _ in kinds:  # the splitting's bodies carry rotors only
        u = _motor(parts, row, pc, n_schedule, hold, y[k], w1, w2, w3, v1, v2, v3)
        y[k] += u * h
        k += 1
        row += rotor_rows(n_schedule)
    y[0] += (t1 - c * w1) * decay_integral(c, moments[0], h)
    y[1] += (t2 - c * w2) * decay_integral(c, moments[1], h)
    y[2] += (t3 - c * w3) * decay_integral(c, moments[2], h)


@njit(inline="always")
def _strang(torque, drive, layout, t, h, hold, y, system):  # type: ignore[no-untyped-def]
    """kick(h/2) ∘ link(h/2) ∘ free(h) ∘ link(h/2) ∘ kick(h/2), from time t."""
    inverse = system[1]
    _kick(torque, drive, layout, t, hold, 0.5 * h, y, system)
    _link(layout, 0.5 * h, y, system)
    # The C library's sines: the kernels turn one body at a time.
    y[0], y[1], y[2], y[3], y[4], y[5], y[6] = free_flow_one_body(
        h, y[0], y[1], y[2], y[3], y[4], y[5], y[6], inverse[0], inverse[1], inverse[2]
    )
    _link(layout, 0.5 * h, y, system)
    _kick(torque, drive, layout, t + h, hold, 0.5 * h, y, system)


@njit(inline="always")
def splitting_step(torque, drive, layout, t, dt, y, work, system, order):  # type: ignore[no-untyped-def]
    """One splitting step of ``dt`` s from ``t``, in place: Strang (``order`` 2) or
    Yoshida's triple jump of it (4). The free flow of the gyrostat,
    ``T = ½ (H − g)ᵀ I_p⁻¹ (H − g)`` with ``g = Σ h a`` constant between kicks,
    is the rigid body's ``½ Hᵀ I_p⁻¹ H`` (the exact rotations of
    :func:`tumble.core.splitting.free_flow_one_body`) and the linear ``−(I_p⁻¹ g)·H``, an
    exact rotation about a body-fixed axis: explicit and symplectic, H kept to
    round-off (``work`` is not used)."""
    fractions, n_sub = sub_steps(order)
    hold = t + 0.5 * dt
    # The sub-steps at one call site, so the compiler inlines the Strang step once.
    for j in range(n_sub):
        h = fractions[j] * dt
        _strang(torque, drive, layout, t, h, hold, y, system)
        t += h
    _normalise(y)


@njit(inline="always")
def strang_step(torque, drive, layout, t, dt, y, work, system):  # type: ignore[no-untyped-def]
    """:func:`splitting_step` of order 2 (Strang)."""
    splitting_step(torque, drive, layout, t, dt, y, work, system, 2)


@njit(inline="always")
def yoshida_step(torque, drive, layout, t, dt, y, work, system):  # type: ignore[no-untyped-def]
    """:func:`splitting_step` of order 4 (Yoshida's triple jump of Strang)."""
    splitting_step(torque, drive, layout, t, dt, y, work, system, 4)


# ------------------------------------------------------------------ loops
@njit(inline="always")
def _steps(step, torque, drive, layout, y, system, dt, n_steps, first_step, record_every, out):  # type: ignore[no-untyped-def]
    """``n_steps`` steps of one body in place; its status (see :func:`single_kernel`)."""
    n = y.shape[0]
    work = np.empty((5, n))
    saved = np.empty(n)
    status = FINITE
    for k in range(n_steps):
        number = first_step + k
        for i in range(n):
            saved[i] = y[i]
        step(torque, drive, layout, number * dt, dt, y, work, system)
        if not _finite(y):
            for i in range(n):
                y[i] = saved[i]
            status = number + 1
            break
        if (number + 1) % record_every == 0:
            row = (number + 1) // record_every
            for i in range(n):
                out[row, i] = y[i]
    return status


def single_kernel(step, torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """``run(y, moments, parts, params, context, dt, n_steps, first_step, record_every,
    out) -> status``: advance one body's state ``y`` (7 + m,) in place by
    ``n_steps`` steps of ``dt`` s with ``step`` (:func:`parts_rk4_step`,
    :func:`strang_step` or :func:`yoshida_step`), for ``layout``.

    After global step ``first_step + k + 1``, if that number is a multiple of
    ``record_every``, the state is written to row ``number // record_every`` of
    ``out`` (·, 7 + m). The time of global step k is ``k dt``. Returns ``FINITE``,
    or the global number of the first step that was not finite (the state is
    left as it was before it).
    """

    @specialise(njit, f"parts.single|{file_stamp(step)}|{layout}|{identity}")
    def run(y, moments, parts, params, context, dt, n_steps, first_step, record_every, out):  # type: ignore[no-untyped-def]
        inverse = 1.0 / moments
        system = (moments, inverse, parts, 0, params, 0, context)
        return _steps(
            step, torque, drive, layout, y, system, dt, n_steps, first_step, record_every, out
        )

    return run


def batch_kernel(step, torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """``batch(y, moments, parts, params, context, t0, dt, n_steps, status)``: N bodies
    (``y`` (7 + m, N), ``moments`` (3, N); ``parts`` and ``params`` shared or one
    column per body) advanced in place, one body per thread at a time; ``status``
    (N,) receives each body's status (a body keeps its last finite state)."""

    # One body per call of a compiled function of its own, as in
    # tumble.core.splitting: inlined into the parallel loop, the stepping
    # defeats numba's parfor analysis.
    @specialise(njit, f"parts.body|{file_stamp(step)}|{layout}|{identity}")
    def one_body(y, moments, parts, pc, params, column, context, t0, dt, n_steps):  # type: ignore[no-untyped-def]
        inverse = 1.0 / moments
        system = (moments, inverse, parts, pc, params, column, context)
        never = np.iinfo(np.int64).max
        first = int(t0 / dt + 0.5) if dt > 0.0 else 0
        return _steps(
            step, torque, drive, layout, y, system, dt, n_steps, first, never, np.zeros((1, 1))
        )

    @specialise(njit_parallel, f"parts.batch|{file_stamp(step)}|{layout}|{identity}")
    def batch(y, moments, parts, params, context, t0, dt, n_steps, status):  # type: ignore[no-untyped-def]
        part_stride = 0 if parts.shape[1] == 1 else 1
        param_stride = 0 if params.shape[1] == 1 else 1
        for body in prange(y.shape[1]):
            state = y[:, body].copy()
            status[body] = one_body(
                state, moments[:, body].copy(), parts, body * part_stride, params,
                body * param_stride, context, t0, dt, n_steps,
            )  # fmt: skip
            y[:, body] = state

    return batch


def adaptive_kernel(torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """``run(y, moments, parts, params, context, t_start, t_stop, control,
    sample_times, out) -> status``: one body's state ``y`` integrated in place from
    ``t_start`` to ``t_stop`` (s) by Dormand–Prince 5(4)
    (:func:`tumble.core.adaptive.adaptive_loop`: ``control``, the samples written
    to the rows of ``out`` (m, 7 + m') and the status as there). The schedules
    are read at the middle of (t_start, t_stop): the driver ends each call at
    the next switch."""

    @njit(inline="always", cache=False)
    def rates_of_parts(t, y, dy, args):  # type: ignore[no-untyped-def]
        system, hold = args
        part_rates(torque, drive, layout, t, hold, y, dy, system)

    @specialise(njit, f"parts.adaptive|{layout}|{identity}")
    def run(y, moments, parts, params, context, t_start, t_stop, control, sample_times, out):  # type: ignore[no-untyped-def]
        inverse = 1.0 / moments
        system = (moments, inverse, parts, 0, params, 0, context)
        hold = 0.5 * (t_start + t_stop)
        return adaptive_loop(
            rates_of_parts, (system, hold), y, t_start, t_stop, control, sample_times, out
        )

    return run
