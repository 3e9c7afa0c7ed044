"""Equations of motion of a body carrying internal parts, and the loops that step it.

A body may carry *parts* that move inside it: rotors (symmetric wheels on
body-fixed axes, driven by motors), Kane dampers (spheres turning in a
viscous fluid), a spring–mass damper (a point mass sliding on a spring), or
any kind registered in :mod:`tumble.parts`. Everything here is in the
principal frame of the body's **platform inertia** ``I_p = diag(p1, p2, p3)``:
its inertia about the reference point (the centre of mass, or a pivot) less
each part's spin inertia, the part of the inertia that turns at the body's
own rate ω.

State ``y`` (``7 + m``):

* ``y[0:3]`` H: total angular momentum about the reference point (the body and
  every part), kg·m²/s;
* ``y[3:7]`` q: unit quaternion ``[w, x, y, z]`` turning principal-platform
  coordinates into space coordinates;
* then each part's momenta, in the order of the parts (a rotor's axial
  momentum, a damper sphere's angular momentum, a spring's displacement and
  momentum: see each kind's equations, :mod:`tumble.core.rotor` and
  :mod:`tumble.core.dampers`).

**A part kind's equations** (:class:`PartEquations`) are compiled functions of
one signature each, reading the part's state from ``y[k], y[k + 1], …`` (``y``
an array, or a tuple where bodies step in blocks: the equations read it, and
only the kicks write it) and its packed values from rows ``row … row + rows −
1`` of column ``pc`` of ``parts``:

* ``momentum(y, k, parts, row, rows, pc) -> (m1, m2, m3)`` and, for a part
  that moves mass, ``inertia(y, k, parts, row, rows, pc) -> (a11, a12, a13,
  a22, a23, a33)``: the body's angular velocity is the solution of
  ``(I_p + Σ inertia) ω = H − Σ momentum`` (for a rotor ``h a``, for a damper
  its sphere's momentum; a spring–mass damper moves the centre of mass:
  :mod:`tumble.core.dampers`);
* ``rates(y, k, parts, row, rows, pc, w, v, hold) -> (ẏ_k, ẏ_k+1, …)``: the
  rates of its state, a tuple of floats as long as its state, with ``w`` = ω
  and ``v`` the torque the parts that act through the rotors must exert on the
  body (a motor's share), read at time ``hold``;
* for a part the splitting integrators take (a rotor: its momentum is fixed
  in the body between kicks), ``kick(y, k, parts, row, rows, pc, w, v, hold,
  h) -> (y_k', …)``: its momenta advanced over ``h`` with the attitude held, a
  tuple as long as its state (reading its own entries of ``y`` alone);
* for a part whose energy a sweep measures, ``energy(y, k, parts, row, rows,
  pc, w) -> ε`` (J): its momenta times their rates relative to the body, plus
  twice its potential energy, so that twice the energy of the body and its
  parts is ``ω · H + Σ ε`` (for a quadratic kinetic energy, twice it is the
  velocities times the momenta: ω · H for the body's ω, each part's own for
  its coordinates);
* for a part whose values no change of axes turns (a rotor's spin rate
  relative to the body), ``values(y, k, parts, row, rows, pc, w) -> (value,
  …)``: what :meth:`tumble.parts.InternalPart.values_from` gives, a tuple as
  long as its state, so that a trajectory is read back in one compiled call
  (:func:`readout`);
* for a part whose momentum lies along a unit axis fixed in the body (a
  rotor's), ``axis_row``: the first of the three packed rows holding that axis,
  so that bodies whose parts all lie on one principal axis take the splitting
  that turns about it (:func:`gyrostat_flow`).

Equations of the body (Hughes, *Spacecraft Attitude Dynamics*, 1986, §6.2 for
the gyrostat; Schaub & Junkins, *Analytical Mechanics of Space Systems*,
§4.5)::

    Ḣ = τ − c ω − ω × H              (τ − c ω: the external torque)
    q̇ = ½ q ⊗ (0, ω)

Internal torques (motors, fluids, springs) move momentum between the body
and its parts and leave H alone.

:func:`part_model` composes the equations of one *layout* (the parts' kinds
in order, with their state sizes and packed rows) into the four functions the
steps close over (``velocity``, ``momentum``, ``rates``, ``kick``); the
kernels are built for one layout and cached under its identity. A batch steps
blocks of bodies (:mod:`tumble.core.part_blocks`), each body's state a tuple;
:func:`batch_kernel` and :func:`tumble.core.part_measures.measuring_kernel` step
one body per thread with the step of one body alone, the reference the blocks
are checked against (``tests/core/test_parts_kernels.py``).
"""

from __future__ import annotations

import math
from functools import cache
from typing import Any, NamedTuple

import numpy as np
from numba.core.extending import overload

from tumble.core._jit import (
    FINITE,
    file_stamp,
    njit,
    njit_parallel,
    prange,
    specialise,
)
from tumble.core.adaptive import adaptive_loop
from tumble.core.dynamics import free_torque, is_free, quaternion_rates
from tumble.core.quaternion import multiply_right_into
from tumble.core.rk4 import entry_by_entry, rk4_tuple_step
from tumble.core.splitting import (
    decay_integral,
    free_turns,
    principal_turn,
    sub_step,
    sub_step_start,
    sub_steps,
    turn,
    turn_about_momentum,
)
from tumble.core.trig import LARGEST_ANGLE, library_cos_sin

__all__ = [
    "GyrostatFlow",
    "PartEquations",
    "PartModel",
    "adaptive_kernel",
    "along_principal_axis",
    "batch_kernel",
    "finite_state",
    "gyrostat_flow",
    "layout_identity",
    "make_rk4_step",
    "make_strang_step",
    "make_yoshida_step",
    "measured_energy",
    "momentum_axis",
    "nothing_after",
    "part_energy",
    "part_model",
    "part_rates",
    "single_kernel",
    "solve3",
    "splitting_step",
    "state_rates",
    "velocities",
]


class PartEquations(NamedTuple):
    """A part kind's compiled equations (see the module's docstring): ``inertia``
    None for a part that moves no mass, ``kick`` None for a part the splitting
    integrators do not take, ``energy`` None for a part whose energy sweeps do
    not measure, ``values`` None for a part whose values a trajectory reads back
    in Python (:meth:`tumble.parts.InternalPart.values_from`).

    ``axis_row``: for a part whose momentum lies along a unit axis fixed in the
    body (a rotor's), the first of the three packed rows that hold that axis;
    None for any other. ``principal_axis``: set by
    :func:`tumble.parts.pack_parts` (:func:`along_principal_axis`) when that axis
    is the principal axis 0, 1 or 2 of every body packed, so that the splitting
    turns about it (:func:`gyrostat_flow`); None otherwise. ``idle``: set by
    :func:`tumble.parts.pack_parts` for a part that says so
    (:attr:`tumble.parts.InternalPart.idle`: a rotor without a motor): only a
    torque through the parts (the drive) changes its state, so without one its
    kick leaves it as it is."""

    momentum: Any
    rates: Any
    inertia: Any = None
    kick: Any = None
    energy: Any = None
    values: Any = None
    axis_row: int | None = None
    principal_axis: int | None = None
    idle: bool = False


#: One part in a layout: its equations, its state size and its packed rows.
LayoutEntry = tuple[PartEquations, int, int]


class PartModel(NamedTuple):
    """The compiled functions of one layout: ``velocity(y, inverse, parts, pc) ->
    ω``, ``momentum(y, parts, pc) -> Σ momentum``, ``rates(y, parts, pc, w, v,
    hold) -> the parts' rates`` (a tuple, in the order of their states) and
    ``kick(y, parts, pc, w, v, hold, h) -> the parts' new states`` (a tuple, the
    kicks of the parts that have one: the splitting kernels take a layout only
    when every part kicks and none moves mass,
    :attr:`tumble.parts.InternalPart.splittable`); ``size``, the state's length
    (7 + m)."""

    velocity: Any
    momentum: Any
    rates: Any
    kick: Any
    size: int


def layout_identity(layout: tuple[LayoutEntry, ...]) -> str:
    """A stable description of a layout, for the kernels' cache keys: each part's
    equations (the source stamp of every one of its functions: two kinds that
    share their rates but not their momentum compile apart), state size and
    rows."""
    return ";".join(
        ",".join(file_stamp(f) for f in equations if callable(f))
        + f":{size}:{rows}"
        + ("" if equations.principal_axis is None else f":axis{equations.principal_axis}")
        + (":idle" if equations.idle else "")
        for equations, size, rows in layout
    )


def along_principal_axis(
    layout: tuple[LayoutEntry, ...], packed: np.ndarray
) -> tuple[LayoutEntry, ...]:
    """``layout`` with every part's :attr:`PartEquations.principal_axis` set to k
    when every part's momentum lies along the principal axis k of every body
    packed in ``packed`` (rows, N): its axis (rows ``axis_row`` …) exactly
    ±e_k, the other two entries zero. ``layout`` itself otherwise (a part that
    moves its momentum's axis, axes on different principal axes, or off them
    by any amount: those bodies take the general splitting)."""
    found: set[int] = set()
    row = 0
    for equations, _, rows in layout:
        if equations.axis_row is None:
            return layout
        axis = packed[row + equations.axis_row : row + equations.axis_row + 3]
        nonzero = axis != 0.0
        if not np.all(np.count_nonzero(nonzero, axis=0) == 1):
            return layout
        found.update(np.flatnonzero(nonzero.any(axis=1)).tolist())
        row += rows
    if len(found) != 1:
        return layout
    (k,) = found
    return tuple(
        (equations._replace(principal_axis=k), size, rows) for equations, size, rows in layout
    )


@njit(inline="always")
def solve3(a11, a12, a13, a22, a23, a33, b1, b2, b3):  # type: ignore[no-untyped-def]
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


# ------------------------------------------------------------------ one layout's functions
# Each function below is a closure over the equations of one part and its place
# (k, row, rows), chained with the previous parts' (as tumble.core.torques.combine
# chains torque terms): the compiler inlines the whole chain, so a layout's
# functions run as if written out by hand for it.
@njit(inline="always")
def _no_momentum(y, parts, pc):  # type: ignore[no-untyped-def]
    return 0.0, 0.0, 0.0


@njit(inline="always")
def _no_inertia(y, parts, pc):  # type: ignore[no-untyped-def]
    return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0


@njit(inline="always")
def _no_rates(y, parts, pc, w, v, hold):  # type: ignore[no-untyped-def]
    return ()


@njit(inline="always")
def _no_kick(y, parts, pc, w, v, hold, h):  # type: ignore[no-untyped-def]
    return ()


@njit(inline="always")
def _no_energy(y, parts, pc, w):  # type: ignore[no-untyped-def]
    return 0.0


def _chain_energy(previous, energy, k, row, rows):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def total(y, parts, pc, w):  # type: ignore[no-untyped-def]
        return previous(y, parts, pc, w) + energy(y, k, parts, row, rows, pc, w)

    return total


@njit(inline="always")
def _no_values(y, parts, pc, w):  # type: ignore[no-untyped-def]
    return ()


def _chain_values(previous, values, k, row, rows):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def every(y, parts, pc, w):  # type: ignore[no-untyped-def]
        return previous(y, parts, pc, w) + values(y, k, parts, row, rows, pc, w)

    return every


def _chain_momentum(previous, momentum, k, row, rows):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def total(y, parts, pc):  # type: ignore[no-untyped-def]
        a1, a2, a3 = previous(y, parts, pc)
        b1, b2, b3 = momentum(y, k, parts, row, rows, pc)
        return a1 + b1, a2 + b2, a3 + b3

    return total


def _chain_inertia(previous, inertia, k, row, rows):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def total(y, parts, pc):  # type: ignore[no-untyped-def]
        a = previous(y, parts, pc)
        b = inertia(y, k, parts, row, rows, pc)
        return a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5]

    return total


def _chain_rates(previous, rates, k, row, rows):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def every(y, parts, pc, w, v, hold):  # type: ignore[no-untyped-def]
        return previous(y, parts, pc, w, v, hold) + rates(y, k, parts, row, rows, pc, w, v, hold)

    return every


def _chain_kick(previous, kick, k, row, rows):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def every(y, parts, pc, w, v, hold, h):  # type: ignore[no-untyped-def]
        moved = previous(y, parts, pc, w, v, hold, h)
        return moved + kick(y, k, parts, row, rows, pc, w, v, hold, h)

    return every


def _diagonal_velocity(momentum):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def velocity(y, inverse, parts, pc):  # type: ignore[no-untyped-def]
        m1, m2, m3 = momentum(y, parts, pc)
        return (y[0] - m1) * inverse[0], (y[1] - m2) * inverse[1], (y[2] - m3) * inverse[2]

    return velocity


def _solved_velocity(momentum, inertia):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def velocity(y, inverse, parts, pc):  # type: ignore[no-untyped-def]
        m1, m2, m3 = momentum(y, parts, pc)
        a11, a12, a13, a22, a23, a33 = inertia(y, parts, pc)
        return solve3(
            1.0 / inverse[0] + a11,
            a12,
            a13,
            1.0 / inverse[1] + a22,
            a23,
            1.0 / inverse[2] + a33,
            y[0] - m1,
            y[1] - m2,
            y[2] - m3,
        )

    return velocity


@cache
def part_model(layout: tuple[LayoutEntry, ...]) -> PartModel:
    """The compiled functions of ``layout`` (:class:`PartModel`): ω solves
    ``(I_p + Σ inertia) ω = H − Σ momentum`` (a division by the platform moments
    when no part moves mass); the rates and kicks run each part's in order."""
    momentum, inertia, rates, kick = _no_momentum, None, _no_rates, _no_kick
    k, row = 7, 0
    for equations, size, rows in layout:
        momentum = _chain_momentum(momentum, equations.momentum, k, row, rows)
        if equations.inertia is not None:
            inertia = _chain_inertia(
                _no_inertia if inertia is None else inertia, equations.inertia, k, row, rows
            )
        rates = _chain_rates(rates, equations.rates, k, row, rows)
        if equations.kick is not None:
            kick = _chain_kick(kick, equations.kick, k, row, rows)
        k += size
        row += rows
    velocity = (
        _diagonal_velocity(momentum) if inertia is None else _solved_velocity(momentum, inertia)
    )
    return PartModel(velocity, momentum, rates, kick, k)


def _every_part(layout, equation, nothing, chain):  # type: ignore[no-untyped-def]
    """The chain (``chain``, from ``nothing``) of every part's function ``equation``
    (a field of :class:`PartEquations`), in the order of their states; None when a
    part of ``layout`` has none."""
    if any(getattr(equations, equation) is None for equations, _, _ in layout):
        return None
    every, k, row = nothing, 7, 0
    for equations, size, rows in layout:
        every = chain(every, getattr(equations, equation), k, row, rows)
        k += size
        row += rows
    return every


@cache
def part_energy(layout: tuple[LayoutEntry, ...]):  # type: ignore[no-untyped-def]
    """``shares(y, parts, pc, w) -> Σ ε`` (J): the parts' shares of twice the energy
    (the module's docstring), so that twice the energy of the body and its parts
    is ``ω · H`` plus it; None when a part of ``layout`` has no ``energy``."""
    return _every_part(layout, "energy", _no_energy, _chain_energy)


@cache
def part_values(layout: tuple[LayoutEntry, ...]):  # type: ignore[no-untyped-def]
    """``values(y, parts, pc, w) -> (value, …)``: the parts' values (a tuple, m)
    from their state and the body's ω, in the order of their states; None when a
    part of ``layout`` has no compiled ``values``."""
    return _every_part(layout, "values", _no_values, _chain_values)


def measured_energy(layout: tuple[LayoutEntry, ...]):  # type: ignore[no-untyped-def]
    """The shares the measuring kernels add to ``ω · H`` for twice the energy:
    :func:`part_energy`'s, or none (``ω · H`` alone) when a part of ``layout`` has
    no ``energy``."""
    return part_energy(layout) or _no_energy


# ------------------------------------------------------------------ the rates
@njit(inline="always")
def _torques(torque, drive, t, w1, w2, w3, q, system):  # type: ignore[no-untyped-def]
    """The external torque ``(τ1, τ2, τ3, c)`` (its damping c apart) and the torque
    ``v`` the rotors must exert on the body (its damping included)."""
    params, column, context = system[4], system[5], system[6]
    t1, t2, t3, c = torque(t, (w1, w2, w3), q, params, column, context)
    v1, v2, v3, cv = drive(t, (w1, w2, w3), q, params, column, context)
    return t1, t2, t3, c, v1 - cv * w1, v2 - cv * w2, v3 - cv * w3


@njit(inline="always")
def state_rates(torque, drive, velocity, rates, t, hold, y, system):  # type: ignore[no-untyped-def]
    """``f(t, y)`` for the state ``y`` of the module's docstring (an array, or a
    tuple), as a tuple (7 + m), the parts' inputs read at time ``hold``.

    ``system`` is ``(moments, inverse, parts, pc, params, column, context)``: the
    platform moments and their inverses (3,), the packed parts and their column,
    and the torque's params, column and context (:mod:`tumble.core.torques`).
    ``torque`` gives the external torque, ``drive`` the torque the rotors must
    exert on the body; ``velocity`` and ``rates`` are the layout's
    (:func:`part_model`).
    """
    inverse, parts, pc = system[1], system[2], system[3]
    w1, w2, w3 = velocity(y, inverse, parts, pc)
    q = (y[3], y[4], y[5], y[6])
    t1, t2, t3, c, v1, v2, v3 = _torques(torque, drive, t, w1, w2, w3, q, system)
    d0, d1, d2, d3 = quaternion_rates(q[0], q[1], q[2], q[3], w1, w2, w3)
    body = (
        t1 - c * w1 - (w2 * y[2] - w3 * y[1]),
        t2 - c * w2 - (w3 * y[0] - w1 * y[2]),
        t3 - c * w3 - (w1 * y[1] - w2 * y[0]),
        d0,
        d1,
        d2,
        d3,
    )
    return body + rates(y, parts, pc, (w1, w2, w3), (v1, v2, v3), hold)


@njit(inline="always")
def part_rates(torque, drive, velocity, rates, t, hold, y, dy, system):  # type: ignore[no-untyped-def]
    """``dy = f(t, y)`` for a state held in an array (:func:`state_rates`)."""
    slopes = state_rates(torque, drive, velocity, rates, t, hold, y, system)
    for i in range(len(slopes)):
        dy[i] = slopes[i]


@njit(inline="always")
def _normalise(y):  # type: ignore[no-untyped-def]
    scale = 1.0 / math.sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6])
    for i in range(3, 7):
        y[i] *= scale


@njit(inline="always")
def finite_state(y):  # type: ignore[no-untyped-def]
    """Whether a body's state ``y`` is finite: the sum of its entries and its
    quaternion's norm finite, that norm above zero."""
    total = 0.0
    for i in range(y.shape[0]):
        total += y[i]
    norm = y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]
    return math.isfinite(total) and math.isfinite(norm) and norm > 0.0


# Every step below is made for one layout and torque by a function of the layout
# and the torques: ``make(torque, drive, layout)`` returns ``step(t, dt, y,
# system)``, which advances ``y`` (7 + m,) in place. The layout's functions
# (:func:`part_model`) are the step's closure constants, so the compiler inlines
# them (held in a tuple, numba would pass them as pointers).
def make_rk4_step(torque, drive, layout):  # type: ignore[no-untyped-def]
    """The classical Runge–Kutta step of ``dt`` s from time ``t``, by the shared
    stepper (:func:`tumble.core.rk4.rk4_tuple_step` of :func:`state_rates`; the state
    read into a tuple, which the compiler keeps in registers: a third faster than
    stepping it in the array), the parts' inputs read at the step's middle, the
    quaternion renormalised after it."""
    velocity, _, rates, _, size = part_model(layout)
    state_of = njit(inline="always", cache=False)(entry_by_entry("state_of", "y", "y[{i}]", size))

    @njit(inline="always", cache=False)
    def derivatives(torque, t, y, hold, system, column, context):  # type: ignore[no-untyped-def]
        return state_rates(torque, drive, velocity, rates, t, hold, y, system)

    stages = rk4_tuple_step(derivatives)

    @njit(inline="always", cache=False)
    def step(t, dt, y, system):  # type: ignore[no-untyped-def]
        new = stages(torque, t, dt, state_of(y), t + 0.5 * dt, system, 0, 0)
        for i in range(size):
            y[i] = new[i]
        _normalise(y)

    return step


# ------------------------------------------------------------------ the gyrostat splitting
# Written on the state held as a tuple (7 + m), as the blocks of bodies hold it
# (tumble.core.part_blocks); one body alone is read into a tuple, stepped and
# written back. ``sines`` are the sines the flow turns by: the C library's one
# body at a time (library_cos_sin), the vectorised ones in blocks (cos_sin), the
# same map to round-off.
@njit(inline="always")
def _linked(momentum, sines, h, y, system):  # type: ignore[no-untyped-def]
    """The state after the exact flow over h of ``−b·H``, ``b = I_p⁻¹ g`` with ``g``
    the parts' momentum (fixed in the body between kicks): the body turns about
    the body-fixed b at the rate −|b|, so H turns about b by +|b| h in the body.
    No turn when b = 0; NaN beyond :data:`~tumble.core.trig.LARGEST_ANGLE` (a step
    far too coarse, as the free flow's). Written without branches, so that a
    block's loop vectorises."""
    inverse, parts, pc = system[1], system[2], system[3]
    g1, g2, g3 = momentum(y, parts, pc)
    b1 = g1 * inverse[0]
    b2 = g2 * inverse[1]
    b3 = g3 * inverse[2]
    size = math.sqrt(b1 * b1 + b2 * b2 + b3 * b3)
    # b = 0 gives e = 0, c = 1 and s = 0, which leave H and q as they are.
    divisor = size if size > 0.0 else 1.0
    e1 = b1 / divisor
    e2 = b2 / divisor
    e3 = b3 / divisor
    half = 0.5 * size * h
    c, s = sines(half)
    c = c if abs(half) <= LARGEST_ANGLE else math.nan
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
    h1 = l1 + 2.0 * s * (c * x1 + s * z1)
    h2 = l2 + 2.0 * s * (c * x2 + s * z2)
    h3 = l3 + 2.0 * s * (c * x3 + s * z3)
    turned = (h1, h2, h3)
    return turned + turn(y[3], y[4], y[5], y[6], c, -s, e1, e2, e3) + y[7:]


def external_kick(torque, y, moments, h, torques, w):  # type: ignore[no-untyped-def]
    """H (a tuple (3,)) after the external torque ``torques`` = (τ1, τ2, τ3, c) over
    h with the attitude held, its damping ``c`` integrated exactly; compiled, H
    itself for a free body (:func:`tumble.core.dynamics.free_torque`)."""
    return _external_kick(torque, y, moments, h, torques, w)


def _external_kick(torque, y, moments, h, torques, w):  # type: ignore[no-untyped-def]
    t1, t2, t3, c = torques
    return (
        y[0] + (t1 - c * w[0]) * decay_integral(c, moments[0], h),
        y[1] + (t2 - c * w[1]) * decay_integral(c, moments[1], h),
        y[2] + (t3 - c * w[2]) * decay_integral(c, moments[2], h),
    )


def _no_external_kick(torque, y, moments, h, torques, w):  # type: ignore[no-untyped-def]
    return y[0], y[1], y[2]


@overload(external_kick, inline="always")
def _external_kick_overload(torque, y, moments, h, torques, w):  # type: ignore[no-untyped-def]
    return _no_external_kick if is_free(torque) else _external_kick


@njit(inline="always")
def _kicked(torque, drive, momentum, kick, t, hold, h, y, system):  # type: ignore[no-untyped-def]
    """The state after the torques over h with the attitude and the torques held:
    the external torque on H (:func:`external_kick`) and the parts' kicks (their
    inputs read at ``hold``)."""
    moments, inverse, parts, pc = system[0], system[1], system[2], system[3]
    g1, g2, g3 = momentum(y, parts, pc)
    w1 = (y[0] - g1) * inverse[0]
    w2 = (y[1] - g2) * inverse[1]
    w3 = (y[2] - g3) * inverse[2]
    q = (y[3], y[4], y[5], y[6])
    t1, t2, t3, c, v1, v2, v3 = _torques(torque, drive, t, w1, w2, w3, q, system)
    moved = kick(y, parts, pc, (w1, w2, w3), (v1, v2, v3), hold, h)
    held = external_kick(torque, y, moments, h, (t1, t2, t3, c), (w1, w2, w3))
    return held + q + moved


# Passed to the steps as values, so compiled apart from them: not cached (its
# arguments' types include the layout's own functions).
@njit(inline="always", cache=False)
def _linked_turns(momentum, sines, h, y, system):  # type: ignore[no-untyped-def]
    """link(h/2) ∘ R1(h/2) R3(h) R1(h/2) ∘ link(h/2): the flow over h of the
    gyrostat's kinetic energy between kicks but its turn about H
    (:func:`_turned_about_momentum`), which commutes with every part of it."""
    inverse = system[1]
    y = _linked(momentum, sines, 0.5 * h, y, system)
    turned = free_turns(
        h, y[0], y[1], y[2], y[3], y[4], y[5], y[6], inverse[0], inverse[1], inverse[2], sines
    )
    return _linked(momentum, sines, 0.5 * h, turned + y[7:], system)


#: For the parts' momentum along principal axis k: the reference axis of the
#: free flow's split and its middle turn's axis (the outer turns are about k).
#: Along axis 1 (0) the split is the general one; along axis 3 its mirror;
#: along the intermediate axis the reference is axis 3 (measured on a dual-spin
#: body, its worst error is 2–8 times smaller than with axis 1 and no larger
#: than the general splitting's: bench/RESULTS.md).
_FOLDED_AXES = {0: (1, 2), 1: (2, 0), 2: (1, 0)}


def _folded_turns(axis: int) -> Any:
    """The gyrostat's turns between kicks, as :func:`_linked_turns`, for parts
    whose momentum ``g`` lies along the principal axis ``axis`` (k): the linear
    ``−b_k H_k`` (``b = I_p⁻¹ g``) and ``½ (1/I_k − 1/I_ref) H_k²`` are both
    functions of H_k, so their flows commute and are one turn about axis k at
    ``ν = (1/I_k − 1/I_ref) H_k − b_k``:

        Rk'(h/2) Rm(h) Rk'(h/2)

    with m the middle axis (:data:`_FOLDED_AXES`): two turns about axis k and one
    about m, where :func:`_linked_turns` takes four (and two general rotations
    of H). Along axis 1 it is the same map, to round-off; along axes 2 and 3 it
    splits the free flow about another axis, a second-order splitting of the
    same kind (symmetric, explicit, H kept to round-off), exact as the other
    for a symmetric platform whose rotors lie on its axis of symmetry."""
    reference, middle = _FOLDED_AXES[axis]

    @njit(inline="always", cache=False)
    def turns(momentum, sines, h, y, system):  # type: ignore[no-untyped-def]
        inverse, parts, pc = system[1], system[2], system[3]
        r = (inverse[0], inverse[1], inverse[2])
        link = momentum(y, parts, pc)[axis] * r[axis]
        outer = r[axis] - r[reference]
        inner = r[middle] - r[reference]
        l1, l2, l3, q0, q1, q2, q3 = y[0], y[1], y[2], y[3], y[4], y[5], y[6]
        half = 0.25 * h * ((l1, l2, l3)[axis] * outer - link)
        c, s = sines(half)
        # The rotors' rate is not bounded by |H|: checked here (the others are
        # by the turn about H's).
        c = c if abs(half) <= LARGEST_ANGLE else math.nan
        l1, l2, l3, q0, q1, q2, q3 = principal_turn(axis, c, s, l1, l2, l3, q0, q1, q2, q3)
        c, s = sines(0.5 * h * (l1, l2, l3)[middle] * inner)
        l1, l2, l3, q0, q1, q2, q3 = principal_turn(middle, c, s, l1, l2, l3, q0, q1, q2, q3)
        half = 0.25 * h * ((l1, l2, l3)[axis] * outer - link)
        c, s = sines(half)
        c = c if abs(half) <= LARGEST_ANGLE else math.nan
        turned = principal_turn(axis, c, s, l1, l2, l3, q0, q1, q2, q3)
        return turned + y[7:]

    return turns


def _turned_about_momentum(reference: int) -> Any:
    """``turned(sines, h, y, inverse)``: the state after R_L(h), the body turned
    about H at |H| / I_ref (:func:`tumble.core.splitting.turn_about_momentum`;
    ``inverse`` the platform's inverse moments, ascending moments)."""

    @njit(inline="always", cache=False)
    def turned(sines, h, y, inverse):  # type: ignore[no-untyped-def]
        q = turn_about_momentum(
            h, y[0], y[1], y[2], y[3], y[4], y[5], y[6], inverse[0], inverse[reference], sines
        )
        return y[:3] + q + y[7:]

    return turned


@njit(inline="always", cache=False)
def nothing_after(sines, h, y, inverse):  # type: ignore[no-untyped-def]
    """The ``finish`` of a step that adds nothing after its sub-steps
    (:class:`GyrostatFlow`): the state as it is. Passed as a value, so not cached."""
    return y


class GyrostatFlow(NamedTuple):
    """The gyrostat's flow between kicks for one layout (:func:`gyrostat_flow`):
    ``flow(momentum, sines, h, y, system)``, the state after it over h;
    ``finish(sines, dt, y, inverse)``, the state after what a whole step of
    ``dt`` adds after its sub-steps (the turn about H where the sub-steps leave
    it out; else nothing); ``kick``, the parts' kicks (:class:`PartModel`'s, or
    none where every part is idle and nothing drives them)."""

    flow: Any
    finish: Any
    kick: Any


def gyrostat_flow(torque: Any, drive: Any, layout: tuple[LayoutEntry, ...]) -> GyrostatFlow:
    """The gyrostat's free flow ``T = ½ (H − g)ᵀ I_p⁻¹ (H − g)`` between kicks, as
    exact turns: the rigid body's turns (:func:`_linked_turns`), or, for parts
    along one principal axis, turns about it (:func:`_folded_turns`), then
    R_L, the turn about H, which commutes with all of them.

    Torque-free, with no torque through the rotors, the kicks change the parts'
    momenta alone and read neither the attitude nor H's direction in space, so
    R_L commutes with them too: a whole step's turns about H are then one,
    R_L(dt), made once after its sub-steps (``finish``; the same map to
    round-off, and for Yoshida's triple jump two turns fewer)."""
    axis = momentum_axis(layout)
    if axis is None:
        turns, reference = _linked_turns, 1
    else:
        turns, reference = _folded_turns(axis), _FOLDED_AXES[axis][0]
    about_momentum = _turned_about_momentum(reference)
    undriven = drive is free_torque
    idle = undriven and all(equations.idle for equations, _, _ in layout)
    kick = _still if idle else part_model(layout).kick
    if torque is free_torque and undriven:
        return GyrostatFlow(turns, about_momentum, kick)

    @njit(inline="always", cache=False)
    def flow(momentum, sines, h, y, system):  # type: ignore[no-untyped-def]
        return about_momentum(sines, h, turns(momentum, sines, h, y, system), system[1])

    return GyrostatFlow(flow, nothing_after, kick)


@njit(inline="always", cache=False)
def _still(y, parts, pc, w, v, hold, h):  # type: ignore[no-untyped-def]
    """The kick of idle parts (:attr:`PartEquations.idle`) that nothing drives:
    their states as they are (the rotors' momenta plus a motor torque of
    exactly zero, without reading it)."""
    return y[7:]


def momentum_axis(layout: tuple[LayoutEntry, ...]) -> int | None:
    """The principal axis (0, 1, 2) along which every part's momentum lies in
    every body of ``layout`` (:func:`along_principal_axis`), or None."""
    axes = {equations.principal_axis for equations, _, _ in layout}
    return axes.pop() if len(axes) == 1 and None not in axes else None


@njit(inline="always")
def _strang(torque, drive, momentum, kick, flow, sines, t, h, hold, y, system):  # type: ignore[no-untyped-def]
    """kick(h/2) ∘ flow(h) ∘ kick(h/2), from time t (``flow`` the gyrostat's,
    :class:`GyrostatFlow`)."""
    y = _kicked(torque, drive, momentum, kick, t, hold, 0.5 * h, y, system)
    y = flow(momentum, sines, h, y, system)
    return _kicked(torque, drive, momentum, kick, t + h, hold, 0.5 * h, y, system)


@njit(inline="always")
def splitting_sub_step(torque, drive, momentum, kick, flow, sines, t, dt, sub, y, system, order):  # type: ignore[no-untyped-def]
    """The state (a tuple) after Strang sub-step ``sub``
    (:func:`~tumble.core.splitting.sub_steps`) of a splitting step of ``dt`` s
    from ``t``: Strang (``order`` 2) or Yoshida's triple jump of it (4), the
    parts' inputs read at the step's middle; its quaternion is not renormalised,
    and the step's ``finish`` (:class:`GyrostatFlow`) follows its last sub-step.
    For a layout whose parts all kick and move no mass
    (:attr:`tumble.parts.InternalPart.splittable`).

    The free flow of the gyrostat, ``T = ½ (H − g)ᵀ I_p⁻¹ (H − g)`` with ``g`` the
    parts' momentum, constant between kicks, is the rigid body's ``½ Hᵀ I_p⁻¹ H``
    (the exact rotations of :func:`tumble.core.splitting.free_flow`) and the
    linear ``−(I_p⁻¹ g)·H``, an exact rotation about a body-fixed axis
    (:func:`gyrostat_flow`): explicit and symplectic, H kept to round-off."""
    hold = t + 0.5 * dt
    start = sub_step_start(order, sub, t, dt)
    h = sub_step(order, sub) * dt
    return _strang(torque, drive, momentum, kick, flow, sines, start, h, hold, y, system)


@njit(inline="always")
def splitting_step(torque, drive, momentum, kick, flow, finish, sines, t, dt, y, system, order):  # type: ignore[no-untyped-def]
    """The state after a whole splitting step: its sub-steps
    (:func:`splitting_sub_step`) one after the other, at one call site, so that the
    compiler inlines the Strang step once, then the step's ``finish``
    (:class:`GyrostatFlow`)."""
    for sub in range(sub_steps(order)):
        y = splitting_sub_step(
            torque, drive, momentum, kick, flow, sines, t, dt, sub, y, system, order
        )
    return finish(sines, dt, y, system[1])


def _make_splitting_step(torque, drive, layout, order):  # type: ignore[no-untyped-def]
    """:func:`splitting_step` of one body held in an array, with the C library's
    sines (one body at a time, they are the faster)."""
    _, momentum, _, _, size = part_model(layout)
    # Each function a closure variable of its own: numba cannot cache a kernel
    # that holds a tuple of functions as a constant.
    flow, finish, kick = gyrostat_flow(torque, drive, layout)
    state_of = njit(inline="always", cache=False)(entry_by_entry("state_of", "y", "y[{i}]", size))

    @njit(inline="always", cache=False)
    def step(t, dt, y, system):  # type: ignore[no-untyped-def]
        state = state_of(y)
        sines = library_cos_sin
        new = splitting_step(
            torque, drive, momentum, kick, flow, finish, sines, t, dt, state, system, order
        )
        for i in range(size):
            y[i] = new[i]
        _normalise(y)

    return step


def make_strang_step(torque, drive, layout):  # type: ignore[no-untyped-def]
    """:func:`splitting_step` of order 2 (Strang)."""
    return _make_splitting_step(torque, drive, layout, 2)


def make_yoshida_step(torque, drive, layout):  # type: ignore[no-untyped-def]
    """:func:`splitting_step` of order 4 (Yoshida's triple jump of Strang)."""
    return _make_splitting_step(torque, drive, layout, 4)


# ------------------------------------------------------------------ loops
@njit(inline="always")
def _steps(step, y, system, dt, n_steps, first_step, record_every, out):  # type: ignore[no-untyped-def]
    """``n_steps`` steps of one body in place; its status (see :func:`single_kernel`)."""
    n = y.shape[0]
    saved = np.empty(n)
    status = FINITE
    for k in range(n_steps):
        number = first_step + k
        for i in range(n):
            saved[i] = y[i]
        step(number * dt, dt, y, system)
        if not finite_state(y):
            for i in range(n):
                y[i] = saved[i]
            status = number + 1
            break
        if (number + 1) % record_every == 0:
            row = (number + 1) // record_every
            for i in range(n):
                out[row, i] = y[i]
    return status


def single_kernel(make_step, torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """``run(y, moments, parts, params, context, dt, n_steps, first_step, record_every,
    out) -> status``: advance one body's state ``y`` (7 + m,) in place by
    ``n_steps`` steps of ``dt`` s with the step ``make_step`` makes
    (:func:`make_rk4_step`, :func:`make_strang_step` or :func:`make_yoshida_step`),
    for ``layout``.

    After global step ``first_step + k + 1``, if that number is a multiple of
    ``record_every``, the state is written to row ``number // record_every`` of
    ``out`` (·, 7 + m). The time of global step k is ``k dt``. Returns ``FINITE``,
    or the global number of the first step that was not finite (the state is
    left as it was before it).
    """
    step = make_step(torque, drive, layout)
    key = layout_identity(layout)

    @specialise(njit, f"parts.single|{file_stamp(make_step)}|{key}|{identity}")
    def run(y, moments, parts, params, context, dt, n_steps, first_step, record_every, out):  # type: ignore[no-untyped-def]
        inverse = 1.0 / moments
        system = (moments, inverse, parts, 0, params, 0, context)
        return _steps(step, y, system, dt, n_steps, first_step, record_every, out)

    return run


def batch_kernel(make_step, torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """``batch(y, moments, parts, params, context, t0, dt, n_steps, status)``: N bodies
    (``y`` (7 + m, N), ``moments`` (3, N); ``parts`` and ``params`` shared or one
    column per body) advanced in place, one body per thread at a time with the
    step of one body alone (``make_step``'s): the reference of the blocked
    kernels that batches run (:func:`tumble.core.part_blocks.block_kernel`).
    ``status`` (N,) receives each body's status (a body keeps its last finite
    state)."""
    step = make_step(torque, drive, layout)
    key = layout_identity(layout)

    # One body per call of a compiled function of its own, as in
    # tumble.core.splitting: inlined into the parallel loop, the stepping
    # defeats numba's parfor analysis.
    @specialise(njit, f"parts.body|{file_stamp(make_step)}|{key}|{identity}")
    def one_body(y, moments, parts, pc, params, column, context, t0, dt, n_steps):  # type: ignore[no-untyped-def]
        inverse = 1.0 / moments
        system = (moments, inverse, parts, pc, params, column, context)
        never = np.iinfo(np.int64).max
        first = int(t0 / dt + 0.5) if dt > 0.0 else 0
        return _steps(step, y, system, dt, n_steps, first, never, np.zeros((1, 1)))

    @specialise(njit_parallel, f"parts.batch|{file_stamp(make_step)}|{key}|{identity}")
    def batch(y, moments, parts, params, context, t0, dt, n_steps, status):  # type: ignore[no-untyped-def]
        part_stride = 0 if parts.shape[1] == 1 else 1
        param_stride = 0 if params.shape[1] == 1 else 1
        for body in prange(y.shape[1]):
            state = y[:, body].copy()
            status[body] = one_body(
                state,
                moments[:, body].copy(),
                parts,
                body * part_stride,
                params,
                body * param_stride,
                context,
                t0,
                dt,
                n_steps,
            )
            y[:, body] = state

    return batch


def adaptive_kernel(torque, drive, layout, identity):  # type: ignore[no-untyped-def]
    """``run(y, moments, parts, params, context, t_start, t_stop, control,
    sample_times, out) -> status``: one body's state ``y`` integrated in place from
    ``t_start`` to ``t_stop`` (s) by Dormand–Prince 5(4)
    (:func:`tumble.core.adaptive.adaptive_loop`: ``control``, the samples written
    to the rows of ``out`` (m, 7 + m') and the status as there). The parts'
    inputs are read at the middle of (t_start, t_stop): the driver ends each
    call at the next switch of a schedule."""
    velocity, _, rates, _, _ = part_model(layout)
    key = layout_identity(layout)

    @njit(inline="always", cache=False)
    def rates_of_parts(t, y, dy, args):  # type: ignore[no-untyped-def]
        system, hold = args
        part_rates(torque, drive, velocity, rates, t, hold, y, dy, system)

    @specialise(njit, f"parts.adaptive|{key}|{identity}")
    def run(y, moments, parts, params, context, t_start, t_stop, control, sample_times, out):  # type: ignore[no-untyped-def]
        inverse = 1.0 / moments
        system = (moments, inverse, parts, 0, params, 0, context)
        hold = 0.5 * (t_start + t_stop)
        return adaptive_loop(
            rates_of_parts, (system, hold), y, t_start, t_stop, control, sample_times, out
        )

    return run


@cache
def readout(layout: tuple[LayoutEntry, ...]):  # type: ignore[no-untyped-def]
    """``read(states, moments, parts, axes, turn, turned, omega, quaternion,
    values)``: one body's ω, rad/s, and attitude, body → space, both in body axes,
    and its parts' values (:func:`part_values`), written into ``omega`` (n, 3),
    ``quaternion`` (n, 4) and ``values`` (n, m; (n, 0) when a part has none
    compiled: then read back in Python), from its kernel states (n, 7 + m) (a row
    per sample), with its platform moments (3,), its packed parts (rows, 1), its
    principal axes ``axes`` (3, 3; columns, body coordinates) and ``turn`` (4,),
    the unit quaternion that takes an attitude of the principal frame to the
    body's (``q ⊗ turn``, renormalised:
    :func:`tumble.core.quaternion.multiply_right`). ``turned`` False: the
    principal axes are the body's, and ω and q are copied as they are. A
    trajectory's samples read back in one call, ω as the kernels solve for it,
    into arrays made by the caller (arrays a compiled call returns cost more to
    hand back to Python than the reading itself)."""
    velocity = part_model(layout).velocity
    values_of = part_values(layout)
    compiled = values_of is not None
    values_of = values_of or _no_values
    key = layout_identity(layout)

    @specialise(njit, f"parts.readout|{key}")
    def read(states, moments, parts, axes, turn, turned, omega, quaternion, values):  # type: ignore[no-untyped-def]
        n, size = states.shape
        inverse = 1.0 / moments
        y = np.empty(size)
        for j in range(n):
            for i in range(size):
                y[i] = states[j, i]
            w = velocity(y, inverse, parts, 0)
            if turned:
                for k in range(3):
                    omega[j, k] = axes[k, 0] * w[0] + axes[k, 1] * w[1] + axes[k, 2] * w[2]
            else:
                omega[j, 0], omega[j, 1], omega[j, 2] = w
            if compiled:
                found = values_of(y, parts, 0, w)
                for i in range(len(found)):
                    values[j, i] = found[i]
        if turned:
            multiply_right_into(states[:, 3:7], turn, quaternion)
        else:
            quaternion[:] = states[:, 3:7]

    return read


@cache
def velocities(layout: tuple[LayoutEntry, ...]):  # type: ignore[no-untyped-def]
    """``omega(states, moments, parts) -> (n, 3)``: the body's ω (rad/s, principal
    platform axes) of kernel states (7 + m, n) (each column a body or a sample),
    with the platform moments (3, n) and the packed parts (rows, 1 shared or n),
    as the kernels solve for it: how a trajectory's samples are read back."""
    velocity = part_model(layout).velocity
    key = layout_identity(layout)

    @specialise(njit, f"parts.velocities|{key}")
    def omega(states, moments, parts):  # type: ignore[no-untyped-def]
        n = states.shape[1]
        out = np.empty((n, 3))
        shared_moments = moments.shape[1] == 1
        part_stride = 0 if parts.shape[1] == 1 else 1
        y = np.empty(states.shape[0])
        inverse = np.empty(3)
        for j in range(n):
            for i in range(states.shape[0]):
                y[i] = states[i, j]
            m = 0 if shared_moments else j
            for i in range(3):
                inverse[i] = 1.0 / moments[i, m]
            out[j, 0], out[j, 1], out[j, 2] = velocity(y, inverse, parts, j * part_stride)
        return out

    return omega
