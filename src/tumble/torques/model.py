"""The base of the torque models, their sums, their parameters and their registry."""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any, ClassVar, cast

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, unknown_choice
from tumble.parameters import Parameter, shown_unit

__all__ = [
    "ACTUATORS",
    "TORQUES",
    "Parameter",
    "TorqueModel",
    "TorqueSum",
    "from_description",
    "register_torque",
]

Array = NDArray[np.float64]


#: Where a torque model's torque comes from (see :attr:`TorqueModel.actuator`).
ACTUATORS = ("external", "rotors")

#: Every registered torque model by its name in scenario files, in registration order.
TORQUES: dict[str, type[TorqueModel]] = {}


def register_torque(cls: type[TorqueModel]) -> type[TorqueModel]:
    """Class decorator: add a torque model to :data:`TORQUES` under ``cls.name``."""
    if not cls.name:
        raise InputError(f"Expected a torque model with a `name`, got {cls.__name__}.")
    TORQUES[cls.name] = cls
    return cls


class TorqueModel:
    """Base of the torque models, and of their sums (:class:`TorqueSum`).

    A model class sets the class attributes below and implements :meth:`pack`
    (and, as needed, :meth:`acts_on`, :meth:`potential_energy`,
    :meth:`conserves`, :meth:`context`, :meth:`uniform_gravity`). Its parameters
    are dataclass fields of the same names, converted to SI on construction.

    A conservative model declares its potential energy U(t, q) with
    :meth:`potential_energy`: :attr:`tumble.Trajectory.energy` adds the
    potentials of every model of a run to the kinetic energy, and the drift
    report lists the energy when each model's :meth:`conserves` keeps it.
    """

    #: Its ``type`` in scenario files ("" for a sum).
    name: ClassVar[str] = ""
    #: What it is, one line.
    summary: ClassVar[str] = ""
    parameters: ClassVar[tuple[Parameter, ...]] = ()
    #: The rows it packs for its compiled function, in the order the function reads them.
    fields: ClassVar[tuple[str, ...]] = ()
    #: Its compiled function (signature of :mod:`tumble.core.torques`), as a staticmethod.
    kernel: ClassVar[Any] = None
    #: What the torque τ its compiled function returns depends on besides the
    #: parameters: "attitude", "time", "omega" (the linear damping c it returns
    #: beside τ multiplies ω by construction and is not counted). A function
    #: that reads q must say "attitude": without it, a sweep that keeps no final
    #: states steps ω alone (with RK4) and gives its function a q that does not
    #: turn.
    depends_on: ClassVar[frozenset[str]] = frozenset()
    #: True when it derives from a potential that does not depend on time
    #: (:meth:`potential_energy`), and does not depend on ω: ``"auto"`` then takes
    #: the symplectic splitting.
    conservative: ClassVar[bool] = False
    #: True when scenario files may use it (its parameters are numbers).
    in_files: ClassVar[bool] = True
    #: The theory checks (names in :data:`tumble.checks.THEORY_CHECKS`) whose closed
    #: forms hold under a torque of this kind: a check asks the kind
    #: (:meth:`tumble.checks.Case.torques_for`), never its name.
    closed_forms: ClassVar[frozenset[str]] = frozenset()
    #: True when simulate_batch and sweeps accept it (parameters may be per body).
    in_batches: ClassVar[bool] = False
    #: None, or why a sum may hold only one model of this class (what to do instead).
    one_per_sum: ClassVar[str | None] = None
    #: True when its torque may be produced by the body's rotors instead of from
    #: outside (the class then has a field ``actuator``).
    drives_rotors: ClassVar[bool] = False
    #: ``"external"``: the torque acts on the body from outside; ``"rotors"``: the
    #: body's rotors produce it (their motor torques are its share-out, so the
    #: body's total angular momentum is untouched: momentum exchange).
    actuator: str = "external"

    def __post_init__(self) -> None:
        for parameter in self.parameters:
            value = parameter.convert(getattr(self, parameter.name), self.in_batches)
            object.__setattr__(self, parameter.name, value)
        if self.actuator not in ACTUATORS or (
            self.actuator != "external" and not self.drives_rotors
        ):
            allowed = ACTUATORS if self.drives_rotors else ("external",)
            raise unknown_choice(self.actuator, allowed, f"`actuator` of {type(self).__name__}")

    # ------------------------------------------------------------ algebra
    @property
    def terms(self) -> tuple[TorqueModel, ...]:
        """The models this one sums (itself for a single model)."""
        return (self,)

    def __add__(self, other: object) -> TorqueModel:
        if not isinstance(other, TorqueModel):
            return NotImplemented
        return TorqueSum((*self.terms, *other.terms))

    def __radd__(self, other: object) -> TorqueModel:
        if isinstance(other, int) and other == 0:  # sum() starts from 0
            return self
        return NotImplemented

    # ------------------------------------------------------------ what it is
    def values(self) -> dict[str, Any]:
        """The parameter values by name, SI."""
        return {p.name: getattr(self, p.name) for p in self.parameters}

    def flat_names(self) -> tuple[str, ...]:
        """The names of the numbers of :meth:`flat_values`: ``coefficient``,
        ``coefficients[0]``, ... (what a fit of the model's parameters calls them)."""
        names: list[str] = []
        for parameter in self.parameters:
            size = int(np.prod(parameter.shape))
            shown = [f"{parameter.name}[{k}]" for k in range(size)]
            names += shown if parameter.shape else [parameter.name]
        return tuple(names)

    def flat_values(self) -> Array:
        """The parameter values as one flat array, SI, in the order of ``parameters``."""
        values = [np.asarray(value, dtype=float).reshape(-1) for value in self.values().values()]
        return np.concatenate(values) if values else np.zeros(0)

    def with_flat_values(self, values: Array) -> TorqueModel:
        """The same model with the parameter values ``values`` (as :meth:`flat_values`
        gives them); every registered model is a dataclass."""
        changed, at = {}, 0
        for parameter in self.parameters:
            size = int(np.prod(parameter.shape))
            chunk = np.array(values[at : at + size], dtype=float)
            changed[parameter.name] = (
                chunk.reshape(parameter.shape) if parameter.shape else chunk[0]
            )
            at += size
        return replace(cast(Any, self), **changed)

    def describe(self) -> dict[str, Any]:
        """The model as JSON-ready SI values with its ``type`` (and its ``actuator``
        when not external), to write beside a trajectory; :func:`from_description`
        builds it back when its class is registered and may be written in files."""
        entry: dict[str, Any] = {"type": self.name or type(self).__name__}
        for name, value in self.values().items():
            entry[name] = None if value is None else np.asarray(value, dtype=float).tolist()
        if self.drives_rotors:
            entry["actuator"] = self.actuator
        return entry

    @cached_property
    def per_body(self) -> int | None:
        """The number of bodies its per-body values are for, or None (read once: a
        model's values do not change)."""
        counts = {
            int(np.shape(value)[0])
            for parameter, value in zip(self.parameters, self.values().values(), strict=True)
            if np.ndim(value) == len(parameter.shape) + 1
        }
        return counts.pop() if counts else None

    def __repr__(self) -> str:
        shown = []
        for parameter, value in zip(self.parameters, self.values().values(), strict=True):
            if value is None:
                shown.append(f"no {parameter.name}")
            elif np.ndim(value) == len(parameter.shape) + 1:
                what = "vectors" if parameter.shape else "values"
                shown.append(f"per body, {len(value)} {what}")
            else:
                unit = shown_unit(parameter.kind)
                number = np.asarray(value).tolist()
                shown.append(f"{number} {unit}".rstrip())
        if self.actuator != "external":
            shown.append(f"actuator={self.actuator!r}")
        return f"{type(self).__name__}({', '.join(shown)})"

    # ------------------------------------------------------------ on a body
    def acts_on(self, body: Any) -> bool:
        """False when the model exerts no torque on this body (then it is left out)."""
        return True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        """The values of ``fields`` for this body (its principal axes), as
        (len(fields),) or (len(fields), N) per body; ``omega0`` the initial
        angular velocity in body axes, rad/s (None for batches)."""
        raise NotImplementedError

    def context(self, body: Any) -> Any:
        """Non-numeric data the compiled function needs (see :class:`UserTorque`), or None."""
        return None

    def potential_energy(self, body: Any, t: Array, quaternion: Array) -> Array | None:
        """The potential energy U(t, q) from which the torque derives, J, (n,), on
        ``body`` (:class:`tumble.body.RigidBody`) at the times ``t`` (n,), s, and
        attitudes ``quaternion`` (n, 4), unit ``[w, x, y, z]`` rotating the body's
        own coordinates into space coordinates; None (the default) when the
        model declares no potential."""
        return None

    def uniform_gravity(self) -> Array | None:
        """The acceleration (3,), m/s², space axes, when this model is uniform
        gravity acting at the centre of mass (then a symmetric top on a pivot
        under it alone has a closed form, and its upward vertical is −g), else
        None (the default)."""
        return None

    def conserves(self, body: Any) -> frozenset[str]:
        """Which of :data:`tumble.invariants.INVARIANTS` the motion of this body keeps
        under this torque (with every other quantity a torque-free body keeps
        that this torque does not change)."""
        return frozenset()


@dataclass(frozen=True, eq=False, repr=False)
class TorqueSum(TorqueModel):
    """A sum of torque models (build with ``+``).

    Examples
    --------
    A motor's constant torque against viscous drag: the spin tends to the
    rate ``τ / c`` where they balance, ``ω(t) = (τ / c) (1 − exp(−c t / I))``.

    >>> import numpy as np
    >>> import tumble as tb
    >>> drive = tb.torques.ConstantBodyTorque([0, 0, 0.008]) + tb.torques.LinearDamping(0.008)
    >>> drive
    ConstantBodyTorque([0.0, 0.0, 0.008] N·m) + LinearDamping(0.008 N·m·s)
    >>> len(drive.terms)
    2
    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)  # I = 0.008 kg·m²
    >>> traj = tb.simulate(ball, [0, 0, 0], torque=drive, duration=5.0, dt=0.01)
    >>> print(f"{traj.omega[-1, 2]:.6f} rad/s, theory {1 - np.exp(-5.0):.6f}")
    0.993262 rad/s, theory 0.993262
    """

    models: tuple[TorqueModel, ...] = ()

    def __post_init__(self) -> None:
        counted = [term for term in self.models if term.per_body is not None]
        for term in counted[1:]:
            if term.per_body != counted[0].per_body:
                raise InputError(
                    "Expected per-body torque terms for the same number of bodies, got "
                    f"{counted[0]!r} and {term!r}."
                )
        for term in self.models:
            hint = type(term).one_per_sum
            if hint is not None and sum(type(t) is type(term) for t in self.models) > 1:
                name = type(term).__name__
                raise InputError(f"Expected at most one {name} in a sum, got two ({hint}).")

    @property
    def terms(self) -> tuple[TorqueModel, ...]:
        return self.models

    @property
    def conservative(self) -> bool:  # type: ignore[override]
        return all(term.conservative for term in self.models)

    @property
    def per_body(self) -> int | None:
        return next((term.per_body for term in self.models if term.per_body is not None), None)

    def potential_energy(self, body: Any, t: Array, quaternion: Array) -> Array | None:
        """The sum of the potentials of the terms that act on ``body`` and declare
        one (J, (n,)); None when none does."""
        total = None
        for term in self.models:
            if term.acts_on(body):
                energy = term.potential_energy(body, t, quaternion)
                if energy is not None:
                    total = energy if total is None else total + energy
        return None if total is None else np.asarray(total, dtype=float)

    def uniform_gravity(self) -> Array | None:
        """The sum of the terms' uniform gravity (m/s², space axes), or None when
        no term is uniform gravity."""
        found = [g for g in (term.uniform_gravity() for term in self.models) if g is not None]
        return np.sum(found, axis=0) if found else None

    def __repr__(self) -> str:
        return " + ".join(repr(term) for term in self.models) if self.models else "no torque"


def from_description(entry: dict[str, Any]) -> TorqueModel | None:
    """A torque model from :meth:`TorqueModel.describe`'s dictionary (a trajectory
    file's metadata), or None when its type is not a registered model that files
    may name (a :class:`tumble.torques.UserTorque`, whose function a file cannot
    hold)."""
    values = dict(entry)
    cls = TORQUES.get(str(values.pop("type", "")))
    if cls is None or not cls.in_files:
        return None
    return cls(**values)
