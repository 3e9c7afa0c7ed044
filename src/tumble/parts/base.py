"""The base of the parts a body carries, their registry, and the checks of their values.

A part kind is one module under :mod:`tumble.parts`: a subclass of
:class:`InternalPart` (its parameters, its state and how it maps to and from
the kernels, its energy and momentum, how it is drawn and read from files)
whose ``equations`` are compiled functions (:class:`tumble.core.parts.PartEquations`),
registered once with :func:`register_part`. Everything else in tumble — the
body model, the integrators, the batch driver, scenario files,
trajectory files, the report — reads the registry :data:`PARTS`.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, fields, is_dataclass
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from tumble.core.parts import PartEquations
from tumble.errors import InputError, unknown_choice
from tumble.parameters import Parameter
from tumble.units import to_si

Array = NDArray[np.float64]

__all__ = [
    "PARTS",
    "FilePart",
    "InternalPart",
    "PartDrawing",
    "Siblings",
    "TableKeyError",
    "internal_rate",
    "limit",
    "part_class",
    "positive",
    "register_part",
]


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


@dataclass(frozen=True)
class PartDrawing:
    """How the report draws a part, in body coordinates: a ``"disc"`` (a wheel, on
    ``axis``, of ``thickness``) or a ``"ball"``, of ``radius`` (m) centred at
    ``position`` (m). ``spin``: the index of the part's value that is its spin
    rate relative to the body (rad/s), turning the disc in the viewer, or None."""

    shape: Literal["disc", "ball"]
    position: Array
    radius: float
    axis: Array | None = None
    thickness: float = 0.0
    spin: int | None = None


@dataclass(frozen=True)
class FilePart:
    """A part read from a table of a scenario file: the part, the solid tumble
    adds to the body for it (a MassProperties in body coordinates, or None:
    already in ``[body]``), and where and how large to draw it (m; None: where
    and as large as the part's :meth:`~InternalPart.drawing` chooses)."""

    part: InternalPart
    solid: Any = None
    position: Array | None = None
    radius: float | None = None
    thickness: float | None = None


class TableKeyError(InputError):
    """A value of a part's table in a file that is wrong (or missing), about one
    ``key``: files place the message at that key."""

    def __init__(self, key: str, message: str) -> None:
        super().__init__(message)
        self.key = key


#: Every registered part kind by its ``type`` in files, in registration order.
PARTS: dict[str, type[InternalPart]] = {}


def register_part(cls: type[InternalPart]) -> type[InternalPart]:
    """Class decorator: add a part kind to :data:`PARTS` under ``cls.kind``.

    Raises
    ------
    InputError
        A class without a ``kind``, ``label``, ``size`` or ``equations``, whose
        ``value_labels`` are not ``size``, or that spins and does not draw itself.
    """
    missing = [name for name in ("kind", "label", "size", "equations") if not getattr(cls, name)]
    if missing:
        raise InputError(
            f"Expected a part kind with {', '.join(f'`{m}`' for m in missing)}, got "
            f"{cls.__name__} without."
        )
    if len(cls.value_labels) != cls.size:
        raise InputError(
            f"Expected {cls.size} `value_labels` of {cls.__name__} (its `size`), got "
            f"{len(cls.value_labels)}."
        )
    if cls.spin is not None and cls.drawing is InternalPart.drawing:
        raise InputError(
            f"Expected a `drawing` of {cls.__name__}, which spins (`spin` = {cls.spin}): the "
            "viewer turns a disc at its speed, got none."
        )
    PARTS[cls.kind] = cls
    return cls


def part_class(kind: Any) -> type[InternalPart]:
    """The registered part class of ``type`` ``kind``.

    Raises
    ------
    InputError
        An unknown kind; the message lists the kinds and the closest.
    """
    if not isinstance(kind, str) or kind not in PARTS:
        raise unknown_choice(kind, PARTS, "`type`")
    return PARTS[kind]


def _required_fields(cls: type) -> set[str]:
    """The names of a dataclass's constructor arguments without a default."""
    if not is_dataclass(cls):
        return set()
    return {
        f.name
        for f in fields(cls)
        if f.init and f.default is MISSING and f.default_factory is MISSING
    }


class Siblings(tuple[Any, ...]):
    """The parts of one body, as :meth:`InternalPart.pack` receives them: a tuple,
    with :meth:`~tumble.parts.Siblings.shared` for what several parts of a kind
    compute once per packing (the rotors' allocation matrix)."""

    _shared: dict[str, Any]

    def __new__(cls, parts: Any) -> Siblings:
        self = super().__new__(cls, parts)
        self._shared = {}
        return self

    def shared(self, key: str, make: Any) -> Any:
        """``make()``, computed once per packing under ``key``."""
        if key not in self._shared:
            self._shared[key] = make()
        return self._shared[key]


class InternalPart:
    """Base of the parts a body carries (see the module's docstring).

    A part has ``size`` state values: its *values* (what a trajectory records,
    in the user's units: a rotor's relative spin rate, a damper sphere's angular
    velocity) and its *momenta* (what the kernels integrate, in the same order:
    the state of :mod:`tumble.core.parts`).
    """

    #: Its ``type`` in scenario files.
    kind: ClassVar[str] = ""
    #: What it is, one line.
    summary: ClassVar[str] = ""
    #: The prefix of its columns in trajectory files (``rotor`` → ``rotor_1_speed``).
    label: ClassVar[str] = ""
    #: State values per part.
    size: ClassVar[int] = 0
    #: Labels of its values, and their unit.
    value_labels: ClassVar[tuple[str, ...]] = ()
    value_unit: ClassVar[str] = "rad/s"
    #: Its constructor's parameters, in SI (what
    #: :meth:`~tumble.parts.InternalPart.describe` writes).
    parameters: ClassVar[tuple[Parameter, ...]] = ()
    #: The keys of its tables in scenario files besides ``type`` (by
    #: default its parameters and ``position``, where it is drawn), each converted
    #: to SI before :meth:`~tumble.parts.InternalPart.from_table`.
    file_keys: ClassVar[tuple[Parameter, ...]] = ()
    #: Its compiled equations.
    equations: ClassVar[PartEquations | None] = None
    #: True for a part the splitting integrators take: its equations kick and it
    #: moves no mass (its momentum is fixed in the body between kicks). Set from
    #: ``equations``.
    splittable: ClassVar[bool] = False
    #: True for a part that may make a gyrostat (a rotor without a motor: its
    #: momentum along a body-fixed principal axis is constant), whose free
    #: motion the exact integrator solves (:attr:`~tumble.parts.InternalPart.gyrostatic_axis`).
    gyrostatic: ClassVar[bool] = False
    #: The index of its value that is its spin rate relative to the body (rad/s)
    #: about a body-fixed axis (a wheel's), or None: what ``rotor_speed`` reads.
    spin: ClassVar[int | None] = None
    #: True for a part that takes a share of the torque models acting through
    #: the body's rotors (``actuator="rotors"``).
    actuated: ClassVar[bool] = False
    #: None, or why a body may carry only one part of this kind.
    one_per_body: ClassVar[str | None] = None
    #: None, or why it needs a free body (no pivot).
    free_body_only: ClassVar[str | None] = None
    #: None, or why batches of bodies (given by their inertia alone) do not take it.
    not_in_batches: ClassVar[str | None] = None
    #: The theory checks (names in :data:`tumble.checks.THEORY_CHECKS`) whose closed
    #: forms hold with parts of this kind on the body: a check asks the kind
    #: (:meth:`tumble.checks.Case.parts_for`), never its name.
    closed_forms: ClassVar[frozenset[str]] = frozenset()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        equations = cls.equations
        cls.splittable = bool(
            equations is not None and equations.kick is not None and equations.inertia is None
        )

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
        """The part as JSON-ready SI values (with ``type``), to write beside a
        trajectory; :meth:`~tumble.parts.InternalPart.from_description` reads it
        back. By default the values of its
        :attr:`~tumble.parts.InternalPart.parameters` (arrays as lists,
        infinities as None)."""
        values: dict[str, Any] = {"type": self.kind}
        for parameter in self.parameters:
            value = getattr(self, parameter.name)
            if isinstance(value, np.ndarray):
                value = value.tolist()
            elif isinstance(value, float) and math.isinf(value):
                value = None
            values[parameter.name] = value
        return values

    @classmethod
    def from_description(cls, values: dict[str, Any]) -> InternalPart:
        """The part from the dictionary of
        :meth:`~tumble.parts.InternalPart.describe`, less its ``type``."""
        return cls(**values)

    @classmethod
    def keys_in_files(cls) -> tuple[Parameter, ...]:
        """The keys of its tables in files:
        :attr:`~tumble.parts.InternalPart.file_keys`, or its parameters and
        ``position``."""
        if cls.file_keys:
            return cls.file_keys
        where = Parameter("position", "length", (3,), "where it is drawn, body coordinates")
        return (*cls.parameters, where)

    @classmethod
    def from_table(cls, values: dict[str, Any]) -> FilePart:
        """The part from a table of a scenario file, its values converted to SI
        (:meth:`~tumble.parts.InternalPart.keys_in_files`), with what tumble adds
        to the body for it. By default the values are the constructor's (``position`` places its
        drawing), each of its parameters without a default required.

        Raises
        ------
        TableKeyError
            A value wrong or missing, about one key.
        InputError
            A value the part refuses.
        """
        values = dict(values)
        position = values.pop("position", None)
        for parameter in cls.parameters:
            if parameter.name not in values and parameter.name in _required_fields(cls):
                raise TableKeyError(
                    parameter.name,
                    f"Expected `{parameter.name}` ({parameter.description}) for a {cls.kind}, "
                    "which is missing.",
                )
        return FilePart(cls(**values), position=position)

    # ------------------------------------------------------------ for the kernels
    def pack(self, frame: Any, parts: tuple[InternalPart, ...]) -> list[Any]:
        """The rows its compiled equations read (:mod:`tumble.core.parts`), each a
        number or an (N,) array (one value per body of a batch), in the kernels'
        frame: ``frame`` is the body (:class:`tumble.body.RigidBody`) or the
        bodies (:class:`tumble.body.BodyBatch`), whose ``to_principal`` turns body
        vectors (3,) into its principal platform axes ((3,) or (N, 3)); ``parts``
        all the parts of the body, itself included (:class:`~tumble.parts.Siblings`: a rotor's
        share of a torque depends on its siblings, computed once for all)."""
        raise NotImplementedError

    def to_kernel(self, momenta: Array, frame: Any) -> Array:
        """Its momenta (..., size) (:meth:`~tumble.parts.InternalPart.momenta`, body
        axes) in the kernels' frame (the same for scalars; vectors turned by
        ``frame.to_principal``)."""
        return momenta

    def from_kernel(self, block: Array, frame: Any) -> Array:
        """Its momenta (n, size) in body axes from the kernels' frame (the inverse
        of :meth:`~tumble.parts.InternalPart.to_kernel`)."""
        return block

    def switch_times(self) -> Array:
        """The times (s) at which its inputs switch (a motor's schedule): an
        adaptive integration ends its steps there."""
        return np.zeros(0)

    @property
    def gyrostatic_axis(self) -> Array | None:
        """For a part that may make a gyrostat
        (:attr:`~tumble.parts.InternalPart.gyrostatic`), the unit axis (body axes)
        along which its momentum is constant in free motion; None when it is not
        constant (a motor drives it)."""
        return None

    def drawing(
        self,
        reach: float,
        centre: Array,
        position: Any = None,
        radius: float | None = None,
        thickness: float | None = None,
    ) -> PartDrawing | None:
        """How to draw it in a body of size ``reach`` (m) whose centre of mass is
        at ``centre`` (body coordinates, m), at ``position`` and of ``radius`` and
        ``thickness`` when the file gave them; None for a part not drawn."""
        return None

    def internal_rates(self, platform_inertia: Array) -> tuple[float, float]:
        """How fast its own motion relative to the body goes, 1/s, on a body whose
        platform inertia is ``platform_inertia`` ((3, 3), kg·m², body axes): the
        rate at which it relaxes or oscillates by itself, and the rate at which it
        pulls the platform along. (0, 0) for a part with no stiffness or damping
        of its own. :func:`~tumble.parts.internal_rate` combines the parts' rates."""
        return 0.0, 0.0

    @property
    def driven(self) -> bool:
        """True when a motor acts on it: the body's energy is then not conserved."""
        return False

    @property
    def idle(self) -> bool:
        """True when nothing but a torque through the parts (``actuator="rotors"``)
        changes its state: its kick then leaves it as it is
        (:attr:`tumble.core.parts.PartEquations.idle`). False unless a kind says so."""
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
