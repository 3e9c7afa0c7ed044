"""The values most recently computed for a few keys, kept for calls that ask again.

A :class:`RecentCache` keeps the last values computed from immutable objects
(mass properties and parts: frozen, their arrays read-only) and plain
values (numbers, strings, short vectors). A key names the objects by identity
and the plain values by :func:`plain_key`; each entry holds the objects it
names, so that no other object can take their identities while it lives.
"""

from __future__ import annotations

import operator
import struct
import threading
from collections import OrderedDict
from collections.abc import Sequence
from typing import Any, Generic, TypeVar

import numpy as np

__all__ = ["UNKEYED", "RecentCache", "plain_key"]

Value = TypeVar("Value")

#: What :func:`plain_key` gives for a value it cannot name as a key.
UNKEYED = object()

#: The longest sequence or array named by value (a vector, a quaternion).
_LONGEST = 4

#: The types of the numbers named by value (not bool: ``True == 1``, and it is refused).
_NUMBERS = frozenset({float, int})

#: The packing of 0 to ``_LONGEST`` float64 values into their bytes, by count.
_PACK = tuple(struct.Struct(f"{count}d").pack for count in range(_LONGEST + 1))


def plain_key(value: Any) -> Any:
    """A hashable key that stands for ``value`` wherever only its value counts:
    None and a string themselves; a float, an int, or a list, tuple or numeric
    array of up to four of them, by the bytes of their float64 values (as the
    unit conversion reads them: ``-0.0`` is not ``0.0``, ``1`` is ``1.0``, a list
    is the array of its values), and by the shape of an array that is not a
    vector. Anything else (bools, quantities, objects, longer arrays):
    :data:`UNKEYED`."""
    kind = type(value)
    if kind is list or kind is tuple:
        # The types checked in one pass of C, not a loop of Python: a short run
        # repeated spends a good part of its time keying (bench/cold_call.py).
        if len(value) > _LONGEST or not _NUMBERS.issuperset(map(type, value)):
            return UNKEYED
    elif kind is float or kind is int:
        value = (value,)
    elif value is None or kind is str:
        return value
    elif kind is np.ndarray:
        if value.size > _LONGEST or value.dtype.kind not in "fiu":
            return UNKEYED
        floats = value.astype(np.float64).tobytes()
        return (False, floats) if value.ndim == 1 else (value.shape, floats)
    else:
        return UNKEYED
    try:  # packed as float64, an int as float(int) would round it
        return (kind is float or kind is int, _PACK[len(value)](*value))
    except struct.error:  # an int beyond float range: refused where it is read
        return UNKEYED


class RecentCache(Generic[Value]):
    """The last ``size`` values stored, by key, each with the objects its key
    names by identity (thread-safe)."""

    def __init__(self, size: int) -> None:
        self.size = size
        self._entries: OrderedDict[Any, tuple[tuple[Any, ...], Value]] = OrderedDict()
        self._lock = threading.Lock()

    def get(self, key: Any, held: Sequence[Any]) -> Value | None:
        """The value stored for ``key`` with the very objects ``held`` (in order), or None."""
        # Each of these two steps is atomic: no lock is needed, only the key that
        # another thread's put may have pushed out in between.
        entry = self._entries.get(key)
        if entry is None:
            return None
        try:
            self._entries.move_to_end(key)
        except KeyError:  # pushed out by another thread's put in between: made anew
            return None
        stored, value = entry
        if len(stored) == len(held) and all(map(operator.is_, stored, held)):
            return value
        return None

    def put(self, key: Any, held: Sequence[Any], value: Value) -> None:
        """Store ``value`` for ``key``, holding ``held``; the oldest beyond ``size`` go."""
        with self._lock:
            self._entries[key] = (tuple(held), value)
            self._entries.move_to_end(key)
            while len(self._entries) > self.size:
                self._entries.popitem(last=False)
