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

import math
import re
import zipfile
import zlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, cut
from tumble.files import check_regular_file
from tumble.identification.tables import (
    HEAD_BYTES,
    check_samples,
    table_columns,
    table_layout,
)
from tumble.resources import format_bytes

__all__ = [
    "EXAMPLE",
    "PHYPHOX_COLUMNS",
    "RATE_UNITS",
    "Recording",
    "example_recording_path",
    "phyphox_csv",
    "rate_unit",
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

#: The signatures a zip file starts with: a member, an empty archive, a spanned one.
_ZIP_SIGNATURES = (b"PK\x03\x04", b"PK\x05\x06", b"PK\x07\x08")

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
        A missing or unreadable file, one that is not a regular file (a FIFO,
        a device), one neither CSV nor Parquet, columns that
        are not there (the message lists those there), a cell that is not a
        number (its line and column), units that are not rates or times, or
        ``units`` that contradict the header.
    tumble.errors.RequestTooLargeError
        A recording of more samples than the memory budget
        (:mod:`tumble.resources`) holds, told from the size of the file (the
        size a zip file declares for its table) before it is read, and from the
        samples read while it is.

    Notes
    -----
    Only the four columns chosen are read into memory, as numbers: a text
    table is read in blocks (by pyarrow's CSV reader, or line by line where that
    one refuses a row, which then finds the row's line), a zip file's table
    straight from the archive.
    """
    file = Path(path)
    shown = str(path)
    if not file.exists():
        raise InputError(
            f"Expected a recording file (CSV or Parquet), got {shown!r} (no such file)."
        )
    if file.is_dir():
        raise InputError(f"Expected a recording file (CSV or Parquet), got {shown!r}, a folder.")
    check_regular_file(file, "the recording")  # a FIFO would wait for a writer forever
    unit = rate_unit(units)
    notes: list[str] = []
    try:
        with file.open("rb") as stream:
            start = stream.read(8)
        if start.startswith(b"PAR1") or file.suffix.lower() in PARQUET_SUFFIXES:
            chosen, values = _parquet_columns(file, shown, columns, notes)
        elif start.startswith(_ZIP_SIGNATURES) or file.suffix.lower() == ".zip":
            chosen, values, shown = _zip_columns(file, start, shown, columns, notes)
        else:
            size = file.stat().st_size
            chosen, values = _csv_columns(lambda: file.open("rb"), size, shown, columns, notes)
    except OSError as exc:
        raise InputError(
            f"Expected a readable recording file, got {shown!r}: {exc.strerror or exc}."
        ) from None
    return _recording(chosen, values, unit, shown, notes)


# ------------------------------------------------------------------ file kinds
def rate_unit(units: str | None, name: str = "`units`") -> str | None:
    """``"rad/s"`` or ``"deg/s"`` for ``units`` in any of their spellings
    (``"°/s"``, ``"dps"``, ...); None for None (``name``: how the message calls it).

    Raises
    ------
    InputError
        For other units.
    """
    if units is None:
        return None
    unit = _RATE_SPELLINGS.get(str(units).strip().lower().replace(" ", ""))
    if unit is None:
        raise InputError(f"Expected {name} to be 'rad/s' or 'deg/s', got {cut(repr(units))}.")
    return unit


def _parquet_columns(
    file: Path, shown: str, columns: str | Sequence[str | int] | None, notes: list[str]
) -> tuple[list[str], list[Array]]:
    """The four columns chosen of a Parquet file, as floats (only they are read)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        with pq.ParquetFile(file) as parquet:
            names = list(parquet.schema_arrow.names)
            chosen = _choose(names, columns, shown, notes)
            check_samples(parquet.metadata.num_rows, shown)
            table = parquet.read(columns=list(dict.fromkeys(chosen)))
    except (pa.ArrowException, OSError) as exc:
        raise InputError(
            f"Expected a CSV or Parquet file, got {shown!r}, which is not valid Parquet "
            f"({cut(str(exc))})."
        ) from None
    return chosen, [_arrow_numbers(table.column(name), name, shown) for name in chosen]


def _zip_columns(
    file: Path,
    start: bytes,
    shown: str,
    columns: str | Sequence[str | int] | None,
    notes: list[str],
) -> tuple[list[str], list[Array], str]:
    """The four columns chosen of the one table of data in a zip file (phyphox
    exports one, with a ``meta/`` folder), read from the archive as it is
    decompressed; and the name of the table, ``ZIP:MEMBER``."""
    try:
        archive = zipfile.ZipFile(file)
    except zipfile.BadZipFile:
        if start.startswith(_ZIP_SIGNATURES):
            raise InputError(
                f"Expected a CSV or Parquet file, got {shown!r}, a damaged zip file."
            ) from None
        raise InputError(
            f"Expected a zip file, as the name {shown!r} says, got a file that is not one "
            "(a CSV table is read from a file named .csv)."
        ) from None
    with archive:
        names = archive.namelist()
        if "[Content_Types].xml" in names:
            raise InputError(
                f"Expected a CSV or Parquet file, got {shown!r}, a spreadsheet (export it as CSV)."
            )
        expected = "Expected a zip file with one CSV table of data (as phyphox exports), got"
        if not names:
            raise InputError(f"{expected} {shown!r}, an empty zip file.")
        tables = [n for n in names if n.lower().endswith(".csv") and not n.startswith("meta/")]
        if len(tables) > 1:
            gyroscope = [n for n in tables if "gyro" in n.lower() or "raw data" in n.lower()]
            tables = gyroscope if len(gyroscope) == 1 else tables
        if not tables:
            raise InputError(
                f"{expected} {shown!r}, which holds none (it holds "
                f"{cut(', '.join(map(repr, names)))})."
            )
        if len(tables) > 1:
            raise InputError(
                f"{expected} {shown!r} with {len(tables)}: {cut(', '.join(map(repr, tables)))} "
                "(unzip it and choose one)."
            )
        member = archive.getinfo(tables[0])
        table = f"{shown}:{tables[0]}"

        def open_member() -> IO[bytes]:
            try:
                return archive.open(member)
            except (RuntimeError, NotImplementedError) as exc:  # encrypted, or compressed unknown
                raise InputError(
                    f"Expected a zip file whose table can be read, got {table!r}: {exc}."
                ) from None

        try:
            chosen, values = _csv_columns(
                open_member, member.file_size, table, columns, notes, " (uncompressed)"
            )
        except (zipfile.BadZipFile, zlib.error, EOFError):
            raise InputError(
                f"Expected a CSV or Parquet file, got {shown!r}, a damaged zip file."
            ) from None
    return chosen, values, table


# ------------------------------------------------------------------ text tables
def _csv_columns(
    open_stream: Callable[[], IO[bytes]],
    size: int,
    shown: str,
    columns: str | Sequence[str | int] | None,
    notes: list[str],
    sized: str = "",
) -> tuple[list[str], list[Array]]:
    """The four columns chosen of a text table of ``size`` bytes, as floats;
    ``open_stream`` opens it, ``sized`` says how its size is known."""
    with open_stream() as stream:
        head = stream.read(HEAD_BYTES)
    layout = table_layout(head, size, shown)
    chosen = _choose(layout.names, columns, shown, notes)
    # The last column of a name (a header naming two alike keeps the last).
    positions = [len(layout.names) - 1 - layout.names[::-1].index(name) for name in chosen]
    rows = max(size - layout.offset, 0) // layout.row_bytes
    check_samples(rows, shown, f" of {format_bytes(size)}{sized}")
    values = table_columns(open_stream, layout, positions, chosen, shown)
    if values[0].size == 0:
        raise InputError(f"Expected rows of samples after the header of {shown!r}, got none.")
    return chosen, values


# ------------------------------------------------------------------ columns
def _recording(
    chosen: list[str], values: list[Array], units: str | None, shown: str, notes: list[str]
) -> Recording:
    """The recording of the chosen columns ``chosen`` and their ``values``."""
    time_unit = _unit_of(chosen[0])
    scale = TIME_UNITS.get(time_unit.lower().replace(" ", "")) if time_unit else 1.0
    if scale is None:
        raise InputError(
            f"Expected the time column in s or ms, got {chosen[0]!r} in {shown!r} "
            f"(unit {time_unit!r})."
        )
    omega = np.stack(values[1:], axis=1)
    omega *= _rate_scale(chosen[1:], omega, units, shown, notes)
    return Recording(
        t=values[0] * scale if scale != 1.0 else values[0],
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
