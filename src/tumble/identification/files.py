"""Gyroscope recordings read from files: :func:`read_recording`.

A recording is a table of sample times and the three rates of a gyroscope fixed
to the body, in the sensor's axes. Read are

* phyphox's exports: ``Time (s)``, ``Gyroscope x (rad/s)``, ``Gyroscope y
  (rad/s)``, ``Gyroscope z (rad/s)``, quoted or not, separated by commas, by
  semicolons with decimal commas, or by tabs; the zip file phyphox exports
  (its one table of data is read);
* any CSV file of the same shape, with or without a header row;
* Parquet files (a tumble trajectory's ``t, omega_x, omega_y, omega_z`` among
  them).

The columns are chosen by name or position, or found: a time column (a name
``t`` or starting with ``time``) and the three after it. The units are those
the header states (``rad/s``, ``deg/s``, ``°/s``; ``s``, ``ms``), else those
given, else told from the magnitude: a rate beyond 20 turns/s in rad/s is
beyond any throw by hand, so such values are read as deg/s, and the
recording's ``note`` says so. Checks of the samples themselves (enough of
them, finite, increasing times) are :func:`tumble.identification.identify`'s.

:func:`example_recording_path` is the recording shipped with tumble, made by
:func:`~tumble.identification.synthetic_phone` with seed 0 and written by
:func:`phyphox_csv`.
"""

from __future__ import annotations

import csv
import io
import math
import re
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError

__all__ = [
    "EXAMPLE",
    "PHYPHOX_COLUMNS",
    "RATE_UNITS",
    "Recording",
    "example_recording_path",
    "phyphox_csv",
    "read_recording",
]

Array = NDArray[np.float64]

#: The file name of the recording shipped with tumble (in this package's ``data``).
EXAMPLE = "phone-flip.csv"

#: The columns of phyphox's gyroscope export.
PHYPHOX_COLUMNS = (
    "Time (s)",
    "Gyroscope x (rad/s)",
    "Gyroscope y (rad/s)",
    "Gyroscope z (rad/s)",
)

#: Rate units a header or ``units`` may name, and their size in rad/s.
RATE_UNITS = {"rad/s": 1.0, "deg/s": math.pi / 180.0}

#: Other spellings of the rate units (lower case, spaces removed).
_RATE_SPELLINGS = {
    "rad/s": "rad/s",
    "rads": "rad/s",
    "rad/sec": "rad/s",
    "deg/s": "deg/s",
    "°/s": "deg/s",
    "degree/s": "deg/s",
    "degrees/s": "deg/s",
    "deg/sec": "deg/s",
    "dps": "deg/s",
}

#: Time units a header may name, in s.
TIME_UNITS = {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "ns": 1e-9}

#: Beyond this rate (rad/s), 20 turns/s, values without units are read as deg/s.
DEGREES_ABOVE = 2.0 * math.pi * 20.0

#: File names read as Parquet; other names are read as text tables (CSV) unless
#: their first bytes say Parquet or zip.
PARQUET_SUFFIXES = (".parquet", ".pq")

_TIME_NAME = re.compile(r"^\s*(t|time|timestamp)(?![a-z])", re.IGNORECASE)
_UNIT_IN_NAME = re.compile(r"[(\[]\s*([^()\[\]]+?)\s*[)\]]\s*$")


@dataclass(frozen=True, eq=False)
class Recording:
    """Gyroscope samples read from a file (:func:`read_recording`).

    Attributes
    ----------
    t : (n,) sample times, s, as the file has them (not checked: the fit does).
    omega : (n, 3) rates in the sensor's axes, rad/s.
    note : how something the file does not state was decided (the units told
        from the magnitude, columns taken by position), one sentence each; ""
        when the file said everything.
    columns : the names of the four columns read (t, ωx, ωy, ωz).
    """

    t: Array
    omega: Array
    note: str
    columns: tuple[str, str, str, str]


def example_recording_path() -> Path:
    """The recording shipped with tumble: a phone thrown about its intermediate
    axis, ``synthetic_phone(seed=0)`` in phyphox's CSV format (rad/s)."""
    return Path(str(resources.files("tumble.identification") / "data" / EXAMPLE))


def phyphox_csv(t: Any, omega: Any) -> str:
    """The text of a phyphox gyroscope export of samples ``t`` (n,) s and
    ``omega`` (n, 3) rad/s, sensor axes: a quoted header, times with 6 decimals
    (µs) and rates with 9 significant digits."""
    times = np.asarray(t, dtype=float)
    rates = np.asarray(omega, dtype=float)
    lines = [",".join(f'"{name}"' for name in PHYPHOX_COLUMNS)]
    lines += [
        f"{time:.6f},{x:.9g},{y:.9g},{z:.9g}" for time, (x, y, z) in zip(times, rates, strict=True)
    ]
    return "\n".join(lines) + "\n"


def read_recording(
    path: str | Path,
    columns: str | Sequence[str | int] | None = None,
    units: str | None = None,
) -> Recording:
    """Read a gyroscope recording from a CSV, phyphox zip or Parquet file.

    Parameters
    ----------
    path : the file.
    columns : the columns of t, ωx, ωy, ωz: four names or zero-based positions,
        as a sequence or a comma-separated string (``"t,wx,wy,wz"``,
        ``"0,1,2,3"``); None to find them (a column named ``t`` or ``time…`` and
        the three after it; the first four of a file without a header).
    units : ``"rad/s"`` or ``"deg/s"``, for rates whose header states no unit;
        None to tell from the magnitude (above 20 turns/s in rad/s: deg/s).

    Returns
    -------
    Recording: times in s, rates in rad/s in the sensor's axes, and a note of
    what was decided.

    Raises
    ------
    InputError
        A missing or unreadable file, one neither CSV nor Parquet, columns that
        are not there (the message lists those there), a cell that is not a
        number (its line and column), units that are not rates or times, or
        ``units`` that contradict the header.
    """
    file = Path(path)
    shown = str(path)
    if not file.exists():
        raise InputError(
            f"Expected a recording file (CSV or Parquet), got {shown!r} (no such file)."
        )
    if file.is_dir():
        raise InputError(f"Expected a recording file (CSV or Parquet), got {shown!r}, a folder.")
    try:
        data = file.read_bytes()
    except OSError as exc:
        raise InputError(
            f"Expected a readable recording file, got {shown!r}: {exc.strerror or exc}."
        ) from None
    rate_unit = _given_units(units)
    if data.startswith(b"PAR1") or file.suffix.lower() in PARQUET_SUFFIXES:
        names, table = _parquet_table(data, shown)
        return _recording(names, table, None, columns, rate_unit, shown)
    if data.startswith(b"PK\x03\x04"):
        data, shown = _member_of_zip(data, shown)
    text = _text(data, shown)
    names, cells, lines = _csv_table(text, shown)
    return _recording(names, cells, lines, columns, rate_unit, shown)


# ------------------------------------------------------------------ file kinds
def _given_units(units: str | None) -> str | None:
    if units is None:
        return None
    unit = _RATE_SPELLINGS.get(str(units).strip().lower().replace(" ", ""))
    if unit is None:
        raise InputError(f"Expected `units` to be 'rad/s' or 'deg/s', got {units!r}.")
    return unit


def _parquet_table(data: bytes, shown: str) -> tuple[list[str], dict[str, Any]]:
    """The column names of a Parquet file and its columns (pyarrow arrays) by name."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        table = pq.read_table(pa.BufferReader(data))
    except (pa.ArrowException, OSError) as exc:
        raise InputError(
            f"Expected a CSV or Parquet file, got {shown!r}, which is not valid Parquet ({exc})."
        ) from None
    return list(table.column_names), {name: table.column(name) for name in table.column_names}


def _member_of_zip(data: bytes, shown: str) -> tuple[bytes, str]:
    """The one table of data in a zip file (phyphox exports one, with a ``meta/`` folder)."""
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
        names = archive.namelist()
    except zipfile.BadZipFile:
        raise InputError(
            f"Expected a CSV or Parquet file, got {shown!r}, a damaged zip file."
        ) from None
    if "[Content_Types].xml" in names:
        raise InputError(
            f"Expected a CSV or Parquet file, got {shown!r}, a spreadsheet (export it as CSV)."
        )
    tables = [n for n in names if n.lower().endswith(".csv") and not n.startswith("meta/")]
    if len(tables) > 1:
        gyroscope = [n for n in tables if "gyro" in n.lower() or "raw data" in n.lower()]
        tables = gyroscope if len(gyroscope) == 1 else tables
    if len(tables) != 1:
        raise InputError(
            f"Expected a zip file with one CSV table of data (as phyphox exports), got {shown!r} "
            f"with {len(tables)}: {', '.join(map(repr, tables)) or 'none'} (unzip it and "
            "choose one)."
        )
    with archive:
        return archive.read(tables[0]), f"{shown}:{tables[0]}"


def _text(data: bytes, shown: str) -> str:
    if b"\x00" in data[:4096]:
        raise InputError(
            f"Expected a CSV or Parquet file, got {shown!r}, which is neither (binary data)."
        )
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        # Spreadsheets of some locales write Latin-1; every byte decodes.
        return data.decode("latin-1")


def _delimiter(line: str) -> str:
    """The separator of a CSV line: a tab or a semicolon wherever one stands
    outside quotes (files with decimal commas use them), else a comma."""
    outside = re.sub(r'"[^"]*"', "", line)
    for candidate in ("\t", ";"):
        if candidate in outside:
            return candidate
    return ","


def _csv_table(text: str, shown: str) -> tuple[list[str], dict[str, list[str]], list[int]]:
    """The header (or the positions, ``"0"``, ``"1"``, … without one), the cells
    by column, and the file's line of each row, of CSV text."""
    lines = text.splitlines()
    first = next((k for k, line in enumerate(lines) if line.strip()), None)
    if first is None:
        raise InputError(
            f"Expected a header row and rows of samples in {shown!r}, got an empty file."
        )
    delimiter = _delimiter(lines[first])
    reader = csv.reader(io.StringIO(text), delimiter=delimiter)
    rows: list[list[str]] = []
    numbers: list[int] = []
    for row in reader:
        if any(cell.strip() for cell in row):
            rows.append([cell.strip() for cell in row])
            numbers.append(reader.line_num)
    decimal_comma = delimiter != ","
    header = not all(_is_number(cell, decimal_comma) for cell in rows[0])
    if header:
        names, rows, numbers = rows[0], rows[1:], numbers[1:]
    else:
        names = [str(k) for k in range(len(rows[0]))]
    if not rows:
        raise InputError(f"Expected rows of samples after the header of {shown!r}, got none.")
    for row, line in zip(rows, numbers, strict=True):
        if len(row) < len(names):
            raise InputError(
                f"Expected {len(names)} cells in each row of {shown!r} (as in its "
                f"{'header' if header else 'first row'}), got {len(row)} in line {line}."
            )
    cells = {name: [row[k] for row in rows] for k, name in enumerate(names)}
    return names, cells, numbers


def _is_number(cell: str, decimal_comma: bool) -> bool:
    try:
        float(cell.replace(",", ".") if decimal_comma else cell)
    except ValueError:
        return False
    return True


# ------------------------------------------------------------------ columns
def _recording(
    names: list[str],
    cells: dict[str, Any],
    lines: list[int] | None,
    columns: str | Sequence[str | int] | None,
    units: str | None,
    shown: str,
) -> Recording:
    """The recording of a table's chosen columns (``lines``: each row's line in
    a CSV file; None for Parquet)."""
    notes: list[str] = []
    chosen = _choose(names, columns, shown, notes)
    csv_file = lines is not None
    values = [
        _numbers(cells[name], name, lines, shown)
        if csv_file
        else _arrow_numbers(cells[name], name, shown)
        for name in chosen
    ]
    time_unit = _unit_of(chosen[0])
    scale = TIME_UNITS.get(time_unit.lower().replace(" ", "")) if time_unit else 1.0
    if scale is None:
        raise InputError(
            f"Expected the time column in s or ms, got {chosen[0]!r} in {shown!r} "
            f"(unit {time_unit!r})."
        )
    omega = np.stack(values[1:], axis=1)
    omega = omega * _rate_scale(chosen[1:], omega, units, shown, notes)
    return Recording(
        t=values[0] * scale,
        omega=omega,
        note="; ".join(notes),
        columns=(chosen[0], chosen[1], chosen[2], chosen[3]),
    )


def _choose(
    names: list[str], columns: str | Sequence[str | int] | None, shown: str, notes: list[str]
) -> list[str]:
    """The names of the four columns asked for, or found."""
    there = ", ".join(map(repr, names))
    if columns is None:
        if all(name.isdigit() for name in names) and len(names) >= 4:
            notes.append("no header row: columns 0, 1, 2, 3 read as t, ωx, ωy, ωz")
            return names[:4]
        found = next((k for k, name in enumerate(names) if _TIME_NAME.match(name)), None)
        if found is None:
            raise InputError(
                f"Expected a time column (named 't' or 'time…') in {shown!r}, got columns "
                f"{there} (choose four with `columns`, --columns t,wx,wy,wz)."
            )
        if found + 3 >= len(names):
            raise InputError(
                f"Expected three rate columns after the time column {names[found]!r} in "
                f"{shown!r}, got columns {there} (choose four with `columns`, --columns "
                "t,wx,wy,wz)."
            )
        return names[found : found + 4]
    given = (
        [part.strip() for part in columns.split(",")] if isinstance(columns, str) else list(columns)
    )
    if len(given) != 4:
        raise InputError(
            f"Expected `columns` to be 4 names or positions (t, ωx, ωy, ωz), got "
            f"{len(given)}: {columns!r}."
        )
    chosen = [_column(names, key, shown, there) for key in given]
    if len(set(chosen)) < 4:
        raise InputError(f"Expected 4 different columns, got {columns!r}.")
    return chosen


def _column(names: list[str], key: str | int, shown: str, there: str) -> str:
    """The column ``key`` names: a position, a name, or a name without case or unit."""
    text = str(key).strip()
    if isinstance(key, int) or re.fullmatch(r"\d+", text):
        position = int(text)
        if position >= len(names):
            raise InputError(
                f"Expected column positions 0 to {len(names) - 1} in {shown!r}, got {position} "
                f"(the columns are {there})."
            )
        return names[position]
    if text in names:
        return text
    for name in names:
        bare = _UNIT_IN_NAME.sub("", name).strip()
        if text.lower() in (name.lower(), bare.lower()):
            return name
    raise InputError(f"Expected a column named {text!r} in {shown!r}, got columns {there}.")


def _unit_of(name: str) -> str | None:
    """The unit a column's name states in parentheses or brackets at its end."""
    found = _UNIT_IN_NAME.search(name)
    return found.group(1) if found else None


def _rate_scale(
    names: list[str], omega: Array, units: str | None, shown: str, notes: list[str]
) -> float:
    """rad/s per unit of the rate columns: from their headers, else ``units``,
    else from the magnitude (a note says which and why)."""
    stated = set()
    for name in names:
        unit = _unit_of(name)
        if unit is None:
            continue
        rate = _RATE_SPELLINGS.get(unit.lower().replace(" ", ""))
        if rate is None:
            raise InputError(
                f"Expected angular rates in rad/s or deg/s, got the column {name!r} in "
                f"{shown!r} (unit {unit!r})."
            )
        stated.add(rate)
    if len(stated) > 1:
        raise InputError(
            f"Expected the three rate columns in one unit, got {', '.join(map(repr, names))}."
        )
    if stated:
        (header,) = stated
        if units is not None and units != header:
            raise InputError(
                f"Expected `units` to agree with the header of {shown!r}, which states "
                f"{header}, got {units!r} (leave it out to read {header})."
            )
        return RATE_UNITS[header]
    if units is not None:
        return RATE_UNITS[units]
    finite = np.abs(omega[np.isfinite(omega)])
    largest = float(finite.max()) if finite.size else 0.0
    if largest > DEGREES_ABOVE:
        notes.append(
            f"read as deg/s: the largest rate, {largest:.4g}, would be "
            f"{largest / (2.0 * math.pi):.3g} turns/s in rad/s; --units rad/s to keep rad/s"
        )
        return RATE_UNITS["deg/s"]
    notes.append(
        f"read as rad/s (no unit stated; the largest rate, {largest:.4g}, is "
        f"{largest / (2.0 * math.pi):.3g} turns/s); --units deg/s if it is deg/s"
    )
    return 1.0


# ------------------------------------------------------------------ numbers
def _numbers(cells: list[str], name: str, lines: list[int] | None, shown: str) -> Array:
    """A CSV column as floats (decimal commas read as points)."""
    text = np.array(cells)
    try:
        return text.astype(np.float64)
    except ValueError:
        pass
    try:
        return np.char.replace(text, ",", ".").astype(np.float64)
    except ValueError:
        pass
    for k, cell in enumerate(cells):
        if not _is_number(cell, decimal_comma=True):
            where = f"line {lines[k]}" if lines is not None else f"row {k}"
            raise InputError(
                f"Expected numbers in {shown!r}, got {cell!r} at {where}, column {name!r}."
            )
    # Every cell reads as a number to Python where numpy's parser balked.
    return np.array([float(cell.replace(",", ".")) for cell in cells])


def _arrow_numbers(column: Any, name: str, shown: str) -> Array:
    """A Parquet column as floats (missing values as NaN, which the fit refuses)."""
    import pyarrow as pa
    import pyarrow.compute as pc

    kind = column.type
    if not (pa.types.is_integer(kind) or pa.types.is_floating(kind)):
        raise InputError(
            f"Expected numbers in the column {name!r} of {shown!r}, got values of type {kind}."
        )
    return np.asarray(pc.cast(column, pa.float64()).to_numpy(zero_copy_only=False), dtype=float)
