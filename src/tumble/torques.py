"""Torque models for :func:`tumble.simulate` and :func:`tumble.simulate_batch`, and their registry.

Each model is one class, registered under the name scenario files give it
(``[[torques]] type = "constant-body"``). The class says everything the rest of
tumble needs, so that nothing else names a torque: its parameters (units,
shapes, limits, per-body sweep names), the fields it packs for its compiled
function in :mod:`tumble.core.torques` (one shared signature), what it
depends on, whether it is conservative (and its potential), whether batches
may give it one value per body, and which quantities the motion keeps under it.

* :class:`Gravity` — uniform gravity acting at the centre of mass; a torque only
  about a pivot (a free body's centre of mass feels none).
* :class:`ConstantBodyTorque` — fixed in body axes (a thruster, a motor).
* :class:`ConstantSpaceTorque` — fixed in space axes.
* :class:`LinearDamping` — ``τ = −c ω`` (bearing friction, air drag at low speed).
* :class:`HoldRotation` — the body-fixed torque ``ω0 × (I ω0)`` that keeps the
  initial rotation steady (a motor holding a shaft at a constant rate).
* :class:`UserTorque` — any torque, from a function compiled with numba.

Models add with ``+``. A new model is a subclass of :class:`TorqueModel`
decorated with :func:`register_torque`, plus its compiled function: simulate,
simulate_batch, sweeps and scenario files then accept it.

A user torque function has the signature::

    @numba.njit
    def torque(t, omega, quaternion, params, out):
        ...

with ``t`` the time (s), ``omega`` (3,) the angular velocity in body axes
(rad/s), ``quaternion`` (4,) the attitude ``[w, x, y, z]`` (body → space),
``params`` the float64 array given to :class:`UserTorque`, and ``out`` (3,) a
zeroed array to fill with the torque on the body in body axes (N·m). It must
not keep references to its arguments (they are scratch buffers).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from tumble.body import FREE_BODY_INVARIANTS
from tumble.core import torques as kernels
from tumble.core._jit import file_stamp
from tumble.errors import InputError
from tumble.units import SI_UNITS, to_si, vector_to_si

__all__ = [
    "TORQUES",
    "BoundTorque",
    "ConstantBodyTorque",
    "ConstantSpaceTorque",
    "Gravity",
    "HoldRotation",
    "LinearDamping",
    "Parameter",
    "TorqueModel",
    "TorqueSum",
    "UserTorque",
    "bind",
    "register_torque",
]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Parameter:
    """A parameter of a torque model.

    Attributes
    ----------
    name : its keyword, and its key in scenario files.
    kind : the kind of quantity (a key of :data:`tumble.units.SI_UNITS`).
    shape : ``()`` for a number, ``(3,)`` for a vector.
    description : what it is, with its frame.
    minimum : the smallest value allowed, or None.
    sweep : the names of its per-body parameters in sweep files, one per
        component (empty: not sweepable).
    """

    name: str
    kind: str
    shape: tuple[int, ...] = ()
    description: str = ""
    minimum: float | None = None
    sweep: tuple[str, ...] = ()

    def convert(self, value: Any, per_body: bool) -> Any:
        """The value in SI: a float or (3,) array, or with ``per_body`` also (N,) or
        (N, 3), one per body of a batch."""
        many = per_body and np.ndim(value) == len(self.shape) + 1 and not isinstance(value, str)
        if not self.shape and not many:
            result: Any = to_si(value, self.kind, self.name)
        else:
            shape = ((-1, *self.shape) if many else self.shape) or (-1,)
            result = vector_to_si(value, self.kind, self.name, shape)
        if self.minimum is not None and np.any(np.asarray(result) < self.minimum):
            unit = SI_UNITS[self.kind].replace("*", "·")
            if np.ndim(result):
                k = int(np.argmin(result))
                shown = f"{self.name}[{k}] = {float(np.ravel(result)[k])!r}"
            else:
                shown = repr(result)
            raise InputError(f"Expected `{self.name}` >= {self.minimum:g} {unit}, got {shown}.")
        if isinstance(result, np.ndarray):
            result.flags.writeable = False
        return result


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
    :meth:`conserves`, :meth:`context`). Its parameters are dataclass fields of
    the same names, converted to SI on construction.
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
    #: What the torque depends on besides its parameters: "attitude", "time", "omega".
    depends_on: ClassVar[frozenset[str]] = frozenset()
    #: True when it derives from a potential (:meth:`potential_energy`).
    conservative: ClassVar[bool] = False
    #: True when scenario files may use it (its parameters are numbers).
    in_files: ClassVar[bool] = True
    #: True when simulate_batch and sweeps accept it (parameters may be per body).
    in_batches: ClassVar[bool] = False

    def __post_init__(self) -> None:
        for parameter in self.parameters:
            value = parameter.convert(getattr(self, parameter.name), self.in_batches)
            object.__setattr__(self, parameter.name, value)

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

    @property
    def per_body(self) -> int | None:
        """The number of bodies its per-body values are for, or None."""
        counts = {
            int(np.shape(value)[0])
            for parameter, value in zip(self.parameters, self.values().values(), strict=True)
            if np.ndim(value) == len(parameter.shape) + 1
        }
        return counts.pop() if counts else None

    def __repr__(self) -> str:
        shown = []
        for parameter, value in zip(self.parameters, self.values().values(), strict=True):
            if np.ndim(value) == len(parameter.shape) + 1:
                what = "vectors" if parameter.shape else "values"
                shown.append(f"per body, {len(value)} {what}")
            else:
                unit = SI_UNITS[parameter.kind].replace("*", "·")
                number = np.asarray(value).tolist()
                shown.append(f"{number} {unit}".rstrip())
        return f"{type(self).__name__}({', '.join(shown)})"

    # ------------------------------------------------------------ on a body
    def acts_on(self, body: Any) -> bool:
        """False when the model exerts no torque on this body (then it is left out)."""
        return True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        """The values of :attr:`fields` for this body (its principal axes), as
        (len(fields),) or (len(fields), N) per body; ``omega0`` the initial
        angular velocity in body axes, rad/s (None for batches)."""
        raise NotImplementedError

    def context(self, body: Any) -> Any:
        """Non-numeric data the compiled function needs (see :class:`UserTorque`), or None."""
        return None

    def potential_energy(self, body: Any, gravity_matrices: Array) -> Array:
        """Potential energy (J) at the attitudes (n, 3, 3) (body → space), for a
        conservative model."""
        return np.zeros(len(gravity_matrices))

    def conserves(self, body: Any) -> frozenset[str]:
        """Which of :data:`tumble.body.INVARIANTS` the motion of this body keeps
        under this torque (with every other quantity a torque-free body keeps
        that this torque does not change)."""
        return frozenset()


@dataclass(frozen=True, eq=False, repr=False)
class TorqueSum(TorqueModel):
    """A sum of torque models (build with ``+``)."""

    models: tuple[TorqueModel, ...] = ()

    def __post_init__(self) -> None:
        counted = [term for term in self.models if term.per_body is not None]
        for term in counted[1:]:
            if term.per_body != counted[0].per_body:
                raise InputError(
                    "Expected per-body torque terms for the same number of bodies, got "
                    f"{counted[0]!r} and {term!r}."
                )
        if sum(isinstance(term, UserTorque) for term in self.models) > 1:
            raise InputError(
                "Expected at most one UserTorque in a sum, got two (compute both torques in "
                "one function)."
            )

    @property
    def terms(self) -> tuple[TorqueModel, ...]:
        return self.models

    @property
    def conservative(self) -> bool:  # type: ignore[override]
        return all(term.conservative for term in self.models)

    @property
    def per_body(self) -> int | None:
        return next((term.per_body for term in self.models if term.per_body is not None), None)

    def __repr__(self) -> str:
        return " + ".join(repr(term) for term in self.models) if self.models else "no torque"


# ------------------------------------------------------------------ the models
def _vector_field(prefix: str) -> tuple[str, str, str]:
    return (f"{prefix}_1", f"{prefix}_2", f"{prefix}_3")


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class Gravity(TorqueModel):
    """Uniform gravity of acceleration ``acceleration`` (space axes, m/s², default
    −9.81 ẑ) acting at the centre of mass: a torque about a pivot only."""

    acceleration: Any = (0.0, 0.0, -9.81)

    name = "gravity"
    summary = "uniform gravity at the centre of mass (a torque about a pivot only)"
    parameters = (
        Parameter("acceleration", "acceleration", (3,), "gravitational acceleration, space axes"),
    )
    fields = (*_vector_field("lever"), "weight_x", "weight_y", "weight_z")
    kernel = staticmethod(kernels.gravity_about_pivot)
    depends_on = frozenset({"attitude"})
    conservative = True

    def acts_on(self, body: Any) -> bool:
        return getattr(body, "pivot", None) is not None and bool(np.any(self.acceleration))

    def pack(self, body: Any, omega0: Array | None) -> Array:
        weight = body.mass_properties.mass * np.asarray(self.acceleration)
        return np.concatenate([body.to_principal(body.lever), weight])

    def potential_energy(self, body: Any, matrices: Array) -> Array:
        """``−m g · (A r)``, r from the pivot to the centre of mass (J; zero for a
        free body, whose energy is about its centre of mass)."""
        if getattr(body, "pivot", None) is None:
            return np.zeros(len(matrices))
        height = np.einsum("nij,j->ni", matrices, body.lever)
        return np.asarray(-body.mass_properties.mass * (height @ np.asarray(self.acceleration)))

    def conserves(self, body: Any) -> frozenset[str]:
        if not self.acts_on(body):
            return FREE_BODY_INVARIANTS
        kept = {"energy", "angular_momentum_vertical"}
        if body.is_symmetric_top():
            kept.add("angular_momentum_axial")
        return frozenset(kept)


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class ConstantBodyTorque(TorqueModel):
    """A constant torque in body axes (N·m): (3,), or (N, 3) one per body of a batch."""

    torque: Any

    name = "constant-body"
    summary = "a constant torque fixed in the body (a thruster, a motor)"
    parameters = (
        Parameter(
            "torque", "torque", (3,), "torque in body axes", sweep=_vector_field("body_torque")
        ),
    )
    fields = _vector_field("torque")
    kernel = staticmethod(kernels.constant_body_torque)
    in_batches = True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return np.asarray(body.to_principal(self.torque)).T


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class ConstantSpaceTorque(TorqueModel):
    """A constant torque in space axes (N·m): (3,), or (N, 3) one per body of a batch."""

    torque: Any

    name = "constant-space"
    summary = "a constant torque fixed in space"
    parameters = (
        Parameter(
            "torque",
            "torque",
            (3,),
            "torque in space axes",
            sweep=("space_torque_x", "space_torque_y", "space_torque_z"),
        ),
    )
    fields = ("torque_x", "torque_y", "torque_z")
    kernel = staticmethod(kernels.constant_space_torque)
    depends_on = frozenset({"attitude"})
    in_batches = True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return np.asarray(self.torque, dtype=float).T


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class LinearDamping(TorqueModel):
    """Viscous damping ``τ = −c ω`` with ``c`` >= 0 in N·m·s: a number, or (N,) one
    per body of a batch."""

    coefficient: Any

    name = "damping"
    summary = "viscous damping τ = −c ω"
    parameters = (
        Parameter("coefficient", "damping", (), "damping coefficient c", 0.0, sweep=("damping",)),
    )
    fields = ("coefficient",)
    kernel = staticmethod(kernels.linear_damping)
    depends_on = frozenset({"omega"})
    in_batches = True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return np.asarray(self.coefficient, dtype=float)[None, ...]


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class HoldRotation(TorqueModel):
    """The body-fixed torque ``ω0 × (I ω0)`` about the reference point that keeps
    the initial rotation ω0 steady: what a motor supplies to hold a shaft at a
    constant rate (the rotating skew rod, an unbalanced rotor). It does no work
    (it is perpendicular to ω) and turns L rigidly: energy and |L| stay."""

    name = "hold-rotation"
    summary = "the torque ω0 × (I ω0) that keeps the initial rotation steady"
    fields = _vector_field("torque")
    kernel = staticmethod(kernels.constant_body_torque)

    def pack(self, body: Any, omega0: Array | None) -> Array:
        w = body.to_principal(np.zeros(3) if omega0 is None else omega0)
        return np.asarray(np.cross(w, body.moments * w))

    def conserves(self, body: Any) -> frozenset[str]:
        return frozenset({"energy", "angular_momentum_norm"})


@dataclass(frozen=True, eq=False, repr=False)
class UserTorque(TorqueModel):
    """A torque computed by ``function``, compiled with ``numba.njit``.

    ``function(t, omega, quaternion, params, out)`` writes the torque on the
    body in body axes (N·m) into ``out``; see this module's docstring for the
    arguments. ``params`` (a sequence of floats) is passed through unchanged, so
    one compiled function serves many parameter values. The function is called
    once here on a test state, so a wrong signature fails now, not mid-run.

    Example
    -------
    >>> import numba
    >>> @numba.njit
    ... def magnetic_damper(t, omega, quaternion, params, out):
    ...     out[0] = -params[0] * omega[0] ** 3
    >>> model = UserTorque(magnetic_damper, [0.01])
    """

    function: Any
    params: Any = ()

    name = "user"
    summary = "a torque from a function compiled with numba"
    kernel = staticmethod(kernels.user_torque)
    depends_on = frozenset({"attitude", "time", "omega"})
    in_files = False

    def __post_init__(self) -> None:
        from numba.core.dispatcher import Dispatcher

        function = self.function
        if not isinstance(function, Dispatcher):
            raise InputError(
                "Expected `function` to be compiled with numba.njit, got "
                f"{type(function).__name__} {getattr(function, '__name__', '')!r}."
            )
        values = np.asarray(self.params, dtype=float).reshape(-1).copy()
        try:
            function(0.0, np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]), values, np.zeros(3))
        except Exception as exc:  # numba raises its own typing errors
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise InputError(
                "Expected `function(t, omega, quaternion, params, out)` to run on a test state "
                f"(t = 0, omega = 0, identity attitude), got {type(exc).__name__}: {first}"
            ) from None
        values.flags.writeable = False
        object.__setattr__(self, "params", values)

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return np.zeros(0)

    def context(self, body: Any) -> Any:
        callback = _callback(self.function)
        return (
            np.ascontiguousarray(body.axes),
            np.asarray(body.principal_rotation.as_quat(scalar_first=True), dtype=float),
            np.array(self.params, dtype=float),  # writable copy
            np.zeros(3),
            np.zeros(4),
            np.zeros(3),
            callback,
        )

    def __repr__(self) -> str:
        name = getattr(self.function, "__name__", "function")
        return f"UserTorque({name}, params={np.asarray(self.params).tolist()})"


#: One C callback per user function, compiled on first use.
_CALLBACKS: dict[Any, Any] = {}


def _callback(function: Any) -> Any:
    callback = _CALLBACKS.get(function)
    if callback is None:
        callback = _CALLBACKS[function] = kernels.compile_user_torque(function)
    return callback


# ------------------------------------------------------------------ bound to a body
@dataclass(frozen=True, eq=False)
class BoundTorque:
    """A torque model bound to a body: what the compiled kernels take.

    Attributes
    ----------
    terms : the models that act on the body, in registry order.
    params : (rows, 1) or (rows, N) the packed fields of every term, principal axes.
    context : the one non-numeric argument of the kernels (0.0 when none).
    identity : names the terms' compiled functions, their sources and rows: the
        key under which kernels specialised for this torque are cached.
    function : the combined compiled function (:func:`tumble.core.torques.combine`).
    """

    terms: tuple[TorqueModel, ...]
    params: Array
    context: Any
    identity: str
    function: Any = field(repr=False)

    @property
    def torque_free(self) -> bool:
        return not self.terms

    @property
    def conservative(self) -> bool:
        """True when every term derives from a potential."""
        return all(term.conservative for term in self.terms)

    @property
    def depends_on(self) -> frozenset[str]:
        found: frozenset[str] = frozenset()
        for term in self.terms:
            found |= term.depends_on
        return found


_COMBINED: dict[str, Any] = {}
_LOCK = threading.Lock()


def bind(
    model: TorqueModel | None, body: Any, omega0: Array | None = None, bodies: int | None = None
) -> BoundTorque:
    """Bind a torque model to a body (:class:`tumble.body.RigidBody`) or a batch
    (:class:`tumble.body.BodyBatch`, ``bodies`` N): the terms that act on it, their
    fields packed in its principal axes, and the combined compiled function.

    Raises
    ------
    InputError
        Per-body values outside a batch or for the wrong number of bodies.
    """
    models = () if model is None else model.terms
    order = {cls: k for k, cls in enumerate(TORQUES.values())}
    acting = sorted(
        (term for term in models if term.acts_on(body)),
        key=lambda term: order.get(type(term), len(order)),
    )
    columns = 1 if bodies is None else bodies
    blocks, kernels_rows, contexts, row = [], [], [], 0
    for term in acting:
        _check_bodies(term, bodies)
        packed = np.asarray(term.pack(body, omega0), dtype=float)
        packed = packed.reshape(len(term.fields), -1) if term.fields else np.zeros((0, 1))
        blocks.append(np.broadcast_to(packed, (len(term.fields), packed.shape[1])))
        kernels_rows.append((type(term).kernel, row))
        row += len(term.fields)
        context = term.context(body)
        if context is not None:
            contexts.append(context)
    per_body = any(block.shape[1] > 1 for block in blocks)
    width = columns if per_body else 1
    params = np.ascontiguousarray(
        np.vstack([np.broadcast_to(block, (len(block), width)) for block in blocks])
        if blocks
        else np.zeros((1, width))
    )
    identity = "+".join(f"{file_stamp(kernel)}@{at}" for kernel, at in kernels_rows) or "free"
    with _LOCK:
        function = _COMBINED.get(identity)
        if function is None:
            function = _COMBINED[identity] = kernels.combine(kernels_rows)
    return BoundTorque(tuple(acting), params, contexts[0] if contexts else 0.0, identity, function)


def _check_bodies(term: TorqueModel, bodies: int | None) -> None:
    """Per-body values only in a batch, and one per body."""
    count = term.per_body
    if count is None:
        return
    if bodies is None:
        raise InputError(
            f"Expected one torque for one body, got per-body values ({term!r}): those are for "
            "simulate_batch."
        )
    if count != bodies:
        for parameter, value in zip(term.parameters, term.values().values(), strict=True):
            if np.ndim(value) == len(parameter.shape) + 1:
                raise InputError(
                    f"Expected per-body {type(term).__name__} values of shape "
                    f"{(bodies, *parameter.shape)} for {bodies} bodies, got {np.shape(value)}."
                )
