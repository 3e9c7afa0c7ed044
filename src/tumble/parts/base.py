"""The base of the parts a body carries, and the checks of their values."""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.units import to_si

Array = NDArray[np.float64]

__all__ = ["InternalPart", "internal_rate", "limit", "positive"]


def positive(value: Any, kind: str, name: str, owner: str, unit: str, strict: bool = True) -> float:
    number = to_si(value, kind, name)
    ok = number > 0 if strict else number >= 0
    if not ok:
        relation = ">" if strict else ">="
        raise InputError(f"Expected `{name}` of a {owner} {relation} 0 {unit}, got {number!r}.")
    return number


def limit(value: Any, kind: str, name: str, unit: str) -> float:
    """A largest torque or speed: > 0, inf (the default) for none."""
    if value is None:
        return math.inf
    return positive(value, kind, name, "Rotor", unit)


class InternalPart:
    """Base of the parts a body carries (see the module's docstring).

    A part has ``size`` state values: its *values* (what a trajectory records,
    in the user's units: a rotor's relative spin rate, a damper sphere's angular
    velocity) and its *momenta* (what the kernels integrate).
    """

    #: Its ``type`` in scenario files.
    kind: ClassVar[str] = ""
    #: State values per part.
    size: ClassVar[int] = 0
    #: Labels of its values, and their unit.
    value_labels: ClassVar[tuple[str, ...]] = ()
    value_unit: ClassVar[str] = "rad/s"

    def attached(self, mp: Any) -> InternalPart:
        """The part as carried by a body of mass properties ``mp`` (what it needs to
        know of the body; the part itself for most)."""
        return self

    def spin_inertia(self) -> Array:
        """(3, 3) the part of the locked inertia that does not turn at the body's
        rate (kg·m², body axes)."""
        raise NotImplementedError

    def initial_values(self, omega0: Array) -> Array:
        """(..., size) its values at t = 0 for the body's initial ω (..., 3) (rad/s,
        body axes)."""
        raise NotImplementedError

    def momentum(self, omega: Array, values: Array) -> Array:
        """(n, 3) its angular momentum beyond the platform's ``I_p ω`` (kg·m²/s, body
        axes), for ω (n, 3) and its values (n, size)."""
        raise NotImplementedError

    def kinetic_energy(self, omega: Array, values: Array) -> Array:
        """(n,) its kinetic energy beyond the platform's ``½ ω·I_p ω`` (J), with the
        elastic energy of a spring."""
        raise NotImplementedError

    def momenta(self, omega: Array, values: Array) -> Array:
        """(n, size) the momenta the kernels integrate (body axes) from ω and values."""
        raise NotImplementedError

    def values_from(self, omega: Array, momenta: Array) -> Array:
        """(n, size) its values from ω (n, 3) and its momenta (n, size), body axes."""
        raise NotImplementedError

    def describe(self) -> dict[str, Any]:
        """The part as JSON-ready SI values (with ``type``), to write beside a trajectory."""
        raise NotImplementedError

    def internal_rates(self, platform_inertia: Array) -> tuple[float, float]:
        """How fast its own motion relative to the body goes, 1/s, on a body whose
        platform inertia is ``platform_inertia`` ((3, 3), kg·m², body axes): the
        rate at which it relaxes or oscillates by itself, and the rate at which it
        pulls the platform along. (0, 0) for a part with no stiffness or damping
        of its own. :func:`internal_rate` combines the parts' rates."""
        return 0.0, 0.0

    @property
    def driven(self) -> bool:
        """True when a motor acts on it: the body's energy is then not conserved."""
        return False

    @property
    def dissipative(self) -> bool:
        """True when it turns kinetic energy into heat."""
        return False


def internal_rate(parts: Any, platform_inertia: Array) -> tuple[float, list[str]]:
    """An upper bound of the fastest rate of the parts' own motion, 1/s, on a
    platform of inertia ``platform_inertia`` ((3, 3), kg·m², body axes), and
    the names of the kinds of parts it comes from.

    The largest rate a part has by itself plus the sum of the rates at which
    they pull the platform (:meth:`InternalPart.internal_rates`): for Kane
    dampers of inertias J_i and couplings D_i on a platform of moment I_p, the
    coupled system's largest rate is at most max_i D_i / J_i + Σ_i D_i / I_p
    (by (a − b)² <= (1 + t) a² + (1 + 1/t) b² in its quadratic form, t chosen
    at the ratio of the two terms), and equal to it for one damper. An explicit
    step h must keep h times this rate within its stability interval.
    """
    rates = [(part.internal_rates(platform_inertia), type(part).__name__) for part in parts]
    own = max((rate[0] for rate, _ in rates), default=0.0)
    pull = sum(rate[1] for rate, _ in rates)
    names = [name for rate, name in rates if rate[0] > 0 or rate[1] > 0]
    return own + pull, names
