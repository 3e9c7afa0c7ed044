"""The quantities a motion may conserve, by name: what drift reports list.

:data:`INVARIANTS` holds every quantity a body model or a torque model can
declare conserved; :func:`reduce_invariants` leaves out those implied by another
(the components of a conserved vector L). :func:`largest_rate` gives the
largest |ω| that the conserved energy and momentum allow a torque-free body.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "FREE_BODY_INVARIANTS",
    "INVARIANTS",
    "Invariant",
    "label",
    "largest_rate",
    "reduce_invariants",
]


@dataclass(frozen=True)
class Invariant:
    """A quantity a motion may conserve: its key in drift reports, a short label
    and what it is."""

    name: str
    label: str
    description: str
    implied_by: str | None = None


#: Every quantity a body model or a torque model can declare conserved.
INVARIANTS: dict[str, Invariant] = {
    invariant.name: invariant
    for invariant in (
        Invariant("energy", "energy", "kinetic plus potential energy, J"),
        Invariant(
            "angular_momentum_vector",
            "vector L",
            "angular momentum about the reference point, space axes, kg·m²/s",
        ),
        Invariant(
            "angular_momentum_norm",
            "|L|",
            "magnitude of the angular momentum, kg·m²/s",
            implied_by="angular_momentum_vector",
        ),
        Invariant(
            "angular_momentum_vertical",
            "L_vertical",
            "component of L along the upward vertical (against gravity), kg·m²/s",
            implied_by="angular_momentum_vector",
        ),
        Invariant(
            "angular_momentum_axial",
            "L_axial",
            "component of L along the body's symmetry axis through the pivot, kg·m²/s",
            implied_by="angular_momentum_vector",
        ),
        Invariant(
            "jacobi_integral",
            "Jacobi integral",
            "energy in a frame turning at a constant rate, J",
        ),
    )
}

#: What a torque-free rigid body conserves (every component of L with L).
FREE_BODY_INVARIANTS = frozenset(
    {
        "energy",
        "angular_momentum_vector",
        "angular_momentum_norm",
        "angular_momentum_vertical",
        "angular_momentum_axial",
    }
)


def label(name: str) -> str:
    """The short label of a conserved quantity (its name when it is a model's own)."""
    invariant = INVARIANTS.get(name)
    return invariant.label if invariant is not None else name.replace("_", " ")


def reduce_invariants(names: frozenset[str] | set[str]) -> tuple[str, ...]:
    """The conserved quantities to report, in the order of :data:`INVARIANTS`,
    leaving out those implied by another one in the set (the components of a
    conserved vector L)."""
    return tuple(
        name
        for name, invariant in INVARIANTS.items()
        if name in names and invariant.implied_by not in names
    )


def largest_rate(moments: NDArray[np.float64], omega: NDArray[np.float64]) -> float:
    """The largest |ω| (rad/s) that the torque-free motion from ``omega``
    (principal axes, rad/s) reaches, for principal ``moments`` I1 ≤ I2 ≤ I3.

    In the squares x_i = ω_i², the energy Σ I_i x_i and the momentum Σ I_i² x_i
    are linear: the motion keeps x on the segment of the line x0 + s d, with
    d = (I2 I3 (I3 − I2), I3 I1 (I1 − I3), I1 I2 (I2 − I1)) orthogonal to both,
    where every x_i ≥ 0. The solution sweeps that whole segment (Jacobi's
    x1 ∝ cn², x2 ∝ sn², x3 ∝ dn² about axis 3, and the like about axis 1, all
    linear in sn² ∈ [0, 1]), and |ω|² = Σ x_i is linear along it, so its largest
    value is at an end: where ω2 = 0, since Σ d = (I1 − I2)(I2 − I3)(I3 − I1) ≥ 0.
    There, with s = x2 / |d2|,

        max |ω|² = |ω|² + ω2² (I2 − I1)(I3 − I2) / (I1 I3),

    free of the scale of the moments (no I³ to overflow or underflow).
    """
    # In Python floats: three of them, where numpy's calls would cost more than the sums.
    i1, i2, i3 = np.asarray(moments, dtype=float).tolist()
    rates = np.asarray(omega, dtype=float).tolist()
    # ω scaled by a power of two to order one, so that its squares cannot overflow.
    exponent = math.frexp(max(map(abs, rates)))[1]
    x1, x2, x3 = (math.ldexp(w, -exponent) ** 2 for w in rates)
    gain = (i2 - i1) / i1 * ((i3 - i2) / i3) if i1 > 0.0 else 0.0
    return math.ldexp(math.sqrt(x1 + x2 + x3 + x2 * max(gain, 0.0)), exponent)
