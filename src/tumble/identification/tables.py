"""Text tables of samples (CSV) read in blocks, only the columns asked for:
:func:`table_layout` tells how a table is written from its first bytes,
:func:`table_columns` reads its columns as floats.

pyarrow's CSV reader reads the table in blocks; where it refuses a row or a cell
(rows with more cells than the header, decimal commas mixed with points, numbers
only Python reads), the table is read again line by line with Python's csv
module, which reads those and names the line and column of a row or a cell that
is no number. Either way the rows read are counted against the memory budget
(:mod:`tumble.resources`) as they come.
"""

from __future__ import annotations

import codecs
import csv
import io
import re
from array import array
from collections.abc import Callable
from dataclasses import dataclass
from typing import IO

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, cut
from tumble.resources import check_memory, format_bytes, memory_budget

__all__ = [
    "HEAD_BYTES",
    "SAMPLE_BYTES",
    "TableLayout",
    "check_samples",
    "table_columns",
    "table_layout",
]

Array = NDArray[np.float64]

#: Bytes of a text table's start read first: its separator, header and the
#: length of its rows are told from them.
HEAD_BYTES = 1 << 16

#: Bytes ``tumble fit`` takes for each sample of a recording, for the memory
#: budget: the four columns as read and as arrays, the fit's passes over the
#: whole recording (its noise, its free flight, the averages) and the figure of
#: it. Measured: its peak memory grew by 210 bytes a sample over the example's
#: for a CSV file of 1.3 million samples (60 MB); twice that, for a margin.
SAMPLE_BYTES = 420


def check_samples(count: int, shown: str, detail: str = "") -> None:
    """Refuse a recording of ``count`` samples (``detail``: how that is known)
    beyond the memory budget."""
    check_memory(
        count * SAMPLE_BYTES,
        f"the recording {shown!r}{detail}, about {count:.3g} samples",
        "Cut the recording to the throw and the free flight (a few seconds).",
    )


@dataclass(frozen=True)
class TableLayout:
    """How a text table is written, from its first bytes."""

    delimiter: str
    encoding: str
    names: list[str]
    header: bool
    offset: int  # bytes before the first row of samples (BOM and header)
    lines: int  # lines before it
    row_bytes: int  # the mean row of the first block, bytes


def table_layout(head: bytes, size: int, shown: str) -> TableLayout:
    """The separator, encoding, header and row length of a text table from its
    first bytes ``head`` (all of it when ``size`` is no more)."""
    if b"\x00" in head[:4096]:
        raise InputError(
            f"Expected a CSV or Parquet file, got {shown!r}, which is neither (binary data)."
        )
    whole = len(head) >= size
    # Whole lines only: a character cut at the end would not decode.
    body = head if whole else head[: head.rfind(b"\n") + 1]
    try:
        text, encoding = body.decode("utf-8-sig"), "utf-8"
    except UnicodeDecodeError:
        # Spreadsheets of some locales write Latin-1; every byte decodes.
        text, encoding = body.decode("latin-1"), "latin-1"
    lines = text.split("\n")
    first = next((k for k, line in enumerate(lines) if line.strip()), None)
    if first is None:
        raise InputError(
            f"Expected a header row and rows of samples in {shown!r}, got "
            + ("an empty file." if whole else f"no row in its first {format_bytes(len(head))}.")
        )
    delimiter = _delimiter(lines[first])
    reader = csv.reader(io.StringIO(text), delimiter=delimiter)
    row = next(r for r in reader if any(cell.strip() for cell in r))
    cells = [cell.strip() for cell in row]
    header = not all(_is_number(cell, delimiter != ",") for cell in cells)
    bom = len(codecs.BOM_UTF8) if head.startswith(codecs.BOM_UTF8) else 0
    if header:
        names, skipped = cells, reader.line_num
    else:
        names, skipped = [str(k) for k in range(len(cells))], 0
    offset = bom
    for _ in range(skipped):
        found = body.find(b"\n", offset)
        offset = found + 1 if found >= 0 else len(body)
    # The mean row of the first block: the count of rows it gives is checked again
    # as the rows are read (:func:`_check_rows`), for files whose rows grow shorter.
    sample_rows = [line for line in body[offset:].split(b"\n") if line.strip()]
    row_bytes = (
        sum(len(line) + 1 for line in sample_rows) // len(sample_rows)
        if sample_rows
        else 2 * len(names)
    )
    return TableLayout(delimiter, encoding, names, header, offset, skipped, max(row_bytes, 2))


def table_columns(
    open_stream: Callable[[], IO[bytes]],
    layout: TableLayout,
    positions: list[int],
    chosen: list[str],
    shown: str,
) -> list[Array]:
    """The columns at ``positions`` (named ``chosen``) of the table ``open_stream``
    opens, written as ``layout`` says, as floats: by pyarrow's reader, or line by
    line where it refuses a row or a cell."""
    values = _columns_by_arrow(open_stream, layout, positions, shown)
    if values is None:
        values = _columns_by_line(open_stream, layout, positions, chosen, shown)
    return values


def _columns_by_arrow(
    open_stream: Callable[[], IO[bytes]], layout: TableLayout, positions: list[int], shown: str
) -> list[Array] | None:
    """The columns at ``positions`` by pyarrow's CSV reader, in blocks; None where
    it refuses a row or a cell (the reader by lines then says which)."""
    import pyarrow as pa
    import pyarrow.csv as pcsv

    keys = [f"c{k}" for k in range(len(layout.names))]
    wanted = list(dict.fromkeys(keys[k] for k in positions))
    # A decimal point first; a decimal comma where a tab or semicolon separates.
    for point in "." if layout.delimiter == "," else ".,":
        chunks: dict[str, list[Array]] = {key: [] for key in wanted}
        count = 0
        try:
            with open_stream() as stream:
                stream.read(layout.offset)
                reader = pcsv.open_csv(
                    stream,
                    read_options=pcsv.ReadOptions(
                        column_names=keys, encoding=layout.encoding, use_threads=False
                    ),
                    parse_options=pcsv.ParseOptions(delimiter=layout.delimiter),
                    convert_options=pcsv.ConvertOptions(
                        column_types=dict.fromkeys(wanted, pa.float64()),
                        include_columns=wanted,
                        null_values=[],
                        decimal_point=point,
                    ),
                )
                for batch in reader:
                    count += batch.num_rows
                    _check_rows(count, shown)
                    for key in wanted:
                        column = batch.column(batch.schema.get_field_index(key))
                        chunks[key].append(column.to_numpy(zero_copy_only=False))
        except pa.ArrowInvalid:
            continue
        joined = {
            key: np.concatenate(parts) if parts else np.empty(0) for key, parts in chunks.items()
        }
        return [np.asarray(joined[keys[k]], dtype=float) for k in positions]
    return None


def _check_rows(count: int, shown: str) -> None:
    """Refuse, while a table is read, more rows than the memory budget holds (a
    file whose first rows are far longer than the rest, a zip file that
    understates its table)."""
    budget, _ = memory_budget()
    if count * SAMPLE_BYTES > budget:
        check_samples(count, shown, " (read so far)")


def _columns_by_line(
    open_stream: Callable[[], IO[bytes]],
    layout: TableLayout,
    positions: list[int],
    chosen: list[str],
    shown: str,
) -> list[Array]:
    """The columns at ``positions`` read line by line with Python's csv module:
    rows with more cells than the header, numbers with decimal commas and with
    anything Python reads as a number; the line and column of a row or a cell
    that is not, in the message."""
    encoding = layout.encoding
    while True:
        columns = [array("d") for _ in positions]
        try:
            with open_stream() as raw:
                raw.read(layout.offset)
                text = io.TextIOWrapper(raw, encoding=encoding, newline="")
                reader = csv.reader(text, delimiter=layout.delimiter)
                for row in reader:
                    if not any(cell.strip() for cell in row):
                        continue
                    line = layout.lines + reader.line_num
                    if len(row) < len(layout.names):
                        raise InputError(
                            f"Expected {len(layout.names)} cells in each row of {shown!r} (as in "
                            f"its {'header' if layout.header else 'first row'}), got {len(row)} "
                            f"in line {line}."
                        )
                    for column, k, name in zip(columns, positions, chosen, strict=True):
                        column.append(_number(row[k].strip(), line, name, shown))
                    if len(columns[0]) % 65536 == 0:
                        _check_rows(len(columns[0]), shown)
        except UnicodeDecodeError:
            if encoding == "latin-1":
                raise
            encoding = "latin-1"  # a byte beyond the first block that is not UTF-8
            continue
        return [np.frombuffer(column, dtype=float).copy() for column in columns]


def _delimiter(line: str) -> str:
    """The separator of a CSV line: a tab or a semicolon wherever one stands
    outside quotes (files with decimal commas use them), else a comma."""
    outside = re.sub(r'"[^"]*"', "", line)
    for candidate in ("\t", ";"):
        if candidate in outside:
            return candidate
    return ","


def _is_number(cell: str, decimal_comma: bool) -> bool:
    try:
        float(cell.replace(",", ".") if decimal_comma else cell)
    except ValueError:
        return False
    return True


def _number(cell: str, line: int, name: str, shown: str) -> float:
    """A cell as a float (a decimal comma read as a point)."""
    try:
        return float(cell)
    except ValueError:
        pass
    try:
        return float(cell.replace(",", "."))
    except ValueError:
        raise InputError(
            f"Expected numbers in {shown!r}, got {cut(repr(cell))} at line {line}, column {name!r}."
        ) from None
