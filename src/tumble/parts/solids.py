"""Parts given in files by their size: a part of ``inertia`` J is already in
``[body]`` (tumble's convention: the body's mass properties hold every part, as
if locked), a part of ``mass`` and ``radius`` is a uniform solid that tumble
adds to the body at ``position``. Shared by the wheels and the spheres."""

from __future__ import annotations

import math
from typing import Any

from tumble.errors import InputError
from tumble.parameters import Parameter
from tumble.parts.base import TableKeyError

__all__ = ["SIZE_KEYS", "moment_from_table", "required"]

#: The keys of a part given by its size: its moment, or its mass and radius,
#: and its position.
SIZE_KEYS = (
    Parameter(
        "inertia", "inertia", (), "its moment of inertia J, already in [body]", 0.0, strict=True
    ),
    Parameter(
        "mass",
        "mass",
        (),
        "the mass of the uniform solid tumble adds to the body",
        0.0,
        strict=True,
    ),
    Parameter(
        "radius", "length", (), "the radius of the uniform solid tumble adds", 0.0, strict=True
    ),
    Parameter("position", "length", (3,), "its centre, body coordinates (default the origin)"),
)


def required(values: dict[str, Any], key: str, what: str) -> Any:
    """``values[key]``, or a TableKeyError saying what it is."""
    if values.get(key) is None:
        raise TableKeyError(key, f"Expected `{key}` ({what}), which is missing.")
    return values[key]


def moment_from_table(kind: str, values: dict[str, Any], factor: float) -> tuple[float, bool]:
    """The part's J (kg·m²) from a table's ``inertia``, or ``factor m r²`` from its
    ``mass`` and ``radius``; and whether it is a solid tumble adds.

    Raises
    ------
    TableKeyError
        Both or neither given, or one of mass and radius alone.
    InputError
        A moment beyond float64's range.
    """
    by_mass = values.get("mass") is not None or values.get("radius") is not None
    if (values.get("inertia") is not None) == by_mass:
        raise TableKeyError(
            "inertia",
            f"Expected either `inertia` (a {kind} already in [body]) or `mass` and `radius` "
            "(a uniform one tumble adds), got " + ("both." if by_mass else "neither."),
        )
    if not by_mass:
        return float(values["inertia"]), False
    for missing, other in (("mass", "radius"), ("radius", "mass")):
        if values.get(missing) is None:
            raise TableKeyError(missing, f"Expected `{missing}` with `{other}`, which is missing.")
    mass, radius = values["mass"], values["radius"]
    moment = factor * mass * radius * radius
    if not math.isfinite(moment):
        raise InputError(
            f"Expected a {kind} whose moment of inertia {factor} m r² is within float64's "
            f"range, got m = {mass:.6g} kg and r = {radius:.6g} m."
        )
    return moment, True
