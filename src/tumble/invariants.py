"""The quantities a motion may conserve, by name: what drift reports list.

:data:`INVARIANTS` holds every quantity a body model or a torque model can
declare conserved; :func:`reduce_invariants` leaves out those implied by another
(the components of a conserved vector L).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "FREE_BODY_INVARIANTS",
    "INVARIANTS",
    "Invariant",
    "label",
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
