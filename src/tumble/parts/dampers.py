"""Internal energy sinks: :class:`KaneDamper` and :class:`SpringMassDamper`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core.dampers import DAMPER_EQUATIONS, SPRING_EQUATIONS
from tumble.errors import InputError
from tumble.parameters import Parameter
from tumble.parts.base import FilePart, InternalPart, PartDrawing, positive, register_part
from tumble.parts.solids import SIZE_KEYS, moment_from_table, required
from tumble.units import to_si, unit_vector, vector_to_si

__all__ = ["KaneDamper", "SpringMassDamper"]

Array = NDArray[np.float64]


@register_part
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

    Examples
    --------
    The major-axis rule: spun about its axis of least moment, a body with a
    damper loses energy at constant |L|, so its nutation grows, at the rate
    :func:`tumble.theory.kane_damper_decay` predicts.

    >>> import numpy as np
    >>> import tumble as tb
    >>> body = tb.MassProperties(1.0, [0, 0, 0], np.diag([2.0, 2.0, 1.0]))
    >>> damper = tb.KaneDamper(inertia=0.05, damping=0.1)
    >>> traj = tb.simulate(body, [0.01, 0, 1.0], internal=[damper], duration=60.0, dt=0.1)
    >>> print(f"E from {traj.energy[0]:.6f} to {traj.energy[-1]:.6f} J")
    E from 0.500100 to 0.500058 J
    >>> L = np.linalg.norm(traj.angular_momentum, axis=1)
    >>> np.allclose(L, L[0])
    True
    >>> wobble = np.hypot(traj.omega[:, 0], traj.omega[:, 1])
    >>> rate = tb.analysis.exponential_rate(traj.t, wobble)
    >>> theory = tb.theory.kane_damper_decay(body, 0.05, 0.1, spin_rate=1.0)
    >>> print(f"growth {rate:.4f} 1/s, theory {-theory.decay_rate:.4f} 1/s")
    growth 0.0029 1/s, theory 0.0029 1/s
    """

    inertia: Any
    damping: Any

    kind = "kane-damper"
    summary = "a sphere turning in viscous fluid inside the body: an energy sink"
    closed_forms = frozenset({"energy-sink"})
    label = "damper"
    size = 3
    value_labels = ("omega_x", "omega_y", "omega_z")
    parameters = (
        Parameter("inertia", "inertia", (), "the sphere's moment of inertia J", 0.0, strict=True),
        Parameter("damping", "damping", (), "the fluid's viscous coupling D", 0.0),
    )
    file_keys = (parameters[1], *SIZE_KEYS)
    equations = DAMPER_EQUATIONS

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "inertia", positive(self.inertia, "inertia", "inertia", "KaneDamper", "kg·m²")
        )
        object.__setattr__(
            self,
            "damping",
            positive(self.damping, "damping", "damping", "KaneDamper", "N·m·s", strict=False),
        )

    @property
    def dissipative(self) -> bool:
        return self.damping > 0

    def internal_rates(self, platform_inertia: Array) -> tuple[float, float]:
        """D / J and D / I_p (I_p the platform's smallest principal moment): the
        fluid brings the sphere and a platform turning about one axis to one
        spin at their sum, D (1/J + 1/I_p)."""
        smallest = float(np.linalg.eigvalsh(platform_inertia)[0])
        return float(self.damping / self.inertia), float(self.damping / smallest)

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

    def pack(self, frame: Any, parts: tuple[InternalPart, ...]) -> list[Any]:
        """J and D: :data:`tumble.core.dampers.DAMPER_FIELDS`."""
        return [self.inertia, self.damping]

    def to_kernel(self, momenta: Array, frame: Any) -> Array:
        return np.asarray(frame.to_principal(momenta))

    def from_kernel(self, block: Array, frame: Any) -> Array:
        return np.asarray(frame.from_principal(block))

    @classmethod
    def from_table(cls, values: dict[str, Any]) -> FilePart:
        """A damper of ``inertia`` (already in ``[body]``), or a uniform sphere of
        ``mass`` and ``radius`` that tumble adds to the body at ``position``."""
        damping = required(values, "damping", "the fluid's viscous coupling D, N·m·s")
        moment, solid = moment_from_table(cls.kind, values, 0.4)
        position = values.get("position")
        position = np.zeros(3) if position is None else np.asarray(position, dtype=float)
        ball = None
        if solid:
            from tumble.shapes import solid_sphere

            ball = solid_sphere(values["mass"], values["radius"]).transformed(None, position)
        return FilePart(cls(moment, damping), ball, position, values.get("radius"))

    def drawing(
        self,
        reach: float,
        centre: Array,
        position: Any = None,
        radius: float | None = None,
        thickness: float | None = None,
    ) -> PartDrawing | None:
        """Its sphere, when its size is known."""
        if radius is None:
            return None
        at = np.asarray(centre if position is None else position, dtype=float)
        return PartDrawing("ball", at, radius)

    def __repr__(self) -> str:
        return f"KaneDamper(inertia={self.inertia!r} kg·m², damping={self.damping!r} N·m·s)"


@register_part
@dataclass(frozen=True, eq=False)
class SpringMassDamper(InternalPart):
    """A point mass on a spring: it slides along the body-fixed ``direction`` through
    its rest point ``position`` (body coordinates, m), pulled back by the spring
    (``stiffness`` k, N/m, > 0) and slowed by a dashpot (``damping`` c, N·s/m, >= 0):
    an internal energy sink, the second classic besides :class:`KaneDamper`.

    ``mass`` (kg, > 0) is in the body's MassProperties at ``position``, as if
    locked there (tumble's convention); ``displacement`` (m) is where it starts
    along ``direction``, at rest relative to the body. The body must be free
    (no pivot) and carry one spring–mass damper at most. The model is exact:
    the body's centre of mass moves with the mass, and the kinetic energy about
    it is ``½ ωᵀ (I_p + Δ(x)) ω + ẋ ω·g + ½ μ ẋ²`` with μ = m (M − m) / M
    (:mod:`tumble.core.dampers`).
    """

    mass: Any
    position: Any
    direction: Any
    stiffness: Any
    damping: Any = 0.0
    displacement: Any = 0.0
    #: Set by :meth:`~tumble.parts.SpringMassDamper.attached` (the reduced mass
    #: μ, kg, and the rest position d0 from the centre of mass of the rest of the
    #: body, m, body axes): what the part knows of the body that carries it; None
    #: for a bare part.
    geometry: Any = field(default=None, init=False, repr=False)

    kind = "spring-mass-damper"
    summary = "a point mass sliding on a spring with a dashpot: an energy sink"
    label = "spring"
    size = 2
    value_labels = ("displacement", "velocity")
    value_unit = "m, m/s"
    parameters = (
        Parameter(
            "mass",
            "mass",
            (),
            "the sliding point mass, in [body] at its rest point",
            0.0,
            strict=True,
        ),
        Parameter("position", "length", (3,), "its rest point, body coordinates"),
        Parameter("direction", "dimensionless", (3,), "the direction it slides along, body axes"),
        Parameter("stiffness", "stiffness", (), "the spring's stiffness k", 0.0, strict=True),
        Parameter("damping", "linear_damping", (), "the dashpot's damping c", 0.0),
        Parameter("displacement", "length", (), "where it starts along its direction"),
    )
    file_keys = (
        parameters[0],
        parameters[1],
        Parameter("axis", "dimensionless", (3,), "the direction it slides along, body axes"),
        *parameters[3:],
    )
    equations = SPRING_EQUATIONS
    one_per_body = "two moving masses couple through the centre of mass; this model holds one"
    free_body_only = "its mass moves the centre of mass the body turns about"
    not_in_batches = "its mass moves each body's centre of mass: use simulate"

    def __post_init__(self) -> None:
        owner = "SpringMassDamper"
        object.__setattr__(self, "mass", positive(self.mass, "mass", "mass", owner, "kg"))
        position = vector_to_si(self.position, "length", "position", (3,))
        position.flags.writeable = False
        object.__setattr__(self, "position", position)
        object.__setattr__(self, "direction", unit_vector(self.direction, "direction", owner=owner))
        stiffness = positive(self.stiffness, "stiffness", "stiffness", owner, "N/m")
        object.__setattr__(self, "stiffness", stiffness)
        damping = positive(self.damping, "linear_damping", "damping", owner, "N·s/m", False)
        object.__setattr__(self, "damping", damping)
        object.__setattr__(self, "displacement", to_si(self.displacement, "length", "displacement"))

    def attached(self, mp: Any) -> SpringMassDamper:
        """With the reduced mass μ = m (M − m) / M and the rest position d0 from the
        centre of mass of the rest of the body (body axes), for a body ``mp``."""
        total = float(mp.mass)
        if not total > self.mass * (1 + 1e-12):
            raise InputError(
                f"Expected the body's mass ({total!r} kg) to hold the SpringMassDamper's mass "
                f"and more, got {self.mass!r} kg."
            )
        reduced = self.mass * (total - self.mass) / total
        rest = (total / (total - self.mass)) * (self.position - np.asarray(mp.center_of_mass))
        values = dict(self.__dict__)
        values.pop("geometry", None)
        copy = SpringMassDamper(**values)
        object.__setattr__(copy, "geometry", (reduced, rest))
        return copy

    @property
    def _geometry(self) -> tuple[float, Array]:
        if self.geometry is None:
            raise InputError("Expected a SpringMassDamper attached to a body, got a bare one.")
        return self.geometry

    @property
    def dissipative(self) -> bool:
        return self.damping > 0

    def internal_rates(self, platform_inertia: Array) -> tuple[float, float]:
        """The largest |λ| of μ' ẍ + c ẋ + k x = 0, and 0 (its pull on the platform
        is in μ'): (c + √(c² − 4 μ' k)) / 2μ' overdamped, √(k/μ') otherwise.
        μ' = μ − gᵀ I_p⁻¹ g, the reduced mass less what the platform's turning
        takes of it (ω and ẋ share the momenta: (I_p ω + g ẋ, g·ω + μ ẋ)), is the
        mass the spring moves when the body's momentum is held; the body's
        rotation adds only rates of its own size."""
        reduced, _ = self._geometry
        coupling = self.coupling()
        moved = reduced - float(coupling @ np.linalg.solve(platform_inertia, coupling))
        moved = max(moved, 1e-12 * reduced)  # positive for any body: its energy is
        discriminant = self.damping**2 - 4.0 * moved * self.stiffness
        if discriminant > 0:
            return float((self.damping + math.sqrt(discriminant)) / (2.0 * moved)), 0.0
        return math.sqrt(self.stiffness / moved), 0.0

    def coupling(self) -> Array:
        """g = μ d0 × n (kg·m, body axes)."""
        reduced, rest = self._geometry
        return np.asarray(reduced * np.cross(rest, self.direction))

    def spin_inertia(self) -> Array:
        return np.zeros((3, 3))

    def initial_values(self, omega0: Array) -> Array:
        shape = (*np.shape(omega0)[:-1], 2)
        values = np.zeros(shape)
        values[..., 0] = self.displacement
        return values

    def _inertia_change(self, omega: Array, x: Array) -> Array:
        """Δ(x) ω, kg·m²/s: the change of the inertia about the moving centre of mass."""
        reduced, rest = self._geometry
        omega = np.asarray(omega, dtype=float)
        d = rest + np.asarray(x)[..., None] * self.direction
        grow = np.einsum("...i,...i->...", d, d) - rest @ rest
        along = np.einsum("...i,...i->...", d, omega)[..., None]
        return np.asarray(
            reduced * (grow[..., None] * omega - d * along + rest * (omega @ rest)[..., None])
        )

    def momentum(self, omega: Array, values: Array) -> Array:
        x, speed = values[..., 0], values[..., 1]
        return np.asarray(self._inertia_change(omega, x) + speed[..., None] * self.coupling())

    def kinetic_energy(self, omega: Array, values: Array) -> Array:
        reduced, _ = self._geometry
        omega = np.asarray(omega, dtype=float)
        x, speed = values[..., 0], values[..., 1]
        change = np.einsum("...i,...i->...", omega, self._inertia_change(omega, x))
        cross = speed * (omega @ self.coupling())
        return np.asarray(
            0.5 * change + cross + 0.5 * reduced * speed**2 + 0.5 * self.stiffness * x**2
        )

    def momenta(self, omega: Array, values: Array) -> Array:
        reduced, _ = self._geometry
        x, speed = values[..., 0], values[..., 1]
        p = np.asarray(omega, dtype=float) @ self.coupling() + reduced * speed
        return np.stack([np.broadcast_to(x, np.shape(p)), p], axis=-1)

    def values_from(self, omega: Array, momenta: Array) -> Array:
        reduced, _ = self._geometry
        x, p = momenta[..., 0], momenta[..., 1]
        speed = (p - np.asarray(omega, dtype=float) @ self.coupling()) / reduced
        return np.stack([x, speed], axis=-1)

    def pack(self, frame: Any, parts: tuple[InternalPart, ...]) -> list[Any]:
        """d0, n (principal platform axes), μ, k and c:
        :data:`tumble.core.dampers.SPRING_FIELDS`."""
        reduced, rest = self._geometry
        d0 = np.asarray(frame.to_principal(rest), dtype=float)
        n = np.asarray(frame.to_principal(self.direction), dtype=float)
        return [*d0, *n, reduced, self.stiffness, self.damping]

    @classmethod
    def from_table(cls, values: dict[str, Any]) -> FilePart:
        """A point mass tumble adds to the body at ``position``, its rest point,
        sliding along ``axis``."""
        from tumble.massprops import point_masses

        mass = required(values, "mass", "kg")
        axis = required(values, "axis", "the direction it slides along")
        stiffness = required(values, "stiffness", "N/m")
        position = values.get("position")
        position = np.zeros(3) if position is None else np.asarray(position, dtype=float)
        damping = values.get("damping")
        part = cls(
            mass,
            position,
            axis,
            stiffness,
            0.0 if damping is None else damping,
            values.get("displacement") or 0.0,
        )
        return FilePart(part, point_masses([mass], [position.tolist()]), position)

    def drawing(
        self,
        reach: float,
        centre: Array,
        position: Any = None,
        radius: float | None = None,
        thickness: float | None = None,
    ) -> PartDrawing:
        """Its mass at rest, as a small ball."""
        return PartDrawing("ball", np.asarray(self.position, dtype=float), 0.04 * reach)

    def __repr__(self) -> str:
        return (
            f"SpringMassDamper(mass={self.mass!r} kg at {self.position.tolist()} m along "
            f"{self.direction.tolist()}, stiffness={self.stiffness!r} N/m, "
            f"damping={self.damping!r} N·s/m)"
        )
