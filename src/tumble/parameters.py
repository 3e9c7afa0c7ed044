"""The parameters of plugins (torque models, parts): a name, a kind of quantity,
a shape and bounds, from which their conversion to SI, their checks and the
keys of scenario and sweep files are made."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from tumble.errors import InputError
from tumble.units import SI_UNITS, to_si, vector_to_si

__all__ = ["Parameter", "shown_unit"]


def shown_unit(kind: str) -> str:
    """The SI unit of a kind of quantity as messages write it (``kg·m²``)."""
    return SI_UNITS[kind].replace("*", "·").replace("^2", "²").replace("^3", "³")


@dataclass(frozen=True)
class Parameter:
    """A parameter of a torque model or a part.

    Attributes
    ----------
    name : its keyword, and its key in scenario files.
    kind : the kind of quantity (a key of :data:`tumble.units.SI_UNITS`), or ""
        for a value taken as written and checked by its owner (a schedule).
    shape : ``()`` for a number, ``(3,)`` for a vector.
    description : what it is, with its frame.
    minimum : the smallest value allowed, or None; ``strict``: the minimum
        itself is not allowed (a value must exceed it).
    sweep : the names of its per-body parameters in sweep files, one per
        component (empty: not sweepable).
    optional : None is allowed (and kept): "none" (no limit, no value).
    """

    name: str
    kind: str
    shape: tuple[int, ...] = ()
    description: str = ""
    minimum: float | None = None
    sweep: tuple[str, ...] = ()
    strict: bool = False
    optional: bool = False

    def convert(self, value: Any, per_body: bool) -> Any:
        """The value in SI: a float or (3,) array, or with ``per_body`` also (N,) or
        (N, 3), one per body of a batch (None stays None when ``optional``)."""
        if (value is None and self.optional) or not self.kind:
            return value
        many = per_body and np.ndim(value) == len(self.shape) + 1 and not isinstance(value, str)
        if not self.shape and not many:
            result: Any = to_si(value, self.kind, self.name)
        else:
            shape = ((-1, *self.shape) if many else self.shape) or (-1,)
            result = vector_to_si(value, self.kind, self.name, shape)
        low = np.asarray(result)
        if self.minimum is not None and np.any(
            low <= self.minimum if self.strict else low < self.minimum
        ):
            unit = shown_unit(self.kind)
            relation = ">" if self.strict else ">="
            if np.ndim(result):
                k = int(np.argmin(result))
                shown = f"{self.name}[{k}] = {float(np.ravel(result)[k])!r}"
            else:
                shown = repr(result)
            raise InputError(
                f"Expected `{self.name}` {relation} {self.minimum:g} {unit}, got {shown}."
            )
        if isinstance(result, np.ndarray):
            result = result.copy()  # frozen: never the caller's own array
            result.flags.writeable = False
        return result
