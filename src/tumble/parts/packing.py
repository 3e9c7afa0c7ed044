"""What the rest of tumble needs of a body's parts: their kinds by name, checks,
the columns of their values in files, and their layout and packed rows for the
kernels (:mod:`tumble.core.parts`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core.parts import DAMPER, ROTOR, SPRING
from tumble.errors import InputError
from tumble.parts.base import InternalPart
from tumble.parts.dampers import KaneDamper, SpringMassDamper
from tumble.parts.rotor import Rotor

__all__ = [
    "PART_TYPES",
    "check_parts",
    "from_description",
    "layout_of",
    "pack_parts",
    "padded_schedule",
    "switch_times",
    "value_columns",
]

Array = NDArray[np.float64]


#: The part classes by their ``type`` in scenario files and run files.
PART_TYPES: dict[str, type[InternalPart]] = {
    cls.kind: cls for cls in (Rotor, KaneDamper, SpringMassDamper)
}


def value_columns(parts: tuple[InternalPart, ...]) -> list[str]:
    """Names of the columns of the parts' values in a trajectory file, in order:
    ``rotor_1_speed``, ``damper_1_omega_x``, ``spring_1_displacement`` … (numbered
    per kind, from 1)."""
    names, counts = [], dict.fromkeys(PART_TYPES, 0)
    prefixes = {"rotor": "rotor", "kane-damper": "damper", "spring-mass-damper": "spring"}
    for part in parts:
        counts[part.kind] += 1
        prefix = prefixes[part.kind]
        names += [f"{prefix}_{counts[part.kind]}_{label}" for label in part.value_labels]
    return names


def check_parts(parts: Any) -> tuple[InternalPart, ...]:
    """``parts`` (None, or a sequence of :class:`InternalPart`) as a tuple.

    Raises
    ------
    InputError
        Anything else in the sequence.
    """
    if parts is None:
        return ()
    if isinstance(parts, InternalPart):
        parts = [parts]
    if not isinstance(parts, list | tuple):
        raise InputError(
            f"Expected `internal` to be a list of Rotor, KaneDamper and SpringMassDamper "
            f"parts, got {type(parts).__name__}."
        )
    for k, part in enumerate(parts):
        if not isinstance(part, InternalPart):
            raise InputError(
                f"Expected `internal[{k}]` to be a Rotor, a KaneDamper or a SpringMassDamper, "
                f"got {type(part).__name__}."
            )
    if sum(isinstance(part, SpringMassDamper) for part in parts) > 1:
        raise InputError(
            "Expected at most one SpringMassDamper in a body, got "
            f"{sum(isinstance(part, SpringMassDamper) for part in parts)} (two moving masses "
            "couple through the centre of mass; this model holds one)."
        )
    return tuple(parts)


def from_description(entry: dict[str, Any]) -> InternalPart:
    """A part from :meth:`InternalPart.describe`'s dictionary (a trajectory file's metadata)."""
    values = dict(entry)
    cls = PART_TYPES[values.pop("type")]
    return cls(**values)


# ------------------------------------------------------------------ for the kernels
def layout_of(parts: tuple[InternalPart, ...]) -> tuple[tuple[int, ...], int]:
    """The kernels' layout of ``parts`` (:mod:`tumble.core.parts`): their kinds in
    order and the longest rotor schedule."""
    kinds = tuple(
        ROTOR
        if isinstance(part, Rotor)
        else SPRING
        if isinstance(part, SpringMassDamper)
        else DAMPER
        for part in parts
    )
    longest = max((len(part.schedule[0]) for part in parts if isinstance(part, Rotor)), default=0)
    return kinds, longest


def pack_parts(body: Any, layout: tuple[tuple[int, ...], int]) -> Array:
    """The parts of ``body`` (:class:`tumble.body.RigidBody`) packed for the kernels,
    (rows, 1), in the principal frame of its platform inertia (see
    :mod:`tumble.core.parts`): each rotor's axis, J, limits and row of the
    allocation matrix (the pseudo-inverse of the rotor axes as columns), then
    its schedule padded to the layout's length; each damper's J and D."""
    _, longest = layout
    rotors = [part for part in body.parts if isinstance(part, Rotor)]
    axes = np.array([body.to_principal(rotor.axis) for rotor in rotors]).reshape(-1, 3)
    allocation = np.linalg.pinv(axes.T) if rotors else np.zeros((0, 3))
    rows: list[float] = []
    k = 0
    for part in body.parts:
        if isinstance(part, Rotor):
            rows += [*axes[k], part.inertia, part.max_torque, part.max_speed, *allocation[k]]
            rows += padded_schedule(part, longest).tolist()
            k += 1
        elif isinstance(part, SpringMassDamper):
            reduced, rest = part.attached(body.mass_properties).geometry
            rows += [*body.to_principal(rest), *body.to_principal(part.direction), reduced]
            rows += [part.stiffness, part.damping]
        else:
            assert isinstance(part, KaneDamper)
            rows += [part.inertia, part.damping]
    return np.asarray(rows, dtype=float)[:, None]


def padded_schedule(rotor: Rotor, longest: int) -> Array:
    """(2 longest,) a rotor's switch times then its torques, padded to ``longest``
    entries each (times with inf, torques with 0), as the kernels read them."""
    times, torques = rotor.schedule
    padded = np.zeros(2 * longest)
    padded[:longest] = np.inf
    padded[: len(times)] = times
    padded[longest : longest + len(torques)] = torques
    return padded


def switch_times(parts: tuple[InternalPart, ...], end: float) -> Array:
    """The times in (0, end) at which a rotor's scheduled torque switches, sorted."""
    times = [part.schedule[0] for part in parts if isinstance(part, Rotor)]
    every = np.unique(np.concatenate(times)) if times else np.zeros(0)
    return np.asarray(every[(every > 0) & (every < end)])
