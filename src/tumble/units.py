"""Units at the public edge: one pint registry and the parsing of quantities.

Public functions accept plain numbers (taken as SI), pint quantities, or strings
such as ``"250 g"``, ``"3000 rpm"`` or ``"30 deg"``; they convert once, on entry,
to SI float64 with :func:`to_si` / :func:`vector_to_si`, and work in SI inside.
"""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Sequence
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError


def _import_pint() -> ModuleType:
    """pint, imported without its support for dask arrays unless dask is imported
    already. When dask is installed, pint imports ``dask.base`` on import
    (0.13 s, a quarter of ``tumble inertia``), only so that quantities can wrap
    dask arrays, which tumble never makes; a ``None`` entry in ``sys.modules``
    makes pint find no dask, and is removed at once, so dask imports as usual
    afterwards (tumble's sweeps on Dask clusters)."""
    if "pint" not in sys.modules and "dask" not in sys.modules:
        sys.modules["dask"] = None  # type: ignore[assignment]
        try:
            import pint
        finally:
            del sys.modules["dask"]
    import pint

    return pint


if TYPE_CHECKING:
    import pint
else:
    pint = _import_pint()

__all__ = ["SI_UNITS", "length_scale", "to_si", "unit_vector", "ureg", "vector_to_si"]


def _registry() -> pint.UnitRegistry:
    """pint's default registry, its parsed definitions cached in the user's cache
    folder (0.06 s to build instead of 0.5 s); without a writable cache, uncached."""
    try:
        return pint.UnitRegistry(cache_folder=":auto:")
    except OSError:
        return pint.UnitRegistry()


#: The registry every quantity in tumble belongs to.
ureg: pint.UnitRegistry = _registry()

#: Physical kinds of value and the SI unit each is converted to (and shown in messages).
SI_UNITS: dict[str, str] = {
    "mass": "kg",
    "length": "m",
    "angle": "rad",
    "angular_velocity": "rad/s",
    "angular_acceleration": "rad/s^2",
    "time": "s",
    "density": "kg/m^3",
    "inertia": "kg*m^2",
    "angular_momentum": "kg*m^2/s",
    "torque": "N*m",
    "damping": "N*m*s",
    "stiffness": "N/m",
    "linear_damping": "N*s/m",
    "acceleration": "m/s^2",
    "dimensionless": "",
}


#: Powers that pint would evaluate at length (``9**9**9``) or overflow (``10**400``).
_RUNAWAY_POWER = re.compile(r"(\*\*|\^)\s*\(?\s*[-+]?\d{3,}|(\*\*|\^)\s*[\d.]+\s*(\*\*|\^)")
_MAX_TEXT = 200


def _parse(value: Any, name: str) -> Any:
    """Turn a string into a pint quantity; leave other values alone."""
    if isinstance(value, str):
        if len(value) > _MAX_TEXT or _RUNAWAY_POWER.search(value):
            raise InputError(
                f"Expected `{name}` to be a number or a quantity such as '250 g', got "
                f"{value[:60]!r}{'...' if len(value) > 60 else ''} (too long or a runaway power)."
            )
        try:
            quantity: Any = ureg.Quantity(value)
        except Exception as exc:  # pint's parser raises many kinds (tokenize, zero division, ...)
            raise InputError(
                f"Expected `{name}` to be a number or a quantity such as "
                f"'250 g', got {value!r} ({type(exc).__name__}: {exc})."
            ) from None
        # A bare number in a string ("0.25") is SI, like a bare float; "50 %" or
        # "5 cm/m" are not bare numbers and go through the dimension check.
        return quantity.magnitude if quantity.units == ureg.dimensionless else quantity
    return value


def _quantity_to_si(value: Any, kind: str, name: str) -> Any:
    """Magnitude of a pint quantity in SI units of ``kind``; checks the dimensions."""
    si_unit = SI_UNITS[kind]
    if kind == "angular_velocity" and "hertz" in str(value.units):
        # pint takes Hz as 1/s, which would read 1 Hz as 1 rad/s: off by 2π.
        raise InputError(
            f"Expected `{name}` in rad/s, rpm or turn/s, got {value} (hertz is ambiguous for "
            "an angular velocity: write '1 turn/s' for 2π rad/s, or 'rad/s')."
        )
    expected = ureg.Quantity(1, si_unit) if si_unit else ureg.Quantity(1)
    if value.dimensionality != expected.dimensionality:
        shown = f"{value:~P}" if np.ndim(value.magnitude) == 0 else str(value)
        what = kind.replace("_", " ")
        unit = f" in {si_unit}" if si_unit else ""
        raise InputError(
            f"Expected `{name}` to be {_article(what)} {what}{unit}, got {shown} "
            f"(dimensions {value.dimensionality or 'dimensionless'})."
        )
    return value.to(si_unit).magnitude if si_unit else value.to("").magnitude


def _article(word: str) -> str:
    return "an" if word[:1] in "aeiou" else "a"


def to_si(value: Any, kind: str, name: str) -> float:
    """Convert one scalar to an SI float.

    Parameters
    ----------
    value : number (taken as SI), pint quantity, or string such as ``"250 g"``.
    kind : a key of :data:`SI_UNITS` ("mass", "length", "angle", ...).
    name : the argument's name, used in error messages.

    Raises
    ------
    InputError
        If the value is not a scalar, cannot be parsed, has the wrong dimensions,
        or is NaN or infinite.

    Examples
    --------
    >>> from tumble.units import to_si, ureg
    >>> print(f"{to_si('3000 rpm', 'angular_velocity', 'spin_rate'):.6f} rad/s")  # 100π
    314.159265 rad/s
    >>> to_si("250 g", "mass", "mass"), to_si(1.5, "length", "radius")
    (0.25, 1.5)
    >>> print(f"{to_si(ureg.Quantity(30, 'deg'), 'angle', 'tilt'):.6f} rad")
    0.523599 rad
    >>> to_si("3 kg", "length", "radius")
    Traceback (most recent call last):
        ...
    tumble.errors.InputError: Expected `radius` to be a length in m, got 3 kg (dimensions [mass]).
    """
    value = _parse(value, name)
    if isinstance(value, pint.Quantity):
        value = _quantity_to_si(value, kind, name)
    try:
        scalar = np.ndim(value) == 0
    except ValueError:  # numpy refuses ragged nestings such as [[1], {}, 2]
        scalar = False
    if isinstance(value, bool | np.bool_) or not scalar:
        raise InputError(f"Expected `{name}` to be a scalar, got {value!r}.")
    if np.iscomplexobj(value):
        raise InputError(f"Expected `{name}` to be a real number, got {value!r}.")
    try:
        result = float(value)
    except (TypeError, ValueError):
        raise InputError(
            f"Expected `{name}` to be a number or a quantity such as '250 g', got {value!r}."
        ) from None
    except OverflowError:  # an integer beyond float range (TOML and Python allow them)
        given = f"an integer of {len(str(abs(value)))} digits" if isinstance(value, int) else value
        raise InputError(
            f"Expected `{name}` to be within float range (|x| < 1.8e308), got {given}."
        ) from None
    if not math.isfinite(result):
        raise InputError(f"Expected `{name}` to be finite, got {result}.")
    return result


def vector_to_si(
    value: Any, kind: str, name: str, shape: tuple[int, ...] = (3,)
) -> NDArray[np.float64]:
    """Convert an array-like of quantities to an SI float64 array of a given shape.

    Accepts a numpy array or sequence of numbers (SI), a pint quantity array,
    a sequence whose elements are numbers, quantities or strings, or a single
    string of comma-separated values with an optional common unit at the end
    (``"10, 20, 30 cm"``). A ``-1`` in ``shape`` matches any length.

    Raises
    ------
    InputError
        On wrong shape, wrong dimensions, or NaN / inf entries.

    Examples
    --------
    >>> from tumble.units import vector_to_si
    >>> vector_to_si("10, 20, 30 cm", "length", "size").round(6).tolist()
    [0.1, 0.2, 0.3]
    >>> vector_to_si(["1 ft", 0.5, "2 in"], "length", "point").round(4).tolist()
    [0.3048, 0.5, 0.0508]
    >>> vector_to_si([[1, 0, 0], [0, 1, 0]], "length", "positions", (-1, 3)).shape
    (2, 3)
    """
    value = _parse_vector_string(value, name) if isinstance(value, str) else value
    if isinstance(value, pint.Quantity):
        array = np.asarray(_quantity_to_si(value, kind, name), dtype=float)
    elif isinstance(value, np.ndarray) and value.dtype != object:
        if value.dtype.kind not in "iuf":
            raise InputError(
                f"Expected `{name}` to hold real numbers, got an array of dtype {value.dtype}."
            )
        array = np.asarray(value, dtype=float)
    elif isinstance(value, Sequence | np.ndarray):
        array = _nested_to_si(value, kind, name)
    else:
        raise InputError(
            f"Expected `{name}` to be an array of shape {_shape_text(shape)}, got {value!r}."
        )
    if array.ndim != len(shape) or any(
        s != -1 and s != a for s, a in zip(shape, array.shape, strict=True)
    ):
        raise InputError(
            f"Expected `{name}` to have shape {_shape_text(shape)}, got {array.shape}."
        )
    if not np.all(np.isfinite(array)):
        raise InputError(f"Expected `{name}` to be finite, got {array.tolist()}.")
    return array


def _nested_to_si(value: Any, kind: str, name: str) -> NDArray[np.float64]:
    """Element-wise conversion of nested sequences that may mix numbers and quantities."""
    if isinstance(value, str) and "," in value:  # a row written as one string: "1, 2, 3 mm"
        value = _parse_vector_string(value, name)
        if isinstance(value, pint.Quantity):
            return np.asarray(_quantity_to_si(value, kind, name), dtype=float)
    if isinstance(value, Sequence | np.ndarray) and not isinstance(value, str):
        items = [_nested_to_si(v, kind, name) for v in value]
        if len({item.shape for item in items}) > 1:
            raise InputError(f"Expected `{name}` to be a rectangular array, got {value!r}.")
        return np.array(items, dtype=float)
    return np.asarray(to_si(value, kind, name), dtype=float)


def _parse_vector_string(text: str, name: str) -> Any:
    """Parse ``"1, 2, 3 mm"`` or ``"1 mm, 2 mm, 3 mm"`` or ``"(1, 2, 3)"``."""
    parts = [p.strip() for p in text.strip().strip("()[]").split(",")]
    if len(parts) < 2:
        raise InputError(
            f"Expected `{name}` to be comma-separated values such as '10, 20, 30 mm', got {text!r}."
        )
    # A unit written once, after the last number, applies to all of them.
    last = _parse(parts[-1], name)
    head = [_parse(p, name) for p in parts[:-1]]
    with_units = [isinstance(h, pint.Quantity) for h in head]
    if isinstance(last, pint.Quantity) and not any(with_units):
        try:
            return ureg.Quantity(
                np.array([float(h) for h in head] + [float(last.magnitude)]), last.units
            )
        except (TypeError, ValueError):
            pass
    if isinstance(last, pint.Quantity) and not all(with_units):
        # "10, 20 cm, 30 cm": is the 10 in metres or centimetres? Refuse to guess.
        raise InputError(
            f"Expected `{name}` to have a unit on every value or one unit after the last, "
            f"got {text!r}."
        )
    return [*head, last]


def _shape_text(shape: tuple[int, ...]) -> str:
    return (
        "("
        + ", ".join("n" if s == -1 else str(s) for s in shape)
        + ("," if len(shape) == 1 else "")
        + ")"
    )


def length_scale(units: Any, name: str = "units") -> float:
    """Metres per file unit, e.g. ``length_scale("mm") == 0.001``.

    Raises
    ------
    InputError
        If ``units`` is not a length unit.
    """
    if isinstance(units, str):
        try:
            quantity = ureg.Quantity(1, units) if units.strip() else None
        except Exception:  # pint's parser raises many kinds ("{": TokenError, "\b": assert)
            quantity = None
        if quantity is None:
            raise InputError(
                f"Expected `{name}` to be a length unit such as 'mm' or 'inch', got {units!r}."
            )
        scale = to_si(quantity, "length", name)
    else:
        scale = to_si(units, "length", name)
    if scale <= 0:
        raise InputError(f"Expected `{name}` to be a positive length unit, got {units!r}.")
    return scale


def unit_vector(
    value: Any,
    name: str,
    *,
    owner: str = "",
    noun: str = "a non-zero vector",
    shape: tuple[int, ...] = (3,),
    floor: float = 0.0,
) -> NDArray[np.float64]:
    """``value`` (numbers of the given ``shape``) scaled to unit length, read-only.

    Raises
    ------
    InputError
        A vector of length at most ``floor`` or not finite: ``Expected `name` of a
        Owner to be a non-zero vector, got [...]``.
    """
    vector = vector_to_si(value, "dimensionless", name, shape)
    size = float(np.linalg.norm(vector))
    if not size > floor or not math.isfinite(size):
        whose = f" of a {owner}" if owner else ""
        raise InputError(f"Expected `{name}`{whose} to be {noun}, got {vector.tolist()}.")
    unit = vector / size
    unit.flags.writeable = False
    return unit
