"""Windows of a recording chosen by hand, one per throw: :func:`check_windows`
checks them against the samples, :func:`read_windows` reads them from a CSV
file (columns ``start`` and ``end``, s, one window a row)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, cut
from tumble.identification.validation import MIN_SAMPLES

__all__ = ["check_windows", "read_windows"]

Array = NDArray[np.float64]


def check_windows(windows: Iterable[Any], t: Array) -> list[tuple[float, float]]:
    """The windows ``[(start, end), ...]``, s, checked against the recording's
    sample times ``t`` (n,) s, sorted by their starts.

    Raises
    ------
    InputError
        No window; one that is not a pair of finite numbers with start < end,
        one outside ``[t[0], t[-1]]``, one of fewer than ``MIN_SAMPLES`` samples,
        or two that overlap (named by their numbers, from 1, as given).
    """
    times = np.asarray(t, dtype=float)
    checked = []
    for number, window in enumerate(windows, start=1):
        try:
            start, end = (float(value) for value in window)
        except (TypeError, ValueError):
            raise InputError(
                f"Expected window {number} to be (start, end) in s, got {cut(repr(window))}."
            ) from None
        if not (math.isfinite(start) and math.isfinite(end) and start < end):
            raise InputError(
                f"Expected window {number} to have finite start < end, got {start!r}–{end!r} s."
            )
        if start < times[0] or end > times[-1]:
            raise InputError(
                f"Expected window {number} inside the recording ({times[0]:.6g}–"
                f"{times[-1]:.6g} s), got {start:.6g}–{end:.6g} s."
            )
        count = int(np.count_nonzero((times >= start) & (times <= end)))
        if count < MIN_SAMPLES:
            raise InputError(
                f"Expected at least {MIN_SAMPLES} samples in window {number}, got {count} in "
                f"{start:.6g}–{end:.6g} s."
            )
        checked.append((number, start, end))
    if not checked:
        raise InputError("Expected at least one window (start, end), got none.")
    checked.sort(key=lambda window: window[1])
    # Windows that share an instant share its sample: each sample is one throw's.
    for (first, start, end), (second, later, last) in itertools.pairwise(checked):
        if later <= end:
            raise InputError(
                f"Expected windows that do not overlap, got window {first} ({start:.6g}–"
                f"{end:.6g} s) and window {second} ({later:.6g}–{last:.6g} s)."
            )
    return [(start, end) for _, start, end in checked]


def read_windows(path: str | Path) -> list[tuple[float, float]]:
    """The windows of a CSV file: one a row, columns named ``start`` and ``end``
    (s; a header is required, other columns are ignored), in the file's order.

    Raises
    ------
    InputError
        A missing file, a folder, one that is not a CSV table, one without the
        columns ``start`` and ``end`` (the columns found are named), a value that
        is not a number (its row, counted from 1 after the header, blank lines
        skipped), or a file of no windows.
    """
    import pandas as pd

    file = Path(path)
    shown = str(path)
    if not file.is_file():
        what = "a folder" if file.is_dir() else "no such file"
        raise InputError(f"Expected a CSV file of windows, got {shown!r} ({what}).")
    try:
        table = pd.read_csv(file, dtype=str, skipinitialspace=True, keep_default_na=False)
    except pd.errors.EmptyDataError:
        raise InputError(
            f"Expected a CSV file of windows with columns start,end, got {shown!r}, which is empty."
        ) from None
    except (pd.errors.ParserError, UnicodeDecodeError, OSError) as exc:
        raise InputError(
            f"Expected a CSV file of windows, got {shown!r}, which is not one ({cut(str(exc))})."
        ) from None
    columns = {str(name).strip(): name for name in table.columns}
    if "start" not in columns or "end" not in columns:
        found = ", ".join(repr(str(name)) for name in table.columns)
        raise InputError(
            f"Expected columns named start and end in {shown!r}, got columns {cut(found)}."
        )
    if table.empty:
        raise InputError(f"Expected at least one window in {shown!r}, got a header only.")
    windows = []
    pairs = zip(table[columns["start"]], table[columns["end"]], strict=True)
    for row, (start, end) in enumerate(pairs, start=1):
        try:
            windows.append((float(start), float(end)))
        except ValueError:
            raise InputError(
                f"Expected numbers (s) for start and end in {shown!r}, got "
                f"{cut(repr(start))}, {cut(repr(end))} in row {row} after the header."
            ) from None
    return windows
