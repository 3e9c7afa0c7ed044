"""Parts a body carries inside it: :class:`Rotor` (reaction and momentum wheels,
the rotor of a dual-spin satellite) and :class:`KaneDamper` (a sphere in viscous
fluid: an internal energy sink).

**Convention.** A body's :class:`~tumble.MassProperties` hold every internal
part *as if it were locked to the body*: its mass and all of its inertia, about
the body's centre of mass, in body axes (build them with ``+``, e.g.
``hub + shapes.solid_cylinder(...).transformed(...)``). The part objects here
add only what locking hides: a rotor's spin relative to the body about its
axis, a damper's sphere turning inside its cavity. (Basilisk's reaction-wheel
effector, for comparison, takes the hub's inertia *without* the wheels and
adds them itself.)

What a part contributes, with ω the body's angular velocity (body axes):

* :class:`Rotor` (axis a, axial moment J, relative spin Ω): angular momentum
  ``J (a·ω + Ω) a`` beyond the locked ``J (a·ω) a``; kinetic energy
  ``h² / (2 J)`` with ``h = J (a·ω + Ω)`` its axial momentum;
* :class:`KaneDamper` (moment J, sphere angular velocity ω_s): ``J ω_s`` and
  ``J |ω_s|² / 2`` in place of the locked ``J ω`` and ``J |ω|² / 2``.

The equations of motion are in :mod:`tumble.core.parts`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from tumble.core.parts import DAMPER, ROTOR
from tumble.errors import InputError
from tumble.units import to_si, vector_to_si

__all__ = [
    "PART_TYPES",
    "InternalPart",
    "KaneDamper",
    "Rotor",
    "check_parts",
    "from_description",
    "layout_of",
    "pack_parts",
    "switch_times",
    "value_columns",
]

Array = NDArray[np.float64]


def _positive(
    value: Any, kind: str, name: str, owner: str, unit: str, strict: bool = True
) -> float:
    number = to_si(value, kind, name)
    ok = number > 0 if strict else number >= 0
    if not ok or math.isnan(number):
        relation = ">" if strict else ">="
        raise InputError(f"Expected `{name}` of a {owner} {relation} 0 {unit}, got {number!r}.")
    return number


def _limit(value: Any, kind: str, name: str, unit: str) -> float:
    """A largest torque or speed: > 0, inf (the default) for none."""
    if value is None:
        return math.inf
    return _positive(value, kind, name, "Rotor", unit)


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
        """(n,) its kinetic energy beyond the platform's ``½ ω·I_p ω`` (J)."""
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

    @property
    def driven(self) -> bool:
        """True when a motor acts on it: the body's energy is then not conserved."""
        return False

    @property
    def dissipative(self) -> bool:
        """True when it turns kinetic energy into heat."""
        return False


@dataclass(frozen=True, eq=False)
class Rotor(InternalPart):
    """A symmetric rotor (a wheel) spinning about a body-fixed axis.

    Parameters
    ----------
    axis : (3,) its spin axis in body coordinates (normalised here).
    inertia : its moment of inertia about that axis, J (kg·m², > 0). Its mass and
        all of its inertia, as if locked, belong in the body's MassProperties.
    speed : its spin rate relative to the body at t = 0 (rad/s, or "6000 rpm").
    torque : the motor torque on the rotor about its axis (N·m; the body feels
        the reaction): a constant, or a schedule, a sequence of ``(time, torque)``
        pairs with increasing times, piecewise constant from each time to the
        next (zero before the first).
    max_torque : the largest motor torque it can give (N·m, > 0; default no limit).
    max_speed : the largest relative speed it can reach (rad/s, > 0; default no
        limit): the motor torque is cut when it would drive the rotor beyond.

    The motor torque adds to the rotor's share of any torque model that acts
    through the rotors (``actuator="rotors"``, e.g. an attitude controller).
    """

    axis: Any
    inertia: Any
    speed: Any = 0.0
    torque: Any = 0.0
    max_torque: Any = None
    max_speed: Any = None

    kind = "rotor"
    size = 1
    value_labels = ("speed",)

    def __post_init__(self) -> None:
        axis = vector_to_si(self.axis, "dimensionless", "axis", (3,))
        size = float(np.linalg.norm(axis))
        if not size > 0 or not math.isfinite(size):
            raise InputError(
                f"Expected `axis` of a Rotor to be a non-zero vector, got {axis.tolist()}."
            )
        unit = axis / size
        unit.flags.writeable = False
        object.__setattr__(self, "axis", unit)
        object.__setattr__(
            self, "inertia", _positive(self.inertia, "inertia", "inertia", "Rotor", "kg·m²")
        )
        speed = to_si(self.speed, "angular_velocity", "speed")
        if not math.isfinite(speed):
            raise InputError(f"Expected `speed` of a Rotor to be finite, got {speed!r}.")
        object.__setattr__(self, "speed", speed)
        object.__setattr__(self, "torque", _schedule(self.torque))
        object.__setattr__(
            self, "max_torque", _limit(self.max_torque, "torque", "max_torque", "N·m")
        )
        object.__setattr__(
            self, "max_speed", _limit(self.max_speed, "angular_velocity", "max_speed", "rad/s")
        )

    @property
    def schedule(self) -> tuple[Array, Array]:
        """(times (s), torques (N·m)): the motor torque is torques[k] from times[k] on."""
        times, torques = self.torque
        return times, torques

    @property
    def driven(self) -> bool:
        return bool(np.any(self.schedule[1] != 0.0))

    def motor_torque(self, t: Any) -> Array:
        """The scheduled motor torque (N·m) at times ``t`` (s), right-continuous."""
        times, torques = self.schedule
        index = np.searchsorted(times, np.asarray(t, dtype=float), side="right") - 1
        return np.where(index >= 0, torques[np.clip(index, 0, None)], 0.0)

    def spin_inertia(self) -> Array:
        return np.asarray(self.inertia * np.outer(self.axis, self.axis))

    def initial_values(self, omega0: Array) -> Array:
        return np.full((*np.shape(omega0)[:-1], 1), self.speed)

    def momenta(self, omega: Array, values: Array) -> Array:
        along = np.asarray(omega, dtype=float) @ self.axis
        return np.asarray(self.inertia * (along + values[..., 0]))[..., None]

    def momentum(self, omega: Array, values: Array) -> Array:
        return self.momenta(omega, values) * self.axis

    def kinetic_energy(self, omega: Array, values: Array) -> Array:
        h = self.momenta(omega, values)[..., 0]
        return np.asarray(0.5 * h * h / self.inertia)

    def values_from(self, omega: Array, momenta: Array) -> Array:
        along = np.asarray(omega, dtype=float) @ self.axis
        return np.asarray(momenta[..., 0] / self.inertia - along)[..., None]

    def describe(self) -> dict[str, Any]:
        times, torques = self.schedule
        return {
            "type": self.kind,
            "axis": self.axis.tolist(),
            "inertia": self.inertia,
            "speed": self.speed,
            "torque": [[float(a), float(b)] for a, b in zip(times, torques, strict=True)],
            "max_torque": None if math.isinf(self.max_torque) else self.max_torque,
            "max_speed": None if math.isinf(self.max_speed) else self.max_speed,
        }

    def __repr__(self) -> str:
        times, torques = self.schedule
        motor = (
            f"{torques[0]!r} N·m"
            if len(times) == 1 and times[0] == 0.0
            else f"schedule of {len(times)} steps"
        )
        return (
            f"Rotor(axis={self.axis.tolist()}, inertia={self.inertia!r} kg·m², "
            f"speed={self.speed!r} rad/s, torque={motor})"
        )


def _schedule(torque: Any) -> tuple[Array, Array]:
    """A constant motor torque or a list of (time, torque) pairs as (times, torques)."""
    pairs = torque if isinstance(torque, list | tuple) and len(torque) > 0 else None
    if pairs is not None and all(isinstance(p, list | tuple) and len(p) == 2 for p in pairs):
        times = np.array([to_si(p[0], "time", "torque") for p in pairs])
        values = np.array([to_si(p[1], "torque", "torque") for p in pairs])
        if not (np.all(np.isfinite(times)) and np.all(np.isfinite(values))):
            raise InputError(
                f"Expected `torque` of a Rotor to hold finite times and torques, got {torque!r}."
            )
        if np.any(np.diff(times) <= 0):
            raise InputError(
                "Expected `torque` of a Rotor as (time, torque) pairs with increasing times, "
                f"got times {times.tolist()} s."
            )
    else:
        try:
            value = to_si(torque, "torque", "torque")
        except InputError as exc:
            raise InputError(
                f"{exc} (a Rotor's `torque` is a torque or a list of (time, torque) pairs)"
            ) from None
        if not math.isfinite(value):
            raise InputError(f"Expected `torque` of a Rotor to be finite, got {value!r}.")
        times, values = np.array([0.0]), np.array([value])
    times.flags.writeable = False
    values.flags.writeable = False
    return times, values


@dataclass(frozen=True, eq=False)
class KaneDamper(InternalPart):
    """A Kane damper: a sphere of moment of inertia ``inertia`` (kg·m², > 0; about
    any axis through its centre) turning in a viscous fluid inside the body.

    The fluid couples it to the body with the torque ``damping · (ω − ω_s)`` on
    the sphere (``damping`` D in N·m·s, >= 0; the body feels the opposite): an
    internal energy sink that keeps the total angular momentum. Its centre is
    fixed in the body and its mass and inertia, as if locked, belong in the
    body's MassProperties. At t = 0 the sphere turns with the body.
    (Kane & Barba, J. Appl. Mech. 33 (1966); Roithmayr & Hodges, *Dynamics:
    Theory and Application of Kane's Method*, §9.6.)
    """

    inertia: Any
    damping: Any

    kind = "kane-damper"
    size = 3
    value_labels = ("omega_x", "omega_y", "omega_z")

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "inertia", _positive(self.inertia, "inertia", "inertia", "KaneDamper", "kg·m²")
        )
        object.__setattr__(
            self,
            "damping",
            _positive(self.damping, "damping", "damping", "KaneDamper", "N·m·s", strict=False),
        )

    @property
    def dissipative(self) -> bool:
        return self.damping > 0

    def spin_inertia(self) -> Array:
        return self.inertia * np.eye(3)

    def initial_values(self, omega0: Array) -> Array:
        return np.array(omega0, dtype=float)

    def momenta(self, omega: Array, values: Array) -> Array:
        return np.asarray(self.inertia * np.asarray(values, dtype=float))

    def momentum(self, omega: Array, values: Array) -> Array:
        return self.momenta(omega, values)

    def kinetic_energy(self, omega: Array, values: Array) -> Array:
        values = np.asarray(values, dtype=float)
        return np.asarray(0.5 * self.inertia * np.einsum("...i,...i->...", values, values))

    def values_from(self, omega: Array, momenta: Array) -> Array:
        return np.asarray(momenta / self.inertia)

    def describe(self) -> dict[str, Any]:
        return {"type": self.kind, "inertia": self.inertia, "damping": self.damping}

    def __repr__(self) -> str:
        return f"KaneDamper(inertia={self.inertia!r} kg·m², damping={self.damping!r} N·m·s)"


#: The part classes by their ``type`` in scenario files and run files.
PART_TYPES: dict[str, type[InternalPart]] = {cls.kind: cls for cls in (Rotor, KaneDamper)}


def value_columns(parts: tuple[InternalPart, ...]) -> list[str]:
    """Names of the columns of the parts' values in a trajectory file, in order:
    ``rotor_1_speed``, ``damper_1_omega_x`` … (numbered per kind, from 1)."""
    names, counts = [], {"rotor": 0, "kane-damper": 0}
    for part in parts:
        counts[part.kind] += 1
        prefix = "rotor" if part.kind == "rotor" else "damper"
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
            f"Expected `internal` to be a list of Rotor and KaneDamper parts, got "
            f"{type(parts).__name__}."
        )
    for k, part in enumerate(parts):
        if not isinstance(part, InternalPart):
            raise InputError(
                f"Expected `internal[{k}]` to be a Rotor or a KaneDamper, got "
                f"{type(part).__name__}."
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
    kinds = tuple(ROTOR if isinstance(part, Rotor) else DAMPER for part in parts)
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
            times, torques = part.schedule
            padded_times = np.full(longest, np.inf)
            padded_times[: len(times)] = times
            padded_torques = np.zeros(longest)
            padded_torques[: len(torques)] = torques
            rows += [*axes[k], part.inertia, part.max_torque, part.max_speed, *allocation[k]]
            rows += [*padded_times, *padded_torques]
            k += 1
        else:
            assert isinstance(part, KaneDamper)
            rows += [part.inertia, part.damping]
    return np.asarray(rows, dtype=float)[:, None]


def switch_times(parts: tuple[InternalPart, ...], end: float) -> Array:
    """The times in (0, end) at which a rotor's scheduled torque switches, sorted."""
    times = [part.schedule[0] for part in parts if isinstance(part, Rotor)]
    every = np.unique(np.concatenate(times)) if times else np.zeros(0)
    return np.asarray(every[(every > 0) & (every < end)])
