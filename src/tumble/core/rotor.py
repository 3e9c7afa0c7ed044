"""Compiled equations of a rotor: a symmetric wheel spinning on a body-fixed axis,
driven by a motor (:class:`tumble.parts.Rotor`; the signatures are those of
:class:`tumble.core.parts.PartEquations`).

State: one entry, its axial angular momentum ``h = J (a·ω + Ω)`` (kg·m²/s; Ω its
spin rate relative to the body), which takes ``h a`` out of the total ``H``
before the body's ω is solved for. Its equation is ``ḣ = u``: the motor torque
on the rotor (the body feels −u a).

Each rotor's motor torque ``u`` is its own schedule (piecewise constant in
time) plus its share of the torque that the torque models acting *through the
rotors* (an attitude controller driving reaction wheels) ask of them: ``u =
−P v`` with ``v`` that torque on the body and P the pseudo-inverse of the
matrix of rotor axes, so that ``−Σ u a = v`` when the axes span space. ``u`` is
then clipped to the rotor's largest torque, and set to zero when it would drive
the rotor past its largest speed.

Packed rows: :data:`ROTOR_FIELDS`, then its ``n`` switch times and ``n``
torques (so ``rows = len(ROTOR_FIELDS) + 2 n``). The schedule is read at one
*hold* time per step (its middle; for the adaptive method, the middle of each
stretch between switches, where the driver ends its calls), so the motor
torque is constant over a step and a switch on a step boundary is integrated
exactly, whatever the stages' times.
"""

from __future__ import annotations

from tumble.core._jit import njit
from tumble.core.parts import PartEquations

__all__ = ["ROTOR_EQUATIONS", "ROTOR_FIELDS"]

#: The rows of one rotor, before its schedule: axis (principal-platform axes),
#: axial moment J (kg·m²), largest motor torque (N·m), largest relative speed
#: (rad/s), and its row of the allocation matrix P (1/… : u = −P v).
ROTOR_FIELDS = (
    "axis_1",
    "axis_2",
    "axis_3",
    "inertia",
    "max_torque",
    "max_speed",
    "allocation_1",
    "allocation_2",
    "allocation_3",
)

_FIELDS = len(ROTOR_FIELDS)


@njit(inline="always")
def _scheduled(parts, row, rows, pc, hold):  # type: ignore[no-untyped-def]
    """The scheduled motor torque at time ``hold`` (right-continuous)."""
    n_schedule = (rows - _FIELDS) // 2
    value = 0.0
    for j in range(n_schedule):
        if parts[row + _FIELDS + j, pc] <= hold:
            value = parts[row + _FIELDS + n_schedule + j, pc]
    return value


@njit(inline="always")
def relative_speed(y, k, parts, row, pc, w1, w2, w3):  # type: ignore[no-untyped-def]
    """``Ω = h / J − a·ω`` (rad/s): the rotor's spin rate relative to the body."""
    along = parts[row, pc] * w1 + parts[row + 1, pc] * w2 + parts[row + 2, pc] * w3
    return y[k] / parts[row + 3, pc] - along


@njit(inline="always")
def motor_torque(y, k, parts, row, rows, pc, w, v, hold):  # type: ignore[no-untyped-def]
    """The rotor's motor torque (N·m): its schedule read at ``hold`` plus its share
    of the torque ``v`` the rotors must exert on the body, clipped to its limits."""
    w1, w2, w3 = w
    v1, v2, v3 = v
    u = _scheduled(parts, row, rows, pc, hold) - (
        parts[row + 6, pc] * v1 + parts[row + 7, pc] * v2 + parts[row + 8, pc] * v3
    )
    largest = parts[row + 4, pc]
    u = min(max(u, -largest), largest)
    speed = relative_speed(y, k, parts, row, pc, w1, w2, w3)
    limit = parts[row + 5, pc]
    if (speed >= limit and u > 0.0) or (speed <= -limit and u < 0.0):
        u = 0.0
    return u


@njit(inline="always")
def rotor_momentum(y, k, parts, row, rows, pc):  # type: ignore[no-untyped-def]
    """``h a``: the rotor's momentum along its axis, principal-platform axes."""
    h = y[k]
    return h * parts[row, pc], h * parts[row + 1, pc], h * parts[row + 2, pc]


@njit(inline="always")
def rotor_rates(y, k, parts, row, rows, pc, w, v, hold):  # type: ignore[no-untyped-def]
    """``ḣ = u``, the motor torque."""
    return (motor_torque(y, k, parts, row, rows, pc, w, v, hold),)


@njit(inline="always")
def rotor_kick(y, k, parts, row, rows, pc, w, v, hold, h):  # type: ignore[no-untyped-def]
    """``(h + u h,)``: its momentum after the motor torque over a kick of ``h`` s,
    the attitude held."""
    return (y[k] + motor_torque(y, k, parts, row, rows, pc, w, v, hold) * h,)


@njit(inline="always")
def rotor_energy(y, k, parts, row, rows, pc, w):  # type: ignore[no-untyped-def]
    """``h Ω`` with ``Ω = h / J − a·ω``: its momentum times its rate relative to the
    body (twice its kinetic energy ``h² / J`` less the ``h a·ω`` of ``ω · H``)."""
    return y[k] * relative_speed(y, k, parts, row, pc, w[0], w[1], w[2])


@njit(inline="always")
def rotor_values(y, k, parts, row, rows, pc, w):  # type: ignore[no-untyped-def]
    """``(Ω,)``: its spin rate relative to the body (rad/s), the value a trajectory keeps."""
    return (relative_speed(y, k, parts, row, pc, w[0], w[1], w[2]),)


#: The rotor's equations, for :mod:`tumble.core.parts`.
ROTOR_EQUATIONS = PartEquations(
    momentum=rotor_momentum,
    rates=rotor_rates,
    kick=rotor_kick,
    energy=rotor_energy,
    values=rotor_values,
    axis_row=0,
)
