"""Numbers in a URDF as its two main readers read them.

urdfdom (ROS's reference parser) reads each number with a C-locale stream that
must take the whole text; PyBullet reads each piece with C's ``atof``, which
takes the longest number at the start and ignores the rest. The URDF reader
takes urdfdom's reading, and PyBullet's where that is what the file meant.
"""

from __future__ import annotations

import math
import re

__all__ = ["atof", "last_digit", "pybullet_numbers", "shown_numbers", "urdf_number", "urdf_numbers"]

#: A number as urdfdom reads it: a C-locale stream that must take the whole text
#: (ASCII digits only, no underscores, no "inf" or "nan", no trailing spaces).
_URDFDOM_NUMBER = re.compile(r"[ \t\n\v\f\r]*[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")

#: What C's ``atof`` reads at the start of a text (PyBullet's reading of each
#: number): the longest such prefix, 0 where there is none.
_ATOF_PREFIX = _URDFDOM_NUMBER

#: What may follow a number in a list that PyBullet still reads as meant: the
#: commas of ``"0.07, 0, -0.69"``.
_SEPARATORS = ","


def urdf_number(text: str) -> float | None:
    """``text`` as urdfdom reads a number, or None where urdfdom refuses it (or it
    is not finite)."""
    if _URDFDOM_NUMBER.fullmatch(text) is None:
        return None
    value = float(text)
    return value if math.isfinite(value) else None


def urdf_numbers(text: str, count: int) -> tuple[float, ...] | None:
    """``text`` as urdfdom reads ``count`` numbers (split at spaces), or None."""
    if count == 1:
        value = urdf_number(text)
        return None if value is None else (value,)
    values = [urdf_number(piece) for piece in text.split(" ") if piece]
    if len(values) != count or any(value is None for value in values):
        return None
    return tuple(values)  # type: ignore[arg-type]


def atof(text: str) -> tuple[float, bool]:
    """C's ``atof`` of ``text`` and whether it read all of it (but a trailing comma)."""
    match = _ATOF_PREFIX.match(text)
    if match is None or not match.group().strip():
        return 0.0, False
    value = float(match.group())
    rest = text[match.end() :]
    return value, math.isfinite(value) and rest.strip(_SEPARATORS) == ""


def pybullet_numbers(text: str, count: int) -> tuple[tuple[float, ...] | None, bool]:
    """``text`` as PyBullet's URDF parser reads ``count`` numbers (pieces split at
    spaces, each read by ``atof``, the first ``count`` taken; a single number
    for a vector is refused), and whether that reading is what was meant (every
    piece a number, but for commas)."""
    if count == 1:
        value, whole = atof(text)
        return (value,), whole
    read = [atof(piece) for piece in text.split(" ") if piece]
    if len(read) < count:
        return None, False
    return tuple(value for value, _ in read[:count]), all(whole for _, whole in read)


def shown_numbers(values: tuple[float, ...]) -> str:
    """``values`` as a message shows them: each with ``%g``, separated by spaces."""
    return " ".join(f"{value:g}" for value in values)


def last_digit(text: str) -> float:
    """The value of one unit in the last digit of a number as written (0.01 for
    ``"1.57"``, 1e-5 for ``"1e-5"``); 0 for text that is not a number."""
    match = re.fullmatch(r"\s*[+-]?[0-9]*(?:\.([0-9]*))?(?:[eE]([+-]?[0-9]+))?\s*", text)
    if match is None:
        return 0.0
    decimals = len(match.group(1) or "")
    exponent = int(match.group(2) or 0)
    try:
        return float(10.0 ** (exponent - decimals))
    except OverflowError:  # "1e400": no limit a float64 can pass
        return math.inf
