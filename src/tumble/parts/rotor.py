"""A wheel spinning about a body-fixed axis: :class:`Rotor`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core.rotor import ROTOR_EQUATIONS
from tumble.errors import InputError
from tumble.parameters import Parameter
from tumble.parts.base import (
    FilePart,
    InternalPart,
    PartDrawing,
    Siblings,
    limit,
    positive,
    register_part,
)
from tumble.parts.solids import SIZE_KEYS, moment_from_table, required
from tumble.units import to_si, unit_vector

__all__ = ["Rotor"]

Array = NDArray[np.float64]


_PARAMETERS = (
    Parameter("axis", "dimensionless", (3,), "its spin axis, body axes (normalised)"),
    Parameter("inertia", "inertia", (), "its moment of inertia J about its axis", 0.0, strict=True),
    Parameter("speed", "angular_velocity", (), "its spin rate relative to the body at t = 0"),
    Parameter(
        "torque",
        "",
        (),
        "the motor torque on it (N·m): a constant, or a schedule of (time, torque) pairs",
    ),
    Parameter(
        "max_torque",
        "torque",
        (),
        "the largest motor torque (default none)",
        0.0,
        strict=True,
        optional=True,
    ),
    Parameter(
        "max_speed",
        "angular_velocity",
        (),
        "the largest relative speed (default none)",
        0.0,
        strict=True,
        optional=True,
    ),
)


def _pseudo_inverse(matrices: Array) -> Array:
    """``np.linalg.pinv`` of a matrix or a stack (N, 3, k): computed once and shared
    when every matrix of the stack is the first (a batch of bodies whose principal
    frames agree; an SVD per body cost 0.09 s for 1e5 bodies)."""
    if (
        matrices.ndim == 3
        and len(matrices) > 1
        and np.array_equal(matrices, np.broadcast_to(matrices[0], matrices.shape))
    ):
        single = np.linalg.pinv(matrices[0])
        return np.broadcast_to(single, (len(matrices), *single.shape))
    return np.asarray(np.linalg.pinv(matrices))


@register_part
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
    max_speed : the largest relative speed it can reach (rad/s, > 0, at least
        ``|speed|``; default no limit): the motor torque is cut when it would
        drive the rotor beyond.

    The motor torque adds to the rotor's share of any torque model that acts
    through the rotors (``actuator="rotors"``, e.g. an attitude controller).

    Examples
    --------
    A reaction wheel (J = 0.002 kg·m²) spun up by its motor (1 mN·m) inside a
    body at rest (I = 0.008 kg·m² with the wheel locked): the body turns the
    other way at ``u t / (I − J)``, and the total angular momentum stays zero.

    >>> import numpy as np
    >>> import tumble as tb
    >>> body = tb.shapes.solid_sphere(2.0, 0.1)
    >>> wheel = tb.Rotor(axis=[0, 0, 1], inertia=0.002, torque=0.001)
    >>> traj = tb.simulate(body, [0, 0, 0], internal=[wheel], duration=1.0, dt=0.01)
    >>> print(f"body {traj.omega[-1, 2]:.4f} rad/s, wheel {traj.rotor_speed[-1, 0]:.4f} rad/s")
    body -0.1667 rad/s, wheel 0.6667 rad/s
    >>> np.allclose(traj.angular_momentum, 0.0)
    True
    """

    axis: Any
    inertia: Any
    speed: Any = 0.0
    torque: Any = 0.0
    max_torque: Any = None
    max_speed: Any = None

    kind = "rotor"
    summary = "a wheel spinning about a body-fixed axis, driven by a motor"
    label = "rotor"
    size = 1
    value_labels = ("speed",)
    parameters = _PARAMETERS
    file_keys = (
        *(p for p in _PARAMETERS if p.name != "inertia"),
        *SIZE_KEYS,
        Parameter(
            "thickness",
            "length",
            (),
            "the thickness of the uniform disc tumble adds (default a fifth of its radius)",
            0.0,
            strict=True,
        ),
    )
    equations = ROTOR_EQUATIONS
    gyrostatic = True
    actuated = True
    closed_forms = frozenset({"dual-spin", "slew"})
    spin = 0

    def __post_init__(self) -> None:
        object.__setattr__(self, "axis", unit_vector(self.axis, "axis", owner="Rotor"))
        object.__setattr__(
            self, "inertia", positive(self.inertia, "inertia", "inertia", "Rotor", "kg·m²")
        )
        object.__setattr__(self, "speed", to_si(self.speed, "angular_velocity", "speed"))
        object.__setattr__(self, "torque", _schedule(self.torque))
        object.__setattr__(
            self, "max_torque", limit(self.max_torque, "torque", "max_torque", "N·m")
        )
        object.__setattr__(
            self, "max_speed", limit(self.max_speed, "angular_velocity", "max_speed", "rad/s")
        )
        # The motor only stops pushing beyond the limit: a rotor started beyond it
        # would keep its speed, not be brought back within.
        if abs(self.speed) > self.max_speed:
            raise InputError(
                f"Expected `speed` of a Rotor within its `max_speed` ({self.max_speed!r} rad/s), "
                f"got {self.speed!r} rad/s."
            )

    @property
    def schedule(self) -> tuple[Array, Array]:
        """(times (s), torques (N·m)): the motor torque is torques[k] from times[k] on."""
        times, torques = self.torque
        return times, torques

    @property
    def driven(self) -> bool:
        return bool(np.any(self.schedule[1] != 0.0))

    @property
    def idle(self) -> bool:
        """Without a motor: its axial momentum changes only by a torque through the
        rotors (its speed limit only ever stops a motor)."""
        return not self.driven

    def motor_torque(self, t: Any) -> Array:
        """The scheduled motor torque (N·m) at times ``t`` (s), right-continuous."""
        times, torques = self.schedule
        index = np.searchsorted(times, np.asarray(t, dtype=float), side="right") - 1
        return np.where(index >= 0, torques[np.clip(index, 0, None)], 0.0)

    def spin_inertia(self) -> Array:
        return np.asarray(self.inertia * np.outer(self.axis, self.axis))

    def switch_times(self) -> Array:
        return self.schedule[0]

    @property
    def gyrostatic_axis(self) -> Array | None:
        return None if self.driven else np.asarray(self.axis)

    def pack(self, frame: Any, parts: tuple[InternalPart, ...]) -> list[Any]:
        """Its axis (principal platform axes), J, limits and row of the allocation
        matrix (the pseudo-inverse of the rotors' axes as columns), then its
        schedule: :data:`tumble.core.rotor.ROTOR_FIELDS`."""
        rotors = [part for part in parts if isinstance(part, Rotor)]

        def axes_and_allocation() -> tuple[Array, Array]:
            turned = np.stack(
                [np.asarray(frame.to_principal(r.axis), dtype=float) for r in rotors], -2
            )
            return turned, _pseudo_inverse(np.swapaxes(turned, -1, -2))  # (..., k, 3)

        if isinstance(parts, Siblings):
            turned, allocation = parts.shared("rotor allocation", axes_and_allocation)
        else:
            turned, allocation = axes_and_allocation()
        k = next(j for j, part in enumerate(rotors) if part is self)
        times, torques = self.schedule
        return [
            *(turned[..., k, i] for i in range(3)),
            self.inertia,
            self.max_torque,
            self.max_speed,
            *(allocation[..., k, i] for i in range(3)),
            *times,
            *torques,
        ]

    @classmethod
    def from_table(cls, values: dict[str, Any]) -> FilePart:
        """A rotor of ``inertia`` (already in ``[body]``), or a uniform disc of
        ``mass``, ``radius`` and ``thickness`` (a fifth of its radius by default)
        that tumble adds to the body at ``position``."""
        axis = required(values, "axis", "the rotor's spin axis, body axes")
        moment, solid = moment_from_table(cls.kind, values, 0.5)
        torque = values.get("torque", 0.0)
        if isinstance(torque, list) and torque and all(isinstance(p, list) for p in torque):
            torque = [tuple(pair) for pair in torque]
        rotor = cls(
            axis,
            moment,
            speed=values.get("speed", 0.0),
            torque=torque,
            max_torque=values.get("max_torque"),
            max_speed=values.get("max_speed"),
        )
        position = values.get("position")
        position = np.zeros(3) if position is None else np.asarray(position, dtype=float)
        radius = values.get("radius")
        thickness = values.get("thickness")
        if thickness is None and radius is not None:
            thickness = radius / 5.0
        disc = None
        if solid:
            from scipy.spatial.transform import Rotation

            from tumble.shapes import solid_cylinder

            turn, _ = Rotation.align_vectors([rotor.axis], [[0.0, 0.0, 1.0]])
            disc = solid_cylinder(values["mass"], radius, thickness).transformed(turn, position)
        return FilePart(rotor, disc, position, radius, thickness)

    def drawing(
        self,
        reach: float,
        centre: Array,
        position: Any = None,
        radius: float | None = None,
        thickness: float | None = None,
    ) -> PartDrawing:
        """A disc on its axis, turning at its speed: its own size, or a quarter of
        the body's."""
        if radius is None:
            radius = float(max(0.2 * reach, 1e-3)) if position is not None else 0.25 * reach
        if thickness is None:
            thickness = radius / 5.0
        at = np.asarray(centre if position is None else position, dtype=float)
        return PartDrawing("disc", at, radius, np.asarray(self.axis), thickness, spin=0)

    def initial_values(self, omega0: Array) -> Array:
        return np.full((*np.shape(omega0)[:-1], 1), self.speed)

    def momenta(self, omega: Array, values: Array) -> Array:
        along = np.asarray(omega, dtype=float) @ self.axis
        return np.asarray(self.inertia * (along + values[..., 0]))[..., None]

    def momentum(self, omega: Array, values: Array) -> Array:
        return self.momenta(omega, values) * self.axis

    def kinetic_energy(self, omega: Array, values: Array) -> Array:
        # ½ J s², s the rotor's rate in space: no square of h = J s, which
        # overflows or underflows for a rotor of 1e±200 kg·m².
        rate = np.asarray(omega, dtype=float) @ self.axis + values[..., 0]
        return np.asarray(0.5 * self.inertia * rate * rate)

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
            f"{float(torques[0])!r} N·m"
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
        times, values = np.array([0.0]), np.array([value])
    times.flags.writeable = False
    values.flags.writeable = False
    return times, values
