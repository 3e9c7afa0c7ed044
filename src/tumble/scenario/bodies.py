"""The scenario file's ``[body]`` table: solids, meshes, point masses, given inertias,
assemblies of parts, each with a pose; orientations; and the converters of
quantities with units that every table uses.

Quantities are numbers (SI) or strings with units (``"250 g"``,
``"0, 0, -10 cm"``), converted to SI floats on validation with
:mod:`tumble.units`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any

import numpy as np
from pydantic import (
    BaseModel,
    BeforeValidator,
    Discriminator,
    Field,
    Tag,
    ValidationInfo,
    model_validator,
)

from tumble.config import StrictModel, key_error
from tumble.errors import InputError, unknown_choice
from tumble.units import to_si, vector_to_si

if TYPE_CHECKING:
    from tumble.massprops import MassProperties

__all__ = [
    "Angle",
    "AngularVelocity",
    "Attitude",
    "Body",
    "InertiaBody",
    "Length",
    "LengthVector",
    "Mass",
    "MeshBody",
    "PartsBody",
    "PointsBody",
    "ShapeBody",
    "Time",
    "Vector",
    "key_path",
    "scalar_field",
    "vector_field",
]

Vector = tuple[float, float, float]


# ------------------------------------------------------------ converters
def _name(info: ValidationInfo) -> str:
    return info.field_name or "value"


def scalar_field(kind: str, positive: bool = False, non_negative: bool = False) -> Any:
    unit = {"mass": "kg", "length": "m", "time": "s", "density": "kg/m^3", "inertia": "kg·m²"}.get(
        kind, ""
    )

    def convert(value: Any, info: ValidationInfo) -> float:
        result = to_si(value, kind, _name(info))
        if positive and not result > 0:
            raise InputError(
                f"Expected `{_name(info)}` > 0 {unit}, got {result!r}.".replace(" ,", ",")
            )
        if non_negative and result < 0:
            raise InputError(f"Expected `{_name(info)}` >= 0 {unit}, got {result!r}.")
        return result

    return BeforeValidator(convert)


def vector_field(kind: str, shape: tuple[int, ...] = (3,), positive: bool = False) -> Any:
    def convert(value: Any, info: ValidationInfo) -> tuple[Any, ...]:
        array = vector_to_si(value, kind, _name(info), shape)
        if positive and np.any(array <= 0):
            raise InputError(f"Expected every entry of `{_name(info)}` > 0, got {array.tolist()}.")
        return tuple(array.tolist())

    return BeforeValidator(convert)


Mass = Annotated[float, scalar_field("mass", positive=True)]
Length = Annotated[float, scalar_field("length", positive=True)]
Time = Annotated[float, scalar_field("time", positive=True)]
Angle = Annotated[float, scalar_field("angle")]
AngularVelocity = Annotated[float, scalar_field("angular_velocity")]
LengthVector = Annotated[Vector, vector_field("length")]
PositiveLengths = Annotated[Vector, vector_field("length", positive=True)]
Angles = Annotated[Vector, vector_field("angle")]


# ------------------------------------------------------------ attitude
class Attitude(StrictModel):
    """An orientation, body → space (or part → assembly): exactly one of

    * ``euler_zxz = "φ, θ, ψ deg"`` — z-x-z Euler angles (precession, nutation,
      spin): ``R = Rz(φ) Rx(θ) Rz(ψ)``;
    * ``axis = [x, y, z]`` with ``angle = "90 deg"`` — a rotation about an axis;
    * ``quaternion = [w, x, y, z]`` — scalar first (normalised here).
    """

    euler_zxz: Angles | None = None
    axis: Annotated[Vector, vector_field("dimensionless")] | None = None
    angle: Angle | None = None
    quaternion: (
        Annotated[tuple[float, float, float, float], vector_field("dimensionless", (4,))] | None
    ) = None

    @model_validator(mode="after")
    def _one_form(self) -> Attitude:
        forms = [
            name
            for name, given in (
                ("euler_zxz", self.euler_zxz is not None),
                ("axis", self.axis is not None or self.angle is not None),
                ("quaternion", self.quaternion is not None),
            )
            if given
        ]
        if len(forms) != 1:
            raise ValueError(
                "Expected exactly one of `euler_zxz`, `axis` with `angle`, or `quaternion`, got "
                + (" and ".join(f"`{f}`" for f in forms) if forms else "none")
                + "."
            )
        if forms == ["axis"]:
            if self.axis is None or self.angle is None:
                raise ValueError("Expected both `axis` and `angle` for an axis-angle attitude.")
            if not _length(self.axis) > 0:
                raise ValueError(f"Expected `axis` to be a non-zero vector, got {list(self.axis)}.")
        if self.quaternion is not None and not _length(self.quaternion) > 1e-12:
            raise ValueError(
                f"Expected `quaternion` to be non-zero [w, x, y, z], got {list(self.quaternion)}."
            )
        return self

    def quaternion_wxyz(self) -> tuple[float, float, float, float]:
        """The unit quaternion ``[w, x, y, z]``."""
        from scipy.spatial.transform import Rotation

        if self.euler_zxz is not None:
            rotation = Rotation.from_euler("ZXZ", self.euler_zxz)
        elif self.quaternion is not None:
            rotation = Rotation.from_quat(_unit(self.quaternion), scalar_first=True)
        else:
            assert self.axis is not None and self.angle is not None  # checked above
            # [cos θ/2, sin θ/2 n], as Rotation.from_rotvec(θ n) gives, without the
            # product θ n, whose length overflows for an angle of 1e300 rad.
            half = 0.5 * self.angle
            q = np.array([np.cos(half), *(np.sin(half) * _unit(self.axis))])
            rotation = Rotation.from_quat(q, scalar_first=True)
        q = rotation.as_quat(scalar_first=True)
        return (float(q[0]), float(q[1]), float(q[2]), float(q[3]))


def _length(vector: Any) -> float:
    """The Euclidean length of ``vector``, without the overflow or underflow of squaring
    entries near 1e±200."""
    array = np.asarray(vector, dtype=float)
    largest = float(np.max(np.abs(array)))
    return largest * float(np.linalg.norm(array / largest)) if largest > 0 else 0.0


def _unit(vector: Any) -> Any:
    """``vector`` (non-zero) scaled to unit length, as :func:`_length` measures it."""
    array = np.asarray(vector, dtype=float)
    array = array / np.max(np.abs(array))
    return array / np.linalg.norm(array)


# ------------------------------------------------------------ bodies
class _Placed(StrictModel):
    """A body that may be moved: first rotated about its origin, then translated."""

    translation: LengthVector | None = None
    rotation: Attitude | None = None


class ShapeBody(_Placed):
    """A closed-form solid from :mod:`tumble.shapes`: ``shape``, ``mass`` and its
    dimensions (those of its kind in :data:`tumble.shapes.SHAPE_KINDS`; the fields
    below are every dimension of the catalogue, a test holds them to it)."""

    shape: str
    mass: Mass
    radius: Length | None = None
    inner_radius: Length | None = None
    outer_radius: Length | None = None
    height: Length | None = None
    length: Length | None = None
    size: PositiveLengths | None = None
    semi_axes: PositiveLengths | None = None
    major_radius: Length | None = None
    minor_radius: Length | None = None
    cylinder_height: Length | None = None
    edge: Length | None = None

    @model_validator(mode="after")
    def _dimensions(self) -> ShapeBody:
        from tumble.shapes import SHAPE_KINDS

        name = self.shape.lower().replace("_", "-")
        if name not in SHAPE_KINDS:
            raise key_error("shape", str(unknown_choice(self.shape, SHAPE_KINDS, "`shape`")))
        needed = SHAPE_KINDS[name].dimensions
        every = {n for kind in SHAPE_KINDS.values() for n in kind.dimensions}
        given = {n for n in every if getattr(self, n) is not None}
        extra = sorted(given - set(needed))
        if extra:
            raise key_error(
                extra[0],
                f"Expected only {', '.join(f'`{n}`' for n in needed)} for a {name}, "
                f"got `{extra[0]}`.",
            )
        missing = [n for n in needed if n not in given]
        if missing:
            raise key_error(
                missing[0],
                f"Expected {', '.join(f'`{n}`' for n in missing)} for a {name} "
                f"(it takes `mass`, {', '.join(f'`{n}`' for n in needed)}).",
            )
        object.__setattr__(self, "shape", name)
        return self

    def dimensions(self) -> dict[str, Any]:
        """Its dimensions by name (SI), those its kind takes."""
        from tumble.shapes import SHAPE_KINDS

        return {n: getattr(self, n) for n in SHAPE_KINDS[self.shape].dimensions}

    def solid(self) -> MassProperties:
        """The solid at its mass, about its centre of mass (before it is placed).

        Raises
        ------
        InputError
            Dimensions its closed form refuses.
        """
        from tumble.shapes import SHAPE_KINDS

        return SHAPE_KINDS[self.shape].function(self.mass, **self.dimensions())


class MeshBody(_Placed):
    """A closed triangle mesh file (path relative to the scenario file) of uniform
    density, or its surface as a shell (``shell_thickness``)."""

    mesh: str
    units: str | None = None
    density: Annotated[float, scalar_field("density", positive=True)] | None = None
    mass: Mass | None = None
    merge_tolerance: Annotated[float, scalar_field("length", non_negative=True)] | None = None
    shell_thickness: Annotated[float, scalar_field("length", positive=True)] | None = None

    @model_validator(mode="after")
    def _one_of(self) -> MeshBody:
        if (self.density is None) == (self.mass is None):
            raise ValueError(
                "Expected exactly one of `density` and `mass` for a mesh, got "
                + ("both." if self.density is not None else "neither.")
            )
        return self


class PointsBody(_Placed):
    """Point masses rigidly joined: ``masses`` (n,) and ``positions`` (n, 3)."""

    masses: Annotated[tuple[float, ...], vector_field("mass", (-1,), positive=True)]
    positions: Annotated[tuple[Vector, ...], vector_field("length", (-1, 3))]

    @model_validator(mode="after")
    def _same_length(self) -> PointsBody:
        if len(self.masses) != len(self.positions):
            raise ValueError(
                f"Expected as many `positions` as `masses` ({len(self.masses)}), "
                f"got {len(self.positions)}."
            )
        return self


class InertiaBody(_Placed):
    """Mass properties given directly: ``mass``, ``center_of_mass`` and ``inertia``, a
    (3, 3) tensor about the centre of mass or its three principal moments (diagonal)."""

    mass: Mass
    center_of_mass: LengthVector = (0.0, 0.0, 0.0)
    inertia: Any

    @model_validator(mode="after")
    def _tensor(self) -> InertiaBody:
        value = self.inertia
        if isinstance(value, str) or (isinstance(value, list | tuple) and np.ndim(value) == 1):
            moments = vector_to_si(value, "inertia", "inertia", (3,))
            tensor = np.diag(moments)
        else:
            tensor = vector_to_si(value, "inertia", "inertia", (3, 3))
        object.__setattr__(self, "inertia", tuple(map(tuple, tensor.tolist())))
        return self


_TAGS = {
    "shape": "shape",
    "mesh": "mesh",
    "masses": "points",
    "inertia": "inertia",
    "parts": "parts",
}


def _body_tag(value: Any) -> str | None:
    if isinstance(value, BaseModel):
        return {
            ShapeBody: "shape",
            MeshBody: "mesh",
            PointsBody: "points",
            InertiaBody: "inertia",
        }.get(type(value), "parts")
    if not isinstance(value, dict):
        return None
    present = [tag for key, tag in _TAGS.items() if key in value]
    if len(present) > 1:
        return "ambiguous"
    return present[0] if present else None


class _Ambiguous(StrictModel):
    @model_validator(mode="before")
    @classmethod
    def _refuse(cls, data: Any) -> Any:
        present = [k for k in ("shape", "mesh", "masses", "inertia", "parts") if k in data]
        raise ValueError(
            "Expected one kind of body (`shape`, `mesh`, `masses`, `inertia` or `parts`), got "
            + " and ".join(f"`{k}`" for k in present)
            + "."
        )


_BODY_ERROR = (
    "Expected a body: `shape` (a solid), `mesh` (a file), `masses` and `positions` "
    "(point masses), `inertia` (given directly) or `parts` (an assembly)."
)

LeafBody = Annotated[
    Annotated[ShapeBody, Tag("shape")]
    | Annotated[MeshBody, Tag("mesh")]
    | Annotated[PointsBody, Tag("points")]
    | Annotated[InertiaBody, Tag("inertia")]
    | Annotated[_Ambiguous, Tag("ambiguous")],
    Discriminator(_body_tag, custom_error_type="body_kind", custom_error_message=_BODY_ERROR),
]


class PartsBody(_Placed):
    """An assembly: ``[[body.parts]]``, each a body with an optional pose
    (``translation``, ``rotation``) in the assembly's coordinates."""

    parts: Annotated[list[LeafBody], Field(min_length=1)]


Body = Annotated[
    Annotated[ShapeBody, Tag("shape")]
    | Annotated[MeshBody, Tag("mesh")]
    | Annotated[PointsBody, Tag("points")]
    | Annotated[InertiaBody, Tag("inertia")]
    | Annotated[PartsBody, Tag("parts")]
    | Annotated[_Ambiguous, Tag("ambiguous")],
    Discriminator(_body_tag, custom_error_type="body_kind", custom_error_message=_BODY_ERROR),
]

_BODY_TAGS = {*_TAGS.values(), "ambiguous"}


def key_path(loc: tuple[Any, ...]) -> list[Any]:
    """The key path of the file from pydantic's location of an error: without the tags
    of the body's union (after ``body``, or after a part's index), which no file writes."""
    path: list[Any] = []
    for k, part in enumerate(loc):
        after_body = k == 1 and loc[0] == "body"
        after_part = k >= 2 and isinstance(loc[k - 1], int) and loc[k - 2] == "parts"
        if (after_body or after_part) and part in _BODY_TAGS:
            continue
        path.append(part)
    return path
