"""One body model per body, shared by the calls that ask for the same one: its
principal frame, its parts' layout and every other derived value are computed
once for a run of simulations."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from tumble.body.model import RigidBody
from tumble.massprops import MassProperties
from tumble.parts import InternalPart
from tumble.recent import RecentCache

__all__ = ["BODY_CACHE_SIZE", "body_model"]

Array = NDArray[np.float64]

#: How many body models :func:`body_model` keeps: the most recently asked for.
BODY_CACHE_SIZE = 64

_BODIES: RecentCache[RigidBody] = RecentCache(BODY_CACHE_SIZE)


def body_model(
    mp: MassProperties, pivot: Array | None = None, parts: tuple[InternalPart, ...] = ()
) -> RigidBody:
    """The :class:`RigidBody` of ``mp`` about ``pivot`` ((3,) body coordinates, m,
    or None: the centre of mass) carrying ``parts``, built once and shared by the
    calls that ask for the same body: its principal frame, its parts' layout and
    every other derived value are computed once for a run of simulations.

    The last :data:`BODY_CACHE_SIZE` are kept, keyed by the identity of ``mp``
    and of each part *and* by the values of ``mp`` and ``pivot``: mass
    properties and parts are immutable (frozen, their arrays read-only), and an
    entry holds them, so that no other object can take their identities while
    it lives; the values in the key guard against arrays made writable and
    changed in place. The pivot is copied (read-only) into the model.

    Raises
    ------
    InputError
        As :class:`RigidBody` (never cached).
    """
    point = None if pivot is None else np.array(pivot, dtype=float)
    key = (
        id(mp),
        mp.mass,
        mp.center_of_mass.tobytes(),
        mp.inertia.tobytes(),
        None if point is None else point.tobytes(),
        tuple(map(id, parts)),
    )
    held = (mp, *parts)
    body = _BODIES.get(key, held)
    if body is not None:
        return body
    if point is not None:
        point.flags.writeable = False
    body = RigidBody(mp, point, tuple(parts))
    _BODIES.put(key, held, body)
    return body
