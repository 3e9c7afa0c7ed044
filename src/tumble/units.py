"""Units at the public edge: one pint registry and the parsing of quantities.

Public functions accept plain numbers (taken as SI), pint quantities, or strings
such as ``"250 g"``, ``"3000 rpm"`` or ``"30 deg"``; they convert once, on entry,
to SI float64 with :func:`to_si` / :func:`vector_to_si`, and work in SI inside.
"""

from __future__ import annotations

import io
import itertools
import math
import re
import sys
import tokenize
from collections.abc import Sequence
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, cut, quoted


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

__all__ = [
    "SI_UNITS",
    "length_scale",
    "quantity",
    "to_si",
    "unit_vector",
    "ureg",
    "vector_to_si",
]


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
    "unbalance": "kg*m",
    "acceleration": "m/s^2",
    "dimensionless": "",
}


#: Powers that pint would evaluate at length (``9**9**9``) or overflow (``10**400``).
_RUNAWAY_POWER = re.compile(r"(\*\*|\^)\s*\(?\s*[-+]?\d{3,}|(\*\*|\^)\s*[\d.]+\s*(\*\*|\^)")
_MAX_TEXT = 200

#: Signs people type that pint does not read, and what they mean: pint's tokenizer
#: would drop them ("−3 kg", with a Unicode minus, would be +3 kg).
_TYPOGRAPHY = str.maketrans({"−": "-", "×": "*", "·": "*", "⋅": "*"})

#: Characters of a number or a unit expression besides letters of any script
#: (µm, Å, Ω): those pint reads ("°", powers such as "m²"). Anything else pint's
#: tokenizer drops without a word ("3 🍕" would be 3, "3 ✓ cm" 3 cm, "3 = m" 3 m),
#: and pint drops commas as thousands separators ("3 m, 4" would be 12 m, "1,5 kg"
#: 15 kg): all are refused.
_EXPRESSION = frozenset("0123456789.+-*/^() _\t°⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def _checked_text(text: str, name: str) -> str:
    """``text`` with typographic signs made plain (every kind of space a space),
    refused where pint would read it otherwise than it is written: characters
    outside numbers and unit names, and a number that follows another, a unit
    or a closing parenthesis with no operator between ("3 4 m", "3..2 m",
    "3 m 4"), which pint multiplies.

    Raises
    ------
    InputError
        Naming the value and the character or number that cannot be read.
    """
    # No-break and narrow no-break spaces separate numbers from units in typeset
    # text (the SI brochure's own choice): read as spaces.
    plain = "".join(" " if c.isspace() else c for c in text.translate(_TYPOGRAPHY))
    prepared = plain
    for preprocess in ureg.preprocessors:  # "%" and "‰" to names
        prepared = preprocess(prepared)
    unknown = sorted({c for c in prepared if c not in _EXPRESSION and not c.isalpha()})
    if unknown:
        shown = ", ".join(repr(c) for c in unknown)
        hint = (
            " (one value, with a decimal point and no thousands separator)"
            if "," in unknown
            else ""
        )
        raise InputError(
            f"Expected `{name}` to be a number or a quantity such as '250 g', got "
            f"{quoted(text)}, which holds {shown}: not part of a number or a unit{hint}."
        )
    tokens = [token for token in _tokens(prepared) if token.string.strip()]
    for before, token in itertools.pairwise(tokens):
        if token.type != tokenize.NUMBER or (before.type == tokenize.OP and before.string != ")"):
            continue
        where = (
            f"the numbers {before.string} and {token.string} side by side"
            if before.type == tokenize.NUMBER
            else f"the number {token.string} after {before.string!r}"
        )
        raise InputError(
            f"Expected `{name}` to be a number or a quantity such as '250 g', got "
            f"{quoted(text)}, with {where} (pint would multiply them: write one number, or "
            "an operator between them)."
        )
    return plain


def _tokens(text: str) -> list[tokenize.TokenInfo]:
    """Python's tokens of one line of text, as pint reads them; none where the
    tokenizer gives up (pint then raises its own error, which is reported)."""
    try:
        return list(tokenize.generate_tokens(io.StringIO(text).readline))
    except (tokenize.TokenError, SyntaxError):
        return []


#: Why pint could not read a text, by the kind of its error.
_PARSE_FAILURES = {
    "TokenError": "unbalanced parentheses",
    "ZeroDivisionError": "a division by zero",
    "UndefinedUnitError": "an unknown unit",
    "DefinitionSyntaxError": "not a valid expression",
    "AssertionError": "not a valid expression",
    "OverflowError": "a number beyond float range",
}


def quantity(text: str, name: str) -> Any:
    """Parse ``text`` (``"250 g"``, ``"3000 rpm"``, ``"0.25"``) into a pint quantity
    of :data:`ureg`, exactly as written or not at all.

    pint alone drops what it does not understand and multiplies numbers written
    side by side; this refuses characters outside numbers and unit names (an
    emoji, ``#``, ``=``, a comma), and two numbers side by side. A Unicode minus,
    ``·`` and ``×`` are read as ``-`` and ``*``.

    Parameters
    ----------
    text : the value as typed.
    name : the argument's name, used in error messages.

    Raises
    ------
    InputError
        Naming the value and why it cannot be read.

    Examples
    --------
    >>> from tumble.units import quantity
    >>> print(quantity("−3 N·m", "torque"))
    -3 meter * newton
    >>> quantity("3 🍕", "radius")
    Traceback (most recent call last):
        ...
    tumble.errors.InputError: Expected `radius` ... got '3 🍕', which holds '🍕': not part ...
    """
    if len(text) > _MAX_TEXT or _RUNAWAY_POWER.search(text):
        raise InputError(
            f"Expected `{name}` to be a number or a quantity such as '250 g', got "
            f"{quoted(text)} (too long or a runaway power)."
        )
    plain = _checked_text(text, name)
    try:
        return ureg.Quantity(plain)
    except Exception as exc:  # pint's parser raises many kinds (tokenize, zero division, ...)
        kind = type(exc).__name__
        reason = _PARSE_FAILURES.get(kind, "not a valid expression")
        if kind == "UndefinedUnitError":  # "'furlongz' is not defined in the unit registry"
            reason = str(exc) or reason
        raise InputError(
            f"Expected `{name}` to be a number or a quantity such as '250 g', got "
            f"{quoted(text)} ({reason})."
        ) from None


def _parse(value: Any, name: str) -> Any:
    """Turn a string into a pint quantity; leave other values alone."""
    if isinstance(value, str):
        parsed = quantity(value, name)
        # A bare number in a string ("0.25") is SI, like a bare float; "50 %" or
        # "5 cm/m" are not bare numbers and go through the dimension check.
        return parsed.magnitude if parsed.units == ureg.dimensionless else parsed
    return value


def _quantity_to_si(value: Any, kind: str, name: str) -> Any:
    """Magnitude of a pint quantity in SI units of ``kind``; checks the dimensions."""
    si_unit = SI_UNITS[kind]
    if kind == "angular_velocity" and "hertz" in str(value.units):
        # pint takes Hz as 1/s, which would read 1 Hz as 1 rad/s: off by 2π.
        raise InputError(
            f"Expected `{name}` in rad/s, rpm or turn/s, got {cut(str(value))} (hertz is "
            "ambiguous for "
            "an angular velocity: write '1 turn/s' for 2π rad/s, or 'rad/s')."
        )
    expected = ureg.Quantity(1, si_unit) if si_unit else ureg.Quantity(1)
    if value.dimensionality != expected.dimensionality:
        shown = f"{value:~P}" if np.ndim(value.magnitude) == 0 else cut(str(value))
        what = "dimensionless number" if kind == "dimensionless" else kind.replace("_", " ")
        unit = f" in {si_unit}" if si_unit else ""
        raise InputError(
            f"Expected `{name}` to be {_article(what)} {what}{unit}, got {shown} "
            f"(dimensions {value.dimensionality or 'dimensionless'})."
        )
    return value.to(si_unit).magnitude if si_unit else value.to("").magnitude


def _not_finite(array: NDArray[np.float64]) -> str:
    """The values of an array that is not finite, as a message shows them: all of a
    small array, else the first value that is not finite, where, and how many."""
    if array.size <= 12:
        return str(array.tolist())
    bad = ~np.isfinite(array)
    where = tuple(int(i) for i in np.argwhere(bad)[0])
    return (
        f"{array[where]} at index {list(where)} ({int(bad.sum())} of its {array.size} values "
        "are NaN or infinite)"
    )


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
    if type(value) in _PLAIN_SCALARS:  # a plain number, SI already: no parsing
        result = _plain_float(value)
        if math.isfinite(result):
            return result
    typed = value
    value = _parse(value, name)
    if isinstance(value, pint.Quantity):
        value = _quantity_to_si(value, kind, name)
    try:
        scalar = np.ndim(value) == 0
    except ValueError:  # numpy refuses ragged nestings such as [[1], {}, 2]
        scalar = False
    if isinstance(value, bool | np.bool_) or not scalar:
        raise InputError(f"Expected `{name}` to be a scalar, got {quoted(value)}.")
    if np.iscomplexobj(value):
        raise InputError(f"Expected `{name}` to be a real number, got {quoted(value)}.")
    try:
        result = float(value)
    except (TypeError, ValueError):
        raise InputError(
            f"Expected `{name}` to be a number or a quantity such as '250 g', got {quoted(value)}."
        ) from None
    except OverflowError:  # an integer beyond float range (TOML and Python allow them)
        given = f"an integer of {len(str(abs(value)))} digits" if isinstance(value, int) else value
        raise InputError(
            f"Expected `{name}` to be within float range (|x| < 1.8e308), got {given}."
        ) from None
    if not math.isfinite(result):
        shown = f"{quoted(typed)} ({result})" if isinstance(typed, str) else f"{result}"
        raise InputError(f"Expected `{name}` to be finite, got {shown}.")
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
    array = _plain_vector(value) if len(shape) == 1 else None
    if array is not None and shape[0] in (-1, len(array)) and all(map(math.isfinite, value)):
        return array
    if array is None:
        array = _array_to_si(value, kind, name, shape)
    if array.ndim != len(shape) or any(
        s != -1 and s != a for s, a in zip(shape, array.shape, strict=True)
    ):
        raise InputError(
            f"Expected `{name}` to have shape {_shape_text(shape)}, got {array.shape}."
        )
    if not np.all(np.isfinite(array)):
        raise InputError(f"Expected `{name}` to be finite, got {_not_finite(array)}.")
    return array


def _array_to_si(value: Any, kind: str, name: str, shape: tuple[int, ...]) -> NDArray[np.float64]:
    """The general path of :func:`vector_to_si`: strings, quantities, arrays and
    nested sequences to a float64 array in SI (its shape not checked yet)."""
    value = _parse_vector_string(value, name) if isinstance(value, str) else value
    if isinstance(value, pint.Quantity):
        return np.asarray(_quantity_to_si(value, kind, name), dtype=float)
    if isinstance(value, np.ndarray) and value.dtype != object:
        if value.dtype.kind not in "iuf":
            raise InputError(
                f"Expected `{name}` to hold real numbers, got an array of dtype {value.dtype}."
            )
        return np.asarray(value, dtype=float)
    if isinstance(value, Sequence | np.ndarray):
        return _nested_to_si(value, kind, name)
    raise InputError(
        f"Expected `{name}` to be an array of shape {_shape_text(shape)}, got {quoted(value)}."
    )


#: The scalars taken as SI numbers without a look at units (not ``bool``: refused).
_PLAIN_SCALARS = frozenset({float, int, np.float64, np.int64})


def _plain_float(value: float | int) -> float:
    """``float(value)``, NaN for an integer beyond float range (which the general
    path then refuses with its message)."""
    try:
        return float(value)
    except OverflowError:
        return math.nan


def _plain_vector(value: Any) -> NDArray[np.float64] | None:
    """A list or tuple of plain numbers (:data:`_PLAIN_SCALARS`) as a float64 array,
    or None for anything else (strings, quantities, nestings, arrays): the fast path
    of :func:`vector_to_si` for the vectors most calls pass."""
    if type(value) not in (list, tuple) or not all(type(v) in _PLAIN_SCALARS for v in value):
        return None
    try:
        return np.array(value, dtype=float)
    except OverflowError:  # an integer beyond float range: the general path says so
        return None


def _nested_to_si(value: Any, kind: str, name: str) -> NDArray[np.float64]:
    """Element-wise conversion of nested sequences that may mix numbers and quantities."""
    if isinstance(value, str) and "," in value:  # a row written as one string: "1, 2, 3 mm"
        value = _parse_vector_string(value, name)
        if isinstance(value, pint.Quantity):
            return np.asarray(_quantity_to_si(value, kind, name), dtype=float)
    if isinstance(value, Sequence | np.ndarray) and not isinstance(value, str):
        items = [_nested_to_si(v, kind, name) for v in value]
        if len({item.shape for item in items}) > 1:
            raise InputError(f"Expected `{name}` to be a rectangular array, got {quoted(value)}.")
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
            unit = ureg.Quantity(1, _checked_text(units, name)) if units.strip() else None
        except Exception:  # pint's parser raises many kinds ("{": TokenError, "\b": assert)
            unit = None
        if unit is None:
            raise InputError(
                f"Expected `{name}` to be a length unit such as 'mm' or 'inch', got "
                f"{quoted(units)}."
            )
        scale = to_si(unit, "length", name)
    else:
        scale = to_si(units, "length", name)
    if scale <= 0:
        raise InputError(f"Expected `{name}` to be a positive length unit, got {quoted(units)}.")
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
