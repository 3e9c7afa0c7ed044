"""What the rest of tumble needs of a body's parts, read from the registry
(:data:`tumble.parts.PARTS`): checks, the columns of their values in files, and
their layout and packed rows for the kernels (:mod:`tumble.core.parts`)."""

from __future__ import annotations

from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from tumble.core.parts import LayoutEntry, PartEquations, along_principal_axis
from tumble.errors import InputError
from tumble.parts.base import PARTS, InternalPart, Siblings, part_class

__all__ = [
    "check_parts",
    "from_description",
    "pack_parts",
    "spin_columns",
    "switch_times",
    "value_columns",
]

Array = NDArray[np.float64]


def value_columns(parts: tuple[InternalPart, ...]) -> list[str]:
    """Names of the columns of the parts' values in a trajectory file, in order:
    ``rotor_1_speed``, ``damper_1_omega_x``, ``spring_1_displacement`` … (each
    kind's :attr:`~tumble.parts.InternalPart.label`, numbered per kind from 1)."""
    names: list[str] = []
    counts: dict[str, int] = {}
    for part in parts:
        counts[part.kind] = counts.get(part.kind, 0) + 1
        names += [f"{part.label}_{counts[part.kind]}_{label}" for label in part.value_labels]
    return names


def spin_columns(parts: tuple[InternalPart, ...]) -> tuple[int, ...]:
    """The columns of the parts' values that are spin rates relative to the body
    (:attr:`InternalPart.spin`: the rotors' speeds), in order."""
    columns, start = [], 0
    for part in parts:
        if part.spin is not None:
            columns.append(start + part.spin)
        start += part.size
    return tuple(columns)


def check_parts(parts: Any) -> tuple[InternalPart, ...]:
    """``parts`` (None, a part, or a sequence of parts of registered kinds) as a tuple.

    Raises
    ------
    InputError
        Anything else in the sequence, or more parts of a kind than a body holds.
    """
    if parts is None:
        return ()
    if isinstance(parts, InternalPart):
        parts = [parts]
    names = ", ".join(cls.__name__ for cls in PARTS.values())
    if not isinstance(parts, list | tuple):
        raise InputError(
            f"Expected `internal` to be a list of parts ({names}), got {type(parts).__name__}."
        )
    for k, part in enumerate(parts):
        if not isinstance(part, InternalPart):
            raise InputError(
                f"Expected `internal[{k}]` to be a part ({names}), got {type(part).__name__}."
            )
    for cls in {type(part) for part in parts}:
        count = sum(type(part) is cls for part in parts)
        if cls.one_per_body is not None and count > 1:
            raise InputError(
                f"Expected at most one {cls.__name__} in a body, got {count} ({cls.one_per_body})."
            )
    return tuple(parts)


def from_description(entry: dict[str, Any]) -> InternalPart:
    """A part from :meth:`InternalPart.describe`'s dictionary (a trajectory file's metadata).

    Raises
    ------
    InputError
        A ``type`` that no registered part kind has.
    """
    values = dict(entry)
    return part_class(values.pop("type", None)).from_description(values)


# ------------------------------------------------------------------ for the kernels
def pack_parts(
    frame: Any, parts: tuple[InternalPart, ...]
) -> tuple[tuple[LayoutEntry, ...], Array]:
    """The kernels' layout of ``parts`` (:func:`tumble.core.parts.part_model`: each
    part's equations, state size and number of packed rows) and the parts packed
    for them, (rows, 1) for one body or (rows, N) for a batch: each part's
    :meth:`~InternalPart.pack` in order, in the principal frame of ``frame`` (a
    :class:`tumble.body.RigidBody` or :class:`tumble.body.BodyBatch`)."""
    siblings = Siblings(parts)
    blocks = [part.pack(frame, siblings) for part in parts]
    layout: tuple[LayoutEntry, ...] = tuple(
        (_equations(part), part.size, len(block)) for part, block in zip(parts, blocks, strict=True)
    )
    rows = [row for block in blocks for row in block]
    columns = max((np.size(row) for row in rows), default=1)
    packed = np.empty((len(rows), columns))
    for k, row in enumerate(rows):
        packed[k] = row
    return along_principal_axis(layout, packed), packed


def _equations(part: InternalPart) -> PartEquations:
    """The kernels' equations of ``part``: its kind's, marked idle
    (:attr:`tumble.core.parts.PartEquations.idle`) for a part that says it is
    (:attr:`InternalPart.idle`: a rotor without a motor)."""
    equations = cast(PartEquations, type(part).equations)
    return equations._replace(idle=True) if part.idle else equations


def switch_times(parts: tuple[InternalPart, ...], end: float) -> Array:
    """The times in (0, end) at which a part's inputs switch, sorted."""
    times = [part.switch_times() for part in parts]
    every = np.unique(np.concatenate(times)) if times else np.zeros(0)
    return np.asarray(every[(every > 0) & (every < end)])
